//! @file SweepTests.cpp
//! @brief isosim --sweep: the sweep file (its errors with file:line:column), the grid's order
//!        and bound, ranges, the rendering of the table and of --sweep-jobs, and runs on 1 and
//!        4 threads giving one table with hand-computed cycle times.
#include <doctest/doctest.h>

#include <sstream>

#include "TestUtil.h"
#include "driver/Sweep.h"

using namespace iso;
using iso::test::readFileBytes;
using iso::test::TempDir;

namespace {
std::string sweepError(const std::string& text) {
  auto s = driver::parseSweep(text, "s.toml");
  if (s) return "";
  return s.error().where + ": " + s.error().message;
}
} // namespace

TEST_CASE("sweep: the grid is programs x the product of the vary lists, the last list fastest") {
  auto s = driver::parseSweep("programs = [\"a.mpf\", \"sub/b.mpf\"]\n"
                              "[[vary]]\nkey = \"axes.X.max_accel\"\nvalues = [2000, 3000]\n"
                              "[[vary]]\nkey = \"feed_override\"\nvalues = [80, 100, 120]\n",
                              "dir/s.toml");
  REQUIRE(s);
  CHECK(s->programs == std::vector<std::string>{"dir/a.mpf", "dir/sub/b.mpf"}); // relative to the sweep file
  CHECK(s->variants == 6);
  CHECK(s->runs() == 12);
  CHECK(driver::sweepVariant(*s, 0).label == "axes.X.max_accel=2000 feed_override=80");
  CHECK(driver::sweepVariant(*s, 1).label == "axes.X.max_accel=2000 feed_override=100");
  CHECK(driver::sweepVariant(*s, 3).label == "axes.X.max_accel=3000 feed_override=80");
  const driver::SweepVariant v = driver::sweepVariant(*s, 5);
  CHECK(v.sets == std::vector<std::string>{"axes.X.max_accel=3000"}); // feed_override is a run option
  CHECK(v.feedOverride == "120");
  CHECK(v.rapidOverride.empty());
  CHECK(v.values == std::vector<std::string>{"3000", "120"});
  // no vary: one variant, the machine as it is
  auto one = driver::parseSweep("programs = [\"/abs/a.mpf\"]\nmachine = \"m.json\"\n", "x/s.toml");
  REQUIRE(one);
  CHECK(one->programs.front() == "/abs/a.mpf");
  CHECK(one->machine == "x/m.json");
  CHECK(one->variants == 1);
  CHECK(driver::sweepVariant(*one, 0).label.empty());
}

TEST_CASE("sweep: ranges count by multiplication and keep short decimals") {
  auto s = driver::parseSweep("programs = [\"a.mpf\"]\n"
                              "[[vary]]\nkey = \"block_time_s\"\nrange = {from = 0, to = 0.3, step = 0.1}\n"
                              "[[vary]]\nkey = \"axes.X.max_accel\"\nrange = {from = 3000, to = 1000, step = -1000}\n"
                              "[[vary]]\nkey = \"dialect\"\nvalues = [\"sidac\"]\n"
                              "[[vary]]\nkey = \"optional_stop\"\nvalues = [true, false]\n",
                              "s.toml");
  REQUIRE(s);
  CHECK(s->vary[0].values == std::vector<std::string>{"0", "0.1", "0.2", "0.3"}); // not 0.30000000000000004
  CHECK(s->vary[1].values == std::vector<std::string>{"3000", "2000", "1000"});
  CHECK(s->vary[2].values == std::vector<std::string>{"sidac"});
  CHECK(s->vary[3].values == std::vector<std::string>{"true", "false"});
  CHECK(s->variants == 4 * 3 * 1 * 2);
  // a step that does not land on `to` stops before it
  auto t = driver::parseSweep("programs = [\"a.mpf\"]\n[[vary]]\nkey = \"m0_wait_s\"\nrange = {from = 1, to = 2, "
                              "step = 0.4}\n",
                              "s.toml");
  REQUIRE(t);
  CHECK(t->vary[0].values == std::vector<std::string>{"1", "1.4", "1.8"});
}

