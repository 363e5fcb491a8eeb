//! @file TimingTests.cpp
//! @brief Closed-form timing of everything that takes time (SPEC §5.2, §5.3, §6.1), exact to
//!        1e-9 relative; positions sampled mid-profile against the formulas.
#include <algorithm>
#include <cmath>

#include <doctest/doctest.h>

#include "SimTestUtil.h"

using namespace iso;
using namespace iso::test;
using sim::EventKind;
using sim::Status;

namespace {
constexpr double V = 500, A = 2000; // the built-in machine, every axis
} // namespace

TEST_CASE("sim: one-axis rapid with a cruise phase") {
  // d = 1000 >= V²/A = 125: t = d/V + V/A
  auto r = simText("G00 X1000\nM30\n");
  REQUIRE(r->diagnostics.empty());
  CHECK(r->status() == Status::Ok);
  CHECK(r->cycle() == exact(1000 / V + V / A));
  CHECK(r->pos('X') == 1000);
  CHECK(r->moveEnd('X') == exact(2.25));
}

TEST_CASE("sim: one-axis rapid without a cruise phase") {
  // d = 100 < V²/A: t = 2·sqrt(d/A)
  auto r = simText("G00 X-100\nM30\n");
  CHECK(r->cycle() == exact(2 * std::sqrt(100 / A)));
  CHECK(r->pos('X') == -100);
}

TEST_CASE("sim: multi-axis rapid: every axis at its own limits, the block ends with the slowest") {
  auto m = machineWith([](machine::Machine& mm) {
    mm.axes[1].maxVelocity = 100; // Y
    mm.axes[2].maxAccel = 500;    // Z
  });
  auto r = simText("G00 X300 Y300 Z-60\nM30\n", m);
  const double tx = moveTime(300, 500, 2000), ty = moveTime(300, 100, 2000), tz = moveTime(60, 500, 500);
  CHECK(r->moveEnd('X') == exact(tx));
  CHECK(r->moveEnd('Y') == exact(ty));
  CHECK(r->moveEnd('Z') == exact(tz));
  CHECK(r->cycle() == exact(std::max({tx, ty, tz})));
  CHECK(r->moveStart('X') == 0);
  CHECK(r->moveStart('Y') == 0);
}

TEST_CASE("sim: interpolated G01 limited by the feed") {
  // L = 500, u = (0.6, 0.8): V = min(100, 500/0.6, 500/0.8) = 100, A = min(2000/0.6, 2000/0.8) = 2500
  auto r = simText("G01 X300 Y400 F100\nM30\n");
  const double L = 500, v = 100, a = 2000 / 0.8;
  CHECK(r->cycle() == exact(L / v + v / a));
  CHECK(r->moveEnd('X') == r->moveEnd('Y')); // they arrive together
}

TEST_CASE("sim: interpolated G01 limited by one axis' velocity") {
  auto m = machineWith([](machine::Machine& mm) { mm.axes[1].maxVelocity = 50; });
  auto r = simText("G01 X300 Y400 F1000\nM30\n", m);
  const double v = 50 / 0.8, a = 2000 / 0.8; // Y bounds V: 62.5 mm/s along the path
  CHECK(r->cycle() == exact(moveTime(500, v, a)));
  CHECK(r->cycle() == exact(500 / v + v / a));
}

TEST_CASE("sim: interpolated G01 limited by one axis' acceleration") {
  auto m = machineWith([](machine::Machine& mm) { mm.axes[1].maxAccel = 100; });
  auto r = simText("G01 X300 Y400 F100\nM30\n", m);
  const double v = 100, a = 100 / 0.8; // Y bounds A: 125 mm/s² along the path
  CHECK(r->cycle() == exact(500 / v + v / a));
  // with a short path the same limits give a triangle
  auto t = simText("G01 X3 Y4 F100\nM30\n", m);
  CHECK(t->cycle() == exact(2 * std::sqrt(5 / a)));
}

