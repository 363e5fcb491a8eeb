//! @file G64Tests.cpp
//! @brief G64 continuous path in the simulator (SPEC §5.2): chains against closed forms —
//!        collinear blocks, the corner of the SPEC example, arcs, zig-zags, the look-ahead
//!        window, the stop points that end a chain, and statements read ahead.
#include <cmath>

#include <doctest/doctest.h>

#include "SimTestUtil.h"

using namespace iso;
using namespace iso::test;
using sim::EventKind;
using sim::Status;

namespace {
constexpr double A = 2000; // built-in axes: 500 mm/s, 2000 mm/s²

/// Time of a trapezoid over d that cruises at V, entering at v0 and leaving at v1.
double cruiseTime(double d, double V, double a, double v0, double v1) {
  const double up = (V - v0) / a, down = (V - v1) / a;
  const double dUp = (V * V - v0 * v0) / (2 * a), dDown = (V * V - v1 * v1) / (2 * a);
  REQUIRE(dUp + dDown <= d);
  return up + down + (d - dUp - dDown) / V;
}

/// Records the exact axis velocities the simulator reports with each sample.
class VelocitySink : public sim::TraceSink {
public:
  void begin(const machine::Machine& m) override { axes_ = m.axes.size(); }
  void sample(double, const double*) override {}
  void sampleWithVelocity(double t, const double*, const double* v) override {
    rows.push_back({t, std::vector<double>(v, v + axes_)});
  }
  void event(const sim::Event&) override {}
  void end(const sim::Summary&) override {}
  bool wantsVelocities() const override { return true; }
  struct Row {
    double t;
    std::vector<double> v;
  };
  std::vector<Row> rows;

private:
  size_t axes_ = 0;
};
} // namespace

TEST_CASE("g64: collinear blocks at the same feed equal one long block") {
  auto one = simText("G01 X100 F100\nM30\n");
  auto chain = simText("G64 G01 F100\nX25\nR1=3\nX50\nX100\nM30\n");
  REQUIRE(chain->diagnostics.empty());
  CHECK(one->cycle() == exact(moveTime(100, 100, A)));
  CHECK(chain->cycle() == exact(one->cycle()));
  CHECK(chain->pos('X') == 100);
  // the statement read ahead after X25 runs when the path passes X25: 0.05 s ramp + 22.5 mm
  CHECK(chain->lineTime(3) == exact(0.05 + 22.5 / 100));
  CHECK(chain->lineTime(4) == exact(0.275));
  CHECK(chain->lineTime(5) == exact(0.05 + 47.5 / 100));
  // a blended block arrives when the path passes its end: move_end X 25 then move_start X 50
  CHECK(chain->moveEnd('X', 0) == exact(0.275));
  CHECK(chain->moveStart('X', 1) == exact(0.275));
  CHECK(chain->summary().blocks == 3); // SPEC §5.3: lines 3-5 are read ahead, not charged nor counted
  // the same in G60 stops at every block end
  auto g60 = simText("G60 G01 F100\nX25\nR1=3\nX50\nX100\nM30\n");
  CHECK(g60->cycle() == exact(moveTime(25, 100, A) + moveTime(25, 100, A) + moveTime(50, 100, A)));
}

