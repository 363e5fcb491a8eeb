//! @file MachineTests.cpp
//! @brief Machine file parsing, validation (exact JSON paths), printing and round trips.
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include "machine/Machine.h"

using iso::machine::Axis;
using iso::machine::Dialect;
using iso::machine::Machine;
using iso::machine::MachineResult;

namespace {

using Json = nlohmann::json;

/// A small valid document that each rejection test breaks in exactly one place.
Json validDoc() {
  return Json::parse(R"({
    "name": "test",
    "axes": [
      {"name": "X", "max_velocity": 500, "max_accel": 2000, "limit_minus": -1000,
       "limit_plus": 3000, "start": 0},
      {"name": "Y", "max_velocity": 400, "max_accel": 1000, "limit_minus": 0,
       "limit_plus": 2000}
    ],
    "m_sequences": {"23": {"duration_s": 0.5, "set_inputs": {"27": 1}}},
    "inputs": {"27": [[0.0, 0], [2.5, 1]]},
    "r_preset": {"1": 5.0}
  })");
}

MachineResult parse(const Json& doc) { return iso::machine::parseMachine(doc.dump()); }

/// Checks that the document is rejected with the given JSON path; returns the message.
std::string rejectedAt(const Json& doc, const std::string& path) {
  const MachineResult r = parse(doc);
  CHECK_FALSE(r.ok());
  CHECK(r.error().where == path);
  CHECK_FALSE(r.error().message.empty());
  return r.error().message;
}

void checkSameMachine(const Machine& a, const Machine& b) {
  CHECK(a.name == b.name);
  CHECK(a.dialect == b.dialect);
  REQUIRE(a.axes.size() == b.axes.size());
  for (size_t i = 0; i < a.axes.size(); ++i) {
    CHECK(a.axes[i].letter == b.axes[i].letter);
    CHECK(a.axes[i].maxVelocity == b.axes[i].maxVelocity);
    CHECK(a.axes[i].maxAccel == b.axes[i].maxAccel);
    CHECK(a.axes[i].limitMinus == b.axes[i].limitMinus);
    CHECK(a.axes[i].limitPlus == b.axes[i].limitPlus);
    CHECK(a.axes[i].start == b.axes[i].start);
  }
  CHECK(a.ipoCycleS == b.ipoCycleS);
  CHECK(a.blockTimeS == b.blockTimeS);
  CHECK(a.cornerDeviationMm == b.cornerDeviationMm);
  CHECK(a.lookaheadBlocks == b.lookaheadBlocks);
  REQUIRE(a.mSequences.size() == b.mSequences.size());
  for (const auto& [n, seq] : a.mSequences) {
    REQUIRE(b.mSequences.count(n) == 1);
    CHECK(seq.durationS == b.mSequences.at(n).durationS);
    CHECK(seq.setInputs == b.mSequences.at(n).setInputs);
  }
  CHECK(a.defaultMDurationS == b.defaultMDurationS);
  CHECK(a.m0WaitS == b.m0WaitS);
  CHECK(a.numInputs == b.numInputs);
  CHECK(a.numOutputs == b.numOutputs);
  CHECK(a.inputs == b.inputs);
  CHECK(a.rPreset == b.rPreset);
  CHECK(a.specialM == b.specialM);
  CHECK(a.optionalStop == b.optionalStop);
  CHECK(a.auxDurationS == b.auxDurationS);
  CHECK(a.origins == b.origins);
  CHECK(a.parameters == b.parameters);
  CHECK(a.palPreset == b.palPreset);
  CHECK(a.zones == b.zones);
}

const char* const kFullFile = R"({
  "name": "router 3",
  "dialect": "z32",
  "axes": [
    {"name": "x", "max_velocity": 800, "max_accel": 2500.5, "limit_minus": -10,
     "limit_plus": 1200, "start": 5.25},
    {"name": "Y", "max_velocity": 600, "max_accel": 1500, "limit_minus": -20,
     "limit_plus": 900},
    {"name": "Z", "max_velocity": 200, "max_accel": 800, "limit_minus": -150,
     "limit_plus": 0, "start": -1}
  ],
  "ipo_cycle_s": 0.004,
  "block_time_s": 0.001,
  "corner_deviation_mm": 0.02,
  "lookahead_blocks": 16,
  "m_sequences": {
    "23": {"duration_s": 0.5, "set_inputs": {"27": 1, "3": 0}},
    "07": {"set_inputs": {}},
    "8": {"duration_s": 0}
  },
  "default_m_duration_s": 0.25,
  "m0_wait_s": 1.5,
  "num_inputs": 32,
  "num_outputs": 16,
  "inputs": {"27": [[0.0, 0], [2.5, 1]], "0": [[1, 1]]},
  "r_preset": {"1": 5.0, "2880": -0.125}
})";

} // namespace

