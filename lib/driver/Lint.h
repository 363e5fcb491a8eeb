//! @file Lint.h
//! @brief isolint: lint a program set and render the diagnostics (SPEC §7, §8).
#pragma once

#include <functional>
#include <iosfwd>
#include <string>
#include <vector>

#include "diag/Diagnostic.h"
#include "diag/DiagnosticEngine.h"
#include "driver/Common.h"
#include "driver/Sources.h"
#include "frontend/ProgramSet.h"

namespace iso::driver {

struct LintOptions {
  CommonOptions common;
  std::vector<std::string> paths;
  std::string format = "text";      ///< text | json | sarif
  std::vector<std::string> disable; ///< codes or names (comma lists allowed)
  std::vector<std::string> select;  ///< --select: only these codes or names (comma lists allowed)
  bool statistics = false;          ///< --statistics: a count per code instead of the diagnostics
  std::string baseline;             ///< --baseline FILE: write it when absent, else leave out what it lists
  bool werror = false;
  unsigned jobs = 0;             ///< 0 = hardware concurrency
  long long maxDiagnostics = -1; ///< per file; -1 = the format's default (text 50, else all); 0 = all
  std::string explain;           ///< --explain CODE|NAME: print the rule's documentation
  std::string stdinFilename;     ///< --stdin-filename PATH: the input "-" is standard input, named PATH
  bool fix = false;              ///< --fix: apply the fixes of the diagnostics shown, then lint again
  bool diff = false;             ///< --diff: print what --fix would change, change nothing
};

/// Runs isolint. `in` is standard input (read when a PATH is "-" with --stdin-filename).
int runLint(const LintOptions& opts, Io& io, std::istream* in = nullptr);

/// isolint's program sets (SPEC §1): every folder is a set of its own. A folder argument is
/// walked recursively (hidden folders and links to folders are skipped) and each folder in it
/// that holds .mpf/.spf files is one set; explicit files are grouped by their folder. Sets come
/// in the order of their first path on the command line. Missing paths go to `errors`.
/// Files for which `excluded` is true are not named (they stay siblings that resolve calls).
std::vector<std::vector<std::string>> groupProgramSets(const std::vector<std::string>& paths,
                                                       std::vector<diag::InputError>& errors,
                                                       const std::function<bool(const std::string&)>& excluded = {});

/// The default per-file limit of text output (SPEC §8).
inline constexpr size_t kDefaultTextMaxDiagnostics = 50;

/// What a user sees of set.diags, applied in place: only files to report, minus `disabled`
/// and inline suppressions; with werror, warnings become errors. With `keepSilencedErrors`
/// (isocc, isosim: an error prevents compiling whatever isolint is told), an error silenced
/// inline stays, with a note saying so.
using DiagnosticFilter = diag::DiagnosticPolicy;
void filterDiagnostics(frontend::ProgramSet& set, const DiagnosticFilter& filter);

struct Settings;
/// The filter of isocc and isosim: errors always stay (silenced ones with a note); the
/// settings' disable/enable and overrides apply to the rest.
DiagnosticFilter settingsFilter(const frontend::ProgramSet& set, const Settings& settings);

/// Resolves --disable values (each may be a comma list); unknown ones are a usage error
/// printed to io.err, and make it return false.
bool resolveCodes(const std::vector<std::string>& names, std::vector<diag::Code>& out, Io& io, const char* tool);

/// The number of files whose diagnostics are reported.
size_t reportedFiles(const frontend::ProgramSet& set);

/// isocc and isosim: the diagnostics of a loaded program set as isolint's text shows them, to
/// io.err: at most common.maxDiagnostics per file (-1: the settings' max-diagnostics, else 50; 0 = all),
/// then the count line. Prints nothing when there are none.
void printToolDiagnostics(const frontend::ProgramSet& set, const CommonOptions& common, const Settings& settings,
                          Io& io);

/// Writes `diags` (pointing into `sources`) in the text format to `os`: at most `maxPerFile` per
/// file (0 = all), then the count line of `files` files when `countLine`.
void printTextDiagnostics(const std::vector<diag::Diagnostic>& diags, const diag::SourceManager& sources, size_t files,
                          std::ostream& os, bool color, bool countLine, size_t maxPerFile = 0);

} // namespace iso::driver
