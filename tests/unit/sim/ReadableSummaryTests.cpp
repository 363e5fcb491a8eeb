//! @file ReadableSummaryTests.cpp
//! @brief The readable summary of isosim: durations as clock time, blocks and lines executed,
//!        the lines whose feed an axis limit capped, and --quiet on a terminal.
#include <sstream>
#include <string>

#include <doctest/doctest.h>
#include <fmt/format.h>

#include "SimTestUtil.h"
#include "SimToolRun.h"
#include "sim/TraceWriter.h"

using namespace iso;
using namespace iso::test;

TEST_CASE("summary: clock time rounds to the tenth, with hours from an hour") {
  CHECK(sim::clockTime(0) == "0:00.0");
  CHECK(sim::clockTime(39.276) == "0:39.3");
  CHECK(sim::clockTime(59.96) == "1:00.0"); // rounding carries into the minutes
  CHECK(sim::clockTime(62.34) == "1:02.3");
  CHECK(sim::clockTime(3599.94) == "59:59.9");
  CHECK(sim::clockTime(3599.96) == "1:00:00.0");
  CHECK(sim::clockTime(3723.4) == "1:02:03.4");
  CHECK(sim::clockTime(36000 * 3 + 0.04) == "30:00:00.0");
  CHECK(sim::readableDuration(39.276) == "39.276 s (0:39.3)");
  CHECK(sim::readableDuration(3723.4) == "3723.4 s (1:02:03.4)");
  CHECK(sim::readableDuration(0.947214) == "0.947214 s (0:00.9)");
  // never produced by a run: the number alone
  CHECK(sim::readableDuration(-1) == "-1 s");
  CHECK(sim::clockTime(-1) == "-1");
}

TEST_CASE("summary: blocks leave out the lines read ahead in a G64 chain, lines_executed counts them") {
  // line 1 runs alone; line 2 starts the chain; 3, 4 and 5 are read ahead (5 is the chain's
  // second block); M30 ends the chain and runs when the path has stopped
  auto r = simText("G64 G01 F100\nX10\nR1 = 1\nR2 = 2\nX20\nM30\n");
  REQUIRE(r->diagnostics.empty());
  CHECK(r->summary().blocks == 3);
  CHECK(r->summary().linesExecuted == 6);
  // a loop's lines count once per pass; without G64 both count every line
  auto loop = simText("R1 = 0\nL: R1 = R1 + 1\nIF R1 < 3 GOTOB L\nM30\n");
  REQUIRE(loop->diagnostics.empty());
  CHECK(loop->summary().blocks == 8); // 1 + 3·2 + 1
  CHECK(loop->summary().linesExecuted == 8);
  // a WHEN body counts when it fires: the WHEN line, its body, G00 and M30
  auto when = simText("WHEN $aa_iw[X] > 10 DO $aa_out[1] = 1\nG00 X1000\nM30\n");
  REQUIRE(when->diagnostics.empty());
  CHECK(when->summary().blocks == 4);
  CHECK(when->summary().linesExecuted == 4);
  const std::string text = sim::summaryText(r->summary());
  CHECK(contains(text, "\nblocks: 3 (lines charged with block_time_s; G64 read-ahead not counted)\n"
                       "lines_executed: 6\n"));
  CHECK(contains(sim::summaryJson(r->summary()), "\"blocks\": 3,\n  \"lines_executed\": 6,\n"));
}

TEST_CASE("summary: a G64 read-ahead rolled back is not counted twice in lines_executed") {
  // the chain X10, X20 is read ahead up to the G00 line, which ends it: the G00 line is rolled
  // back and runs again once the path has stopped, counted once
  auto r = simText("G64 G01 F100\nX10\nX20\nG00 X0\nM30\n");
  REQUIRE(r->diagnostics.empty());
  CHECK(r->summary().linesExecuted == 5);
  CHECK(r->summary().blocks == 4); // X20 was read ahead
}

TEST_CASE("summary: the lines whose F an axis max_velocity capped, in one warning") {
  // the built-in machine: every axis 500 mm/s, 2000 mm/s². X100 Y100 at F600 runs at 600 (each
  // axis at 424 mm/s); X100 at F600 is capped, and so are an arc of radius 500 (its centripetal
  // bound is sqrt(500 · 2000) = 1000) and an independent move of four axes at F800
  auto r = simText("G01 X100 Y100 F600\nG01 X200\nG02 X300 CR=500 F1000\nG01 X200 Y0 Z10 A5 F800\nM30\n");
  REQUIRE(r->diagnostics.find("error") == std::string::npos);
  const auto& w = r->summary().warnings;
  REQUIRE(w.size() == 1);
  CHECK(w[0] == "feed capped by an axis max_velocity (F is in mm/s) on 3 lines: t.mpf:2, t.mpf:3, t.mpf:4");
  // a feed within every limit: no warning
  auto ok = simText("G01 X100 F500\nM30\n");
  CHECK(ok->summary().warnings.empty());
  // bounded: the first 10 lines, then how many more (a loop's line once)
  std::string many;
  for (int i = 1; i <= 13; ++i)
    many += fmt::format("G01 X{} F1000\n", i * 10);
  many += "L: G01 X0\nR1 = R1 + 1\nIF R1 < 5 GOTOB L\nM30\n";
  auto m = simText(many);
  REQUIRE(m->summary().warnings.size() == 1);
  CHECK(m->summary().warnings[0] ==
        "feed capped by an axis max_velocity (F is in mm/s) on 14 lines: t.mpf:1, t.mpf:2, "
        "t.mpf:3, t.mpf:4, t.mpf:5, t.mpf:6, t.mpf:7, t.mpf:8, t.mpf:9, t.mpf:10 and 4 more");
}

TEST_CASE("summary: --quiet leaves out the hint on a terminal, not the summary") {
  TempDir dir;
  driver::SimulateOptions o;
  o.program = dir.write("p.mpf", "G00 X10\nM30\n");
  for (bool quiet : {false, true}) {
    CAPTURE(quiet);
    o.quiet = quiet;
    std::ostringstream out, err;
    driver::Io tty{out, err, true, true};
    CHECK(driver::runSimulate(o, tty) == 0);
    CHECK(contains(out.str(), "status: ok\ncycle_time_s: 0.141421 s (0:00.1)\n")); // 2·sqrt(10/2000)
    CHECK(contains(err.str(), "the trace is not printed on a terminal") == !quiet);
  }
}
