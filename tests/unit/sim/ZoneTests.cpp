//! @file ZoneTests.cpp
//! @brief Crash zones of the machine file: the entry instant on the commanded path, by hand, for
//!        a line, arcs and a rapid whose axes run on their own profiles; exact to 1e-9 relative.
#include <cmath>
#include <limits>
#include <string>

#include <doctest/doctest.h>

#include "SimTestUtil.h"

using namespace iso;
using namespace iso::test;
using sim::EventKind;
using sim::Status;

namespace {
constexpr double V = 500, A = 2000; // the built-in machine, every axis
constexpr double kInf = std::numeric_limits<double>::infinity();
const double kPi = std::acos(-1.0);

/// The time a rest-to-rest trapezoid (distance d, speed v, acceleration a) takes to cover s.
double timeAlong(double s, double d, double v, double a) {
  const double vp = std::min(v, std::sqrt(a * d)); // the peak speed
  const double ta = vp / a, sa = vp * vp / (2 * a);
  if (s <= sa) return std::sqrt(2 * s / a);
  if (s <= d - sa) return ta + (s - sa) / vp;
  const double total = 2 * ta + (d - 2 * sa) / vp;
  return total - std::sqrt(2 * (d - s) / a);
}

machine::Machine withZone(const char* name, bool forbidden, std::vector<machine::ZoneAxis> box) {
  return machineWith([&](machine::Machine& m) { m.zones.push_back(machine::Zone{name, forbidden, std::move(box)}); });
}
} // namespace

TEST_CASE("zones: a G01 line enters a forbidden box when it is inside on every axis") {
  // X 0 -> 100 and Y 0 -> 100 at F100: u = (1, 1)/sqrt 2, V = 100, A = 2000·sqrt 2; the box
  // X 40..60, Y 50..70 is entered when Y reaches 50 (X is 50 then, inside already)
  auto m = withZone("morsa", true, {{'X', 40, 60}, {'Y', 50, 70}});
  auto r = simText("G01 X100 Y100 F100\nM30\n", m);
  REQUIRE(r->diagnostics.empty());
  const double L = 100 * std::sqrt(2.0), a = A * std::sqrt(2.0);
  const double t = timeAlong(50 * std::sqrt(2.0), L, 100, a);
  CHECK(r->status() == Status::Emergency);
  CHECK(r->cycle() == exact(t));
  CHECK(r->pos('X') == exact(50));
  CHECK(r->pos('Y') == exact(50));
  CHECK(r->message().find(":1: emergency at t=") != std::string::npos);
  CHECK(r->message().find("enters the forbidden zone 'morsa'") != std::string::npos);
  const auto zones = r->events(EventKind::Zone);
  REQUIRE(zones.size() == 1);
  CHECK(zones[0].t == exact(t));
  CHECK(zones[0].forbidden);
  CHECK(zones[0].line == 1);
  REQUIRE(zones[0].zonePosition.size() == 2);
  CHECK(zones[0].zonePosition[1] == exact(50));
}

TEST_CASE("zones: a G03 arc enters a warn box where the later of its bounds holds") {
  // G00 to (100, 0), then a quarter circle r = 100 about the origin at F100 (V = 100, A =
  // 2000, L = 50π). The box X <= 60, Y >= 50: Y >= 50 from φ = π/6 on, X <= 60 from
  // φ = acos(0.6) on; the entry is at s = 100·acos(0.6).
  auto m = withZone("probe", false, {{'X', -kInf, 60}, {'Y', 50, kInf}});
  auto r = simText("G00 X100 Y0\nG03 X0 Y100 I-100 J0 F100\nM30\n", m);
  REQUIRE(r->diagnostics.empty());
  CHECK(r->status() == Status::Ok);
  const double t0 = moveTime(100, V, A);
  const double t = t0 + timeAlong(100 * std::acos(0.6), 50 * kPi, 100, A);
  const auto zones = r->events(EventKind::Zone);
  REQUIRE(zones.size() == 1);
  CHECK(zones[0].t == exact(t));
  CHECK(zones[0].zone == "probe");
  CHECK_FALSE(zones[0].forbidden);
  CHECK(zones[0].line == 2);
  REQUIRE(zones[0].zonePosition.size() == 2);
  CHECK(zones[0].zonePosition[0] == exact(60));
  CHECK(zones[0].zonePosition[1] == exact(80));
  REQUIRE(r->summary().warnings.size() == 1);
  CHECK(r->summary().warnings[0].find("the tool entered zone 'probe' at ") != std::string::npos);
  CHECK(r->summary().warnings[0].find(":2 (t=") != std::string::npos);
}

TEST_CASE("zones: a G02 arc enters a forbidden box bounded on one axis") {
  // G00 Y100 (X stays 0), then clockwise about the origin to (100, 0): X = 100·cos φ with φ
  // from π/2 down; X >= 80 from φ = acos(0.8), at s = 100·(π/2 − acos(0.8))
  auto m = withZone("clamp", true, {{'X', 80, kInf}});
  auto r = simText("G00 Y100\nG02 X100 Y0 I0 J-100 F100\nM30\n", m);
  REQUIRE(r->diagnostics.empty());
  CHECK(r->status() == Status::Emergency);
  const double t0 = moveTime(100, V, A);
  const double t = t0 + timeAlong(100 * (kPi / 2 - std::acos(0.8)), 50 * kPi, 100, A);
  CHECK(r->cycle() == exact(t));
  CHECK(r->pos('X') == exact(80));
  CHECK(r->pos('Y') == exact(60));
  CHECK(r->message().find(":2: emergency") != std::string::npos);
}

