//! @file Lint.cpp
//! @brief The isolint driver.
#include "driver/Lint.h"

#include <algorithm>
#include <filesystem>
#include <ostream>
#include <thread>
#include <unordered_set>

#include <fmt/format.h>

#include "diag/Render.h"
#include "diag/RuleDocs.h"
#include "image/ImageWriter.h"

namespace iso::driver {

bool resolveCodes(const std::vector<std::string>& names, std::vector<diag::Code>& out, Io& io, const char* tool) {
  for (const auto& list : names) {
    size_t from = 0;
    for (;;) {
      size_t comma = list.find(',', from);
      std::string n = list.substr(from, comma == std::string::npos ? std::string::npos : comma - from);
      if (!n.empty()) {
        auto c = diag::findCode(n);
        if (!c) {
          usageError(io, tool,
                     fmt::format("unknown diagnostic '{}' (give a code like W402 or a name like feed-unset)", n));
          return false;
        }
        out.push_back(*c);
      }
      if (comma == std::string::npos) break;
      from = comma + 1;
    }
  }
  return true;
}

size_t reportedFiles(const frontend::ProgramSet& set) {
  size_t files = 0;
  for (auto r : set.reported) files += r;
  return files;
}

void filterDiagnostics(frontend::ProgramSet& set, const DiagnosticFilter& filter) {
  // Suppressions as hash sets: (file, line, code) for line ones, (file, code) for file ones.
  auto key = [](uint64_t file, uint64_t line, diag::Code code) {
    return (file << 40) ^ (line << 12) ^ static_cast<uint64_t>(code);
  };
  std::unordered_set<uint64_t> lineSup, fileSup;
  for (const auto& f : set.files)
    for (const auto& s : f.suppressions) {
      if (s.line == 0) fileSup.insert(key(f.id, 0, s.code));
      else
        for (uint32_t l = s.line; l <= s.lastLine; ++l) lineSup.insert(key(f.id, l, s.code));
    }
  auto& items = set.diags.items();
  size_t out = 0;
  for (size_t i = 0; i < items.size(); ++i) {
    diag::Diagnostic& d = items[i];
    if (d.loc.file >= set.files.size() || !set.reported[d.loc.file]) continue;
    if (std::find(filter.disabled.begin(), filter.disabled.end(), d.code) != filter.disabled.end()) continue;
    const bool suppressed = (!fileSup.empty() && fileSup.count(key(d.loc.file, 0, d.code))) ||
                            (!lineSup.empty() && lineSup.count(key(d.loc.file, d.loc.line, d.code)));
    if (suppressed) {
      if (!filter.keepSilencedErrors || d.severity != diag::Severity::Error) continue;
      d.notes.push_back({d.loc, "silenced for isolint by an inline 'isolint: disable', but it still prevents "
                                "compiling"});
    }
    if (filter.werror && d.severity == diag::Severity::Warning) d.severity = diag::Severity::Error;
    if (out != i) items[out] = std::move(d);
    ++out;
  }
  items.resize(out);
}

void printTextDiagnostics(const std::vector<diag::Diagnostic>& diags, const frontend::ProgramSet& set,
                          std::ostream& os, bool color, bool countLine, size_t maxPerFile) {
  diag::TextRenderer r(os, set.sources, color, maxPerFile);
  for (const auto& d : diags) r.add(d);
  r.finish();
  if (countLine) os << diag::renderCountLine(diag::countOf(diags), reportedFiles(set));
}

frontend::LoadOptions loadOptionsFor(const machine::Machine& m, unsigned jobs) {
  frontend::LoadOptions lo;
  lo.machine = &m;
  lo.dialect = m.dialect;
  lo.jobs = jobs;
  lo.imageMagic = std::string_view(reinterpret_cast<const char*>(image::kMagic.data()), image::kMagic.size());
  return lo;
}

namespace {
/// Keeps at most `n` diagnostics of each file (the list is sorted by file).
void keepFirstPerFile(std::vector<diag::Diagnostic>& diags, size_t n) {
  size_t out = 0, inFile = 0;
  uint32_t file = UINT32_MAX;
  for (size_t i = 0; i < diags.size(); ++i) {
    if (diags[i].loc.file != file) {
      file = diags[i].loc.file;
      inFile = 0;
    }
    if (inFile++ >= n) continue;
    if (out != i) diags[out] = std::move(diags[i]);
    ++out;
  }
  diags.resize(out);
}
} // namespace

int runLint(const LintOptions& opts, Io& io) {
  if (!opts.explain.empty()) {
    auto code = diag::findCode(opts.explain);
    if (!code)
      return usageError(io, "isolint",
                        fmt::format("unknown diagnostic '{}' (give a code like W402 or a name like feed-unset)",
                                    opts.explain));
    io.out << diag::explainRule(*code);
    return kExitOk;
  }
  if (opts.paths.empty()) return usageError(io, "isolint", "no input files (give .mpf/.spf files or directories)");
  std::vector<diag::Code> disabled;
  if (!resolveCodes(opts.disable, disabled, io, "isolint")) return kExitUsage;
  auto m = loadMachine(opts.common, io);
  if (!m) return kExitUsage;
  frontend::ProgramSet set;
  frontend::SetError err;
  frontend::loadProgramSet(opts.paths,
                           loadOptionsFor(*m, opts.jobs ? opts.jobs : std::max(1u, std::thread::hardware_concurrency())),
                           set, err);
  printInputErrors(io, set.inputErrors);
  const size_t files = reportedFiles(set);
  if (files == 0 && set.inputErrors.empty())
    return usageError(io, "isolint", "no .mpf or .spf files found in the given directories");
  filterDiagnostics(set, {disabled, opts.werror, false});
  auto& diags = set.diags.items();
  const diag::Counts counts = diag::countOf(diags);
  const bool text = opts.format == "text";
  if (text) {
    const size_t limit = opts.maxDiagnostics < 0 ? kDefaultTextMaxDiagnostics : static_cast<size_t>(opts.maxDiagnostics);
    printTextDiagnostics(diags, set, io.out, useColor(opts.common, io.outIsTty), files > 0, limit);
  } else {
    if (opts.maxDiagnostics > 0) keepFirstPerFile(diags, static_cast<size_t>(opts.maxDiagnostics));
    if (opts.format == "json") {
      diag::writeJson(io.out, diags, set.sources, files, set.inputErrors, &counts);
    } else if (opts.format == "github") {
      diag::writeGithub(io.out, diags, set.sources);
      io.out << diag::renderCountLine(counts, files);
    } else {
      std::error_code ec;
      diag::writeSarif(io.out, diags, set.sources, "isolint", ISO_VERSION, set.inputErrors,
                       std::filesystem::current_path(ec).string());
    }
  }
  if (!set.inputErrors.empty()) return kExitUsage;
  return counts.errors > 0 ? kExitErrors : kExitOk;
}

} // namespace iso::driver
