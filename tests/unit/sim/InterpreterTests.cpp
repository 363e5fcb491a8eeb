//! @file InterpreterTests.cpp
//! @brief The language at run time: R parameters, operator tiers, control flow, calls with
//!        SAVE, system variables, outputs and markers, block skip (SPEC §3, §4).
#include <cmath>

#include <doctest/doctest.h>

#include "SimTestUtil.h"

using namespace iso;
using namespace iso::test;
using sim::EventKind;
using sim::Status;

TEST_CASE("sim: arithmetic is strictly left to right") {
  // the final X position shows the value
  auto r = simText("R1 = 2 + 3 * 4\nR2 = R1 - 4 / 2\nR3 = -R2 + 100\nG00 X=R3\nM30\n");
  REQUIRE(r->diagnostics.empty());
  CHECK(r->pos('X') == 92); // (2+3)*4 = 20; (20-4)/2 = 8; -8 + 100
  auto p = simText("R1 = 2 + (3 * 4)\nG00 X=R1\nM30\n");
  CHECK(p->pos('X') == 14);
}

TEST_CASE("sim: comparisons treat values within 1e-12 relative as equal") {
  auto r = simText("R1 = 0.1 + 0.2\nIF R1 == 0.3 GOTOF Eq\nG00 X1\nEq: IF R1 > 0.3 GOTOF Gt\nIF R1 >= 0.3 GOTOF Ge\n"
                   "Gt: G00 Y1\nGe: M30\n");
  CHECK(r->pos('X') == 0);
  CHECK(r->pos('Y') == 0);
  auto d = simText("R1 = 1000000\nR2 = R1 + 0.001\nIF R1 < R2 GOTOF Lt\nG00 X1\nLt: M30\n");
  CHECK(d->pos('X') == 0); // 1e-9 relative apart: not equal
}

TEST_CASE("sim: logic operators are left to right - NOT applies to the group") {
  auto r = simText("R1 = 1\nIF (R1 == 1) OR (R1 == 2) AND (R1 == 3) GOTOF Bad\nIF NOT (R1 == 2) GOTOF Ok\n"
                   "Bad: G00 X1\nOk: M30\n");
  CHECK(r->pos('X') == 0);
}

TEST_CASE("sim: R parameters, indirect addressing and presets") {
  auto m = machineWith([](machine::Machine& mm) { mm.rPreset[7] = 12.5; });
  auto r = simText("R10 = 3\nR[R10 + 1] = R7 * 2\nG00 X=R4\nY=R[2 + 2]\nM30\n", m);
  CHECK(r->pos('X') == 25);
  CHECK(r->pos('Y') == 25);
  // an index within 1e-9 of an integer is that integer
  auto n = simText("R1 = 1 + 0.0000000001\nR[R1 + 1] = 7\nG00 X=R2\nM30\n");
  REQUIRE(n->diagnostics.empty());
  CHECK(n->status() == Status::Ok);
  CHECK(n->pos('X') == 7);
}

TEST_CASE("sim: IF/ELSE/ENDIF, GOTOF/GOTOB loops and CASE") {
  auto r = simText("R1 = 0\nL: R1 = R1 + 1\nIF R1 < 5 GOTOB L\nIF R1 == 5\n  G00 X=R1\nELSE\n  G00 X1\nENDIF\n"
                   "CASE R1 OF 4 GOTOF Four 5 GOTOF Five DEFAULT GOTOF Other\nFour: G00 Y4\nFive: G00 Y5\n"
                   "GOTOF Done\nOther: G00 Y9\nDone: M30\n");
  CHECK(r->pos('X') == 5);
  CHECK(r->pos('Y') == 5);
  // no match and no DEFAULT: the next line
  auto c = simText("R1 = 7\nCASE R1 OF 1 GOTOF One\nG00 X7\nOne: M30\n");
  CHECK(c->pos('X') == 7);
}

