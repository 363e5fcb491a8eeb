//! @file Machine.cpp
//! @brief Machine file (SPEC §5.1): strict JSON validation, canonical printing, built-in default.
#include "machine/Machine.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <set>
#include <vector>

#include <nlohmann/json.hpp>

#include "lang/Addresses.h"
#include "lang/Axes.h"
#include "lang/Limits.h"
#include "machine/MachineKeys.h"
#include "support/CaseFold.h"
#include "support/JsonDepth.h"
#include "support/Text.h"

namespace iso::machine {

namespace {

using Json = nlohmann::json;

/// Thrown inside this file only; parseMachine turns it into a MachineError.
struct ValidationFailure {
  MachineError error;
};

[[noreturn]] void fail(std::string path, std::string message) {
  throw ValidationFailure{MachineError{std::move(path), std::move(message)}};
}

/// Collects the errors of one file. Each reader still stops at its value's first problem (it
/// throws a ValidationFailure); attempt() records that one and lets the check go on with the
/// next value, so that a file with several errors shows them all.
class Errors {
public:
  explicit Errors(MachineErrors& out) : out_(out) {}
  void add(MachineError e) {
    if (out_.shown.size() < kMaxMachineErrors) out_.shown.push_back(std::move(e));
    ++out_.count;
  }
  template <class F> bool attempt(F&& read) {
    try {
      read();
      return true;
    } catch (ValidationFailure& f) {
      add(std::move(f.error));
      return false;
    }
  }
  size_t count() const { return out_.count; }

private:
  MachineErrors& out_;
};

/// JSON Pointer (RFC 6901) escaping of one reference token.
std::string escapePointerToken(std::string_view token) {
  std::string out;
  out.reserve(token.size());
  for (char c : token) {
    if (c == '~') {
      out += "~0";
    } else if (c == '/') {
      out += "~1";
    } else {
      out += c;
    }
  }
  return out;
}

std::string child(const std::string& path, std::string_view key) { return path + "/" + escapePointerToken(key); }

std::string child(const std::string& path, size_t index) { return path + "/" + std::to_string(index); }

char upper(char c) { return support::upperAscii(c); } // no C locale

// The nesting limit of structured input; a valid machine file nests 4 deep (/inputs/N/i/j).
constexpr unsigned kMaxDepth = support::kMaxNesting;

/// Tracks the parse position so duplicate object keys (which nlohmann would silently collapse)
/// are reported with their path, and so nesting depth is bounded.
class DuplicateKeyGuard {
public:
  bool operator()(int depth, Json::parse_event_t event, Json& parsed) {
    switch (event) {
    case Json::parse_event_t::object_start:
    case Json::parse_event_t::array_start:
      if (depth >= static_cast<int>(kMaxDepth)) {
        fail(currentPath(), "arrays and objects nested deeper than " + std::to_string(kMaxDepth) + " levels");
      }
      frames_.push_back(Frame{event == Json::parse_event_t::array_start, elementSegment(), {}, 0});
      break;
    case Json::parse_event_t::object_end:
    case Json::parse_event_t::array_end:
      if (!frames_.empty()) {
        frames_.pop_back();
      }
      break;
    case Json::parse_event_t::key: {
      Frame& top = frames_.back();
      const std::string& key = parsed.get_ref<const std::string&>();
      if (!top.keys.insert(key).second) {
        fail(child(currentPath(), key), "duplicate key");
      }
      lastKey_ = key;
      break;
    }
    case Json::parse_event_t::value: elementSegment(); break;
    }
    return true;
  }

private:
  struct Frame {
    bool isArray;
    std::string segment; ///< escaped path segment of this container ("" for the root)
    std::set<std::string> keys;
    size_t nextIndex;
  };

  /// The path segment of the element that starts now (and counts it in an enclosing array).
  std::string elementSegment() {
    if (frames_.empty()) {
      return "";
    }
    Frame& top = frames_.back();
    if (top.isArray) {
      return std::to_string(top.nextIndex++);
    }
    return escapePointerToken(lastKey_);
  }

  std::string currentPath() const {
    std::string path;
    for (size_t i = 1; i < frames_.size(); ++i) {
      path += "/" + frames_[i].segment;
    }
    return path;
  }

