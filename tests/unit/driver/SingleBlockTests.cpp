//! @file SingleBlockTests.cpp
//! @brief isosim --single-block in process through runSingleBlock, the commands from a string:
//!        the block lines (time, line, source text, axes; a WHEN body named; an image without
//!        its sources: the line only), Enter, c, q, the end of the input, an unknown command,
//!        the prompt on a terminal, the summary and exit codes, the refused options. Times are
//!        hand-computed: X 50 mm/s, 1000 mm/s² (a move of d >= 2.5 mm takes d/50 + 0.05 s).
#include <filesystem>
#include <sstream>
#include <string>

#include <doctest/doctest.h>

#include "TestUtil.h"
#include "driver/Compile.h"
#include "driver/SingleBlock.h"
#include "sim/SimToolRun.h"

using namespace iso;
using test::TempDir;

namespace {

constexpr const char* kSingleBlockMachine = R"({"name": "single", "dialect": "sidac",
    "axes": [{"name": "X", "max_velocity": 50, "max_accel": 1000, "limit_minus": -100, "limit_plus": 100},
             {"name": "Y", "max_velocity": 50, "max_accel": 1000, "limit_minus": -100, "limit_plus": 100}]})";

constexpr const char* kSingleBlockMoves = "G00 X10\nG00 X20  ; second\n  G00 X0   \nM30\n";

struct SingleRun {
  int rc = -1;
  std::string out, err;
};

SingleRun singleBlock(const driver::SimulateOptions& o, const std::string& commands, bool tty = false) {
  std::ostringstream out, err;
  std::istringstream in(commands);
  driver::Io io{out, err, false, false, &in};
  SingleRun r;
  r.rc = driver::runSingleBlock(o, io, tty);
  r.out = out.str();
  r.err = err.str();
  return r;
}

driver::SimulateOptions singleBlockOptions(const TempDir& dir, const std::string& program) {
  driver::SimulateOptions o;
  o.program = dir.write("p.mpf", program);
  o.common.machinePath = dir.write("m.json", kSingleBlockMachine);
  return o;
}

constexpr const char* kSingleBlockHelp =
    "isosim: single block: Enter runs the next block, c continues to the end, q stops the run\n";

} // namespace

TEST_CASE("single block: each line once with its text and the axes the program uses, Enter runs it") {
  TempDir dir;
  SingleRun r = singleBlock(singleBlockOptions(dir, kSingleBlockMoves), "\n\n\n\n");
  CHECK(r.rc == 0);
  CHECK(r.err == kSingleBlockHelp);
  CHECK(r.out == "t=0.000 s  p.mpf:1  G00 X10  X=0\n"
                 "t=0.250 s  p.mpf:2  G00 X20  ; second  X=10\n"
                 "t=0.500 s  p.mpf:3  G00 X0  X=20\n"
                 "t=0.950 s  p.mpf:4  M30  X=0\n"
                 "status: ok\n"
                 "cycle_time_s: 0.95 s (0:01.0)\n"
                 "blocks: 4 (lines charged with block_time_s; G64 read-ahead not counted)\n"
                 "lines_executed: 4\n"
                 "final_position: X=0 Y=0\n");
}

TEST_CASE("single block: c runs to the end without stopping, the end of the input too") {
  TempDir dir;
  for (const char* commands : {"\nc\n", "\n"}) {
    CAPTURE(commands);
    SingleRun r = singleBlock(singleBlockOptions(dir, kSingleBlockMoves), commands);
    CHECK(r.rc == 0);
    CHECK(r.out == "t=0.000 s  p.mpf:1  G00 X10  X=0\n"
                   "t=0.250 s  p.mpf:2  G00 X20  ; second  X=10\n"
                   "status: ok\n"
                   "cycle_time_s: 0.95 s (0:01.0)\n"
                   "blocks: 4 (lines charged with block_time_s; G64 read-ahead not counted)\n"
                   "lines_executed: 4\n"
                   "final_position: X=0 Y=0\n");
  }
}