TEST_CASE("sweep: errors of the file name its line and column") {
  CHECK(sweepError("programs = []\n") == "s.toml:1:12: 'programs' must be a non-empty array of program paths");
  CHECK(sweepError("vary = 1\n").rfind("s.toml:1:8: 'vary' must be tables", 0) == 0);
  CHECK(sweepError("programs = [\"a.mpf\"]\n[[vary]]\nkey = \"x\"\nvalues = [1, [2]]\n") ==
        "s.toml:4:14: each value must be a number, true, false or a string");
  CHECK(sweepError("programs = [\"a.mpf\"]\n[[vary]]\nkey = \"x\"\n") ==
        "s.toml:2:1: 'vary' of 'x' needs either 'values' or 'range'");
  CHECK(sweepError("programs = [\"a.mpf\"]\n[[vary]]\nvalues = [1]\n").rfind("s.toml:2:1: 'vary' needs a 'key'", 0) ==
        0);
  CHECK(sweepError("programs = [\"a.mpf\"]\n[[vary]]\nkey = \"x\"\nrange = {from = 0, to = 1, step = 0}\n") ==
        "s.toml:4:35: 'range.step' must not be 0");
  CHECK(sweepError("programs = [\"a.mpf\"]\n[[vary]]\nkey = \"x\"\nrange = {from = 0, to = 1, step = -1}\n") ==
        "s.toml:4:35: 'range.step' -1 goes away from 'to' (0 to 1)");
  CHECK(sweepError("programs = [\"a.mpf\"]\n[[vary]]\nkey = \"x\"\nrange = {from = 0, to = 1}\n") ==
        "s.toml:4:9: 'range' needs 'step'");
  CHECK(sweepError("programs = [\"a.mpf\"]\n[[vary]]\nkey = \"x\"\nvalues = [nan]\n") ==
        "s.toml:4:11: each value must be a number, true, false or a string");
  CHECK(sweepError("programs = [\"a.mpf\"]\n[[vary]]\nkey = \"x\"\nvalue = [1]\n") ==
        "s.toml:4:9: unknown key 'value' in 'vary' (key, values, range)");
  CHECK(sweepError("programs = [\"a.mpf\"]\nprogram = 1\n") ==
        "s.toml:2:11: unknown key 'program'; did you mean 'programs'? (programs, machine, vary)");
  CHECK(sweepError("machine = \"m.json\"\n") == "s.toml: the sweep names no program: programs = [\"a.mpf\", ...]");
  CHECK(sweepError("programs = [\"a.mpf\"\n") == "s.toml:1:21: Error while parsing array: encountered end-of-file");
  CHECK(sweepError(std::string(100, '[')).rfind("s.toml:1:", 0) == 0); // nesting, before the parser
}

TEST_CASE("sweep: the grid is bounded before anything is expanded") {
  // 2 x 1000 x 100 = 200000 runs
  const std::string big = "programs = [\"a.mpf\", \"b.mpf\"]\n"
                          "[[vary]]\nkey = \"block_time_s\"\nrange = {from = 1, to = 1000, step = 1}\n"
                          "[[vary]]\nkey = \"m0_wait_s\"\nrange = {from = 1, to = 100, step = 1}\n";
  CHECK(sweepError(big) ==
        "s.toml: the sweep has 200000 runs (2 programs x 100000 variants); at most 100000 are allowed");
  // exactly the bound is allowed
  CHECK(sweepError("programs = [\"a.mpf\"]\n"
                   "[[vary]]\nkey = \"block_time_s\"\nrange = {from = 1, to = 1000, step = 1}\n"
                   "[[vary]]\nkey = \"m0_wait_s\"\nrange = {from = 1, to = 100, step = 1}\n")
            .empty());
  // a range alone larger than the bound is refused without building it; products do not overflow
  CHECK(sweepError("programs = [\"a.mpf\"]\n[[vary]]\nkey = \"x\"\nrange = {from = 0, to = 1e300, step = 1}\n") ==
        "s.toml:4:9: the range has more than 100000 values");
  std::string many = "programs = [\"a.mpf\"]\n";
  for (int k = 0; k < 40; ++k)
    many += fmt::format("[[vary]]\nkey = \"k{}\"\nvalues = [1, 2, 3, 4, 5, 6, 7, 8]\n", k);
  CHECK(sweepError(many) == "s.toml:18:7: the sweep has more than 100000 variants with this vary list; at most 100000 "
                            "runs are allowed"); // the 6th list: 8^6 = 262144
}

