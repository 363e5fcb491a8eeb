//! @file WhenTests.cpp
//! @brief WHEN … DO … CANCEL anticipations (SPEC §4.4): firing instants against closed forms,
//!        drops, chains, bodies as threads, and the join of the trigger with its bodies.
#include <cmath>

#include <doctest/doctest.h>

#include "SimTestUtil.h"

using namespace iso;
using namespace iso::test;
using sim::EventKind;
using sim::Status;

namespace {
constexpr double A = 2000; // built-in axes: 500 mm/s, 2000 mm/s²
}

TEST_CASE("sim: WHEN fires mid-acceleration at the exact crossing") {
  auto r = simText("WHEN $aa_iw[X] > 10 DO $aa_out[1] = 1\nG00 X1000\nM30\n");
  REQUIRE(r->diagnostics.empty());
  const double t = std::sqrt(10 / (A / 2)); // x = A t²/2
  CHECK(r->whenTime("armed") == 0);
  CHECK(r->whenTime("fired") == exact(t));
  auto outs = r->events(EventKind::Output);
  REQUIRE(outs.size() == 1);
  CHECK(outs[0].t == exact(t));
  CHECK(r->cycle() == exact(2.25));
}

TEST_CASE("sim: WHEN fires mid-cruise at the exact crossing") {
  auto r = simText("WHEN $aa_iw[X] > 500 DO $aa_out[1] = 1\nG00 X1000\nM30\n");
  CHECK(r->whenTime("fired") == exact(0.25 + (500 - 62.5) / 500));
  // and mid-deceleration, on the way down
  auto d = simText("G00 X1000\nWHEN $aa_iw[X] < 2.5 DO $aa_out[1] = 1\nG00 X0\nM30\n");
  CHECK(d->whenTime("fired") == exact(2.25 + 2.25 - std::sqrt(2.5 / (A / 2))));
}

TEST_CASE("sim: a WHEN that never fires is dropped when its trigger ends") {
  auto r = simText("WHEN $aa_iw[X] > 2000 DO $aa_out[1] = 1\nG00 X1000\nM30\n");
  CHECK(std::isnan(r->whenTime("fired")));
  CHECK(r->whenTime("dropped") == exact(2.25));
  CHECK(r->count(EventKind::Output) == 0);
  CHECK(r->cycle() == exact(2.25));
}

TEST_CASE("sim: a WHEN that holds at the start fires at once - one that first holds at the end fires then") {
  auto r = simText("WHEN $aa_iw[X] < 5 DO $aa_out[1] = 1\nG00 X1000\nM30\n");
  CHECK(r->whenTime("fired") == 0);
  auto e = simText("WHEN $aa_iw[X] >= 1000 DO $aa_out[1] = 1\nG00 X1000\nM30\n");
  // X >= 1000 holds once X is within the comparison tolerance 1e-12·1000 mm of 1000: during the
  // final deceleration, 1e-9 = A σ²/2 before the end
  CHECK(e->whenTime("fired") == exact(2.25 - std::sqrt(2 * 1e-12 * 1000 / A)));
  CHECK(e->count(EventKind::Output) == 1);
}

TEST_CASE("sim: a WHEN equality is found between samples") {
  auto r = simText("WHEN $aa_iw[X] == 437.5 DO $aa_out[1] = 1\nG00 X1000\nM30\n");
  CHECK(r->whenTime("fired") == exact(1.0)); // 62.5 + 500 · (1 − 0.25)
}

TEST_CASE("sim: a WHEN body runs as its own thread - the next line waits for trigger and body") {
  // the body's Y move (1000 mm, 2.25 s) outlasts the trigger: the next line waits for it
  auto r = simText("WHEN $aa_iw[X] > 500 DO G00 Y1000\nG00 X1000\nR1 = 1\nM30\n");
  const double fire = 1.125;
  CHECK(r->moveStart('Y') == exact(fire));
  CHECK(r->lineTime(3) == exact(fire + 2.25));
  // a short body: the trigger is the last to finish
  auto s = simText("WHEN $aa_iw[X] > 500 DO G00 Y100\nG00 X1000\nR1 = 1\nM30\n");
  CHECK(s->lineTime(3) == exact(2.25));
  // a Posa in a body keeps running on its own
  auto p = simText("WHEN $aa_iw[X] > 500 DO G00 Posa[Y]=1000\nG00 X1000\nR1 = 1\nM30\n");
  CHECK(p->lineTime(3) == exact(2.25));
  CHECK(p->cycle() == exact(fire + 2.25));
}

