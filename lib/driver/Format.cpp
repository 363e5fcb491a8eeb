//! @file Format.cpp
//! @brief isofmt (Format.h): inputs, settings, the layout and renumbering of each file, and the
//!        four ways to show the result.
#include "driver/Format.h"

#include <filesystem>
#include <optional>
#include <ostream>

#include <fmt/format.h>

#include "diag/Fix.h"
#include "driver/Policy.h"
#include "driver/Settings.h"
#include "format/Formatter.h"
#include "format/Renumber.h"
#include "frontend/ProgramSet.h"
#include "support/File.h"
#include "support/Text.h"

namespace iso::driver {

namespace fs = std::filesystem;

namespace {

constexpr const char* kTool = "isofmt";

struct Numbering {
  uint64_t start = 10;
  uint64_t step = 10;
};

/// "START[,STEP]": whole numbers, START from 0 and STEP from 1, at most 9 digits.
std::optional<Numbering> parseNumbering(const std::string& spec) {
  Numbering n;
  const size_t comma = spec.find(',');
  auto whole = [](const std::string& s, uint64_t least, uint64_t& out) {
    if (s.empty() || s.size() > 9 || s.find_first_not_of("0123456789") != std::string::npos) return false;
    out = std::stoull(s);
    return out >= least;
  };
  if (!whole(spec.substr(0, comma), 0, n.start)) return std::nullopt;
  if (comma != std::string::npos && !whole(spec.substr(comma + 1), 1, n.step)) return std::nullopt;
  return n;
}

format::Style styleOf(const Settings::Format& f) {
  format::Style s;
  if (f.wordCase)
    s.wordCase = *f.wordCase == "lower"  ? format::WordCase::Lower
                 : *f.wordCase == "keep" ? format::WordCase::Keep
                                         : format::WordCase::Upper;
  if (f.spaceBetweenWords) s.spaceBetweenWords = *f.spaceBetweenWords;
  if (f.spaceAroundOperators) s.spaceAroundOperators = *f.spaceAroundOperators;
  if (f.indent) s.indent = static_cast<uint32_t>(*f.indent);
  if (f.numbers)
    s.numbers = *f.numbers == "normalised" ? format::NumberStyle::Normalised : format::NumberStyle::AsWritten;
  if (f.blankLines) s.maxBlankLines = static_cast<uint32_t>(*f.blankLines);
  return s;
}

frontend::LexOptions lexOptionsOf(const machine::Machine& m) {
  frontend::LoadOptions lo;
  lo.machine = &m;
  lo.dialect = m.dialect;
  return frontend::lexOptionsFor(lo);
}

/// The layout of every file under `settings` with machine `m`: isofmt's and the editor's.
format::FormatOptions layoutOf(const Settings& settings, const machine::Machine& m) {
  format::FormatOptions layout;
  layout.style = styleOf(settings.format);
  layout.lex = lexOptionsOf(m);
  return layout;
}

/// Files as given, folders as their .mpf/.spf files (those the settings exclude left out).
bool expandInputs(const std::vector<std::string>& paths, const Settings& settings, std::vector<std::string>& out,
                  Io& io) {
  bool ok = true;
  for (const auto& p : paths) {
    std::error_code ec;
    if (p == kStdinName || !fs::is_directory(p, ec)) {
      out.push_back(p);
      continue;
    }
    std::vector<std::string> files;
    if (!frontend::listProgramFiles(p, files)) {
      io.err << fmt::format("{}: error: cannot read the folder\n", support::escapeForTerminal(p));
      ok = false;
      continue;
    }
    for (auto& f : files)
      if (!settings.excludes(f)) out.push_back(std::move(f));
  }
  return ok;
}

struct Job {
  std::string path;
  std::string original;
  std::string text;
  std::vector<diag::ByteEdit> edits;
  bool changed() const { return !edits.empty(); }
};

struct Plan {
  format::FormatOptions layout;
  std::optional<format::RenumberOptions> numbering;
};

/// Formats (and renumbers) one file. False when it cannot be renumbered (the reason printed).
bool formatOne(const Plan& plan, Job& job, Io& io) {
  const std::string shown = support::escapeForTerminal(job.path);
  std::string text = job.original;
  if (plan.numbering) {
    auto r = format::renumber(job.original, *plan.numbering);
    if (!r) {
      const auto& e = r.error();
      io.err << fmt::format("{}{}: error: cannot renumber: {}; nothing was written\n", shown,
                            e.where.empty() ? "" : fmt::format(":{}", e.where), e.message);
      return false;
    }
    text = std::move(*r);
  }
  const auto result = format::formatLines(text, plan.layout);
  for (const auto& n : result.notes)
    io.err << fmt::format("{}{}: note: {}\n", shown, n.line == 0 ? "" : fmt::format(":{}", n.line), n.message);
  auto a = format::assemble(job.original, result.lines);
  job.text = std::move(a.text);
  job.edits = std::move(a.edits);
  return true;
}

int usage(Io& io, const std::string& message) { return usageError(io, kTool, message); }

/// The options that make sense together; kExitOk or a usage error.
int checkOptions(const FormatOptions& o, Io& io) {
  if (o.paths.empty()) return usage(io, "no input: give program files, folders, or - for standard input");
  if (o.inPlace && (o.check || o.diff)) return usage(io, "-i cannot be combined with --check or --diff");
  if (o.renumberAll && o.renumber.empty()) return kExitOk; // the settings' numbering, else 10,10
  if (!o.renumber.empty() && !parseNumbering(o.renumber))
    return usage(io, fmt::format("--renumber '{}': expected START[,STEP], whole numbers of at most 9 digits "
                                 "(STEP at least 1)",
                                 support::escapeForTerminal(o.renumber)));
  return kExitOk;
}

std::optional<Plan> makePlan(const FormatOptions& o, const Settings& settings, const machine::Machine& m, Io& io) {
  Plan plan;
  plan.layout = layoutOf(settings, m);
  std::string spec = o.renumber;
  if (spec.empty() && settings.format.renumber) spec = *settings.format.renumber;
  const bool all = o.renumberAll || settings.format.renumberAll.value_or(false);
  if (spec.empty() && all) spec = "10,10";
  if (spec.empty()) return plan;
  auto n = parseNumbering(spec);
  if (!n) {
    io.err << fmt::format("{}: error: 'format.renumber' must be \"START[,STEP]\"\n",
                          support::escapeForTerminal(settings.path));
    return std::nullopt;
  }
  plan.numbering = format::RenumberOptions{n->start, n->step, all, plan.layout.lex};
  return plan;
}

/// -i: each changed file written atomically (standard input printed), never onto the settings
/// or the machine file, never one file twice.
int writeInPlace(const std::vector<Job>& jobs, const CommonOptions& common, Io& io) {
  std::vector<OutputPath> outputs;
  for (const auto& j : jobs)
    if (j.path != kStdinName) outputs.push_back({"-i", j.path});
  std::vector<std::string> inputs;
  if (!common.machinePath.empty()) inputs.push_back(common.machinePath);
  if (!common.settingsFile.empty()) inputs.push_back(common.settingsFile);
  if (int rc = checkOutputs(io, kTool, outputs, inputs); rc != kExitOk) return rc;
  int rc = kExitOk;
  for (const auto& j : jobs) {
    if (j.path == kStdinName) {
      io.out << j.text;
      continue;
    }
    if (!j.changed()) continue;
    if (auto st = support::writeFileAtomically(j.path, j.text); !st.ok()) {
      io.err << fmt::format("{}: error: cannot write the file: {}\n", support::escapeForTerminal(j.path),
                            st.error().message);
      rc = kExitUsage;
    }
  }
  return rc;
}

int show(const FormatOptions& o, const std::vector<Job>& jobs, Io& io) {
  if (o.inPlace) return writeInPlace(jobs, o.common, io);
  bool changed = false;
  for (const auto& j : jobs) {
    changed = changed || j.changed();
    if (o.diff) {
      if (j.changed()) {
        const std::string d = diag::unifiedDiff(j.original, j.edits, j.path);
        io.out << (useColor(o.common, io.outIsTty) ? diag::colorDiff(d) : d);
      }
    } else if (o.check) {
      if (j.changed()) io.out << support::escapeForTerminal(j.path) << "\n";
    } else {
      io.out << j.text;
    }
  }
  return o.check && changed ? kExitErrors : kExitOk;
}

} // namespace

FormattedBuffer formatBuffer(std::string_view text, const Settings& settings, const machine::Machine& machine,
                             LineSpan lines) {
  auto r = format::formatLines(text, layoutOf(settings, machine));
  if (lines.first != 0) { // the lines outside the span stay as written
    const auto phys = format::splitLines(text);
    for (size_t i = 0; i < r.lines.size() && i < phys.size(); ++i)
      if (!lines.contains(static_cast<uint32_t>(i + 1)))
        r.lines[i] = {false, std::string(text.substr(phys[i].begin, phys[i].end - phys[i].begin))};
  }
  auto a = format::assemble(text, r.lines);
  return {std::move(a.text), std::move(a.edits), r.keptAsWritten};
}

support::Expected<FormattedBuffer> formatBuffer(std::string_view text, const std::string& path, LintPolicies& policies,
                                                LineSpan lines) {
  const Settings* st = policies.settingsFor(path);
  if (!st) return support::Error{path, "the settings file cannot be used"};
  const machine::Machine* m = policies.machineFor(*st);
  if (!m) return support::Error{path, "the machine file cannot be used"};
  return formatBuffer(text, *st, *m, lines);
}

int runFormat(const FormatOptions& opts, Io& io) {
  FormatOptions o = opts;
  if (int rc = checkOptions(o, io); rc != kExitOk) return rc;
  if (!readStandardInput(o.paths, io, kTool)) return kExitUsage;
  Settings settings;
  if (!applySettings(o.common, o.paths.front(), settings, io)) return kExitUsage;
  auto m = loadMachine(o.common, io);
  if (!m) return kExitUsage;
  const auto plan = makePlan(o, settings, *m, io);
  if (!plan) return kExitUsage;
  std::vector<std::string> files;
  int rc = expandInputs(o.paths, settings, files, io) ? kExitOk : kExitUsage;
  std::vector<Job> jobs;
  bool refused = false;
  for (const auto& f : files) {
    auto text = support::readFile(f);
    if (!text) {
      io.err << fmt::format("{}: error: {}\n", support::escapeForTerminal(f), text.error().message);
      rc = kExitUsage;
      continue;
    }
    Job job{f, std::move(*text), {}, {}};
    if (!formatOne(*plan, job, io)) {
      refused = true;
      continue;
    }
    jobs.push_back(std::move(job));
  }
  if (refused) return kExitErrors; // nothing is written when a file cannot be renumbered
  const int shown = show(o, jobs, io);
  return rc != kExitOk ? rc : shown;
}

} // namespace iso::driver