TEST_CASE("g64: a 90 degree corner runs at the junction-deviation speed (the SPEC example)") {
  const machine::Machine m = machineWith([](machine::Machine& mm) { mm.axes[1].maxAccel = 1000; });
  auto r = simText("G64 G01 X100 F100\nY100\nM30\n", m);
  REQUIRE(r->diagnostics.empty());
  // u_in = (1,0), u_out = (0,1): θ = 90°, s = sin 45°, ĵ = (−1,1)/√2,
  // a_j = min(2000·√2, 1000·√2), v_j² = a_j·δ·s/(1−s)
  const double s = std::sqrt(0.5);
  const double aj = 1000 * std::sqrt(2.0);
  const double vj = std::sqrt(aj * 0.05 * s / (1 - s));
  CHECK(vj == doctest::Approx(13.066).epsilon(1e-4));
  const double t1 = cruiseTime(100, 100, 2000, 0, vj);
  const double t2 = cruiseTime(100, 100, 1000, vj, 0);
  CHECK(r->lineTime(2) == exact(t1));
  CHECK(r->moveStart('Y') == exact(t1));
  CHECK(r->moveEnd('X') == exact(t1));
  CHECK(r->cycle() == exact(t1 + t2));
  CHECK(r->cycle() == doctest::Approx(2.131682).epsilon(1e-6));
  // a larger corner deviation allows a faster corner: still between the stop and no corner
  const machine::Machine wide = machineWith([](machine::Machine& mm) {
    mm.axes[1].maxAccel = 1000;
    mm.cornerDeviationMm = 1;
  });
  auto w = simText("G64 G01 X100 F100\nY100\nM30\n", wide);
  const double vj1 = std::sqrt(aj * 1.0 * s / (1 - s));
  CHECK(vj1 < 100);
  CHECK(w->cycle() == exact(cruiseTime(100, 100, 2000, 0, vj1) + cruiseTime(100, 100, 1000, vj1, 0)));
}

TEST_CASE("g64: the path speed at a corner is the junction speed, on both sides") {
  const machine::Machine m = machineWith([](machine::Machine& mm) { mm.axes[1].maxAccel = 1000; });
  auto set = loadText("G64 G01 X100 F100\nY100\nM30\n", "t.mpf", m, m.dialect);
  std::string diags;
  image::Image img = compileSet(*set, m, &diags);
  REQUIRE(diags.empty());
  VelocitySink vs;
  sim::SimOptions o;
  o.dt = 1e-4;
  test::runImage(img, m, o, &vs);
  const double s = std::sqrt(0.5);
  const double vj = std::sqrt(1000 * std::sqrt(2.0) * 0.05 * s / (1 - s));
  const double t1 = cruiseTime(100, 100, 2000, 0, vj);
  // last sample before the corner: X brakes at 2000 mm/s² towards vj; first after: Y accelerates
  // from vj at 1000 mm/s²
  size_t k = 0;
  while (k + 1 < vs.rows.size() && vs.rows[k + 1].t < t1)
    ++k;
  REQUIRE(k + 1 < vs.rows.size());
  const auto& before = vs.rows[k];
  const auto& after = vs.rows[k + 1];
  CHECK(before.v[0] == exact(vj + 2000 * (t1 - before.t)));
  CHECK(before.v[1] == 0);
  CHECK(after.v[0] == 0);
  CHECK(after.v[1] == exact(vj + 1000 * (after.t - t1)));
}

TEST_CASE("g64: a reversal stops at the junction") {
  auto r = simText("G64 G01 X100 F100\nX0\nM30\n");
  CHECK(r->cycle() == exact(2 * moveTime(100, 100, A)));
}

TEST_CASE("g64: a long zig-zag lies between the G60 time and distance/feed") {
  std::string body;
  for (int k = 0; k < 40; ++k)
    body += k % 2 ? "X10 Y-10\n" : "X10 Y10\n";
  auto g64 = simText("G91 G64 G01 F200\n" + body + "M30\n");
  auto g60 = simText("G91 G60 G01 F200\n" + body + "M30\n");
  REQUIRE(g64->diagnostics.empty());
  const double d = std::sqrt(200.0);
  // each diagonal block: V = min(200, 500·√2), A = 2000·√2
  CHECK(g60->cycle() == exact(40 * moveTime(d, 200, A * std::sqrt(2.0))));
  CHECK(g64->cycle() < g60->cycle());
  CHECK(g64->cycle() > 40 * d / 200);
  CHECK(g64->pos('X') == exact(400));
  CHECK(g64->pos('Y') == doctest::Approx(0).epsilon(1e-9));
}

