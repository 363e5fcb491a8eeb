//! @file SearchTests.cpp
//! @brief isosim --search (block search), in process through runSimulate: the line a TEXT
//!        finds in both dialects, search mode before it (zero time, axes at their targets,
//!        modal G and F carried, M functions not sent, WHENs not armed, calls as one block),
//!        the state output at the found line, the cycle time from there (hand-computed), and
//!        the refusals (not found, in a subprogram, an image, the program ending first).
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include "TestUtil.h"
#include "sim/SimToolRun.h"

using namespace iso;
using Json = nlohmann::json;
using test::contains;
using test::runSim;
using test::TempDir;
using test::ToolRun;

namespace {

/// X: 50 mm/s, 1000 mm/s²: a G00 move of d >= 2.5 mm takes d/50 + 0.05 s, and so does a feed
/// move at F >= 50. M23 lasts 5 s and sets input 27; limits -100..100.
std::string machineJson(const std::string& dialect) {
  return R"({"name": "searchtest", "dialect": ")" + dialect + R"(",
    "axes": [{"name": "X", "max_velocity": 50, "max_accel": 1000, "limit_minus": -100, "limit_plus": 100}],
    "m_sequences": {"23": {"duration_s": 5, "set_inputs": {"27": 1}}}})";
}

/// Runs `main` (p.mpf, with `more` files beside it) with --summary --format json (and a JSON
/// trace in t.json when `trace`).
struct SearchRun {
  ToolRun tool;
  Json summary;
  Json trace;
};

SearchRun search(const std::string& main, const std::string& text, const std::string& dialect = "sidac",
                 const std::vector<std::pair<std::string, std::string>>& more = {}, bool trace = false) {
  TempDir dir;
  driver::SimulateOptions o;
  o.program = dir.write("p.mpf", main);
  for (const auto& [name, body] : more)
    dir.write(name, body);
  o.common.machinePath = dir.write("m.json", machineJson(dialect));
  if (!text.empty()) o.search = text;
  o.format = "json";
  if (trace)
    o.output = dir.path() + "/t.json";
  else
    o.summary = true;
  SearchRun r;
  r.tool = runSim(o);
  if (r.tool.rc <= 3 && !r.tool.out.empty()) r.summary = Json::parse(r.tool.out);
  if (trace && r.tool.rc <= 3) {
    std::ifstream in(o.output);
    if (in) r.trace = Json::parse(in);
  }
  return r;
}

double approx(const Json& v) { return v.get<double>(); }

} // namespace

TEST_CASE("search: sidac, a label: the lines before it take no time, the axes and G91/F are carried") {
  const std::string prog = "G01 F=50 X10\n"  // search: X takes 10 at once
                           "G91\n"           // modal, carried
                           "R1=2\n"          // computed as written
                           "M23\n"           // not sent: no 5 s, no input
                           "G04 F3\n"        // no time
                           "Start: X=R1*5\n" // G91 F50: X 10 -> 20, 10/50 + 0.05 = 0.25 s
                           "M30\n";
  SearchRun full = search(prog, "");
  REQUIRE(full.tool.rc == 0);
  CHECK(approx(full.summary["cycle_time_s"]) == doctest::Approx(0.25 + 5 + 3 + 0.25));
  CHECK_FALSE(full.summary.contains("search"));

  SearchRun r = search(prog, "start"); // any case
  INFO(r.tool.err);
  REQUIRE(r.tool.rc == 0);
  CHECK(approx(r.summary["cycle_time_s"]) == doctest::Approx(0.25));
  CHECK(r.summary["blocks"] == 2);         // the found line and M30
  CHECK(r.summary["lines_executed"] == 2); // nor the lines run in search mode
  CHECK(approx(r.summary["final_position"]["X"]) == doctest::Approx(20));
  CHECK(r.summary["search"] == Json{{"text", "start"}, {"file", "p.mpf"}, {"line", 6}});
}

