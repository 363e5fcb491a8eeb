//! @file MotionProfileTests.cpp
//! @brief Closed-form checks of trapezoids, line/arc limits and junction speeds (SPEC §5.2).
#include <algorithm>
#include <cmath>
#include <vector>

#include <doctest/doctest.h>

#include "sim/MotionProfile.h"

using doctest::Approx;
using iso::sim::SpeedBound;
using iso::sim::Trapezoid;

namespace {

Approx near(double x) { return Approx(x).epsilon(1e-9); }

const double kPi = std::acos(-1.0);

/// position(timeAt(s)) == s over the whole move, and timeAt(position(t)) == t while moving.
void checkInverse(const Trapezoid& p) {
  for (int i = 0; i <= 200; ++i) {
    const double s = p.distance * i / 200.0;
    CAPTURE(s);
    CHECK(p.position(p.timeAt(s)) == Approx(s).epsilon(1e-9).scale(p.distance));
  }
  for (int i = 1; i < 200; ++i) {
    const double t = p.duration() * i / 200.0;
    CAPTURE(t);
    CHECK(p.timeAt(p.position(t)) == Approx(t).epsilon(1e-9).scale(p.duration()));
  }
}

} // namespace

TEST_CASE("profile: rest to rest without cruise (d < V^2/A)") {
  // d = 100, V = 500, A = 2000: V²/A = 125 > d, so t = 2·sqrt(d/A) = 2·sqrt(0.05),
  // peak sqrt(A·d) = sqrt(200000), reached at sqrt(0.05) after d/2 = 50.
  const Trapezoid p = iso::sim::makeTrapezoid(100, 500, 2000);
  const double total = 2 * std::sqrt(0.05);
  CHECK(p.duration() == near(total));
  CHECK_FALSE(p.cruises());
  CHECK(p.vPeak == near(std::sqrt(200000.0)));
  CHECK(p.tAccelEnd == near(std::sqrt(0.05)));
  CHECK(p.tCruiseEnd == near(std::sqrt(0.05)));
  CHECK(p.sAccelEnd == near(50));
  // Mid-acceleration t = 0.1: s = A·t²/2 = 2000·0.01/2 = 10, v = A·t = 200.
  CHECK(p.position(0.1) == near(10));
  CHECK(p.velocity(0.1) == near(200));
  // Mid-deceleration t = T − 0.1: s = d − A·0.1²/2 = 90, v = A·0.1 = 200.
  CHECK(p.position(total - 0.1) == near(90));
  CHECK(p.velocity(total - 0.1) == near(200));
  // At the peak: s = 50, v = sqrt(200000).
  CHECK(p.position(std::sqrt(0.05)) == near(50));
  CHECK(p.velocity(std::sqrt(0.05)) == near(std::sqrt(200000.0)));
  // Inverse.
  CHECK(p.timeAt(10) == near(0.1));
  CHECK(p.timeAt(50) == near(std::sqrt(0.05)));
  CHECK(p.timeAt(90) == near(total - 0.1));
  // Clamping outside [0, T] and [0, d].
  CHECK(p.position(-1) == 0);
  CHECK(p.position(total + 1) == 100);
  CHECK(p.position(total) == 100);
  CHECK(p.velocity(-0.1) == 0);
  CHECK(p.velocity(total + 0.1) == 0);
  CHECK(p.timeAt(-5) == 0);
  CHECK(p.timeAt(0) == 0);
  CHECK(p.timeAt(100) == near(total));
  CHECK(p.timeAt(1e9) == near(total));
  checkInverse(p);
}