TEST_CASE("machine: builtin machine has the SPEC 5.1 defaults") {
  const Machine m = iso::machine::builtinMachine();
  CHECK(m.name == "default");
  CHECK(m.dialect == Dialect::Sidac);
  REQUIRE(m.axes.size() == 9);
  const std::string letters = "XYZABCUVW";
  for (size_t i = 0; i < 9; ++i) {
    CHECK(m.axes[i].letter == letters[i]);
    CHECK(m.axes[i].maxVelocity == 500);
    CHECK(m.axes[i].maxAccel == 2000);
    CHECK(m.axes[i].limitMinus == -1000);
    CHECK(m.axes[i].limitPlus == 3000);
    CHECK(m.axes[i].start == 0);
  }
  CHECK(m.ipoCycleS == 0.002);
  CHECK(m.blockTimeS == 0.0);
  CHECK(m.cornerDeviationMm == 0.05);
  CHECK(m.lookaheadBlocks == 64);
  CHECK(m.mSequences.empty());
  CHECK(m.defaultMDurationS == 0.0);
  CHECK(m.m0WaitS == 0.0);
  CHECK(m.numInputs == 256);
  CHECK(m.numOutputs == 256);
  CHECK(m.inputs.empty());
  CHECK(m.rPreset.empty());
  CHECK(m.axisIndex('x') == 0);
  CHECK(m.axisIndex('W') == 8);
  CHECK(m.axisIndex('Q') == -1);
}

TEST_CASE("machine: dialect names") {
  CHECK(std::string(iso::machine::dialectName(Dialect::Sidac)) == "sidac");
  CHECK(std::string(iso::machine::dialectName(Dialect::Z32)) == "z32");
  CHECK(iso::machine::parseDialect("sidac") == Dialect::Sidac);
  CHECK(iso::machine::parseDialect("Z32") == Dialect::Z32);
  CHECK_FALSE(iso::machine::parseDialect("fanuc").has_value());
}

TEST_CASE("machine: builtin round trip through JSON") {
  const Machine m = iso::machine::builtinMachine();
  const std::string text = iso::machine::machineToJson(m);
  // §5.1 key order, 2-space indent.
  CHECK(text.rfind("{\n  \"name\": \"default\",\n  \"dialect\": \"sidac\",\n  \"axes\": [\n"
                   "    {\n      \"name\": \"X\",\n      \"max_velocity\": 500.0,\n",
                   0) == 0);
  const Json j = Json::parse(text);
  const std::vector<std::string> keys = {"name",
                                         "dialect",
                                         "axes",
                                         "ipo_cycle_s",
                                         "block_time_s",
                                         "corner_deviation_mm",
                                         "lookahead_blocks",
                                         "m_sequences",
                                         "default_m_duration_s",
                                         "m0_wait_s",
                                         "num_inputs",
                                         "num_outputs",
                                         "inputs",
                                         "r_preset"};
  size_t pos = 0;
  for (const std::string& key : keys) {
    const size_t at = text.find("\n  \"" + key + "\": ");
    REQUIRE(at != std::string::npos);
    CHECK(at >= pos);
    pos = at;
  }
  const MachineResult r = iso::machine::parseMachine(text);
  REQUIRE_MESSAGE(r.ok(), r.error().where << ": " << r.error().message);
  checkSameMachine(*r, m);
  CHECK(iso::machine::machineToJson(*r) == text);
}

TEST_CASE("machine: a full file with every key") {
  const MachineResult r = iso::machine::parseMachine(kFullFile);
  REQUIRE_MESSAGE(r.ok(), r.error().where << ": " << r.error().message);
  const Machine& m = *r;
  CHECK(m.name == "router 3");
  CHECK(m.dialect == Dialect::Z32);
  REQUIRE(m.axes.size() == 3);
  CHECK(m.axes[0].letter == 'X'); // stored upper-case
  CHECK(m.axes[0].maxVelocity == 800);
  CHECK(m.axes[0].maxAccel == 2500.5);
  CHECK(m.axes[0].limitMinus == -10);
  CHECK(m.axes[0].limitPlus == 1200);
  CHECK(m.axes[0].start == 5.25);
  CHECK(m.axes[1].letter == 'Y');
  CHECK(m.axes[1].start == 0); // default
  CHECK(m.axes[2].letter == 'Z');
  CHECK(m.axes[2].limitPlus == 0);
  CHECK(m.axes[2].start == -1);
  CHECK(m.ipoCycleS == 0.004);
  CHECK(m.blockTimeS == 0.001);
  CHECK(m.cornerDeviationMm == 0.02);
  CHECK(m.lookaheadBlocks == 16);
  REQUIRE(m.mSequences.size() == 3);
  CHECK(m.mSequences.at(23).durationS == 0.5);
  CHECK(m.mSequences.at(23).setInputs == std::vector<std::pair<int, int>>{{3, 0}, {27, 1}});
  CHECK(m.mSequences.at(7).durationS == 0.25); // no duration_s: default_m_duration_s
  CHECK(m.mSequences.at(7).setInputs.empty());
  CHECK(m.mSequences.at(8).durationS == 0);
  CHECK(m.defaultMDurationS == 0.25);
  CHECK(m.m0WaitS == 1.5);
  CHECK(m.numInputs == 32);
  CHECK(m.numOutputs == 16);
  REQUIRE(m.inputs.size() == 2);
  CHECK(m.inputs.at(27) == std::vector<std::pair<double, int>>{{0.0, 0}, {2.5, 1}});
  CHECK(m.inputs.at(0) == std::vector<std::pair<double, int>>{{1.0, 1}});
  CHECK(m.rPreset == std::map<int, double>{{1, 5.0}, {2880, -0.125}});

  const std::string text = iso::machine::machineToJson(m);
  const MachineResult again = iso::machine::parseMachine(text);
  REQUIRE_MESSAGE(again.ok(), again.error().where << ": " << again.error().message);
  checkSameMachine(*again, m);
  CHECK(iso::machine::machineToJson(*again) == text);
}

