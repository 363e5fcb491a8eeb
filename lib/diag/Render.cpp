//! @file Render.cpp
//! @brief Text, JSON and SARIF renderers.
#include "diag/Render.h"

#include <algorithm>

#include <fmt/format.h>

namespace iso::diag {

Counts countOf(const std::vector<Diagnostic>& diags) {
  Counts c;
  for (const auto& d : diags) {
    if (d.severity == Severity::Error) ++c.errors;
    else if (d.severity == Severity::Warning) ++c.warnings;
    else ++c.infos;
  }
  return c;
}

namespace {
const char* kReset = "\x1b[0m";
const char* kBold = "\x1b[1m";
const char* colorOf(Severity s) {
  switch (s) {
  case Severity::Error: return "\x1b[1;31m";
  case Severity::Warning: return "\x1b[1;35m";
  case Severity::Info: return "\x1b[1;36m";
  }
  return "";
}

void snippet(std::string& out, const SourceManager& sm, const Loc& loc, uint32_t endLine, uint32_t endCol, bool color) {
  if (loc.line == 0) return;
  std::string_view text = sm.lineText(loc.file, loc.line);
  out += "  ";
  for (char ch : text) out.push_back(static_cast<unsigned char>(ch) < 0x20 && ch != '\t' ? ' ' : ch);
  out += "\n  ";
  uint32_t col = loc.col == 0 ? 1 : loc.col;
  for (uint32_t i = 1; i < col; ++i) out.push_back(i - 1 < text.size() && text[i - 1] == '\t' ? '\t' : ' ');
  if (color) out += "\x1b[1;32m";
  out.push_back('^');
  uint32_t len = (endLine == loc.line && endCol > col) ? endCol - col : 1;
  uint32_t maxLen = text.size() >= col ? static_cast<uint32_t>(text.size()) - col + 1 : 1;
  if (len > maxLen) len = maxLen;
  for (uint32_t i = 1; i < len; ++i) out.push_back('~');
  if (color) out += kReset;
  out.push_back('\n');
}

std::string where(const SourceManager& sm, const Loc& l) {
  if (l.line == 0) return sm.path(l.file);
  return fmt::format("{}:{}:{}", sm.path(l.file), l.line, l.col == 0 ? 1 : l.col);
}

std::string plural(size_t n, const char* one, const char* many) {
  return fmt::format("{} {}", n, n == 1 ? one : many);
}

std::string uriOf(const std::string& path) {
  std::string out;
  for (unsigned char c : path) {
    if ((c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') ||
        std::string_view("-._~/").find(static_cast<char>(c)) != std::string_view::npos)
      out.push_back(static_cast<char>(c));
    else
      out += fmt::format("%{:02X}", c);
  }
  return out;
}

const char* sarifLevel(Severity s) {
  switch (s) {
  case Severity::Error: return "error";
  case Severity::Warning: return "warning";
  case Severity::Info: return "note";
  }
  return "note";
}
} // namespace

std::string renderText(const std::vector<Diagnostic>& diags, const SourceManager& sm, bool color) {
  std::string out;
  for (const auto& d : diags) {
    const CodeInfo& ci = info(d.code);
    if (color) out += kBold;
    out += where(sm, d.loc);
    out += ": ";
    if (color) out += colorOf(d.severity);
    out += severityName(d.severity);
    out += ":";
    if (color) out += kReset;
    if (color) out += kBold;
    out += " ";
    out += d.message;
    if (color) out += kReset;
    out += fmt::format(" [{} {}]\n", ci.code, ci.name);
    snippet(out, sm, d.loc, d.endLine, d.endCol, color);
    for (const auto& n : d.notes) {
      out += "  ";
      if (color) out += kBold;
      out += where(sm, n.loc);
      out += ": ";
      if (color) out += "\x1b[1;36m";
      out += "note:";
      if (color) out += kReset;
      out += " ";
      out += n.message;
      out += "\n";
    }
  }
  return out;
}

std::string renderCountLine(const Counts& c, size_t files) {
  return fmt::format("{} checked: {}, {}, {}\n", plural(files, "file", "files"), plural(c.errors, "error", "errors"),
                     plural(c.warnings, "warning", "warnings"), plural(c.infos, "info", "infos"));
}

nlohmann::ordered_json renderJson(const std::vector<Diagnostic>& diags, const SourceManager& sm, size_t files) {
  using J = nlohmann::ordered_json;
  J arr = J::array();
  for (const auto& d : diags) {
    const CodeInfo& ci = info(d.code);
    J o;
    o["file"] = sm.path(d.loc.file);
    o["line"] = d.loc.line;
    o["column"] = d.loc.col;
    o["end_line"] = d.endLine;
    o["end_column"] = d.endCol;
    o["severity"] = severityName(d.severity);
    o["code"] = ci.code;
    o["name"] = ci.name;
    o["message"] = d.message;
    J notes = J::array();
    for (const auto& n : d.notes) {
      J nj;
      nj["file"] = sm.path(n.loc.file);
      nj["line"] = n.loc.line;
      nj["column"] = n.loc.col;
      nj["message"] = n.message;
      notes.push_back(std::move(nj));
    }
    o["notes"] = std::move(notes);
    arr.push_back(std::move(o));
  }
  Counts c = countOf(diags);
  J root;
  root["diagnostics"] = std::move(arr);
  root["files"] = files;
  root["errors"] = c.errors;
  root["warnings"] = c.warnings;
  root["infos"] = c.infos;
  return root;
}

uint32_t utf16Column(std::string_view line, uint32_t byteCol) {
  // UTF-8 lead bytes start a code point (two units for 4-byte sequences); continuation bytes
  // add nothing; a byte that is not valid UTF-8 (e.g. Latin-1 text) counts as one unit.
  uint32_t units = 0;
  const size_t n = std::min<size_t>(byteCol - 1, line.size());
  for (size_t i = 0; i < n;) {
    const auto b = static_cast<unsigned char>(line[i]);
    size_t len = b < 0x80 ? 1 : (b >> 5) == 0x6 ? 2 : (b >> 4) == 0xE ? 3 : (b >> 3) == 0x1E ? 4 : 0;
    bool ok = len > 0 && i + len <= line.size();
    for (size_t k = 1; ok && k < len; ++k) ok = (static_cast<unsigned char>(line[i + k]) & 0xC0) == 0x80;
    if (!ok) len = 1;
    units += ok && len == 4 ? 2 : 1;
    i += len;
  }
  // columns past the end of the line (an end column after the last byte) keep their distance
  const uint32_t beyond = byteCol - 1 > line.size() ? static_cast<uint32_t>(byteCol - 1 - line.size()) : 0;
  return units + beyond + 1;
}

nlohmann::ordered_json renderSarif(const std::vector<Diagnostic>& diags, const SourceManager& sm,
                                   const std::string& toolName, const std::string& version) {
  using J = nlohmann::ordered_json;
  J rules = J::array();
  for (size_t i = 0; i < codeCount(); ++i) {
    const CodeInfo& ci = info(static_cast<Code>(i));
    J r;
    r["id"] = ci.code;
    r["name"] = ci.name;
    r["shortDescription"] = {{"text", ci.description}};
    r["defaultConfiguration"] = {{"level", sarifLevel(ci.severity)}};
    r["helpUri"] = fmt::format("man:isolint(1)#{}", ci.code);
    rules.push_back(std::move(r));
  }
  // Columns are bytes in the diagnostics; SARIF counts UTF-16 code units (columnKind below).
  auto column = [&](uint32_t file, uint32_t line, uint32_t byteCol) -> uint32_t {
    if (byteCol == 0) return 1;
    if (line == 0) return byteCol;
    return utf16Column(sm.lineText(file, line), byteCol);
  };
  auto location = [&](const Loc& l, uint32_t endLine, uint32_t endCol) {
    J region;
    region["startLine"] = l.line == 0 ? 1 : l.line;
    region["startColumn"] = column(l.file, l.line, l.col);
    if (endLine >= l.line && endLine > 0) {
      region["endLine"] = endLine;
      region["endColumn"] = column(l.file, endLine, endCol);
    }
    J phys;
    phys["artifactLocation"] = {{"uri", uriOf(sm.path(l.file))}};
    phys["region"] = std::move(region);
    return J{{"physicalLocation", std::move(phys)}};
  };
  J results = J::array();
  for (const auto& d : diags) {
    const CodeInfo& ci = info(d.code);
    J r;
    r["ruleId"] = ci.code;
    r["ruleIndex"] = static_cast<size_t>(d.code);
    r["level"] = sarifLevel(d.severity);
    r["message"] = {{"text", d.message}};
    r["locations"] = J::array({location(d.loc, d.endLine, d.endCol)});
    if (!d.notes.empty()) {
      J rel = J::array();
      int id = 1;
      for (const auto& n : d.notes) {
        J l = location(n.loc, 0, 0);
        l["id"] = id++;
        l["message"] = {{"text", n.message}};
        rel.push_back(std::move(l));
      }
      r["relatedLocations"] = std::move(rel);
    }
    results.push_back(std::move(r));
  }
  J driver;
  driver["name"] = toolName;
  driver["version"] = version;
  driver["semanticVersion"] = version;
  driver["rules"] = std::move(rules);
  J run;
  run["tool"] = {{"driver", std::move(driver)}};
  run["columnKind"] = "utf16CodeUnits";
  run["results"] = std::move(results);
  J root;
  root["$schema"] = "https://json.schemastore.org/sarif-2.1.0.json";
  root["version"] = "2.1.0";
  root["runs"] = J::array({std::move(run)});
  return root;
}

} // namespace iso::diag
