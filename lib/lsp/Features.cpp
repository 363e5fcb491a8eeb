//! @file Features.cpp
//! @brief Hover, navigation, symbols, completion, quick fixes and diagnostics as LSP JSON.
#include "lsp/Features.h"

#include <algorithm>
#include <vector>

#include <fmt/format.h>

#include "frontend/GoTarget.h"

#include "frontend/Lexer.h"
#include "lsp/FeaturesInternal.h"
#include "lsp/LanguageDocs.h"
#include "support/CaseFold.h"

namespace iso::lsp {

using frontend::Tok;
using frontend::Token;
using nlohmann::json;

using detail::Lexed;
using detail::lexFile;
using detail::location;
using detail::toJson;

namespace {

/// The token under (or just before) a byte location, with its neighbours on the logical line.
struct TokenAt {
  const Token* tok = nullptr;
  const Token* prev = nullptr;
  const Token* next = nullptr;
};

TokenAt tokenAt(const Lexed& lx, diag::Loc at) {
  TokenAt best;
  for (const auto& l : lx.lines) {
    if (at.line < l.firstLine || at.line > l.lastLine) continue;
    const auto& t = l.tokens;
    for (int pass = 0; pass < 2 && !best.tok; ++pass)
      for (size_t i = 0; i < t.size(); ++i) {
        if (t[i].kind == Tok::End || t[i].line != at.line) continue;
        bool inside = pass == 0 ? at.col >= t[i].col && at.col < t[i].col + t[i].len : at.col == t[i].col + t[i].len;
        if (!inside) continue;
        best.tok = &t[i];
        best.prev = i > 0 ? &t[i - 1] : nullptr;
        best.next = i + 1 < t.size() && t[i + 1].kind != Tok::End ? &t[i + 1] : nullptr;
        break;
      }
  }
  return best;
}

/// The token kind a keyword spelled `text` gets, or Tok::Ident.
Tok keywordTokOf(std::string_view text) {
  auto k = lang::findKeyword(text);
  return k ? frontend::keywordTok(*k) : Tok::Ident;
}

bool isJumpKeyword(const Token* t) { return t && frontend::isJumpTok(t->kind); }

/// What a name under the cursor refers to.
struct Target {
  enum Kind { None, Label, Subprogram } kind = None;
  std::string name;
  Range range; ///< of the name under the cursor
};

Target targetAt(const Analysis& a, uint32_t file, Position p, const Lexed& lx) {
  TokenAt at = tokenAt(lx, a.loc(file, p));
  Target t;
  if (!at.tok || !frontend::isNameTok(at.tok->kind) || frontend::isReservedTok(at.tok->kind)) return t;
  t.name = std::string(at.tok->text);
  t.range = a.range({file, at.tok->line, at.tok->col}, at.tok->len);
  bool label = isJumpKeyword(at.prev) || (at.next && at.next->kind == Tok::Colon);
  t.kind = label ? Target::Label : Target::Subprogram;
  return t;
}

Range nameRange(const Analysis& a, const diag::Loc& loc, std::string_view name) {
  return a.range(loc, static_cast<uint32_t>(name.size()));
}

json labelDefinitions(const Analysis& a, uint32_t file, std::string_view name) {
  json out = json::array();
  const auto& f = a.set.files[file];
  for (const auto& s : f.stmts)
    if (s.hasLabel() && support::iequals(f.labelOf(s).text, name))
      out.push_back(location(a, file, nameRange(a, f.labelOf(s).loc, f.labelOf(s).text)));
  return out;
}

json procDefinitions(const Analysis& a, std::string_view name) {
  json out = json::array();
  for (const auto& f : a.set.files)
    for (const auto& s : f.stmts)
      if (s.kind == frontend::StmtKind::Proc && support::iequals(f.nameOf(s).text, name))
        out.push_back(location(a, f.id, a.range(f.nameOf(s).loc, f.nameOf(s).len)));
  return out;
}

json markup(const std::string& text, bool markdown) {
  return {{"kind", markdown ? "markdown" : "plaintext"}, {"value", text}};
}

json severityJson(diag::Severity s) {
  switch (s) {
  case diag::Severity::Error: return 1;
  case diag::Severity::Warning: return 2;
  case diag::Severity::Info: return 3;
  }
  return 3;
}

// No codeDescription (optional in the protocol): the rules have no web page to link to; their
// text is in isolint(1) and `isolint --explain CODE`.
json diagnosticJson(const LineText& text, const std::vector<std::string>& uris, const diag::Diagnostic& d) {
  const diag::CodeInfo& info = diag::info(d.code);
  json j = {{"range", toJson(rangeIn(text, d.loc.file, d.loc.line, d.loc.col, d.endLine, d.endCol))},
            {"severity", severityJson(d.severity)},
            {"code", info.code},
            {"source", "isolint"},
            {"message", d.message}};
  if (!d.notes.empty()) {
    json related = json::array();
    for (const auto& n : d.notes) {
      uint32_t file = n.loc.file < uris.size() ? n.loc.file : d.loc.file;
      related.push_back({{"location",
                          {{"uri", file < uris.size() ? uris[file] : std::string()},
                           {"range", toJson(rangeIn(text, file, n.loc.line, n.loc.col, n.loc.line, n.loc.col + 1))}}},
                         {"message", n.message}});
    }
    j["relatedInformation"] = std::move(related);
  }
  return j;
}

LineText linesOf(const Analysis& a) {
  return [&a](uint32_t f, uint32_t l) { return f < a.set.sources.size() ? a.set.sources.lineText(f, l) : ""; };
}

json diagnosticJson(const Analysis& a, const diag::Diagnostic& d) { return diagnosticJson(linesOf(a), a.uris, d); }

} // namespace

json diagnosticsJson(const std::vector<diag::Diagnostic>& diags, const LineText& text,
                     const std::vector<std::string>& uris) {
  json out = json::array();
  for (const auto& d : diags)
    out.push_back(diagnosticJson(text, uris, d));
  return out;
}

json hover(const Analysis& a, uint32_t file, Position p, bool markdown) {
  Lexed lx;
  lexFile(a, file, lx);
  TokenAt at = tokenAt(lx, a.loc(file, p));
  if (!at.tok) return nullptr;
  const Token& t = *at.tok;
  std::optional<std::string> text;
  const bool z32 = a.dialect == machine::Dialect::Z32;
  if (z32 && t.kind == Tok::GoTarget) {
    text = hoverZ32Word("GO");
  } else if (z32 && t.kind == Tok::Word && t.addr[0] == 'G' && t.addr[1] == 0 && hoverZ32G(static_cast<int>(t.value))) {
    text = hoverZ32G(static_cast<int>(t.value));
  } else if (z32 && t.kind == Tok::Word && hoverZ32Word(t.addr)) {
    text = hoverZ32Word(t.addr);
  } else if (z32 && t.kind == Tok::Ident &&
             std::any_of(a.userParams.begin(), a.userParams.end(),
                         [&](const std::string& u) { return support::iequals(u, t.text); })) {
    text = hoverUserParam(support::upperCopy(t.text));
  } else if (z32 && t.kind == Tok::Word && t.addr[1] != 0 &&
             std::any_of(a.userParams.begin(), a.userParams.end(),
                         [&](const std::string& u) { return support::iequals(u, t.addr); })) {
    text = hoverUserParam(t.addr);
  } else if (z32 && frontend::isNameTok(t.kind) && hoverZ32Word(t.text)) {
    text = hoverZ32Word(t.text);
  } else if (t.kind == Tok::Word && t.addr[1] == 0) {
    const bool integer = !t.hasSep;
    if (t.addr[0] == 'G' && integer)
      text = hoverG(static_cast<int>(t.value))
                 .value_or(fmt::format("**G{}** — not a G code of this language (E310)", t.text));
    else if (t.addr[0] == 'M' && integer)
      text = hoverM(static_cast<int>(t.value));
    else if (t.addr[0] == 'R' && integer)
      text = hoverR(static_cast<long>(t.value));
  } else if (t.kind == Tok::SysVar) {
    text = hoverSysVar(frontend::sysVarName(t.sysvar));
  } else if (frontend::isNameTok(t.kind)) {
    if (support::iequals(t.text, "R") && at.next && at.next->kind == Tok::LBracket)
      text = hoverR(-1);
    else if (auto w = hoverWord(t.text))
      text = w;
    else {
      Target target = targetAt(a, file, p, lx);
      if (target.kind == Target::Label) {
        json defs = labelDefinitions(a, file, target.name);
        text = defs.empty() ? fmt::format("**{}** — label (not defined in this file)", target.name)
                            : fmt::format("**{}** — label, line {}", target.name,
                                          defs[0]["range"]["start"]["line"].get<uint32_t>() + 1);
      } else if (target.kind == Target::Subprogram) {
        for (const auto& f : a.set.files)
          if (f.kind == frontend::UnitKind::Sub && support::iequals(f.procName, target.name))
            text = fmt::format("**{}** — subprogram (`PROC {} SAVE` in {})", target.name, f.procName, f.path);
        if (!text)
          text = fmt::format("**{}** — call of a subprogram that the program set does not define", target.name);
      }
    }
  }
  if (!text) return nullptr;
  return {{"contents", markup(*text, markdown)}, {"range", toJson(a.range({file, t.line, t.col}, t.len))}};
}

json definition(const Analysis& a, uint32_t file, Position p) {
  Lexed lx;
  lexFile(a, file, lx);
  // z32: a GO target (or a range end) goes to the line the GO rule finds
  if (TokenAt at = tokenAt(lx, a.loc(file, p)); at.tok && at.tok->kind == Tok::GoTarget) {
    const uint32_t line = frontend::findGoLine(a.set.sources.file(file).text, at.tok->text).line;
    if (line == 0) return json::array();
    return json::array({location(a, file, a.range(file, line, 1, line, 1))});
  }
  Target t = targetAt(a, file, p, lx);
  if (t.kind == Target::Label) return labelDefinitions(a, file, t.name);
  if (t.kind == Target::Subprogram) return procDefinitions(a, t.name);
  return json::array();
}

json references(const Analysis& a, uint32_t file, Position p, bool includeDeclaration) {
  Lexed lx;
  lexFile(a, file, lx);
  Target t = targetAt(a, file, p, lx);
  if (detail::SiteAt at = detail::siteAt(a, file, p, lx); at.kind != detail::SiteAt::None) // GOP and KG names too
    t = {at.kind == detail::SiteAt::Label ? Target::Label : Target::Subprogram, std::string(at.site.text), {}};
  json out = json::array(), uses = json::array();
  auto add = [&](const detail::NameSite& site) {
    if (!support::iequals(site.text, t.name) || (site.definition && !includeDeclaration)) return;
    (site.definition ? out : uses).push_back(location(a, site.file, a.range(site.loc, site.len)));
  };
  if (t.kind == Target::Label) detail::forEachLabelSite(a, file, lx, add);
  if (t.kind == Target::Subprogram) detail::forEachSubprogramSite(a, add);
  for (auto& u : uses) // the definitions first
    out.push_back(std::move(u));
  return out;
}

json documentSymbols(const Analysis& a, uint32_t file) {
  constexpr int kModule = 2, kFunction = 12, kKey = 20;
  json out = json::array();
  const auto& f = a.set.files[file];
  for (const auto& s : f.stmts) {
    Range line = a.range(file, s.line, 1, s.lastLine, UINT32_MAX);
    auto symbol = [&](std::string name, int kind, const char* detail, Range sel) {
      out.push_back({{"name", std::move(name)},
                     {"kind", kind},
                     {"detail", detail},
                     {"range", toJson(line)},
                     {"selectionRange", toJson(sel)}});
    };
    if (const auto& name = f.nameOf(s); s.kind == frontend::StmtKind::Proc && !name.text.empty())
      symbol(std::string(name.text), kFunction, "PROC", a.range(name.loc, name.len));
    if (s.kind == frontend::StmtKind::Semi)
      symbol(f.semiName.empty() ? "SEMI" : f.semiName, kModule, "SEMI", a.range(s.loc, 4));
    if (const auto& label = f.labelOf(s); s.hasLabel() && !label.text.empty())
      symbol(std::string(label.text), kKey, "label", nameRange(a, label.loc, label.text));
  }
  return out;
}

json semanticTokenTypes() {
  return {"keyword", "function", "property", "parameter", "variable", "enumMember", "number"};
}

json semanticTokens(const Analysis& a, uint32_t file) {
  enum : uint32_t { kKeyword, kFunction, kProperty, kParameter, kVariable, kLabel, kNumber, kNone };
  Lexed lx;
  lexFile(a, file, lx);
  const std::string_view axes = a.axisLetters;
  json data = json::array();
  uint32_t prevLine = 0, prevChar = 0;
  for (const auto& l : lx.lines)
    for (size_t i = 0; i < l.tokens.size(); ++i) {
      const Token& t = l.tokens[i];
      uint32_t type = kNone;
      if (frontend::isKeywordTok(t.kind))
        type = kKeyword;
      else if (t.kind == Tok::SysVar)
        type = kVariable;
      else if (t.kind == Tok::Number)
        type = kNumber;
      else if (t.kind == Tok::Ident && i + 1 < l.tokens.size() && l.tokens[i + 1].kind == Tok::Colon)
        type = kLabel;
      else if (t.kind == Tok::Word && (t.addr[0] == 'G' || t.addr[0] == 'M') && t.addr[1] == 0)
        type = kFunction;
      else if (t.kind == Tok::Word && t.addr[0] == 'R' && t.addr[1] == 0)
        type = kParameter;
      else if (t.kind == Tok::Word && t.addr[1] == 0 && axes.find(t.addr[0]) != std::string_view::npos)
        type = kProperty;
      if (type == kNone || t.kind == Tok::End) continue;
      Range r = a.range(file, t.line, t.col, t.line, t.col + t.len);
      if (r.end.line != r.start.line || r.end.character <= r.start.character) continue;
      const uint32_t dLine = r.start.line - prevLine;
      const uint32_t dChar = dLine == 0 ? r.start.character - prevChar : r.start.character;
      for (uint32_t v : {dLine, dChar, r.end.character - r.start.character, type, 0u})
        data.push_back(v);
      prevLine = r.start.line;
      prevChar = r.start.character;
    }
  return {{"data", std::move(data)}};
}

json completion(const Analysis& a, uint32_t file, const TextDocument& doc, Position p) {
  constexpr int kFunction = 3, kProperty = 10, kVariable = 6, kKeyword = 14, kReference = 18, kConstant = 21;
  std::string_view line = doc.line(p.line);
  size_t end = byteColumn(line, p.character), start = end;
  auto identChar = [](char c) {
    return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_';
  };
  while (start > 0 && identChar(line[start - 1]))
    --start;
  if (start > 0 && line[start - 1] == '$') --start;
  const bool sysvarOnly = start < end && line[start] == '$';
  // The word before the one being typed: after a jump keyword only labels make sense.
  size_t w = start;
  while (w > 0 && (line[w - 1] == ' ' || line[w - 1] == '\t'))
    --w;
  size_t wEnd = w;
  while (w > 0 && identChar(line[w - 1]))
    --w;
  std::string_view before = line.substr(w, wEnd - w);
  const bool afterJump = w < start && wEnd < start && frontend::isJumpTok(keywordTokOf(before));
  Range replace{{p.line, utf16Column(line, start)}, {p.line, utf16Column(line, end)}};

  json items = json::array();
  auto add = [&](const std::string& label, int kind, const std::string& detail, const std::string& text) {
    json item = {{"label", label},
                 {"kind", kind},
                 {"detail", detail},
                 {"textEdit", {{"range", toJson(replace)}, {"newText", label}}}};
    if (!text.empty()) item["documentation"] = markup(text, true);
    items.push_back(std::move(item));
  };
  if (afterJump) {
    const auto& f = a.set.files[file];
    for (const auto& s : f.stmts)
      if (s.hasLabel() && !f.labelOf(s).text.empty())
        add(std::string(f.labelOf(s).text), kReference, fmt::format("label, line {}", s.line), "");
    return {{"isIncomplete", false}, {"items", std::move(items)}};
  }
  for (const auto& e : languageEntries()) {
    if (sysvarOnly && e.kind != EntryKind::SysVar) continue;
    int kind = e.kind == EntryKind::Keyword  ? kKeyword
               : e.kind == EntryKind::SysVar ? kVariable
               : e.kind == EntryKind::Item   ? kProperty
                                             : kConstant;
    add(e.label, kind, e.detail, e.doc);
  }
  if (!sysvarOnly && a.dialect == machine::Dialect::Z32)
    for (const auto& e : z32Entries())
      add(e.label, e.kind == EntryKind::GCode ? kConstant : kProperty, e.detail, e.doc);
  if (!sysvarOnly)
    for (const auto& f : a.set.files)
      if (f.kind == frontend::UnitKind::Sub && !f.procName.empty())
        add(std::string(f.procName), kFunction, fmt::format("subprogram ({})", f.path), "");
  return {{"isIncomplete", false}, {"items", std::move(items)}};
}

json codeActions(const Analysis& a, uint32_t file, Range range) {
  json out = json::array();
  for (const auto& d : a.set.diags.items()) {
    if (d.loc.file != file || d.loc.line == 0) continue;
    uint32_t last = std::max(d.loc.line, d.endLine);
    if (last < range.start.line + 1 || d.loc.line > range.end.line + 1) continue;
    // The fix-its of the diagnostic (Diagnostic::fixes, made by the frontend), as quick fixes
    // whose edits count UTF-16 units like every LSP position.
    bool first = true;
    for (const auto& fix : d.fixes) {
      json edits = json::array();
      for (const auto& e : fix.edits)
        edits.push_back({{"range", toJson(a.range(e.start.file, e.start.line, e.start.col, e.endLine, e.endCol))},
                         {"newText", e.replacement}});
      std::string title = fix.description; // a sentence in a menu: capitalised
      if (!title.empty()) title[0] = support::upperAscii(title[0]);
      out.push_back({{"title", std::move(title)},
                     {"kind", "quickfix"},
                     {"isPreferred", first},
                     {"diagnostics", json::array({diagnosticJson(a, d)})},
                     {"edit", {{"changes", {{a.uris[file], std::move(edits)}}}}}});
      first = false;
    }
  }
  return out;
}

json textEdits(const TextDocument& doc, const std::vector<diag::ByteEdit>& edits) {
  const std::string& text = doc.text();
  std::vector<diag::ByteEdit> runs;
  for (const auto& e : edits) {
    if (!runs.empty() && e.begin >= runs.back().end) {
      diag::ByteEdit& run = runs.back();
      const std::string_view between = std::string_view(text).substr(run.end, e.begin - run.end);
      if (between.empty() || between == "\n" || between == "\r\n") { // the next line: one edit
        run.replacement.append(between).append(e.replacement);
        run.end = e.end;
        continue;
      }
    }
    runs.push_back(e);
  }
  json out = json::array();
  for (const auto& r : runs)
    out.push_back({{"range", toJson(Range{doc.position(r.begin), doc.position(r.end)})}, {"newText", r.replacement}});
  return out;
}

} // namespace iso::lsp
