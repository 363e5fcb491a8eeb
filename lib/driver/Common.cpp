//! @file Common.cpp
//! @brief Shared CLI plumbing.
#include "driver/Common.h"

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <ostream>
#include <sstream>
#include <streambuf>

#include <charconv>
#include <cmath>
#include <csignal>
#include <signal.h>

#include <unistd.h>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "driver/Settings.h"
#include "driver/ShellCompletion.h"
#include "support/File.h"
#include "support/SourceText.h"
#include "support/Text.h"
#include "support/Version.h"

namespace iso::driver {

std::string versionString(const char* tool) { return fmt::format("{} {}", tool, kVersion); }

void addCommonOptions(CLI::App& app, CommonOptions& opts, const char* toolName) {
  addCompletionOption(app); // first: see Completion.h
  app.add_option("--machine", opts.machinePath, "Machine file (JSON, see isosim(1)); default: the built-in machine")
      ->type_name("FILE");
  app.add_option("--config", opts.config,
                 "Settings file (TOML); default: isotools.toml in the input's folder or the nearest above")
      ->type_name("FILE");
  app.add_option("--dialect", opts.dialect, "Language dialect (overrides the machine file)")
      ->check(CLI::IsMember({"sidac", "z32"}).description(""))
      ->type_name("sidac|z32");
  app.add_option("--color", opts.color, "Colour the output: auto (a terminal and no NO_COLOR), always, never")
      ->check(CLI::IsMember({"auto", "always", "never"}).description(""))
      ->type_name("auto|always|never");
  app.set_version_flag("--version", versionString(toolName), "Print the version and exit");
}

std::optional<std::string> readStandardInputText(std::istream& in, const std::string& name, Io& io) {
  auto text = support::readStreamBounded(in, name);
  if (text) return std::move(*text);
  io.err << fmt::format("{}: error: {}\n", support::escapeForTerminal(name), text.error().message);
  return std::nullopt;
}

bool readStandardInput(std::vector<std::string>& paths, Io& io, const char* tool) {
  const auto dashes = std::count(paths.begin(), paths.end(), "-");
  if (dashes == 0) return true;
  if (dashes > 1) {
    usageError(io, tool, "standard input ('-') can be read only once");
    return false;
  }
  if (!io.in) {
    usageError(io, tool, "no standard input to read '-' from");
    return false;
  }
  auto text = readStandardInputText(*io.in, kStdinName, io);
  if (!text) return false;
  support::setStreamInput(kStdinName, std::move(*text));
  std::replace(paths.begin(), paths.end(), std::string("-"), std::string(kStdinName));
  return true;
}

void addMaxDiagnosticsOption(CLI::App& app, CommonOptions& opts) {
  app.add_option("--max-diagnostics", opts.maxDiagnostics,
                 "Show at most N diagnostics of the program per file (default: 50; 0 = all)")
      ->type_name("N")
      ->check(wholeNumberAtLeast(0));
}

bool applySettings(CommonOptions& opts, const std::string& input, Settings& out, Io& io) {
  std::string path = opts.config.empty() ? findSettings(input) : opts.config;
  out = Settings{};
  if (path.empty()) return true;
  std::string error;
  if (!loadSettings(path, out, error)) {
    io.err << support::escapeForTerminal(error) << "\n";
    return false;
  }
  if (opts.machinePath.empty()) opts.machinePath = out.machine;
  if (opts.dialect.empty()) opts.dialect = out.dialect;
  opts.settingsFile = path;
  return true;
}

void printMachineErrors(Io& io, const std::string& where, const std::string& what,
                        const machine::MachineErrors& errors) {
  for (const auto& e : errors.shown)
    io.err << fmt::format("{}: error: {} at {}: {}\n", where, what,
                          e.where.empty() ? "/" : support::escapeForTerminal(e.where),
                          support::escapeForTerminal(e.message));
  if (errors.count > errors.shown.size())
    io.err << fmt::format("{}: error: {} more errors in the machine file\n", where, errors.count - errors.shown.size());
}

std::optional<machine::Machine> loadMachine(const CommonOptions& opts, Io& io) {
  machine::Machine m;
  if (opts.machinePath.empty()) {
    m = machine::builtinMachine();
  } else {
    bool whole = false;
    const auto text = support::readFilePrefix(opts.machinePath, machine::kMaxMachineFileBytes + 1, whole);
    const std::string shownPath = support::escapeForTerminal(opts.machinePath);
    if (!text) {
      io.err << fmt::format("{}: error: cannot open the machine file: {}\n", shownPath, text.error().message);
      return std::nullopt;
    }
    if (text->size() > machine::kMaxMachineFileBytes) {
      io.err << fmt::format("{}: error: the machine file is larger than {} MiB\n", shownPath,
                            machine::kMaxMachineFileBytes >> 20);
      return std::nullopt;
    }
    machine::MachineErrors errors;
    auto r = machine::parseMachine(*text, errors);
    if (!r) {
      printMachineErrors(io, shownPath, "invalid machine file", errors);
      return std::nullopt;
    }
    m = std::move(*r);
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

namespace {
/// "; did you mean '--max-time'?" for each unknown option of `extras` near an option of `app`
/// (a hidden option is never suggested).
std::string optionHints(const CLI::App& app, const std::vector<std::string>& extras) {
  std::vector<std::string> names;
  for (const CLI::Option* o : app.get_options()) {
    if (o->get_group().empty()) continue;
    for (const auto& l : o->get_lnames())
      names.push_back("--" + l);
    for (const auto& n : o->get_snames())
      names.push_back("-" + n);
  }
  const std::vector<std::string_view> candidates(names.begin(), names.end());
  std::string hints;
  for (const auto& extra : extras) {
    if (extra.size() < 2 || extra[0] != '-') continue;
    const std::string_view word = std::string_view(extra).substr(0, extra.find('='));
    const std::string_view near = support::closestMatch(word, candidates);
    if (!near.empty())
      hints += fmt::format("; {}did you mean '{}'?", extras.size() > 1 ? fmt::format("for '{}' ", word) : "", near);
  }
  return hints;
}
} // namespace

int parseCommandLine(CLI::App& app, int argc, char** argv, Io& io, const char* tool) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    io.out << app.help();
    return kExitOk;
  } catch (const CLI::CallForVersion&) {
    io.out << app.version() << "\n";
    return kExitOk;
  } catch (const CLI::ExtrasError& e) {
    return usageError(io, tool, e.what() + optionHints(app, app.remaining()));
  } catch (const CLI::ParseError& e) {
    return usageError(io, tool, e.what());
  }
  return handleCompletionOption(app, tool, io);
}

int usageError(Io& io, const char* tool, const std::string& message) {
  io.err << fmt::format("{}: error: {} (run '{} --help')\n", tool, support::escapeForTerminal(message), tool);
  return kExitUsage;
}

void printInputErrors(Io& io, const std::vector<diag::InputError>& errors) {
  for (const auto& e : errors)
    io.err << fmt::format("{}: error: {}\n", support::escapeForTerminal(e.path), e.message);
}

namespace {
/// The same spelling once made absolute and normal (for files that do not exist yet).
bool samePath(const std::string& a, const std::string& b) {
  std::error_code ec;
  return std::filesystem::absolute(a, ec).lexically_normal() == std::filesystem::absolute(b, ec).lexically_normal();
}
} // namespace

int checkOutputs(Io& io, const char* tool, const std::vector<OutputPath>& outputs,
                 const std::vector<std::string>& inputs) {
  std::vector<std::pair<support::FileId, const std::string*>> ids;
  for (const auto& in : inputs)
    if (auto id = support::fileId(in)) ids.emplace_back(*id, &in);
  for (size_t i = 0; i < outputs.size(); ++i) {
    const OutputPath& o = outputs[i];
    if (o.path.empty() || o.path == "-") continue;
    auto id = support::fileId(o.path);
    for (size_t k = 0; k < i; ++k)
      if (samePath(outputs[k].path, o.path) || (id && support::fileId(outputs[k].path) == id))
        return usageError(
            io, tool,
            fmt::format("{} {} and {} {} name the same file", outputs[k].option, outputs[k].path, o.option, o.path));
    if (!id) continue;
    for (const auto& [inId, in] : ids)
      if (inId == *id)
        return usageError(
            io, tool,
            fmt::format("{} {} would overwrite the input {}; choose another output file", o.option, o.path, *in));
  }
  return kExitOk;
}

namespace {
const char* gInterruptedTool = "isotools";
const char* gInterruptOutcome = "no output file was changed";

/// A message put together without allocating, for the signal handlers.
struct HandlerMessage {
  char text[512];
  size_t n = 0;
  HandlerMessage& operator<<(const char* s) {
    while (*s && n < sizeof text - 1)
      text[n++] = *s++;
    return *this;
  }
  void write() const {
    ssize_t w = ::write(2, text, n);
    (void)w;
  }
};

extern "C" void onInterrupt(int sig) {
  iso::support::removeRegisteredTemporaries();
  (HandlerMessage() << "\n" << gInterruptedTool << ": interrupted; " << gInterruptOutcome << "\n").write();
  ::_exit(128 + sig);
}

/// SIGBUS on the bytes of a mapped source (support::readSource) that its file lost: the file
/// shrank while it was read. A usage-class error (exit 2), told as such; any other SIGBUS is
/// not ours to explain and ends the process as it would have.
extern "C" void onBusError(int sig, siginfo_t* info, void*) {
  const char* path = info ? iso::support::mappedSourceAt(info->si_addr) : nullptr;
  if (!path) {
    ::signal(sig, SIG_DFL);
    ::raise(sig);
    return;
  }
  iso::support::removeRegisteredTemporaries();
  (HandlerMessage() << gInterruptedTool << ": error: " << path << ": the file shrank while it was read; "
                    << gInterruptOutcome << "\n")
      .write();
  ::_exit(kExitUsage);
}
} // namespace

void installInterruptHandler(const char* tool, const char* outcome) {
  gInterruptedTool = tool;
  gInterruptOutcome = outcome;
  struct sigaction sa {};
  sa.sa_handler = onInterrupt;
  sigemptyset(&sa.sa_mask);
  for (int sig : {SIGINT, SIGTERM, SIGHUP})
    ::sigaction(sig, &sa, nullptr);
  struct sigaction bus {};
  bus.sa_sigaction = onBusError;
  bus.sa_flags = SA_SIGINFO;
  sigemptyset(&bus.sa_mask);
  ::sigaction(SIGBUS, &bus, nullptr);
}

CLI::Validator wholeNumberAtLeast(unsigned long long min) {
  return CLI::Validator(
      [min](std::string& s) -> std::string {
        unsigned long long v = 0;
        auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
        if (s.empty() || ec != std::errc() || p != s.data() + s.size())
          return fmt::format("'{}' is not a whole number", s);
        if (v < min) return fmt::format("{} is below the least value {}", s, min);
        return "";
      },
      "", "");
}

CLI::Validator positiveSeconds() {
  return CLI::Validator(
      [](std::string& s) -> std::string {
        double v = 0;
        auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
        if (s.empty() || ec != std::errc() || p != s.data() + s.size() || !std::isfinite(v) || !(v > 0))
          return fmt::format("'{}' is not a number of seconds > 0", s);
        return "";
      },
      "", "");
}

bool useColor(const CommonOptions& opts, bool isTty) {
  if (opts.color == "always") return true;
  if (opts.color == "never") return false;
  const char* nc = std::getenv("NO_COLOR");
  return isTty && !(nc && *nc);
}

namespace {
/// Standard output as a tool writes it: buffered, and the first failed write remembered with
/// its reason (errno), after which every write fails at once (the stream goes bad).
class FdOutBuf : public std::streambuf {
public:
  explicit FdOutBuf(int fd) : fd_(fd) { setp(buf_, buf_ + sizeof buf_); }
  int error() const { return error_; }

protected:
  int overflow(int c) override {
    if (!drain()) return traits_type::eof();
    if (c != traits_type::eof()) {
      *pptr() = static_cast<char>(c);
      pbump(1);
    }
    return traits_type::not_eof(c);
  }
  int sync() override { return drain() ? 0 : -1; }
  std::streamsize xsputn(const char* s, std::streamsize n) override {
    if (n <= epptr() - pptr()) {
      std::memcpy(pptr(), s, static_cast<size_t>(n));
      pbump(static_cast<int>(n));
      return n;
    }
    if (!drain() || !writeAll(s, static_cast<size_t>(n))) return 0;
    return n;
  }

private:
  bool writeAll(const char* p, size_t n) {
    while (n > 0 && error_ == 0) {
      const ssize_t w = ::write(fd_, p, n);
      if (w < 0 && errno == EINTR) continue;
      if (w <= 0) {
        error_ = w < 0 ? errno : EIO;
        break;
      }
      p += w;
      n -= static_cast<size_t>(w);
    }
    return error_ == 0;
  }
  bool drain() {
    const bool ok = writeAll(pbase(), static_cast<size_t>(pptr() - pbase()));
    setp(buf_, buf_ + sizeof buf_);
    return ok;
  }
  int fd_;
  int error_ = 0;
  char buf_[1 << 16];
};

/// Every byte a tool writes to standard output reaches it, or the run fails: the final flush is
/// checked (a full disk, an I/O error), and so is standard error.
int checkedOutputs(Io& io, const char* tool, int rc, const FdOutBuf* stdoutBuf) {
  io.out.flush();
  if (!io.out) {
    const int e = stdoutBuf ? stdoutBuf->error() : 0;
    io.err << fmt::format("{}: error: error writing standard output: {}\n", tool,
                          e != 0 ? std::strerror(e) : "the output stream failed");
    io.err.flush();
    return kExitUsage;
  }
  io.err.flush();
  return io.err ? rc : kExitUsage;
}

/// While a tool runs, std::cout writes through an FdOutBuf on file descriptor 1.
class StdoutScope {
public:
  explicit StdoutScope(std::ostream& out) : active_(&out == &std::cout) {
    if (active_) old_ = std::cout.rdbuf(&buf_);
  }
  ~StdoutScope() {
    if (!active_) return;
    std::cout.flush();
    std::cout.rdbuf(old_);
  }
  StdoutScope(const StdoutScope&) = delete;
  StdoutScope& operator=(const StdoutScope&) = delete;
  const FdOutBuf* buf() const { return active_ ? &buf_ : nullptr; }

private:
  bool active_;
  FdOutBuf buf_{1};
  std::streambuf* old_ = nullptr;
};
} // namespace

int guarded(Io& io, const char* tool, int (*body)(void*), void* ctx) {
  StdoutScope scope(io.out);
  try {
    const int rc = body(ctx);
    return checkedOutputs(io, tool, rc, scope.buf());
  } catch (const std::exception& e) {
    io.err << fmt::format("{}: internal error: {} (please report this bug)\n", tool, e.what());
  } catch (...) {
    io.err << fmt::format("{}: internal error: unknown exception (please report this bug)\n", tool);
  }
  return kExitInternal;
}

} // namespace iso::driver
