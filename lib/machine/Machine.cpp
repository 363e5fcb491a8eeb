//! @file Machine.cpp
//! @brief Machine file (SPEC §5.1): strict JSON validation, canonical printing, built-in default.
#include "machine/Machine.h"

#include <cctype>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <set>
#include <vector>

#include <nlohmann/json.hpp>

#include "lang/Addresses.h"
#include "lang/Axes.h"
#include "lang/Limits.h"
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
// Upper bound for counts (inputs, outputs, look-ahead): keeps later allocations sane.
constexpr int kMaxCount = 1'000'000;
constexpr int kMaxAxes = lang::kMaxMachineAxes;
constexpr int kMaxRIndex = lang::kMaxRIndex;

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

double readNumber(const Json& v, const std::string& path, const char* what) {
  if (!v.is_number()) {
    fail(path, std::string("must be ") + what);
  }
  const double x = v.get<double>();
  if (!std::isfinite(x)) {
    fail(path, "must be a finite number");
  }
  return x;
}

double readFinite(const Json& v, const std::string& path) { return readNumber(v, path, "a number"); }

double readPositive(const Json& v, const std::string& path) {
  const double x = readNumber(v, path, "a number > 0");
  if (!(x > 0)) {
    fail(path, "must be a number > 0");
  }
  return x;
}

double readNonNegative(const Json& v, const std::string& path) {
  const double x = readNumber(v, path, "a number >= 0");
  if (!(x >= 0)) {
    fail(path, "must be a number >= 0");
  }
  return x;
}

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

