//! @file OverrideTimingTests.cpp
//! @brief The feed and rapid overrides of a run (SimOptions::feedScale, rapidScale): closed-form
//!        cycle times (SPEC §5.2) exact to 1e-9 relative; the axis limits still cap the speed;
//!        what the overrides leave alone (rapids, feeds, dwells, M times).
#include <cmath>

#include <doctest/doctest.h>

#include "SimTestUtil.h"

using namespace iso;
using namespace iso::test;
using sim::Status;

namespace {
constexpr double V = 500, A = 2000; // the built-in machine, every axis
constexpr double kPi = 3.14159265358979323846;

sim::SimOptions scaled(double feed, double rapid) {
  sim::SimOptions o;
  o.feedScale = feed;
  o.rapidScale = rapid;
  return o;
}
} // namespace

TEST_CASE("override: 50% feed halves the programmed feed of a line, an arc and an Fa axis") {
  // X 100 at F=50 -> 25 mm/s: 100/25 + 25/2000 (trapezoid, d >= V²/A)
  auto r = simText("G01 X100 F=50\nM30\n", builtin(), scaled(0.5, 1));
  REQUIRE(r->diagnostics.empty());
  CHECK(r->status() == Status::Ok);
  CHECK(r->cycle() == exact(100.0 / 25 + 25 / A));
  CHECK(r->cycle() == exact(moveTime(100, 25, A)));
  // a half circle of radius 10 (length 10·π) at F=20 -> 10 mm/s; sqrt(r·A) = 141 does not bound it
  r = simText("G02 X20 Y0 I10 J0 F=20\nM30\n", builtin(), scaled(0.5, 1));
  REQUIRE(r->diagnostics.empty());
  CHECK(r->cycle() == exact(10 * kPi / 10 + 10 / A));
  // an axis at its own feed Fa (independent): Fa[X]=50 -> 25 mm/s
  r = simText("G01 X100 Fa[X]=50\nM30\n", builtin(), scaled(0.5, 1));
  REQUIRE(r->diagnostics.empty());
  CHECK(r->cycle() == exact(moveTime(100, 25, A)));
}

TEST_CASE("override: the feed override leaves rapids, dwells and M times alone") {
  // G00 X1000 at 500 mm/s: 1000/500 + 500/2000 = 2.25; G04 F1.5 dwells 1.5 s; G01 X900 at 25 mm/s
  auto m = machineWith([](machine::Machine& mm) { mm.defaultMDurationS = 0.75; });
  auto r = simText("G00 X1000\nG04 F1.5\nM23\nG01 X900 F=50\nM30\n", m, scaled(0.5, 1));
  REQUIRE(r->diagnostics.empty());
  CHECK(r->cycle() == exact((1000 / V + V / A) + 1.5 + 0.75 + (100.0 / 25 + 25 / A)));
}

TEST_CASE("override: the axes' max_velocity still caps an overridden feed") {
  // F=400 at 200% is 800 mm/s, capped at X's 500 mm/s: X 1000 takes 1000/500 + 500/2000
  auto r = simText("G01 X1000 F=400\nM30\n", builtin(), scaled(2, 1));
  REQUIRE(r->diagnostics.empty());
  CHECK(r->cycle() == exact(1000 / V + V / A));
  // the same 200% on F=100 (200 mm/s) is below the cap: 1000/200 + 200/2000
  r = simText("G01 X1000 F=100\nM30\n", builtin(), scaled(2, 1));
  CHECK(r->cycle() == exact(1000.0 / 200 + 200 / A));
  // an interpolated line: V = min(F·s, vmax_i/|u_i|); u = (0.6, 0.8), Y bounds at 500/0.8 = 625
  r = simText("G01 X300 Y400 F=400\nM30\n", builtin(), scaled(2, 1));
  CHECK(r->cycle() == exact(moveTime(500, 625, A / 0.8)));
}

TEST_CASE("override: 50% rapid halves each axis's G00 speed, accelerations unchanged") {
  // G00 X1000 at 250 mm/s: 1000/250 + 250/2000; G01 X1100 at F=50 unchanged: 100/50 + 50/2000;
  // G00 X1110 (10 mm < 250²/2000) never reaches its top speed: 2·sqrt(10/2000) as at 100%
  auto r = simText("G00 X1000\nG01 X1100 F=50\nG00 X1110\nM30\n", builtin(), scaled(1, 0.5));
  REQUIRE(r->diagnostics.empty());
  CHECK(r->cycle() == exact((1000.0 / 250 + 250 / A) + (100.0 / 50 + 50 / A) + 2 * std::sqrt(10 / A)));
  // each axis at its own limit: Y's 100 mm/s becomes 50 mm/s, X's 500 becomes 250
  auto m = machineWith([](machine::Machine& mm) { mm.axes[1].maxVelocity = 100; });
  r = simText("G00 X1000 Y300\nM30\n", m, scaled(1, 0.5));
  CHECK(r->moveEnd('X') == exact(moveTime(1000, 250, A)));
  CHECK(r->moveEnd('Y') == exact(moveTime(300, 50, A)));
  CHECK(r->cycle() == exact(moveTime(300, 50, A)));
}

TEST_CASE("override: scales of 1 give the times of a run without overrides") {
  const char* text = "G00 X1000\nG01 X0 Y30 F=70\nG02 X20 Y30 I10 J0\nG04 F0.5\nM30\n";
  auto plain = simText(text);
  auto ones = simText(text, builtin(), scaled(1, 1));
  REQUIRE(plain->diagnostics.empty());
  CHECK(ones->cycle() == plain->cycle());
}

TEST_CASE("override: a G64 chain at 50% feed runs as the same chain programmed at half the feed") {
  // collinear blocks blend at full speed: X 100 in one trapezoid at 50 mm/s, 100/50 + 50/2000
  auto r = simText("G64 G01 F100\nX25\nX50\nX100\nM30\n", builtin(), scaled(0.5, 1));
  REQUIRE(r->diagnostics.empty());
  CHECK(r->cycle() == exact(100.0 / 50 + 50 / A));
  // a corner (junction speed from the halved feed's planning): the same times as F=50
  auto over = simText("G64 G01 X100 F100\nY100\nM30\n", builtin(), scaled(0.5, 1));
  auto half = simText("G64 G01 X100 F50\nY100\nM30\n");
  CHECK(over->cycle() == exact(half->cycle()));
  CHECK(over->cycle() > simText("G64 G01 X100 F100\nY100\nM30\n")->cycle() + 1); // 2.131682 s at 100%
}
