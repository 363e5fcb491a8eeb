//! @file FeaturesInternal.h
//! @brief What the feature files of the language server share (Features.cpp, Rename.cpp):
//!        LSP JSON of positions, a file lexed again, the token at a position, and the places a
//!        label or a subprogram name is written. Private to the area.
#pragma once

#include <cstdint>
#include <deque>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "frontend/Lexer.h"
#include "frontend/Sema.h"
#include "lsp/Workspace.h"

namespace iso::lsp::detail {

inline nlohmann::json toJson(Position p) { return {{"line", p.line}, {"character", p.character}}; }
inline nlohmann::json toJson(Range r) { return {{"start", toJson(r.start)}, {"end", toJson(r.end)}}; }
inline nlohmann::json location(const Analysis& a, uint32_t file, Range r) {
  return {{"uri", a.uris[file]}, {"range", toJson(r)}};
}

/// The tokens of one file, lexed again (the AST does not keep keywords and words).
struct Lexed {
  std::deque<std::string> owned;
  std::vector<frontend::Suppression> suppressions;
  diag::DiagnosticList diags;
  std::vector<frontend::LogicalLine> lines;
};

inline frontend::LexOptions lexOptions(const Analysis& a) {
  frontend::LexOptions lo;
  lo.dialect = a.dialect;
  lo.axisLetters = a.axisLetters;
  lo.userParams = a.userParams;
  return lo;
}

/// Lexes `text` (a file of the analysis, or a line made up to try a name) into `out`.
inline void lexText(const Analysis& a, std::string_view text, uint32_t file, Lexed& out) {
  frontend::Lexer lx(text, file, lexOptions(a), out.diags, out.suppressions, out.owned);
  frontend::LogicalLine l;
  while (lx.next(l))
    out.lines.push_back(std::move(l));
}
inline void lexFile(const Analysis& a, uint32_t file, Lexed& out) {
  lexText(a, a.set.sources.file(file).text, file, out);
}

/// Calls `fn(stmt)` for every statement of a file, the inner ones of THEN/DO included.
template <class Fn> void forEachStmt(const frontend::File& f, Fn&& fn) {
  for (const auto& s : f.stmts)
    fn(s);
  for (const auto& s : f.inner)
    fn(s);
}

/// Calls `fn(jump)` for every jump of a file: GOTO statements, IF ... GOTO, CASE branches.
template <class Fn> void forEachJump(const frontend::File& f, Fn&& fn) {
  forEachStmt(f, [&](const frontend::Stmt& s) {
    if (s.hasJump()) fn(f.jumpOf(s));
    if (s.kind == frontend::StmtKind::Case)
      for (const auto& arm : f.armsOf(s))
        fn(arm.jump);
  });
}

/// One place a label or a subprogram name is written.
struct NameSite {
  uint32_t file = 0;
  diag::Loc loc;
  uint32_t len = 1;        ///< bytes on its physical line
  std::string_view text;   ///< the name as written
  bool definition = false; ///< `Name:` of a label, the name after PROC
};

/// Calls `fn(site)` for every label of file `file`, defined (`Name:`) or jumped to. The
/// parser gives up on a line at its first error and may keep no jump of it (`IF R1 > GOTOF
/// L1`, a CASE with one bad branch, `IF c THEN GOTOF L1 )`): on such a line each name right
/// after GOTOF, GOTOB or GOTO (the lexer reads it as a name there whatever it looks like) is a
/// use too. `lx` is the file lexed again.
template <class Fn> void forEachLabelSite(const Analysis& a, uint32_t file, const Lexed& lx, Fn&& fn) {
  const frontend::File& f = a.set.files[file];
  for (const auto& s : f.stmts)
    if (const auto& l = f.labelOf(s); s.hasLabel() && !l.text.empty())
      fn(NameSite{file, l.loc, static_cast<uint32_t>(l.text.size()), l.text, true});
  std::set<std::pair<uint32_t, uint32_t>> kept; // line and column of the jumps of the tree
  forEachJump(f, [&](const frontend::Jump& j) {
    if (j.label.empty()) return;
    kept.insert({j.loc.line, j.loc.col});
    fn(NameSite{file, j.loc, j.len, j.label, false});
  });
  std::set<uint32_t> broken; // the first lines of the statements with an error
  for (const auto& s : f.stmts)
    if (s.kind == frontend::StmtKind::Invalid || (s.kind == frontend::StmtKind::Block && s.partial))
      broken.insert(s.line);
  for (const auto& l : lx.lines) {
    if (!broken.count(l.firstLine)) continue;
    for (size_t i = 0; i + 1 < l.tokens.size(); ++i) {
      const frontend::Token& name = l.tokens[i + 1];
      if (!frontend::isJumpTok(l.tokens[i].kind) || name.kind != frontend::Tok::Ident) continue;
      if (kept.count({name.line, name.col})) continue;
      fn(NameSite{file, {file, name.line, name.col}, name.len, name.text, false});
    }
  }
}

/// Calls `fn(site)` for every subprogram name of the set: after PROC, in calls (z32: GOP<name>
/// too) and in z32 KG<name> items.
template <class Fn> void forEachSubprogramSite(const Analysis& a, Fn&& fn) {
  for (const auto& f : a.set.files) {
    auto site = [&](const frontend::StmtName& n, bool definition) {
      if (!n.text.empty()) fn(NameSite{f.id, n.loc, n.len, n.text, definition});
    };
    for (const auto& s : f.stmts)
      if (s.kind == frontend::StmtKind::Proc) site(f.nameOf(s), true);
    frontend::forEachCall(
        f, nullptr, [&](const frontend::Stmt& s) { site(f.nameOf(s), false); },
        [](const frontend::Item&, const std::string&) {},
        [&](const frontend::Item& x, std::string_view) { site(f.names.at(static_cast<size_t>(x.code)), false); });
  }
}

/// The label or subprogram name written at `p` of `file`.
struct SiteAt {
  enum Kind { None, Label, Subprogram } kind = None;
  NameSite site;
};

/// The label (its definition or a jump to it) or subprogram name (after PROC, a call, a KG
/// item) at `p`; the cursor may also stand just after the name.
inline SiteAt siteAt(const Analysis& a, uint32_t file, Position p, const Lexed& lx) {
  const diag::Loc at = a.loc(file, p);
  SiteAt t;
  bool inside = false; // a name the cursor is in wins over one it ends
  auto consider = [&](SiteAt::Kind kind) {
    return [&, kind](const NameSite& s) {
      if (s.file != file || s.loc.line != at.line || at.col < s.loc.col || at.col > s.loc.col + s.len) return;
      const bool in = at.col < s.loc.col + s.len;
      if (t.kind != SiteAt::None && (inside || !in)) return;
      t = {kind, s};
      inside = in;
    };
  };
  forEachLabelSite(a, file, lx, consider(SiteAt::Label));
  forEachSubprogramSite(a, consider(SiteAt::Subprogram));
  return t;
}

} // namespace iso::lsp::detail