TEST_CASE("sweep: CSV quoting, the JSON table and the command lines of --sweep-jobs") {
  auto s = driver::parseSweep("programs = [\"my dir/a,b.mpf\"]\nmachine = \"m.json\"\n"
                              "[[vary]]\nkey = \"axes.X.max_accel\"\nvalues = [2000, 2500.5]\n"
                              "[[vary]]\nkey = \"rapid_override\"\nvalues = [\"50%\"]\n",
                              "s.toml");
  REQUIRE(s);
  std::vector<driver::SweepRow> rows(2);
  rows[0].cycleTimeS = 1.5;
  rows[0].blocks = 3;
  rows[1].variant = 1;
  rows[1].status = sim::Status::Emergency;
  rows[1].message = "a.mpf:2: emergency at t=0 s: soft limit, \"X\"";
  CHECK(driver::renderSweepCsv(*s, rows) ==
        "program,variant,axes.X.max_accel,rapid_override,status,cycle_time_s,blocks,spindle_on_s,tool_changes,"
        "warnings,message\n"
        "\"my dir/a,b.mpf\",axes.X.max_accel=2000 rapid_override=50%,2000,50%,ok,1.5,3,0,0,0,\n"
        "\"my dir/a,b.mpf\",axes.X.max_accel=2500.5 rapid_override=50%,2500.5,50%,emergency,0,0,0,0,0,"
        "\"a.mpf:2: emergency at t=0 s: soft limit, \"\"X\"\"\"\n");
  auto j = nlohmann::json::parse(driver::renderSweepJson(*s, rows));
  CHECK(j["runs"] == 2);
  CHECK(j["ok"] == 1);
  CHECK(j["emergency"] == 1);
  CHECK(j["rows"][1]["values"]["axes.X.max_accel"] == 2500.5);
  CHECK(j["rows"][1]["values"]["rapid_override"] == "50%");
  CHECK(j["rows"][0]["cycle_time_s"] == 1.5);
  driver::SweepOptions opts;
  CHECK(driver::sweepJobLines(*s, opts) ==
        "isosim 'my dir/a,b.mpf' --machine m.json --set axes.X.max_accel=2000 --rapid-override 50% --summary --format "
        "json\n"
        "isosim 'my dir/a,b.mpf' --machine m.json --set axes.X.max_accel=2500.5 --rapid-override 50% --summary "
        "--format json\n");
  opts.run.common.machinePath = "cli.json"; // the command line wins over the sweep's machine
  opts.run.maxTime = 60;
  CHECK(driver::sweepJobLines(*s, opts).rfind("isosim 'my dir/a,b.mpf' --machine cli.json --max-time 60 --set", 0) ==
        0);
  CHECK(driver::shellWord("it's") == "'it'\\''s'");
  CHECK(driver::shellWord("") == "''");
  CHECK(driver::shellWord("a=$(x)") == "'a=$(x)'");
}

