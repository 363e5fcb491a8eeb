//! @file ExitCode.h
//! @brief The one exit-code table of SPEC §8, shared by all three tools.
#pragma once

namespace iso::driver {

enum ExitCode : int {
  kExitOk = 0,        ///< success (isolint: no error-severity diagnostics)
  kExitErrors = 1,    ///< the program has errors, or isosim hit a runtime error
  kExitUsage = 2,     ///< usage error, unreadable file, invalid machine file, invalid image
  kExitEmergency = 3, ///< isosim: emergency (soft limit, axis re-programmed while moving)
  kExitInternal = 70, ///< internal error (a bug)
};

} // namespace iso::driver
