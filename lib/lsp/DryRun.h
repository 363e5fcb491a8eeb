//! @file DryRun.h
//! @brief The cycle time beside the code: the language server dry-runs a document's program
//!        as isosim would (the machine and settings isolint's policy finds for it), with the
//!        time profile per line, within a wall-clock budget, and stops when the editor sends
//!        something (the run is then done again later).
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "driver/Common.h"
#include "sim/TimeProfile.h"
#include "sim/Trace.h"

namespace iso::lsp {

/// initializationOptions.cycleTime.
struct DryRunOptions {
  bool enabled = true;
  double budgetSeconds = 5;           ///< wall-clock seconds a dry run may take
  bool inlayHints = true;             ///< a hint at the end of each line that ran, with its time
  uint32_t inlayHintsMaxLines = 5000; ///< no hints in a document with more lines
};

struct DryRun {
  enum class State : uint8_t {
    Ok,
    Error,      ///< a runtime error
    Emergency,  ///< an emergency
    Failed,     ///< it could not run: errors in the program set, a missing file, a bad machine file
    OverBudget, ///< stopped at the budget
    Cancelled,  ///< stopped because the editor sent a message
  };
  State state = State::Failed;
  std::string program; ///< the program's path
  std::string folder;  ///< the folder its image's file names are relative to
  std::string title;   ///< "cycle 39.276 s · 148 blocks", or what went wrong
  sim::Summary summary;
  sim::TimeProfile profile;
  uint64_t statements = 0;
};

/// "ok", "error", "emergency", "failed", "over budget", "cancelled".
const char* dryRunStateName(DryRun::State s);

/// Runs `program` (a .mpf main or semi-automatic program, from disk) with the policy's
/// --config/--machine/--dialect (`policy` may be null: the settings found from the program and
/// the built-in machine). `cancel` is asked every few thousand statements.
DryRun dryRun(const std::string& program, const driver::CommonOptions* policy, const DryRunOptions& opts,
              const std::function<bool()>& cancel);

/// "1.234 s" under a minute, "1:02.3" (m:ss.s) from a minute, "1:02:03.4" from an hour.
std::string readableSeconds(double s);

} // namespace iso::lsp
