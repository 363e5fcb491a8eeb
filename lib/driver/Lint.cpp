//! @file Lint.cpp
//! @brief The isolint driver.
#include "driver/Lint.h"

#include <algorithm>
#include <filesystem>
#include <functional>
#include <istream>
#include <map>
#include <memory>
#include <optional>
#include <ostream>
#include <sstream>
#include <unordered_map>
#include <unordered_set>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "diag/DiagnosticEngine.h"
#include "diag/Fix.h"
#include "diag/Render.h"
#include "diag/RuleDocs.h"
#include "driver/Baseline.h"
#include "driver/Policy.h"
#include "driver/Settings.h"
#include "support/File.h"
#include "support/Version.h"

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
          const std::string near = suggestCode(n);
          usageError(io, tool,
                     fmt::format("unknown diagnostic '{}'{} (give a code like W402 or a name like feed-unset)", n,
                                 near.empty() ? "" : fmt::format("; did you mean '{}'?", near)));
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
  for (auto r : set.reported)
    files += r;
  return files;
}

namespace {
/// Puts each of `extra` into `items` after the diagnostics of its file on earlier lines or
/// columns (after every file when its file has none), keeping the order of `items`: a file's
/// diagnostics are one run, sorted by line and column. O((n + m) log m).
void insertInPlace(std::vector<diag::Diagnostic>& items, std::vector<diag::Diagnostic>&& extra) {
  std::unordered_map<uint32_t, std::pair<size_t, size_t>> runs; // file -> [begin, end) in items
  for (size_t i = 0; i < items.size(); ++i) {
    auto [it, inserted] = runs.emplace(items[i].loc.file, std::make_pair(i, i + 1));
    if (!inserted) it->second.second = i + 1;
  }
  const auto before = [](const diag::Diagnostic& a, const diag::Diagnostic& b) {
    return a.loc.line < b.loc.line || (a.loc.line == b.loc.line && a.loc.col < b.loc.col);
  };
  std::vector<std::pair<size_t, size_t>> at; // (position in items, index in extra)
  for (size_t k = 0; k < extra.size(); ++k) {
    size_t pos = items.size();
    if (auto r = runs.find(extra[k].loc.file); r != runs.end()) {
      const auto first = items.begin() + static_cast<std::ptrdiff_t>(r->second.first);
      const auto last = items.begin() + static_cast<std::ptrdiff_t>(r->second.second);
      pos = static_cast<size_t>(std::upper_bound(first, last, extra[k], before) - items.begin());
    }
    at.emplace_back(pos, k);
  }
  std::stable_sort(at.begin(), at.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<diag::Diagnostic> merged;
  merged.reserve(items.size() + extra.size());
  size_t next = 0;
  for (const auto& [pos, k] : at) {
    for (; next < pos; ++next)
      merged.push_back(std::move(items[next]));
    merged.push_back(std::move(extra[k]));
  }
  for (; next < items.size(); ++next)
    merged.push_back(std::move(items[next]));
  items = std::move(merged);
}
} // namespace

void filterDiagnostics(frontend::ProgramSet& set, const DiagnosticFilter& filter) {
  diag::DiagnosticEngine engine(filter);
  engine.setShownFiles(set.reported);
  for (const auto& f : set.files)
    for (const auto& s : f.suppressions)
      engine.addSuppression({f.id, s.line, s.lastLine, s.code, s.commentLine, s.col, s.length});
  engine.apply(set.diags.items());
  // W421: a suppression nothing used (itself under the policy: disabled, selected, shown)
  diag::DiagnosticList unused;
  for (const auto& s : engine.unusedSuppressions()) {
    const auto& ci = diag::info(s.code);
    const diag::Loc at{s.file, s.commentLine, s.col};
    if (s.line == 0)
      unused.report(diag::Msg::SuppressionUnusedFile, at, s.length, ci.code, ci.name);
    else
      unused.report(diag::Msg::SuppressionUnusedLine, at, s.length, ci.code, ci.name);
  }
  if (unused.items().empty()) return;
  engine.apply(unused.items());
  insertInPlace(set.diags.items(), std::move(unused.items()));
}

DiagnosticFilter settingsFilter(const frontend::ProgramSet& set, const Settings& settings) {
  DiagnosticFilter f{{}, false, true, {}};
  if (!settings.path.empty())
    f.disabledFor = [&set, &settings](uint32_t file, diag::Code code) {
      return diag::info(code).severity != diag::Severity::Error && settings.disabledFor(set.sources.path(file), code);
    };
  return f;
}

void printTextDiagnostics(const std::vector<diag::Diagnostic>& diags, const diag::SourceManager& sources, size_t files,
                          std::ostream& os, bool color, bool countLine, size_t maxPerFile) {
  diag::TextRenderer r(os, sources, color, maxPerFile);
  for (const auto& d : diags)
    r.add(d);
  r.finish();
  if (countLine) os << diag::renderCountLine(diag::countOf(diags), files);
}

void printToolDiagnostics(const frontend::ProgramSet& set, const CommonOptions& common, const Settings& settings,
                          Io& io) {
  const auto& diags = set.diags.items();
  if (diags.empty()) return;
  long long maxPerFile = common.maxDiagnostics;
  if (maxPerFile < 0) maxPerFile = settings.maxDiagnostics.value_or(static_cast<long long>(kDefaultTextMaxDiagnostics));
  printTextDiagnostics(diags, set.sources, reportedFiles(set), io.err, useColor(common, io.errIsTty), true,
                       static_cast<size_t>(maxPerFile));
}

namespace {
std::string plural(size_t n, const char* one, const char* many) { return fmt::format("{} {}", n, n == 1 ? one : many); }

} // namespace

std::vector<std::vector<std::string>> groupProgramSets(const std::vector<std::string>& paths,
                                                       std::vector<diag::InputError>& errors,
                                                       const std::function<bool(const std::string&)>& excluded) {
  namespace fs = std::filesystem;
  std::vector<std::vector<std::string>> groups;
  std::unordered_map<std::string, size_t> byFolder; // canonical folder -> group
  auto groupOf = [&](const fs::path& folder) -> std::vector<std::string>& {
    std::error_code ec;
    fs::path c = fs::weakly_canonical(folder.empty() ? fs::path(".") : folder, ec);
    auto [it, inserted] = byFolder.emplace(ec ? folder.string() : c.string(), groups.size());
    if (inserted) groups.emplace_back();
    return groups[it->second];
  };
  for (const auto& p : paths) {
    std::error_code ec;
    if (!fs::is_directory(p, ec)) {
      if (!fs::exists(p, ec)) {
        errors.push_back({p, "no such file or directory"});
        continue;
      }
      groupOf(fs::path(p).parent_path()).push_back(p);
      continue;
    }
    std::vector<fs::path> dirs{fs::path(p)};
    fs::recursive_directory_iterator it(p, fs::directory_options::skip_permission_denied, ec), end;
    if (ec) {
      errors.push_back({p, "cannot read directory"});
      continue;
    }
    for (; it != end; it.increment(ec)) {
      if (ec) break;
      std::error_code ec2;
      if (!it->is_directory(ec2) || it->is_symlink(ec2)) continue;
      if (it->path().filename().string().rfind('.', 0) == 0) {
        it.disable_recursion_pending(); // .git, .cache, ...
        continue;
      }
      dirs.push_back(it->path());
    }
    std::sort(dirs.begin() + 1, dirs.end());
    bool any = false;
    for (const auto& d : dirs) {
      std::vector<std::string> files;
      if (!frontend::listProgramFiles(d.string(), files) || files.empty()) continue;
      any = true;
      if (!excluded) {
        groupOf(d).push_back(d.string());
        continue;
      }
      // with exclusions the folder's files are named one by one (excluded ones stay
      // siblings: they still resolve calls, but are not reported)
      std::erase_if(files, excluded);
      if (files.empty()) continue; // every file of the folder is excluded
      auto& grp = groupOf(d);
      grp.insert(grp.end(), files.begin(), files.end());
    }
    if (!any) groupOf(fs::path(p)).push_back(p); // reported as "no .mpf or .spf files found"
  }
  return groups;
}

namespace {
/// The diagnostics of several program sets, with the sources they point into.
struct LintRun {
  diag::SourceManager sources;
  std::vector<diag::Diagnostic> diags;
  std::vector<diag::InputError> inputErrors;
  size_t files = 0;
};

/// Moves the reported part of a linted set into `run`, renumbering its file ids.
void mergeInto(LintRun& run, frontend::ProgramSet& set) {
  const auto base = static_cast<uint32_t>(run.sources.size());
  for (uint32_t i = 0; i < set.sources.size(); ++i) {
    auto& f = set.sources.file(i);
    // sources that no diagnostic points into are kept without their text
    run.sources.add(f.path, std::move(f.text));
  }
  for (auto& d : set.diags.items()) {
    d.loc.file += base;
    for (auto& n : d.notes)
      n.loc.file += base;
    for (auto& f : d.fixes)
      for (auto& e : f.edits)
        e.start.file += base;
    run.diags.push_back(std::move(d));
  }
  for (auto& e : set.inputErrors)
    run.inputErrors.push_back(std::move(e));
  run.files += reportedFiles(set);
}
/// What the passes of --fix have done so far.
struct FixTally {
  unsigned passes = 0;
  size_t problems = 0;
  std::unordered_set<std::string> files; ///< paths written
};

/// A fix can uncover another diagnostic of its line (E108 first, then the colon of the jump
/// after it): --fix lints again and fixes again until nothing is left to fix, at most this often.
constexpr unsigned kMaxFixPasses = 10;

/// Standard input: "-", read as the file --stdin-filename PATH (its folder gives the program
/// set), else as "<stdin>", a program set of its own. kExitOk, or the usage error printed.
int readStdinBuffer(const LintOptions& opts, std::istream* in, std::vector<std::string>& paths,
                    std::optional<frontend::ProgramText>& buffer, Io& io) {
  const size_t dashes = static_cast<size_t>(std::count(paths.begin(), paths.end(), "-"));
  if (dashes == 0 && opts.stdinFilename.empty()) return kExitOk;
  if (dashes != 1 || !in) return usageError(io, "isolint", "standard input is read as one file: give '-' once");
  if (paths.size() > 1 && opts.stdinFilename.empty())
    return usageError(io, "isolint",
                      "'-' (standard input) is a program set of its own: give it alone, or with "
                      "--stdin-filename PATH to check it beside PATH's folder");
  const std::string name = opts.stdinFilename.empty() ? std::string(kStdinName) : opts.stdinFilename;
  auto text = readStandardInputText(*in, name, io);
  if (!text) return kExitUsage;
  if (opts.stdinFilename.empty()) support::setStreamInput(name, *text); // no siblings, no folder
  buffer = frontend::ProgramText{name, std::move(*text), true};
  std::replace(paths.begin(), paths.end(), std::string("-"), name);
  return kExitOk;
}

int runLintImpl(const LintOptions& opts, Io& io, std::istream* in, FixTally* tally);

/// --fix and --diff: applies the first fix of each diagnostic of `run` (all of them: the
/// per-file output limit does not apply) to its file. --diff prints the changes as a unified
/// diff; --fix writes each changed file atomically (standard input: keeps the text), lints
/// again and repeats; the last pass prints what remains, with its exit status.
int fixRun(const LintOptions& opts, LintRun& run, Io& io, bool fromStdin, FixTally* tally) {
  std::vector<std::vector<const diag::Fix*>> byFile(run.sources.size());
  for (const auto& d : run.diags)
    if (!d.fixes.empty() && d.loc.file < byFile.size()) byFile[d.loc.file].push_back(&d.fixes.front());
  size_t problems = 0;
  std::string stdinText;
  for (uint32_t id = 0; id < byFile.size(); ++id) {
    const diag::SourceFile& sf = run.sources.file(id);
    const bool isStdin = fromStdin && sf.path == opts.stdinFilename;
    if (isStdin) stdinText = sf.text;
    if (byFile[id].empty()) continue;
    diag::FixResult r = diag::applyFixes(sf.text, byFile[id]);
    if (r.edits.empty() || r.text == sf.text) continue;
    if (opts.diff) {
      const std::string d = diag::unifiedDiff(sf.text, r.edits, sf.path);
      io.out << (useColor(opts.common, io.outIsTty) ? diag::colorDiff(d) : d);
      continue;
    }
    if (isStdin) {
      stdinText = std::move(r.text);
    } else {
      if (support::Status w = support::writeFileAtomically(sf.path, r.text); !w) {
        io.err << fmt::format("isolint: cannot write {}: {}\n", sf.path, w.why());
        return kExitUsage;
      }
    }
    problems += r.applied;
    tally->files.insert(sf.path);
  }
  if (opts.diff) {
    if (!run.inputErrors.empty()) return kExitUsage;
    return diag::countOf(run.diags).errors > 0 ? kExitErrors : kExitOk;
  }
  tally->problems += problems;
  ++tally->passes;
  std::istringstream fixed(stdinText);
  if (problems > 0 && tally->passes < kMaxFixPasses) return runLintImpl(opts, io, &fixed, tally);
  // Nothing more to fix: report what remains.
  LintOptions last = opts;
  last.fix = false;
  int rc = kExitOk;
  if (fromStdin) {
    // the fixed text goes to standard output (editors replace the buffer with it); the exit
    // status is that of the text as fixed
    std::ostringstream quiet;
    Io silent{quiet, quiet, false, false};
    rc = runLintImpl(last, silent, &fixed, nullptr);
    io.out << stdinText;
  } else {
    rc = runLintImpl(last, io, nullptr, nullptr);
  }
  io.err << fmt::format("isolint: fixed {} in {}\n", plural(tally->problems, "problem", "problems"),
                        plural(tally->files.size(), "file", "files"));
  return rc;
}
} // namespace

int runLint(const LintOptions& opts, Io& io, std::istream* in) {
  FixTally tally;
  return runLintImpl(opts, io, in, opts.fix ? &tally : nullptr);
}

namespace {
/// isolint --explain CODE: the rule's documentation.
int explain(const std::string& what, Io& io) {
  auto code = diag::findCode(what);
  if (!code)
    return usageError(io, "isolint",
                      fmt::format("unknown diagnostic '{}' (give a code like W402 or a name like feed-unset)", what));
  io.out << diag::explainRule(*code);
  return kExitOk;
}

/// --statistics: one row per code shown (most frequent first, then by code) and the count
/// line, or the same as JSON.
void printStatistics(const LintOptions& opts, const LintRun& run, Io& io) {
  std::map<diag::Code, size_t> byCode;
  for (const auto& d : run.diags)
    ++byCode[d.code];
  std::vector<std::pair<diag::Code, size_t>> rows(byCode.begin(), byCode.end());
  std::stable_sort(rows.begin(), rows.end(), [](const auto& a, const auto& b) { return a.second > b.second; });
  const diag::Counts counts = diag::countOf(run.diags);
  if (opts.format == "json") {
    nlohmann::ordered_json doc;
    doc["statistics"] = nlohmann::ordered_json::array();
    for (const auto& [code, n] : rows) {
      const auto& ci = diag::info(code);
      doc["statistics"].push_back(
          {{"code", ci.code}, {"name", ci.name}, {"severity", diag::severityName(ci.severity)}, {"count", n}});
    }
    doc["files"] = run.files;
    doc["errors"] = counts.errors;
    doc["warnings"] = counts.warnings;
    io.out << doc.dump(2) << "\n";
    return;
  }
  for (const auto& [code, n] : rows) {
    const auto& ci = diag::info(code);
    io.out << fmt::format("{:>7}  {}  {}\n", n, ci.code, ci.name);
  }
  io.out << diag::renderCountLine(counts, run.files);
}

/// Prints the diagnostics of `run` in the chosen format.
void printReport(const LintOptions& opts, LintRun& run, long long maxDiagnostics, Io& io) {
  auto& diags = run.diags;
  const size_t files = run.files;
  const diag::Counts counts = diag::countOf(diags);
  if (opts.format == "text") {
    const size_t limit = maxDiagnostics < 0 ? kDefaultTextMaxDiagnostics : static_cast<size_t>(maxDiagnostics);
    printTextDiagnostics(diags, run.sources, files, io.out, useColor(opts.common, io.outIsTty), files > 0, limit);
    return;
  }
  if (maxDiagnostics > 0) diag::DiagnosticEngine::limitPerFile(diags, static_cast<size_t>(maxDiagnostics));
  if (opts.format == "json") {
    diag::writeJson(io.out, diags, run.sources, files, run.inputErrors, &counts);
  } else if (opts.format == "github") {
    diag::writeGithub(io.out, diags, run.sources);
    io.out << diag::renderCountLine(counts, files);
  } else {
    std::error_code ec;
    diag::writeSarif(io.out, diags, run.sources, "isolint", kVersion, run.inputErrors,
                     std::filesystem::current_path(ec).string());
  }
}

/// The options that exclude each other; kExitOk or the usage error printed.
int checkCombinations(const LintOptions& opts, Io& io) {
  if (opts.paths.empty()) return usageError(io, "isolint", "no input files (give .mpf/.spf files or directories)");
  if (opts.fix && opts.diff)
    return usageError(io, "isolint", "--fix and --diff cannot be combined (--diff changes nothing)");
  if (!opts.baseline.empty() && (opts.fix || opts.diff))
    return usageError(io, "isolint", "--baseline cannot be combined with --fix or --diff");
  if (opts.statistics && (opts.fix || opts.diff))
    return usageError(io, "isolint", "--statistics cannot be combined with --fix or --diff");
  if (opts.statistics && opts.format != "text" && opts.format != "json")
    return usageError(io, "isolint", "--statistics prints text or json (not " + opts.format + ")");
  return kExitOk;
}

/// --baseline FILE: read when it exists (nullopt and `write` when it does not); kExitOk, or
/// kExitUsage with the reason printed.
int loadBaseline(const std::string& path, std::optional<Baseline>& out, bool& write, Io& io) {
  write = false;
  if (path.empty()) return kExitOk;
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) {
    write = true;
    return kExitOk;
  }
  auto b = readBaseline(path);
  if (!b) {
    io.err << fmt::format("isolint: error: {}: {}\n", b.error().where, b.error().message);
    return kExitUsage;
  }
  out = std::move(*b);
  return kExitOk;
}

/// Writes the baseline of `run` (when it did not exist) or leaves out what it lists.
int useBaseline(const LintOptions& opts, const std::optional<Baseline>& baseline, bool write, LintRun& run, Io& io) {
  if (write) {
    if (auto st = support::writeFileAtomically(opts.baseline, baselineText(run.diags, run.sources)); !st) {
      io.err << fmt::format("isolint: error: {}: {}\n", opts.baseline, st.error().message);
      return kExitUsage;
    }
    io.err << fmt::format("isolint: wrote the baseline {} ({} {}); later runs report only new ones\n", opts.baseline,
                          run.diags.size(), run.diags.size() == 1 ? "finding" : "findings");
  } else if (baseline) {
    const size_t known = applyBaseline(run.diags, run.sources, *baseline);
    if (known > 0)
      io.err << fmt::format("isolint: {} {} of the baseline {} left out\n", known,
                            known == 1 ? "known finding" : "known findings", opts.baseline);
  }
  return kExitOk;
}

int runLintImpl(const LintOptions& opts, Io& io, std::istream* in, FixTally* tally) {
  if (!opts.explain.empty()) return explain(opts.explain, io);
  if (int rc = checkCombinations(opts, io); rc != kExitOk) return rc;
  std::vector<diag::Code> disabled, selected;
  if (!resolveCodes(opts.disable, disabled, io, "isolint")) return kExitUsage;
  if (!resolveCodes(opts.select, selected, io, "isolint")) return kExitUsage;
  std::optional<Baseline> baseline;
  bool writeBaseline = false;
  if (int rc = loadBaseline(opts.baseline, baseline, writeBaseline, io); rc != kExitOk) return rc;
  std::vector<std::string> paths = opts.paths;
  std::optional<frontend::ProgramText> buffer;
  if (int rc = readStdinBuffer(opts, in, paths, buffer, io); rc != kExitOk) return rc;
  // Settings: --config FILE, else the isotools.toml found from each program set's folder.
  LintPolicies policies(opts.common, std::move(disabled), opts.werror, io);
  policies.select(std::move(selected));
  auto settingsFor = [&](const std::string& input) { return policies.settingsFor(input); };
  const Settings* first = settingsFor(paths.front() == "-" ? std::string(".") : paths.front());
  if (!first) return kExitUsage;
  long long maxDiagnostics = policies.maxDiagnostics(opts.maxDiagnostics, *first);
  const unsigned jobs = opts.jobs ? opts.jobs : hardwareJobs();
  LintRun run;
  std::vector<std::vector<std::string>> groups;
  if (buffer) {
    groups.push_back(paths); // one set: the buffer's folder
  } else {
    groups = groupProgramSets(paths, run.inputErrors, [&](const std::string& file) {
      const Settings* st = settingsFor(file);
      return st && st->excludes(file);
    });
  }
  for (const auto& g : groups) {
    if (g.empty()) continue;
    const Settings* st = settingsFor(g.front());
    if (!st) return kExitUsage;
    const machine::Machine* m = policies.machineFor(*st);
    if (!m) return kExitUsage;
    SourceOptions so;
    so.jobs = jobs;
    so.siblings = frontend::SiblingLoad::Called;
    so.compactTrees = true;
    so.buffer = buffer ? &*buffer : nullptr;
    so.filter = [&](const frontend::ProgramSet& set) { return policies.filterFor(set, *st); };
    frontend::ProgramSet set;
    loadSources(g, *m, so, set); // what could not be read is in set.inputErrors
    mergeInto(run, set);
  }
  // --fix: the first pass prints them for standard input, the last one for files
  if (!opts.fix || (buffer && tally->passes == 0)) printInputErrors(io, run.inputErrors);
  if (run.files == 0 && run.inputErrors.empty())
    return usageError(io, "isolint", "no .mpf or .spf files found in the given directories");
  if (opts.fix || opts.diff) {
    FixTally none;
    return fixRun(opts, run, io, buffer.has_value(), tally ? tally : &none);
  }
  if (int rc = useBaseline(opts, baseline, writeBaseline, run, io); rc != kExitOk) return rc;
  const diag::Counts counts = diag::countOf(run.diags);
  if (opts.statistics)
    printStatistics(opts, run, io);
  else
    printReport(opts, run, maxDiagnostics, io);
  if (!run.inputErrors.empty()) return kExitUsage;
  return counts.errors > 0 ? kExitErrors : kExitOk;
}
} // namespace

} // namespace iso::driver