TEST_CASE("search: the trace starts at the found line, and outputs written while searching are output there") {
  SearchRun r = search("G00 X10\n$aa_out[3]=1\nM23\nWHEN $aa_iw[X] > 5 DO $aa_out[4]=1\nX20\nHere: X30\nM30\n", "HERE",
                       "sidac", {}, true);
  INFO(r.tool.err);
  REQUIRE(r.tool.rc == 0);
  const Json& ev = r.trace["events"];
  REQUIRE(ev.size() >= 3);
  CHECK(ev[0] == Json{{"t", 0}, {"kind", "output"}, {"index", 3}, {"value", 1}});
  CHECK(ev[1]["kind"] == "line");
  CHECK(ev[1]["line"] == 6);
  for (const Json& e : ev) {
    CHECK(e["kind"] != "m_start");                             // M23 not sent
    CHECK_FALSE((e["kind"] == "output" && e["index"] == 4));   // the WHEN was not armed
    if (e["kind"] == "line") CHECK(e["line"].get<int>() >= 6); // no line before the found one
  }
  // the first sample shows the axis where the search left it; X 20 -> 30 takes 10/50 + 0.05 s
  CHECK(r.trace["samples"][0][1] == 20);
  CHECK(approx(r.trace["summary"]["cycle_time_s"]) == doctest::Approx(0.25));
  CHECK(r.trace["summary"]["search"]["line"] == 6);
}

TEST_CASE("search: z32, a GO target: spindle, coolant and the tool the skipped M6 mounted are output at the line") {
  const std::string prog = "N10 G00 X10\n"
                           "N20 T1 M6\n"
                           "N30 S1000 M3 M8\n"
                           "T2\n" // programmed, not mounted
                           "M23\n"
                           " N40 G04 F9\n"      // blanks before N: never found
                           "N40 G01 F=50 X20\n" // 10/50 + 0.05 = 0.25 s
                           "M30\n";
  SearchRun r = search(prog, "N40", "z32", {}, true);
  INFO(r.tool.err);
  REQUIRE(r.tool.rc == 0);
  const Json& ev = r.trace["events"];
  REQUIRE(ev.size() >= 4);
  CHECK(ev[0] == Json{{"t", 0}, {"kind", "spindle"}, {"state", "cw"}, {"rpm", 1000}});
  CHECK(ev[1] == Json{{"t", 0}, {"kind", "coolant"}, {"c1", false}, {"c2", true}});
  CHECK(ev[2]["kind"] == "tool");
  CHECK(ev[2]["tool"] == 1);
  CHECK(ev[3]["kind"] == "line");
  CHECK(ev[3]["line"] == 7);
  for (const Json& e : ev)
    CHECK(e["kind"] != "m_start");
  const Json& s = r.trace["summary"];
  CHECK(approx(s["cycle_time_s"]) == doctest::Approx(0.25));
  CHECK(approx(s["spindle_on_s"]) == doctest::Approx(0.25));
  CHECK(s["tool"] == 1);
  CHECK(s["tool_changes"] == 1);
  CHECK(s["search"] == Json{{"text", "N40"}, {"file", "p.mpf"}, {"line", 7}});
}

TEST_CASE("search: a call before the found line runs as one block in search mode (SAVE restores G90)") {
  SearchRun r = search("G00 X10\nLift\nHere: G00 X1\nM30\n", "Here", "sidac",
                       {{"lift.spf", "PROC Lift SAVE\nG91\nG00 X5\nG04 F2\nM17\n"}});
  INFO(r.tool.err);
  REQUIRE(r.tool.rc == 0);
  // X is at 15 after the call; G90 again: X 15 -> 1, 14/50 + 0.05 s
  CHECK(approx(r.summary["cycle_time_s"]) == doctest::Approx(14.0 / 50 + 0.05));
  CHECK(approx(r.summary["final_position"]["X"]) == doctest::Approx(1));
}

TEST_CASE("search: a target outside the soft limits is still an emergency, but the path is not checked") {
  SearchRun r = search("G00 X150\nHere: X0\nM30\n", "Here");
  CHECK(r.tool.rc == 3);
  CHECK(contains(r.summary["message"].get<std::string>(), "p.mpf:1: emergency at t=0 s: soft limit"));
}

