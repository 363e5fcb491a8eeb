//! @file Report.cpp
//! @brief The HTML page of `isosim --report`.
#include "driver/Report.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <string_view>
#include <utility>
#include <vector>

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
#source-view{position:sticky;top:0;z-index:1;background:#fffbe6;border:1px solid #e0c060;padding:6px 10px;font-size:13px}
#source-view pre{margin:0;font-family:"DejaVu Sans Mono",monospace}#source-view pre.cur{background:#ffe58a;font-weight:bold}
#source-view .where{font-weight:bold}polyline.path{cursor:pointer}polyline.path:hover{stroke-width:5}
polyline.path.selected{stroke:#000;stroke-width:5}tr[data-line]{cursor:pointer}tr.selected td{background:#ffe58a}
th[data-sort]{cursor:pointer;user-select:none}th[aria-sort=ascending]::after{content:" \25B2"}
th[aria-sort=descending]::after{content:" \25BC"}
)";

/// Links the views: a click on anything with data-line (a path segment, a profile row) marks
/// every element of that line and shows its source in #source-view; a click on a heading with
/// data-sort sorts the profile table; "#line=FILE:N" and "#sort=K" do the same on opening.
constexpr const char* kScript = R"(
(function () {
  var src = JSON.parse(document.getElementById('iso-source').textContent);
  var view = document.getElementById('source-view');
  var marked = [];
  function show(file, line) {
    marked.forEach(function (e) { e.classList.remove('selected'); });
    marked = Array.prototype.filter.call(document.querySelectorAll('[data-line="' + line + '"]'), function (e) {
      return e.getAttribute('data-file') === file && !view.contains(e);
    });
    marked.forEach(function (e) { e.classList.add('selected'); });
    var lines = src[file] || {};
    view.textContent = '';
    view.setAttribute('data-file', file);
    view.setAttribute('data-line', String(line));
    var h = document.createElement('div');
    h.className = 'where';
    h.textContent = file + ':' + line + (marked.length ? '' : ' (not drawn)');
    view.appendChild(h);
    if (!(line in lines)) {
      var p = document.createElement('pre');
      p.textContent = 'source not available';
      view.appendChild(p);
      return;
    }
    for (var k = line - 2; k <= line + 2; ++k) {
      if (!(k in lines)) continue;
      var d = document.createElement('pre');
      d.className = k === line ? 'line cur' : 'line';
      d.textContent = ('     ' + k).slice(-5) + '  ' + lines[k];
      view.appendChild(d);
    }
  }
  document.addEventListener('click', function (ev) {
    var t = ev.target.closest ? ev.target.closest('[data-line]') : null;
    if (!t || view.contains(t)) return;
    var line = parseInt(t.getAttribute('data-line'), 10);
    if (line > 0) show(t.getAttribute('data-file'), line);
  });
  var table = document.getElementById('profile-table');
  function sortBy(col, desc) {
    var heads = table.querySelectorAll('th');
    var num = heads[col].getAttribute('data-sort') === 'num';
    var body = table.tBodies[0];
    var rows = Array.prototype.slice.call(body.rows);
    function key(r) {
      var c = r.cells[col], v = c.getAttribute('data-v') || c.textContent;
      return num ? parseFloat(v) || 0 : v;
    }
    rows.sort(function (a, b) {
      var x = key(a), y = key(b), c = x < y ? -1 : x > y ? 1 : 0;
      return desc ? -c : c;
    });
    rows.forEach(function (r) { body.appendChild(r); });
    Array.prototype.forEach.call(heads, function (th, i) {
      if (i === col) th.setAttribute('aria-sort', desc ? 'descending' : 'ascending');
      else th.removeAttribute('aria-sort');
    });
  }
  if (table) {
    Array.prototype.forEach.call(table.querySelectorAll('th[data-sort]'), function (th, i) {
      th.addEventListener('click', function () {
        sortBy(i, th.getAttribute('aria-sort') === 'ascending');
      });
    });
  }
  var m = /line=([^&]*):(\d+)/.exec(decodeURIComponent(location.hash));
  if (m) show(m[1], parseInt(m[2], 10));
  var s = /sort=(-?)(\d+)/.exec(location.hash);
  if (s && table) sortBy(parseInt(s[2], 10), s[1] === '-');
})();
)";