TEST_CASE("profile: rest to rest with cruise (d >= V^2/A)") {
  // d = 1000, V = 500, A = 2000: t = d/V + V/A = 2 + 0.25 = 2.25.
  // Accel 0..0.25 s over V²/(2A) = 62.5; cruise 0.25..2.0 s; decel 2.0..2.25 s.
  const Trapezoid p = iso::sim::makeTrapezoid(1000, 500, 2000);
  CHECK(p.duration() == near(2.25));
  CHECK(p.cruises());
  CHECK(p.vPeak == near(500));
  CHECK(p.tAccelEnd == near(0.25));
  CHECK(p.tCruiseEnd == near(2.0));
  CHECK(p.sAccelEnd == near(62.5));
  CHECK(p.sCruiseEnd == near(937.5));
  // Mid-acceleration t = 0.1: s = 2000·0.01/2 = 10, v = 200.
  CHECK(p.position(0.1) == near(10));
  CHECK(p.velocity(0.1) == near(200));
  // Mid-cruise t = 1.0: s = 62.5 + 500·(1.0 − 0.25) = 437.5, v = 500.
  CHECK(p.position(1.0) == near(437.5));
  CHECK(p.velocity(1.0) == near(500));
  // Mid-deceleration t = 2.1, σ = T − t = 0.15: s = d − A·σ²/2 = 1000 − 22.5, v = A·σ = 300.
  CHECK(p.position(2.1) == near(977.5));
  CHECK(p.velocity(2.1) == near(300));
  CHECK(p.timeAt(10) == near(0.1));
  CHECK(p.timeAt(437.5) == near(1.0));
  CHECK(p.timeAt(977.5) == near(2.1));
  CHECK(p.timeAt(62.5) == near(0.25));
  CHECK(p.timeAt(937.5) == near(2.0));
  // Exactly at the SPEC threshold d = V²/A = 125: both formulas give 2·sqrt(d/A) = 0.5.
  CHECK(iso::sim::makeTrapezoid(125, 500, 2000).duration() == near(0.5));
  checkInverse(p);
}

TEST_CASE("profile: inverse keeps relative precision near both ends") {
  const Trapezoid p = iso::sim::makeTrapezoid(1000, 500, 2000);
  // s = A·t²/2 → t = sqrt(2s/A); s = 1e-12 → t = sqrt(1e-15).
  CHECK(p.timeAt(1e-12) == near(std::sqrt(1e-15)));
  // s = d − 1e-9 → σ = sqrt(2·1e-9/A) = 1e-6 before the end.
  const double sigma = p.duration() - p.timeAt(1000 - 1e-9);
  CHECK(sigma == Approx(1e-6).epsilon(1e-6));
  // With a high entry speed the textbook root (−v + sqrt(v² + 2As))/A would cancel.
  const Trapezoid q = iso::sim::makeTrapezoid(10, 1e4, 1, 1e4, 1e4);
  CHECK(q.timeAt(1e-6) == near(1e-10));
}

TEST_CASE("profile: entry and exit speeds with cruise") {
  // d = 100, V = 100, A = 1000, v0 = 20, v1 = 50:
  // A·d + (v0²+v1²)/2 = 101450 > V² → cruise at 100.
  // accel (100−20)/1000 = 0.08 s over (10000−400)/2000 = 4.8;
  // decel (100−50)/1000 = 0.05 s over (10000−2500)/2000 = 3.75;
  // cruise (100 − 4.8 − 3.75)/100 = 0.9145 s; total 0.08 + 0.9145 + 0.05 = 1.0445.
  const Trapezoid p = iso::sim::makeTrapezoid(100, 100, 1000, 20, 50);
  CHECK(p.duration() == near(1.0445));
  CHECK(p.tAccelEnd == near(0.08));
  CHECK(p.tCruiseEnd == near(0.9945));
  CHECK(p.sAccelEnd == near(4.8));
  CHECK(p.sCruiseEnd == near(96.25));
  CHECK(p.velocity(0) == near(20));
  CHECK(p.velocity(p.duration()) == near(50));
  // t = 0.04: s = v0·t + A·t²/2 = 0.8 + 0.8 = 1.6, v = 20 + 40 = 60.
  CHECK(p.position(0.04) == near(1.6));
  CHECK(p.velocity(0.04) == near(60));
  // t = 0.5: s = 4.8 + 100·0.42 = 46.8.
  CHECK(p.position(0.5) == near(46.8));
  // σ = 0.02 before the end: s = d − (v1·σ + A·σ²/2) = 100 − 1.2 = 98.8, v = 50 + 20 = 70.
  CHECK(p.position(1.0445 - 0.02) == near(98.8));
  CHECK(p.velocity(1.0445 - 0.02) == near(70));
  CHECK(p.timeAt(1.6) == near(0.04));
  CHECK(p.timeAt(98.8) == near(1.0445 - 0.02));
  checkInverse(p);
}

