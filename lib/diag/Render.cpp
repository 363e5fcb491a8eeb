//! @file Render.cpp
//! @brief Text, JSON and SARIF renderers (streaming).
#include "diag/Render.h"

#include <algorithm>
#include <functional>
#include <ostream>
#include <sstream>
#include <unordered_map>

#include <fmt/format.h>

#include "diag/RuleDocs.h"
#include "support/Bytes.h"
#include "support/Text.h"

namespace iso::diag {

using J = nlohmann::ordered_json;
using support::appendEscaped;
using support::toValidUtf8;

namespace {
const char* kReset = "\x1b[0m";
const char* kBold = "\x1b[1m";
const char* kEllipsis = "\xE2\x80\xA6"; // …
const char* colorOf(Severity s) {
  switch (s) {
  case Severity::Error: return "\x1b[1;31m";
  case Severity::Warning: return "\x1b[1;35m";
  case Severity::Info: return "\x1b[1;36m";
  }
  return "";
}

bool isContinuation(char c) { return (static_cast<unsigned char>(c) & 0xC0) == 0x80; }

/// Appends `where` of a location, escaped: `file:line:col` (or the file alone for line 0).
void appendWhere(std::string& out, const SourceManager& sm, const Loc& l) {
  appendEscaped(out, sm.path(l.file));
  if (l.line != 0) out += fmt::format(":{}:{}", l.line, l.col == 0 ? 1 : l.col);
}

void snippet(std::string& out, const SourceManager& sm, const Loc& loc, uint32_t endLine, uint32_t endCol, bool color) {
  if (loc.line == 0) return;
  std::string_view text = sm.lineText(loc.file, loc.line);
  const uint32_t col = loc.col == 0 ? 1 : loc.col;
  const uint32_t len = (endLine == loc.line && endCol > col) ? endCol - col : 1;
  size_t caret = 0, underline = 1;
  std::string prefix;
  std::string window = sourceWindow(text, col, len, TextRenderer::kWindowColumns, caret, underline);
  out += "  ";
  out += window;
  out += "\n  ";
  // the caret line repeats the window's tabs so that it lines up in any tab width
  size_t shown = 0;
  for (size_t i = 0; i < window.size() && shown < caret;) {
    if (window[i] == '\t') {
      out.push_back('\t');
      ++shown;
      ++i;
      continue;
    }
    size_t n = std::max<size_t>(1, support::utf8SequenceLength(window, i));
    out.push_back(' ');
    ++shown;
    i += n;
  }
  for (; shown < caret; ++shown)
    out.push_back(' ');
  if (color) out += "\x1b[1;32m";
  out.push_back('^');
  for (size_t i = 1; i < underline; ++i)
    out.push_back('~');
  if (color) out += kReset;
  out.push_back('\n');
}

std::string plural(size_t n, const char* one, const char* many) { return fmt::format("{} {}", n, n == 1 ? one : many); }

std::string uriOf(const std::string& path) {
  std::string out;
  for (char ch : path) {
    const auto c = static_cast<unsigned char>(ch);
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

/// JSON text of `j` (indent 2); never throws on text that is not UTF-8 (it is made valid first
/// where it enters, this is a second guard).
std::string dumpJson(const J& j) { return j.dump(2, ' ', false, J::error_handler_t::replace); }

/// Writes `doc` (indent 2) with the string `placeholder` in it replaced by an array whose
/// elements `next` yields one at a time, so that the array is never built in memory.
void writeWithStreamedArray(std::ostream& os, const J& doc, const std::string& placeholder,
                            const std::function<bool(J&)>& next) {
  const std::string text = dumpJson(doc);
  const std::string token = fmt::format("\"{}\"", placeholder);
  const size_t at = text.find(token);
  const size_t lineStart = text.rfind('\n', at) + 1;
  const size_t indent = text.find_first_not_of(' ', lineStart) - lineStart;
  os << std::string_view(text).substr(0, at);
  std::string inner(indent + 3, ' ');
  inner[0] = '\n';
  J item;
  bool first = true;
  while (next(item)) {
    os << (first ? "[" : ",") << inner;
    first = false;
    std::string s = dumpJson(item);
    size_t from = 0;
    for (size_t nl = s.find('\n'); nl != std::string::npos; nl = s.find('\n', from)) {
      os << std::string_view(s).substr(from, nl - from) << inner;
      from = nl + 1;
    }
    os << std::string_view(s).substr(from);
  }
  if (first)
    os << "[]";
  else
    os << '\n' << std::string(indent, ' ') << ']';
  os << std::string_view(text).substr(at + token.size());
}

constexpr const char* kArrayPlaceholder = "@@streamed-array@@";

J diagnosticJson(const Diagnostic& d, const SourceManager& sm) {
  const CodeInfo& ci = info(d.code);
  J o;
  o["file"] = toValidUtf8(sm.path(d.loc.file));
  o["line"] = d.loc.line;
  o["column"] = d.loc.col;
  o["end_line"] = d.endLine;
  o["end_column"] = d.endCol;
  o["severity"] = severityName(d.severity);
  o["code"] = ci.code;
  o["name"] = ci.name;
  o["message"] = toValidUtf8(d.message);
  J notes = J::array();
  for (const auto& n : d.notes) {
    J nj;
    nj["file"] = toValidUtf8(sm.path(n.loc.file));
    nj["line"] = n.loc.line;
    nj["column"] = n.loc.col;
    nj["message"] = toValidUtf8(n.message);
    notes.push_back(std::move(nj));
  }
  o["notes"] = std::move(notes);
  if (!d.fixes.empty()) { // only when there are some: diagnostics without keep their shape
    J fixes = J::array();
    for (const auto& f : d.fixes) {
      J edits = J::array();
      for (const auto& e : f.edits) {
        J ej;
        ej["line"] = e.start.line;
        ej["column"] = e.start.col;
        ej["end_line"] = e.endLine;
        ej["end_column"] = e.endCol;
        ej["replacement"] = toValidUtf8(e.replacement);
        edits.push_back(std::move(ej));
      }
      J fj;
      fj["description"] = toValidUtf8(f.description);
      fj["edits"] = std::move(edits);
      fixes.push_back(std::move(fj));
    }
    o["fixes"] = std::move(fixes);
  }
  return o;
}

/// Streams the elements of a vector through writeWithStreamedArray.
template <class T, class F> std::function<bool(J&)> each(const std::vector<T>& v, F make) {
  return [&v, make, i = size_t{0}](J& out) mutable {
    if (i >= v.size()) return false;
    out = make(v[i++]);
    return true;
  };
}

} // namespace

// ---- text

std::string sourceWindow(std::string_view line, uint32_t col, uint32_t len, size_t width, size_t& caretCol,
                         size_t& underline) {
  const size_t caretByte = std::min<size_t>(col == 0 ? 0 : col - 1, line.size());
  size_t start = 0, end = line.size();
  if (line.size() > width) {
    const size_t before = width * 2 / 5;
    start = caretByte > before ? caretByte - before : 0;
    end = std::min(line.size(), start + width);
    if (end - start < width) start = end > width ? end - width : 0;
    start = std::min(start, caretByte);
    while (start < caretByte && isContinuation(line[start]))
      ++start;
    while (end > caretByte && end < line.size() && isContinuation(line[end]))
      --end;
  }
  std::string out;
  size_t display = 0;
  if (start > 0) {
    out += kEllipsis;
    ++display;
  }
  const size_t ulEnd = std::min<size_t>(end, caretByte + std::max<uint32_t>(len, 1));
  caretCol = display;
  underline = 0;
  for (size_t i = start; i < end;) {
    if (i == caretByte) caretCol = display;
    size_t n = support::utf8SequenceLength(line, i);
    if (n == 0) n = 1;
    const size_t before = out.size();
    appendEscaped(out, line.substr(i, n));
    // display width: an escape is 4 columns a byte; a tab or a printable character is 1
    size_t w = out.compare(before, 2, "\\x") == 0 ? out.size() - before : 1;
    if (i >= caretByte && i < ulEnd) underline += w;
    display += w;
    i += n;
  }
  if (caretByte >= end) caretCol = display;
  if (end < line.size()) out += kEllipsis;
  if (underline == 0) underline = 1;
  return out;
}

void TextRenderer::flushHidden() {
  if (hiddenInFile_ > 0) {
    buf_.clear();
    buf_ += fmt::format("{} more diagnostic{} in ", hiddenInFile_, hiddenInFile_ == 1 ? "" : "s");
    appendEscaped(buf_, sm_.path(file_));
    buf_ += " (--max-diagnostics 0 shows all)\n";
    os_ << buf_;
  }
  hiddenInFile_ = 0;
  shownInFile_ = 0;
}

void TextRenderer::add(const Diagnostic& d) {
  if (d.loc.file != file_) {
    flushHidden();
    file_ = d.loc.file;
  }
  if (maxPerFile_ != 0 && shownInFile_ >= maxPerFile_) {
    ++hiddenInFile_;
    return;
  }
  ++shownInFile_;
  buf_.clear();
  const CodeInfo& ci = info(d.code);
  if (color_) buf_ += kBold;
  appendWhere(buf_, sm_, d.loc);
  buf_ += ": ";
  if (color_) buf_ += colorOf(d.severity);
  buf_ += severityName(d.severity);
  buf_ += ":";
  if (color_) buf_ += kReset;
  if (color_) buf_ += kBold;
  buf_ += " ";
  appendEscaped(buf_, d.message);
  if (color_) buf_ += kReset;
  buf_ += fmt::format(" [{} {}]\n", ci.code, ci.name);
  snippet(buf_, sm_, d.loc, d.endLine, d.endCol, color_);
  for (const auto& n : d.notes) {
    buf_ += "  ";
    if (color_) buf_ += kBold;
    appendWhere(buf_, sm_, n.loc);
    buf_ += ": ";
    if (color_) buf_ += "\x1b[1;36m";
    buf_ += "note:";
    if (color_) buf_ += kReset;
    buf_ += " ";
    appendEscaped(buf_, n.message);
    buf_ += "\n";
  }
  for (const auto& f : d.fixes) {
    buf_ += "  fix: ";
    appendEscaped(buf_, f.description);
    buf_ += "\n";
  }
  os_ << buf_;
}

void TextRenderer::finish() { flushHidden(); }

std::string renderText(const std::vector<Diagnostic>& diags, const SourceManager& sm, bool color) {
  std::ostringstream os;
  TextRenderer r(os, sm, color);
  for (const auto& d : diags)
    r.add(d);
  r.finish();
  return os.str();
}

std::string renderCountLine(const Counts& c, size_t files) {
  return fmt::format("{} checked: {}, {}, {}\n", plural(files, "file", "files"), plural(c.errors, "error", "errors"),
                     plural(c.warnings, "warning", "warnings"), plural(c.infos, "info", "infos"));
}

// ---- JSON

void writeJson(std::ostream& os, const std::vector<Diagnostic>& diags, const SourceManager& sm, size_t files,
               const std::vector<InputError>& inputErrors, const Counts* counts) {
  const Counts c = counts ? *counts : countOf(diags);
  J root;
  root["format_version"] = kLintJsonFormatVersion;
  root["diagnostics"] = kArrayPlaceholder;
  if (!inputErrors.empty()) {
    J errs = J::array();
    for (const auto& e : inputErrors)
      errs.push_back({{"file", toValidUtf8(e.path)}, {"message", e.message}});
    root["input_errors"] = std::move(errs);
  }
  root["files"] = files;
  root["errors"] = c.errors;
  root["warnings"] = c.warnings;
  root["infos"] = c.infos;
  writeWithStreamedArray(os, root, kArrayPlaceholder,
                         each(diags, [&](const Diagnostic& d) { return diagnosticJson(d, sm); }));
  os << "\n";
}

nlohmann::ordered_json renderJson(const std::vector<Diagnostic>& diags, const SourceManager& sm, size_t files) {
  std::ostringstream os;
  writeJson(os, diags, sm, files);
  return J::parse(os.str());
}

// ---- GitHub workflow commands

std::string githubEscape(std::string_view s, bool property) {
  std::string out;
  for (char c : s) {
    switch (c) {
    case '%': out += "%25"; break;
    case '\r': out += "%0D"; break;
    case '\n': out += "%0A"; break;
    case ':': out += property ? "%3A" : ":"; break;
    case ',': out += property ? "%2C" : ","; break;
    default: out.push_back(c);
    }
  }
  return out;
}

void writeGithub(std::ostream& os, const std::vector<Diagnostic>& diags, const SourceManager& sm) {
  std::string buf;
  for (const auto& d : diags) {
    const CodeInfo& ci = info(d.code);
    const char* kind = d.severity == Severity::Error ? "error" : d.severity == Severity::Warning ? "warning" : "notice";
    buf.clear();
    buf += fmt::format("::{} file={}", kind, githubEscape(support::escapeForTerminal(sm.path(d.loc.file)), true));
    if (d.loc.line != 0) {
      buf += fmt::format(",line={},col={}", d.loc.line, d.loc.col == 0 ? 1 : d.loc.col);
      if (d.endLine >= d.loc.line && d.endLine > 0) buf += fmt::format(",endLine={},endColumn={}", d.endLine, d.endCol);
    }
    buf += fmt::format(",title={}::", githubEscape(fmt::format("{} {}", ci.code, ci.name), true));
    std::string message = support::escapeForTerminal(d.message);
    for (const auto& n : d.notes)
      message += fmt::format("\n{}:{}: note: {}", support::escapeForTerminal(sm.path(n.loc.file)), n.loc.line,
                             support::escapeForTerminal(n.message));
    buf += githubEscape(message, false);
    buf += '\n';
    os << buf;
  }
}

// ---- SARIF

uint32_t utf16Column(std::string_view line, uint32_t byteCol) {
  // A code point counts one unit (two for 4-byte sequences); a byte that is not valid UTF-8
  // (e.g. Latin-1 text) counts as one unit.
  uint32_t units = 0;
  const size_t n = std::min<size_t>(byteCol - 1, line.size());
  for (size_t i = 0; i < n;) {
    size_t len = support::utf8SequenceLength(line, i);
    units += len == 4 ? 2 : 1;
    i += len == 0 ? 1 : len;
  }
  // columns past the end of the line (an end column after the last byte) keep their distance
  const uint32_t beyond = byteCol - 1 > line.size() ? static_cast<uint32_t>(byteCol - 1 - line.size()) : 0;
  return units + beyond + 1;
}

std::string sarifFingerprint(std::string_view ruleId, std::string_view path, std::string_view lineText,
                             size_t occurrence) {
  // FNV-1a over the rule, the file and the line's text with its blanks folded: stable when
  // other lines are added or removed, or the line is re-indented; `occurrence` tells apart the
  // same finding on identical lines of one file.
  support::Fnv1a h;
  const auto mix = [&h](unsigned char c) { h.byte(c); };
  for (char c : ruleId)
    mix(static_cast<unsigned char>(c));
  mix(0);
  for (char c : path)
    mix(static_cast<unsigned char>(c));
  mix(0);
  bool blank = true; // leading blanks dropped, runs folded to one
  for (char c : lineText) {
    const bool isBlank = c == ' ' || c == '\t' || c == '\r';
    if (isBlank) {
      blank = true;
      continue;
    }
    if (blank) mix(' ');
    blank = false;
    mix(static_cast<unsigned char>(c));
  }
  mix(0);
  return fmt::format("{:016x}:{}", h.value(), occurrence);
}

std::vector<std::string> findingFingerprints(const std::vector<Diagnostic>& diags, const SourceManager& sm) {
  std::vector<std::string> out;
  out.reserve(diags.size());
  std::unordered_map<std::string, size_t> seen; // fingerprint without occurrence -> count
  for (const auto& d : diags) {
    const CodeInfo& ci = info(d.code);
    const std::string_view path = sm.path(d.loc.file), line = sm.lineText(d.loc.file, d.loc.line);
    const std::string base = sarifFingerprint(ci.code, path, line, 0);
    out.push_back(sarifFingerprint(ci.code, path, line, seen[base]++));
  }
  return out;
}

namespace {
/// The rule table of every SARIF log (tool.driver.rules): the same for every run, built once.
const J& sarifRules() {
  static const J rules = [] {
    J all = J::array();
    for (size_t i = 0; i < codeCount(); ++i) {
      const CodeInfo& ci = info(static_cast<Code>(i));
      J r;
      r["id"] = ci.code;
      r["name"] = ci.name;
      r["shortDescription"] = {{"text", ci.description}};
      const RuleDoc& doc = ruleDoc(static_cast<Code>(i));
      r["fullDescription"] = {{"text", doc.text.empty() ? std::string(ci.description) : doc.text}};
      r["defaultConfiguration"] = {{"level", sarifLevel(ci.severity)}};
      r["help"] = {{"text", explainRule(static_cast<Code>(i))}, {"markdown", ruleHelpMarkdown(static_cast<Code>(i))}};
      all.push_back(std::move(r));
    }
    return all;
  }();
  return rules;
}
} // namespace

void writeSarif(std::ostream& os, const std::vector<Diagnostic>& diags, const SourceManager& sm,
                const std::string& toolName, const std::string& version, const std::vector<InputError>& inputErrors,
                const std::string& srcRoot, bool ruleTable) {
  // Relative paths are relative to SRCROOT (originalUriBaseIds), absolute ones are file URIs.
  auto artifact = [&](const std::string& path) {
    if (!path.empty() && path[0] == '/') return J{{"uri", fmt::format("file://{}", uriOf(path))}};
    if (srcRoot.empty()) return J{{"uri", uriOf(path)}};
    return J{{"uri", uriOf(path)}, {"uriBaseId", "SRCROOT"}};
  };
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
    phys["artifactLocation"] = artifact(sm.path(l.file));
    phys["region"] = std::move(region);
    return J{{"physicalLocation", std::move(phys)}};
  };
  const std::vector<std::string> fingerprints = findingFingerprints(diags, sm);
  size_t index = 0;
  auto result = [&](const Diagnostic& d) {
    const CodeInfo& ci = info(d.code);
    J r;
    r["ruleId"] = ci.code;
    r["ruleIndex"] = static_cast<size_t>(d.code);
    r["level"] = sarifLevel(d.severity);
    r["message"] = {{"text", toValidUtf8(d.message)}};
    r["locations"] = J::array({location(d.loc, d.endLine, d.endCol)});
    r["partialFingerprints"] = {{"isolint/v1", fingerprints[index++]}};
    if (!d.notes.empty()) {
      J rel = J::array();
      int id = 1;
      for (const auto& n : d.notes) {
        J l = location(n.loc, 0, 0);
        l["id"] = id++;
        l["message"] = {{"text", toValidUtf8(n.message)}};
        rel.push_back(std::move(l));
      }
      r["relatedLocations"] = std::move(rel);
    }
    if (!d.fixes.empty()) {
      J fixes = J::array();
      for (const auto& f : d.fixes) {
        J replacements = J::array();
        for (const auto& e : f.edits) {
          J region;
          region["startLine"] = e.start.line;
          region["startColumn"] = column(e.start.file, e.start.line, e.start.col);
          region["endLine"] = e.endLine;
          region["endColumn"] = column(e.start.file, e.endLine, e.endCol);
          replacements.push_back(
              {{"deletedRegion", std::move(region)}, {"insertedContent", {{"text", toValidUtf8(e.replacement)}}}});
        }
        J change;
        change["artifactLocation"] = artifact(sm.path(d.loc.file));
        change["replacements"] = std::move(replacements);
        J fj;
        fj["description"] = {{"text", toValidUtf8(f.description)}};
        fj["artifactChanges"] = J::array({std::move(change)});
        fixes.push_back(std::move(fj));
      }
      r["fixes"] = std::move(fixes);
    }
    return r;
  };
  J driver;
  driver["name"] = toolName;
  driver["version"] = version;
  driver["semanticVersion"] = version;
  if (ruleTable) driver["rules"] = sarifRules();
  J run;
  run["tool"] = {{"driver", std::move(driver)}};
  if (!inputErrors.empty()) {
    J notes = J::array();
    for (const auto& e : inputErrors) {
      J n;
      n["level"] = "error";
      n["message"] = {{"text", e.message}};
      n["locations"] = J::array({{{"physicalLocation", {{"artifactLocation", artifact(e.path)}}}}});
      notes.push_back(std::move(n));
    }
    run["invocations"] = J::array({{{"executionSuccessful", false}, {"toolExecutionNotifications", notes}}});
  }
  if (!srcRoot.empty()) {
    std::string root = uriOf(srcRoot);
    if (root.empty() || root.back() != '/') root += '/';
    run["originalUriBaseIds"] = {{"SRCROOT", {{"uri", fmt::format("file://{}", root)}}}};
  }
  run["columnKind"] = "utf16CodeUnits";
  run["results"] = kArrayPlaceholder;
  J root;
  root["$schema"] = "https://json.schemastore.org/sarif-2.1.0.json";
  root["version"] = "2.1.0";
  root["runs"] = J::array({std::move(run)});
  writeWithStreamedArray(os, root, kArrayPlaceholder, each(diags, result));
  os << "\n";
}

nlohmann::ordered_json renderSarif(const std::vector<Diagnostic>& diags, const SourceManager& sm,
                                   const std::string& toolName, const std::string& version) {
  std::ostringstream os;
  writeSarif(os, diags, sm, toolName, version);
  return J::parse(os.str());
}

} // namespace iso::diag
