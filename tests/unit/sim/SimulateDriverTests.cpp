//! @file SimulateDriverTests.cpp
//! @brief isosim end to end, in process: exit codes, where trace and summary go, the CSV and
//!        JSON formats, bad machine files, every sample (from source and from its image, with
//!        byte-identical traces), determinism, the --plot SVG.
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include "SimTestUtil.h"
#include "SimToolRun.h"
#include "XmlCheck.h"
#include "frontend/ProgramSet.h"
#include "image/ImageWriter.h"

using namespace iso;
using namespace iso::test;
using Json = nlohmann::json;

namespace {

namespace fs = std::filesystem;

std::string readFile(const std::string& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

const std::string kSamples = std::string(ISO_SOURCE_DIR) + "/samples";

/// The samples and the machine files they come with (SPEC: every sample runs).
struct SampleRun {
  std::string program;
  std::string machine; ///< "" = built-in
  std::string entry;
};
std::vector<SampleRun> sampleRuns() {
  return {
      {"pallet_loader/pallettizzatore.mpf", "", ""},
      {"drilling_when/foratura_piastra.mpf", "", ""},
      {"wait_input/stazione_saldatura.mpf", "", ""},
      {"wait_input/stazione_saldatura.mpf", "wait_input/machine.json", ""},
      {"recipe_case/dosatrice.mpf", "", ""},
      {"recipe_case/dosatrice.mpf", "recipe_case/ricetta3.json", ""},
      {"five_axis/marcatura_5assi.mpf", "", ""},
      {"semi_auto/fresatura_cornice.mpf", "", ""},
      {"semi_auto/fresatura_cornice.mpf", "", "Cambio utensile manuale"},
      {"semi_auto/fresatura_cornice.mpf", "", "Posizione di carico"},
      {"contour_g64/taglio_piastra.mpf", "", ""},
  };
}

/// Compiles a program set exactly as isocc does and writes the image file.
std::string writeImageOf(const std::string& program, const std::string& machinePath, const std::string& dir) {
  machine::Machine m = machine::builtinMachine();
  if (!machinePath.empty()) m = machineFromJson(readFile(machinePath));
  frontend::LoadOptions lo;
  lo.machine = &m;
  lo.dialect = m.dialect;
  frontend::ProgramSet set;
  frontend::SetError err;
  REQUIRE(frontend::loadProgramSet({program}, lo, set, err));
  std::string diags;
  image::Image img = compileSet(set, m, &diags);
  REQUIRE(diags.empty());
  auto bytes = image::writeImage(img);
  std::string path = dir + "/" + fs::path(program).stem().string() + ".isob";
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  return path;
}

} // namespace

TEST_CASE("sim: isosim with -o writes the trace file and prints the summary with the cycle time") {
  TempDir dir;
  std::string prog = dir.write("p.mpf", "G00 X100\nG04 F0.5\nM30\n");
  driver::SimulateOptions o;
  o.program = prog;
  o.output = dir.path() + "/trace.csv";
  o.dt = 0.1;
  ToolRun r = runSim(o);
  CHECK(r.rc == 0);
  CHECK(r.err.empty());
  CHECK(contains(r.out, "status: ok\n"));
  CHECK(contains(r.out, "cycle_time_s: 0.947214 s (0:00.9)\n")); // 2·sqrt(100/2000) + 0.5
  std::string csv = readFile(o.output);
  CHECK(csv.rfind("t,X,Y,Z,A,B,C,U,V,W\n0,0,0,0,0,0,0,0,0,0\n0.1,10,", 0) == 0);
  // the last row is the exact end (0.947214 is not a multiple of 0.1)
  CHECK(contains(csv, "\n0.9,100,0,0,0,0,0,0,0,0\n0.947214,100,0,0,0,0,0,0,0,0\n"));
  CHECK(csv.size() == csv.rfind("0.947214,") + std::string("0.947214,100,0,0,0,0,0,0,0,0\n").size());
}

TEST_CASE("sim: isosim without -o writes the trace to stdout and the summary to stderr") {
  TempDir dir;
  driver::SimulateOptions o;
  o.program = dir.write("p.mpf", "G04 F0.25\nM30\n");
  o.dt = 0.05;
  ToolRun r = runSim(o);
  CHECK(r.rc == 0);
  // 0.25 is a sample time: no extra row
  CHECK(r.out == "t,X,Y,Z,A,B,C,U,V,W\n0,0,0,0,0,0,0,0,0,0\n0.05,0,0,0,0,0,0,0,0,0\n0.1,0,0,0,0,0,0,0,0,0\n"
                 "0.15,0,0,0,0,0,0,0,0,0\n0.2,0,0,0,0,0,0,0,0,0\n0.25,0,0,0,0,0,0,0,0,0\n");
  CHECK(r.err == "status: ok\ncycle_time_s: 0.25 s (0:00.3)\n"
                 "blocks: 2 (lines charged with block_time_s; G64 read-ahead not counted)\n"
                 "lines_executed: 2\nfinal_position: X=0 Y=0 Z=0 A=0 B=0 C=0 U=0 V=0 W=0\n");
}

TEST_CASE("sim: --summary prints only the summary, as text or JSON") {
  TempDir dir;
  driver::SimulateOptions o;
  o.program = dir.write("p.mpf", "G00 X1000\nM77\nM30\n");
  o.summary = true;
  ToolRun t = runSim(o);
  CHECK(t.rc == 0);
  CHECK(t.out == "status: ok\ncycle_time_s: 2.25 s (0:02.3)\n"
                 "blocks: 3 (lines charged with block_time_s; G64 read-ahead not counted)\n"
                 "lines_executed: 3\nfinal_position: X=1000 Y=0 Z=0 A=0 B=0 C=0 U=0 V=0 "
                 "W=0\nwarning: M77 has no model in the machine file: default_m_duration_s (0 s) was used\n");
  o.format = "json";
  ToolRun j = runSim(o);
  CHECK(j.rc == 0);
  Json s = Json::parse(j.out);
  CHECK(s["status"] == "ok");
  CHECK(s["cycle_time_s"].get<double>() == 2.25);
  CHECK(s["final_position"]["X"].get<double>() == 1000);
  CHECK(s["blocks"] == 3);
  CHECK(s["message"].is_null());
  CHECK(s["warnings"].size() == 1);
  // key order is fixed
  CHECK(j.out.find("\"status\"") < j.out.find("\"cycle_time_s\""));
  CHECK(j.out.find("\"final_position\"") < j.out.find("\"blocks\""));
}

TEST_CASE("sim: the JSON trace has samples, events and the summary") {
  TempDir dir;
  driver::SimulateOptions o;
  o.program = dir.write("p.mpf", "N10 WHEN $aa_iw[X] > 10 DO $aa_out[2] = 1\nN20 G00 X100\nM30\n");
  o.output = dir.path() + "/t.json"; // the format follows the extension
  o.dt = 0.1;
  ToolRun r = runSim(o);
  CHECK(r.rc == 0);
  Json j = Json::parse(readFile(o.output));
  CHECK(j["format_version"] == 1);
  CHECK(j["machine"] == "default");
  CHECK(j["columns"][0] == "t");
  CHECK(j["columns"].size() == 10);
  CHECK(j["samples"].size() == 6); // 0 .. 0.4 and the end 0.447214
  CHECK(j["samples"][5][0].get<double>() == doctest::Approx(0.447214));
  std::vector<std::string> kinds;
  for (const auto& e : j["events"])
    kinds.push_back(e["kind"]);
  CHECK(kinds == std::vector<std::string>{"line", "line", "move_start", "when", "when", "line", "output", "when",
                                          "move_end", "line", "end"});
  CHECK(j["events"][0]["n"] == 10);
  CHECK(j["events"][3]["action"] == "armed");
  CHECK(j["events"][4]["action"] == "fired");
  CHECK(j["events"][7]["action"] == "ended"); // the body is done (it only wrote an output)
  CHECK(j["summary"]["status"] == "ok");
}

TEST_CASE("sim: a trace that stops on an error is complete up to that instant and says why") {
  TempDir dir;
  driver::SimulateOptions o;
  o.program = dir.write("p.mpf", "G00 Posa[X]=1000\nG04 F0.5\nX0\nM30\n");
  o.output = dir.path() + "/t.json";
  ToolRun r = runSim(o);
  CHECK(r.rc == 3);
  CHECK(contains(r.err, "isosim: p.mpf:3: emergency at t=0.5 s: axis X programmed while moving"));
  Json j = Json::parse(readFile(o.output));
  CHECK(j["summary"]["status"] == "emergency");
  CHECK(j["events"].back()["kind"] == "error");
  CHECK(j["events"].back()["status"] == "emergency");
  CHECK(j["samples"].back()[0].get<double>() == 0.5);
  CHECK(j["samples"].back()[1].get<double>() == doctest::Approx(62.5 + 500 * 0.25));
  // runtime error: exit 1
  o.program = dir.write("q.mpf", "R1 = 0\nR2 = 1 / R1\nM30\n");
  o.output.clear();
  o.summary = true;
  ToolRun e = runSim(o);
  CHECK(e.rc == 1);
  CHECK(contains(e.out, "status: error\n"));
  CHECK(contains(e.out, "message: q.mpf:2: runtime error at t=0 s: division by zero"));
}

TEST_CASE("sim: a source program with errors: diagnostics on stderr, status error, exit 1") {
  TempDir dir;
  driver::SimulateOptions o;
  o.program = dir.write("bad.mpf", "G00 X1\nGOTOF Nowhere\nM30\n");
  o.summary = true;
  ToolRun r = runSim(o);
  CHECK(r.rc == 1);
  CHECK(contains(r.err, "bad.mpf:2:"));
  CHECK(contains(r.err, "E202"));
  CHECK(contains(r.out, "status: error\n"));
  CHECK(contains(r.out, "cycle_time_s: 0 s (0:00.0)\n"));
}

TEST_CASE("sim: z32 O<n> for an origin the built-in machine lacks is a runtime error, E313 with a machine file") {
  TempDir dir;
  driver::SimulateOptions o;
  o.program = dir.write("o.mpf", "G00 X1\nO5\nX2\nM30\n");
  o.common.dialect = "z32";
  o.summary = true;
  ToolRun run = runSim(o);
  CHECK(run.rc == 1);
  CHECK(!contains(run.err, "E313"));
  CHECK(contains(run.out, "status: error\n"));
  CHECK(contains(run.out, "message: o.mpf:2: runtime error at t="));
  CHECK(contains(run.out, "origin O5 is not in the origins of machine"));
  CHECK(contains(run.out, "final_position: X=1 "));
  o.common.machinePath = dir.write("m.json", R"({"dialect": "z32", "axes": [{"name": "X", "max_velocity": 500,
      "max_accel": 2000, "limit_minus": -1000, "limit_plus": 3000}], "origins": {"1": {"X": 10}}})");
  ToolRun lint = runSim(o);
  CHECK(lint.rc == 1);
  CHECK(contains(lint.err, "o.mpf:2:1: error: origin O5 is not in the machine file (its origins: O1)"));
  CHECK(contains(lint.out, "cycle_time_s: 0 s (0:00.0)\n"));
}

