//! @file GoJumps.cpp
//! @brief z32 GO jumps and ranges (SPEC §4.7): each target resolved by the GO rule to its
//!        statement, E215 when no line is found (with the line the target nearly names).
#include "frontend/checks/FileChecker.h"

#include <algorithm>

#include "frontend/GoTarget.h"

namespace iso::frontend::checks {

using diag::Msg;

/// The statement whose first physical line is `line`; -1 when `line` continues a statement
/// (a `$` join) or holds none.
int32_t FileChecker::stmtAtLine(uint32_t line) const {
  auto it = std::lower_bound(f_.stmts.begin(), f_.stmts.end(), line,
                             [](const Stmt& s, uint32_t l) { return s.lastLine < l; });
  if (it == f_.stmts.end() || it->line != line) return -1;
  return static_cast<int32_t>(it - f_.stmts.begin());
}

/// The statement a GO target finds, or -1 after E215 (`from`: a range end searches at or after it).
int32_t FileChecker::resolveGoTarget(std::string_view text, const Loc& loc, uint32_t len, int32_t rangeStart) {
  const GoLineMatch m = findGoLine(f_.source, text);
  const uint32_t startLine = rangeStart >= 0 ? st(rangeStart).line : 0;
  int32_t found = m.line ? stmtAtLine(m.line) : -1;
  if (found >= 0 && (rangeStart < 0 || m.line >= startLine)) return found;
  auto& d = rangeStart < 0 ? diags_.report(Msg::GoTargetUnknown, loc, len, text)
                           : diags_.report(Msg::GoRangeEndUnknown, loc, len, startLine, text);
  if (m.line && found < 0) d.note(Msg::GoContinuationNote, L(m.line), text);
  if (m.line && found >= 0) {
    d.note(Msg::GoEndBeforeNote, L(m.line), text);
    if (uint32_t later = findGoLineFrom(f_.source, text, startLine); later)
      d.note(Msg::GoDuplicateNote, L(later), text, m.line);
  }
  if (m.blankCandidate) d.note(Msg::GoBlankNote, L(m.blankCandidate), text);
  return -1;
}

void FileChecker::resolveGos() {
  if (f_.gos.empty() || f_.source.empty()) return;
  for (int32_t i = 0; i < n_; ++i) {
    const Stmt& s = st(i);
    if (s.kind != StmtKind::Go) continue;
    GoJump& g = f_.goOf(s);
    g.target = resolveGoTarget(g.from, g.fromLoc, g.fromLen, -1);
    if (g.range && g.target >= 0) g.rangeEnd = resolveGoTarget(g.to, g.toLoc, g.toLen, g.target);
  }
}

} // namespace iso::frontend::checks
