//! @file Sweep.cpp
//! @brief isosim --sweep: the sweep file, the grid, the runs on threads, the table.
#include "driver/Sweep.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <mutex>
#include <optional>
#include <ostream>
#include <stdexcept>

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <toml++/toml.h>

#include "driver/Batch.h"
#include "driver/MachineOverrides.h"
#include "driver/Settings.h"
#include "driver/Sources.h"
#include "sim/Run.h"
#include "sim/TraceWriter.h"
#include "support/CaseFold.h"
#include "support/File.h"
#include "support/Text.h"
#include "support/TomlDepth.h"

namespace iso::driver {

bool isSweepRunOption(std::string_view key) { return key == "feed_override" || key == "rapid_override"; }

namespace {

/// "FILE:LINE:COL" of a TOML node.
std::string sweepWhere(const std::string& path, const toml::node& n) {
  return fmt::format("{}:{}:{}", path, n.source().begin.line, n.source().begin.column);
}

/// A number of a sweep file as --set VALUE text: the shortest text that reads back as it.
std::string sweepNumberText(double v) { return fmt::format("{}", v); }

/// One value of a `values` array as its --set VALUE text; nullopt when it is not a number,
/// boolean or string.
std::optional<std::string> sweepValueText(const toml::node& n) {
  if (auto i = n.value_exact<int64_t>()) return std::to_string(*i);
  if (auto d = n.value_exact<double>()) {
    if (!std::isfinite(*d)) return std::nullopt;
    return sweepNumberText(*d);
  }
  if (auto b = n.value_exact<bool>()) return *b ? "true" : "false";
  if (auto s = n.value_exact<std::string>()) return *s;
  return std::nullopt;
}

/// The values of `range = {from, to, step}`: from, from + step, ... up to to (inclusive, to
/// within 1e-9 steps), each computed as from + i·step and rounded to 12 significant digits.
support::Expected<std::vector<std::string>> sweepRange(const std::string& path, const toml::node& n) {
  const toml::table* t = n.as_table();
  auto fail = [&](const toml::node& at, const std::string& why) -> support::Error {
    return {sweepWhere(path, at), why};
  };
  if (!t) return fail(n, "'range' must be a table {from = A, to = B, step = S}");
  double part[3] = {0, 0, 0};
  bool whole = true;
  const char* names[3] = {"from", "to", "step"};
  for (const auto& [k, v] : *t)
    if (k.str() != "from" && k.str() != "to" && k.str() != "step")
      return fail(v, fmt::format("unknown key '{}' in 'range' (from, to, step)", k.str()));
  for (int i = 0; i < 3; ++i) {
    const toml::node* v = t->get(names[i]);
    if (!v) return fail(n, fmt::format("'range' needs '{}'", names[i]));
    if (!v->is_number() || !std::isfinite(*v->value<double>()))
      return fail(*v, fmt::format("'range.{}' must be a number", names[i]));
    part[i] = *v->value<double>();
    whole = whole && v->is_integer();
  }
  const double from = part[0], to = part[1], step = part[2];
  if (step == 0) return fail(*t->get("step"), "'range.step' must not be 0");
  const double steps = (to - from) / step;
  if (steps < -1e-9)
    return fail(*t->get("step"), fmt::format("'range.step' {} goes away from 'to' ({} to {})", sweepNumberText(step),
                                             sweepNumberText(from), sweepNumberText(to)));
  if (!(steps + 1 <= static_cast<double>(kMaxSweepRuns)))
    return fail(n, fmt::format("the range has more than {} values", kMaxSweepRuns));
  const auto count = static_cast<size_t>(std::floor(steps + 1e-9)) + 1;
  std::vector<std::string> out;
  for (size_t i = 0; i < count; ++i) {
    const double v = from + static_cast<double>(i) * step;
    out.push_back(whole ? std::to_string(static_cast<int64_t>(v))
                        : sweepNumberText(std::stod(fmt::format("{:.12g}", v))));
  }
  return out;
}

/// One [[vary]] table.
support::Expected<SweepVary> sweepVary(const std::string& path, const toml::node& n) {
  auto fail = [&](const toml::node& at, const std::string& why) -> support::Error {
    return {sweepWhere(path, at), why};
  };
  const toml::table* t = n.as_table();
  if (!t) return fail(n, "each 'vary' must be a table with 'key' and 'values' (or 'range')");
  SweepVary out;
  out.where = sweepWhere(path, n);
  for (const auto& [k, v] : *t)
    if (k.str() != "key" && k.str() != "values" && k.str() != "range")
      return fail(v, fmt::format("unknown key '{}' in 'vary' (key, values, range)", k.str()));
  const toml::node* key = t->get("key");
  if (!key) return fail(n, "'vary' needs a 'key' (a machine-file key such as axes.X.max_accel, or feed_override)");
  if (!key->is_string() || key->value<std::string>()->empty())
    return fail(*key, "'key' must be a machine-file key such as \"axes.X.max_accel\"");
  out.key = *key->value<std::string>();
  out.where = sweepWhere(path, *key);
  if (out.key.find('=') != std::string::npos) return fail(*key, fmt::format("'key' '{}' has a '='", out.key));
  const toml::node* values = t->get("values");
  const toml::node* range = t->get("range");
  if ((values != nullptr) == (range != nullptr))
    return fail(n, fmt::format("'vary' of '{}' needs either 'values' or 'range'", out.key));
  if (range) {
    auto r = sweepRange(path, *range);
    if (!r) return r.error();
    out.values = std::move(*r);
    out.valueWhere.assign(out.values.size(), sweepWhere(path, *range));
  } else {
    const toml::array* a = values->as_array();
    if (!a || a->empty()) return fail(*values, "'values' must be a non-empty array");
    for (const auto& e : *a) {
      auto text = sweepValueText(e);
      if (!text) return fail(e, "each value must be a number, true, false or a string");
      out.values.push_back(std::move(*text));
      out.valueWhere.push_back(sweepWhere(path, e));
    }
  }
  return out;
}

/// `a` × `b`, saturated at the largest size_t.
size_t timesSaturated(size_t a, size_t b) {
  if (a != 0 && b > std::numeric_limits<size_t>::max() / a) return std::numeric_limits<size_t>::max();
  return a * b;
}

/// The top-level keys of a parsed sweep file into `out`.
support::Status sweepKeys(const std::string& path, const toml::table& tbl, SweepSpec& out) {
  auto fail = [&](const toml::node& at, const std::string& why) { return support::Error{sweepWhere(path, at), why}; };
  for (const auto& [k, v] : tbl) {
    if (k.str() == "programs") {
      const toml::array* a = v.as_array();
      if (!a || a->empty()) return fail(v, "'programs' must be a non-empty array of program paths");
      for (const auto& e : *a) {
        if (!e.is_string() || e.value<std::string>()->empty()) return fail(e, "each program must be a path (a string)");
        out.programs.push_back(pathBeside(path, *e.value<std::string>()));
      }
    } else if (k.str() == "machine") {
      if (!v.is_string() || v.value<std::string>()->empty()) return fail(v, "'machine' must be a path (a string)");
      out.machine = pathBeside(path, *v.value<std::string>());
    } else if (k.str() == "vary") {
      const toml::array* a = v.as_array();
      if (!a) return fail(v, "'vary' must be tables: [[vary]]");
      for (const auto& e : *a) {
        auto vr = sweepVary(path, e);
        if (!vr) return vr.error();
        for (const SweepVary& seen : out.vary)
          if (seen.key == vr->key)
            return support::Error{vr->where, fmt::format("'{}' is varied twice (first at {})", vr->key, seen.where)};
        out.variants = timesSaturated(out.variants, vr->values.size());
        if (out.variants > kMaxSweepRuns) // before more lists are expanded
          return support::Error{vr->where, fmt::format("the sweep has more than {} variants with this vary list; at "
                                                       "most {} runs are allowed",
                                                       kMaxSweepRuns, kMaxSweepRuns)};
        out.vary.push_back(std::move(*vr));
      }
    } else {
      const std::string_view near = support::closestMatch(k.str(), {"programs", "machine", "vary"});
      return fail(v, fmt::format("unknown key '{}'{} (programs, machine, vary)", k.str(),
                                 near.empty() ? "" : fmt::format("; did you mean '{}'?", near)));
    }
  }
  return {};
}

} // namespace

support::Expected<SweepSpec> parseSweep(std::string_view text, const std::string& path) {
  if (const size_t at = support::tomlNestingBeyond(text); at != std::string_view::npos) {
    const std::string_view before = text.substr(0, at);
    const size_t nl = before.rfind('\n');
    return support::Error{fmt::format("{}:{}:{}", path, std::count(before.begin(), before.end(), '\n') + 1,
                                      nl == std::string_view::npos ? at + 1 : at - nl),
                          fmt::format("tables or arrays nested deeper than {} levels", support::kMaxNesting)};
  }
  toml::table tbl;
  try {
    tbl = toml::parse(text, path);
  } catch (const toml::parse_error& e) {
    return support::Error{fmt::format("{}:{}:{}", path, e.source().begin.line, e.source().begin.column),
                          std::string(e.description())};
  }
  SweepSpec out;
  out.path = path;
  if (support::Status s = sweepKeys(path, tbl, out); !s) return s.error();
  if (out.programs.empty()) return support::Error{path, "the sweep names no program: programs = [\"a.mpf\", ...]"};
  const size_t runs = timesSaturated(out.programs.size(), out.variants);
  if (runs > kMaxSweepRuns)
    return support::Error{
        path, fmt::format("the sweep has {} runs ({} program{} x {} variants); at most {} are allowed", runs,
                          out.programs.size(), out.programs.size() == 1 ? "" : "s", out.variants, kMaxSweepRuns)};
  return out;
}

support::Expected<SweepSpec> loadSweep(const std::string& path) {
  auto text = readBatchFile(path, "sweep");
  if (!text) return text.error();
  return parseSweep(*text, path);
}

SweepVariant sweepVariant(const SweepSpec& spec, size_t i) {
  SweepVariant v;
  v.values.resize(spec.vary.size());
  for (size_t k = spec.vary.size(); k-- > 0;) {
    const auto& vals = spec.vary[k].values;
    v.values[k] = vals[i % vals.size()];
    i /= vals.size();
  }
  for (size_t k = 0; k < spec.vary.size(); ++k) {
    const std::string& key = spec.vary[k].key;
    const std::string& val = v.values[k];
    if (key == "feed_override") {
      v.feedOverride = val;
    } else if (key == "rapid_override") {
      v.rapidOverride = val;
    } else {
      v.sets.push_back(key + "=" + val); // read as --set reads VALUE
    }
    if (!v.label.empty()) v.label += ' ';
    v.label += key + "=" + val;
  }
  return v;
}

std::string shellWord(std::string_view word) {
  const bool safe = !word.empty() && std::all_of(word.begin(), word.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) ||
           std::string_view("_-./=:%+,@").find(c) != std::string_view::npos;
  });
  if (safe) return std::string(word);
  std::string out = "'";
  for (char c : word)
    if (c == '\'')
      out += "'\\''";
    else
      out += c;
  return out + "'";
}