TEST_CASE("sweep: runs on 1 and 4 threads give one table, in grid order, with hand-computed cycle times") {
  TempDir dir;
  // X 0 -> 100 at 50 mm/s: 100/50 + 50/A; a dwell of 0.5 s; 4 lines with a statement
  dir.write("p.mpf", "G01 X100 F=50\nG04 F0.5\nM30\n");
  const std::string file = dir.write("s.toml", "programs = [\"p.mpf\"]\n"
                                               "[[vary]]\nkey = \"axes.X.max_accel\"\nvalues = [1000, 2000, 5000]\n"
                                               "[[vary]]\nkey = \"block_time_s\"\nvalues = [0, 0.25]\n");
  std::string tables[2];
  for (unsigned jobs : {1u, 4u}) {
    driver::SweepOptions opts;
    opts.file = file;
    opts.jobs = jobs;
    opts.run.format = "csv";
    std::ostringstream out, err;
    driver::Io io{out, err};
    CHECK(driver::runSweep(opts, io) == 0);
    CHECK(err.str().empty());
    tables[jobs == 1 ? 0 : 1] = out.str();
  }
  CHECK(tables[0] == tables[1]);
  const std::string p = dir.path() + "/p.mpf";
  // 2 + 50/A + 0.5, and 3 blocks x 0.25 s more with block_time_s 0.25
  CHECK(tables[0] == "program,variant,axes.X.max_accel,block_time_s,status,cycle_time_s,blocks,spindle_on_s,"
                     "tool_changes,warnings,message\n" +
                         p + ",axes.X.max_accel=1000 block_time_s=0,1000,0,ok,2.55,3,0,0,0,\n" + p +
                         ",axes.X.max_accel=1000 block_time_s=0.25,1000,0.25,ok,3.3,3,0,0,0,\n" + p +
                         ",axes.X.max_accel=2000 block_time_s=0,2000,0,ok,2.525,3,0,0,0,\n" + p +
                         ",axes.X.max_accel=2000 block_time_s=0.25,2000,0.25,ok,3.275,3,0,0,0,\n" + p +
                         ",axes.X.max_accel=5000 block_time_s=0,5000,0,ok,2.51,3,0,0,0,\n" + p +
                         ",axes.X.max_accel=5000 block_time_s=0.25,5000,0.25,ok,3.26,3,0,0,0,\n");
}

TEST_CASE("sweep: every value is checked on the machine before any run") {
  TempDir dir;
  dir.write("p.mpf", "G01 X100 F=50\nM30\n");
  auto run = [&](const std::string& vary, std::string& err) {
    driver::SweepOptions opts;
    opts.file = dir.write("s.toml", "programs = [\"p.mpf\"]\n[[vary]]\n" + vary);
    opts.run.output = dir.path() + "/out.csv";
    std::ostringstream out, e;
    driver::Io io{out, e};
    const int rc = driver::runSweep(opts, io);
    err = e.str();
    return rc;
  };
  std::string err;
  CHECK(run("key = \"axes.X.limit_plus\"\nvalues = [200, -2000]\n", err) == 2);
  CHECK(err == dir.path() +
                   "/s.toml:4:16: error: axes.X.limit_plus=-2000: the machine is not valid at /axes/0/limit_plus: must "
                   "be >= limit_minus\n");
  CHECK_FALSE(std::filesystem::exists(dir.path() + "/out.csv")); // nothing ran, nothing written
  CHECK(run("key = \"m_sequences.23.duration_s\"\nvalues = [1, \"x\"]\n", err) == 2);
  CHECK(err.find("/s.toml:4:14: error: m_sequences.23.duration_s=x: the machine is not valid") ==
        0 + dir.path().size());
  CHECK(run("key = \"rapid_override\"\nvalues = [100, 101]\n", err) == 2);
  CHECK(err ==
        dir.path() + "/s.toml:4:16: error: rapid_override=101: expected a percent of the rapid speed from 1 to 100\n");
  CHECK(run("key = \"axes.X.name\"\nvalues = [\"Q\"]\n", err) == 2);
  CHECK(err.find("it changes how the programs compile") != std::string::npos);
  // -o written whole, the best and worst on standard output
  CHECK(run("key = \"axes.X.max_accel\"\nvalues = [1000, 5000]\n", err) == 0);
  CHECK(readFileBytes(dir.path() + "/out.csv").find(",5000,ok,2.01,2,") != std::string::npos);
}

