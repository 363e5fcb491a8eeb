//! @file MachineOverrides.cpp
//! @brief isosim --set: a machine changed by JSON paths, validated as a machine file.
#include "driver/MachineOverrides.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "support/CaseFold.h"
#include "support/Text.h"

namespace iso::driver {

namespace {
using J = nlohmann::ordered_json;

/// The element of `axes` (an array of axis objects) named `name` (any case), else nullptr.
J* axisNamed(J& axes, const std::string& name) {
  for (auto& a : axes)
    if (a.is_object() && a.contains("name") && a["name"].is_string() &&
        support::iequals(a["name"].get<std::string>(), name))
      return &a;
  return nullptr;
}

/// Applies one "KEY=VALUE" to `doc`; "" or the reason it cannot.
std::string assign(J& doc, const std::string& set) {
  const size_t eq = set.find('=');
  if (eq == std::string::npos || eq == 0) return "expected KEY=VALUE (e.g. axes.X.max_accel=3000)";
  const std::string key = set.substr(0, eq), text = set.substr(eq + 1);
  J value = J::parse(text, nullptr, false);
  if (value.is_discarded()) value = text; // a word: a string (e.g. dialect=z32)
  J* at = &doc;
  size_t from = 0;
  for (;;) {
    const size_t dot = key.find('.', from);
    const std::string part = key.substr(from, dot == std::string::npos ? std::string::npos : dot - from);
    if (part.empty()) return fmt::format("'{}' has an empty part", key);
    const bool last = dot == std::string::npos;
    if (at->is_array()) {
      J* axis = axisNamed(*at, part);
      if (!axis) return fmt::format("no axis named '{}' in {}", part, key.substr(0, from ? from - 1 : 0));
      at = axis;
    } else if (at->is_object()) {
      if (!last && !at->contains(part)) (*at)[part] = J::object(); // e.g. a new m_sequences entry
      at = &(*at)[part];
    } else {
      return fmt::format("'{}' is not an object: '{}' cannot be set in it", key.substr(0, from - 1), part);
    }
    if (last) break;
    from = dot + 1;
  }
  *at = std::move(value);
  return "";
}
} // namespace

std::optional<machine::Machine> overrideMachine(const machine::Machine& m, const std::vector<std::string>& sets,
                                                Io& io) {
  J doc = J::parse(machine::machineToJson(m));
  for (const auto& s : sets)
    if (std::string why = assign(doc, s); !why.empty()) {
      io.err << fmt::format("isosim: error: --set {}: {}\n", support::escapeForTerminal(s),
                            support::escapeForTerminal(why));
      return std::nullopt;
    }
  machine::MachineErrors errors;
  auto r = machine::parseMachine(doc.dump(), errors);
  if (!r) {
    printMachineErrors(io, "isosim", "--set: the machine is not valid", errors);
    return std::nullopt;
  }
  r->builtin = m.builtin;
  return r;
}

support::Expected<machine::Machine> overriddenMachine(const machine::Machine& m, const std::vector<std::string>& sets) {
  J doc = J::parse(machine::machineToJson(m));
  for (const auto& s : sets)
    if (std::string why = assign(doc, s); !why.empty()) return support::Error{s, why};
  machine::MachineErrors errors;
  auto r = machine::parseMachine(doc.dump(), errors);
  if (!r) {
    std::string why = "the machine is not valid";
    for (size_t i = 0; i < errors.shown.size(); ++i)
      why += fmt::format("{} at {}: {}", i == 0 ? "" : ";", errors.shown[i].where.empty() ? "/" : errors.shown[i].where,
                         errors.shown[i].message);
    return support::Error{"", why};
  }
  r->builtin = m.builtin;
  return std::move(*r);
}

} // namespace iso::driver
