//! @file Lint.h
//! @brief isolint: lint a program set and render the diagnostics (SPEC §7, §8).
#pragma once

#include <string>
#include <vector>

#include "diag/Diagnostic.h"
#include "driver/Common.h"
#include "frontend/ProgramSet.h"

namespace iso::driver {

struct LintOptions {
  CommonOptions common;
  std::vector<std::string> paths;
  std::string format = "text";          ///< text | json | sarif
  std::vector<std::string> disable;     ///< codes or names
  bool werror = false;
  unsigned jobs = 0;                    ///< 0 = hardware concurrency
};

int runLint(const LintOptions& opts, Io& io);

/// The diagnostics a user sees: only files to report, minus --disable and inline suppressions;
/// with werror, warnings become errors. Shared by isolint and isocc.
std::vector<diag::Diagnostic> visibleDiagnostics(const frontend::ProgramSet& set,
                                                 const std::vector<diag::Code>& disabled, bool werror);

/// Resolves --disable values; unknown ones are reported to io.err and make it return false.
bool resolveCodes(const std::vector<std::string>& names, std::vector<diag::Code>& out, Io& io, const char* tool);

/// Writes diagnostics in the text format (with the count line) to `os`.
void printTextDiagnostics(const std::vector<diag::Diagnostic>& diags, const frontend::ProgramSet& set,
                          std::ostream& os, bool color, bool countLine);

} // namespace iso::driver
