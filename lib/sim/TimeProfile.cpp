//! @file TimeProfile.cpp
//! @brief Rendering of `isosim --profile` (text table and JSON).
#include "sim/TimeProfile.h"
#include "sim/TraceWriter.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

namespace iso::sim {

const char* timeCatName(TimeCat c) {
  switch (c) {
  case TimeCat::Accel: return "accel";
  case TimeCat::Cruise: return "cruise";
  case TimeCat::Decel: return "decel";
  case TimeCat::Dwell: return "dwell";
  case TimeCat::Plc: return "plc";
  case TimeCat::Inputs: return "inputs";
  case TimeCat::Block: return "block";
  case TimeCat::Stop: return "stop";
  case TimeCat::When: return "when";
  case TimeCat::Count: break;
  }
  return "?";
}

void ExactSum::add(double x) {
  const double t = sum_ + x;
  if (std::fabs(sum_) >= std::fabs(x))
    comp_ += (sum_ - t) + x;
  else
    comp_ += (x - t) + sum_;
  sum_ = t;
}

double TimeSplit::total() const {
  ExactSum s;
  for (const auto& p : parts)
    s.add(p.value());
  return s.value();
}

namespace {

/// The columns of the text table: the motion phases, then the waits; block, stop and when
/// are shown together as "other" (JSON keeps them apart).
std::string cells(const TimeSplit& t) {
  const double other = t.part(TimeCat::Block) + t.part(TimeCat::Stop) + t.part(TimeCat::When);
  return fmt::format("{:>11.6f} {:>10.6f} {:>10.6f} {:>10.6f} {:>10.6f} {:>10.6f} {:>10.6f} {:>10.6f}", t.total(),
                     t.part(TimeCat::Accel), t.part(TimeCat::Cruise), t.part(TimeCat::Decel), t.part(TimeCat::Dwell),
                     t.part(TimeCat::Plc), t.part(TimeCat::Inputs), other);
}

const char* kHeader = "{:<{}} {:>8} {:>11} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10}";

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) {
    if (!s.empty()) s += ", ";
    s += x;
  }
  return s;
}

nlohmann::ordered_json splitJson(const TimeSplit& t) {
  nlohmann::ordered_json j;
  j["total_s"] = t.total();
  for (size_t c = 0; c < kTimeCats; ++c)
    j[std::string(timeCatName(static_cast<TimeCat>(c))) + "_s"] = t.parts[c].value();
  return j;
}

} // namespace

std::vector<size_t> linesBySlowest(const TimeProfile& p) {
  std::vector<double> total(p.lines.size());
  for (size_t i = 0; i < p.lines.size(); ++i)
    total[i] = p.lines[i].time.total();
  std::vector<size_t> order(p.lines.size());
  std::iota(order.begin(), order.end(), size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    if (total[a] != total[b]) return total[a] > total[b];
    if (p.lines[a].file != p.lines[b].file) return p.lines[a].file < p.lines[b].file;
    return p.lines[a].line < p.lines[b].line;
  });
  return order;
}

std::string renderProfileText(const TimeProfile& p, size_t maxLines) {
  std::string out =
      fmt::format("profile: cycle time {:.6f} s (the main program's time, by line, slowest first)\n", p.cycleTimeS);
  std::vector<size_t> order = linesBySlowest(p);
  const size_t shown = maxLines == 0 ? order.size() : std::min(order.size(), maxLines);
  size_t w = 4;
  std::vector<std::string> names;
  for (size_t k = 0; k < shown; ++k) {
    const auto& l = p.lines[order[k]];
    names.push_back(l.line ? fmt::format("{}:{}", l.file, l.line) : l.file);
    w = std::max(w, names.back().size());
  }
  for (const auto& pr : p.procs)
    w = std::max(w, pr.name.size() + 2);
  out += fmt::format(fmt::runtime(kHeader), "line", w, "count", "total_s", "accel", "cruise", "decel", "dwell", "plc",
                     "inputs", "other");
  out += "  bound\n";
  for (size_t k = 0; k < shown; ++k) {
    const auto& l = p.lines[order[k]];
    out += fmt::format("{:<{}} {:>8} {}", names[k], w, l.count, cells(l.time));
    if (!l.bounds.empty()) out += "  " + join(l.bounds);
    out += "\n";
  }
  if (shown < order.size())
    out += fmt::format("... and {} more lines (--profile-lines 0 shows all)\n", order.size() - shown);
  out += fmt::format("{:<{}} {:>8} {}\n", "total", w, "", cells(p.total));
  if (!p.procs.empty()) {
    out += "\n";
    out += fmt::format(fmt::runtime(kHeader), "program", w, "calls", "total_s", "accel", "cruise", "decel", "dwell",
                       "plc", "inputs", "other");
    out += "\n";
    for (const auto& pr : p.procs)
      out += fmt::format("{:<{}} {:>8} {}\n", pr.name, w, pr.calls, cells(pr.time));
  }
  if (!p.ms.empty()) {
    out += "\n";
    out += fmt::format("{:<{}} {:>8} {:>11} {:>10}\n", "M", w, "count", "waited_s", "running_s");
    for (const auto& m : p.ms)
      out += fmt::format("{:<{}} {:>8} {:>11.6f} {:>10.6f}\n", fmt::format("M{}", m.m), w, m.count, m.time.total(),
                         m.running.value());
  }
  return out;
}

nlohmann::ordered_json profileValue(const TimeProfile& p) {
  nlohmann::ordered_json j;
  j["format_version"] = kSummaryFormatVersion;
  j["cycle_time_s"] = p.cycleTimeS;
  j["total"] = splitJson(p.total);
  auto& lines = j["lines"] = nlohmann::ordered_json::array();
  for (const auto& l : p.lines) {
    nlohmann::ordered_json e = {{"file", l.file}, {"line", l.line}, {"count", l.count}};
    e.update(splitJson(l.time));
    e["bounds"] = l.bounds;
    lines.push_back(std::move(e));
  }
  auto& procs = j["programs"] = nlohmann::ordered_json::array();
  for (const auto& pr : p.procs) {
    nlohmann::ordered_json e = {{"name", pr.name}, {"file", pr.file}, {"calls", pr.calls}};
    e.update(splitJson(pr.time));
    procs.push_back(std::move(e));
  }
  auto& ms = j["m"] = nlohmann::ordered_json::array();
  for (const auto& m : p.ms) {
    nlohmann::ordered_json e;
    e["m"] = m.m;
    e["count"] = m.count;
    e["waited_s"] = m.time.total();
    e["running_s"] = m.running.value();
    ms.push_back(std::move(e));
  }
  return j;
}

std::string renderProfileJson(const TimeProfile& p) { return profileValue(p).dump(2); }

} // namespace iso::sim
