//! @file DebugAdapter.h
//! @brief `isosim --dap`: a Debug Adapter Protocol server over a stream pair. One session
//!        runs one program: launch loads it (as isosim does), configurationDone starts the run,
//!        and the run stops at breakpoints (lines, conditions, hit counts, subprograms,
//!        simulated times), steps (one statement; into and out of calls), pauses and faults.
//!        Single-threaded: the run calls back into the session at each statement, and the
//!        session reads the client's messages there while the run is stopped.
#pragma once

#include <iosfwd>
#include <string>

namespace iso::dap {

struct AdapterOptions {
  /// While the program runs, look for messages (pause, breakpoints) every so many statements:
  /// the file descriptor of the input, polled without waiting (-1: never; tests that write
  /// every message first).
  int pollFd = -1;
  /// Where relative paths of a launch without `cwd` start ("": the working directory).
  std::string baseDir;
};

/// Serves one debug session on `in`/`out` until disconnect or the end of the input. Returns
/// the process exit code (0; 1 when the input ended without a disconnect).
int runDebugAdapter(std::istream& in, std::ostream& out, const AdapterOptions& opts = {});

} // namespace iso::dap
