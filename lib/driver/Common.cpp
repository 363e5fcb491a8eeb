//! @file Common.cpp
//! @brief Shared CLI plumbing.
#include "driver/Common.h"

#include <cstdlib>
#include <exception>
#include <fstream>
#include <ostream>
#include <sstream>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

namespace iso::driver {

std::string versionString(const char* tool) {
#ifdef ISO_VERSION
  return fmt::format("{} {}", tool, ISO_VERSION);
#else
  return fmt::format("{} 0.0.0", tool);
#endif
}

void addCommonOptions(CLI::App& app, CommonOptions& opts, const char* toolName) {
  app.add_option("--machine", opts.machinePath, "Machine file (JSON, SPEC 5.1); default: the built-in machine")
      ->type_name("FILE");
  app.add_option("--dialect", opts.dialect, "Language dialect (overrides the machine file)")
      ->check(CLI::IsMember({"sidac", "z32"}).description(""))
      ->type_name("sidac|z32");
  app.add_option("--color", opts.color, "Colour the output: auto (a terminal and no NO_COLOR), always, never")
      ->check(CLI::IsMember({"auto", "always", "never"}).description(""))
      ->type_name("auto|always|never");
  app.set_version_flag("--version", versionString(toolName), "Print the version and exit");
}

std::optional<machine::Machine> loadMachine(const CommonOptions& opts, Io& io) {
  machine::Machine m;
  if (opts.machinePath.empty()) {
    m = machine::builtinMachine();
  } else {
    std::ifstream in(opts.machinePath, std::ios::binary);
    if (!in) {
      io.err << fmt::format("{}: error: cannot open machine file\n", opts.machinePath);
      return std::nullopt;
    }
    std::ostringstream ss;
    ss << in.rdbuf();
    auto r = machine::parseMachine(ss.str());
    if (!r.machine) {
      io.err << fmt::format("{}: error: invalid machine file at {}: {}\n", opts.machinePath,
                            r.error.jsonPath.empty() ? "/" : r.error.jsonPath, r.error.message);
      return std::nullopt;
    }
    m = std::move(*r.machine);
  }
  if (!opts.dialect.empty()) {
    auto d = machine::parseDialect(opts.dialect);
    if (d) m.dialect = *d;
    if (m.dialect == machine::Dialect::Z32)
      for (const auto& a : m.axes)
        if (a.letter == 'S' || a.letter == 'T') {
          io.err << fmt::format("{}: error: invalid machine file at /axes: axis name '{}' is an address in the z32 "
                                "dialect\n",
                                opts.machinePath.empty() ? "<built-in>" : opts.machinePath, a.letter);
          return std::nullopt;
        }
  }
  return m;
}

int parseCommandLine(CLI::App& app, int argc, char** argv, Io& io, const char* tool) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    io.out << app.help();
    return kExitOk;
  } catch (const CLI::CallForVersion&) {
    io.out << app.version() << "\n";
    return kExitOk;
  } catch (const CLI::ParseError& e) {
    io.err << fmt::format("{}: error: {}\n{}: run '{} --help' for the options\n", tool, e.what(), tool, tool);
    return kExitUsage;
  }
  return -1;
}

bool useColor(const CommonOptions& opts, bool isTty) {
  if (opts.color == "always") return true;
  if (opts.color == "never") return false;
  const char* nc = std::getenv("NO_COLOR");
  return isTty && !(nc && *nc);
}

int guarded(Io& io, const char* tool, int (*body)(void*), void* ctx) {
  try {
    return body(ctx);
  } catch (const std::exception& e) {
    io.err << fmt::format("{}: internal error: {} (please report this bug)\n", tool, e.what());
  } catch (...) {
    io.err << fmt::format("{}: internal error: unknown exception (please report this bug)\n", tool);
  }
  return kExitInternal;
}

} // namespace iso::driver