namespace {

/// A CSV field: quoted when it holds a comma, a quote or a line break.
std::string csvField(std::string_view f) {
  if (f.find_first_of(",\"\r\n") == std::string_view::npos) return std::string(f);
  std::string out = "\"";
  for (char c : f) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

struct SweepCounts {
  size_t ok = 0, error = 0, emergency = 0;
};

SweepCounts countRows(const std::vector<SweepRow>& rows) {
  SweepCounts c;
  for (const SweepRow& r : rows)
    (r.status == sim::Status::Ok ? c.ok : r.status == sim::Status::Error ? c.error : c.emergency)++;
  return c;
}

} // namespace

std::string renderSweepCsv(const SweepSpec& spec, const std::vector<SweepRow>& rows) {
  std::string out = "program,variant";
  for (const SweepVary& v : spec.vary)
    out.append(",").append(csvField(v.key));
  out += ",status,cycle_time_s,blocks,spindle_on_s,tool_changes,warnings,message\n";
  for (const SweepRow& r : rows) {
    const SweepVariant v = sweepVariant(spec, r.variant);
    out += csvField(spec.programs[r.program]) + "," + csvField(v.label);
    for (const std::string& val : v.values)
      out.append(",").append(csvField(val));
    out += fmt::format(",{},{},{},{},{},{},{}\n", sim::statusName(r.status), sim::formatNumber(r.cycleTimeS), r.blocks,
                       sim::formatNumber(r.spindleOnS), r.toolChanges, r.warnings, csvField(r.message));
  }
  return out;
}

std::string renderSweepJson(const SweepSpec& spec, const std::vector<SweepRow>& rows) {
  nlohmann::ordered_json j;
  const SweepCounts c = countRows(rows);
  j["format_version"] = 1;
  j["sweep"] = spec.path;
  j["runs"] = rows.size();
  j["ok"] = c.ok;
  j["error"] = c.error;
  j["emergency"] = c.emergency;
  j["rows"] = nlohmann::ordered_json::array();
  for (const SweepRow& r : rows) {
    const SweepVariant v = sweepVariant(spec, r.variant);
    nlohmann::ordered_json row;
    row["program"] = spec.programs[r.program];
    row["variant"] = v.label;
    row["values"] = nlohmann::ordered_json::object();
    for (size_t k = 0; k < spec.vary.size(); ++k) {
      nlohmann::ordered_json val = nlohmann::ordered_json::parse(v.values[k], nullptr, false);
      row["values"][spec.vary[k].key] = val.is_discarded() ? nlohmann::ordered_json(v.values[k]) : val;
    }
    row["status"] = sim::statusName(r.status);
    row["cycle_time_s"] = sim::jsonNumber(r.cycleTimeS);
    row["blocks"] = r.blocks;
    row["spindle_on_s"] = sim::jsonNumber(r.spindleOnS);
    row["tool_changes"] = r.toolChanges;
    row["warnings"] = r.warnings;
    row["message"] = r.status == sim::Status::Ok ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(r.message);
    j["rows"].push_back(std::move(row));
  }
  return j.dump(2) + "\n";
}

std::string renderSweepBest(const SweepSpec& spec, const std::vector<SweepRow>& rows) {
  const SweepCounts c = countRows(rows);
  std::string out =
      fmt::format("{}: {} run{} ({} program{} x {} variant{}): {} ok", support::escapeForTerminal(spec.path),
                  rows.size(), rows.size() == 1 ? "" : "s", spec.programs.size(), spec.programs.size() == 1 ? "" : "s",
                  spec.variants, spec.variants == 1 ? "" : "s", c.ok);
  if (c.error > 0) out += fmt::format(", {} error", c.error);
  if (c.emergency > 0) out += fmt::format(", {} emergency", c.emergency);
  out += "\n";
  auto label = [&](size_t variant) {
    std::string l = sweepVariant(spec, variant).label;
    return l.empty() ? std::string("(the machine as it is)") : support::escapeForTerminal(l);
  };
  for (size_t p = 0; p < spec.programs.size(); ++p) {
    const SweepRow *best = nullptr, *worst = nullptr, *failed = nullptr;
    for (const SweepRow& r : rows) {
      if (r.program != p) continue;
      if (r.status != sim::Status::Ok) {
        if (!failed) failed = &r;
        continue;
      }
      if (!best || r.cycleTimeS < best->cycleTimeS) best = &r;
      if (!worst || r.cycleTimeS > worst->cycleTimeS) worst = &r;
    }
    out += support::escapeForTerminal(spec.programs[p]) + "\n";
    if (best == worst && best) {
      out += fmt::format("  ok     {:>12} s  {}\n", sim::formatNumber(best->cycleTimeS), label(best->variant));
    } else if (best) {
      out += fmt::format("  best   {:>12} s  {}\n", sim::formatNumber(best->cycleTimeS), label(best->variant));
      out += fmt::format("  worst  {:>12} s  {}\n", sim::formatNumber(worst->cycleTimeS), label(worst->variant));
    }
    if (failed)
      out += fmt::format("  {:<6} {:>12} s  {}: {}\n", sim::statusName(failed->status),
                         sim::formatNumber(failed->cycleTimeS), label(failed->variant),
                         support::escapeForTerminal(failed->message));
  }
  return out;
}

std::string sweepJobLines(const SweepSpec& spec, const SweepOptions& opts) {
  const SimulateOptions& ro = opts.run;
  std::vector<std::string> common;
  const std::string machine = !ro.common.machinePath.empty() ? ro.common.machinePath : spec.machine;
  if (!ro.common.config.empty()) common.insert(common.end(), {"--config", ro.common.config});
  if (!machine.empty()) common.insert(common.end(), {"--machine", machine});
  if (!ro.common.dialect.empty()) common.insert(common.end(), {"--dialect", ro.common.dialect});
  if (ro.blockSkip) common.emplace_back("--block-skip");
  const SimulateOptions defaults;
  if (ro.maxSteps != defaults.maxSteps) common.insert(common.end(), {"--max-steps", std::to_string(ro.maxSteps)});
  if (ro.maxTime != defaults.maxTime) common.insert(common.end(), {"--max-time", sim::formatNumber(ro.maxTime)});
  if (ro.maxRows != defaults.maxRows) common.insert(common.end(), {"--max-rows", std::to_string(ro.maxRows)});
  std::vector<SweepVariant> variants;
  for (size_t v = 0; v < spec.variants; ++v)
    variants.push_back(sweepVariant(spec, v));
  std::string out;
  for (const std::string& program : spec.programs)
    for (const SweepVariant& v : variants) {
      std::vector<std::string> words{"isosim", program};
      words.insert(words.end(), common.begin(), common.end());
      for (const std::string& set : v.sets)
        words.insert(words.end(), {"--set", set});
      if (!v.feedOverride.empty()) words.insert(words.end(), {"--feed-override", v.feedOverride});
      if (!v.rapidOverride.empty()) words.insert(words.end(), {"--rapid-override", v.rapidOverride});
      words.insert(words.end(), {"--summary", "--format", "json"});
      for (size_t i = 0; i < words.size(); ++i)
        out.append(i ? " " : "").append(shellWord(words[i]));
      out += "\n";
    }
  return out;
}

namespace {

/// The options that have no meaning in a sweep: exit code; `format` the table's.
int checkSweepOptions(const SweepOptions& opts, Io& io, std::string& format) {
  const SimulateOptions& ro = opts.run;
  const std::pair<bool, const char*> refused[] = {
      {!ro.program.empty() || !ro.paths.empty(), "PROGRAM (the sweep file names the programs)"},
      {!ro.entry.empty(), "--entry"},
      {!ro.sets.empty(), "--set (vary the key in the sweep file, with one value to fix it)"},
      {ro.m0Wait.has_value(), "--m0-wait (vary m0_wait_s in the sweep file)"},
      {!ro.feedOverride.empty(), "--feed-override (vary feed_override in the sweep file)"},
      {!ro.rapidOverride.empty(), "--rapid-override (vary rapid_override in the sweep file)"},
      {!ro.optionalStop.empty(), "--optional-stop (vary optional_stop in the sweep file)"},
      {!ro.compare.empty() || !ro.budget.empty(), "--compare"},
      {!ro.plot.empty() || !ro.timeline.empty() || !ro.report.empty(), "--plot, --timeline and --report"},
      {ro.profile, "--profile"},
      {ro.summary, "--summary"},
      {ro.search.has_value(), "--search"},
      {ro.printMachine, "--print-machine"},
  };
  for (const auto& [given, what] : refused)
    if (given) return usageError(io, "isosim", fmt::format("--sweep cannot be combined with {}", what));
  const std::string output = ro.output == "-" ? std::string() : ro.output;
  format = ro.format.empty() ? (support::iendsWith(output, ".json") ? "json" : "csv") : ro.format;
  if (format != "csv" && format != "json")
    return usageError(io, "isosim", fmt::format("unknown format '{}' for --sweep (csv or json)", format));
  if (opts.printJobs && !ro.output.empty())
    return usageError(io, "isosim", "--sweep-jobs prints the commands on standard output: -o does not apply");
  return kExitOk;
}

/// Every value of the sweep, alone, on every base machine; then every variant whole: the
/// first that is not valid printed, exit 2.
int checkSweepValues(const SweepSpec& spec, const std::vector<BatchMachine>& bases, unsigned jobs, Io& io) {
  auto machineOf = [&](const BatchMachine& b) {
    return bases.size() == 1
               ? std::string()
               : fmt::format(" (on the machine {})", b.m.builtin ? "built in" : b.key.substr(0, b.key.find('\n')));
  };
  for (const SweepVary& vary : spec.vary)
    for (size_t i = 0; i < vary.values.size(); ++i) {
      const std::string set = vary.key + "=" + vary.values[i];
      auto refuse = [&](const std::string& why) {
        io.err << fmt::format("{}: error: {}: {}\n", support::escapeForTerminal(vary.valueWhere[i]),
                              support::escapeForTerminal(set), support::escapeForTerminal(why));
        return kExitUsage;
      };
      if (vary.key == "feed_override" && !overridePercent(vary.values[i], kMaxFeedOverride))
        return refuse(fmt::format("expected a percent of the programmed feed from 1 to {}", kMaxFeedOverride));
      if (vary.key == "rapid_override" && !overridePercent(vary.values[i], kMaxRapidOverride))
        return refuse(fmt::format("expected a percent of the rapid speed from 1 to {}", kMaxRapidOverride));
      if (isSweepRunOption(vary.key)) continue;
      for (const BatchMachine& b : bases) {
        auto changed = overriddenMachine(b.m, {set});
        if (!changed) return refuse(changed.error().message + machineOf(b));
        if (!compilesAlike(b.m, *changed))
          return refuse("it changes how the programs compile (dialect, special M functions, parameters or axis "
                        "names): a sweep compiles each program once; use a machine file per dialect");
      }
    }
  std::vector<std::string> errors(timesSaturated(spec.variants, bases.size()));
  parallelFor(errors.size(), jobs, [&](size_t i) {
    const SweepVariant v = sweepVariant(spec, i / bases.size());
    auto changed = overriddenMachine(bases[i % bases.size()].m, v.sets);
    if (!changed)
      errors[i] = fmt::format("{}: {}{}", v.label, changed.error().message, machineOf(bases[i % bases.size()]));
  });
  for (const std::string& e : errors)
    if (!e.empty()) {
      io.err << fmt::format("{}: error: the variant {}\n", support::escapeForTerminal(spec.path),
                            support::escapeForTerminal(e));
      return kExitUsage;
    }
  return kExitOk;
}

/// One run of the grid.
SweepRow runSweepRow(const SweepSpec& spec, const SweepOptions& opts, const std::vector<BatchProgram>& programs,
                     const std::vector<BatchMachine>& bases, size_t i) {
  SweepRow row;
  row.program = i / spec.variants;
  row.variant = i % spec.variants;
  const BatchProgram& p = programs[row.program];
  const SweepVariant v = sweepVariant(spec, row.variant);
  std::optional<support::Expected<machine::Machine>> changed;
  if (p.img && !v.sets.empty()) {
    changed.emplace(overriddenMachine(bases[p.base].m, v.sets));
    if (!*changed)
      throw std::logic_error("a sweep variant checked before the runs is not valid: " + changed->error().message);
  }
  const machine::Machine& m = changed ? changed->value() : bases[p.base].m;
  SimulateOptions ro = opts.run;
  ro.feedOverride = v.feedOverride;
  ro.rapidOverride = v.rapidOverride;
  static_cast<BatchRun&>(row) = runBatchProgram(p, m, ro);
  return row;
}

/// The progress line of a long sweep on a terminal (standard error): shown after the first
/// second, refreshed at most ten times a second by whichever thread finishes a run, erased at
/// the end.
class SweepProgress {
public:
  SweepProgress(std::ostream& err, bool enabled, size_t total)
      : err_(err), enabled_(enabled), total_(total), start_(Clock::now()), last_(start_) {}
  void runDone() {
    const size_t n = ++done_;
    if (!enabled_) return;
    const std::unique_lock<std::mutex> lock(mutex_, std::try_to_lock);
    if (!lock.owns_lock()) return;
    const auto now = Clock::now();
    if (now - start_ < std::chrono::seconds(1) || now - last_ < std::chrono::milliseconds(100)) return;
    last_ = now;
    err_ << fmt::format("\risosim: sweep: {} of {} runs done\x1b[K", n, total_) << std::flush;
    shown_ = true;
  }
  void erase() {
    if (shown_) err_ << "\r\x1b[K" << std::flush;
  }

private:
  using Clock = std::chrono::steady_clock;
  std::ostream& err_;
  bool enabled_;
  size_t total_;
  std::atomic<size_t> done_{0};
  std::mutex mutex_;
  Clock::time_point start_, last_;
  bool shown_ = false;
};

} // namespace

int runSweep(const SweepOptions& opts, Io& io) {
  std::string format;
  if (int rc = checkSweepOptions(opts, io, format); rc != kExitOk) return rc;
  auto spec = loadSweep(opts.file);
  if (!spec) {
    io.err << fmt::format("{}: error: {}\n", support::escapeForTerminal(spec.error().where),
                          support::escapeForTerminal(spec.error().message));
    return kExitUsage;
  }
  const unsigned jobs = opts.jobs == 0 ? hardwareJobs() : opts.jobs;
  std::vector<BatchProgram> programs;
  std::vector<BatchMachine> bases;
  if (int rc = batchMachines(spec->programs, opts.run.common, spec->machine, programs, bases, io); rc != kExitOk)
    return rc;
  if (int rc = checkSweepValues(*spec, bases, jobs, io); rc != kExitOk) return rc;
  if (opts.printJobs) {
    io.out << sweepJobLines(*spec, opts);
    return kExitOk;
  }
  const std::string output = opts.run.output == "-" ? std::string() : opts.run.output;
  if (int rc = loadBatchPrograms(programs, bases, {{"-o", output}}, {spec->path}, io); rc != kExitOk) return rc;
  std::vector<SweepRow> rows(spec->runs());
  SweepProgress progress(io.err, io.errIsTty, rows.size());
  parallelFor(rows.size(), jobs, [&](size_t i) {
    rows[i] = runSweepRow(*spec, opts, programs, bases, i);
    progress.runDone();
  });
  progress.erase();

  const std::string table = format == "json" ? renderSweepJson(*spec, rows) : renderSweepCsv(*spec, rows);
  if (!output.empty()) {
    if (support::Status w = support::writeFileAtomically(output, table); !w) {
      io.err << fmt::format("{}: error: cannot write the sweep table: {}\n", support::escapeForTerminal(output),
                            w.why());
      return kExitUsage;
    }
    io.out << renderSweepBest(*spec, rows);
  } else if (io.outIsTty && opts.run.output.empty()) {
    io.out << renderSweepBest(*spec, rows);
    io.err << "isosim: the table is not printed on a terminal: write it with -o FILE (.csv or .json)\n";
  } else {
    io.out << table;
  }
  const SweepCounts c = countRows(rows);
  return c.emergency > 0 ? kExitEmergency : c.error > 0 ? kExitErrors : kExitOk;
}

} // namespace iso::driver