TEST_CASE("sim: calls restore the modal state and F on return (SAVE)") {
  auto r = simFiles(
      {{"main.mpf", "G90 G01 F100\nSub1\nX10\nM30\n"}, {"sub1.spf", "PROC Sub1 SAVE\nG91 F=50\nX5\nX5\nM17\n"}});
  REQUIRE(r->diagnostics.empty());
  // Sub1 moves X to 10 in two incremental 5 mm steps at F=50; main's X10 is then absolute
  // (no motion) at F=100: the cycle is the two steps only.
  CHECK(r->pos('X') == 10);
  CHECK(r->cycle() == exact(2 * moveTime(5, 50, 2000)));
  auto f = simFiles({{"main.mpf", "G01 F100\nSub1\nX100\nM30\n"}, {"sub1.spf", "PROC Sub1 SAVE\nF=10\nG00\nM17\n"}});
  CHECK(f->cycle() == exact(moveTime(100, 100, 2000))); // G01 and F=100 again after the call
}

TEST_CASE("sim: system variables") {
  auto m = machineWith([](machine::Machine& mm) {
    mm.axes[0].maxVelocity = 321;
    mm.axes[0].limitPlus = 777;
    mm.axes[0].limitMinus = -55;
  });
  auto r = simText("R1 = $MAX_VELO[X]\nR2 = $POS_LIMIT_PLUS[X]\nR3 = $POS_LIMIT_MINUS[X]\n"
                   "G00 Y=R1\nG00 Z=R2\nG00 A=R3\nM30\n",
                   m);
  CHECK(r->pos('Y') == 321);
  CHECK(r->pos('Z') == 777);
  CHECK(r->pos('A') == -55);
  // $aa_fw is the end of the current move; $aa_iw the position now
  auto fw = simText("G00 Posa[X]=1000\nR1 = $aa_fw[X] R2 = $aa_iw[X]\nG00 Y=R1\nZ=R2\nM30\n");
  CHECK(fw->pos('Y') == 1000);
  CHECK(fw->pos('Z') == exact(2000 * 0.002 * 0.002 / 2)); // read at the first ipo boundary
}

TEST_CASE("sim: outputs and markers start at 0 - each write is an event") {
  auto r = simText("IF $aa_out[5] == 0 THEN $aa_out[5] = 1\n$aa_out[5] = 1\n$aa_marker[200] = 1\n"
                   "IF ($aa_out[5] == 1) AND ($aa_marker[200] == 1) THEN G00 X1\nM30\n");
  CHECK(r->pos('X') == 1);
  auto outs = r->events(EventKind::Output);
  REQUIRE(outs.size() == 2); // unchanged writes count too
  CHECK(outs[0].index == 5);
  CHECK(outs[0].value == 1);
  CHECK(r->count(EventKind::Marker) == 1);
}

TEST_CASE("sim: block skip") {
  const char* prog = "G00 X10\n/G00 X20\n/N5 G04 F1\nM30\n";
  auto off = simText(prog);
  CHECK(off->pos('X') == 20);
  sim::SimOptions o;
  o.blockSkip = true;
  auto on = simText(prog, builtin(), o);
  CHECK(on->pos('X') == 10);
  CHECK(on->summary().blocks == 2);
  CHECK(on->cycle() == exact(moveTime(10, 500, 2000)));
}

TEST_CASE("sim: line events carry file, line and N") {
  auto r = simText("N10 G00 X1\n\nN20 M30\n");
  auto lines = r->events(EventKind::Line);
  REQUIRE(lines.size() == 2);
  CHECK(lines[0].file == "t.mpf");
  CHECK(lines[0].line == 1);
  CHECK(lines[1].line == 3);
  CHECK(r->summary().blocks == 2);
}

TEST_CASE("sim: semi-automatic programs run by --entry (SEMI name or file stem)") {
  std::vector<std::pair<std::string, std::string>> files = {{"main.mpf", "G00 X1\nM30\n"},
                                                            {"semi.mpf", "SEMI \"Carico pezzo\"\nG00 X2\nM30\n"}};
  sim::SimOptions o;
  o.entry = "carico PEZZO";
  auto byName = simFiles(files, builtin(), o);
  CHECK(byName->pos('X') == 2);
  o.entry = "semi";
  auto byStem = simFiles(files, builtin(), o);
  CHECK(byStem->pos('X') == 2);
  o.entry = "nope";
  auto none = simFiles(files, builtin(), o);
  CHECK(none->result.setupError == sim::SetupError::UnknownEntry);
  CHECK(none->result.setupMessage.find("Carico pezzo") != std::string::npos);
}
