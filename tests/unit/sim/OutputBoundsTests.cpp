//! @file OutputBoundsTests.cpp
//! @brief Bounded outputs of isosim: the --max-rows limit of the trace, the smallest --dt, views
//!        that say what they leave out (timeline, plot, report, --profile text), --profile-lines.
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include "SimTestUtil.h"
#include "SimToolRun.h"
#include "sim/TimeProfile.h"

using namespace iso;
using namespace iso::test;
using Json = nlohmann::json;
using sim::EventKind;
using sim::Status;

namespace {

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

TEST_CASE("sim: isosim --max-rows exits 1 with the rows so far, and --dt below 1e-6 s is a usage error") {
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

namespace {

/// 20000 times X1, X0 (3 lines an iteration): 60000 line events and 40000 moves, past the
/// timeline's 100000 events, the plot's 2000 markers and the path view's 20000 points.
/// (The path runs over the same millimetre 40000 times: its tolerance doubles to 8.192 mm.)
const char* kLongRun = "R1 = 0\nG01 F500\nLoop: X1\nX0\nR1 = R1 + 1\nIF R1 < 20000 GOTOB Loop\nM30\n";

} // namespace

TEST_CASE("sim: views that cap what they show say so in their output and in the summary's warnings") {
  TempDir dir;
  driver::SimulateOptions o;
  o.program = dir.write("long.mpf", kLongRun);
  o.summary = true;
  o.timeline = dir.path() + "/t.json";
  o.plot = dir.path() + "/p.svg";
  ToolRun r = runSim(o);
  INFO(r.out << r.err);
  CHECK(r.rc == 0);
  CHECK(contains(r.out, "status: ok\n"));
  CHECK(contains(r.out, "warning: --timeline: the timeline holds its first 100000 events;"));
  CHECK(contains(r.out, "warning: --plot: no block marker (80003 lines run; they are drawn up to 2000)"));
  CHECK(contains(r.out, "warning: --plot: the tool path is drawn to within 0.256 mm (at most 200000 points)"));
  // the timeline says so itself
  Json t = Json::parse(test::readFileBytes(o.timeline));
  CHECK(t["otherData"]["max_events"] == 100000);
  CHECK(t["otherData"]["dropped"].get<uint64_t>() > 0);
  REQUIRE(t["otherData"]["warnings"].size() == 1);
  CHECK(contains(t["otherData"]["warnings"][0].get<std::string>(), "more were left out"));
  // and so does the plot, under its title
  const std::string svg = test::readFileBytes(o.plot);
  CHECK(contains(svg, "not everything is drawn: no block marker (80003 lines run"));
  CHECK(!contains(svg, "<title>long.mpf:3</title>"));
  CHECK(contains(svg, "the tool path is drawn to within 0.256 mm"));
  // the JSON summary carries the same warnings
  o.format = "json";
  ToolRun j = runSim(o);
  Json s = Json::parse(j.out);
  size_t viewWarnings = 0;
  for (const auto& w : s["warnings"])
    viewWarnings += w.get<std::string>().rfind("--", 0) == 0 ? 1 : 0;
  CHECK(viewWarnings == 3);
  // a short run shows everything: no warning, an empty list in the timeline
  o.format.clear();
  o.program = dir.write("short.mpf", "G01 X10 F100\nM30\n");
  ToolRun q = runSim(o);
  CHECK(q.rc == 0);
  CHECK(!contains(q.out, "warning"));
  CHECK(Json::parse(test::readFileBytes(o.timeline))["otherData"]["warnings"].empty());
  CHECK(!contains(test::readFileBytes(o.plot), "not everything is drawn"));
}

TEST_CASE("sim: the JSON trace's summary has the views' warnings too") {
  TempDir dir;
  driver::SimulateOptions o;
  o.program = dir.write("long.mpf", kLongRun);
  o.output = dir.path() + "/trace.json";
  o.dt = 1;
  o.timeline = dir.path() + "/t.json";
  ToolRun r = runSim(o);
  CHECK(r.rc == 0);
  Json trace = Json::parse(test::readFileBytes(o.output));
  REQUIRE(trace["summary"]["warnings"].size() == 1);
  CHECK(contains(trace["summary"]["warnings"][0].get<std::string>(), "--timeline: the timeline holds its first"));
}

TEST_CASE("sim: --profile text is sorted by time, shows the 50 slowest lines by default, and says how many more") {
  // line k (1..60) dwells k ms; line 61 is M30 (no time)
  std::string prog;
  for (int k = 1; k <= 60; ++k)
    prog += "G04 F" + std::to_string(k / 1000.0).substr(0, 5) + "\n";
  prog += "M30\n";
  TempDir dir;
  driver::SimulateOptions o;
  o.program = dir.write("p.mpf", prog);
  o.profile = true;
  ToolRun r = runSim(o);
  INFO(r.out);
  CHECK(r.rc == 0);
  const size_t table = r.out.find("\nline ");
  REQUIRE(table != std::string::npos);
  const std::string rows = r.out.substr(r.out.find('\n', table + 1) + 1);
  CHECK(rows.rfind("p.mpf:60 ", 0) == 0); // the slowest first
  CHECK(contains(rows, "\np.mpf:59 "));
  CHECK(contains(rows, "\np.mpf:11 "));
  CHECK(!contains(rows, "p.mpf:10 "));
  CHECK(contains(rows, "\n... and 11 more lines (--profile-lines 0 shows all)\ntotal "));
  CHECK(rows.find("p.mpf:60 ") < rows.find("p.mpf:59 "));
  CHECK(contains(r.out, "warning: --profile: the table shows the 50 slowest of 61 lines (--profile-lines 0 shows "
                        "all)\n"));
  // --profile-lines 0: every line, M30 (no time) last; no warning
  o.profileLines = 0;
  ToolRun all = runSim(o);
  CHECK(contains(all.out, "\np.mpf:1 "));
  CHECK(contains(all.out, "\np.mpf:61 "));
  CHECK(all.out.find("\np.mpf:1 ") < all.out.find("\np.mpf:61 "));
  CHECK(!contains(all.out, "more lines"));
  CHECK(!contains(all.out, "warning"));
  // --profile-lines 3
  o.profileLines = 3;
  ToolRun three = runSim(o);
  CHECK(contains(three.out, "... and 58 more lines"));
  // JSON stays complete: every line, in file order, and no warning
  o.profileLines = 50;
  o.format = "json";
  ToolRun j = runSim(o);
  Json doc = Json::parse(j.out);
  CHECK(doc["profile"]["lines"].size() == 61);
  CHECK(doc["profile"]["lines"][0]["line"] == 1);
  CHECK(doc["summary"]["warnings"].empty());
}

TEST_CASE("sim: ties in the --profile table go by file, then line") {
  sim::TimeProfile p;
  p.cycleTimeS = 1;
  for (uint32_t line : {7u, 3u, 5u}) {
    sim::LineProfile lp;
    lp.file = "b.mpf";
    lp.line = line;
    p.lines.push_back(lp);
  }
  sim::LineProfile a;
  a.file = "a.mpf";
  a.line = 9;
  p.lines.push_back(a);
  sim::LineProfile slow;
  slow.file = "z.mpf";
  slow.line = 1;
  slow.time.add(sim::TimeCat::Dwell, 1);
  p.lines.push_back(slow);
  std::vector<size_t> order = sim::linesBySlowest(p);
  REQUIRE(order.size() == 5);
  CHECK(order == std::vector<size_t>{4, 3, 1, 2, 0}); // z:1, then a:9, b:3, b:5, b:7
  const std::string text = sim::renderProfileText(p, 2);
  CHECK(text.find("z.mpf:1 ") < text.find("a.mpf:9 "));
  CHECK(contains(text, "... and 3 more lines (--profile-lines 0 shows all)\n"));
}

TEST_CASE("sim: --report says in the summary's warnings that its page lists only the slowest lines") {
  std::string prog;
  for (int k = 0; k < 510; ++k)
    prog += "G04 F0.001\n";
  prog += "M30\n";
  TempDir dir;
  driver::SimulateOptions o;
  o.program = dir.write("p.mpf", prog);
  o.summary = true;
  o.report = dir.path() + "/r.html";
  ToolRun r = runSim(o);
  CHECK(r.rc == 0);
  CHECK(contains(r.out, "warning: --report: the page lists the 500 slowest of 511 lines\n"));
  CHECK(contains(test::readFileBytes(o.report), "faster lines are not listed"));
}