TEST_CASE("profile: entry and exit speeds without cruise") {
  // d = 10, V = 500, A = 1000, v0 = 30, v1 = 10: peak² = A·d + (900+100)/2 = 10500 < V².
  // Accel distance (10500−900)/2000 = 4.8, decel distance (10500−100)/2000 = 5.2.
  const Trapezoid p = iso::sim::makeTrapezoid(10, 500, 1000, 30, 10);
  const double peak = std::sqrt(10500.0);
  CHECK_FALSE(p.cruises());
  CHECK(p.vPeak == near(peak));
  CHECK(p.tAccelEnd == near((peak - 30) / 1000));
  CHECK(p.duration() == near((2 * peak - 40) / 1000));
  CHECK(p.sAccelEnd == near(4.8));
  // t = 0.02: s = 30·0.02 + 500·0.0004 = 0.8.
  CHECK(p.position(0.02) == near(0.8));
  CHECK(p.velocity(0.02) == near(50));
  CHECK(p.position(p.tAccelEnd) == near(4.8));
  checkInverse(p);

  // Deceleration only: v0 = 100, v1 = 0, 2·A·d = v0² exactly → peak = v0, T = v0/A = 0.02.
  const Trapezoid stop = iso::sim::makeTrapezoid(1, 200, 5000, 100, 0);
  CHECK(stop.vPeak == near(100));
  CHECK(stop.tAccelEnd == 0);
  CHECK(stop.duration() == near(0.02));
  // t = 0.01: s = 100·0.01 − 2500·0.0001 = 0.75.
  CHECK(stop.position(0.01) == near(0.75));
  CHECK(stop.velocity(0.01) == near(50));
  checkInverse(stop);

  // Constant speed: v0 = v1 = V, all cruise: t = d/V.
  const Trapezoid cruise = iso::sim::makeTrapezoid(50, 100, 1000, 100, 100);
  CHECK(cruise.duration() == near(0.5));
  CHECK(cruise.position(0.2) == near(20));
}

TEST_CASE("profile: degenerate and infeasible inputs never give NaN") {
  const Trapezoid zero = iso::sim::makeTrapezoid(0, 500, 2000);
  CHECK(zero.duration() == 0);
  CHECK(zero.position(1) == 0);
  CHECK(zero.timeAt(0) == 0);
  CHECK(zero.timeAt(1) == 0);
  // Exit speed unreachable over d: clamped to sqrt(v0² + 2·A·d) = sqrt(2000).
  const Trapezoid up = iso::sim::makeTrapezoid(1, 1000, 1000, 0, 1000);
  CHECK(up.v1 == near(std::sqrt(2000.0)));
  CHECK(up.duration() == near(std::sqrt(2000.0) / 1000));
  // Entry too fast to stop: exit clamped to sqrt(v0² − 2·A·d) = sqrt(8000).
  const Trapezoid down = iso::sim::makeTrapezoid(1, 1000, 1000, 100, 0);
  CHECK(down.v1 == near(std::sqrt(8000.0)));
  CHECK(down.position(down.duration()) == 1);
  CHECK_FALSE(std::isnan(down.timeAt(0.5)));
}

TEST_CASE("profile: interpolated line bound by the feed") {
  // Δ = (30, 40, 0): L = 50, u = (0.6, 0.8, 0).
  // V = min(100, 500/0.6, 500/0.8) = 100 (feed); A = min(2000/0.6, 1000/0.8) = 1250 (Y).
  const iso::sim::LineLimits l = iso::sim::lineLimits({30, 40, 0}, {500, 500, 500}, {2000, 1000, 3000}, 100);
  CHECK(l.length == near(50));
  REQUIRE(l.dir.size() == 3);
  CHECK(l.dir[0] == near(0.6));
  CHECK(l.dir[1] == near(0.8));
  CHECK(l.dir[2] == 0);
  CHECK(l.vmax == near(100));
  CHECK(l.vBound == SpeedBound::Feed);
  CHECK(l.vAxis == -1);
  CHECK(l.accel == near(1250));
  CHECK(l.aAxis == 1);
}

TEST_CASE("profile: interpolated line bound by an axis velocity") {
  // u = (0.6, −0.8): V = min(1000, 300/0.6 = 500, 500/0.8 = 625) = 500 (X).
  const iso::sim::LineLimits l = iso::sim::lineLimits({-30, 40}, {300, 500}, {2000, 2000}, 1000);
  CHECK(l.dir[0] == near(-0.6));
  CHECK(l.vmax == near(500));
  CHECK(l.vBound == SpeedBound::AxisVelocity);
  CHECK(l.vAxis == 0);
  // A = min(2000/0.6, 2000/0.8) = 2500 (Y).
  CHECK(l.accel == near(2500));
  CHECK(l.aAxis == 1);
  // Infinite feed: the axes alone bound V.
  const iso::sim::LineLimits free = iso::sim::lineLimits({0, 0, 10}, {500, 500, 200}, {1, 1, 50}, INFINITY);
  CHECK(free.vmax == near(200));
  CHECK(free.vAxis == 2);
}