TEST_CASE("sim: usage and input errors exit 2") {
  TempDir dir;
  std::string prog = dir.write("p.mpf", "G00 X1 Y1\nM30\n");
  driver::SimulateOptions o;
  CHECK(runSim(o).rc == 2); // no program
  o.program = dir.path() + "/missing.mpf";
  CHECK(runSim(o).rc == 2);
  o.program = prog;
  o.dt = 0;
  CHECK(runSim(o).rc == 2);
  o.dt = 0.01;
  // the machine has no Y
  o.common.machinePath = dir.write("m.json", R"({"axes": [{"name": "X", "max_velocity": 500, "max_accel": 2000,
      "limit_minus": -1000, "limit_plus": 3000}]})");
  o.program = writeImageOf(prog, "", dir.path());
  ToolRun miss = runSim(o);
  CHECK(miss.rc == 2);
  CHECK(contains(miss.err, "axis Y"));
  // an image with a damaged byte
  o.common.machinePath.clear();
  std::string img = readFile(o.program);
  img[img.size() - 3] = static_cast<char>(img[img.size() - 3] ^ 0x55);
  std::string bad = dir.write("bad.isob", img);
  o.program = bad;
  ToolRun inv = runSim(o);
  CHECK(inv.rc == 2);
  CHECK(contains(inv.err, "invalid image"));
  // PATH... after an image
  o.program = writeImageOf(prog, "", dir.path());
  o.paths = {dir.path()};
  CHECK(runSim(o).rc == 2);
}