TEST_CASE("machine: minimal file takes every default") {
  const MachineResult r = iso::machine::parseMachine(
      R"({"axes": [{"name": "a", "max_velocity": 1, "max_accel": 1, "limit_minus": 0,
          "limit_plus": 0}]})");
  REQUIRE(r.ok());
  CHECK(r->name == "default");
  CHECK(r->axes[0].letter == 'A');
  CHECK(r->lookaheadBlocks == 64);
  CHECK(r->numInputs == 256);
}

TEST_CASE("machine: invalid JSON reports the byte position") {
  const MachineResult r = iso::machine::parseMachine("{\"axes\": [}");
  CHECK_FALSE(r.ok());
  CHECK(r.error().where.empty());
  CHECK(r.error().message.find("byte 11") != std::string::npos);
  const MachineResult empty = iso::machine::parseMachine("");
  CHECK_FALSE(empty.ok());
  CHECK(empty.error().where.empty());
  CHECK(empty.error().message.find("byte") != std::string::npos);
}

TEST_CASE("machine: rejects a document that is not an object or has no axes") {
  rejectedAt(Json::array(), "");
  Json doc = validDoc();
  doc.erase("axes");
  rejectedAt(doc, "");
}

TEST_CASE("machine: rejects unknown keys") {
  Json top = validDoc();
  top["speed"] = 1;
  rejectedAt(top, "/speed");
  Json axis = validDoc();
  axis["axes"][1]["max_velo"] = 100;
  rejectedAt(axis, "/axes/1/max_velo");
  Json seq = validDoc();
  seq["m_sequences"]["23"]["durat"] = 1;
  rejectedAt(seq, "/m_sequences/23/durat");
}

TEST_CASE("machine: rejects duplicate JSON keys") {
  const MachineResult r = iso::machine::parseMachine(
      R"({"axes": [{"name": "X", "name": "Y", "max_velocity": 1, "max_accel": 1,
          "limit_minus": 0, "limit_plus": 0}]})");
  CHECK_FALSE(r.ok());
  CHECK(r.error().where == "/axes/0/name");
}

TEST_CASE("machine: rejects wrong types") {
  Json a = validDoc();
  a["ipo_cycle_s"] = "0.002";
  rejectedAt(a, "/ipo_cycle_s");
  Json b = validDoc();
  b["axes"] = Json::object();
  rejectedAt(b, "/axes");
  Json c = validDoc();
  c["name"] = 3;
  rejectedAt(c, "/name");
  Json d = validDoc();
  d["axes"][0]["name"] = 'X';
  rejectedAt(d, "/axes/0/name");
  Json e = validDoc();
  e["axes"][1]["limit_minus"] = nullptr;
  rejectedAt(e, "/axes/1/limit_minus");
  Json f = validDoc();
  f["m_sequences"] = Json::array();
  rejectedAt(f, "/m_sequences");
  Json g = validDoc();
  g["axes"][0] = 5;
  rejectedAt(g, "/axes/0");
  Json h = validDoc();
  h["inputs"]["27"] = Json::parse("[[0.0, 0, 1]]");
  rejectedAt(h, "/inputs/27/0");
  Json i = validDoc();
  i["r_preset"]["1"] = true;
  rejectedAt(i, "/r_preset/1");
  Json j = validDoc();
  j["dialect"] = "fanuc";
  rejectedAt(j, "/dialect");
}

