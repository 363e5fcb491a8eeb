//! @file Compare.cpp
//! @brief `isosim NEW --compare OLD`: two profiled runs, their difference line by line.
#include "driver/Compare.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <ostream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "diag/Render.h"
#include "driver/Settings.h"
#include "driver/Simulate.h"
#include "sim/Run.h"
#include "sim/TraceWriter.h"
#include "support/File.h"
#include "support/Text.h"

namespace iso::driver {

namespace {

/// A line's text with its blanks collapsed and trimmed; a trailing CR dropped.
std::string normalise(std::string_view s) {
  std::string out;
  bool blank = false;
  for (char c : s) {
    if (c == ' ' || c == '\t' || c == '\r') {
      blank = true;
      continue;
    }
    if (blank && !out.empty()) out += ' ';
    blank = false;
    out += c;
  }
  return out;
}

/// The µs-rounded value every isosim output prints (so that JSON and text agree).
double rounded(double v) {
  std::string s = sim::formatNumber(v);
  return std::isfinite(v) ? std::stod(s) : v;
}

/// "12.5%" of the old value, or "" when there is none.
std::string percent(double diff, double base) {
  if (!(base > 0)) return "";
  return fmt::format("{:+.1f}%", diff / base * 100);
}

std::string signedNumber(double v) {
  std::string s = sim::formatNumber(v);
  return s[0] == '-' || s == "0" ? s : fmt::format("+{}", s);
}

/// The keys of one side's lines, in profile order.
std::vector<std::string> keysOf(const CompareSide& side) {
  const std::string mainFile = side.profile.procs.empty() ? std::string() : side.profile.procs.front().file;
  std::map<std::string, int> seen;
  std::vector<std::string> keys;
  for (size_t i = 0; i < side.profile.lines.size(); ++i) {
    const sim::LineProfile& lp = side.profile.lines[i];
    std::string base = i < side.n.size() && !side.n[i].empty()         ? side.n[i]
                       : i < side.text.size() && !side.text[i].empty() ? side.text[i]
                                                                       : fmt::format("{}:{}", lp.file, lp.line);
    // the main programs match each other whatever their names; subprograms by file name
    std::string key = lp.file == mainFile ? base : fmt::format("{}: {}", lp.file, base);
    const int k = ++seen[key];
    if (k > 1) key += fmt::format(" #{}", k);
    keys.push_back(std::move(key));
  }
  return keys;
}

nlohmann::ordered_json sideJson(const std::optional<LineChange::Side>& s) {
  if (!s) return nullptr;
  nlohmann::ordered_json j;
  j["file"] = s->file;
  j["line"] = s->line;
  j["count"] = s->count;
  j["time_s"] = rounded(s->timeS);
  return j;
}

nlohmann::ordered_json runJson(const CompareSide& s) {
  nlohmann::ordered_json j;
  j["program"] = s.program;
  j["summary"] = sim::summaryValue(s.summary);
  return j;
}

} // namespace

Comparison compareProfiles(const CompareSide& oldSide, const CompareSide& newSide, size_t maxLines) {
  Comparison c;
  c.oldSide = &oldSide;
  c.newSide = &newSide;
  c.differenceS = newSide.summary.cycleTimeS - oldSide.summary.cycleTimeS;
  std::map<std::string, LineChange> byKey;
  auto add = [&](const CompareSide& side, bool isNew) {
    const std::vector<std::string> keys = keysOf(side);
    for (size_t i = 0; i < keys.size(); ++i) {
      const sim::LineProfile& lp = side.profile.lines[i];
      LineChange& lc = byKey[keys[i]];
      lc.key = keys[i];
      LineChange::Side s{lp.file, lp.line, lp.count, lp.time.total()};
      if (isNew)
        lc.newLine = s;
      else
        lc.oldLine = s;
      if (i < side.text.size() && !side.text[i].empty() && (isNew || lc.text.empty())) lc.text = side.text[i];
    }
  };
  add(oldSide, false);
  add(newSide, true);
  std::vector<LineChange> all;
  for (auto& [key, lc] : byKey) {
    lc.changeS = (lc.newLine ? lc.newLine->timeS : 0) - (lc.oldLine ? lc.oldLine->timeS : 0);
    if (lc.oldLine && lc.newLine)
      ++c.matched;
    else if (lc.oldLine)
      ++c.onlyOld;
    else
      ++c.onlyNew;
    // a change below the printed resolution (1 µs) is no change
    if (rounded(std::abs(lc.changeS)) == 0) continue;
    ++c.changed;
    all.push_back(std::move(lc));
  }
  std::stable_sort(all.begin(), all.end(),
                   [](const LineChange& a, const LineChange& b) { return std::abs(a.changeS) > std::abs(b.changeS); });
  if (all.size() > maxLines) all.resize(maxLines);
  c.lines = std::move(all);
  return c;
}

std::optional<CycleBudget> parseBudget(const std::string& text) {
  std::string t = text;
  while (!t.empty() && t.back() == ' ')
    t.pop_back();
  CycleBudget b;
  b.given = text;
  if (!t.empty() && t.back() == '%') {
    b.percent = true;
  } else if (t.empty() || t.back() != 's') {
    return std::nullopt;
  }
  t.pop_back();
  while (!t.empty() && t.back() == ' ')
    t.pop_back();
  if (t.empty() || t.find_first_not_of("0123456789.") != std::string::npos || t.find('.') != t.rfind('.') || t == ".")
    return std::nullopt;
  b.value = std::stod(t);
  if (!std::isfinite(b.value)) return std::nullopt;
  return b;
}

void applyBudget(Comparison& c, const CycleBudget& budget) {
  c.budget = budget;
  c.allowedS = budget.allowedS(c.oldSide->summary.cycleTimeS);
  c.overBudget = rounded(c.differenceS) > rounded(c.allowedS);
}

namespace {
/// "budget  +0.785 s (2% of the old cycle time): exceeded by 0.4 s" (text and annotations).
std::string budgetLine(const Comparison& c, const char* gap = "  ") {
  const std::string what =
      c.budget->percent ? fmt::format(" ({} of the old cycle time)", c.budget->given) : std::string();
  const std::string verdict =
      c.overBudget ? fmt::format("exceeded by {} s", sim::formatNumber(c.differenceS - c.allowedS)) : "within";
  return fmt::format("budget{}+{} s{}: {}", gap, sim::formatNumber(c.allowedS), what, verdict);
}
} // namespace

std::string renderComparisonGithub(const Comparison& c, const std::string& dir) {
  // as isolint --format github writes them: control bytes escaped, then GitHub's escaping
  auto data = [](std::string_view s) { return diag::githubEscape(support::escapeForTerminal(s), false); };
  auto prop = [](std::string_view s) { return diag::githubEscape(support::escapeForTerminal(s), true); };
  const CompareSide& o = *c.oldSide;
  const CompareSide& n = *c.newSide;
  std::string pc = percent(c.differenceS, o.summary.cycleTimeS);
  std::string msg =
      fmt::format("{}: cycle time {} s, {} s{} against {} ({} s)", n.program, sim::formatNumber(n.summary.cycleTimeS),
                  signedNumber(c.differenceS), pc.empty() ? std::string() : fmt::format(" ({})", pc), o.program,
                  sim::formatNumber(o.summary.cycleTimeS));
  if (c.budget) msg += "; " + budgetLine(c, " ");
  std::string out = fmt::format("::{} title={}::{}\n", c.overBudget ? "error" : "notice",
                                prop(c.overBudget ? "cycle time over budget" : "cycle time"), data(msg));
  for (const LineChange& lc : c.lines) {
    if (!lc.newLine || !(lc.changeS > 0)) continue;
    const std::string file = (std::filesystem::path(dir) / lc.newLine->file).lexically_normal().string();
    const std::string what =
        lc.oldLine ? fmt::format("this line takes {} s longer: {} s, was {} s", sim::formatNumber(lc.changeS),
                                 sim::formatNumber(lc.newLine->timeS), sim::formatNumber(lc.oldLine->timeS))
                   : fmt::format("this new line takes {} s", sim::formatNumber(lc.newLine->timeS));
    out += fmt::format("::warning file={},line={},title={}::{}\n", prop(file), lc.newLine->line,
                       prop(fmt::format("cycle time {} s", signedNumber(lc.changeS))), data(what));
  }
  return out;
}

std::string renderComparisonText(const Comparison& c) {
  const CompareSide& o = *c.oldSide;
  const CompareSide& n = *c.newSide;
  auto run = [](const char* label, const CompareSide& s) {
    std::string status =
        s.summary.status == sim::Status::Ok ? "" : fmt::format(" ({})", sim::statusName(s.summary.status));
    return fmt::format("{}  {}  cycle time {} s{}\n", label, support::escapeForTerminal(s.program),
                       sim::formatNumber(s.summary.cycleTimeS), status);
  };
  std::string out = run("old", o) + run("new", n);
  std::string pc = percent(c.differenceS, o.summary.cycleTimeS);
  out += fmt::format("difference  {} s{}\n", signedNumber(c.differenceS),
                     pc.empty() ? std::string() : fmt::format(" ({})", pc));
  if (c.budget) out += budgetLine(c) + "\n";
  // both sides ran on the same machine, with the same overrides
  for (const auto& ov : n.summary.overrides)
    out += fmt::format("override  {}\n", support::escapeForTerminal(ov));
  out += fmt::format("\nlines: {} in both, {} only in the old program, {} only in the new one; {} changed their time\n",
                     c.matched, c.onlyOld, c.onlyNew, c.changed);
  if (c.lines.empty()) return out;
  out += c.lines.size() < c.changed ? fmt::format("the {} that changed most:\n", c.lines.size())
                                    : std::string("the lines that changed:\n");
  out += fmt::format("  {:>12}  {:>12}  {:>12}  {}\n", "change (s)", "old (s)", "new (s)", "line");
  for (const LineChange& lc : c.lines) {
    auto t = [](const std::optional<LineChange::Side>& s) {
      return s ? sim::formatNumber(s->timeS) : std::string("-");
    };
    // where the line is: in the new program, and in the old one when it was elsewhere (the
    // main programs' names differ, as a rule: only the line number tells)
    std::string where;
    if (lc.newLine) where = fmt::format("{}:{}", lc.newLine->file, lc.newLine->line);
    if (!lc.newLine)
      where = fmt::format("(old) {}:{}", lc.oldLine->file, lc.oldLine->line);
    else if (lc.oldLine && lc.oldLine->line != lc.newLine->line)
      where += fmt::format(" (old {}:{})", lc.oldLine->file, lc.oldLine->line);
    if (!lc.oldLine) where += " (new)";
    std::string text = lc.text.empty() ? lc.key : lc.text;
    if (text.size() > 60) text = text.substr(0, 57) + "...";
    out += fmt::format("  {:>12}  {:>12}  {:>12}  {}  {}\n", signedNumber(lc.changeS), t(lc.oldLine), t(lc.newLine),
                       support::escapeForTerminal(where), support::escapeForTerminal(text));
  }
  return out;
}

std::string renderComparisonJson(const Comparison& c) {
  nlohmann::ordered_json j;
  j["format_version"] = 1;
  j["old"] = runJson(*c.oldSide);
  j["new"] = runJson(*c.newSide);
  j["difference_s"] = rounded(c.differenceS);
  j["lines_matched"] = c.matched;
  j["lines_only_old"] = c.onlyOld;
  j["lines_only_new"] = c.onlyNew;
  j["lines_changed"] = c.changed;
  if (c.budget)
    j["budget"] = {{"given", c.budget->given}, {"allowed_s", rounded(c.allowedS)}, {"exceeded", c.overBudget}};
  auto& lines = j["lines"] = nlohmann::ordered_json::array();
  for (const LineChange& lc : c.lines) {
    nlohmann::ordered_json e;
    e["key"] = lc.key;
    e["text"] = lc.text;
    e["change_s"] = rounded(lc.changeS);
    e["old"] = sideJson(lc.oldLine);
    e["new"] = sideJson(lc.newLine);
    lines.push_back(std::move(e));
  }
  return j.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace) + "\n";
}