TEST_CASE("sim: bad machine files exit 2 naming the JSON path") {
  TempDir dir;
  std::string prog = dir.write("p.mpf", "G00 X1\nM30\n");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {R"({"axes": [{"name": "X", "max_velocity": 500, "max_accel": 2000, "limit_minus": -1, "limit_plus": 1}],
          "colour": 1})",
       "/colour"},
      {R"({"axes": [{"name": "X", "max_velocity": -5, "max_accel": 2000, "limit_minus": -1, "limit_plus": 1}]})",
       "/axes/0/max_velocity"},
      {R"({"axes": [{"name": "X", "max_velocity": 5, "max_accel": "fast", "limit_minus": -1, "limit_plus": 1}]})",
       "/axes/0/max_accel"},
      {R"({"axes": [{"name": "X", "max_velocity": 5, "max_accel": 5, "limit_minus": -1, "limit_plus": 1},
                    {"name": "X", "max_velocity": 5, "max_accel": 5, "limit_minus": -1, "limit_plus": 1}]})",
       "/axes/1"},
      {R"({"axes": []})", "/axes"},
      {R"({"axes": [{"name": "X", "max_velocity": 5, "max_accel": 5, "limit_minus": -1, "limit_plus": 1}],
          "ipo_cycle_s": 0})",
       "/ipo_cycle_s"},
      {"not json", "/"},
  };
  for (const auto& c : cases) {
    const std::string json = c.first; // not a structured binding: clang 14 cannot capture those
    const std::string path = c.second;
    CAPTURE(json);
    driver::SimulateOptions o;
    o.program = prog;
    o.common.machinePath = dir.write("m.json", json);
    ToolRun r = runSim(o);
    CHECK(r.rc == 2);
    CHECK(contains(r.err, "invalid machine file at " + path));
  }
}