TEST_CASE("search: the program ending before the found line is a runtime error naming it") {
  SearchRun r = search("G00 X10\nGOTOF Past\nHere: X20\nPast: M30\n", "here");
  CHECK(r.tool.rc == 1);
  CHECK(r.summary["status"] == "error");
  CHECK(
      contains(r.summary["message"].get<std::string>(),
               "p.mpf:4: runtime error at t=0 s: the program ended before the searched line p.mpf:3 (--search here)"));
  CHECK(r.summary["search"]["line"] == 3);
}

TEST_CASE("search: TEXT not found, or found only in a subprogram, is a usage error naming it") {
  SearchRun none = search("G00 X10\nM30\n", "Nowhere");
  CHECK(none.tool.rc == 2);
  CHECK(contains(none.tool.err, "isosim: error: --search Nowhere: "));
  CHECK(contains(none.tool.err, "has no label Nowhere"));

  SearchRun sub = search("Lift\nM30\n", "Inside", "sidac", {{"lift.spf", "PROC Lift SAVE\nInside: G04 F1\nM17\n"}});
  CHECK(sub.tool.rc == 2);
  CHECK(contains(sub.tool.err, "--search Inside: the line is in subprogram Lift ("));
  CHECK(contains(sub.tool.err, "lift.spf:2), not in the entry program "));

  SearchRun z = search("N10 G00 X1\n N20 X2\nM30\n", "N20", "z32");
  CHECK(z.tool.rc == 2);
  CHECK(contains(z.tool.err, "begins with N20 (line 2 would but for the blanks before it"));

  // in sidac a GO-target shape is only a label
  SearchRun s = search("N20 G00 X1\nM30\n", "N20");
  CHECK(s.tool.rc == 2);
  CHECK(contains(s.tool.err, "has no label N20"));

  SearchRun empty = search("G00 X1\nM30\n", "");
  CHECK(empty.tool.rc == 0); // no --search at all
}

TEST_CASE("search: an image as PROGRAM is refused (it keeps no labels)") {
  TempDir dir;
  // any file with the image magic is an image for isosim: the refusal comes before it is read
  driver::SimulateOptions o;
  o.program = dir.write("p.isob", std::string("ISOB\r\n\x1a\n", 8) + "rest");
  o.search = "Here";
  o.summary = true;
  ToolRun r = runSim(o);
  CHECK(r.rc == 2);
  CHECK(contains(r.err, "--search needs the source program"));
}

TEST_CASE("search: real-time reads see time 0: a wait for an input before the found line never ends") {
  TempDir dir;
  driver::SimulateOptions o;
  o.program = dir.write("p.mpf", "Wait: IF $aa_in[27] == 0 GOTOB Wait\nHere: G04 F1\nM30\n");
  o.common.machinePath = dir.write("m.json", R"({"axes": [{"name": "X", "max_velocity": 50, "max_accel": 1000,
    "limit_minus": -100, "limit_plus": 100}], "inputs": {"27": [[0.0, 0], [2.5, 1]]}})");
  o.summary = true;
  o.maxSteps = 5000; // the wait takes 1250 statements (one per 2 ms interpolation cycle)
  ToolRun plain = runSim(o);
  CHECK(plain.rc == 0); // without --search the loop waits until 2.5 s
  CHECK(contains(plain.out, "cycle_time_s: 3.5"));
  o.search = "Here";
  ToolRun r = runSim(o);
  CHECK(r.rc == 1);
  CHECK(contains(r.out, "runtime error at t=0 s: the program reached 5000 statements, the limit of --max-steps"));
}

TEST_CASE("search: --block-skip skips a / line before the found line as it would after it") {
  SearchRun r = search("G00 X10\n/G00 X30\nHere: G91 G00 X10\nM30\n", "Here");
  CHECK(approx(r.summary["final_position"]["X"]) == doctest::Approx(40)); // the / line ran
  TempDir dir;
  driver::SimulateOptions o;
  o.program = dir.write("p.mpf", "G00 X10\n/G00 X30\nHere: G91 G00 X10\nM30\n");
  o.search = "Here";
  o.blockSkip = true;
  o.summary = true;
  ToolRun skipped = runSim(o);
  CHECK(skipped.rc == 0);
  CHECK(contains(skipped.out, "final_position: X=20 "));
}