void describeLines(CompareSide& side, const image::Image& img) {
  std::map<std::pair<std::string, uint32_t>, std::string> nOf;
  for (const image::LineEntry& le : img.lines)
    if (le.hasN && le.file < img.strings.size())
      nOf[{image::printableName(img.strings[le.file]), le.line}] = fmt::format("N{}", sim::formatNumber(le.n));
  const std::filesystem::path dir = std::filesystem::path(side.program).parent_path();
  std::map<std::string, std::vector<std::string>> sources;
  side.n.clear();
  side.text.clear();
  for (const sim::LineProfile& lp : side.profile.lines) {
    auto it = nOf.find({lp.file, lp.line});
    side.n.push_back(it != nOf.end() ? it->second : std::string());
    auto src = sources.find(lp.file);
    if (src == sources.end()) {
      std::vector<std::string> lines;
      // only files beside the program or below it: an image names them, and an image is not trusted
      const std::filesystem::path rel(lp.file);
      const bool inside =
          rel.is_relative() && std::none_of(rel.begin(), rel.end(), [](const auto& c) { return c == ".."; });
      support::Expected<std::string> read = support::Error{};
      if (inside) read = support::readFile((dir / rel).string());
      if (read) {
        const std::string& text = *read;
        size_t at = 0;
        while (at <= text.size() && lines.size() < 10'000'000) {
          size_t nl = text.find('\n', at);
          if (nl == std::string::npos) nl = text.size();
          lines.push_back(normalise(std::string_view(text).substr(at, nl - at)));
          at = nl + 1;
        }
      }
      src = sources.emplace(lp.file, std::move(lines)).first;
    }
    side.text.push_back(lp.line >= 1 && lp.line <= src->second.size() ? src->second[lp.line - 1] : std::string());
  }
}