TEST_CASE("machine: rejects non-positive velocities, accelerations, cycle and deviation") {
  Json a = validDoc();
  a["axes"][0]["max_velocity"] = 0;
  rejectedAt(a, "/axes/0/max_velocity");
  Json b = validDoc();
  b["axes"][1]["max_accel"] = -5;
  rejectedAt(b, "/axes/1/max_accel");
  Json c = validDoc();
  c["ipo_cycle_s"] = 0;
  rejectedAt(c, "/ipo_cycle_s");
  Json d = validDoc();
  d["corner_deviation_mm"] = -0.01;
  rejectedAt(d, "/corner_deviation_mm");
}

TEST_CASE("machine: rejects negative durations") {
  Json a = validDoc();
  a["m_sequences"]["23"]["duration_s"] = -0.5;
  rejectedAt(a, "/m_sequences/23/duration_s");
  Json b = validDoc();
  b["block_time_s"] = -1e-3;
  rejectedAt(b, "/block_time_s");
  Json c = validDoc();
  c["m0_wait_s"] = -1;
  rejectedAt(c, "/m0_wait_s");
  Json d = validDoc();
  d["default_m_duration_s"] = -2;
  rejectedAt(d, "/default_m_duration_s");
}

TEST_CASE("machine: rejects lookahead_blocks < 1 or non-integer") {
  Json a = validDoc();
  a["lookahead_blocks"] = 0;
  rejectedAt(a, "/lookahead_blocks");
  Json b = validDoc();
  b["lookahead_blocks"] = 2.5;
  rejectedAt(b, "/lookahead_blocks");
  Json c = validDoc();
  c["lookahead_blocks"] = 8.0; // an integral value written as a float is fine
  const MachineResult r = parse(c);
  REQUIRE(r.ok());
  CHECK(r->lookaheadBlocks == 8);
  Json d = validDoc();
  d["num_inputs"] = -1;
  rejectedAt(d, "/num_inputs");
}

TEST_CASE("machine: rejects limit_plus < limit_minus") {
  Json a = validDoc();
  a["axes"][1]["limit_plus"] = -1;
  rejectedAt(a, "/axes/1/limit_plus");
}

TEST_CASE("machine: rejects start outside the limits") {
  Json a = validDoc();
  a["axes"][0]["start"] = 3000.5;
  rejectedAt(a, "/axes/0/start");
  Json b = validDoc();
  b["axes"][1]["start"] = -0.001;
  rejectedAt(b, "/axes/1/start");
  Json c = validDoc(); // no start, default 0 outside 10..20
  c["axes"][1]["limit_minus"] = 10;
  c["axes"][1]["limit_plus"] = 20;
  rejectedAt(c, "/axes/1");
}

TEST_CASE("machine: rejects duplicate axis names case-insensitively") {
  Json a = validDoc();
  a["axes"][1]["name"] = "x";
  const std::string message = rejectedAt(a, "/axes/1/name");
  CHECK(message.find("duplicate") != std::string::npos);
}

TEST_CASE("machine: rejects invalid axis names") {
  for (const char* bad : {"XY", "", "1", "_", "G", "m", "N", "F", "r", "I", "J", "K"}) {
    CAPTURE(bad);
    Json a = validDoc();
    a["axes"][1]["name"] = bad;
    rejectedAt(a, "/axes/1/name");
  }
  // S and T are axis names in sidac but fixed addresses in z32.
  Json sidac = validDoc();
  sidac["axes"][1]["name"] = "S";
  CHECK(parse(sidac).ok());
  Json z32 = validDoc();
  z32["dialect"] = "z32";
  z32["axes"][1]["name"] = "s";
  rejectedAt(z32, "/axes/1/name");
  z32["axes"][1]["name"] = "T";
  rejectedAt(z32, "/axes/1/name");
}

TEST_CASE("machine: rejects 0 or more than 9 axes") {
  Json none = validDoc();
  none["axes"] = Json::array();
  rejectedAt(none, "/axes");
  Json ten = validDoc();
  ten["axes"] = Json::array();
  for (const char* letter : {"X", "Y", "Z", "A", "B", "C", "U", "V", "W", "Q"}) {
    ten["axes"].push_back(
        {{"name", letter}, {"max_velocity", 1}, {"max_accel", 1}, {"limit_minus", 0}, {"limit_plus", 1}});
  }
  rejectedAt(ten, "/axes");
  ten["axes"].erase(9);
  CHECK(parse(ten).ok());
}

TEST_CASE("machine: rejects missing required axis keys") {
  for (const char* key : {"name", "max_velocity", "max_accel", "limit_minus", "limit_plus"}) {
    CAPTURE(key);
    Json a = validDoc();
    a["axes"][1].erase(key);
    const std::string message = rejectedAt(a, "/axes/1");
    CHECK(message.find(key) != std::string::npos);
  }
}

