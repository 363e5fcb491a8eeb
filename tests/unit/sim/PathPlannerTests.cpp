//! @file PathPlannerTests.cpp
//! @brief G64 chain planning against hand-computed closed forms (SPEC §5.2).
#include <cmath>

#include <doctest/doctest.h>

#include "sim/PathPlanner.h"

using namespace iso::sim;

namespace {
PlanBlock line(double dx, double dy, double feed, double vx, double vy, double ax, double ay) {
  LineLimits l = lineLimits({dx, dy}, {vx, vy}, {ax, ay}, feed);
  PlanBlock b;
  b.length = l.length;
  b.vmax = l.vmax;
  b.accel = l.accel;
  b.uStart = l.dir;
  b.uEnd = l.dir;
  return b;
}
double total(const std::vector<PlannedBlock>& p) {
  double t = 0;
  for (const auto& b : p)
    t += b.profile.duration();
  return t;
}
} // namespace

TEST_CASE("planner: the SPEC corner example (X 100 then Y 100 at F=100)") {
  auto plan =
      planChain({line(100, 0, 100, 500, 500, 2000, 1000), line(0, 100, 100, 500, 500, 2000, 1000)}, {2000, 1000}, 0.05);
  REQUIRE(plan.size() == 2);
  // 90 degree corner: s = sin(45°), ĵ = (-1, 1)/√2, a_j = min(2000, 1000)·√2
  double s = std::sqrt(0.5);
  double aj = 1000 * std::sqrt(2.0);
  double vj = std::sqrt(aj * 0.05 * s / (1 - s));
  CHECK(plan[0].vExit == doctest::Approx(vj).epsilon(1e-12));
  CHECK(plan[1].vEntry == doctest::Approx(vj).epsilon(1e-12));
  CHECK(vj == doctest::Approx(13.066).epsilon(1e-4));
  CHECK(plan[0].exitBound == JunctionBound::Corner);
  // block 1: accelerate 0->100 at 2000, cruise, brake 100->vj at 2000
  double t1 = 100.0 / 2000 + (100 - vj) / 2000 + (100 - 2.5 - (100 * 100 - vj * vj) / 4000) / 100;
  // block 2: accelerate vj->100 at 1000, cruise, brake 100->0 at 1000
  double t2 = (100 - vj) / 1000 + 0.1 + (100 - (100 * 100 - vj * vj) / 2000 - 5) / 100;
  CHECK(plan[0].profile.duration() == doctest::Approx(t1).epsilon(1e-12));
  CHECK(plan[1].profile.duration() == doctest::Approx(t2).epsilon(1e-12));
  CHECK(total(plan) == doctest::Approx(2.131682).epsilon(1e-6));
}

TEST_CASE("planner: collinear blocks at the same feed equal one long block") {
  auto plan = planChain({line(30, 0, 200, 500, 500, 2000, 2000), line(50, 0, 200, 500, 500, 2000, 2000),
                         line(20, 0, 200, 500, 500, 2000, 2000)},
                        {2000, 2000}, 0.05);
  Trapezoid one = makeTrapezoid(100, 200, 2000);
  CHECK(total(plan) == doctest::Approx(one.duration()).epsilon(1e-12));
  CHECK(plan[1].entryBound == JunctionBound::Velocity);
}

TEST_CASE("planner: a reversal stops at the junction") {
  auto plan =
      planChain({line(10, 0, 100, 500, 500, 2000, 2000), line(-10, 0, 100, 500, 500, 2000, 2000)}, {2000, 2000}, 0.05);
  CHECK(plan[0].vExit == doctest::Approx(0.0));
  CHECK(total(plan) == doctest::Approx(2 * makeTrapezoid(10, 100, 2000).duration()).epsilon(1e-12));
}

TEST_CASE("planner: a short block limits its neighbours by acceleration") {
  // 0.01 mm middle block: the speed cannot change by more than sqrt(2·A·d) across it.
  auto plan = planChain({line(50, 0, 300, 500, 500, 2000, 2000), line(0.01, 0.01, 300, 500, 500, 2000, 2000),
                         line(0, 50, 300, 500, 500, 2000, 2000)},
                        {2000, 2000}, 0.05);
  for (const auto& b : plan) {
    double reach = std::sqrt(b.vEntry * b.vEntry + 2 * b.profile.accel * b.profile.distance);
    CHECK(b.vExit <= reach * (1 + 1e-12));
  }
  CHECK(plan.front().vEntry == 0.0);
  CHECK(plan.back().vExit == 0.0);
}

TEST_CASE("planner: a zig-zag lies between the G60 time and distance/feed") {
  std::vector<PlanBlock> blocks;
  double g60 = 0, dist = 0;
  for (int k = 0; k < 20; ++k) {
    blocks.push_back(line(10, k % 2 ? 3 : -3, 100, 500, 500, 2000, 2000));
    g60 += makeTrapezoid(blocks.back().length, blocks.back().vmax, blocks.back().accel).duration();
    dist += blocks.back().length;
  }
  double t = total(planChain(blocks, {2000, 2000}, 0.05));
  CHECK(t < g60);
  CHECK(t > dist / 100);
}