int runCompare(const SimulateOptions& opts, const machine::Machine& m, const Settings& settings, Io& io) {
  if (opts.format == "csv")
    return usageError(io, "isosim", "--compare prints text, JSON with --format json, or --format github");
  std::optional<CycleBudget> budget;
  if (!opts.budget.empty() && !(budget = parseBudget(opts.budget)))
    return usageError(io, "isosim",
                      fmt::format("--budget '{}': give a share of the old cycle time (2%) or seconds (1.5s)",
                                  support::escapeForTerminal(opts.budget)));
  for (const auto& [opt, path] : {std::pair<const char*, const std::string&>{"--plot", opts.plot},
                                  {"--timeline", opts.timeline},
                                  {"--report", opts.report}})
    if (!path.empty()) return usageError(io, "isosim", fmt::format("{} cannot be combined with --compare", opt));
  if (opts.summary || opts.profile)
    return usageError(io, "isosim", "--compare prints its own summary: drop --summary and --profile");
  const std::string output = opts.output == "-" ? std::string() : opts.output;
  const bool json = opts.format == "json" ||
                    (opts.format.empty() && output.size() >= 5 && output.compare(output.size() - 5, 5, ".json") == 0);
  auto checkOut = [&](const std::vector<std::string>& inputs) {
    return checkOutputs(io, "isosim", {{"-o", output}}, inputs);
  };
  if (int rc = checkOut({}); rc != kExitOk) return rc;
  CompareSide sides[2];
  // new first: its errors are the ones the user is working on
  const std::string* programs[2] = {&opts.program, &opts.compare};
  const std::vector<std::string> noPaths;
  for (int i = 0; i < 2; ++i) {
    CompareSide& side = sides[i];
    side.program = *programs[i];
    std::optional<image::VerifiedImage> img;
    std::string entry = opts.entry, compileError;
    if (int rc = loadProgram(side.program, i == 0 ? opts.paths : noPaths, opts.common, settings, m, io, checkOut, img,
                             entry, compileError);
        rc != kExitOk) {
      if (!compileError.empty()) io.err << fmt::format("isosim: {}\n", support::escapeForTerminal(compileError));
      return rc;
    }
    sim::SimOptions so = simOptions(opts, entry);
    so.profile = &side.profile;
    sim::SimResult res = sim::simulate(*img, m, so, nullptr);
    if (res.setupError != sim::SetupError::None) {
      io.err << fmt::format("{}: error: {}\n", support::escapeForTerminal(side.program),
                            support::escapeForTerminal(res.setupMessage));
      return kExitUsage;
    }
    side.summary = std::move(res.summary);
    side.summary.overrides = summaryOverrides(opts, so);
    describeLines(side, img->image());
  }
  Comparison c = compareProfiles(sides[1], sides[0]);
  if (budget) applyBudget(c, *budget);
  const std::string text = opts.format == "github"
                               ? renderComparisonGithub(c, std::filesystem::path(opts.program).parent_path().string())
                           : json ? renderComparisonJson(c)
                                  : renderComparisonText(c);
  if (!output.empty()) {
    if (support::Status w = support::writeFileAtomically(output, text); !w) {
      io.err << fmt::format("{}: error: cannot write the comparison: {}\n", support::escapeForTerminal(output),
                            w.why());
      return kExitUsage;
    }
  } else {
    io.out << text;
  }
  for (const CompareSide& s : sides) {
    if (s.summary.status == sim::Status::Ok) continue;
    io.err << "isosim: " << support::escapeForTerminal(s.summary.message) << "\n";
    return s.summary.status == sim::Status::Emergency ? kExitEmergency : kExitErrors;
  }
  if (c.overBudget) {
    io.err << fmt::format("isosim: the cycle time grew by {} s, over the budget of +{} s ({})\n",
                          sim::formatNumber(c.differenceS), sim::formatNumber(c.allowedS),
                          support::escapeForTerminal(c.budget->given));
    return kExitErrors;
  }
  return kExitOk;
}

} // namespace iso::driver