TEST_CASE("sim: interpolated G01 over three axes counts rotary degrees in the path") {
  auto r = simText("G01 X100 Y200 A200 F150\nM30\n");
  const double L = 300; // sqrt(100² + 200² + 200²)
  const double a = 2000 / (200 / L);
  CHECK(r->cycle() == exact(moveTime(L, 150, a)));
}

TEST_CASE("sim: G01 with Fa is independent: each axis at its Fa or F") {
  auto r = simText("G01 X100 Y100 Fa[Y]=20 F=50\nM30\n");
  CHECK(r->moveEnd('X') == exact(moveTime(100, 50, A)));
  CHECK(r->moveEnd('Y') == exact(moveTime(100, 20, A)));
  CHECK(r->cycle() == exact(100.0 / 20 + 20 / A));
  // Fa above the axis' max velocity is capped
  auto c = simText("G01 X1000 Fa[X]=900\nM30\n");
  CHECK(c->cycle() == exact(1000 / V + V / A));
}

TEST_CASE("sim: G01 with four or more axes is independent") {
  auto r = simText("G01 X100 Y200 Z300 A400 F100\nM30\n");
  for (char ax : {'X', 'Y', 'Z', 'A'}) {
    const double d = 100.0 * (ax == 'X' ? 1 : ax == 'Y' ? 2 : ax == 'Z' ? 3 : 4);
    CAPTURE(ax);
    CHECK(r->moveEnd(ax) == exact(d / 100 + 100 / A));
  }
  CHECK(r->cycle() == exact(400.0 / 100 + 100 / A));
}

TEST_CASE("sim: Posa overlaps the blocks after it - M30 waits for it") {
  auto r = simText("G00 Posa[X]=1000\nG00 Y100\nG04 F1\nM30\n");
  const double tx = 1000 / V + V / A, ty = 2 * std::sqrt(100 / A);
  CHECK(r->moveStart('Y') == 0); // the next line ran at once
  CHECK(r->lineTime(3) == exact(ty));
  CHECK(r->lineTime(4) == exact(ty + 1));
  CHECK(r->cycle() == exact(std::max(tx, ty + 1)));
  CHECK(r->cycle() == exact(tx));
  // a Posa axis still moving at M30
  auto m30 = simText("G01 Posa[Z]=-200 F10\nM30\n");
  CHECK(m30->cycle() == exact(200.0 / 10 + 10 / A));
}

TEST_CASE("sim: G91 chains accumulate on the final position") {
  auto r = simText("G91 G01 F100\nX10\nX10\nX-30\nG90 X5\nM30\n");
  // X: 0 -> 10 -> 20 -> -10, then G90 X5 (15 mm)
  const double t10 = moveTime(10, 100, A), t30 = moveTime(30, 100, A), t15 = moveTime(15, 100, A);
  CHECK(r->cycle() == exact(2 * t10 + t30 + t15));
  CHECK(r->pos('X') == 5);
  // G91 targets the final position: after a Posa, the next G91 move starts from its end
  auto p = simText("G91 G00 Posa[X]=100\nR1 = $aa_fw[X]\nIF R1 <> 100 GOTOF Bad\nM30\nBad: G00 Y1\nM30\n");
  CHECK(p->pos('Y') == 0);
}

TEST_CASE("sim: dwell") {
  auto r = simText("G04 F1.5\nR1 = 0.25\nG04 F=R1\nM30\n");
  CHECK(r->cycle() == exact(1.75));
  auto d = r->events(EventKind::Dwell);
  REQUIRE(d.size() == 2);
  CHECK(d[1].t == exact(1.5));
  CHECK(d[1].duration == exact(0.25));
  // G04 does not wait for non-blocking axes
  auto nb = simText("G00 Posa[X]=1000\nG04 F0.5\nR1 = 1\nM30\n");
  CHECK(nb->lineTime(3) == exact(0.5));
  CHECK(nb->cycle() == exact(2.25));
}

