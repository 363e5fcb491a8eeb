//! @file Simulate.h
//! @brief isosim: run an image (or a .mpf compiled in memory) on a machine; write the trace and
//!        the summary (SPEC §8).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "driver/Common.h"
#include "image/Image.h"

namespace iso::driver {

struct SimulateOptions {
  CommonOptions common;
  std::string program;             ///< image file or .mpf source
  std::vector<std::string> paths;  ///< more sources of the program set (sources only)
  std::string entry;               ///< --entry NAME
  std::string format;              ///< csv | json; "" = json when -o ends in .json, else csv
  std::string output;              ///< -o FILE ("" = standard output)
  std::string plot;                ///< --plot FILE: an SVG of the run ("" = none)
  double dt = 0.01;                ///< --dt S
  bool summary = false;            ///< --summary
  bool profile = false;            ///< --profile
  bool blockSkip = false;          ///< --block-skip
  uint64_t maxSteps = 100'000'000; ///< --max-steps N
  double maxTime = 86'400;         ///< --max-time S
  bool printMachine = false;       ///< --print-machine
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

} // namespace iso::driver
