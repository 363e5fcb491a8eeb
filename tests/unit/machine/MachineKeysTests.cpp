//! @file MachineKeysTests.cpp
//! @brief The table of machine-file keys (MachineKeys.def) against schemas/machine.schema.json,
//!        the defaults of the structs and the printer.
#include <algorithm>
#include <fstream>
#include <map>
#include <optional>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <doctest/doctest.h>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "machine/Machine.h"
#include "machine/MachineKeys.h"

using namespace iso::machine;
using namespace iso::machine::keys;

namespace {

using Json = nlohmann::json;

Json machineSchema() {
  std::ifstream in(std::string(ISO_SOURCE_DIR) + "/schemas/machine.schema.json");
  REQUIRE(in.good());
  std::stringstream text;
  text << in.rdbuf();
  return Json::parse(text.str());
}

/// The object of the schema that describes the keys of O.
template <class O> const Json& schemaObject(const Json& schema);
template <> const Json& schemaObject<Machine>(const Json& schema) { return schema; }
template <> const Json& schemaObject<Axis>(const Json& schema) { return schema.at("$defs").at("axis"); }
template <> const Json& schemaObject<MSequence>(const Json& schema) { return schema.at("$defs").at("mSequence"); }

const char* schemaType(JsonType t) {
  switch (t) {
  case JsonType::String: return "string";
  case JsonType::Enum: return "";
  case JsonType::Array: return "array";
  case JsonType::Number: return "number";
  case JsonType::Integer: return "integer";
  case JsonType::Boolean: return "boolean";
  case JsonType::Object: return "object";
  }
  return "?";
}

/// The schema keywords a row's bounds stand for, with their values.
std::map<std::string, int> tableRange(JsonType type, Bound min, Bound max) {
  std::map<std::string, int> out;
  const auto add = [&](Bound b, const char* above, const char* atLeast, const char* atMost) {
    if (b.kind == Bound::Above) out[above] = b.value;
    if (b.kind == Bound::AtLeast) out[atLeast] = b.value;
    if (b.kind == Bound::AtMost) out[atMost] = b.value;
  };
  const bool value = type == JsonType::Number || type == JsonType::Integer;
  const std::string count = type == JsonType::Array ? "Items" : "Properties";
  const std::string minCount = "min" + count;
  const std::string maxCount = "max" + count;
  for (Bound b : {min, max}) {
    if (value) {
      add(b, "exclusiveMinimum", "minimum", "maximum");
    } else {
      add(b, "(a count is never above a bound)", minCount.c_str(), maxCount.c_str());
    }
  }
  return out;
}

std::map<std::string, int> schemaRange(const Json& property) {
  std::map<std::string, int> out;
  for (const char* keyword : {"minimum", "exclusiveMinimum", "maximum", "exclusiveMaximum", "minItems", "maxItems",
                              "minProperties", "maxProperties"}) {
    if (property.contains(keyword)) out[keyword] = property.at(keyword).get<int>();
  }
  return out;
}

/// The default a schema description states ("default 0.002", "Default: none.", "sidac
/// (default)"), or "" when it states none.
std::string schemaDefault(const std::string& description) {
  std::smatch match;
  if (std::regex_search(description, match, std::regex(R"(\b([a-z0-9_]+) \(default\))"))) return match[1];
  if (std::regex_search(description, match, std::regex(R"(\b[Dd]efault:? ([-A-Za-z0-9_.]*[A-Za-z0-9_]))")))
    return match[1];
  return "";
}

std::string defaultText(const Given<double>& d) { return fmt::format("{}", d.value); }
std::string defaultText(const Given<int>& d) { return std::to_string(d.value); }
std::string defaultText(const Given<bool>& d) { return d.value ? "true" : "false"; }
std::string defaultText(const Given<const char*>& d) { return d.value; }
std::string defaultText(const Given<Dialect>& d) { return dialectName(d.value); }
std::string defaultText(NoEntries) { return "none"; }
std::string defaultText(OtherKey d) { return std::string(d.key); }
template <class T> std::string defaultText(const Needed<T>&) { return ""; }

template <class T> bool same(const T& a, const T& b) { return a == b; }
bool same(const std::map<int, MSequence>& a, const std::map<int, MSequence>& b) {
  if (a.size() != b.size()) return false;
  for (const auto& [number, seq] : a) {
    if (b.count(number) == 0 || b.at(number).durationS != seq.durationS || b.at(number).setInputs != seq.setInputs)
      return false;
  }
  return true;
}

template <class O> void checkRowsAgainstSchema(const Json& schema) {
  const Json& object = schemaObject<O>(schema);
  const Json& properties = object.at("properties");
  const std::vector<std::string> required = object.value("required", std::vector<std::string>{});
  forEachKey<O>([&](const auto& key) {
    const std::string name = key.name;
    CAPTURE(name);
    REQUIRE(properties.contains(key.name));
    const Json& property = properties.at(key.name);
    if (key.type == JsonType::Enum) {
      CHECK(property.contains("enum"));
      CHECK_FALSE(property.contains("type"));
    } else {
      CHECK(property.value("type", "") == schemaType(key.type));
    }
    CHECK(tableRange(key.type, key.min, key.max) == schemaRange(property));
    const bool isRequired = kIsRequired<std::decay_t<decltype(key.def)>>;
    CHECK(isRequired == (std::find(required.begin(), required.end(), key.name) != required.end()));
    const std::string stated = schemaDefault(property.value("description", ""));
    const std::string table = defaultText(key.def);
    CAPTURE(stated);
    CAPTURE(table);
    // A table with no entries by default may leave that unsaid.
    CHECK((stated == table || (table == "none" && stated.empty())));
  });
  for (const auto& [name, property] : properties.items()) {
    CAPTURE(name);
    const std::vector<std::string_view>& names = keyNames<O>();
    CHECK(std::find(names.begin(), names.end(), name) != names.end());
  }
  for (const std::string& name : required) {
    CAPTURE(name);
    CHECK(properties.contains(name));
  }
}

} // namespace

