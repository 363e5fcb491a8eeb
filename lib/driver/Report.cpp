//! @file Report.cpp
//! @brief The HTML page of `isosim --report`.
#include "driver/Report.h"

#include <algorithm>
#include <filesystem>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "sim/TraceWriter.h"
#include "support/Text.h"

namespace iso::driver {

namespace {

std::string seconds(double v) { return sim::formatNumber(v); }

constexpr const char* kStyle =
    R"(body{font-family:"DejaVu Sans",Arial,sans-serif;margin:24px;color:#222;max-width:1100px}
h1{font-size:22px}h2{font-size:18px;border-bottom:1px solid #ccc;padding-bottom:4px;margin-top:28px}
table{border-collapse:collapse;font-size:13px}th,td{padding:3px 8px;border-bottom:1px solid #e4e4e4;text-align:left}
td.n,th.n{text-align:right;font-variant-numeric:tabular-nums}.bad{color:#b00020;font-weight:bold}.ok{color:#1b7f3b;font-weight:bold}
.bar{display:inline-block;height:10px;background:#1f77b4;vertical-align:middle}svg{max-width:100%;height:auto}
)";

} // namespace

std::string renderReport(const ReportInput& in) {
  const sim::Summary& s = *in.summary;
  std::string o;
  o += "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n";
  o +=
      fmt::format("<title>{}</title>\n<style>\n{}</style>\n</head>\n<body>\n", support::escapeMarkup(in.title), kStyle);
  o += fmt::format("<h1>{}</h1>\n", support::escapeMarkup(in.title));

  // ---- summary
  o += "<section id=\"summary\">\n<h2>Summary</h2>\n<table>\n";
  o += fmt::format("<tr><th>program</th><td>{}</td></tr>\n", support::escapeMarkup(in.program));
  o += fmt::format("<tr><th>status</th><td class=\"{}\">{}</td></tr>\n", s.status == sim::Status::Ok ? "ok" : "bad",
                   sim::statusName(s.status));
  o += fmt::format("<tr><th>cycle time</th><td>{} s</td></tr>\n", seconds(s.cycleTimeS));
  o += fmt::format("<tr><th>blocks</th><td>{}</td></tr>\n", s.blocks);
  std::string pos;
  for (const auto& [axis, p] : s.finalPosition)
    pos += fmt::format("{}{}={}", pos.empty() ? "" : " ", axis, sim::formatNumber(p));
  o += fmt::format("<tr><th>final position</th><td>{}</td></tr>\n", support::escapeMarkup(pos));
  if (!s.message.empty())
    o += fmt::format("<tr><th>message</th><td class=\"bad\">{}</td></tr>\n", support::escapeMarkup(s.message));
  o += "</table>\n</section>\n";

  // ---- spindle and tool (z32): from the summary's JSON, where those fields are added
  const auto j = in.summaryJson.empty() ? sim::summaryValue(s) : nlohmann::ordered_json::parse(in.summaryJson);
  if (j.contains("spindle_on_s") || j.contains("tool_changes") || j.contains("tool")) {
    o += "<section id=\"machine-state\">\n<h2>Spindle and tool</h2>\n<table>\n";
    if (j.contains("spindle_on_s") && j["spindle_on_s"].is_number())
      o += fmt::format("<tr><th>spindle on</th><td>{} s</td></tr>\n", seconds(j["spindle_on_s"].get<double>()));
    if (j.contains("tool_changes"))
      o += fmt::format("<tr><th>tool changes</th><td>{}</td></tr>\n", support::escapeMarkup(j["tool_changes"].dump()));
    if (j.contains("tool"))
      o += fmt::format("<tr><th>tool at the end</th><td>{}</td></tr>\n", support::escapeMarkup(j["tool"].dump()));
    o += "</table>\n</section>\n";
  }

  // ---- warnings
  o += "<section id=\"warnings\">\n<h2>Warnings</h2>\n";
  if (s.warnings.empty()) {
    o += "<p>None.</p>\n";
  } else {
    o += "<ul>\n";
    for (const auto& w : s.warnings)
      o += fmt::format("<li>{}</li>\n", support::escapeMarkup(w));
    o += "</ul>\n";
  }
  o += "</section>\n";

  // ---- plot
  o += "<section id=\"plot\">\n<h2>Plot</h2>\n";
  o += "<p>Position and velocity of the axes that move against time (per pixel: the minimum and the maximum), "
       "then the tool path in the plane of the program, coloured by path speed.</p>\n";
  std::string svg = in.plotSvg;
  if (svg.rfind("<svg", 0) == 0)
    o += svg;
  else
    o += "<p>No plot.</p>\n";
  o += "</section>\n";

  // ---- profile
  o += "<section id=\"profile\">\n<h2>Profile</h2>\n";
  if (!in.profile || in.profile->lines.empty()) {
    o += "<p>No line ran.</p>\n";
  } else {
    const sim::TimeProfile& p = *in.profile;
    std::vector<const sim::LineProfile*> rows;
    for (const auto& lp : p.lines)
      rows.push_back(&lp);
    std::stable_sort(rows.begin(), rows.end(), [](const sim::LineProfile* a, const sim::LineProfile* b) {
      return a->time.total() > b->time.total();
    });
    o += fmt::format("<p>Where the cycle time ({} s) goes, line by line, slowest first{}.</p>\n", seconds(p.cycleTimeS),
                     rows.size() > kReportMaxRows
                         ? fmt::format(" (the {} slowest of {} lines)", kReportMaxRows, rows.size())
                         : std::string());
    o += "<table>\n<tr><th>line</th><th class=\"n\">runs</th><th class=\"n\">time (s)</th><th class=\"n\">share</th>"
         "<th></th><th class=\"n\">accel</th><th class=\"n\">cruise</th><th class=\"n\">decel</th>"
         "<th class=\"n\">dwell</th><th class=\"n\">plc</th><th class=\"n\">inputs</th><th class=\"n\">other</th>"
         "<th>bounds</th></tr>\n";
    const double total = p.cycleTimeS > 0 ? p.cycleTimeS : 1;
    for (size_t i = 0; i < rows.size() && i < kReportMaxRows; ++i) {
      const sim::LineProfile& lp = *rows[i];
      const sim::TimeSplit& t = lp.time;
      const double share = t.total() / total;
      std::string bounds;
      for (const auto& b : lp.bounds)
        bounds += fmt::format("{}{}", bounds.empty() ? "" : ", ", b);
      const double other = t.part(sim::TimeCat::Block) + t.part(sim::TimeCat::Stop) + t.part(sim::TimeCat::When);
      o += fmt::format("<tr><td>{}</td><td class=\"n\">{}</td><td class=\"n\">{}</td><td class=\"n\">{:.1f}%</td>"
                       "<td><span class=\"bar\" style=\"width:{}px\"></span></td>",
                       support::escapeMarkup(lp.line ? fmt::format("{}:{}", lp.file, lp.line) : lp.file), lp.count,
                       seconds(t.total()), share * 100, static_cast<int>(std::clamp(share, 0.0, 1.0) * 120));
      for (sim::TimeCat c : {sim::TimeCat::Accel, sim::TimeCat::Cruise, sim::TimeCat::Decel, sim::TimeCat::Dwell,
                             sim::TimeCat::Plc, sim::TimeCat::Inputs})
        o += fmt::format("<td class=\"n\">{}</td>", seconds(t.part(c)));
      o += fmt::format("<td class=\"n\">{}</td><td>{}</td></tr>\n", seconds(other), support::escapeMarkup(bounds));
    }
    o += "</table>\n";
    if (rows.size() > kReportMaxRows)
      o += fmt::format("<p>{} faster lines are not listed.</p>\n", rows.size() - kReportMaxRows);
  }
  o += "</section>\n";
  o += fmt::format("<footer><p>Made by isosim from {}.</p></footer>\n</body>\n</html>\n",
                   support::escapeMarkup(std::filesystem::path(in.program).filename().string()));
  return o;
}

} // namespace iso::driver