TEST_CASE("machine: rejects m_sequences keys that are not non-negative integers") {
  for (const char* bad : {"-1", "abc", "1.5", "", " 2", "+3", "1e3"}) {
    CAPTURE(bad);
    Json a = validDoc();
    a["m_sequences"][bad] = {{"duration_s", 1}};
    rejectedAt(a, std::string("/m_sequences/") + bad);
  }
  Json dup = validDoc();
  dup["m_sequences"]["023"] = {{"duration_s", 1}};
  rejectedAt(dup, "/m_sequences/23"); // "023" sorts first, "23" is the duplicate
}

TEST_CASE("machine: rejects set_inputs values that are not 0 or 1") {
  for (const Json& bad : {Json(2), Json(-1), Json(0.5), Json(true), Json("1")}) {
    CAPTURE(bad.dump());
    Json a = validDoc();
    a["m_sequences"]["23"]["set_inputs"]["27"] = bad;
    rejectedAt(a, "/m_sequences/23/set_inputs/27");
  }
}

TEST_CASE("machine: rejects input indices outside 0..num_inputs-1") {
  Json a = validDoc();
  a["m_sequences"]["23"]["set_inputs"]["256"] = 1;
  rejectedAt(a, "/m_sequences/23/set_inputs/256");
  Json b = validDoc();
  b["inputs"]["256"] = Json::parse("[[0, 1]]");
  rejectedAt(b, "/inputs/256");
  Json c = validDoc();
  c["num_inputs"] = 27; // input 27 of the valid document no longer exists
  c.erase("m_sequences");
  rejectedAt(c, "/inputs/27");
  Json d = validDoc();
  d["inputs"]["x"] = Json::parse("[[0, 1]]");
  rejectedAt(d, "/inputs/x");
  Json e = validDoc();
  e["num_inputs"] = 0;
  e.erase("inputs");
  e.erase("m_sequences");
  e["m_sequences"]["23"]["set_inputs"]["0"] = 1;
  rejectedAt(e, "/m_sequences/23/set_inputs/0");
}

TEST_CASE("machine: rejects input schedules with negative or non-ascending times") {
  Json a = validDoc();
  a["inputs"]["27"] = Json::parse("[[1.0, 0], [0.5, 1]]");
  rejectedAt(a, "/inputs/27/1/0");
  Json b = validDoc();
  b["inputs"]["27"] = Json::parse("[[1.0, 0], [1.0, 1]]");
  rejectedAt(b, "/inputs/27/1/0");
  Json c = validDoc();
  c["inputs"]["27"] = Json::parse("[[-0.1, 0]]");
  rejectedAt(c, "/inputs/27/0/0");
  Json d = validDoc();
  d["inputs"]["27"] = Json::parse("{\"0\": 1}");
  rejectedAt(d, "/inputs/27");
}

TEST_CASE("machine: rejects input values that are not 0 or 1") {
  Json a = validDoc();
  a["inputs"]["27"] = Json::parse("[[0.0, 0], [2.5, 2]]");
  rejectedAt(a, "/inputs/27/1/1");
}

TEST_CASE("machine: rejects r_preset keys outside 1..2880") {
  for (const char* bad : {"0", "2881", "-1", "R1"}) {
    CAPTURE(bad);
    Json a = validDoc();
    a["r_preset"][bad] = 1.0;
    rejectedAt(a, std::string("/r_preset/") + bad);
  }
}

TEST_CASE("machine: rejects non-finite numbers") {
  // JSON has no NaN/Infinity literals; an overflowing literal is the only way to write one.
  const std::string text = validDoc().dump();
  const std::string overflow = "1e999";
  std::string bad = text;
  const std::string key = "\"ipo_cycle_s\":";
  bad.insert(1, key + overflow + ",");
  const MachineResult r = iso::machine::parseMachine(bad);
  CHECK_FALSE(r.ok());
  CHECK(r.error().where.empty());
  CHECK(r.error().message.find("1e999") != std::string::npos);
  const MachineResult nan = iso::machine::parseMachine("{\"axes\": NaN}");
  CHECK_FALSE(nan.ok());
  CHECK(nan.error().where.empty());
}

TEST_CASE("machine: bounds nesting depth of hostile input") {
  const std::string deep = "{\"axes\": " + std::string(100000, '[') + std::string(100000, ']') + "}";
  const MachineResult r = iso::machine::parseMachine(deep);
  CHECK_FALSE(r.ok());
  CHECK(r.error().message == "arrays and objects nested deeper than 64 levels");
  // 64 levels are not refused for their depth (the value is still of the wrong type)
  const std::string deep64 = "{\"name\": " + std::string(63, '[') + std::string(63, ']') + ", \"axes\": []}";
  const MachineResult r64 = iso::machine::parseMachine(deep64);
  CHECK_FALSE(r64.ok());
  CHECK(r64.error().where == "/name");
  const std::string deep65 = "{\"name\": " + std::string(64, '[') + std::string(64, ']') + ", \"axes\": []}";
  CHECK(iso::machine::parseMachine(deep65).error().message == "arrays and objects nested deeper than 64 levels");
}