  std::vector<Frame> frames_;
  std::string lastKey_;
};

// ---- typed readers: each one fails with the value's path ----

double readNumber(const Json& v, const std::string& path, const std::string& what) {
  if (!v.is_number()) {
    fail(path, "must be " + what);
  }
  const double x = v.get<double>();
  if (!std::isfinite(x)) {
    fail(path, "must be a finite number");
  }
  return x;
}

double readFinite(const Json& v, const std::string& path) { return readNumber(v, path, "a number"); }

/// A number within `min`: Above(n) is > n, AtLeast(n) >= n; any other bound takes every finite number.
double readBounded(const Json& v, const std::string& path, keys::Bound min) {
  if (min.kind != keys::Bound::Above && min.kind != keys::Bound::AtLeast) {
    return readFinite(v, path);
  }
  const bool above = min.kind == keys::Bound::Above;
  const std::string want = (above ? "a number > " : "a number >= ") + std::to_string(min.value);
  const double x = readNumber(v, path, want);
  if (!(above ? x > min.value : x >= min.value)) {
    fail(path, "must be " + want);
  }
  return x;
}

double readNonNegative(const Json& v, const std::string& path) { return readBounded(v, path, keys::AtLeast(0)); }

/// An integer in [lo, hi]. JSON numbers written with a fraction of zero (64.0) are accepted.
int readInt(const Json& v, const std::string& path, int lo, int hi) {
  const std::string want = "must be an integer in " + std::to_string(lo) + ".." + std::to_string(hi);
  if (!v.is_number()) {
    fail(path, want);
  }
  double x = 0;
  if (v.is_number_unsigned()) {
    const auto u = v.get<uint64_t>();
    if (u > static_cast<uint64_t>(hi)) {
      fail(path, want);
    }
    x = static_cast<double>(u);
  } else if (v.is_number_integer()) {
    const auto i = v.get<int64_t>();
    if (i < lo || i > hi) {
      fail(path, want);
    }
    x = static_cast<double>(i);
  } else {
    x = v.get<double>();
    if (!std::isfinite(x) || x != std::floor(x)) {
      fail(path, want);
    }
  }
  if (x < lo || x > hi) {
    fail(path, want);
  }
  return static_cast<int>(x);
}

int readBit(const Json& v, const std::string& path) {
  if (!v.is_number()) {
    fail(path, "must be 0 or 1");
  }
  const double x = v.get<double>();
  if (x != 0 && x != 1) {
    fail(path, "must be 0 or 1");
  }
  return x == 1 ? 1 : 0;
}

std::string readString(const Json& v, const std::string& path) {
  if (!v.is_string()) {
    fail(path, "must be a string");
  }
  return v.get<std::string>();
}

const Json& requireObject(const Json& v, const std::string& path) {
  if (!v.is_object()) {
    fail(path, "must be an object");
  }
  return v;
}

void rejectUnknownKeys(const Json& obj, const std::string& path, const std::vector<std::string_view>& known,
                       Errors& errors) {
  for (const auto& item : obj.items()) {
    bool ok = false;
    for (std::string_view k : known) {
      ok = ok || item.key() == k;
    }
    if (!ok) {
      const std::string_view near = support::closestMatch(item.key(), known);
      errors.add(
          MachineError{child(path, item.key()),
                       near.empty() ? "unknown key" : "unknown key; did you mean \"" + std::string(near) + "\"?"});
    }
  }
}

/// A decimal object key ("27", "007") as an integer in [lo, hi]; `what` names it in messages.
int readKeyIndex(const std::string& key, const std::string& path, int lo, int hi, const char* what) {
  const std::string want =
      std::string("key must be ") + what + ", a decimal integer in " + std::to_string(lo) + ".." + std::to_string(hi);
  if (key.empty() || key.size() > 9) {
    fail(path, want);
  }
  long value = 0;
  for (char c : key) {
    if (c < '0' || c > '9') {
      fail(path, want);
    }
    value = value * 10 + (c - '0');
  }
  if (value < lo || value > hi) {
    fail(path, want);
  }
  return static_cast<int>(value);
}

// ---- the values of MachineKeys.def, chosen by the type of the member they fill ----

/// What the reader of one value needs besides the value: its row's bounds, the dialect.
struct ValueSpec {
  keys::Bound min;
  keys::Bound max;
  Dialect dialect;
  std::string_view key; ///< the row's key (r_preset and pal_preset share a type)
};

void readValue(const Json& v, const std::string& path, const ValueSpec& spec, double& x) {
  x = readBounded(v, path, spec.min);
}

void readValue(const Json& v, const std::string& path, const ValueSpec& spec, int& x) {
  x = readInt(v, path, spec.min.value, spec.max.value);
}

void readValue(const Json& v, const std::string& path, const ValueSpec&, std::string& s) { s = readString(v, path); }

void readValue(const Json& v, const std::string& path, const ValueSpec&, bool& b) {
  if (!v.is_boolean()) {
    fail(path, "must be true or false");
  }
  b = v.get<bool>();
}

void readValue(const Json& v, const std::string& path, const ValueSpec&, Dialect& d) {
  const std::optional<Dialect> dialect = parseDialect(readString(v, path));
  if (!dialect) {
    fail(path, "must be \"sidac\" or \"z32\"");
  }
  d = *dialect;
}

/// An axis name: one letter, not a fixed address of the dialect.
void readValue(const Json& v, const std::string& path, const ValueSpec& spec, char& letter) {
  const std::string name = readString(v, path);
  if (name.size() != 1 || !std::isalpha(static_cast<unsigned char>(name[0]))) {
    fail(path, "axis name must be a single letter");
  }
  letter = upper(name[0]);
  if (lang::isFixedAddress(letter, spec.dialect)) {
    fail(path, std::string("axis name \"") + letter + "\" is a fixed address of dialect " + dialectName(spec.dialect));
  }
}

/// A value of one type: read in an attempt of its own; false when it is wrong.
template <class T>
bool readEntry(const Json& v, const std::string& path, const ValueSpec& spec, T& field, Machine&, Errors& errors) {
  return errors.attempt([&] { readValue(v, path, spec, field); });
}

// The keys of more than one value, defined below.
bool readEntry(const Json& v, const std::string& path, const ValueSpec& spec, std::vector<Axis>& axes, Machine& m,
               Errors& errors);
bool readEntry(const Json& v, const std::string& path, const ValueSpec& spec,
               std::vector<std::pair<int, int>>& setInputs, Machine& m, Errors& errors);
bool readEntry(const Json& v, const std::string& path, const ValueSpec& spec, std::map<int, MSequence>& seqs,
               Machine& m, Errors& errors);
bool readEntry(const Json& v, const std::string& path, const ValueSpec& spec,
               std::map<int, std::vector<std::pair<double, int>>>& inputs, Machine& m, Errors& errors);
bool readEntry(const Json& v, const std::string& path, const ValueSpec& spec, std::map<int, double>& presets,
               Machine& m, Errors& errors);
bool readEntry(const Json& v, const std::string& path, const ValueSpec& spec, std::map<int, std::string>& specialM,
               Machine& m, Errors& errors);
bool readEntry(const Json& v, const std::string& path, const ValueSpec& spec,
               std::map<int, std::vector<std::pair<char, double>>>& origins, Machine& m, Errors& errors);
bool readEntry(const Json& v, const std::string& path, const ValueSpec& spec, std::vector<std::string>& names,
               Machine& m, Errors& errors);
bool readEntry(const Json& v, const std::string& path, const ValueSpec& spec, std::vector<Zone>& zones, Machine& m,
               Errors& errors);

/// The keys of object O of one read stage into `object`, in table order. A missing required key
/// is an error at `path` when `reportMissing`. Returns the keys not read (absent or wrong).
template <class O>
std::vector<std::string_view> readKeys(const Json& v, const std::string& path, O& object, keys::Read stage,
                                       bool reportMissing, Machine& m, Errors& errors) {
  std::vector<std::string_view> unread;
  keys::forEachKey<O>([&](const auto& key) {
    if (key.read != stage) {
      return;
    }
    if (!v.contains(key.name)) {
      if (keys::kIsRequired<std::decay_t<decltype(key.def)>> && reportMissing) {
        errors.add(MachineError{path, std::string("missing required key \"") + key.name + "\""});
      }
      unread.push_back(key.name);
      return;
    }
    const ValueSpec spec{key.min, key.max, m.dialect, key.name};
    if (!readEntry(v[key.name], child(path, key.name), spec, object.*key.field, m, errors)) {
      unread.push_back(key.name);
    }
  });
  return unread;
}

/// Every required key of object O that `v` lacks, as errors at `path`.
template <class O> void reportMissingKeys(const Json& v, const std::string& path, Errors& errors) {
  keys::forEachKey<O>([&](const auto& key) {
    if (keys::kIsRequired<std::decay_t<decltype(key.def)>> && !v.contains(key.name)) {
      errors.add(MachineError{path, std::string("missing required key \"") + key.name + "\""});
    }
  });
}

// ---- the defaults of MachineKeys.def ----

template <class T, class V> void setDefault(T& field, const keys::Given<V>& d, const Machine&) { field = d.value; }
template <class T, class V> void setDefault(T& field, const keys::Needed<V>& d, const Machine&) { field = d.value; }
template <class T> void setDefault(T& field, keys::NoEntries, const Machine&) { field = T{}; }
void setDefault(std::vector<Axis>& axes, const keys::Needed<std::string_view>& letters, const Machine& m);

/// A default that is the value of another key of the document.
template <class T> void setDefault(T& field, keys::OtherKey d, const Machine& m) {
  keys::forEachKey<Machine>([&](const auto& key) {
    if constexpr (std::is_same_v<std::decay_t<decltype(m.*key.field)>, T>) {
      if (key.name == d.key) {
        field = m.*key.field;
      }
    }
  });
}

/// Every key of `object` at its default; `m` is the document (for defaults that are other keys).
template <class O> void applyDefaults(O& object, const Machine& m) {
  keys::forEachKey<O>([&](const auto& key) { setDefault(object.*key.field, key.def, m); });
}

/// The axes of the built-in machine: one per letter, every other key at its value of the table.
void setDefault(std::vector<Axis>& axes, const keys::Needed<std::string_view>& letters, const Machine& m) {
  axes.clear();
  for (char letter : letters.value) {
    Axis axis;
    applyDefaults(axis, m);
    axis.letter = letter;
    axes.push_back(axis);
  }
}

template <class T, class V> bool isDefault(const T& field, const keys::Given<V>& d) { return field == d.value; }
template <class T> bool isDefault(const T& field, keys::NoEntries) { return field.empty(); }
/// A key that must be given (or whose default is another key) is never left at a default of its own.
template <class T, class D> bool isDefault(const T&, const D&) { return false; }

// ---- the objects of a machine file ----

/// Checked after the other keys of an axis: the limits against each other, start (or its default)
/// against the limits.
void checkLimitsAndStart(const Json& v, const std::string& path, Axis& axis) {
  if (axis.limitPlus < axis.limitMinus) {
    fail(child(path, "limit_plus"), "must be >= limit_minus");
  }
  if (v.contains("start")) {
    const std::string startPath = child(path, "start");
    axis.start = readFinite(v["start"], startPath);
    if (axis.start < axis.limitMinus || axis.start > axis.limitPlus) {
      fail(startPath, "start position is outside the soft limits");
    }
  } else if (axis.start < axis.limitMinus || axis.start > axis.limitPlus) {
    fail(path, "the default start 0 is outside the soft limits; give \"start\"");
  }
}

bool contains(const std::vector<std::string_view>& keys, std::string_view key) {
  return std::find(keys.begin(), keys.end(), key) != keys.end();
}

/// One axis, or nullopt when any of its keys is wrong (each error is recorded).
std::optional<Axis> readAxis(const Json& v, const std::string& path, Machine& m, Errors& errors) {
  if (!errors.attempt([&] { requireObject(v, path); })) {
    return std::nullopt;
  }
  const size_t before = errors.count();
  rejectUnknownKeys(v, path, keys::keyNames<Axis>(), errors);
  reportMissingKeys<Axis>(v, path, errors);
  Axis axis;
  const std::vector<std::string_view> unread = readKeys(v, path, axis, keys::Read::Early, false, m, errors);
  // start is checked against both limits: without them there is nothing to check it against.
  if (contains(unread, "limit_minus") || contains(unread, "limit_plus")) {
    return std::nullopt;
  }
  errors.attempt([&] { checkLimitsAndStart(v, path, axis); });
  if (errors.count() != before) {
    return std::nullopt;
  }
  return axis;
}

bool readEntry(const Json& v, const std::string& path, const ValueSpec& spec, std::vector<Axis>& axes, Machine& m,
               Errors& errors) {
  if (!errors.attempt([&] {
        if (!v.is_array()) {
          fail(path, "must be an array of axis objects");
        }
        if (v.size() < static_cast<size_t>(spec.min.value) || v.size() > static_cast<size_t>(spec.max.value)) {
          fail(path, "must hold " + std::to_string(spec.min.value) + " to " + std::to_string(spec.max.value) + " axes");
        }
      })) {
    return false;
  }
  for (size_t i = 0; i < v.size(); ++i) {
    const std::string axisPath = child(path, i);
    const std::optional<Axis> axis = readAxis(v[i], axisPath, m, errors);
    if (!axis) {
      continue;
    }
    if (m.axisIndex(axis->letter) >= 0) {
      errors.add(MachineError{child(axisPath, "name"), std::string("duplicate axis name \"") + axis->letter + "\""});
    }
    axes.push_back(*axis);
  }
  return true;
}

/// The inputs an M sequence sets: input index to 0 or 1. Not an object: the entry is wrong.
bool readEntry(const Json& v, const std::string& path, const ValueSpec&, std::vector<std::pair<int, int>>& setInputs,
               Machine& m, Errors& errors) {
  const Json& set = requireObject(v, path);
  std::map<int, int> byIndex;
  for (const auto& item : set.items()) {
    errors.attempt([&] {
      const std::string itemPath = child(path, item.key());
      const int index = readKeyIndex(item.key(), itemPath, 0, m.numInputs - 1, "an input index");
      const int bit = readBit(item.value(), itemPath);
      if (!byIndex.emplace(index, bit).second) {
        fail(itemPath, "duplicate input index " + std::to_string(index));
      }
    });
  }
  setInputs.assign(byIndex.begin(), byIndex.end());
  return true;
}

MSequence readMSequence(const Json& v, const std::string& path, Machine& m, Errors& errors) {
  requireObject(v, path);
  rejectUnknownKeys(v, path, keys::keyNames<MSequence>(), errors);
  MSequence seq;
  // An entry without its own duration lasts default_m_duration_s, like an M with no entry.
  applyDefaults(seq, m);
  readKeys(v, path, seq, keys::Read::Early, false, m, errors);
  return seq;
}

std::vector<std::pair<double, int>> readSchedule(const Json& v, const std::string& path) {
  if (!v.is_array()) {
    fail(path, "must be an array of [time_s, value] pairs");
  }
  std::vector<std::pair<double, int>> steps;
  for (size_t i = 0; i < v.size(); ++i) {
    const std::string stepPath = child(path, i);
    const Json& step = v[i];
    if (!step.is_array() || step.size() != 2) {
      fail(stepPath, "must be a [time_s, value] pair");
    }
    const std::string timePath = child(stepPath, size_t{0});
    const double t = readNonNegative(step[0], timePath);
    if (!steps.empty() && !(t > steps.back().first)) {
      fail(timePath, "times must be strictly ascending");
    }
    steps.emplace_back(t, readBit(step[1], child(stepPath, size_t{1})));
  }
  return steps;
}

/// A subprogram name as PROC takes it: a letter or '_', then letters, digits and '_'.
bool isProcName(const std::string& s) {
  if (s.empty() || s.size() > 64) return false;
  for (size_t i = 0; i < s.size(); ++i) {
    const auto c = static_cast<unsigned char>(s[i]);
    const bool ok = std::isalpha(c) != 0 || c == '_' || (i > 0 && std::isdigit(c) != 0);
    if (!ok) return false;
  }
  return true;
}

/// One entry of special_m: an M number the control lets a subprogram take, and its name.
void readSpecialM(const std::string& key, const Json& value, const std::string& path,
                  std::map<int, std::string>& specialM) {
  const int number = readKeyIndex(key, path, 0, lang::kMaxMNumber, "an M number");
  if (!lang::mayBeSpecial(number)) {
    std::string why = "M"; // "M6 cannot be special: M0 M1 ... M30 are managed by the control"
    why.append(std::to_string(number)).append(" cannot be special: ");
    const char* sep = "M";
    for (int n = 0; n <= lang::kMEnd; ++n)
      if (!lang::mayBeSpecial(n)) {
        why.append(sep).append(std::to_string(n));
        sep = " M";
      }
    fail(path, why.append(" are managed by the control"));
  }
  if (specialM.count(number) != 0) {
    fail(path, "duplicate M number " + std::to_string(number));
  }
  std::string name = readString(value, path);
  if (!isProcName(name)) {
    fail(path, "must be a subprogram name (a letter or '_', then letters, digits or '_')");
  }
  specialM.emplace(number, std::move(name));
}

/// Every item of a table (an object keyed by number or index) through `readItem(key, value,
/// path)`, each error recorded and the others still read.
template <class F> void readTable(const Json& v, const std::string& path, Errors& errors, F&& readItem) {
  if (!errors.attempt([&] { requireObject(v, path); })) {
    return;
  }
  for (const auto& item : v.items()) {
    errors.attempt([&] { readItem(item.key(), item.value(), child(path, item.key())); });
  }
}

bool readEntry(const Json& v, const std::string& path, const ValueSpec&, std::map<int, MSequence>& seqs, Machine& m,
               Errors& errors) {
  readTable(v, path, errors, [&](const std::string& key, const Json& item, const std::string& at) {
    const int number = readKeyIndex(key, at, 0, lang::kMaxMNumber, "an M number");
    if (seqs.count(number) != 0) {
      fail(at, "duplicate M number " + std::to_string(number));
    }
    seqs.emplace(number, readMSequence(item, at, m, errors));
  });
  return true;
}

bool readEntry(const Json& v, const std::string& path, const ValueSpec&,
               std::map<int, std::vector<std::pair<double, int>>>& inputs, Machine& m, Errors& errors) {
  readTable(v, path, errors, [&](const std::string& key, const Json& item, const std::string& at) {
    const int index = readKeyIndex(key, at, 0, m.numInputs - 1, "an input index");
    if (inputs.count(index) != 0) {
      fail(at, "duplicate input index " + std::to_string(index));
    }
    inputs.emplace(index, readSchedule(item, at));
  });
  return true;
}

/// r_preset (the R indices) and, in z32, pal_preset (the PAL indices).
bool readEntry(const Json& v, const std::string& path, const ValueSpec& spec, std::map<int, double>& presets, Machine&,
               Errors& errors) {
  const bool pal = spec.key == "pal_preset";
  readTable(v, path, errors, [&](const std::string& key, const Json& item, const std::string& at) {
    const int index = pal ? readKeyIndex(key, at, 0, kMaxPalIndex, "a PAL index")
                          : readKeyIndex(key, at, 1, lang::kMaxRIndex, "an R index");
    if (presets.count(index) != 0) {
      fail(at, std::string(pal ? "duplicate PAL index " : "duplicate R index ") + std::to_string(index));
    }
    presets.emplace(index, readFinite(item, at));
  });
  return true;
}

/// origins: number (1..99) -> {axis letter: offset}, each axis one of the machine's.
bool readEntry(const Json& v, const std::string& path, const ValueSpec&,
               std::map<int, std::vector<std::pair<char, double>>>& origins, Machine& m, Errors& errors) {
  readTable(v, path, errors, [&](const std::string& key, const Json& item, const std::string& at) {
    const int number = readKeyIndex(key, at, 1, kMaxOrigin, "an origin number");
    requireObject(item, at);
    std::vector<std::pair<char, double>> offsets;
    for (const auto& axis : item.items()) {
      errors.attempt([&] {
        const std::string axisPath = child(at, axis.key());
        const int index = axis.key().size() == 1 ? m.axisIndex(axis.key()[0]) : -1;
        if (index < 0) {
          fail(axisPath, "key must be an axis of the machine");
        }
        const char letter = m.axes[static_cast<size_t>(index)].letter;
        for (const auto& [l, off] : offsets)
          if (l == letter) {
            fail(axisPath, std::string("duplicate axis ") + letter);
          }
        offsets.emplace_back(letter, readFinite(axis.value(), axisPath));
      });
    }
    std::sort(offsets.begin(), offsets.end());
    origins.emplace(number, std::move(offsets)); // keys of one JSON object: never a duplicate number
  });
  return true;
}

/// One user parameter name: one or two letters, no axis and no fixed address; upper-cased.
std::string readParameterName(const Json& v, const std::string& path, const Machine& m,
                              const std::vector<std::string>& before) {
  std::string name = readString(v, path);
  if (name.empty() || name.size() > 2 ||
      !std::all_of(name.begin(), name.end(), [](char c) { return std::isalpha(static_cast<unsigned char>(c)) != 0; })) {
    fail(path, "a parameter name is one or two letters");
  }
  name = support::upperCopy(name);
  if (name.size() == 1 && m.axisIndex(name[0]) >= 0) {
    fail(path, "parameter name \"" + name + "\" is an axis of the machine");
  }
  if (lang::isZ32AddressName(name)) {
    fail(path, "parameter name \"" + name + "\" is a fixed address of dialect z32");
  }
  if (std::find(before.begin(), before.end(), name) != before.end()) {
    fail(path, "duplicate parameter name \"" + name + "\"");
  }
  return name;
}

/// parameters: the user parameter names, in file order.
bool readEntry(const Json& v, const std::string& path, const ValueSpec&, std::vector<std::string>& names, Machine& m,
               Errors& errors) {
  if (!errors.attempt([&] {
        if (!v.is_array()) {
          fail(path, "must be an array of parameter names");
        }
      })) {
    return false;
  }
  for (size_t i = 0; i < v.size(); ++i) {
    errors.attempt([&] { names.push_back(readParameterName(v[i], child(path, i), m, names)); });
  }
  return true;
}

/// One bound object of a zone ("min" or "max"): axis letter -> number, each an axis of the machine.
void readZoneBounds(const Json& v, const std::string& path, bool isMin, Zone& zone, const Machine& m, Errors& errors) {
  requireObject(v, path);
  for (const auto& item : v.items()) {
    errors.attempt([&] {
      const std::string at = child(path, item.key());
      const int index = item.key().size() == 1 ? m.axisIndex(item.key()[0]) : -1;
      if (index < 0) {
        fail(at, "key must be an axis of the machine");
      }
      const char letter = m.axes[static_cast<size_t>(index)].letter;
      const double x = readFinite(item.value(), at);
      auto it = std::find_if(zone.axes.begin(), zone.axes.end(), [&](const ZoneAxis& a) { return a.letter == letter; });
      if (it == zone.axes.end()) {
        zone.axes.push_back(ZoneAxis{letter});
        it = zone.axes.end() - 1;
      } else if (isMin ? std::isfinite(it->min) : std::isfinite(it->max)) {
        fail(at, std::string("duplicate axis ") + letter);
      }
      (isMin ? it->min : it->max) = x;
    });
  }
}

/// One zone: {"name", "kind", "min", "max"}; at least one axis, min <= max on each.
Zone readZone(const Json& v, const std::string& path, const Machine& m, const std::vector<Zone>& before,
              Errors& errors) {
  requireObject(v, path);
  rejectUnknownKeys(v, path, {"name", "kind", "min", "max"}, errors);
  Zone zone;
  if (!v.contains("name")) {
    fail(path, "missing required key \"name\"");
  }
  zone.name = readString(v["name"], child(path, "name"));
  if (zone.name.empty()) {
    fail(child(path, "name"), "a zone name must not be empty");
  }
  for (const Zone& z : before)
    if (z.name == zone.name) {
      fail(child(path, "name"), "duplicate zone name \"" + zone.name + "\"");
    }
  if (!v.contains("kind")) {
    fail(path, "missing required key \"kind\"");
  }
  const std::string kind = readString(v["kind"], child(path, "kind"));
  if (kind != "forbidden" && kind != "warn") {
    fail(child(path, "kind"), "must be \"forbidden\" or \"warn\"");
  }
  zone.forbidden = kind == "forbidden";
  for (const bool isMin : {true, false}) {
    const char* key = isMin ? "min" : "max";
    if (v.contains(key)) {
      errors.attempt([&] { readZoneBounds(v[key], child(path, key), isMin, zone, m, errors); });
    }
  }
  if (zone.axes.empty()) {
    fail(path, "a zone must bound at least one axis in \"min\" or \"max\"");
  }
  for (const ZoneAxis& a : zone.axes)
    if (!(a.min <= a.max)) {
      fail(child(child(path, "min"), std::string(1, a.letter)),
           std::string("min of axis ") + a.letter + " is above its max");
    }
  std::sort(zone.axes.begin(), zone.axes.end(),
            [&](const ZoneAxis& a, const ZoneAxis& b) { return m.axisIndex(a.letter) < m.axisIndex(b.letter); });
  return zone;
}

/// zones: the crash zones, in file order.
bool readEntry(const Json& v, const std::string& path, const ValueSpec&, std::vector<Zone>& zones, Machine& m,
               Errors& errors) {
  if (!errors.attempt([&] {
        if (!v.is_array()) {
          fail(path, "must be an array of zones");
        }
      })) {
    return false;
  }
  for (size_t i = 0; i < v.size(); ++i) {
    errors.attempt([&] { zones.push_back(readZone(v[i], child(path, i), m, zones, errors)); });
  }
  return true;
}

/// special_m: at most spec.max entries.
bool readEntry(const Json& v, const std::string& path, const ValueSpec& spec, std::map<int, std::string>& specialM,
               Machine&, Errors& errors) {
  return errors.attempt([&] {
    const Json& map = requireObject(v, path);
    if (spec.max.kind == keys::Bound::AtMost && map.size() > static_cast<size_t>(spec.max.value)) {
      fail(path, "may map at most " + std::to_string(spec.max.value) + " M numbers (seed 004)");
    }
    for (const auto& item : map.items()) {
      errors.attempt([&] { readSpecialM(item.key(), item.value(), child(path, item.key()), specialM); });
    }
  });
}

Machine readMachine(const Json& doc, Errors& errors) {
  Machine m;
  if (!errors.attempt([&] { requireObject(doc, ""); })) {
    return m;
  }
  rejectUnknownKeys(doc, "", keys::keyNames<Machine>(), errors);
  // The Late keys after the Early ones: the tables depend on num_inputs and default_m_duration_s.
  readKeys(doc, "", m, keys::Read::Early, true, m, errors);
  readKeys(doc, "", m, keys::Read::Late, true, m, errors);
  return m;
}

// ---- printing ----

std::string jsonNumber(double x) { return Json(x).dump(); }

std::string str(const std::string& s) { return Json(s).dump(); }

/// Appends `"key": value` lines of one object, 2-space indent per level, §5.1 layout.
class ObjectWriter {
public:
  ObjectWriter(std::string& out, int level) : out_(out), level_(level) {}