/// An attribute value of our own SVG back to its text (escapeMarkup's five entities).
std::string unescapeAttribute(std::string_view v) {
  static constexpr std::pair<std::string_view, char> kEntities[] = {
      {"&amp;", '&'}, {"&lt;", '<'}, {"&gt;", '>'}, {"&quot;", '"'}, {"&#39;", '\''}};
  std::string out;
  for (size_t i = 0; i < v.size(); ++i) {
    bool done = false;
    for (const auto& [name, c] : kEntities)
      if (!done && v.substr(i, name.size()) == name) {
        out += c;
        i += name.size() - 1;
        done = true;
      }
    if (!done) out += v[i];
  }
  return out;
}

/// The lines of a text, without their line ends.
std::vector<std::string_view> textLines(std::string_view text) {
  std::vector<std::string_view> lines;
  while (!text.empty()) {
    const size_t nl = text.find('\n');
    std::string_view l = text.substr(0, nl);
    if (!l.empty() && l.back() == '\r') l.remove_suffix(1);
    lines.push_back(l);
    if (nl == std::string_view::npos) break;
    text.remove_prefix(nl + 1);
  }
  return lines;
}

/// The (file, line) pairs an SVG's path segments carry (data-file="F" data-line="N").
void svgLines(const std::string& svg, std::map<std::string, std::set<uint32_t>>& out) {
  const std::string fileKey = "data-file=\"", lineKey = "\" data-line=\"";
  for (size_t at = svg.find(fileKey); at != std::string::npos; at = svg.find(fileKey, at + 1)) {
    const size_t f0 = at + fileKey.size();
    const size_t f1 = svg.find('"', f0);
    if (f1 == std::string::npos || svg.compare(f1, lineKey.size(), lineKey) != 0) continue;
    const auto line = static_cast<uint32_t>(std::strtoul(svg.c_str() + f1 + lineKey.size(), nullptr, 10));
    if (line > 0) out[unescapeAttribute(std::string_view(svg).substr(f0, f1 - f0))].insert(line);
  }
}

/// The source lines the page links to, two either side, as the JSON of the script's data.
std::string sourceData(const ReportInput& in, const std::map<std::string, std::set<uint32_t>>& wanted) {
  nlohmann::ordered_json j = nlohmann::ordered_json::object();
  for (const auto& [file, lines] : wanted) {
    auto it = in.sources.find(file);
    if (it == in.sources.end()) continue;
    const std::vector<std::string_view> text = textLines(it->second);
    nlohmann::ordered_json& f = j[file];
    f = nlohmann::ordered_json::object();
    std::set<uint32_t> keep;
    for (uint32_t l : lines)
      for (uint32_t k = l > 2 ? l - 2 : 1; k <= l + 2; ++k)
        if (k <= text.size()) keep.insert(k);
    for (uint32_t k : keep)
      f[std::to_string(k)] = support::toValidUtf8(text[k - 1]);
  }
  std::string out = j.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
  // inside <script>: no "</" that could end it
  std::string safe;
  for (size_t i = 0; i < out.size(); ++i) {
    if (out[i] == '<' && i + 1 < out.size() && (out[i + 1] == '/' || out[i + 1] == '!')) {
      safe += "\\u003c";
      continue;
    }
    safe += out[i];
  }
  return safe;
}