TEST_CASE("single block: q ends the run at the block shown, exit 0, the summary says so") {
  TempDir dir;
  SingleRun r = singleBlock(singleBlockOptions(dir, kSingleBlockMoves), "\n q \n");
  CHECK(r.rc == 0);
  CHECK(r.err == kSingleBlockHelp); // no "isosim: message": the run was stopped, not faulty
  CHECK(test::contains(r.out,
                       "t=0.250 s  p.mpf:2  G00 X20  ; second  X=10\nstatus: error\ncycle_time_s: 0.25 s (0:00.3)\n"));
  CHECK(test::contains(r.out, "message: p.mpf:2: runtime error at t=0.25 s: the debugger ended the run\n"));
  CHECK(!test::contains(r.out, "p.mpf:3"));
}

TEST_CASE("single block: an unknown command prints the commands and asks again") {
  TempDir dir;
  SingleRun r = singleBlock(singleBlockOptions(dir, kSingleBlockMoves), "next\nq\n");
  CHECK(r.rc == 0);
  CHECK(r.out.rfind(std::string("t=0.000 s  p.mpf:1  G00 X10  X=0\n") + kSingleBlockHelp + "status: error\n", 0) == 0);
}

TEST_CASE("single block: on a terminal each block line ends with the prompt, the echo follows it") {
  TempDir dir;
  SingleRun r = singleBlock(singleBlockOptions(dir, kSingleBlockMoves), "\nx\nc\n", true);
  CHECK(r.out.rfind(std::string("t=0.000 s  p.mpf:1  G00 X10  X=0  > t=0.250 s  p.mpf:2  G00 X20  ; second  X=10  > ") +
                        kSingleBlockHelp + "  > status: ok\n",
                    0) == 0);
}

TEST_CASE("single block: a WHEN body's block names its WHEN") {
  TempDir dir;
  // G01 X10 F=50: 0.25 s, symmetric: X passes 5 mm at 0.125 s
  SingleRun all = singleBlock(
      singleBlockOptions(dir, "WHEN $aa_iw[X] > 5 DO\n  $aa_out[3] = 1\nCANCEL\nG01 X10 F=50\nM30\n"), "\n\n\n\n\n");
  CHECK(all.out.rfind("t=0.000 s  p.mpf:1  WHEN $aa_iw[X] > 5 DO  X=0\n"
                      "t=0.000 s  p.mpf:3  CANCEL  X=0\n"
                      "t=0.000 s  p.mpf:4  G01 X10 F=50  X=0\n"
                      "t=0.125 s  p.mpf:2  [WHEN p.mpf:1]  $aa_out[3] = 1  X=5\n"
                      "t=0.250 s  p.mpf:5  M30  X=10\n"
                      "status: ok\n",
                      0) == 0);
}

TEST_CASE("single block: the text is escaped for the terminal, a subprogram's lines show its file") {
  TempDir dir;
  dir.write("sub.spf", "PROC Sub SAVE\nG00 X5 ; \x1b[31mred\n\tM17\n");
  SingleRun r = singleBlock(singleBlockOptions(dir, "Sub\nM30\n"), "\n\n\n\n");
  CHECK(r.rc == 0);
  CHECK(r.out.rfind("t=0.000 s  p.mpf:1  Sub  X=0\n"
                    "t=0.000 s  sub.spf:2  G00 X5 ; \\x1b[31mred  X=0\n"
                    "t=0.150 s  sub.spf:3  M17  X=5\n"
                    "t=0.150 s  p.mpf:2  M30  X=5\n",
                    0) == 0);
}

