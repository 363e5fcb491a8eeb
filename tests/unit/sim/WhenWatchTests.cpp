//! @file WhenWatchTests.cpp
//! @brief The root search of WHEN watching: first instants to adjacent doubles (SPEC §4.4).
#include <cmath>
#include <functional>

#include <doctest/doctest.h>

#include "sim/WhenWatch.h"

using namespace iso::sim;

namespace {

/// A condition `t op c` of time alone, with one recorded comparison; counts its evaluations.
struct Threshold final : WhenCondition {
  std::function<bool(int)> test; ///< of cmpClass(t, c)
  double c = 0;
  mutable int evals = 0;
  bool holds(double t, int* classes, size_t* n) const override {
    ++evals;
    const int k = cmpClass(t, c);
    if (classes) {
      classes[0] = k;
      *n = 1;
    }
    return test(k);
  }
};

struct Throws final : WhenCondition {
  double from = 0;
  bool holds(double t, int*, size_t*) const override {
    if (t >= from) fault("R index 0 is outside 1..1000");
    return false;
  }
};

} // namespace

TEST_CASE("WHEN search: a threshold crossed between two samples, to adjacent doubles") {
  Threshold cond;
  cond.c = 0.123456789;
  cond.test = [](int k) { return k >= 0; };
  const WhenHit hit = searchCondition(cond, 0, 1, {}, 0.01);
  REQUIRE(hit.found);
  CHECK_FALSE(hit.error);
  CHECK(cond.holds(hit.t, nullptr, nullptr));
  CHECK_FALSE(cond.holds(std::nextafter(hit.t, 0.0), nullptr, nullptr));
  CHECK(hit.t == doctest::Approx(0.123456789).epsilon(1e-11));
}

TEST_CASE("WHEN search: an equality true only for a moment is found by its comparison's change") {
  Threshold cond;
  cond.c = 0.25;
  cond.test = [](int k) { return k == 0; };
  const WhenHit hit = searchCondition(cond, 0, 1, {}, 0.1);
  REQUIRE(hit.found);
  CHECK(cmpEqual(hit.t, 0.25));
}

TEST_CASE("WHEN search: nothing in the interval") {
  Threshold cond;
  cond.c = 2;
  cond.test = [](int k) { return k >= 0; };
  CHECK_FALSE(searchCondition(cond, 0, 1, {}, 0.1).found);
  // true at a, the start of the open interval, and never after it
  cond.c = 0;
  cond.test = [](int k) { return k <= 0; };
  CHECK_FALSE(searchCondition(cond, 0, 1, {}, 0.1).found);
}

TEST_CASE("WHEN search: the phase boundaries of a moving axis are sample points") {
  AxisMotion ax;
  ax.t0 = 0;
  ax.prof = makeTrapezoid(100, 100, 2000); // accelerates until 0.05 s, ends at 1.05 s
  ax.tEnd = ax.prof.duration();
  Threshold cond;
  cond.c = 0.05;
  cond.test = [](int k) { return k == 0; };
  // a grid coarser than the interval: only the phase boundary can see the equality
  const WhenHit hit = searchCondition(cond, 0, 2, {ax}, 10);
  REQUIRE(hit.found);
  CHECK(cmpEqual(hit.t, 0.05));
}

TEST_CASE("WHEN search: a fault reports the last sample before it") {
  Throws cond;
  cond.from = 0.35;
  const WhenHit hit = searchCondition(cond, 0, 1, {}, 0.1);
  REQUIRE(hit.found);
  CHECK(hit.error);
  CHECK(hit.fault.what == "R index 0 is outside 1..1000");
  CHECK(hit.t == doctest::Approx(0.3));
}