TEST_CASE("sim: a long-form body runs its statements in order, taking their time") {
  auto m = machineWith([](machine::Machine& mm) { mm.mSequences[23] = {0.5, {}}; });
  auto r = simText("WHEN $aa_iw[X] > 10 DO\n  $aa_out[1] = 1\n  G04 F3\n  M23\n  $aa_out[1] = 0\nCANCEL\n"
                   "G00 X1000\nR1 = 1\nM30\n",
                   m);
  REQUIRE(r->diagnostics.empty());
  const double t = std::sqrt(10 / (A / 2));
  auto outs = r->events(EventKind::Output);
  REQUIRE(outs.size() == 2);
  CHECK(outs[0].t == exact(t));
  CHECK(outs[1].t == exact(t + 3.5));
  CHECK(r->lineTime(8) == exact(t + 3.5));
}

TEST_CASE("sim: G/F changes in a body are discarded at its end") {
  auto r = simText("G00\nWHEN $aa_iw[X] > 10 DO G01 Y10 F10\nG00 X100\nX0\nM30\n");
  const double trig = 2 * std::sqrt(100 / A);
  const double body = std::sqrt(10 / (A / 2)) + moveTime(10, 10, A);
  // the last X move is a rapid again (not G01 at F10)
  CHECK(r->cycle() == exact(body + trig));
}

TEST_CASE("sim: a three-level WHEN chain fires each level at its exact instant") {
  const char* prog = "WHEN $aa_iw[Y] > 50 DO\n"
                     "  $aa_out[1] = 1\n"
                     "CANCEL\n"
                     "WHEN $aa_iw[Z] < -20 DO G00 Y100\n"
                     "WHEN $aa_iw[X] > 10 DO G00 Z-100\n"
                     "G00 X1000\n"
                     "R1 = 1\n"
                     "M30\n";
  auto r = simText(prog);
  REQUIRE(r->diagnostics.empty());
  const double t1 = std::sqrt(10 / (A / 2));      // X passes 10
  const double t2 = t1 + std::sqrt(20 / (A / 2)); // Z passes -20
  const double t3 = t2 + std::sqrt(50 / (A / 2)); // Y passes 50 (half of its triangle)
  CHECK(r->whenTime("fired", 0) == exact(t1));
  CHECK(r->whenTime("fired", 1) == exact(t2));
  CHECK(r->whenTime("fired", 2) == exact(t3));
  auto outs = r->events(EventKind::Output);
  REQUIRE(outs.size() == 1);
  CHECK(outs[0].t == exact(t3));
  CHECK(r->lineTime(7) == exact(2.25));
  // when the first level never fires, the chain below it is never armed
  auto d = simText("WHEN $aa_iw[Y] > 50 DO\n  $aa_out[1] = 1\nCANCEL\nWHEN $aa_iw[Z] < -20 DO G00 Y100\n"
                   "WHEN $aa_iw[X] > 5000 DO G00 Z-100\nG00 X1000\nM30\n");
  CHECK(d->count(EventKind::When) == 2); // armed, dropped
  CHECK(d->count(EventKind::Output) == 0);
}

TEST_CASE("sim: a body that moves the trigger axis is an emergency") {
  auto r = simText("WHEN $aa_iw[X] > 10 DO G00 X0\nG00 X1000\nM30\n");
  CHECK(r->status() == Status::Emergency);
  CHECK(r->message().find("axis X programmed while moving") != std::string::npos);
  CHECK(r->cycle() == exact(std::sqrt(10 / (A / 2))));
}

TEST_CASE("sim: WHEN conditions see inputs and outputs as they change") {
  auto m = machineFromJson(R"({"axes": [{"name": "X", "max_velocity": 500, "max_accel": 2000,
      "limit_minus": -1000, "limit_plus": 3000}], "inputs": {"2": [[1.5, 1]]}})");
  auto r = simText("WHEN ($aa_iw[X] > 10) AND ($aa_in[2] == 1) DO $aa_out[1] = 1\nG00 X1000\nM30\n", m);
  CHECK(r->whenTime("fired") == exact(1.5));
}

TEST_CASE("sim: a WHEN on an arc fires where the circle crosses the condition") {
  // centre (0,0), r = 100, from (100,0) counter-clockwise: y = 100·sin(s/100) reaches 50 at
  // s = 100·π/6; at F = 100 the path ramps 0.05 s (2.5 mm) and then cruises
  const double pi = std::acos(-1.0);
  auto r = simText("G00 X100\nWHEN $aa_iw[Y] > 50 DO $aa_out[1] = 1\nG03 X0 Y100 I-100 J0 F100\nM30\n");
  REQUIRE(r->diagnostics.empty());
  const double t0 = 2 * std::sqrt(100 / A); // the rapid to X100
  CHECK(r->whenTime("fired") == exact(t0 + 0.05 + (100 * pi / 6 - 2.5) / 100));
}
