//! @file Common.h
//! @brief Options shared by the three tools (SPEC §8) and the plumbing to apply them.
#pragma once

#include <iosfwd>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

#include "driver/ExitCode.h"
#include "machine/Machine.h"

namespace CLI {
class App;
}

namespace iso::driver {

/// Where a tool writes. Tools pass std::cout/std::cerr; tests pass string streams.
struct Io {
  std::ostream& out;
  std::ostream& err;
  bool outIsTty = false;
  bool errIsTty = false;
};

struct CommonOptions {
  std::string machinePath;          ///< --machine FILE ("" = built-in)
  std::string dialect;              ///< --dialect sidac|z32 ("" = the machine's)
  std::string color = "auto";       ///< --color auto|always|never
};

/// Adds --machine, --dialect, --color (and --version) to a CLI11 app.
void addCommonOptions(CLI::App& app, CommonOptions& opts, const char* toolName);

/// Loads the machine (or the built-in one) and applies --dialect. On failure prints
/// "FILE: error: invalid machine file at /json/path: message" to io.err and returns nullopt.
std::optional<machine::Machine> loadMachine(const CommonOptions& opts, Io& io);

/// Colour decision: always / never / auto (a terminal and NO_COLOR unset).
bool useColor(const CommonOptions& opts, bool isTty);

/// Parses the command line. Returns -1 to go on, or the exit code: 0 after --help/--version,
/// 2 after a usage error (printed as "TOOL: error: ..." with a hint to --help).
int parseCommandLine(CLI::App& app, int argc, char** argv, Io& io, const char* tool);

/// Runs a tool body, turning any escaping exception into exit 70 with a message.
int guarded(Io& io, const char* tool, int (*body)(void*), void* ctx);

/// The same for any callable returning the exit code: guarded(io, "isosim", [&] { return ...; }).
template <class Body>
int guarded(Io& io, const char* tool, Body&& body) {
  return guarded(io, tool, [](void* c) { return (*static_cast<std::remove_reference_t<Body>*>(c))(); },
                 static_cast<void*>(&body));
}

std::string versionString(const char* tool);

} // namespace iso::driver