  void field(std::string_view key, const std::string& valueText) {
    out_ += first_ ? "{\n" : ",\n";
    first_ = false;
    out_.append(static_cast<size_t>(2 * (level_ + 1)), ' ');
    out_ += str(std::string(key));
    out_ += ": ";
    out_ += valueText;
  }

  void close() {
    if (first_) {
      out_ += "{}";
      return;
    }
    out_ += "\n";
    out_.append(static_cast<size_t>(2 * level_), ' ');
    out_ += "}";
  }

private:
  std::string& out_;
  int level_;
  bool first_ = true;
};

template <class O> std::string objectJson(const O& object, int level, bool withZ32Keys);

// Each value as JSON text; `level` is that of the object that holds it.
std::string valueJson(double x, int) { return jsonNumber(x); }
std::string valueJson(int x, int) { return std::to_string(x); }
std::string valueJson(bool b, int) { return b ? "true" : "false"; }
std::string valueJson(const std::string& s, int) { return str(s); }
std::string valueJson(char letter, int) { return str(std::string(1, letter)); }
std::string valueJson(Dialect d, int) { return str(dialectName(d)); }

std::string valueJson(const std::vector<Axis>& axes, int level) {
  std::string out = "[";
  for (size_t i = 0; i < axes.size(); ++i) {
    out += i == 0 ? "\n" : ",\n";
    out.append(static_cast<size_t>(2 * (level + 2)), ' ');
    out += objectJson(axes[i], level + 2, false);
  }
  if (axes.empty()) {
    out += "]";
  } else {
    out += "\n";
    out.append(static_cast<size_t>(2 * (level + 1)), ' ');
    out += "]";
  }
  return out;
}

/// A table by number or index, one level deeper than its holder.
template <class Entries, class F> std::string entriesJson(const Entries& entries, int level, F&& valueText) {
  std::string out;
  ObjectWriter w(out, level + 1);
  for (const auto& [key, value] : entries) {
    w.field(std::to_string(key), valueText(value));
  }
  w.close();
  return out;
}

std::string scheduleJson(const std::vector<std::pair<double, int>>& steps) {
  std::string out = "[";
  for (size_t i = 0; i < steps.size(); ++i) {
    out += i == 0 ? "[" : ", [";
    out += jsonNumber(steps[i].first) + ", " + std::to_string(steps[i].second) + "]";
  }
  out += "]";
  return out;
}

std::string valueJson(const std::map<int, MSequence>& seqs, int level) {
  return entriesJson(seqs, level, [&](const MSequence& s) { return objectJson(s, level + 2, false); });
}
std::string valueJson(const std::vector<std::pair<int, int>>& setInputs, int level) {
  return entriesJson(setInputs, level, [](int bit) { return std::to_string(bit); });
}
std::string valueJson(const std::map<int, std::vector<std::pair<double, int>>>& inputs, int level) {
  return entriesJson(inputs, level, scheduleJson);
}
std::string valueJson(const std::map<int, double>& presets, int level) {
  return entriesJson(presets, level, jsonNumber);
}
std::string valueJson(const std::map<int, std::string>& specialM, int level) {
  return entriesJson(specialM, level, str);
}
std::string valueJson(const std::map<int, std::vector<std::pair<char, double>>>& origins, int level) {
  return entriesJson(origins, level, [](const std::vector<std::pair<char, double>>& offsets) {
    std::string out = "{";
    for (size_t i = 0; i < offsets.size(); ++i)
      out += (i == 0 ? "" : ", ") + str(std::string(1, offsets[i].first)) + ": " + jsonNumber(offsets[i].second);
    return out + "}";
  });
}
std::string valueJson(const std::vector<std::string>& names, int) {
  std::string out = "[";
  for (size_t i = 0; i < names.size(); ++i)
    out += (i == 0 ? "" : ", ") + str(names[i]);
  return out + "]";
}

std::string valueJson(const std::vector<Zone>& zones, int level) {
  std::string out = "[";
  const auto bounds = [](const Zone& z, bool isMin) {
    std::string text = "{";
    for (const ZoneAxis& a : z.axes) {
      const double x = isMin ? a.min : a.max;
      if (!std::isfinite(x)) continue;
      text += (text.size() > 1 ? ", " : "") + str(std::string(1, a.letter)) + ": " + jsonNumber(x);
    }
    return text + "}";
  };
  for (size_t i = 0; i < zones.size(); ++i) {
    out += i == 0 ? "\n" : ",\n";
    out.append(static_cast<size_t>(2 * (level + 2)), ' ');
    std::string zone;
    ObjectWriter w(zone, level + 2);
    w.field("name", str(zones[i].name));
    w.field("kind", str(zones[i].forbidden ? "forbidden" : "warn"));
    w.field("min", bounds(zones[i], true));
    w.field("max", bounds(zones[i], false));
    w.close();
    out += zone;
  }
  if (!zones.empty()) {
    out += "\n";
    out.append(static_cast<size_t>(2 * (level + 1)), ' ');
  }
  return out + "]";
}

/// The keys of object O in table order; the IfZ32 keys only when `withZ32Keys`.
template <class O> std::string objectJson(const O& object, int level, bool withZ32Keys) {
  std::string out;
  ObjectWriter w(out, level);
  keys::forEachKey<O>([&](const auto& key) {
    if (key.print == keys::Print::Always || (key.print == keys::Print::IfZ32 && withZ32Keys) ||
        (key.print == keys::Print::IfSet && !isDefault(object.*key.field, key.def))) {
      w.field(key.name, valueJson(object.*key.field, level));
    }
  });
  w.close();
  return out;
}

/// The z32 keys are printed for a z32 machine or when one of them is set, so that a sidac
/// machine prints exactly the keys of the sidac dialect.
bool printsZ32Keys(const Machine& m) {
  bool print = m.dialect == Dialect::Z32;
  keys::forEachKey<Machine>([&](const auto& key) {
    if (key.print == keys::Print::IfZ32 && !isDefault(m.*key.field, key.def)) {
      print = true;
    }
  });
  return print;
}

/// nlohmann's what() without its "[json.exception.parse_error.101] " prefix.
std::string withoutExceptionId(const Json::exception& e) {
  const std::string what = e.what();
  const size_t close = what.find("] ");
  return what.rfind("[json.exception.", 0) == 0 && close != std::string::npos ? what.substr(close + 2) : what;
}

} // namespace

const char* dialectName(Dialect d) {
  switch (d) {
  case Dialect::Sidac: return "sidac";
  case Dialect::Z32: return "z32";
  }
  return "sidac";
}

std::optional<Dialect> parseDialect(std::string_view s) {
  const std::string lower = support::lowerCopy(s);
  if (lower == "sidac") {
    return Dialect::Sidac;
  }
  if (lower == "z32") {
    return Dialect::Z32;
  }
  return std::nullopt;
}

int Machine::axisIndex(char letter) const {
  const char want = upper(letter);
  for (size_t i = 0; i < axes.size(); ++i) {
    if (upper(axes[i].letter) == want) {
      return static_cast<int>(i);
    }
  }
  return -1;
}

Machine builtinMachine() {
  Machine m;
  applyDefaults(m, m);
  m.builtin = true;
  return m;
}

std::optional<Machine> parseMachine(std::string_view jsonText, MachineErrors& errors) {
  errors = MachineErrors{};
  Errors collect(errors);
  if (!support::jsonNestingWithin(jsonText, kMaxDepth)) {
    collect.add(MachineError{"", "arrays and objects nested deeper than " + std::to_string(kMaxDepth) + " levels"});
    return std::nullopt;
  }
  try {
    DuplicateKeyGuard guard;
    const Json doc =
        Json::parse(jsonText.begin(), jsonText.end(), [&guard](int depth, Json::parse_event_t event, Json& parsed) {
          return guard(depth, event, parsed);
        });
    Machine m = readMachine(doc, collect);
    if (errors.count == 0) {
      return m;
    }
  } catch (const ValidationFailure& f) {
    collect.add(f.error);
  } catch (const Json::parse_error& e) {
    // e.byte is 1-based: the byte at which the parser gave up.
    collect.add(MachineError{"", "invalid JSON at byte " + std::to_string(e.byte) + ": " + withoutExceptionId(e)});
  } catch (const Json::exception& e) {
    collect.add(MachineError{"", "invalid JSON: " + withoutExceptionId(e)});
  } catch (const std::exception& e) {
    collect.add(MachineError{"", std::string("cannot read the machine file: ") + e.what()});
  }
  return std::nullopt;
}

MachineResult parseMachine(std::string_view jsonText) {
  MachineErrors errors;
  std::optional<Machine> m = parseMachine(jsonText, errors);
  if (!m) {
    return errors.shown.front();
  }
  return std::move(*m);
}

std::string machineToJson(const Machine& m) { return objectJson(m, 0, printsZ32Keys(m)) + "\n"; }

} // namespace iso::machine