TEST_CASE("sim: --print-machine prints the built-in machine") {
  driver::SimulateOptions o;
  o.printMachine = true;
  ToolRun r = runSim(o);
  CHECK(r.rc == 0);
  auto back = machine::parseMachine(r.out);
  REQUIRE(back.ok());
  CHECK(back->axes.size() == 9);
  CHECK(machine::machineToJson(*back) + "\n" == r.out);
}

TEST_CASE("sim: every sample runs, from source and from its image, with identical traces") {
  TempDir dir;
  for (const auto& s : sampleRuns()) {
    CAPTURE(s.program);
    CAPTURE(s.machine);
    CAPTURE(s.entry);
    driver::SimulateOptions o;
    o.program = kSamples + "/" + s.program;
    if (!s.machine.empty()) o.common.machinePath = kSamples + "/" + s.machine;
    o.entry = s.entry;
    o.format = "json";
    o.dt = 0.05;
    ToolRun src = runSim(o);
    CHECK(src.rc == 0);
    Json j = Json::parse(src.out);
    CHECK(j["summary"]["status"] == "ok");
    CHECK(j["summary"]["cycle_time_s"].get<double>() > 0);
    CHECK(j["summary"]["cycle_time_s"].get<double>() < 120);
    // samples strictly increase in time, events never go back, the end is the last instant
    double last = -1;
    for (const auto& row : j["samples"]) {
      CHECK(row[0].get<double>() > last);
      last = row[0].get<double>();
    }
    CHECK(last == j["summary"]["cycle_time_s"].get<double>());
    double lastEvent = 0;
    for (const auto& e : j["events"]) {
      CHECK(e["t"].get<double>() >= lastEvent);
      lastEvent = e["t"].get<double>();
    }
    CHECK(j["events"].back()["kind"] == "end");
    // the same run from the image isocc would write
    driver::SimulateOptions io = o;
    io.program = writeImageOf(o.program, s.machine.empty() ? "" : kSamples + "/" + s.machine, dir.path());
    ToolRun img = runSim(io);
    CHECK(img.rc == 0);
    CHECK(img.out == src.out);
    CHECK(img.err == src.err);
    // CSV too, and the same bytes again (deterministic)
    o.format = io.format = "csv";
    ToolRun a = runSim(o), b = runSim(io), c = runSim(o);
    CHECK(a.out == b.out);
    CHECK(a.out == c.out);
  }
}