TEST_CASE("sim: blocking and non-blocking M with durations and input effects") {
  auto m = machineWith([](machine::Machine& mm) {
    mm.mSequences[23] = {0.5, {{27, 1}}};
    mm.mSequences[34] = {2.0, {{5, 1}}};
    mm.defaultMDurationS = 0.125;
  });
  // blocking: the next line runs at the end of the sequence
  auto b = simText("M23\nG00 X1000\nM30\n", m);
  CHECK(b->lineTime(2) == exact(0.5));
  CHECK(b->cycle() == exact(0.5 + 2.25));
  // non-blocking: the program goes on; the sequence sets its input at its end
  auto nb = simText("M=NB(34)\nG00 X100\nR1 = $aa_in[5]\nM30\n", m);
  CHECK(nb->lineTime(2) == 0);
  CHECK(nb->cycle() == exact(2.0)); // M30 waits for the sequence
  auto in = nb->events(EventKind::Input);
  REQUIRE(in.size() == 1);
  CHECK(in[0].t == exact(2.0));
  CHECK(in[0].index == 5);
  // starting a running sequence first waits for it
  auto again = simText("M=NB(34)\nM34\nM30\n", m);
  CHECK(again->lineTime(2) == 0);
  CHECK(again->cycle() == exact(4.0));
  auto ms = again->events(EventKind::MStart);
  REQUIRE(ms.size() == 2);
  CHECK(ms[1].t == exact(2.0));
  // an M without a model takes default_m_duration_s and is listed in the warnings
  auto dflt = simText("M77\nM77\nM30\n", m);
  CHECK(dflt->cycle() == exact(0.25));
  REQUIRE(dflt->summary().warnings.size() == 1);
  CHECK(dflt->summary().warnings[0].find("M77") != std::string::npos);
  // M functions run before the motion of their line (SPEC §4.5)
  auto order = simText("G00 X1000 M23\nM30\n", m);
  CHECK(order->moveStart('X') == exact(0.5));
  CHECK(order->cycle() == exact(0.5 + 2.25));
}

TEST_CASE("sim: M30 waits for running axes and sequences") {
  auto m = machineWith([](machine::Machine& mm) { mm.mSequences[40] = {3.0, {}}; });
  auto seq = simText("M=NB(40)\nG00 X100\nM30\n", m);
  CHECK(seq->cycle() == exact(3.0));
  auto both = simText("M=NB(40)\nG01 Posa[Y]=400 F100\nM30\n", m);
  CHECK(both->cycle() == exact(400.0 / 100 + 100 / A));
  // G00 X0 M30 on one line ends after the move
  auto line = simText("G00 X100 M30\n");
  CHECK(line->cycle() == exact(2 * std::sqrt(100 / A)));
  // the end of the main program without M30 also waits, and warns
  auto implicitEnd = simText("G00 Posa[X]=100\n");
  CHECK(implicitEnd->status() == Status::Ok);
  CHECK(implicitEnd->cycle() == exact(2 * std::sqrt(100 / A)));
  REQUIRE(implicitEnd->summary().warnings.size() == 1);
  CHECK(implicitEnd->summary().warnings[0].find("without M30") != std::string::npos);
}

TEST_CASE("sim: M0 waits m0_wait_s") {
  auto m = machineWith([](machine::Machine& mm) { mm.m0WaitS = 1.25; });
  auto r = simText("M0\nM30\n", m);
  CHECK(r->cycle() == exact(1.25));
  auto st = r->events(EventKind::Stop);
  REQUIRE(st.size() == 1);
  CHECK(st[0].duration == exact(1.25));
}

TEST_CASE("sim: block_time_s is charged at the start of each statement") {
  auto m = machineWith([](machine::Machine& mm) { mm.blockTimeS = 0.01; });
  // statements: R1, IF, R2 (skipped by the IF? no: runs), ELSE, ENDIF, G00, M30 -- count them
  auto r = simText("R1 = 1\n; comment\n\nIF R1 == 1\n  R2 = 2\nELSE\n  R2 = 3\nENDIF\nG00 X100\nM30\n", m);
  // executed statements: R1, IF, R2=2, ELSE, ENDIF, G00, M30 = 7 (blank/comment lines are free)
  CHECK(r->summary().blocks == 7);
  CHECK(r->lineTime(9) == exact(5 * 0.01)); // the line event is at the start of the statement
  CHECK(r->cycle() == exact(6 * 0.01 + 2 * std::sqrt(100 / A) + 0.01));
}