void rejectUnknownKeys(const Json& obj, const std::string& path, std::initializer_list<std::string_view> known,
                       Errors& errors) {
  const std::vector<std::string_view> candidates(known);
  for (const auto& item : obj.items()) {
    bool ok = false;
    for (std::string_view k : known) {
      ok = ok || item.key() == k;
    }
    if (!ok) {
      const std::string_view near = support::closestMatch(item.key(), candidates);
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

/// One axis, or nullopt when any of its keys is wrong (each error is recorded).
std::optional<Axis> readAxis(const Json& v, const std::string& path, Dialect dialect, Errors& errors) {
  if (!errors.attempt([&] { requireObject(v, path); })) {
    return std::nullopt;
  }
  const size_t before = errors.count();
  rejectUnknownKeys(v, path, {"name", "max_velocity", "max_accel", "limit_minus", "limit_plus", "start"}, errors);
  for (const char* key : {"name", "max_velocity", "max_accel", "limit_minus", "limit_plus"}) {
    if (!v.contains(key)) {
      errors.add(MachineError{path, std::string("missing required key \"") + key + "\""});
    }
  }
  Axis axis;
  const auto read = [&](const char* key, auto&& reader) {
    return v.contains(key) && errors.attempt([&] { reader(v[key], child(path, key)); });
  };
  read("name", [&](const Json& n, const std::string& namePath) {
    const std::string name = readString(n, namePath);
    if (name.size() != 1 || !std::isalpha(static_cast<unsigned char>(name[0]))) {
      fail(namePath, "axis name must be a single letter");
    }
    axis.letter = upper(name[0]);
    if (lang::isFixedAddress(axis.letter, dialect)) {
      fail(namePath,
           std::string("axis name \"") + axis.letter + "\" is a fixed address of dialect " + dialectName(dialect));
    }
  });
  read("max_velocity", [&](const Json& x, const std::string& at) { axis.maxVelocity = readPositive(x, at); });
  read("max_accel", [&](const Json& x, const std::string& at) { axis.maxAccel = readPositive(x, at); });
  const bool minus =
      read("limit_minus", [&](const Json& x, const std::string& at) { axis.limitMinus = readFinite(x, at); });
  const bool plus =
      read("limit_plus", [&](const Json& x, const std::string& at) { axis.limitPlus = readFinite(x, at); });
  if (!minus || !plus) {
    return std::nullopt;
  }
  errors.attempt([&] {
    if (axis.limitPlus < axis.limitMinus) {
      fail(child(path, "limit_plus"), "must be >= limit_minus");
    }
    axis.start = 0;
    if (v.contains("start")) {
      const std::string startPath = child(path, "start");
      axis.start = readFinite(v["start"], startPath);
      if (axis.start < axis.limitMinus || axis.start > axis.limitPlus) {
        fail(startPath, "start position is outside the soft limits");
      }
    } else if (axis.limitMinus > 0 || axis.limitPlus < 0) {
      fail(path, "the default start 0 is outside the soft limits; give \"start\"");
    }
  });
  if (errors.count() != before) {
    return std::nullopt;
  }
  return axis;
}

MSequence readMSequence(const Json& v, const std::string& path, const Machine& m, Errors& errors) {
  requireObject(v, path);
  rejectUnknownKeys(v, path, {"duration_s", "set_inputs"}, errors);
  MSequence seq;
  // An entry without its own duration lasts default_m_duration_s, like an M with no entry.
  seq.durationS = m.defaultMDurationS;
  if (v.contains("duration_s")) {
    errors.attempt([&] { seq.durationS = readNonNegative(v["duration_s"], child(path, "duration_s")); });
  }
  if (v.contains("set_inputs")) {
    const std::string setPath = child(path, "set_inputs");
    const Json& set = requireObject(v["set_inputs"], setPath);
    std::map<int, int> byIndex;
    for (const auto& item : set.items()) {
      errors.attempt([&] {
        const std::string itemPath = child(setPath, item.key());
        const int index = readKeyIndex(item.key(), itemPath, 0, m.numInputs - 1, "an input index");
        const int bit = readBit(item.value(), itemPath);
        if (!byIndex.emplace(index, bit).second) {
          fail(itemPath, "duplicate input index " + std::to_string(index));
        }
      });
    }
    seq.setInputs.assign(byIndex.begin(), byIndex.end());
  }
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
void readSpecialM(const std::string& key, const Json& value, Machine& m) {
  const std::string path = child("/special_m", key);
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
  if (m.specialM.count(number) != 0) {
    fail(path, "duplicate M number " + std::to_string(number));
  }
  std::string name = readString(value, path);
  if (!isProcName(name)) {
    fail(path, "must be a subprogram name (a letter or '_', then letters, digits or '_')");
  }
  m.specialM.emplace(number, std::move(name));
}

/// The keys of dialect z32 (SPEC §4.6): special_m, optional_stop, aux_duration_s.
void readZ32Keys(const Json& doc, Machine& m, Errors& errors) {
  if (doc.contains("special_m")) {
    errors.attempt([&] {
      const Json& map = requireObject(doc["special_m"], "/special_m");
      if (map.size() > static_cast<size_t>(lang::kMaxSpecialM)) {
        fail("/special_m", "may map at most " + std::to_string(lang::kMaxSpecialM) + " M numbers (seed 004)");
      }
      for (const auto& item : map.items()) {
        errors.attempt([&] { readSpecialM(item.key(), item.value(), m); });
      }
    });
  }
  if (doc.contains("optional_stop")) {
    errors.attempt([&] {
      if (!doc["optional_stop"].is_boolean()) {
        fail("/optional_stop", "must be true or false");
      }
      m.optionalStop = doc["optional_stop"].get<bool>();
    });
  }
  if (doc.contains("aux_duration_s")) {
    errors.attempt([&] { m.auxDurationS = readNonNegative(doc["aux_duration_s"], "/aux_duration_s"); });
  }
}

/// Every item of the object at `key` (when present) through `readItem(key, value, path)`,
/// each error recorded and the others still read.
template <class F> void readEach(const Json& doc, const char* key, Errors& errors, F&& readItem) {
  if (!doc.contains(key)) {
    return;
  }
  const std::string path = std::string("/") + key;
  if (!errors.attempt([&] { requireObject(doc[key], path); })) {
    return;
  }
  for (const auto& item : doc[key].items()) {
    errors.attempt([&] { readItem(item.key(), item.value(), child(path, item.key())); });
  }
}

void readAxes(const Json& doc, Machine& m, Errors& errors) {
  if (!doc.contains("axes")) {
    errors.add(MachineError{"", "missing required key \"axes\""});
    return;
  }
  const Json& axes = doc["axes"];
  if (!errors.attempt([&] {
        if (!axes.is_array()) {
          fail("/axes", "must be an array of axis objects");
        }
        if (axes.empty() || axes.size() > kMaxAxes) {
          fail("/axes", "must hold 1 to " + std::to_string(kMaxAxes) + " axes");
        }
      })) {
    return;
  }
  for (size_t i = 0; i < axes.size(); ++i) {
    const std::string axisPath = child("/axes", i);
    const std::optional<Axis> axis = readAxis(axes[i], axisPath, m.dialect, errors);
    if (!axis) {
      continue;
    }
    if (m.axisIndex(axis->letter) >= 0) {
      errors.add(MachineError{child(axisPath, "name"), std::string("duplicate axis name \"") + axis->letter + "\""});
    }
    m.axes.push_back(*axis);
  }
}

/// The keys that hold one number each.
void readScalars(const Json& doc, Machine& m, Errors& errors) {
  const auto read = [&](const char* key, auto&& reader) {
    if (doc.contains(key)) {
      errors.attempt([&] { reader(doc[key], std::string("/") + key); });
    }
  };
  read("ipo_cycle_s", [&](const Json& v, const std::string& at) { m.ipoCycleS = readPositive(v, at); });
  read("block_time_s", [&](const Json& v, const std::string& at) { m.blockTimeS = readNonNegative(v, at); });
  read("corner_deviation_mm", [&](const Json& v, const std::string& at) { m.cornerDeviationMm = readPositive(v, at); });
  read("lookahead_blocks",
       [&](const Json& v, const std::string& at) { m.lookaheadBlocks = readInt(v, at, 1, kMaxCount); });
  read("default_m_duration_s",
       [&](const Json& v, const std::string& at) { m.defaultMDurationS = readNonNegative(v, at); });
  read("m0_wait_s", [&](const Json& v, const std::string& at) { m.m0WaitS = readNonNegative(v, at); });
  read("num_inputs", [&](const Json& v, const std::string& at) { m.numInputs = readInt(v, at, 0, kMaxCount); });
  read("num_outputs", [&](const Json& v, const std::string& at) { m.numOutputs = readInt(v, at, 0, kMaxCount); });
}

Machine readMachine(const Json& doc, Errors& errors) {
  Machine m;
  if (!errors.attempt([&] { requireObject(doc, ""); })) {
    return m;
  }
  rejectUnknownKeys(doc, "",
                    {"name", "dialect", "axes", "ipo_cycle_s", "block_time_s", "corner_deviation_mm",
                     "lookahead_blocks", "m_sequences", "default_m_duration_s", "m0_wait_s", "num_inputs",
                     "num_outputs", "inputs", "r_preset", "special_m", "optional_stop", "aux_duration_s"},
                    errors);
  if (doc.contains("name")) {
    errors.attempt([&] { m.name = readString(doc["name"], "/name"); });
  }
  if (doc.contains("dialect")) {
    errors.attempt([&] {
      const std::optional<Dialect> dialect = parseDialect(readString(doc["dialect"], "/dialect"));
      if (!dialect) {
        fail("/dialect", "must be \"sidac\" or \"z32\"");
      }
      m.dialect = *dialect;
    });
  }
  readAxes(doc, m, errors);
  readScalars(doc, m, errors);
  // Read after the scalars they depend on (num_inputs, default_m_duration_s).
  readEach(doc, "m_sequences", errors, [&](const std::string& key, const Json& v, const std::string& path) {
    const int number = readKeyIndex(key, path, 0, lang::kMaxMNumber, "an M number");
    if (m.mSequences.count(number) != 0) {
      fail(path, "duplicate M number " + std::to_string(number));
    }
    m.mSequences.emplace(number, readMSequence(v, path, m, errors));
  });
  readEach(doc, "inputs", errors, [&](const std::string& key, const Json& v, const std::string& path) {
    const int index = readKeyIndex(key, path, 0, m.numInputs - 1, "an input index");
    if (m.inputs.count(index) != 0) {
      fail(path, "duplicate input index " + std::to_string(index));
    }
    m.inputs.emplace(index, readSchedule(v, path));
  });
  readEach(doc, "r_preset", errors, [&](const std::string& key, const Json& v, const std::string& path) {
    const int index = readKeyIndex(key, path, 1, kMaxRIndex, "an R index");
    if (m.rPreset.count(index) != 0) {
      fail(path, "duplicate R index " + std::to_string(index));
    }
    m.rPreset.emplace(index, readFinite(v, path));
  });
  readZ32Keys(doc, m, errors);
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

std::string axisJson(const Axis& a, int level) {
  std::string out;
  ObjectWriter w(out, level);
  w.field("name", str(std::string(1, a.letter)));
  w.field("max_velocity", jsonNumber(a.maxVelocity));
  w.field("max_accel", jsonNumber(a.maxAccel));
  w.field("limit_minus", jsonNumber(a.limitMinus));
  w.field("limit_plus", jsonNumber(a.limitPlus));
  w.field("start", jsonNumber(a.start));
  w.close();
  return out;
}

std::string mSequenceJson(const MSequence& s, int level) {
  std::string out;
  ObjectWriter w(out, level);
  w.field("duration_s", jsonNumber(s.durationS));
  std::string inputs;
  ObjectWriter iw(inputs, level + 1);
  for (const auto& [index, bit] : s.setInputs) {
    iw.field(std::to_string(index), std::to_string(bit));
  }
  iw.close();
  w.field("set_inputs", inputs);
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
  for (char letter : lang::kDefaultAxisLetters) {
    Axis axis;
    axis.letter = letter;
    axis.maxVelocity = 500;
    axis.maxAccel = 2000;
    axis.limitMinus = -1000;
    axis.limitPlus = 3000;
    axis.start = 0;
    m.axes.push_back(axis);
  }
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

std::string machineToJson(const Machine& m) {
  std::string out;
  ObjectWriter w(out, 0);
  w.field("name", str(m.name));
  w.field("dialect", str(dialectName(m.dialect)));

  std::string axes = "[";
  for (size_t i = 0; i < m.axes.size(); ++i) {
    axes += i == 0 ? "\n    " : ",\n    ";
    axes += axisJson(m.axes[i], 2);
  }
  axes += m.axes.empty() ? "]" : "\n  ]";
  w.field("axes", axes);

  w.field("ipo_cycle_s", jsonNumber(m.ipoCycleS));
  w.field("block_time_s", jsonNumber(m.blockTimeS));
  w.field("corner_deviation_mm", jsonNumber(m.cornerDeviationMm));
  w.field("lookahead_blocks", std::to_string(m.lookaheadBlocks));

  std::string seqs;
  ObjectWriter sw(seqs, 1);
  for (const auto& [number, seq] : m.mSequences) {
    sw.field(std::to_string(number), mSequenceJson(seq, 2));
  }
  sw.close();
  w.field("m_sequences", seqs);

  w.field("default_m_duration_s", jsonNumber(m.defaultMDurationS));
  w.field("m0_wait_s", jsonNumber(m.m0WaitS));
  w.field("num_inputs", std::to_string(m.numInputs));
  w.field("num_outputs", std::to_string(m.numOutputs));

  std::string inputs;
  ObjectWriter iw(inputs, 1);
  for (const auto& [index, steps] : m.inputs) {
    iw.field(std::to_string(index), scheduleJson(steps));
  }
  iw.close();
  w.field("inputs", inputs);

  std::string presets;
  ObjectWriter pw(presets, 1);
  for (const auto& [index, value] : m.rPreset) {
    pw.field(std::to_string(index), jsonNumber(value));
  }
  pw.close();
  w.field("r_preset", presets);
  // The z32 keys are printed for a z32 machine or when they are set, so that a sidac
  // machine prints exactly the §5.1 keys.
  if (m.dialect == Dialect::Z32 || !m.specialM.empty() || m.optionalStop || m.auxDurationS != 0) {
    std::string special;
    ObjectWriter spw(special, 1);
    for (const auto& [number, name] : m.specialM) {
      spw.field(std::to_string(number), str(name));
    }
    spw.close();
    w.field("special_m", special);
    w.field("optional_stop", m.optionalStop ? "true" : "false");
    w.field("aux_duration_s", jsonNumber(m.auxDurationS));
  }
  w.close();
  out += "\n";
  return out;
}

} // namespace iso::machine
