//! @file Run.h
//! @brief isosim's public run API: runs a verified image on a machine in continuous,
//!        event-driven time (SPEC §4–§6) and reports samples, events and the summary to a
//!        TraceSink.
//!
//! Time advances only when a program thread waits (block time, dwell, M sequence, blocking
//! motion, §6.2 real-time read, M0, end of program). Axis positions are closed-form functions
//! of time (Motion.h), sampled at k·dt. WHEN anticipations (§4.4) are watched between events
//! and fire at the first instant their condition holds (bisection to adjacent doubles); each
//! body runs as its own thread. Deterministic: no wall clock, no unordered iteration.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "image/Image.h"
#include "image/ImageVerifier.h"
#include "machine/Machine.h"
#include "sim/TimeProfile.h"
#include "sim/Trace.h"

namespace iso::sim {

class DebugHook;

struct SimOptions {
  double dt = 0.01;                ///< sample period of the trace (s, > 0)
  bool blockSkip = false;          ///< skip `/` lines (StmtSkip)
  uint64_t maxSteps = 100'000'000; ///< statements a run may execute (SPEC §6.3)
  double maxTime = 86'400;         ///< simulated seconds a run may reach (SPEC §6.3)
  /// Sample rows a run may write (--max-rows): the run that needs one more stops with an
  /// error at that row's time, the rows so far written.
  uint64_t maxRows = 20'000'000;
  std::string entry; ///< "" = the main program; else a SEMI name or file stem
  /// --feed-override: the share of the programmed feed (F, Fa) feed moves run at (1 = 100%);
  /// the axes' max_velocity still caps the result. Rapids, dwells and M times are unchanged.
  double feedScale = 1.0;
  /// --rapid-override: the share of each axis's max_velocity a rapid (G00) runs at (1 = 100%).
  double rapidScale = 1.0;
  /// Block search (--search): the lines before the found one run in search mode (Search.cpp).
  struct Search {
    uint32_t offset = 0; ///< code offset of the found line's stmt (or stmt.skip) instruction
    SearchInfo where;    ///< the summary's `search`
  };
  std::optional<Search> search;
  TimeProfile* profile = nullptr; ///< when set, filled with where the time went (--profile)
  /// When set, called now and then (every 16 scheduler rounds) with the simulated
  /// time, the blocks (the summary's) and the lines executed so far: the driver's progress line.
  std::function<void(double simTime, uint64_t blocks, uint64_t lines)> progress;
  /// When set, a debugger watches the run (Debug.h): it is called before each statement, at
  /// the times it asks for and at a fault. It never changes the run, but it may end it.
  DebugHook* debug = nullptr;
};

/// Why a run could not start (the driver exits 2 for all of them).
enum class SetupError : uint8_t {
  None,
  InvalidImage, ///< the machine has no or too many axes (an image is verified before: VerifiedImage)
  AxisMissing,  ///< the image uses an axis the machine does not have
  UnknownEntry, ///< --entry names no entry point
};

struct SimResult {
  SetupError setupError = SetupError::None;
  std::string setupMessage; ///< e.g. "the program uses axis Q, which machine 'default' does not have"
  Summary summary;          ///< valid when setupError == None
};

/// Runs `img` on `m`. `sink` may be null (summary only). Never prints; never throws for program
/// errors (they end the run with status error/emergency). Throws only on internal errors. The
/// image is trusted: only image::verifyImage makes a VerifiedImage.
SimResult simulate(const image::VerifiedImage& img, const machine::Machine& m, const SimOptions& opts,
                   TraceSink* sink = nullptr);

/// The names --entry accepts, in image order: the main program's stem, then each SEMI name
/// (as text: image::printableName).
std::vector<std::string> entryNames(const image::Image& img);

/// The procedure index of the entry point that `entry` names ("" = the main program), as
/// simulate() selects it; nullopt when it names none.
std::optional<uint32_t> entryProc(const image::Image& img, const std::string& entry);

} // namespace iso::sim