TEST_CASE("sim: arcs at the path feed (quarter and full circle)") {
  const double pi = std::acos(-1.0);
  // quarter circle r = 100 at F = 100: L = 50π, V = min(F, vmax, sqrt(r·amax)) = 100
  auto q = simText("G00 X100 Y0\nG03 X0 Y100 I-100 J0 F100\nM30\n");
  const double t0 = moveTime(100, V, A);
  CHECK(q->cycle() == exact(t0 + 50 * pi / 100 + 100 / A));
  CHECK(q->pos('X') == 0);
  CHECK(q->pos('Y') == 100);
  // full circle (I/J and end = start) with the centripetal limit binding: r = 10 ->
  // sqrt(10·2000) = 141.42 < F = 400
  auto f = simText("G02 X0 Y0 I10 J0 F400\nM30\n");
  const double vc = std::sqrt(10 * A);
  CHECK(f->cycle() == exact(moveTime(20 * pi, vc, A)));
  // CR form: a semicircle from (0,0) to (20,0), radius 10, CCW (below the chord)
  auto cr = simText("G03 X20 Y0 CR=10 F50\nM30\n");
  CHECK(cr->cycle() == exact(moveTime(10 * pi, 50, A)));
}

TEST_CASE("sim: arcs with and without the centripetal limit, in every plane, CR over 180 degrees") {
  const double pi = std::acos(-1.0);
  // quarter circle r = 5 at F = 400: sqrt(r·amax) = 100 binds
  auto q = simText("G00 X5\nG03 X0 Y5 I-5 J0 F400\nM30\n");
  CHECK(q->cycle() == exact(moveTime(5, V, A) + moveTime(2.5 * pi, 100, A)));
  CHECK(q->pos('X') == doctest::Approx(0).epsilon(1e-12));
  CHECK(q->pos('Y') == 5);
  // full circle r = 50 at F = 100: sqrt(50·2000) = 316 does not bind; every sample lies on it
  auto f = simText("G02 X0 Y0 I50 J0 F100\nM30\n");
  CHECK(f->cycle() == exact(moveTime(100 * pi, 100, A)));
  REQUIRE(f->rec.samples.size() > 100);
  double worst = 0;
  for (const auto& row : f->rec.samples)
    worst = std::max(worst, std::fabs(std::hypot(row[1] - 50, row[2]) - 50));
  CHECK(worst < 1e-9);
  // G18 (p = Z, q = X, centre by K and I) and G19 (p = Y, q = Z, centre by J and K): quarters
  auto g18 = simText("G18 G02 Z100 X100 K100 I0 F100\nM30\n");
  CHECK(g18->cycle() == exact(moveTime(50 * pi, 100, A)));
  CHECK(g18->pos('Z') == exact(100));
  CHECK(g18->pos('X') == exact(100));
  auto g19 = simText("G19 G02 Y100 Z100 J100 K0 F100\nM30\n");
  CHECK(g19->cycle() == exact(moveTime(50 * pi, 100, A)));
  CHECK(g19->pos('Y') == exact(100));
  CHECK(g19->pos('Z') == exact(100));
  // CR = +10 takes the short way (90°), CR = -10 the long way (270°)
  auto minor = simText("G03 X10 Y10 CR=10 F50\nM30\n");
  CHECK(minor->cycle() == exact(moveTime(5 * pi, 50, A)));
  auto major = simText("G03 X10 Y10 CR=-10 F50\nM30\n");
  CHECK(major->cycle() == exact(moveTime(15 * pi, 50, A)));
  // the axis velocity limit binds a large arc: r = 1000, F = 600 > 500 mm/s of X and Y
  auto big = simText("G00 X1000\nG03 X-1000 Y0 I-1000 J0 F600\nM30\n");
  CHECK(big->cycle() == exact(moveTime(1000, V, A) + moveTime(1000 * pi, V, A)));
}