TEST_CASE("sim: --plot writes an SVG of the moving axes, with units and a legend, beside the trace") {
  TempDir dir;
  driver::SimulateOptions o;
  o.program = dir.write("p.mpf", "N10 G00 X100\nG01 Z-5 F50\nM23\nM30\n");
  o.output = dir.path() + "/trace.csv";
  o.dt = 0.05;
  ToolRun plain = runSim(o);
  std::string csvAlone = readFile(o.output);
  o.plot = dir.path() + "/p.svg";
  ToolRun r = runSim(o);
  CHECK(r.rc == 0);
  CHECK(r.out == plain.out); // the summary and the trace do not change
  CHECK(readFile(o.output) == csvAlone);
  std::string svg = readFile(o.plot);
  CHECK(xmlProblem(svg) == "");
  CHECK(svg.rfind("<svg xmlns=\"http://www.w3.org/2000/svg\"", 0) == 0);
  CHECK(contains(r.out, "cycle_time_s: 0.572214 s (0:00.6)\n")); // 2·sqrt(100/2000) + 5/50 + 50/2000
  CHECK(contains(svg, ">p.mpf - cycle time 0.572214 s<"));
  CHECK(contains(svg, ">axis X<"));
  CHECK(contains(svg, ">axis Z<"));
  for (const char* still : {">axis Y<", ">axis A<", ">axis B<", ">axis C<", ">axis U<", ">axis V<", ">axis W<"}) {
    CAPTURE(still);
    CHECK_FALSE(contains(svg, still));
  }
  CHECK(contains(svg, ">time (s)<"));
  CHECK(contains(svg, ">position (mm"));
  CHECK(contains(svg, ">velocity (mm/s"));
  CHECK(contains(svg, ">block<"));
  CHECK(contains(svg, ">M, WHEN, dwell<"));
  CHECK(contains(svg, "<title>p.mpf:1 N10</title>"));
  CHECK(contains(svg, "<title>M23 start"));
}

TEST_CASE("sim: --plot with --summary or a JSON trace - the same run twice gives the same bytes") {
  TempDir dir;
  driver::SimulateOptions o;
  o.program = kSamples + "/five_axis/marcatura_5assi.mpf";
  o.summary = true;
  o.plot = dir.path() + "/a.svg";
  ToolRun a = runSim(o);
  CHECK(a.rc == 0);
  o.plot = dir.path() + "/b.svg";
  ToolRun b = runSim(o);
  CHECK(b.out == a.out);
  std::string svg = readFile(dir.path() + "/a.svg");
  CHECK(svg == readFile(o.plot));
  CHECK(xmlProblem(svg) == "");
  CHECK(contains(svg, ">marcatura_5assi.mpf - cycle time "));
  for (const char* moving : {">axis X<", ">axis Y<", ">axis Z<", ">axis A<", ">axis C<"}) {
    CAPTURE(moving);
    CHECK(contains(svg, moving));
  }
  CHECK_FALSE(contains(svg, ">axis B<"));
  // with a JSON trace on stdout: the same plot
  o.summary = false;
  o.format = "json";
  o.plot = dir.path() + "/c.svg";
  ToolRun c = runSim(o);
  CHECK(c.rc == 0);
  CHECK(Json::parse(c.out)["summary"]["status"] == "ok");
  CHECK(readFile(o.plot) == svg);
}

TEST_CASE("sim: --plot is written when the run ends in an emergency or an error, up to that instant") {
  TempDir dir;
  driver::SimulateOptions o;
  o.program = dir.write("p.mpf", "G00 Posa[X]=1000\nG04 F0.5\nX0\nM30\n");
  o.plot = dir.path() + "/e.svg";
  o.summary = true;
  ToolRun r = runSim(o);
  CHECK(r.rc == 3);
  std::string svg = readFile(o.plot);
  CHECK(xmlProblem(svg) == "");
  CHECK(contains(svg, ">p.mpf - emergency at t=0.5 s<"));
  CHECK(contains(svg, "axis X programmed while moving"));
  CHECK(contains(svg, ">error, emergency<"));
  CHECK(contains(svg, "<title>dwell 0.5 s</title>"));
  // a runtime error before anything moved: a plot of nothing that says why
  o.program = dir.write("q.mpf", "R1 = 0\nR2 = 1 / R1\nM30\n");
  ToolRun e = runSim(o);
  CHECK(e.rc == 1);
  svg = readFile(o.plot);
  CHECK(xmlProblem(svg) == "");
  CHECK(contains(svg, ">q.mpf - error at t=0 s<"));
  CHECK(contains(svg, "division by zero"));
  CHECK(contains(svg, ">no axis moves<"));
}

