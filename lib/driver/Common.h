//! @file Common.h
//! @brief Options shared by the three tools (SPEC §8) and the plumbing to apply them.
#pragma once

#include <iosfwd>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

#include "diag/Diagnostic.h"
#include "driver/ExitCode.h"
#include "machine/Machine.h"

namespace CLI {
class App;
class Validator;
} // namespace CLI

namespace iso::driver {

/// Where a tool writes. Tools pass std::cout/std::cerr; tests pass string streams.
struct Io {
  std::ostream& out;
  std::ostream& err;
  bool outIsTty = false;
  bool errIsTty = false;
  std::istream* in = nullptr; ///< standard input, for an input "-" (nullptr: none)
};

/// How standard input is named in messages when no other name is given.
inline constexpr const char* kStdinName = "<stdin>";

/// An input "-" is standard input: read once now (at most 256 MiB) and named kStdinName in
/// `paths`, a program set of its own. False, with the error printed as exit 2, when it is given
/// twice, cannot be read or is too large.
bool readStandardInput(std::vector<std::string>& paths, Io& io, const char* tool);
/// All of `in` (standard input) as the input `name`, at most 256 MiB; nullopt with
/// `NAME: error: REASON` printed when it cannot be read or is too large.
std::optional<std::string> readStandardInputText(std::istream& in, const std::string& name, Io& io);

struct CommonOptions {
  std::string machinePath;    ///< --machine FILE ("" = built-in)
  std::string dialect;        ///< --dialect sidac|z32 ("" = the machine's)
  std::string color = "auto"; ///< --color auto|always|never
  std::string config;         ///< --config FILE ("" = isotools.toml found from the inputs)
  /// isocc, isosim: --max-diagnostics per file (-1: the settings', else 50; 0 = all). isolint
  /// has its own (LintOptions), whose default depends on the format.
  long long maxDiagnostics = -1;
  std::string settingsFile; ///< the settings file in force, set by applySettings ("" = none): an input
};

struct Settings;

/// The settings for a run whose first input is `input`: --config FILE, else the isotools.toml
/// found from `input`. Applies its machine and dialect to `opts` where the command line did
/// not give them. On an invalid file prints its error and returns false.
bool applySettings(CommonOptions& opts, const std::string& input, Settings& out, Io& io);

/// Adds --machine, --dialect, --color (and --version, and the hidden --completion SHELL) to a
/// CLI11 app.
void addCommonOptions(CLI::App& app, CommonOptions& opts, const char* toolName);

/// isocc and isosim: --max-diagnostics N into opts.maxDiagnostics.
void addMaxDiagnosticsOption(CLI::App& app, CommonOptions& opts);

/// Loads the machine (or the built-in one) and applies --dialect. On failure prints
/// "FILE: error: invalid machine file at /json/path: message" to io.err and returns nullopt.
std::optional<machine::Machine> loadMachine(const CommonOptions& opts, Io& io);
/// Prints each shown error of a machine as "WHERE: error: WHAT at KEY: MESSAGE", then
/// "WHERE: error: N more errors in the machine file" when there are more.
void printMachineErrors(Io& io, const std::string& where, const std::string& what,
                        const machine::MachineErrors& errors);

/// Colour decision: always / never / auto (a terminal and NO_COLOR unset).
bool useColor(const CommonOptions& opts, bool isTty);

/// Parses the command line. Returns -1 to go on, or the exit code: 0 after --help/--version
/// or after printing the script of --completion SHELL, 2 after a usage error (printed by
/// usageError).
int parseCommandLine(CLI::App& app, int argc, char** argv, Io& io, const char* tool);

/// Prints the one shape of usage errors, `TOOL: error: MESSAGE (run 'TOOL --help')`, and
/// returns kExitUsage.
int usageError(Io& io, const char* tool, const std::string& message);

/// Prints `PATH: error: MESSAGE` for each input that could not be read.
void printInputErrors(Io& io, const std::vector<diag::InputError>& errors);

/// Outputs never destroy inputs: an output path (not "-") that names an existing file which is
/// also one of `inputs` (same device and inode, however spelled, links followed) is a usage
/// error naming both. Two outputs naming one file are one too. Returns kExitOk or kExitUsage.
struct OutputPath {
  std::string option; ///< "-o", "--plot"
  std::string path;
};
int checkOutputs(Io& io, const char* tool, const std::vector<OutputPath>& outputs,
                 const std::vector<std::string>& inputs);

/// Installs SIGINT/SIGTERM/SIGHUP handlers that remove the temporary files of unfinished
/// outputs (the previous files stay untouched), print `TOOL: interrupted; OUTCOME` and exit
/// 128 + the signal (130, 143, 129). OUTCOME is by default "no output file was changed".
/// A SIGBUS on a mapped source (support::readSource) whose file shrank while it was read
/// prints `TOOL: error: PATH: the file shrank while it was read; OUTCOME` and exits 2.
void installInterruptHandler(const char* tool, const char* outcome = "no output file was changed");

/// CLI11 validators for numeric options: a whole number >= min, a number of seconds > 0.
CLI::Validator wholeNumberAtLeast(unsigned long long min);
CLI::Validator positiveSeconds();

/// Runs a tool body, turning any escaping exception into exit 70 with a message.
int guarded(Io& io, const char* tool, int (*body)(void*), void* ctx);

/// The same for any callable returning the exit code: guarded(io, "isosim", [&] { return ...; }).
template <class Body> int guarded(Io& io, const char* tool, Body&& body) {
  return guarded(
      io, tool, [](void* c) { return (*static_cast<std::remove_reference_t<Body>*>(c))(); }, static_cast<void*>(&body));
}

std::string versionString(const char* tool);

} // namespace iso::driver