TEST_CASE("machine: every error of a file is reported, each with its path, up to a limit") {
  Json doc = validDoc();
  doc["axes"][0]["max_velocity"] = -1;
  doc["axes"][1].erase("max_accel");
  doc["axes"][1]["max_acel"] = 10;
  doc["ipo_cycle_s"] = 0;
  doc["r_preset"]["0"] = 1;
  doc["r_preset"]["2"] = "x";
  iso::machine::MachineErrors errors;
  CHECK_FALSE(iso::machine::parseMachine(doc.dump(), errors));
  std::vector<std::string> where;
  for (const auto& e : errors.shown)
    where.push_back(e.where);
  CHECK(where == std::vector<std::string>{"/axes/0/max_velocity", "/axes/1/max_acel", "/axes/1", "/ipo_cycle_s",
                                          "/r_preset/0", "/r_preset/2"});
  CHECK(errors.count == 6);
  CHECK(errors.shown[1].message == "unknown key; did you mean \"max_accel\"?");
  CHECK(errors.shown[2].message == "missing required key \"max_accel\"");
  // the first one is also what the one-error form returns
  CHECK(parse(doc).error().where == "/axes/0/max_velocity");
  Json many = validDoc();
  for (int i = 100; i < 130; ++i)
    many["r_preset"][std::to_string(i)] = "x";
  CHECK_FALSE(iso::machine::parseMachine(many.dump(), errors));
  CHECK(errors.shown.size() == iso::machine::kMaxMachineErrors);
  CHECK(errors.count == 30);
  // a valid file has none
  CHECK(iso::machine::parseMachine(validDoc().dump(), errors));
  CHECK(errors.count == 0);
}

TEST_CASE("machine: an unknown key names the known one it is near") {
  Json top = validDoc();
  top["num_input"] = 3;
  CHECK(rejectedAt(top, "/num_input") == "unknown key; did you mean \"num_inputs\"?");
  Json far = validDoc();
  far["speed"] = 1;
  CHECK(rejectedAt(far, "/speed") == "unknown key");
}

TEST_CASE("machine: the z32 keys special_m, optional_stop, aux_duration_s") {
  Json doc = validDoc();
  doc["dialect"] = "z32";
  doc["special_m"] = {{"6", "CAMBIO"}, {"040", "Pallet_1"}};
  doc["optional_stop"] = true;
  doc["aux_duration_s"] = 0.25;
  const MachineResult r = parse(doc);
  REQUIRE(r.ok());
  CHECK(r->specialM == std::map<int, std::string>{{6, "CAMBIO"}, {40, "Pallet_1"}});
  CHECK(r->optionalStop);
  CHECK(r->auxDurationS == 0.25);
  // printed and read back
  const MachineResult again = iso::machine::parseMachine(iso::machine::machineToJson(*r));
  REQUIRE(again.ok());
  checkSameMachine(*r, *again);
  CHECK(iso::machine::machineToJson(*r).find("\"special_m\"") != std::string::npos);
  // a sidac machine prints exactly the SPEC 5.1 keys
  CHECK(iso::machine::machineToJson(iso::machine::builtinMachine()).find("special_m") == std::string::npos);
}

TEST_CASE("machine: special_m refuses the control's M, more than 48 entries, bad names") {
  for (const char* n : {"0", "1", "2", "3", "4", "5", "7", "8", "9", "17", "19", "30", "03"}) {
    CAPTURE(n);
    Json doc = validDoc();
    doc["special_m"] = {{n, "SUB"}};
    CHECK(rejectedAt(doc, std::string("/special_m/") + n).find("cannot be special") != std::string::npos);
  }
  Json many = validDoc();
  for (int i = 0; i < 49; ++i)
    many["special_m"][std::to_string(100 + i)] = "SUB";
  CHECK(rejectedAt(many, "/special_m").find("at most 48") != std::string::npos);
  Json ok48 = validDoc();
  for (int i = 0; i < 48; ++i)
    ok48["special_m"][std::to_string(100 + i)] = "SUB";
  CHECK(parse(ok48).ok());
  Json badName = validDoc();
  badName["special_m"] = {{"40", "9lives"}};
  rejectedAt(badName, "/special_m/40");
  Json notString = validDoc();
  notString["special_m"] = {{"40", 5}};
  rejectedAt(notString, "/special_m/40");
  Json badKey = validDoc();
  badKey["special_m"] = {{"M40", "SUB"}};
  rejectedAt(badKey, "/special_m/M40");
  Json stop = validDoc();
  stop["optional_stop"] = 1;
  rejectedAt(stop, "/optional_stop");
  Json aux = validDoc();
  aux["aux_duration_s"] = -1;
  rejectedAt(aux, "/aux_duration_s");
}

