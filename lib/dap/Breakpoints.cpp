//! @file Breakpoints.cpp
//! @brief isosim --dap's breakpoints: lines (moved to the next line with a statement),
//!        subprograms and simulated times (function breakpoints), exceptions, conditions and
//!        hit counts; the steps.
#include <algorithm>
#include <cmath>
#include <cstdlib>

#include <fmt/format.h>

#include "dap/Session.h"
#include "sim/TraceWriter.h"
#include "support/CaseFold.h"
#include "support/Text.h"

namespace iso::dap {

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {
std::string trimmed(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t'))
    s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t'))
    s.remove_suffix(1);
  return std::string(s);
}

/// A function breakpoint's name as a simulated time: `t=12.5`, `time=12.5`, `12.5s`, `12.5 s`.
std::optional<double> timeName(const std::string& name) {
  std::string s = trimmed(name);
  for (const char* prefix : {"time=", "t="})
    if (s.size() > std::strlen(prefix) && support::iequals(s.substr(0, std::strlen(prefix)), prefix)) {
      s = trimmed(s.substr(std::strlen(prefix)));
      if (!s.empty() && (s.back() == 's' || s.back() == 'S')) s = trimmed(s.substr(0, s.size() - 1));
      break;
    }
  if (s.size() > 1 && (s.back() == 's' || s.back() == 'S') && name.find('=') == std::string::npos)
    s = trimmed(s.substr(0, s.size() - 1));
  else if (name.find('=') == std::string::npos)
    return std::nullopt; // a bare name is a subprogram
  if (s.empty() || s.find_first_not_of("0123456789.") != std::string::npos || s.find('.') != s.rfind('.') || s == ".")
    return std::nullopt;
  return std::strtod(s.c_str(), nullptr);
}

fs::path normal(const std::string& p) {
  std::error_code ec;
  fs::path a = fs::absolute(fs::path(p), ec).lexically_normal();
  fs::path c = fs::weakly_canonical(a, ec);
  return ec ? a : c;
}
} // namespace

bool HitCondition::holds(uint64_t hits) const {
  switch (op) {
  case Op::Always: return true;
  case Op::Eq: return hits == n;
  case Op::Gt: return hits > n;
  case Op::Ge: return hits >= n;
  case Op::Lt: return hits < n;
  case Op::Le: return hits <= n;
  case Op::Mod: return n > 0 && hits % n == 0;
  }
  return true;
}

std::optional<HitCondition> HitCondition::parse(const std::string& text) {
  std::string s = trimmed(text);
  HitCondition h;
  if (s.empty()) return h;
  struct Prefix {
    const char* text;
    Op op;
  };
  h.op = Op::Eq;
  for (const Prefix& p : {Prefix{">=", Op::Ge}, Prefix{"<=", Op::Le}, Prefix{"==", Op::Eq}, Prefix{">", Op::Gt},
                          Prefix{"<", Op::Lt}, Prefix{"%", Op::Mod}}) {
    const size_t n = std::strlen(p.text);
    if (s.compare(0, n, p.text) == 0) {
      h.op = p.op;
      s = trimmed(s.substr(n));
      break;
    }
  }
  if (s.empty() || s.size() > 12 || s.find_first_not_of("0123456789") != std::string::npos) return std::nullopt;
  h.n = std::strtoull(s.c_str(), nullptr, 10);
  if (h.op == Op::Mod && h.n == 0) return std::nullopt;
  return h;
}

bool Session::readConditions(const json& b, Breakpoint& bp) const {
  if (b.contains("condition") && b["condition"].is_string() && !trimmed(b["condition"].get<std::string>()).empty())
    bp.conditionText = b["condition"].get<std::string>(); // parsed when the program is loaded (compileCondition)
  if (b.contains("hitCondition") && b["hitCondition"].is_string()) {
    auto h = HitCondition::parse(b["hitCondition"].get<std::string>());
    if (!h) {
      bp.message = "hit count: write N (the Nth hit), ==N, >N, >=N, <N, <=N or %N (every Nth hit)";
      return false;
    }
    bp.hit = *h;
  }
  return true;
}

bool Session::compileCondition(Breakpoint& bp) const {
  if (bp.conditionText.empty() || bp.condition || !prepared_.image) return true;
  auto e = Expression::parse(bp.conditionText, *prepared_.machine, prepared_.image->image().z32());
  if (!e) {
    bp.verified = false;
    bp.message =
        fmt::format("condition: {}{}", e.error().where.empty() ? "" : e.error().where + ": ", e.error().message);
    return false;
  }
  bp.condition = std::move(*e);
  return true;
}

std::optional<uint32_t> Session::imageFile(const std::string& path) const {
  if (!prepared_.image) return std::nullopt;
  const image::Image& img = prepared_.image->image();
  const fs::path want = normal(path);
  std::optional<uint32_t> byName;
  int sameName = 0;
  std::vector<uint8_t> seen(img.strings.size(), 0);
  for (const image::LineEntry& le : img.lines) {
    if (le.file >= seen.size() || seen[le.file]) continue;
    seen[le.file] = 1;
    if (normal((base_ / img.strings[le.file]).string()) == want) return le.file;
    if (fs::path(img.strings[le.file]).filename() == want.filename()) {
      byName = le.file;
      ++sameName;
    }
  }
  if (sameName == 1) return byName; // an image moved away from its sources: the file name alone
  return std::nullopt;
}

std::string Session::clientPath(uint32_t fileString) const {
  const image::Image& img = prepared_.image->image();
  if (fileString >= img.strings.size()) return "";
  return clientPath(img.strings[fileString]);
}

std::string Session::clientPath(std::string_view file) const { return (base_ / file).lexically_normal().string(); }

bool Session::loaded(Breakpoint& bp) const {
  if (prepared_.image) return compileCondition(bp);
  bp.verified = false;
  bp.message = "the program is not loaded yet";
  return false;
}

void Session::resolveLine(Breakpoint& bp) {
  bp.entries.clear();
  bp.actualLine = 0;
  if (!loaded(bp)) return;
  const image::Image& img = prepared_.image->image();
  if (img.stripped()) {
    bp.verified = false;
    bp.message = "the image was compiled with --strip: it has no line table";
    return;
  }
  const std::optional<uint32_t> file = imageFile(bp.path);
  if (!file) {
    bp.verified = false;
    bp.message = "this file is not part of the program that runs";
    return;
  }
  // the first line at or after bp.line that has a statement
  uint32_t best = UINT32_MAX;
  for (const image::LineEntry& le : img.lines)
    if (le.file == *file && le.line >= static_cast<uint32_t>(bp.line)) best = std::min(best, le.line);
  if (best == UINT32_MAX) {
    bp.verified = false;
    bp.message = "no statement runs on or after this line";
    return;
  }
  for (uint32_t i = 0; i < img.lines.size(); ++i)
    if (img.lines[i].file == *file && img.lines[i].line == best) bp.entries.push_back(i);
  bp.actualLine = static_cast<int>(best);
  bp.message = best != static_cast<uint32_t>(bp.line)
                   ? fmt::format("moved to line {}, the next line with a statement", best)
                   : std::string();
  bp.verified = true;
}

void Session::resolveFunction(Breakpoint& bp) {
  bp.entries.clear();
  if (auto t = timeName(bp.function)) {
    if (!compileCondition(bp)) return;
    bp.time = *t;
    bp.verified = std::isfinite(*t) && *t > 0;
    bp.message = bp.verified ? "" : "a time breakpoint needs a time after 0 s";
    return;
  }
  if (!loaded(bp)) return;
  const image::Image& img = prepared_.image->image();
  for (const image::Proc& p : img.procs) {
    if (p.name >= img.strings.size() || !support::iequals(img.strings[p.name], trimmed(bp.function))) continue;
    for (uint32_t i = 0; i < img.lines.size(); ++i)
      if (img.lines[i].offset >= p.entry && img.lines[i].offset < p.entry + p.size) {
        bp.entries.push_back(i);
        break;
      }
    bp.verified = !bp.entries.empty();
    bp.message = bp.verified ? "" : "the subprogram has no line table (an image compiled with --strip)";
    if (bp.verified) bp.actualLine = static_cast<int>(img.lines[bp.entries.front()].line);
    return;
  }
  bp.verified = false;
  bp.message = "no subprogram or program of that name runs (or write t=SECONDS for a time)";
}

void Session::rebuildIndex() {
  bpsAt_.clear();
  const size_t rows = prepared_.image ? prepared_.image->image().lines.size() : 0;
  marked_.assign(rows, 0);
  auto add = [&](Breakpoint& bp) {
    if (!bp.verified) return;
    for (uint32_t e : bp.entries)
      if (e < rows) {
        marked_[e] = 1;
        bpsAt_[e].push_back(&bp);
      }
  };
  for (auto& [path, list] : lineBps_)
    for (Breakpoint& bp : list)
      add(bp);
  for (Breakpoint& bp : functionBps_)
    add(bp);
}

json Session::breakpointJson(const Breakpoint& bp) const {
  json j = {{"id", bp.id}, {"verified", bp.verified}};
  if (!bp.message.empty()) j["message"] = bp.message;
  if (!bp.path.empty()) {
    j["source"] = {{"path", bp.path}, {"name", fs::path(bp.path).filename().string()}};
    j["line"] = bp.actualLine > 0 ? bp.actualLine : bp.line;
  } else if (bp.actualLine > 0 && !bp.entries.empty() && prepared_.image) {
    const image::LineEntry& le = prepared_.image->image().lines[bp.entries.front()];
    const std::string path = clientPath(le.file);
    j["source"] = {{"path", path}, {"name", fs::path(path).filename().string()}};
    j["line"] = bp.actualLine;
  }
  return j;
}

json Session::setBreakpoints(const json& args) {
  if (!args.contains("source") || !args["source"].is_object() || !args["source"].contains("path") ||
      !args["source"]["path"].is_string())
    throw json::other_error::create(501, "setBreakpoints needs source.path", nullptr);
  const std::string path = args["source"]["path"].get<std::string>();
  json requested = json::array();
  if (args.contains("breakpoints") && args["breakpoints"].is_array())
    requested = args["breakpoints"];
  else if (args.contains("lines") && args["lines"].is_array())
    for (const json& l : args["lines"])
      requested.push_back({{"line", l}});
  if (requested.size() > kMaxBreakpoints)
    throw json::other_error::create(501, fmt::format("more than {} breakpoints in one file", kMaxBreakpoints), nullptr);
  std::vector<Breakpoint> list;
  for (const json& b : requested) {
    Breakpoint bp;
    bp.id = nextBpId_++;
    bp.path = path;
    bp.line = b.is_object() && b.contains("line") && b["line"].is_number_integer() ? b["line"].get<int>() : 0;
    if (bp.line < 1) {
      bp.message = "a breakpoint needs a line number from 1";
    } else if (b.is_object() && readConditions(b, bp)) {
      resolveLine(bp);
    }
    list.push_back(std::move(bp));
  }
  auto& slot = lineBps_[path];
  slot = std::move(list);
  json out = json::array();
  for (const Breakpoint& bp : slot)
    out.push_back(breakpointJson(bp));
  if (slot.empty()) lineBps_.erase(path);
  rebuildIndex();
  return {{"breakpoints", std::move(out)}};
}

json Session::setFunctionBreakpoints(const json& args) {
  std::vector<Breakpoint> list;
  if (args.contains("breakpoints") && args["breakpoints"].is_array()) {
    if (args["breakpoints"].size() > kMaxBreakpoints)
      throw json::other_error::create(501, "too many function breakpoints", nullptr);
    for (const json& b : args["breakpoints"]) {
      Breakpoint bp;
      bp.id = nextBpId_++;
      bp.function = b.is_object() && b.contains("name") && b["name"].is_string() ? b["name"].get<std::string>() : "";
      if (trimmed(bp.function).empty()) {
        bp.message = "a function breakpoint needs a name: a subprogram, or t=SECONDS";
      } else if (readConditions(b, bp)) {
        resolveFunction(bp);
      }
      list.push_back(std::move(bp));
    }
  }
  functionBps_ = std::move(list);
  json out = json::array();
  for (const Breakpoint& bp : functionBps_)
    out.push_back(breakpointJson(bp));
  rebuildIndex();
  return {{"breakpoints", std::move(out)}};
}

void Session::setExceptionBreakpoints(const json& args) {
  breakOnError_ = breakOnEmergency_ = false;
  if (args.contains("filters") && args["filters"].is_array())
    for (const json& f : args["filters"]) {
      if (f == "error") breakOnError_ = true;
      if (f == "emergency") breakOnEmergency_ = true;
    }
}

std::vector<int> Session::breakpointsHit(const sim::RunView& view, uint32_t lineEntry) {
  std::vector<int> hit;
  auto it = bpsAt_.find(lineEntry);
  if (it == bpsAt_.end()) return hit;
  for (Breakpoint* bp : it->second)
    if (stops(*bp, view)) hit.push_back(bp->id);
  return hit;
}

bool Session::stops(Breakpoint& bp, const sim::RunView& view) {
  if (bp.condition) {
    support::Expected<double> v = bp.condition->evaluate(view);
    if (!v) {
      output("stderr", fmt::format("isosim: breakpoint condition '{}': {}\n", bp.conditionText, v.error().message));
      return true; // an error stops: the programmer sees why
    }
    if (*v == 0) return false;
  }
  ++bp.hits;
  return bp.hit.holds(bp.hits);
}

bool Session::stepDone(const sim::RunView& view, uint32_t thread, size_t depth) const {
  if (thread != stepThread_) {
    // the stepped thread (a WHEN body) ended: the step ends at the next statement of any thread
    for (const sim::DebugThread& t : view.threads())
      if (t.id == stepThread_) return false;
    return true;
  }
  switch (step_) {
  case Step::In: return true;
  case Step::Over: return depth <= stepDepth_;
  case Step::Out: return depth < stepDepth_;
  case Step::None: return false;
  }
  return false;
}

} // namespace iso::dap