TEST_CASE("single block: an image without its sources shows the lines only") {
  TempDir dir;
  driver::SimulateOptions o = singleBlockOptions(dir, kSingleBlockMoves);
  driver::CompileOptions c;
  c.paths = {o.program};
  c.output = dir.path() + "/p.isob";
  std::ostringstream cout, cerr;
  driver::Io cio{cout, cerr, false, false};
  REQUIRE(driver::runCompile(c, cio) == 0);
  std::filesystem::remove(o.program);
  o.program = c.output;
  SingleRun r = singleBlock(o, "\nq\n");
  CHECK(r.rc == 0);
  CHECK(r.out.rfind("t=0.000 s  p.mpf:1  X=0\nt=0.250 s  p.mpf:2  X=10\nstatus: error\n", 0) == 0);
}

TEST_CASE("single block: a stripped image stops at each statement and names the file only") {
  TempDir dir;
  driver::SimulateOptions o = singleBlockOptions(dir, "R1 = 1 R2 = 2\nG00 X10\nM30\n");
  driver::CompileOptions c;
  c.paths = {o.program};
  c.output = dir.path() + "/p.isob";
  c.strip = true;
  std::ostringstream cout, cerr;
  driver::Io cio{cout, cerr, false, false};
  REQUIRE(driver::runCompile(c, cio) == 0);
  o.program = c.output;
  SingleRun r = singleBlock(o, "\n\n\n\n");
  CHECK(r.rc == 0);
  // the two assignments are one statement; G00 X10 takes 10/50 + 0.05 s
  CHECK(r.out == "t=0.000 s  p.mpf  X=0\nt=0.000 s  p.mpf  X=0\nt=0.250 s  p.mpf  X=10\n"
                 "status: ok\ncycle_time_s: 0.25 s (0:00.3)\n"
                 "blocks: 3 (lines charged with block_time_s; G64 read-ahead not counted)\n"
                 "lines_executed: 3\nfinal_position: X=10 Y=0\n");
}

TEST_CASE("single block: a runtime error is reported as --summary reports it, exit 1, also with --format json") {
  TempDir dir;
  driver::SimulateOptions o = singleBlockOptions(dir, "G00 X10\nG00 X200\nM30\n");
  o.format = "json";
  SingleRun r = singleBlock(o, "c\n");
  CHECK(r.rc == 3); // a soft limit: an emergency
  CHECK(test::contains(r.err, "isosim: p.mpf:2: "));
  CHECK(test::contains(r.out,
                       "t=0.000 s  p.mpf:1  G00 X10  X=0\n{\n  \"format_version\": 1,\n  \"status\": \"emergency\""));
  r = singleBlock(singleBlockOptions(dir, "R1 = 2000\nR2 = R[R1 + R1]\nM30\n"), "");
  CHECK(r.rc == 1);
  CHECK(test::contains(r.out, "status: error\n"));
  CHECK(test::contains(r.err, "isosim: p.mpf:2: "));
}

TEST_CASE("single block: outputs, --compare and the program on standard input are refused") {
  TempDir dir;
  driver::SimulateOptions base = singleBlockOptions(dir, kSingleBlockMoves);
  auto refused = [&](driver::SimulateOptions o, const std::string& what) {
    SingleRun r = singleBlock(o, "");
    CHECK(r.rc == 2);
    CHECK(test::contains(r.err, what));
    CHECK(r.out.empty());
  };
  driver::SimulateOptions o = base;
  o.output = dir.path() + "/t.csv";
  refused(o, "isosim: error: --single-block cannot be combined with -o (run 'isosim --help')");
  o = base;
  o.plot = dir.path() + "/p.svg";
  refused(o, "--single-block cannot be combined with --plot");
  o = base;
  o.compare = base.program;
  refused(o, "--single-block cannot be combined with --compare");
  o = base;
  o.profile = true;
  refused(o, "--single-block cannot be combined with --profile");
  o = base;
  o.program = "-";
  refused(o, "with --single-block the program cannot be standard input: the commands come from there");
  o = base;
  o.format = "xml";
  refused(o, "unknown format 'xml' (csv or json)");
  o = base;
  o.program = dir.path() + "/missing.mpf";
  SingleRun r = singleBlock(o, "");
  CHECK(r.rc == 2);
  CHECK(r.out.empty());
}