TEST_CASE("machine: the z32 keys origins, parameters and pal_preset") {
  Json doc = validDoc();
  doc["dialect"] = "z32";
  doc["origins"] = Json::parse(R"({"1": {"y": -20.5, "X": 100}, "099": {}})");
  doc["parameters"] = {"ha", "Q", "Zz"};
  doc["pal_preset"] = Json::parse(R"({"0": 1.5, "255": -2})");
  const MachineResult r = parse(doc);
  REQUIRE_MESSAGE(r.ok(), (r.ok() ? "" : r.error().message));
  using Offsets = std::vector<std::pair<char, double>>;
  CHECK(r->origins == std::map<int, Offsets>{{1, {{'X', 100.0}, {'Y', -20.5}}}, {99, {}}}); // sorted by letter
  CHECK(r->parameters == std::vector<std::string>{"HA", "Q", "ZZ"});
  CHECK(r->palPreset == std::map<int, double>{{0, 1.5}, {255, -2.0}});
  const std::string text = iso::machine::machineToJson(*r);
  CHECK(text.find("\"origins\": {\n    \"1\": {\"X\": 100.0, \"Y\": -20.5},\n    \"99\": {}\n  }") !=
        std::string::npos);
  CHECK(text.find("\"parameters\": [\"HA\", \"Q\", \"ZZ\"]") != std::string::npos);
  CHECK(text.find("\"pal_preset\": {\n    \"0\": 1.5,\n    \"255\": -2.0\n  }") != std::string::npos);
  const MachineResult again = iso::machine::parseMachine(text);
  REQUIRE(again.ok());
  checkSameMachine(*r, *again);
  // a sidac machine prints none of them
  CHECK(iso::machine::machineToJson(iso::machine::builtinMachine()).find("origins") == std::string::npos);
}

TEST_CASE("machine: origins, parameters and pal_preset refuse what the control does not take") {
  const auto with = [](const char* key, const char* json) {
    Json doc = validDoc();
    doc["dialect"] = "z32";
    doc[key] = Json::parse(json);
    return doc;
  };
  CHECK(rejectedAt(with("origins", R"({"0": {"X": 1}})"), "/origins/0").find("1..99") != std::string::npos);
  CHECK(rejectedAt(with("origins", R"({"100": {"X": 1}})"), "/origins/100").find("1..99") != std::string::npos);
  CHECK(rejectedAt(with("origins", R"({"O1": {"X": 1}})"), "/origins/O1").find("origin number") != std::string::npos);
  CHECK(rejectedAt(with("origins", R"({"1": {"Z": 1}})"), "/origins/1/Z").find("axis of the machine") !=
        std::string::npos);
  CHECK(rejectedAt(with("origins", R"({"1": {"XY": 1}})"), "/origins/1/XY").find("axis") != std::string::npos);
  CHECK(rejectedAt(with("origins", R"({"1": {"X": 1, "x": 2}})"), "/origins/1/x").find("duplicate axis X") !=
        std::string::npos);
  rejectedAt(with("origins", R"({"1": {"X": "1"}})"), "/origins/1/X");
  rejectedAt(with("origins", R"({"1": [1]})"), "/origins/1");
  rejectedAt(with("origins", R"([1])"), "/origins");
  CHECK(rejectedAt(with("parameters", R"(["HAB"])"), "/parameters/0").find("one or two letters") != std::string::npos);
  rejectedAt(with("parameters", R"(["H1"])"), "/parameters/0");
  rejectedAt(with("parameters", R"([""])"), "/parameters/0");
  rejectedAt(with("parameters", R"([7])"), "/parameters/0");
  rejectedAt(with("parameters", R"({"HA": 1})"), "/parameters");
  CHECK(rejectedAt(with("parameters", R"(["Q", "y"])"), "/parameters/1").find("\"Y\" is an axis") != std::string::npos);
  for (const char* fixed :
       {"G", "M", "N", "F", "R", "I", "J", "K", "S", "T", "O", "MA", "mb", "MC", "TA", "TB", "KG", "GO", "CR"}) {
    CAPTURE(fixed);
    CHECK(rejectedAt(with("parameters", (std::string("[\"") + fixed + "\"]").c_str()), "/parameters/0")
              .find("fixed address of dialect z32") != std::string::npos);
  }
  CHECK(rejectedAt(with("parameters", R"(["HA", "ha"])"), "/parameters/1").find("duplicate parameter name \"HA\"") !=
        std::string::npos);
  CHECK(rejectedAt(with("pal_preset", R"({"256": 1})"), "/pal_preset/256").find("a PAL index") != std::string::npos);
  rejectedAt(with("pal_preset", R"({"1": true})"), "/pal_preset/1");
  // r_preset keeps its own range
  CHECK(rejectedAt(with("r_preset", R"({"0": 1})"), "/r_preset/0").find("an R index") != std::string::npos);
}

