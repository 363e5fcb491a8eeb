//! @file Sweep.h
//! @brief isosim --sweep FILE.toml: a grid of programs × machine variants run on several
//!        threads, one table of the results (CSV or JSON), the best and worst rows on a
//!        terminal; --sweep-jobs: one isosim command per run for an outside runner.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "driver/Batch.h"
#include "driver/Common.h"
#include "driver/Simulate.h"
#include "sim/Trace.h"
#include "support/Expected.h"

namespace iso::driver {

/// The most runs a sweep may have (programs × variants); a larger grid is refused.
inline constexpr size_t kMaxSweepRuns = 100'000;

/// One [[vary]] table: a key and the values it takes, in order.
struct SweepVary {
  std::string key;                       ///< a machine-file key path, or feed_override / rapid_override
  std::vector<std::string> values;       ///< each as the VALUE of --set KEY=VALUE (or of the option)
  std::string where;                     ///< "FILE:LINE:COL" of the table (for errors about the key)
  std::vector<std::string> valueWhere{}; ///< "FILE:LINE:COL" of each value (a range: the range)
};

/// A sweep file, read and checked (not yet against a machine).
struct SweepSpec {
  std::string path;                  ///< the sweep file
  std::vector<std::string> programs; ///< as resolved from the sweep file's folder
  std::string machine;               ///< machine file resolved the same way ("" = none)
  std::vector<SweepVary> vary;
  size_t variants = 1; ///< the product of the vary lists' sizes
  size_t runs() const { return programs.size() * variants; }
};

/// The keys a sweep varies that are run options and not machine-file keys.
bool isSweepRunOption(std::string_view key);

/// Reads sweep text (TOML). Keys: `programs` (array of paths, relative to the file's folder),
/// `machine` (a path, optional), `[[vary]]` tables with `key` and either `values` (numbers,
/// booleans or strings) or `range = {from, to, step}`. Errors: `where` is "FILE:LINE:COL".
support::Expected<SweepSpec> parseSweep(std::string_view text, const std::string& path);
/// parseSweep of the file PATH (at most 16 MiB); `where` "PATH" when it cannot be read.
support::Expected<SweepSpec> loadSweep(const std::string& path);

/// One variant of the grid: index i counts with the last vary list changing fastest.
struct SweepVariant {
  std::vector<std::string> values; ///< one per vary list
  std::vector<std::string> sets;   ///< the machine changes, "KEY=VALUE"
  std::string feedOverride;        ///< "" = 100%
  std::string rapidOverride;       ///< "" = 100%
  std::string label;               ///< "axes.X.max_accel=2000 feed_override=80" ("" = no change)
};
SweepVariant sweepVariant(const SweepSpec& spec, size_t i);

/// The result of one run of the grid: its place in the grid and the run's outcome.
struct SweepRow : BatchRun {
  size_t program = 0;
  size_t variant = 0;
};

/// The table: a header, then one row per run in grid order (program, then variant). Columns:
/// program, variant, each varied key, status, cycle_time_s, blocks, spindle_on_s,
/// tool_changes, warnings, message.
std::string renderSweepCsv(const SweepSpec& spec, const std::vector<SweepRow>& rows);
/// {"format_version": 1, "sweep": FILE, "runs": N, "ok": N, "error": N, "emergency": N,
///  "rows": [{"program", "variant", "values": {KEY: VALUE}, "status", "cycle_time_s", ...}]}
/// (schemas/isosim-sweep.schema.json); a row's message is null when its status is ok.
std::string renderSweepJson(const SweepSpec& spec, const std::vector<SweepRow>& rows);
/// The terminal view: the counts, then per program its best and worst ok variant by cycle
/// time, and its first failed run.
std::string renderSweepBest(const SweepSpec& spec, const std::vector<SweepRow>& rows);

/// A word as a POSIX shell reads it back: unchanged when it has only safe characters, else
/// in single quotes.
std::string shellWord(std::string_view word);

struct SweepOptions {
  SimulateOptions run;    ///< --machine, --dialect, --config, -o, --format, --block-skip, --max-*
  std::string file;       ///< --sweep FILE
  unsigned jobs = 0;      ///< -j N (0 = every core)
  bool printJobs = false; ///< --sweep-jobs
};

/// The isosim command lines of every run, one a line, in table order (--sweep-jobs).
std::string sweepJobLines(const SweepSpec& spec, const SweepOptions& opts);

/// isosim --sweep. Every program is loaded and compiled once, and every value checked against
/// each machine, before any run. Output: -o FILE (csv or json by --format or its name) and the
/// best and worst rows on stdout; no -o: the best and worst rows on a terminal, else the table
/// on stdout. Exit codes: 0 every run ok, 1 some run ended in error (none in emergency), 3
/// some run ended in emergency, 2 usage, unreadable input or an invalid sweep file or value.
int runSweep(const SweepOptions& opts, Io& io);

} // namespace iso::driver
