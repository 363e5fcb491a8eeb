//! @file Lint.cpp
//! @brief The isolint driver.
#include "driver/Lint.h"

#include <algorithm>
#include <ostream>
#include <thread>

#include <fmt/format.h>

#include "diag/Render.h"

namespace iso::driver {

bool resolveCodes(const std::vector<std::string>& names, std::vector<diag::Code>& out, Io& io, const char* tool) {
  for (const auto& n : names) {
    auto c = diag::findCode(n);
    if (!c) {
      io.err << fmt::format("{}: error: unknown diagnostic '{}' (give a code like W402 or a name like feed-unset)\n",
                            tool, n);
      return false;
    }
    out.push_back(*c);
  }
  return true;
}

std::vector<diag::Diagnostic> visibleDiagnostics(const frontend::ProgramSet& set,
                                                 const std::vector<diag::Code>& disabled, bool werror) {
  std::vector<diag::Diagnostic> out;
  for (const auto& d : set.diags.items()) {
    if (d.loc.file >= set.files.size() || !set.reported[d.loc.file]) continue;
    if (std::find(disabled.begin(), disabled.end(), d.code) != disabled.end()) continue;
    bool suppressed = false;
    for (const auto& s : set.files[d.loc.file].suppressions)
      if (s.code == d.code && (s.line == 0 || (d.loc.line >= s.line && d.loc.line <= s.lastLine))) suppressed = true;
    if (suppressed) continue;
    out.push_back(d);
    if (werror && out.back().severity == diag::Severity::Warning) out.back().severity = diag::Severity::Error;
  }
  return out;
}

void printTextDiagnostics(const std::vector<diag::Diagnostic>& diags, const frontend::ProgramSet& set,
                          std::ostream& os, bool color, bool countLine) {
  os << diag::renderText(diags, set.sources, color);
  if (countLine) {
    size_t files = 0;
    for (auto r : set.reported) files += r;
    os << diag::renderCountLine(diag::countOf(diags), files);
  }
}

int runLint(const LintOptions& opts, Io& io) {
  if (opts.paths.empty()) {
    io.err << "isolint: error: no input files (give .mpf/.spf files or directories)\n";
    return kExitUsage;
  }
  std::vector<diag::Code> disabled;
  if (!resolveCodes(opts.disable, disabled, io, "isolint")) return kExitUsage;
  auto m = loadMachine(opts.common, io);
  if (!m) return kExitUsage;
  frontend::LoadOptions lo;
  lo.machine = &*m;
  lo.dialect = m->dialect;
  lo.jobs = opts.jobs ? opts.jobs : std::max(1u, std::thread::hardware_concurrency());
  frontend::ProgramSet set;
  frontend::SetError err;
  if (!frontend::loadProgramSet(opts.paths, lo, set, err)) {
    io.err << fmt::format("{}: error: {}\n", err.path, err.message);
    return kExitUsage;
  }
  size_t files = 0;
  for (auto r : set.reported) files += r;
  if (files == 0) {
    io.err << "isolint: error: no .mpf or .spf files found in the given directories\n";
    return kExitUsage;
  }
  auto diags = visibleDiagnostics(set, disabled, opts.werror);
  if (opts.format == "json") {
    io.out << diag::renderJson(diags, set.sources, files).dump(2) << "\n";
  } else if (opts.format == "sarif") {
    io.out << diag::renderSarif(diags, set.sources, "isolint", ISO_VERSION).dump(2) << "\n";
  } else {
    printTextDiagnostics(diags, set, io.out, useColor(opts.common, io.outIsTty), true);
  }
  return diag::countOf(diags).errors > 0 ? kExitErrors : kExitOk;
}

} // namespace iso::driver
