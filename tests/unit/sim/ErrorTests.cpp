//! @file ErrorTests.cpp
//! @brief Runtime errors and emergencies (SPEC §6.4), runaway bounds (§6.3): status, message
//!        with file, line and time, the machine stopped at that instant.
#include <cmath>
#include <string>

#include <doctest/doctest.h>

#include "SimTestUtil.h"
#include "sim/Motion.h"

using namespace iso;
using namespace iso::test;
using sim::EventKind;
using sim::Status;

namespace {

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

/// A run that must stop with `st` on `line` (of t.mpf) with `part` in its message.
void expectStop(const SimRun& r, Status st, uint32_t line, const std::string& part) {
  INFO("message: " << r.message() << "\ndiagnostics: " << r.diagnostics);
  REQUIRE(r.diagnostics.empty());
  CHECK(r.status() == st);
  CHECK(contains(r.message(), "t.mpf:" + std::to_string(line) + ":"));
  CHECK(contains(r.message(), st == Status::Emergency ? "emergency at t=" : "runtime error at t="));
  CHECK(contains(r.message(), part));
  // the trace says why it stopped
  auto err = r.events(EventKind::Error);
  REQUIRE(err.size() == 1);
  CHECK(err[0].message == r.message());
  CHECK(err[0].t == r.cycle());
  CHECK(r.rec.ended);
}

} // namespace

TEST_CASE("sim: division by zero is a runtime error") {
  auto r = simText("G04 F0.5\nR2 = 0\nR1 = 1 / R2\nM30\n");
  expectStop(*r, Status::Error, 3, "division by zero");
  CHECK(r->cycle() == exact(0.5));
  CHECK(contains(r->message(), "t=0.5 s"));
}

TEST_CASE("sim: arithmetic overflow is a runtime error") {
  auto r = simText("R1 = 999999999\nL: R1 = R1 * R1\nIF R1 > 0 GOTOB L\nM30\n");
  expectStop(*r, Status::Error, 2, "overflow");
}

TEST_CASE("sim: R[expr] index checks") {
  expectStop(*simText("R1 = 0\nR2 = R[R1]\nM30\n"), Status::Error, 2, "R index 0 is outside 1..2880");
  expectStop(*simText("R1 = 2881\nR[R1] = 1\nM30\n"), Status::Error, 2, "R index 2881 is outside 1..2880");
  expectStop(*simText("R1 = 2.5\nR2 = R[R1]\nM30\n"), Status::Error, 2, "R index 2.5 is not an integer");
  // the value as it is, not rounded to the trace's 6 decimals
  expectStop(*simText("R2 = 0.000000001\nR1 = R2 * 2 + 3\nR[R1] = 1\nM30\n"), Status::Error, 3,
             "R index 3.000000002 is not an integer");
}

TEST_CASE("sim: runtime errors name the value exactly (a rounded value would contradict the message)") {
  expectStop(*simText("R1 = 1.0000001\n$aa_out[1] = R1\nM30\n"), Status::Error, 2,
             "$aa_out[1] = 1.0000001: only 0 or 1 can be written");
  expectStop(*simText("R2 = 0.0000001\nR1 = R2 * -1\nG04 F=R1\nM30\n"), Status::Error, 3,
             "G04 dwell time -1e-07 s is not a duration >= 0");
  expectStop(*simText("R2 = 0.0000001\nR1 = R2 * -1\nG01 X10 F=R1\nM30\n"), Status::Error, 3,
             "feed move with F=-1e-07 mm/s");
  // values the trace's text shows exactly stay as they were
  expectStop(*simText("R1 = 0\nG01 X10 F=R1\nM30\n"), Status::Error, 2, "feed move with F=0 mm/s");
}

TEST_CASE("sim: I/O index and value checks") {
  expectStop(*simText("R1 = 256\n$aa_out[R1] = 1\nM30\n"), Status::Error, 2, "$aa_out index 256 is outside 0..255");
  expectStop(*simText("R1 = 201\nR2 = $aa_marker[R1]\nM30\n"), Status::Error, 2, "$aa_marker index 201");
  expectStop(*simText("R1 = -1\nR2 = $aa_in[R1]\nM30\n"), Status::Error, 2, "$aa_in index -1");
  expectStop(*simText("R1 = 2\n$aa_out[3] = R1\nM30\n"), Status::Error, 2, "only 0 or 1");
}