TEST_CASE("machine keys: every row of the table is in the schema with its type, range and default") {
  const Json schema = machineSchema();
  checkRowsAgainstSchema<Machine>(schema);
  checkRowsAgainstSchema<Axis>(schema);
  checkRowsAgainstSchema<MSequence>(schema);
}

TEST_CASE("machine keys: the dialect values of the schema are the dialect names") {
  const Json schema = machineSchema();
  const Json& values = schema.at("properties").at("dialect").at("enum");
  CHECK(values.size() == 2);
  for (const Json& value : values) {
    const std::optional<Dialect> d = parseDialect(value.get<std::string>());
    REQUIRE(d.has_value());
    CHECK(dialectName(*d) == value.get<std::string>());
  }
}

TEST_CASE("machine keys: the built-in machine and the structs' defaults agree with the table") {
  const Machine builtin = builtinMachine();
  const Machine plain;
  forEachKey<Machine>([&](const auto& key) {
    const std::string name = key.name;
    CAPTURE(name);
    if constexpr (!kIsRequired<std::decay_t<decltype(key.def)>>) {
      CHECK(same(builtin.*key.field, plain.*key.field));
    }
  });
  REQUIRE(builtin.axes.size() == kBuiltinAxisLetters.size());
  for (size_t i = 0; i < builtin.axes.size(); ++i) {
    CHECK(builtin.axes[i].letter == kBuiltinAxisLetters[i]);
    const Axis axis;
    forEachKey<Axis>([&](const auto& key) {
      const std::string name = key.name;
      CAPTURE(name);
      if (name != "name") CHECK(builtin.axes[i].*key.field == axis.*key.field);
    });
  }
  CHECK(builtin.axes[0].maxVelocity == 500);
  CHECK(builtin.axes[0].maxAccel == 2000);
  CHECK(builtin.axes[0].limitMinus == -1000);
  CHECK(builtin.axes[0].limitPlus == 3000);
  CHECK(builtin.axes[0].start == 0);
}

TEST_CASE("machine keys: the printer writes the keys in table order, the z32 ones when one is set") {
  Machine m = builtinMachine();
  const auto printedKeys = [](const Machine& machine) {
    std::vector<std::string> out;
    const Json doc = Json::parse(machineToJson(machine));
    // nlohmann keeps object keys sorted; the order of the text is found by position.
    const std::string text = machineToJson(machine);
    std::map<size_t, std::string> byPosition;
    for (const auto& item : doc.items())
      byPosition[text.find("\n  \"" + item.key() + "\":")] = item.key();
    for (const auto& entry : byPosition)
      out.push_back(entry.second);
    return out;
  };
  std::vector<std::string> all;
  std::vector<std::string> sidac;
  forEachKey<Machine>([&](const auto& key) {
    if (key.print != Print::IfSet) all.emplace_back(key.name);
    if (key.print == Print::Always) sidac.emplace_back(key.name);
  });
  CHECK(printedKeys(m) == sidac);
  m.optionalStop = true;
  CHECK(printedKeys(m) == all);
  m.optionalStop = false;
  m.dialect = Dialect::Z32;
  CHECK(printedKeys(m) == all);
  m.dialect = Dialect::Sidac;
  m.zones.push_back(Zone{"morsa", true, {ZoneAxis{'X', 40, 60}}});
  std::vector<std::string> withZones = sidac;
  withZones.emplace_back("zones");
  CHECK(printedKeys(m) == withZones);
}