TEST_CASE("zones: a G00 rapid with two axes on their own profiles enters when the later axis does") {
  // Y at most 100 mm/s. X: 100 mm without a cruise, X >= 50 at sqrt(2·50/A) = 0.2236 s.
  // Y: V = 100, A = 2000, Y >= 50 at 0.05 + 47.5/100 = 0.525 s: the entry.
  auto m = withZone("morsa", true, {{'X', 50, kInf}, {'Y', 50, kInf}});
  m.axes[1].maxVelocity = 100;
  auto r = simText("G00 X100 Y100\nM30\n", m);
  REQUIRE(r->diagnostics.empty());
  CHECK(r->status() == Status::Emergency);
  CHECK(r->cycle() == exact(0.525));
  CHECK(r->pos('X') == 100); // X arrived at 2·sqrt(100/A) = 0.447 s
  CHECK(r->pos('Y') == exact(50));
  CHECK(r->message().find("enters the forbidden zone 'morsa'") != std::string::npos);
}

TEST_CASE("zones: a box never entered on every axis at once, and a machine without zones") {
  // X is in 20..40 from 0.1414 s to 0.2 s; Y reaches 50 only at 0.525 s: never both
  auto m = withZone("morsa", true, {{'X', 20, 40}, {'Y', 50, kInf}});
  m.axes[1].maxVelocity = 100;
  auto r = simText("G00 X100 Y100\nM30\n", m);
  CHECK(r->status() == Status::Ok);
  CHECK(r->events(EventKind::Zone).empty());
  CHECK(r->summary().warnings.empty());
  auto plain = simText("G00 X100 Y100\nM30\n");
  CHECK(plain->status() == Status::Ok);
  CHECK(plain->events(EventKind::Zone).empty());
}

TEST_CASE("zones: a warn zone gives one event per entry and one warning, at rest at the start too") {
  // out at F100 (X = 40 at 0.05 + 37.5/100 = 0.425 s), back from t1 = 100/100 + 100/A
  auto m = withZone("probe", false, {{'X', 40, 60}});
  auto r = simText("G01 X100 F100\nG01 X0\nM30\n", m);
  CHECK(r->status() == Status::Ok);
  const auto zones = r->events(EventKind::Zone);
  REQUIRE(zones.size() == 2);
  CHECK(zones[0].t == exact(0.425));
  CHECK(zones[0].line == 1);
  CHECK(zones[1].t == exact(1.05 + 0.425));
  CHECK(zones[1].line == 2);
  REQUIRE(r->summary().warnings.size() == 1);
  // a machine whose X starts inside: the entry is at t = 0, once while it stays there
  auto inside = withZone("probe", false, {{'X', 40, 60}});
  inside.axes[0].start = 50;
  auto s = simText("G01 X55 F100\nG04 F1\nM30\n", inside);
  const auto atStart = s->events(EventKind::Zone);
  REQUIRE(atStart.size() == 1);
  CHECK(atStart[0].t == 0);
  REQUIRE(atStart[0].zonePosition.size() == 1);
  CHECK(atStart[0].zonePosition[0] == 50);
}

TEST_CASE("zones: a full circle crosses a band three times, one entry each") {
  // G02 full circle r = 50 about (50, 0) from the origin at F100 (V = 100, L = 100π):
  // φ runs from π down to −π; |Y| <= 10 while |sin φ| <= 0.2: inside at the start, again
  // from φ = asin(0.2) (s = 50·(π − asin 0.2)) and from φ = −π + asin(0.2) (s = 50·(2π − asin 0.2))
  auto m = withZone("band", false, {{'Y', -10, 10}});
  auto r = simText("G02 X0 Y0 I50 J0 F100\nM30\n", m);
  REQUIRE(r->diagnostics.empty());
  CHECK(r->status() == Status::Ok);
  const double L = 100 * kPi, a = std::asin(0.2);
  const auto zones = r->events(EventKind::Zone);
  REQUIRE(zones.size() == 3);
  CHECK(zones[0].t == 0);
  CHECK(zones[1].t == exact(timeAlong(50 * (kPi - a), L, 100, A)));
  CHECK(zones[2].t == exact(timeAlong(50 * (2 * kPi - a), L, 100, A)));
  CHECK(zones[1].zonePosition[0] == exact(10));
  CHECK(zones[2].zonePosition[0] == exact(-10));
  CHECK(r->summary().warnings.size() == 1);
}

TEST_CASE("zones: in a G64 path the entry is found on the block that reaches the zone") {
  // two collinear blocks X 0 -> 50 -> 100 at F100 blend into one trapezoid (V = 100, A = 2000):
  // X = 70 at 0.05 + 67.5/100 = 0.725 s, on the second block
  auto m = withZone("morsa", true, {{'X', 70, kInf}});
  auto r = simText("G64 G01 X50 F100\nG01 X100\nM30\n", m);
  REQUIRE(r->diagnostics.empty());
  CHECK(r->status() == Status::Emergency);
  CHECK(r->cycle() == exact(0.725));
  CHECK(r->pos('X') == exact(70));
  CHECK(r->message().find(":2: emergency") != std::string::npos);
  // the same path without the zone ends at 100/100 + 100/A
  auto plain = simText("G64 G01 X50 F100\nG01 X100\nM30\n");
  CHECK(plain->cycle() == exact(1.05));
}