TEST_CASE("profile: interpolated line bound by an axis acceleration") {
  // u = (0.6, 0.8): A = min(1000/0.6 = 1666.67, 2000/0.8 = 2500) = 1000/0.6 (X).
  const iso::sim::LineLimits l = iso::sim::lineLimits({3, 4}, {500, 500}, {1000, 2000}, 50);
  CHECK(l.length == near(5));
  CHECK(l.accel == near(1000 / 0.6));
  CHECK(l.aAxis == 0);
  CHECK(l.vBound == SpeedBound::Feed);
  // One axis only: A and V are that axis' own.
  const iso::sim::LineLimits one = iso::sim::lineLimits({0, -7}, {500, 400}, {1000, 800}, 1e6);
  CHECK(one.length == near(7));
  CHECK(one.vmax == near(400));
  CHECK(one.accel == near(800));
  // Zero length: nothing bounds anything.
  const iso::sim::LineLimits none = iso::sim::lineLimits({0, 0}, {500, 500}, {1, 1}, 100);
  CHECK(none.length == 0);
  CHECK(none.vBound == SpeedBound::None);
  CHECK(none.aAxis == -1);
  CHECK(iso::sim::makeTrapezoid(none.length, none.vmax, none.accel).duration() == 0);
  // A tie between feed and an axis goes to the feed.
  CHECK(iso::sim::lineLimits({10, 0}, {100, 100}, {1, 1}, 100).vBound == SpeedBound::Feed);
}

TEST_CASE("profile: one moving axis gives exactly what the general line arithmetic gives") {
  // The general arithmetic, written out (the scaled norm, then each limit over |u|): the
  // planner skips it for one moving axis, so both must agree bit for bit.
  const double vmax = 437.3, amax = 1234.5;
  for (const double d : {7.0, -7.0, 0.1, -261.9, 1e-310, -1e-310, 1e300, -3.0e-5, 123456.789}) {
    CAPTURE(d);
    const double scale = std::fabs(d);
    const double y = d / scale;
    const double length = scale * std::sqrt(y * y);
    const double u = std::fabs(d / length);
    for (const double feed : {50.0, 1e6, double{INFINITY}}) {
      const iso::sim::LineLimits l = iso::sim::lineLimits({0, d, 0}, {500, vmax, 500}, {900, amax, 900}, feed);
      CHECK(l.length == length);
      CHECK(l.dir[1] == d / length);
      CHECK(l.dir[0] == 0);
      CHECK(l.dir[2] == 0);
      CHECK(l.vmax == std::min(feed, vmax / u));
      CHECK(l.vBound == (vmax / u < feed ? SpeedBound::AxisVelocity : SpeedBound::Feed));
      CHECK(l.vAxis == (vmax / u < feed ? 1 : -1));
      CHECK(l.accel == amax / u);
      CHECK(l.aAxis == 1);
    }
  }
  // Not finite: no length, as for more axes.
  CHECK(iso::sim::lineLimits({0, INFINITY}, {500, 500}, {1, 1}, 100).length == 0);
  CHECK(iso::sim::lineLimits({0, NAN}, {500, 500}, {1, 1}, 100).length == 0);
}

TEST_CASE("profile: arc limits") {
  // r = 100, quarter circle: d = 50π; sqrt(r·min(2000, 1000)) = 316.2 > F = 100 → feed.
  const iso::sim::ArcLimits a = iso::sim::arcLimits(100, kPi / 2, 100, 500, 400, 2000, 1000);
  CHECK(a.length == near(50 * kPi));
  CHECK(a.vmax == near(100));
  CHECK(a.vBound == SpeedBound::Feed);
  CHECK(a.accel == near(1000));
  CHECK(a.aAxis == 1);
  // Negative sweep (CW) gives the same length.
  CHECK(iso::sim::arcLimits(100, -kPi / 2, 100, 500, 400, 2000, 1000).length == near(50 * kPi));
  // r = 1: sqrt(1·1000) = 31.62 < F → centripetal.
  const iso::sim::ArcLimits c = iso::sim::arcLimits(1, 2 * kPi, 100, 500, 400, 2000, 1000);
  CHECK(c.length == near(2 * kPi));
  CHECK(c.vmax == near(std::sqrt(1000.0)));
  CHECK(c.vBound == SpeedBound::Centripetal);
  CHECK(c.vAxis == -1);
  // r = 1000: sqrt(1000·1000) = 1000 > vmax_q = 400 < F → axis q.
  const iso::sim::ArcLimits v = iso::sim::arcLimits(1000, 1, 1000, 500, 400, 1000, 1500);
  CHECK(v.vmax == near(400));
  CHECK(v.vBound == SpeedBound::AxisVelocity);
  CHECK(v.vAxis == 1);
  CHECK(v.accel == near(1000));
  CHECK(v.aAxis == 0);
}

