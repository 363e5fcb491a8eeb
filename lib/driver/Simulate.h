//! @file Simulate.h
//! @brief isosim: run an image (or a .mpf compiled in memory) on a machine; write the trace and
//!        the summary (SPEC §8).
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "driver/Common.h"
#include "image/Image.h"
#include "image/ImageVerifier.h"
#include "sim/Run.h"

namespace iso::driver {

struct SimulateOptions {
  CommonOptions common;
  std::string program;             ///< image file or .mpf source
  std::vector<std::string> paths;  ///< more sources of the program set (sources only)
  std::string entry;               ///< --entry NAME
  std::string format;              ///< csv | json; "" = json when -o ends in .json, else csv
  std::string output;              ///< -o FILE ("" = standard output)
  std::string plot;                ///< --plot FILE: an SVG of the run ("" = none)
  std::string plotPlane;           ///< --plot-plane xy|zx|yz ("" = the plane of the program)
  std::string timeline;            ///< --timeline FILE: trace-event JSON of the run ("" = none)
  std::string compare;             ///< --compare OLD: compare with another program ("" = none)
  std::string budget;              ///< --budget 2%|1.5s: with --compare, exit 1 past it ("" = none)
  std::string report;              ///< --report FILE: a self-contained HTML page ("" = none)
  double dt = 0.01;                ///< --dt S
  bool summary = false;            ///< --summary
  bool quiet = false;              ///< --quiet: no progress line, no terminal hint
  bool profile = false;            ///< --profile
  bool blockSkip = false;          ///< --block-skip
  uint64_t maxSteps = 100'000'000; ///< --max-steps N
  double maxTime = 86'400;         ///< --max-time S
  uint64_t maxRows = 20'000'000;   ///< --max-rows N
  size_t profileLines = 50;        ///< --profile-lines N (0 = all)
  bool printMachine = false;       ///< --print-machine
  std::vector<std::string> sets;   ///< --set KEY=VALUE: machine-file keys changed for this run
  std::optional<double> m0Wait;    ///< --m0-wait S: m0_wait_s for this run
  std::string feedOverride;        ///< --feed-override P: percent of the programmed feed, 1..1000 ("" = 100)
  std::string rapidOverride;       ///< --rapid-override P: percent of each axis's G00 speed, 1..100 ("" = 100)
  std::string optionalStop;        ///< --optional-stop on|off: optional_stop for this run ("" = the machine's)
  /// --search TEXT: start the cycle at the line TEXT names.
  std::optional<std::string> search;
};

/// A block search to resolve while the program loads (--search TEXT): the line of the entry
/// program that TEXT names (dialect z32, TEXT shaped as a GO target: the line the GO rule finds;
/// else the label TEXT, any case), as the simulator's search option.
struct SearchRequest {
  std::string text;
  std::optional<sim::SimOptions::Search> found; ///< set by loadProgram
};

/// The isosim tool body. Output contract:
/// - `--print-machine`: the machine (built-in, or --machine) as JSON on stdout.
/// - `--summary`: no trace; the summary (text, or JSON with --format json) on stdout, or in
///   the -o file.
/// - `--plot FILE`: also the SVG plot of the run (sim/SvgPlot.h), in any mode but
///   --print-machine, written
///   when the run is over whatever its outcome (up to the instant it stopped); not when the
///   program does not run (errors, refused before it starts).
/// - `--profile`: no trace unless -o; the summary followed by where the time went
///   (sim/TimeProfile.h) on stdout (or in the -o file with --summary): a text table, or one
///   JSON object {"summary": …, "profile": …} with --format json.
/// - `-o FILE`: the trace in FILE; the summary on stdout.
/// - otherwise: the trace on stdout and the summary, as text, on stderr.
/// Runtime errors and emergencies are also reported on stderr as "file:line: error: …".
/// Exit codes: 0 ok, 1 runtime error / program with errors, 2 usage / input errors,
/// 3 emergency (70 internal errors come from `guarded`).
int runSimulate(const SimulateOptions& opts, Io& io);

/// A run prepared as isosim prepares it, for the debugger (isosim --dap, --single-block): the
/// settings, the machine with the overrides, the program loaded and verified, the simulator's
/// options.
struct PreparedRun {
  std::optional<machine::Machine> machine;
  std::optional<image::VerifiedImage> image;
  sim::SimOptions options;
  std::string entry;                  ///< the entry point run ("" = the main program)
  std::vector<std::string> overrides; ///< the summary's overrides
};

/// Prepares the run `opts` describes (PROGRAM, PATHS, --machine, --config, --dialect, --entry,
/// --search, the overrides, the limits; no outputs). Returns kExitOk; else the exit code with
/// the reason (and a program's diagnostics) printed to io.err.
int prepareRun(const SimulateOptions& opts, Io& io, PreparedRun& out);

inline constexpr int kMaxFeedOverride = 1000; ///< percent: --feed-override runs feed moves at most 10 times faster
inline constexpr int kMaxRapidOverride = 100; ///< percent: a rapid already runs at max_velocity

/// --feed-override / --rapid-override P (a number, optionally with %): P from 1 to `max`, else nullopt.
std::optional<double> overridePercent(const std::string& text, double max);

/// The simulator's options of a run: --dt, --block-skip, --max-steps, --max-time, --max-rows and
/// `entry`.
sim::SimOptions simOptions(const SimulateOptions& opts, const std::string& entry);
/// The summary's overrides: the machine-file keys changed (--set and the options made of it),
/// then the feed and rapid overrides that are not 100%.
std::vector<std::string> summaryOverrides(const SimulateOptions& opts, const sim::SimOptions& so);

/// Loads PROGRAM (an image; or a source program set with PATHS, compiled in memory) for a run on
/// `m`, verified (image::verifyImage) either way. `checkInputs` gets the files read (before anything is written) and
/// returns kExitOk or the exit code of its refusal. A semi-automatic program named as PROGRAM sets `entry` when it is
/// empty. Returns kExitOk; else the exit code with the reason printed, and for a program with
/// errors (diagnostics printed) kExitErrors with `compileError` set to the summary's message.
/// With `search`, its line is resolved in the entry program (`entry`) and its code offset set;
/// TEXT naming no line of it, and an image as PROGRAM, are usage errors (kExitUsage).
int loadProgram(const std::string& program, const std::vector<std::string>& paths, const CommonOptions& common,
                const Settings& settings, const machine::Machine& m, Io& io,
                const std::function<int(const std::vector<std::string>&)>& checkInputs,
                std::optional<image::VerifiedImage>& img, std::string& entry, std::string& compileError,
                SearchRequest* search = nullptr);

} // namespace iso::driver