TEST_CASE("sweep: the terminal view lists each program's fastest and slowest ok run and its first failure") {
  auto s = driver::parseSweep("programs = [\"a.mpf\", \"b.mpf\"]\n"
                              "[[vary]]\nkey = \"block_time_s\"\nvalues = [0, 0.1, 0.2]\n",
                              "s.toml");
  REQUIRE(s);
  std::vector<driver::SweepRow> rows(6);
  const double cycles[6] = {2, 1.5, 3, 4, 0, 0};
  for (size_t i = 0; i < 6; ++i) {
    rows[i].program = i / 3;
    rows[i].variant = i % 3;
    rows[i].cycleTimeS = cycles[i];
  }
  rows[4].status = sim::Status::Error;
  rows[4].message = "b.mpf:2: runtime error at t=0 s: division by zero (5 / 0)";
  rows[5].status = sim::Status::Emergency;
  rows[5].message = "b.mpf:1: emergency at t=0 s: soft limit";
  CHECK(driver::renderSweepBest(*s, rows) == "s.toml: 6 runs (2 programs x 3 variants): 4 ok, 1 error, 1 emergency\n"
                                             "a.mpf\n"
                                             "  best            1.5 s  block_time_s=0.1\n"
                                             "  worst             3 s  block_time_s=0.2\n"
                                             "b.mpf\n"
                                             "  ok                4 s  block_time_s=0\n"
                                             "  error             0 s  block_time_s=0.1: b.mpf:2: runtime error at t=0 "
                                             "s: division by zero (5 / 0)\n");
  // nothing varied: the one run of a program is the machine as it is
  auto one = driver::parseSweep("programs = [\"a.mpf\"]\n", "s.toml");
  REQUIRE(one);
  CHECK(driver::renderSweepBest(*one, {driver::SweepRow{}}) == "s.toml: 1 run (1 program x 1 variant): 1 ok\n"
                                                               "a.mpf\n"
                                                               "  ok                0 s  (the machine as it is)\n");
}

TEST_CASE("sweep: a terminal gets the view and a hint, -o the table and the view") {
  TempDir dir;
  dir.write("p.mpf", "G01 X100 F=50\nM30\n");
  const std::string file = dir.write("s.toml", "programs = [\"p.mpf\"]\n[[vary]]\nkey = \"axes.X.max_accel\"\n"
                                               "values = [1000, 5000]\n");
  driver::SweepOptions opts;
  opts.file = file;
  std::ostringstream out, err;
  driver::Io tty{out, err, true, false};
  CHECK(driver::runSweep(opts, tty) == 0);
  CHECK(out.str() == file + ": 2 runs (1 program x 2 variants): 2 ok\n" + dir.path() +
                         "/p.mpf\n  best           2.01 s  axes.X.max_accel=5000\n"
                         "  worst          2.05 s  axes.X.max_accel=1000\n");
  CHECK(err.str() == "isosim: the table is not printed on a terminal: write it with -o FILE (.csv or .json)\n");
  opts.run.output = dir.path() + "/t.json";
  std::ostringstream out2, err2;
  driver::Io pipe{out2, err2};
  CHECK(driver::runSweep(opts, pipe) == 0);
  CHECK(out2.str() == out.str()); // the view also with -o
  auto j = nlohmann::json::parse(readFileBytes(opts.run.output));
  CHECK(j["rows"][1]["cycle_time_s"] == 2.01); // 100/50 + 50/5000
  CHECK(j["rows"][0]["message"].is_null());
}