TEST_CASE("g64: a line running tangentially into an arc does not slow down") {
  const double pi = std::acos(-1.0);
  // r = 50: sqrt(r·amax) = 316 > F; the arc starts along +X like the line
  auto r = simText("G64 G01 X100 Y0 F100\nG03 X150 Y50 I0 J50\nM30\n");
  REQUIRE(r->diagnostics.empty());
  CHECK(r->cycle() == exact(moveTime(100 + 25 * pi, 100, A)));
  CHECK(r->pos('X') == exact(150));
  CHECK(r->pos('Y') == exact(50));
  // r = 2: the centripetal limit sqrt(2·2000) binds the arc and the junction speed
  auto c = simText("G64 G01 X100 Y0 F100\nG03 X102 Y2 I0 J2\nM30\n");
  const double vc = std::sqrt(2 * A);
  const double t1 = cruiseTime(100, 100, A, 0, vc);
  const double t2 = cruiseTime(pi, vc, A, vc, 0);
  CHECK(c->lineTime(2) == exact(t1));
  CHECK(c->cycle() == exact(t1 + t2));
}

TEST_CASE("g64: the chain ends after lookahead_blocks blocks") {
  const machine::Machine m = machineWith([](machine::Machine& mm) { mm.lookaheadBlocks = 2; });
  auto r = simText("G64 G01 F100\nX25\nX50\nX75\nX100\nM30\n", m);
  CHECK(r->cycle() == exact(2 * moveTime(50, 100, A)));
  const machine::Machine one = machineWith([](machine::Machine& mm) { mm.lookaheadBlocks = 1; });
  auto s = simText("G64 G01 F100\nX25\nX50\nM30\n", one);
  CHECK(s->cycle() == exact(2 * moveTime(25, 100, A)));
}

TEST_CASE("g64: stop points end the chain - the path stops first") {
  const double t50 = moveTime(50, 100, A);
  SUBCASE("G04") { CHECK(simText("G64 G01 F100\nX50\nG04 F0\nX100\nM30\n")->cycle() == exact(2 * t50)); }
  SUBCASE("an M function") { CHECK(simText("G64 G01 F100\nX50\nM5\nX100\nM30\n")->cycle() == exact(2 * t50)); }
  SUBCASE("G60") { CHECK(simText("G64 G01 F100\nX50\nG60 X100\nM30\n")->cycle() == exact(2 * t50)); }
  SUBCASE("G00") {
    CHECK(simText("G64 G01 F100\nX50\nG00 Y10\nG01 X100\nM30\n")->cycle() == exact(2 * t50 + moveTime(10, 500, A)));
  }
  SUBCASE("a Posa move") {
    CHECK(simText("G64 G01 F100\nX50\nPosa[Y]=10\nG01 X100\nM30\n")->cycle() == exact(2 * t50));
  }
  SUBCASE("an independent move (Fa)") {
    CHECK(simText("G64 G01 F100\nX50\nX100 Fa[X]=100\nM30\n")->cycle() == exact(2 * t50));
  }
  SUBCASE("a real-time read waits for the next interpolation cycle after the stop") {
    auto r = simText("G64 G01 F100\nX50\nR1=$aa_iw[X]\nX100\nM30\n");
    const double tick = std::ceil(t50 / 0.002 + 1e-9) * 0.002;
    CHECK(r->lineTime(3) == exact(t50));
    CHECK(r->cycle() == exact(tick + t50));
  }
  SUBCASE("a WHEN") {
    auto r = simText("G64 G01 F100\nX50\nWHEN $aa_iw[X] > 75 DO $aa_out[1]=1\nX100\nM30\n");
    CHECK(r->cycle() == exact(2 * t50));
    CHECK(r->whenTime("fired") == exact(t50 + 0.05 + 22.5 / 100));
  }
  SUBCASE("the end of the program") { CHECK(simText("G64 G01 F100\nX50\n")->cycle() == exact(t50)); }
}