/// The profile section: the slowest lines first, each row tagged with its file and line.
std::string profileSection(const ReportInput& in, std::map<std::string, std::set<uint32_t>>& wanted) {
  std::string o;
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
    o += "<table id=\"profile-table\">\n<thead><tr><th data-sort=\"text\">line</th>"
         "<th class=\"n\" data-sort=\"num\">runs</th><th class=\"n\" data-sort=\"num\" aria-sort=\"descending\">time "
         "(s)</th><th class=\"n\" data-sort=\"num\">share</th><th></th>";
    for (const char* h : {"accel", "cruise", "decel", "dwell", "plc", "inputs", "other"})
      o += fmt::format("<th class=\"n\" data-sort=\"num\">{}</th>", h);
    o += "<th data-sort=\"text\">bounds</th></tr></thead>\n<tbody>\n";
    const double total = p.cycleTimeS > 0 ? p.cycleTimeS : 1;
    for (size_t i = 0; i < rows.size() && i < kReportMaxRows; ++i) {
      const sim::LineProfile& lp = *rows[i];
      const sim::TimeSplit& t = lp.time;
      const double share = t.total() / total;
      std::string bounds;
      for (const auto& b : lp.bounds)
        bounds += fmt::format("{}{}", bounds.empty() ? "" : ", ", b);
      const double other = t.part(sim::TimeCat::Block) + t.part(sim::TimeCat::Stop) + t.part(sim::TimeCat::When);
      wanted[lp.file].insert(lp.line);
      // the line column sorts by file, then by line number (data-v)
      o += fmt::format("<tr data-file=\"{}\" data-line=\"{}\"><td data-v=\"{}\">{}</td><td class=\"n\">{}</td>"
                       "<td class=\"n\">{}</td><td class=\"n\">{:.1f}%</td>"
                       "<td><span class=\"bar\" style=\"width:{}px\"></span></td>",
                       support::escapeMarkup(lp.file), lp.line,
                       support::escapeMarkup(fmt::format("{}:{:010}", lp.file, lp.line)),
                       support::escapeMarkup(lp.line ? fmt::format("{}:{}", lp.file, lp.line) : lp.file), lp.count,
                       seconds(t.total()), share * 100, static_cast<int>(std::clamp(share, 0.0, 1.0) * 120));
      for (sim::TimeCat c : {sim::TimeCat::Accel, sim::TimeCat::Cruise, sim::TimeCat::Decel, sim::TimeCat::Dwell,
                             sim::TimeCat::Plc, sim::TimeCat::Inputs})
        o += fmt::format("<td class=\"n\">{}</td>", seconds(t.part(c)));
      o += fmt::format("<td class=\"n\">{}</td><td>{}</td></tr>\n", seconds(other), support::escapeMarkup(bounds));
    }
    o += "</tbody>\n</table>\n";
    if (rows.size() > kReportMaxRows)
      o += fmt::format("<p>{} faster lines are not listed.</p>\n", rows.size() - kReportMaxRows);
  }
  o += "</section>\n";
  return o;
}

} // namespace

std::string renderReport(const ReportInput& in) {
  const sim::Summary& s = *in.summary;
  std::map<std::string, std::set<uint32_t>> wanted; // the source lines the page links to
  std::string o;
  o += "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n";
  o +=
      fmt::format("<title>{}</title>\n<style>\n{}</style>\n</head>\n<body>\n", support::escapeMarkup(in.title), kStyle);
  o += fmt::format("<h1>{}</h1>\n", support::escapeMarkup(in.title));
  o += "<div id=\"source-view\"><div class=\"where\">Source</div><pre>A click on a path segment or a profile row "
       "shows its line here.</pre></div>\n";

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
       "then the tool path in each plane it moves in, feed moves coloured by path speed, rapids grey and dashed. "
       "A click on a path segment shows its line.</p>\n";
  std::string svg = in.plotSvg;
  if (svg.rfind("<svg", 0) == 0)
    o += svg;
  else
    o += "<p>No plot.</p>\n";
  o += "</section>\n";

  o += profileSection(in, wanted);
  svgLines(in.plotSvg, wanted);
  o += fmt::format("<footer><p>Made by isosim from {}.</p></footer>\n",
                   support::escapeMarkup(std::filesystem::path(in.program).filename().string()));
  o += fmt::format("<script type=\"application/json\" id=\"iso-source\">{}</script>\n<script>{}</script>\n",
                   sourceData(in, wanted), kScript);
  o += "</body>\n</html>\n";
  return o;
}

} // namespace iso::driver