TEST_CASE("machine: zones are boxes over the axes they bound, printed and read back") {
  Json doc = validDoc();
  doc["zones"] = Json::parse(R"([
    {"name": "morsa", "kind": "forbidden", "min": {"y": -5, "X": 40}, "max": {"X": 60, "Y": 5}},
    {"name": "probe", "kind": "warn", "max": {"Y": 10}}
  ])");
  const MachineResult r = parse(doc);
  REQUIRE_MESSAGE(r.ok(), (r.ok() ? "" : r.error().message));
  REQUIRE(r->zones.size() == 2);
  const iso::machine::Zone& morsa = r->zones[0];
  CHECK(morsa.name == "morsa");
  CHECK(morsa.forbidden);
  REQUIRE(morsa.axes.size() == 2); // machine order, whatever the file's order
  CHECK(morsa.axes[0] == iso::machine::ZoneAxis{'X', 40, 60});
  CHECK(morsa.axes[1] == iso::machine::ZoneAxis{'Y', -5, 5});
  const iso::machine::Zone& probe = r->zones[1];
  CHECK_FALSE(probe.forbidden);
  REQUIRE(probe.axes.size() == 1);
  CHECK(probe.axes[0].letter == 'Y');
  CHECK(std::isinf(probe.axes[0].min));
  CHECK(probe.axes[0].min < 0);
  CHECK(probe.axes[0].max == 10);
  const std::string text = iso::machine::machineToJson(*r);
  CHECK(text.find("\"min\": {\"X\": 40.0, \"Y\": -5.0}") != std::string::npos);
  CHECK(text.find("\"min\": {},\n      \"max\": {\"Y\": 10.0}") != std::string::npos);
  const MachineResult again = iso::machine::parseMachine(text);
  REQUIRE(again.ok());
  checkSameMachine(*r, *again);
  // a machine without zones prints no zones key
  CHECK(iso::machine::machineToJson(iso::machine::builtinMachine()).find("zones") == std::string::npos);
}

TEST_CASE("machine: zones refuse unknown axes, min above max, duplicate names and empty boxes") {
  const auto with = [](const char* json) {
    Json doc = validDoc();
    doc["zones"] = Json::parse(json);
    return doc;
  };
  CHECK(rejectedAt(with(R"([{"name": "a", "kind": "forbidden", "min": {"Z": 1}}])"), "/zones/0/min/Z")
            .find("axis of the machine") != std::string::npos);
  CHECK(rejectedAt(with(R"([{"name": "a", "kind": "forbidden", "min": {"X": 2}, "max": {"X": 1}}])"), "/zones/0/min/X")
            .find("above its max") != std::string::npos);
  CHECK(rejectedAt(with(R"([{"name": "a", "kind": "warn", "min": {"X": 1}},
                           {"name": "a", "kind": "warn", "min": {"Y": 1}}])"),
                   "/zones/1/name")
            .find("duplicate zone name \"a\"") != std::string::npos);
  CHECK(rejectedAt(with(R"([{"name": "a", "kind": "forbidden"}])"), "/zones/0").find("at least one axis") !=
        std::string::npos);
  CHECK(rejectedAt(with(R"([{"name": "a", "kind": "forbidden", "min": {}}])"), "/zones/0").find("at least one axis") !=
        std::string::npos);
  CHECK(rejectedAt(with(R"([{"name": "a", "kind": "danger", "min": {"X": 1}}])"), "/zones/0/kind")
            .find("\"forbidden\" or \"warn\"") != std::string::npos);
  CHECK(rejectedAt(with(R"([{"kind": "warn", "min": {"X": 1}}])"), "/zones/0").find("\"name\"") != std::string::npos);
  CHECK(rejectedAt(with(R"([{"name": "a", "kind": "warn", "min": {"X": 1, "x": 2}}])"), "/zones/0/min/x")
            .find("duplicate axis X") != std::string::npos);
  rejectedAt(with(R"([{"name": "a", "kind": "warn", "min": {"X": "1"}}])"), "/zones/0/min/X");
  rejectedAt(with(R"([{"name": "a", "kind": "warn", "min": {"X": 1}, "color": 3}])"), "/zones/0/color");
  rejectedAt(with(R"([{"name": "a", "kind": "warn", "min": [1]}])"), "/zones/0/min");
  rejectedAt(with(R"({"a": 1})"), "/zones");
}