TEST_CASE("sim: feed errors") {
  expectStop(*simText("G01 X10\nM30\n"), Status::Error, 1, "no F was ever set");
  expectStop(*simText("R1 = 0\nG01 X10 F=R1\nM30\n"), Status::Error, 2, "F must be > 0");
  expectStop(*simText("R1 = -5\nG01 X10 Y10 Z10 A10 F100 Fa[A]=R1\nM30\n"), Status::Error, 2, "Fa[A]=-5");
  // G00 needs no F; an axis with its own Fa needs no F either
  CHECK(simText("G00 X10\nM30\n")->status() == Status::Ok);
  CHECK(simText("G01 X10 Fa[X]=20\nM30\n")->status() == Status::Ok);
}

TEST_CASE("sim: negative dwell is a runtime error") {
  expectStop(*simText("R1 = -1\nG04 F=R1\nM30\n"), Status::Error, 2, "dwell");
}

TEST_CASE("sim: arc end point off the circle is a runtime error with the mismatch") {
  auto r = simText("R1 = 10.5\nG02 X=R1 Y0 I5 J0 F10\nM30\n");
  // centre (5, 0), start radius 5, end radius 5.5
  expectStop(*r, Status::Error, 2, "0.5 mm off the circle");
  // within 0.01 mm it runs
  CHECK(simText("R1 = 10.005\nG02 X=R1 Y0 I5 J0 F10\nM30\n")->status() == Status::Ok);
}

TEST_CASE("sim: an arc with an absurd radius is a runtime error, not undefined arithmetic") {
  // R1 = 1e256: CR squared overflows to infinity, and a chord along X (no Y component) made
  // the centre inf * 0 = NaN, a NaN start angle, and a NaN cast to an integer (UBSan).
  const std::string big = "R1 = 100000000\nR1 = R1 * R1\nR1 = R1 * R1\nR1 = R1 * R1\nR1 = R1 * R1\nR1 = R1 * R1\n";
  expectStop(*simText(big + "G02 X10 CR=R1 F10\nM30\n"), Status::Error, 7, "out of range");
  expectStop(*simText(big + "G03 X10 CR=-R1 F10\nM30\n"), Status::Error, 7, "at most 1000000000 mm");
  // I/J far away: the centre is finite but the arc's length and angles are meaningless
  expectStop(*simText(big + "G02 X0 Y0 I=R1 J=R1 F10\nM30\n"), Status::Error, 7, "arc radius out of range");
  // a large but sensible radius still runs: a quarter of a circle of 1000 mm radius
  auto ok = simText("G02 X1000 Y1000 I1000 J0 F500\nM30\n");
  CHECK(ok->status() == Status::Ok);
  CHECK(ok->pos('X') == doctest::Approx(1000));
}

TEST_CASE("sim: arcExtremes is bounded for any angles (no integer cast, no long loop)") {
  sim::ArcGeom g;
  g.r0 = g.r1 = 2;
  g.cp = 1;
  g.cq = -1;
  double pMin = 0, pMax = 0, qMin = 0, qMax = 0;
  // a huge finite sweep: every quadrant point, at once
  g.sweep = 1e300;
  sim::arcExtremes(g, pMin, pMax, qMin, qMax);
  CHECK(pMin == doctest::Approx(-1));
  CHECK(pMax == doctest::Approx(3));
  CHECK(qMin == doctest::Approx(-3));
  CHECK(qMax == doctest::Approx(1));
  // a huge start angle with a small sweep: no cast of 1e300 / (pi/2) to an integer
  g.phi0 = 1e300;
  g.sweep = 0.1;
  sim::arcExtremes(g, pMin, pMax, qMin, qMax);
  CHECK(std::isfinite(pMin));
  CHECK(pMin <= pMax);
  // a NaN angle: the end points only (makeArc never builds such an arc)
  g.phi0 = std::nan("");
  sim::arcExtremes(g, pMin, pMax, qMin, qMax);
  // a quarter circle from angle 0 counter-clockwise: reaches q = cq + r at the end
  g.phi0 = 0;
  g.sweep = std::acos(-1.0) / 2;
  sim::arcExtremes(g, pMin, pMax, qMin, qMax);
  CHECK(pMax == doctest::Approx(3));
  CHECK(qMax == doctest::Approx(1));
  CHECK(pMin == doctest::Approx(1));
  CHECK(qMin == doctest::Approx(-1));
}