TEST_CASE("sim: --plot errors: an unwritable file or the file of -o exit 2 - no plot when nothing runs") {
  TempDir dir;
  driver::SimulateOptions o;
  std::string prog = dir.write("p.mpf", "G00 X1 Y1\nM30\n");
  o.program = prog;
  o.summary = true;
  o.plot = dir.path() + "/no/such/dir/p.svg";
  ToolRun r = runSim(o);
  CHECK(r.rc == 2);
  CHECK(r.err == o.plot + ": error: cannot create the plot file: cannot create the file: no such file or directory\n");
  CHECK(r.out.empty());
  // with a trace file: the run does not start, and no empty trace is left behind
  o.summary = false;
  o.output = dir.path() + "/t.csv";
  ToolRun t = runSim(o);
  CHECK(t.rc == 2);
  CHECK(t.err == o.plot + ": error: cannot create the plot file: cannot create the file: no such file or directory\n");
  CHECK_FALSE(fs::exists(o.output));
  o.output.clear();
  o.summary = true;
  // the same file as the trace
  o.summary = false;
  o.output = dir.path() + "/x.svg";
  o.plot = dir.path() + "/./x.svg";
  ToolRun same = runSim(o);
  CHECK(same.rc == 2);
  CHECK(same.err ==
        "isosim: error: -o " + o.output + " and --plot " + o.plot + " name the same file (run 'isosim --help')\n");
  CHECK_FALSE(fs::exists(o.output));
  // refused before it runs (the image uses Y, the machine has none), or a program with errors:
  // no plot file
  o.output.clear();
  o.program = writeImageOf(prog, "", dir.path());
  o.plot = dir.path() + "/none.svg";
  o.common.machinePath = dir.write("m.json", R"({"axes": [{"name": "X", "max_velocity": 500, "max_accel": 2000,
      "limit_minus": -1000, "limit_plus": 3000}]})");
  CHECK(runSim(o).rc == 2);
  CHECK_FALSE(fs::exists(o.plot));
  o.common.machinePath.clear();
  o.program = dir.write("bad.mpf", "G00 X1\nGOTOF Nowhere\nM30\n");
  CHECK(runSim(o).rc == 1);
  CHECK_FALSE(fs::exists(o.plot));
}

TEST_CASE("sim: --profile prints the summary and the profile - JSON is one object - -o keeps the trace") {
  TempDir dir;
  driver::SimulateOptions o;
  o.program = dir.write("p.mpf", "G00 X1000\nG04 F0.5\nM30\n");
  o.profile = true;
  ToolRun t = runSim(o);
  CHECK(t.rc == 0);
  CHECK(t.err.empty());
  CHECK(t.out.find("status: ok\ncycle_time_s: 2.75 s (0:02.8)\n") == 0);
  CHECK(contains(t.out, "profile: cycle time 2.750000 s"));
  CHECK(contains(t.out, "p.mpf:1"));
  CHECK(contains(t.out, "velocity X"));
  o.format = "json";
  ToolRun j = runSim(o);
  CHECK(j.rc == 0);
  Json all = Json::parse(j.out);
  CHECK(all["summary"]["cycle_time_s"].get<double>() == 2.75);
  const Json& p = all["profile"];
  CHECK(p["cycle_time_s"].get<double>() == 2.75);
  CHECK(p["total"]["dwell_s"].get<double>() == 0.5);
  REQUIRE(p["lines"].size() == 3);
  CHECK(p["lines"][0]["line"] == 1);
  CHECK(p["lines"][0]["cruise_s"].get<double>() == doctest::Approx(1.75).epsilon(1e-12));
  CHECK(p["lines"][0]["bounds"][0] == "velocity X");
  CHECK(p["programs"][0]["calls"] == 1);
  // with -o the trace is written as usual and the profile follows the summary on stdout
  o.format.clear();
  o.output = dir.path() + "/t.csv";
  ToolRun f = runSim(o);
  CHECK(f.rc == 0);
  CHECK(readFile(o.output).rfind("t,X,Y,Z", 0) == 0);
  CHECK(contains(f.out, "profile: cycle time 2.750000 s"));
  // an emergency still profiles up to the stop
  o.output.clear();
  o.program = dir.write("e.mpf", "G00 X100\nX5000\nM30\n");
  ToolRun e = runSim(o);
  CHECK(e.rc == 3);
  CHECK(contains(e.out, "status: emergency"));
  CHECK(contains(e.out, "profile: cycle time 0.447214 s"));
}

TEST_CASE("finding: --entry accepts a SEMI name as isosim lists it (escaped bytes that are not UTF-8)") {
  test::TempDir dir;
  dir.write("main.mpf", "G00 X1\nM30\n");
  dir.write("semi.mpf", "SEMI \"Caff\xE8 manuale\"\nG00 X2\nM30\n");
  driver::SimulateOptions o;
  o.program = dir.path() + "/main.mpf";
  o.summary = true;
  o.entry = "Caff\\xE8 manuale";
  std::ostringstream out, err;
  driver::Io io{out, err};
  int rc = driver::runSimulate(o, io);
  INFO(out.str(), err.str());
  CHECK(rc == 0);
  CHECK(out.str().find("X=2") != std::string::npos);
}
