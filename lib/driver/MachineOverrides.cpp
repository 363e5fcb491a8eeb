//! @file MachineOverrides.cpp
//! @brief isosim --set: a machine changed by JSON paths, validated as a machine file.
#include "driver/MachineOverrides.h"

#include <type_traits>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "machine/MachineKeys.h"
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
      const std::string list = key.substr(0, from ? from - 1 : 0);
      if (!axis) return fmt::format("no {} named '{}' in {}", list == "zones" ? "zone" : "axis", part, list);
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

namespace {

/// The row `name` of object O of the key table as a NumberKey (its value the default, when the
/// default is a number), with the key of the document its default comes from ("" when none);
/// false when O has no number row `name` with a lower bound.
template <class O> bool numberRow(const std::string& name, NumberKey& out, std::string& defaultKey) {
  bool found = false;
  machine::keys::forEachKey<O>([&](const auto& row) {
    using machine::keys::Bound;
    if (found || name != row.name || row.type != machine::keys::JsonType::Number) return;
    if (row.min.kind != Bound::Above && row.min.kind != Bound::AtLeast) return;
    found = true;
    out.positive = row.min.kind == Bound::Above;
    out.lower = row.min.value;
    if (row.max.kind == Bound::AtMost) out.upper = row.max.value;
    using Def = std::decay_t<decltype(row.def)>;
    if constexpr (std::is_same_v<Def, machine::keys::OtherKey>) defaultKey = std::string(row.def.key);
    if constexpr (std::is_same_v<Def, machine::keys::Given<double>>) out.value = row.def.value;
  });
  return found;
}

} // namespace

support::Expected<NumberKey> machineNumberKey(const machine::Machine& m, const std::string& key) {
  std::vector<std::string> parts;
  for (size_t from = 0;;) {
    const size_t dot = key.find('.', from);
    parts.push_back(key.substr(from, dot == std::string::npos ? std::string::npos : dot - from));
    if (dot == std::string::npos) break;
    from = dot + 1;
  }
  J doc = J::parse(machine::machineToJson(m));
  NumberKey out;
  std::string defaultKey;
  const J* at = nullptr;
  bool row = false;
  if (parts.size() == 1) {
    row = numberRow<machine::Machine>(parts[0], out, defaultKey);
    if (row && doc.contains(parts[0])) at = &doc[parts[0]];
  } else if (parts.size() == 3 && parts[0] == "axes") {
    row = numberRow<machine::Axis>(parts[2], out, defaultKey);
    J* axis = axisNamed(doc["axes"], parts[1]);
    if (row && !axis) return support::Error{key, fmt::format("no axis named '{}' in axes", parts[1])};
    if (row && axis->contains(parts[2])) at = &(*axis)[parts[2]];
  } else if (parts.size() == 3 && parts[0] == "m_sequences") {
    row = numberRow<machine::MSequence>(parts[2], out, defaultKey);
    J& seqs = doc["m_sequences"];
    if (row && seqs.is_object() && seqs.contains(parts[1]) && seqs[parts[1]].contains(parts[2]))
      at = &seqs[parts[1]][parts[2]];
    else if (row && doc.contains(defaultKey))
      at = &doc[defaultKey];
  }
  // a key the machine does not print (aux_duration_s of a sidac machine) has its default
  const bool defaulted = row && parts.size() == 1 && !at && defaultKey.empty();
  if (!row || (!defaulted && (!at || !at->is_number())))
    return support::Error{key, "not a number key of the machine file with a lower bound (axes.X.max_accel, "
                               "axes.X.max_velocity, block_time_s, m_sequences.23.duration_s, ...)"};
  if (at) out.value = at->get<double>();
  if (auto check = overriddenMachine(m, {fmt::format("{}={}", key, out.value)}); !check)
    return support::Error{key, check.error().message};
  return out;
}

} // namespace iso::driver