TEST_CASE("sim: call nesting limit: the 31st nested call is a runtime error (z32: the 11th)") {
  std::vector<std::pair<std::string, std::string>> files = {
      {"main.mpf", "R1 = 0\nRec\nM30\n"}, {"rec.spf", "PROC Rec SAVE\nR1 = R1 + 1\nIF R1 < 1000 THEN Rec\nM17\n"}};
  auto r = simFiles(files);
  REQUIRE(r->diagnostics.empty());
  CHECK(r->status() == Status::Error);
  CHECK(contains(r->message(), "rec.spf:3:"));
  CHECK(contains(r->message(), "deeper than 30"));
  // a depth of exactly 30 is fine
  auto ok = simFiles(
      {{"main.mpf", "R1 = 0\nRec\nM30\n"}, {"rec.spf", "PROC Rec SAVE\nR1 = R1 + 1\nIF R1 < 30 THEN Rec\nM17\n"}});
  CHECK(ok->status() == Status::Ok);
  auto z32 = machineWith([](machine::Machine& m) { m.dialect = machine::Dialect::Z32; });
  auto z = simFiles(
      {{"main.mpf", "R1 = 0\nRec\nM30\n"}, {"rec.spf", "PROC Rec SAVE\nR1 = R1 + 1\nIF R1 < 11 THEN Rec\nM17\n"}}, z32);
  CHECK(z->status() == Status::Error);
  CHECK(contains(z->message(), "deeper than 10"));
  auto z10 = simFiles(
      {{"main.mpf", "R1 = 0\nRec\nM30\n"}, {"rec.spf", "PROC Rec SAVE\nR1 = R1 + 1\nIF R1 < 10 THEN Rec\nM17\n"}}, z32);
  CHECK(z10->status() == Status::Ok);
}

TEST_CASE("sim: soft limits are an emergency - nothing of the block moves") {
  auto r = simText("G00 X100\nG00 X3000.001 Y50\nM30\n");
  expectStop(*r, Status::Emergency, 2, "soft limit: axis X would reach 3000.001");
  CHECK(r->pos('X') == 100);
  CHECK(r->pos('Y') == 0);
  CHECK(r->cycle() == exact(moveTime(100, 500, 2000)));
  // limits are inclusive
  CHECK(simText("G00 X3000\nG00 X-1000\nM30\n")->status() == Status::Ok);
  // G91 accumulates before the check
  expectStop(*simText("G91 G00 X2000\nX1000.5\nM30\n"), Status::Emergency, 2, "3000.5");
  // arcs are checked at their extreme points: a full circle of radius 600 around X 2500
  auto arc = simText("G00 X1900\nG02 X1900 Y0 I600 J0 F100\nM30\n");
  expectStop(*arc, Status::Emergency, 2, "axis X would reach 3100");
  CHECK(arc->pos('X') == 1900);
}

TEST_CASE("sim: a target within 1e-9 of a soft limit is on it - the message shows every digit") {
  // thirty G91 X0.1 steps end at 3.0000000000000013 in doubles: on a limit of 3
  std::string steps = "G91 G01 F1000\n";
  for (int i = 0; i < 30; ++i)
    steps += "X0.1\n";
  steps += "M30\n";
  auto at3 = machineWith([](machine::Machine& m) { m.axes[0].limitPlus = 3; });
  auto ok = simText(steps, at3);
  INFO(ok->message());
  CHECK(ok->status() == Status::Ok);
  CHECK(ok->pos('X') == 3.0000000000000013);
  auto lowAt = machineWith([](machine::Machine& m) { m.axes[0].limitMinus = -2.9999999995; });
  CHECK(simText("G00 X-3\nM30\n", lowAt)->status() == Status::Ok);
  // past the tolerance it is an emergency, and the message does not round the target to 3
  auto below = machineWith([](machine::Machine& m) { m.axes[0].limitPlus = 2.999999998; });
  expectStop(*simText(steps, below), Status::Emergency, 31,
             "soft limit: axis X would reach 3.0000000000000013, outside [-1000, 2.999999998]");
  auto lowPast = machineWith([](machine::Machine& m) { m.axes[0].limitMinus = -2.999999997; });
  expectStop(*simText("G00 X-3\nM30\n", lowPast), Status::Emergency, 1, "would reach -3, outside [-2.999999997, 3000]");
}

