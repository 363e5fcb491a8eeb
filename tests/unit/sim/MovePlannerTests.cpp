//! @file MovePlannerTests.cpp
//! @brief The pure move planner against hand-computed closed forms (SPEC §5.1–§5.3).
#include <cmath>
#include <limits>
#include <string>

#include <doctest/doctest.h>

#include "sim/FaultOf.h"
#include "sim/MovePlanner.h"
#include "sim/RunMath.h"

using namespace iso::sim;
using iso::machine::Axis;
using iso::machine::Machine;

namespace {

constexpr double kPi = 3.14159265358979323846;

/// X Y Z, each 500 mm/s and 2000 mm/s² (the built-in machine's limits).
struct Fixture {
  Machine m;
  std::vector<double> vmax, amax;
  double cur[kMaxMoveAxes] = {};
  Fixture() {
    for (char c : std::string("XYZ")) {
      Axis a;
      a.letter = c;
      m.axes.push_back(a);
      vmax.push_back(a.maxVelocity);
      amax.push_back(a.maxAccel);
    }
  }
  MoveLimits limits() const { return MoveLimits{&m, &vmax, &amax}; }
  MoveRequest request(uint8_t motion, double feed) const {
    MoveRequest rq;
    rq.motion = motion;
    rq.feed = feed;
    rq.cur = cur;
    return rq;
  }
};

void target(MoveWords& w, int axis, double v, bool nb = false) {
  w.prog |= 1u << axis;
  ++w.progCount;
  w.tgt[axis] = v;
  w.nb[axis] = nb;
  w.anyNb = w.anyNb || nb;
}

std::string faultOf(const MoveRequest& rq, const MoveLimits& lim) {
  return iso::sim::test::faultOf([&] { planMove(rq, lim); });
}

} // namespace

TEST_CASE("move planner: a G01 line at feed takes L/F + F/A (§5.2)") {
  Fixture f;
  MoveRequest rq = f.request(1, 100);
  target(rq.words, 0, 100);
  const MovePlan p = planMove(rq, f.limits());
  REQUIRE(p.path);
  CHECK(p.block.plan.length == doctest::Approx(100));
  CHECK(p.block.plan.vmax == doctest::Approx(100));
  CHECK(p.block.vBound == SpeedBound::Feed);
  REQUIRE(p.block.segs.size() == 1);
  CHECK(p.block.segs[0].axis == 0);
  CHECK(p.block.segs[0].seg.target == 100);
  const Trapezoid t = makeTrapezoid(p.block.plan.length, p.block.plan.vmax, p.block.plan.accel);
  CHECK(t.duration() == doctest::Approx(100.0 / 100 + 100.0 / 2000).epsilon(1e-12));
  CHECK(p.block.check == 1u);
  REQUIRE(p.block.limits.size() == 1);
  CHECK(p.block.limits[0].lo == 100);
}

TEST_CASE("move planner: a diagonal line splits the feed over its axes") {
  Fixture f;
  MoveRequest rq = f.request(1, 100);
  target(rq.words, 0, 30);
  target(rq.words, 1, 40);
  const MovePlan p = planMove(rq, f.limits());
  REQUIRE(p.block.segs.size() == 2);
  CHECK(p.block.plan.length == doctest::Approx(50));
  CHECK(p.block.segs[0].seg.scale == doctest::Approx(0.6));
  CHECK(p.block.segs[1].seg.scale == doctest::Approx(0.8));
}

TEST_CASE("move planner: a line that does not move needs no feed and has no length") {
  Fixture f;
  MoveRequest rq = f.request(1, std::numeric_limits<double>::quiet_NaN());
  target(rq.words, 0, 0);
  const MovePlan p = planMove(rq, f.limits());
  CHECK(p.path);
  CHECK(p.block.plan.length == 0);
  CHECK(p.block.segs.empty());
}