TEST_CASE("profile: junction speed of the SPEC example") {
  // X 100 then Y 100 at F = 100, amax X 2000, Y 1000, δ = 0.05.
  // ĵ = (−1, 1)/√2 → a_j = min(2000·√2, 1000·√2) = 1000·√2; θ = 90°, s = √2/2:
  // v_j² = 1000·√2 · 0.05 · (√2/2)/(1 − √2/2) = 100 + 50·√2 → v_j = 13.0656...
  const double vj = iso::sim::junctionSpeed({1, 0}, {0, 1}, {2000, 1000}, 0.05, 100, 100);
  CHECK(vj == near(std::sqrt(100 + 50 * std::sqrt(2.0))));
  CHECK(vj == Approx(13.066).epsilon(1e-4));

  // Total time of the two-block chain: X accelerates to 100 and leaves at v_j (A = 2000);
  // Y enters at v_j and stops (A = 1000). SPEC: 2.131682 s.
  const Trapezoid x = iso::sim::makeTrapezoid(100, 100, 2000, 0, vj);
  const Trapezoid y = iso::sim::makeTrapezoid(100, 100, 1000, vj, 0);
  CHECK(x.duration() + y.duration() == Approx(2.131682).epsilon(1e-6));
}

TEST_CASE("profile: junction speed limits") {
  const std::vector<double> amax = {2000, 1000, 500};
  // Collinear: no junction limit.
  CHECK(iso::sim::junctionSpeed({1, 0, 0}, {1, 0, 0}, amax, 0.05, 80, 60) == 60);
  // Reversal: full stop.
  CHECK(iso::sim::junctionSpeed({1, 0, 0}, {-1, 0, 0}, amax, 0.05, 80, 60) == 0);
  // Zero direction: stop.
  CHECK(iso::sim::junctionSpeed({0, 0, 0}, {1, 0, 0}, amax, 0.05, 80, 60) == 0);
  // Large δ: the block speeds bound v_j.
  CHECK(iso::sim::junctionSpeed({1, 0, 0}, {0, 1, 0}, amax, 1e6, 80, 60) == 60);
  // A 30° turn in XZ, against the textbook formula with cos θ = −u_in·u_out.
  const double turn = kPi / 6;
  const std::vector<double> uIn = {1, 0, 0};
  const std::vector<double> uOut = {std::cos(turn), 0, std::sin(turn)};
  const double cosTheta = -std::cos(turn);
  const double s = std::sqrt((1 - cosTheta) / 2);
  const double jx = uOut[0] - uIn[0];
  const double jz = uOut[2] - uIn[2];
  const double jn = std::hypot(jx, jz);
  const double aj = std::min(2000 / (std::fabs(jx) / jn), 500 / (std::fabs(jz) / jn));
  const double expected = std::sqrt(aj * 0.02 * s / (1 - s));
  CHECK(iso::sim::junctionSpeed(uIn, uOut, amax, 0.02, 1e3, 1e3) == near(expected));
  // Non-unit inputs are normalised.
  CHECK(iso::sim::junctionSpeed({5, 0, 0}, {2 * std::cos(turn), 0, 2 * std::sin(turn)}, amax, 0.02, 1e3, 1e3) ==
        near(expected));
  // A tiny turn is limited only by the block speeds.
  CHECK(iso::sim::junctionSpeed({1, 0, 0}, {1, 1e-9, 0}, amax, 0.05, 80, 90) == 80);
  // A near reversal: s = sin(θ/2) ≈ 5e-7 without cancellation, a_j = 2000 (X),
  // v_j ≈ sqrt(2000·0.05·5e-7) = sqrt(5e-5).
  CHECK(iso::sim::junctionSpeed({1, 0, 0}, {-1, 1e-6, 0}, amax, 0.05, 80, 90) == Approx(std::sqrt(5e-5)).epsilon(1e-6));
}
