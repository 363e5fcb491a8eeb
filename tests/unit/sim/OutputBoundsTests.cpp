//! @file OutputBoundsTests.cpp
//! @brief Bounded outputs of isosim: the --max-rows limit of the trace, the smallest --dt, views
//!        that say what they leave out (timeline, plot, report, --profile text), --profile-lines.
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>

#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include "SimTestUtil.h"
#include "driver/Simulate.h"

using namespace iso;
using namespace iso::test;
using Json = nlohmann::json;
using sim::EventKind;
using sim::Status;

namespace {

struct ToolRun {
  int rc = -1;
  std::string out, err;
};

ToolRun runSim(const driver::SimulateOptions& o) {
  std::ostringstream out, err;
  driver::Io io{out, err, false, false};
  ToolRun r;
  r.rc = driver::runSimulate(o, io);
  r.out = out.str();
  r.err = err.str();
  return r;
}

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

size_t countOf(const std::string& s, const std::string& part) {
  size_t n = 0;
  for (size_t at = s.find(part); at != std::string::npos; at = s.find(part, at + 1))
    ++n;
  return n;
}

} // namespace

TEST_CASE("sim: --max-rows stops the run at the row it may not write, naming the option and the rows") {
  // G04 F1 at dt 0.01: rows at 0, 0.01, ..., 1 (101 rows; 1 s is a sample time, no extra row)
  sim::SimOptions so;
  so.maxRows = 101;
  auto all = simText("G04 F1\nM30\n", builtin(), so);
  CHECK(all->status() == Status::Ok);
  CHECK(all->rec.samples.size() == 101);
  so.maxRows = 50;
  auto cut = simText("G04 F1\nM30\n", builtin(), so);
  INFO(cut->message());
  CHECK(cut->status() == Status::Error);
  REQUIRE(cut->rec.samples.size() == 50);
  CHECK(cut->rec.samples.back()[0] == exact(0.49));
  CHECK(cut->cycle() == exact(0.5)); // the time of the 51st row, not written
  CHECK(contains(cut->message(), "t.mpf:1: runtime error at t=0.5 s"));
  CHECK(contains(cut->message(), "--max-rows"));
  CHECK(contains(cut->message(), "50 rows written"));
  CHECK(cut->count(EventKind::Error) == 1);
  // 100 rows: the 101st is due at the end instant itself
  so.maxRows = 100;
  auto edge = simText("G04 F1\nM30\n", builtin(), so);
  CHECK(edge->status() == Status::Error);
  CHECK(edge->rec.samples.size() == 100);
  CHECK(edge->cycle() == exact(1));
  // the exact end row counts too: G04 F0.995 needs rows 0..0.99 (100) and one at 0.995
  so.maxRows = 100;
  auto end = simText("G04 F0.995\nM30\n", builtin(), so);
  CHECK(end->status() == Status::Error);
  CHECK(end->rec.samples.size() == 100);
  so.maxRows = 101;
  CHECK(simText("G04 F0.995\nM30\n", builtin(), so)->status() == Status::Ok);
}

TEST_CASE("sim: isosim --max-rows exits 1 with the rows so far; --dt below 1e-6 s is a usage error") {
  TempDir dir;
  driver::SimulateOptions o;
  o.program = dir.write("p.mpf", "G04 F1\nM30\n");
  o.output = dir.path() + "/t.csv";
  o.maxRows = 50;
  ToolRun r = runSim(o);
  CHECK(r.rc == 1);
  CHECK(contains(r.out, "status: error\n"));
  CHECK(contains(r.out, "50 rows written"));
  CHECK(contains(r.err, "--max-rows"));
  std::ifstream in(o.output);
  std::string csv((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  CHECK(countOf(csv, "\n") == 51); // the header and 50 rows
  o.maxRows = 0;
  CHECK(runSim(o).rc == 2);
  o.maxRows = 20'000'000;
  o.dt = 1e-9;
  ToolRun d = runSim(o);
  CHECK(d.rc == 2);
  CHECK(contains(d.err, "--dt"));
  CHECK(contains(d.err, "1e-6 s"));
  o.dt = 1e-6;
  o.summary = true;
  o.output.clear();
  CHECK(runSim(o).rc == 0);
}