TEST_CASE("move planner: a G03 quarter circle by centre") {
  Fixture f;
  f.cur[0] = 10;
  MoveRequest rq = f.request(3, 100);
  target(rq.words, 0, 0);
  target(rq.words, 1, 10);
  rq.words.arcWord[0] = true; // I
  rq.words.arcVal[0] = -10;
  const MovePlan p = planMove(rq, f.limits());
  REQUIRE(p.path);
  CHECK(p.block.plan.length == doctest::Approx(10 * kPi / 2).epsilon(1e-12));
  REQUIRE(p.block.segs.size() == 2);
  CHECK(p.block.segs[0].seg.kind == SegKind::ArcP);
  CHECK(p.block.segs[1].seg.kind == SegKind::ArcQ);
  CHECK(p.block.segs[0].seg.start == 10);
  CHECK(p.block.segs[1].seg.target == 10);
  CHECK(p.block.check == 3u);
  // the start tangent of a counter-clockwise arc from (10, 0) around the origin is +Y
  CHECK(p.block.plan.uStart[1] == doctest::Approx(1));
  CHECK(p.block.plan.uEnd[0] == doctest::Approx(-1));
  // the extremes of the quarter: X in [0, 10], Y in [0, 10]
  REQUIRE(p.block.limits.size() == 2);
  CHECK(p.block.limits[0].hi == doctest::Approx(10));
  CHECK(p.block.limits[1].lo == doctest::Approx(0).epsilon(1e-12));
}

TEST_CASE("move planner: G00 moves each axis on its own at its limits") {
  Fixture f;
  MoveRequest rq = f.request(0, std::numeric_limits<double>::quiet_NaN());
  target(rq.words, 0, 100);
  target(rq.words, 1, -50, true);
  const MovePlan p = planMove(rq, f.limits());
  CHECK_FALSE(p.path);
  CHECK(p.check == 3u);
  REQUIRE(p.segs.size() == 2);
  // 100 mm never reaches 500 mm/s at 2000 mm/s²: a triangle of 2·sqrt(d/A)
  CHECK(p.segs[0].seg.tEnd == doctest::Approx(2 * std::sqrt(100.0 / 2000)).epsilon(1e-12));
  CHECK(p.segs[0].blocking);
  CHECK(p.segs[1].seg.scale == -1);
  CHECK_FALSE(p.segs[1].blocking);
}

TEST_CASE("move planner: G01 with Fa runs the axes independently, each at its feed") {
  Fixture f;
  MoveRequest rq = f.request(1, 100);
  target(rq.words, 0, 100);
  target(rq.words, 1, 100);
  rq.words.faMask = 2;
  rq.words.fa[1] = 50;
  const MovePlan p = planMove(rq, f.limits());
  CHECK_FALSE(p.path);
  REQUIRE(p.segs.size() == 2);
  CHECK(p.segs[0].seg.tEnd == doctest::Approx(1.0 + 100.0 / 2000));
  CHECK(p.segs[1].seg.tEnd == doctest::Approx(2.0 + 50.0 / 2000));
}

TEST_CASE("move planner: faults and the G00 Fa warning") {
  Fixture f;
  MoveRequest line = f.request(1, std::numeric_limits<double>::quiet_NaN());
  target(line.words, 0, 1);
  CHECK(faultOf(line, f.limits()) == "feed move without F: no F was ever set (F is modal, in mm/s)");
  MoveRequest arc = f.request(2, 100);
  target(arc.words, 0, 1);
  CHECK(faultOf(arc, f.limits()) == "arc (G02) without centre (I/J/K) or radius (CR)");
  MoveRequest fa = f.request(1, 100);
  target(fa.words, 0, 1);
  fa.words.faMask = 2;
  CHECK(faultOf(fa, f.limits()) == "Fa[Y] but axis Y does not move in this block");
  MoveRequest rapid = f.request(0, 100);
  target(rapid.words, 0, 1);
  rapid.words.faMask = 1;
  rapid.words.fa[0] = 10;
  CHECK(planMove(rapid, f.limits()).faIgnored);
}

TEST_CASE("move planner: decoding a move's operands") {
  Fixture f;
  f.cur[0] = 5;
  const std::vector<uint8_t> moves = {0x00, 0x11, 0x30};
  const double vals[] = {1, 2, 3};
  const std::vector<int> axisMap = {0, 1};
  const MoveWords w = decodeMove(moves, 0, 3, vals, axisMap, f.m, true, f.cur);
  CHECK(w.prog == 3u);
  CHECK(w.tgt[0] == 6);
  CHECK(w.nb[1]);
  CHECK(w.anyNb);
  CHECK(w.arcWord[0]);
  CHECK(w.arcVal[0] == 3);
  const std::vector<uint8_t> twice = {0x00, 0x00};
  CHECK_THROWS_AS(decodeMove(twice, 0, 2, vals, axisMap, f.m, false, f.cur), Fault);
}