TEST_CASE("g64: statements read ahead run once, at the junction, without block time") {
  // the dwell line ends the chain: its assignment must not be applied twice
  auto r = simText("R1=0\nG64 G01 X10 F100\nR1=R1+1 G04 F0.5\nG01 X=R1*20\nM30\n");
  REQUIRE(r->diagnostics.empty());
  CHECK(r->pos('X') == 20);
  CHECK(r->lineTime(3) == exact(moveTime(10, 100, A)));
  CHECK(r->cycle() == exact(moveTime(10, 100, A) + 0.5 + moveTime(10, 100, A)));
  // block_time_s is charged for the lines that start and end the chain, not for those read ahead
  const machine::Machine m = machineWith([](machine::Machine& mm) { mm.blockTimeS = 0.1; });
  auto b = simText("G64 G01 F100\nX50\nX100\nM30\n", m);
  CHECK(b->cycle() == exact(0.3 + moveTime(100, 100, A)));
  CHECK(b->summary().blocks == 3); // SPEC §5.3: blocks counts the lines charged, X100 is read ahead
  // the audit's case: lines 2 and 3 are read ahead, lines 1 and 4 are charged and counted
  const machine::Machine bt = machineWith([](machine::Machine& mm) { mm.blockTimeS = 0.01; });
  auto c = simText("G64 G01 X10 F300\nR1=5\nX20 F100\nM30\n", bt);
  REQUIRE(c->status() == Status::Ok);
  CHECK(c->summary().blocks == 2);
  auto plain = simText("G60 G01 X10 F300\nR1=5\nX20 F100\nM30\n", bt);
  CHECK(plain->summary().blocks == 4);
  // jumps and calls are read through
  auto j = simFiles({{"main.mpf", "G64 G01 F100\nX25\nSUB1\nR1=0\nL1:\nR1=R1+1\nX=R1*10+50\nIF R1 < 5 GOTOB L1\nM30\n"},
                     {"SUB1.spf", "PROC SUB1 SAVE\nX50\nM17\n"}});
  REQUIRE(j->diagnostics.empty());
  CHECK(j->pos('X') == 100);
  CHECK(j->cycle() == exact(moveTime(100, 100, A)));
}

TEST_CASE("g64: errors and emergencies of blocks read ahead happen when the path gets there") {
  auto e = simText("G64 G01 X100 F100\nR1=1/0\nX200\nM30\n");
  CHECK(e->status() == Status::Error);
  CHECK(e->cycle() == exact(moveTime(100, 100, A)));
  CHECK(e->message().find("t.mpf:2") != std::string::npos);
  // soft limit of the second block: checked when the path reaches it, at full speed
  auto s = simText("G64 G01 X100 F100\nX5000\nM30\n");
  CHECK(s->status() == Status::Emergency);
  CHECK(s->cycle() == exact(0.05 + 97.5 / 100));
  CHECK(s->pos('X') == exact(100));
  CHECK(s->message().find("t.mpf:2") != std::string::npos);
  // an axis still moving (Posa) when the chain reaches the block that programs it
  auto p = simText("Posa[Y]=400\nG64 G01 X10 F100\nY10\nM30\n");
  CHECK(p->status() == Status::Emergency);
  CHECK(p->message().find("axis Y programmed while moving") != std::string::npos);
  // a zero-length block read ahead is checked too, when the path gets there
  auto z = simText("Posa[Y]=400\nG64 G01 X10 F100\nY400\nM30\n");
  CHECK(z->status() == Status::Emergency);
  CHECK(z->cycle() == exact(moveTime(10, 100, A)));
  CHECK(z->message().find("t.mpf:3") != std::string::npos);
  CHECK(z->message().find("axis Y programmed while moving") != std::string::npos);
}