TEST_CASE("sim: programming an axis that is still moving is an emergency - the axes stop at once") {
  auto r = simText("G00 Posa[X]=1000\nG04 F1\nG00 X0\nM30\n");
  expectStop(*r, Status::Emergency, 3, "axis X programmed while moving");
  CHECK(r->cycle() == exact(1.0));
  // X was cruising at 1 s: 62.5 + 500 · 0.75, and stays there
  CHECK(r->pos('X') == exact(62.5 + 500 * 0.75));
  CHECK(r->count(EventKind::MoveEnd) == 0); // it never arrived
  // even to the same target
  expectStop(*simText("G00 Posa[X]=1000\nG00 X1000\nM30\n"), Status::Emergency, 2, "programmed while moving");
  // an axis arriving exactly at the instant it is programmed is no longer moving: X and Y
  // have the same limits and distance, so they arrive at the same instant
  auto tie = simText("G00 Posa[X]=100\nG00 Y100\nG00 X0\nM30\n");
  CHECK(tie->status() == Status::Ok);
}

TEST_CASE("sim: runaway bounds --max-steps and --max-time name the line") {
  sim::SimOptions o;
  o.maxSteps = 1000;
  auto s = simText("R1 = 0\nL: R1 = R1 + 1\nGOTOB L\nM30\n", builtin(), o);
  REQUIRE(s->status() == Status::Error);
  CHECK(contains(s->message(), "--max-steps"));
  CHECK(s->summary().blocks == 999); // the statement number 1000 does not run
  CHECK((contains(s->message(), "t.mpf:2:") || contains(s->message(), "t.mpf:3:")));
  // SPEC §6.3: a program that executes --max-steps statements stops, even when the last is M30
  o.maxSteps = 3;
  auto three = simText("R1 = 1\nR2 = 2\nM30\n", builtin(), o);
  REQUIRE(three->status() == Status::Error);
  CHECK(contains(three->message(), "t.mpf:3:"));
  CHECK(contains(three->message(), "the program reached 3 statements, the limit of --max-steps"));
  o.maxSteps = 4;
  CHECK(simText("R1 = 1\nR2 = 2\nM30\n", builtin(), o)->status() == Status::Ok);
  sim::SimOptions t;
  t.maxTime = 10;
  auto tm = simText("G04 F4\nW: IF $aa_in[1] == 0 GOTOB W\nM30\n", builtin(), t);
  REQUIRE(tm->status() == Status::Error);
  CHECK(contains(tm->message(), "--max-time"));
  CHECK(contains(tm->message(), "t.mpf:2:"));
  CHECK(tm->cycle() == 10);
  // SPEC §6.3: a run that reaches the limit stops, even one that would end there
  auto at = simText("G04 F10\nM30\n", builtin(), t);
  REQUIRE(at->status() == Status::Error);
  CHECK(contains(at->message(), "--max-time"));
  CHECK(at->cycle() == 10);
  CHECK(simText("G04 F9.999\nM30\n", builtin(), t)->status() == Status::Ok);
}

TEST_CASE("sim: a machine without an axis the image uses refuses to run") {
  auto m = machineFromJson(R"({"axes": [{"name": "X", "max_velocity": 500, "max_accel": 2000,
      "limit_minus": -1000, "limit_plus": 3000}]})");
  auto set = loadText("G00 X1 Y2\nM30\n");
  std::string diags;
  image::Image img = compileSet(*set, builtin(), &diags);
  REQUIRE(diags.empty());
  auto res = test::runImage(img, m, {}, nullptr);
  CHECK(res.setupError == sim::SetupError::AxisMissing);
  CHECK(contains(res.setupMessage, "axis Y"));
}

TEST_CASE("sim: a stripped image runs the same and names files without lines") {
  auto set = loadText("G00 X100\nR1 = 0\nR2 = 1 / R1\nM30\n");
  image::Image img;
  compiler::CompileOptions co;
  co.strip = true;
  compiler::CompileError err;
  REQUIRE(compiler::compileProgramSet(*set, co, img, err));
  Recorder rec;
  auto res = test::runImage(img, builtin(), {}, &rec);
  CHECK(res.summary.status == Status::Error);
  CHECK(res.summary.cycleTimeS == exact(moveTime(100, 500, 2000)));
  CHECK(contains(res.summary.message, "t.mpf: runtime error at t="));
  for (const auto& e : rec.events)
    if (e.kind == EventKind::Line) CHECK(e.line == 0);
}
