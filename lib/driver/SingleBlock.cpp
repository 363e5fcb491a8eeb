//! @file SingleBlock.cpp
//! @brief isosim --single-block: a debug hook that prints each block and waits for a command.
#include "driver/SingleBlock.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <istream>
#include <map>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include <fmt/format.h>

#include "driver/ExitCode.h"
#include "sim/Debug.h"
#include "sim/TraceWriter.h"
#include "support/File.h"
#include "support/Text.h"

namespace iso::driver {

namespace fs = std::filesystem;

namespace {

constexpr const char* kSingleBlockHelp =
    "isosim: single block: Enter runs the next block, c continues to the end, q stops the run\n";

/// After a block line on a terminal: the command typed is echoed after it.
constexpr const char* kPrompt = "  > ";

/// `s` without the blanks (and a CR) at its ends.
std::string_view trimBlanks(std::string_view s) {
  const size_t b = s.find_first_not_of(" \t\r");
  if (b == std::string_view::npos) return {};
  return s.substr(b, s.find_last_not_of(" \t\r") - b + 1);
}

/// The physical lines of the program's sources, read when first shown.
class SourceLines {
public:
  explicit SourceLines(fs::path base) : base_(std::move(base)) {}

  /// Line `line` (from 1) of `file` as the image names it, trimmed; "" when unknown.
  std::string text(const std::string& file, uint32_t line) {
    auto it = files_.find(file);
    if (it == files_.end()) it = files_.emplace(file, load(file)).first;
    const std::vector<std::string>& lines = it->second;
    if (line == 0 || line > lines.size()) return {};
    return lines[line - 1];
  }

private:
  std::vector<std::string> load(const std::string& file) const {
    std::vector<std::string> lines;
    if (file.empty() || file == "?") return lines;
    fs::path p(file);
    if (p.is_relative()) p = base_ / p;
    support::Expected<std::string> bytes = support::readFile(p.string());
    if (!bytes) return lines;
    std::string_view rest = bytes.value();
    while (!rest.empty()) {
      const size_t nl = rest.find('\n');
      std::string_view line = rest.substr(0, nl);
      rest = nl == std::string_view::npos ? std::string_view() : rest.substr(nl + 1);
      lines.emplace_back(trimBlanks(line));
    }
    return lines;
  }

  fs::path base_;
  std::map<std::string, std::vector<std::string>> files_;
};

/// The hook: a line per block, then a command from `in`.
class SingleBlockHook : public sim::DebugHook {
public:
  SingleBlockHook(Io& io, bool inIsTty, const image::Image& img, fs::path base)
      : io_(io), inIsTty_(inIsTty), sources_(std::move(base)) {
    axes_.assign(img.axes.begin(), img.axes.end());
  }

  bool statement(const sim::RunView& view, uint32_t thread, uint32_t lineEntry, size_t /*depth*/) override {
    if (continuing_) return true;
    // A block is a line: its first statement stops, the others on it run on (a stripped image
    // has no lines: each statement stops).
    auto [it, fresh] = lastLine_.try_emplace(thread, lineEntry);
    if (!fresh && it->second == lineEntry && lineEntry != UINT32_MAX) return true;
    it->second = lineEntry;
    io_.out << blockLine(view, thread, lineEntry) << (inIsTty_ ? kPrompt : "\n");
    return ask();
  }

  bool timeReached(const sim::RunView& /*view*/) override { return true; }
  void fault(const sim::RunView& /*view*/, sim::Status /*status*/, const std::string& /*message*/,
             uint32_t /*thread*/) override {}

  bool quit() const { return quit_; }

private:
  std::string blockLine(const sim::RunView& view, uint32_t thread, uint32_t lineEntry) {
    sim::DebugFrame where = view.where(lineEntry);
    if (lineEntry == UINT32_MAX) {
      std::vector<sim::DebugFrame> frames = view.stack(thread);
      if (!frames.empty()) where.file = frames.front().file;
    }
    std::string line = fmt::format("t={:.3f} s  {}", view.time(), support::escapeForTerminal(where.file));
    if (where.line != 0) line += fmt::format(":{}", where.line);
    if (thread != 1)
      for (const sim::DebugThread& t : view.threads())
        if (t.id == thread) line += fmt::format("  [{}]", support::escapeForTerminal(t.name));
    if (std::string text = sources_.text(where.file, where.line); !text.empty())
      line += "  " + support::escapeForTerminal(text);
    std::string axes;
    for (const sim::DebugAxis& a : view.axes()) {
      if (std::find(axes_.begin(), axes_.end(), a.letter) == axes_.end()) continue;
      axes += fmt::format(" {}={}", a.letter, sim::formatNumber(a.position));
    }
    if (!axes.empty()) line += " " + axes;
    return line;
  }