TEST_CASE("sim: positions sampled mid-profile follow the trapezoid") {
  sim::SimOptions o;
  o.dt = 0.05;
  auto r = simText("G00 X1000\nM30\n", builtin(), o);
  // accelerate for V/A = 0.25 s (62.5 mm), cruise to T − 0.25, decelerate; T = 2.25
  const double T = 2.25;
  auto xAt = [&](double t) {
    if (t <= 0.25) return A * t * t / 2;
    if (t <= T - 0.25) return 62.5 + V * (t - 0.25);
    const double s = T - t;
    return 1000 - A * s * s / 2;
  };
  int checked = 0;
  for (const auto& row : r->rec.samples) {
    CAPTURE(row[0]);
    CHECK(row[1] == exact(xAt(row[0])));
    ++checked;
  }
  CHECK(checked == 46); // k·0.05 for k = 0..45, and 2.25 is itself a sample time
  // interpolated: each axis at its share of the path
  auto l = simText("G01 X300 Y400 F100\nM30\n", builtin(), o);
  const double a = 2500, v = 100, Tl = 5.04;
  auto sAt = [&](double t) {
    if (t <= v / a) return a * t * t / 2;
    if (t <= Tl - v / a) return v * v / (2 * a) + v * (t - v / a);
    const double s = Tl - t;
    return 500 - a * s * s / 2;
  };
  for (const auto& row : l->rec.samples) {
    CAPTURE(row[0]);
    CHECK(row[1] == exact(0.6 * sAt(row[0])));
    CHECK(row[2] == exact(0.8 * sAt(row[0])));
  }
}

TEST_CASE("sim: polling loops advance by interpolation cycles") {
  // the input goes to 1 at 1.2345 s: the loop leaves at the first ipo boundary at or after it
  auto m = machineFromJson(R"({"axes": [{"name": "X", "max_velocity": 500, "max_accel": 2000,
      "limit_minus": -1000, "limit_plus": 3000}], "inputs": {"3": [[0, 0], [1.2345, 1]]}})");
  auto r = simText("Wait: IF $aa_in[3] == 0 GOTOB Wait\nR1 = 1\nM30\n", m);
  const double leave = r->lineTime(2);
  CHECK(leave >= 1.2345);
  CHECK(leave < 1.2345 + 0.002);
  CHECK(leave == exact(618 * 0.002));
  // $aa_iw: X reaches 50 at sqrt(50/1000) while moving to 100 non-blocking
  auto iw = simText("G00 Posa[X]=100\nW: IF $aa_iw[X] < 50 GOTOB W\nR1 = 1\nM30\n");
  const double cross = std::sqrt(50 / (A / 2));
  const double left = iw->lineTime(3);
  CHECK(left >= cross);
  CHECK(left < cross + 0.002);
  CHECK(left == exact(std::ceil(cross / 0.002) * 0.002));
  // a real-time read always waits for the next boundary, strictly later
  auto one = simText("R1 = $aa_in[0]\nR2 = $aa_in[0]\nM30\n");
  CHECK(one->cycle() == exact(0.004));
  // 3.0 s is boundary 1500, never read as 2.9999999
  auto dw = simText("G04 F3\nR1 = $aa_out[0]\nM30\n");
  CHECK(dw->cycle() == exact(3.002));
}

TEST_CASE("sim: an input's value is its latest step or M effect - the M effect wins a tie") {
  auto m = machineFromJson(R"({"axes": [{"name": "X", "max_velocity": 500, "max_accel": 2000,
      "limit_minus": -1000, "limit_plus": 3000}],
      "m_sequences": {"23": {"duration_s": 1.0, "set_inputs": {"4": 0}}},
      "inputs": {"4": [[0, 0], [1.0, 1], [3.0, 0]]}})");
  // at t = 1 the schedule sets 1 and M23 sets 0: 0 wins
  auto r = simText("M23\nR1 = $aa_in[4]\nIF R1 == 0 GOTOF Ok\nG00 X1\nOk: M30\n", m);
  CHECK(r->pos('X') == 0);
}