  /// Reads commands until one runs the program on; false for q.
  bool ask() {
    for (;;) {
      io_.out.flush();
      std::string cmd;
      if (!io_.in || !std::getline(*io_.in, cmd)) {
        if (inIsTty_) io_.out << "\n"; // Ctrl-D echoes nothing
        continuing_ = true;            // the end of the input: run to the end
        return true;
      }
      cmd = std::string(trimBlanks(cmd));
      if (cmd.empty()) return true;
      if (cmd == "c" || cmd == "C") {
        continuing_ = true;
        return true;
      }
      if (cmd == "q" || cmd == "Q") {
        quit_ = true;
        return false;
      }
      io_.out << kSingleBlockHelp << (inIsTty_ ? kPrompt : "");
    }
  }

  Io& io_;
  bool inIsTty_ = false;
  SourceLines sources_;
  std::vector<char> axes_;                ///< the axes the program uses
  std::map<uint32_t, uint32_t> lastLine_; ///< per thread: the line entry of its last statement
  bool continuing_ = false;
  bool quit_ = false;
};

/// The options --single-block refuses: kExitOk or the usage error.
int checkSingleBlockOptions(const SimulateOptions& opts, Io& io) {
  const std::pair<const char*, bool> refused[] = {
      {"-o", !opts.output.empty()},           {"--plot", !opts.plot.empty()}, {"--timeline", !opts.timeline.empty()},
      {"--report", !opts.report.empty()},     {"--profile", opts.profile},    {"--compare", !opts.compare.empty()},
      {"--print-machine", opts.printMachine},
  };
  for (const auto& [name, given] : refused)
    if (given) return usageError(io, "isosim", fmt::format("--single-block cannot be combined with {}", name));
  if (opts.program == "-" || std::find(opts.paths.begin(), opts.paths.end(), "-") != opts.paths.end())
    return usageError(io, "isosim",
                      "with --single-block the program cannot be standard input: the commands come from there");
  if (!opts.format.empty() && opts.format != "csv" && opts.format != "json")
    return usageError(io, "isosim", fmt::format("unknown format '{}' (csv or json)", opts.format));
  return kExitOk;
}

} // namespace

int runSingleBlock(const SimulateOptions& opts, Io& io, bool inIsTty) {
  if (int rc = checkSingleBlockOptions(opts, io); rc != kExitOk) return rc;
  PreparedRun run;
  if (int rc = prepareRun(opts, io, run); rc != kExitOk) return rc;
  SingleBlockHook hook(io, inIsTty, run.image->image(), fs::path(opts.program).parent_path());
  sim::SimOptions so = run.options;
  so.debug = &hook;
  io.err << kSingleBlockHelp;
  sim::SimResult res = sim::simulate(*run.image, *run.machine, so);
  if (res.setupError != sim::SetupError::None) {
    io.err << fmt::format("{}: error: {}\n", support::escapeForTerminal(opts.program),
                          support::escapeForTerminal(res.setupMessage));
    return kExitUsage;
  }
  sim::Summary& s = res.summary;
  s.overrides = run.overrides;
  if (s.status != sim::Status::Ok && !hook.quit())
    io.err << "isosim: " << support::escapeForTerminal(s.message) << "\n";
  io.out << (opts.format == "json" ? sim::summaryJson(s, 2) + "\n" : sim::summaryText(s));
  if (hook.quit()) return kExitOk;
  switch (s.status) {
  case sim::Status::Ok: return kExitOk;
  case sim::Status::Error: return kExitErrors;
  case sim::Status::Emergency: return kExitEmergency;
  }
  return kExitInternal;
}

} // namespace iso::driver
