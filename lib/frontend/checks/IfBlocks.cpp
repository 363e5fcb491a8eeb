//! @file IfBlocks.cpp
//! @brief E201: IF / ELSE / ENDIF matched, one walk that also resolves the jumps.
#include "frontend/checks/FileChecker.h"

#include <algorithm>

namespace iso::frontend::checks {

using diag::Msg;

void FileChecker::matchIf(OpenIfs& open, int32_t i, const Stmt& s) {
  std::vector<int32_t>& stack = open.stack;
  std::vector<int32_t>& elseOf = open.elseOf;
  if (isKind(s, StmtKind::If) && s.inner < 0 && !s.hasJump()) {
    stack.push_back(i);
    elseOf.push_back(-1);
  } else if (isKind(s, StmtKind::Else)) {
    if (stack.empty()) {
      diags_.report(Msg::IfElseWithoutIf, s.loc, 4);
    } else if (elseOf.back() >= 0) {
      auto& d = diags_.report(Msg::IfSecondElse, s.loc, 4);
      d.note(Msg::IfFirstElseNote, f_.stmts[static_cast<size_t>(elseOf.back())].loc);
    } else {
      elseOf.back() = i;
      flow_.match[static_cast<size_t>(stack.back())] = i;
    }
  } else if (isKind(s, StmtKind::EndIf)) {
    if (stack.empty()) {
      diags_.report(Msg::IfEndifWithoutIf, s.loc, 5);
    } else {
      int32_t ifIdx = stack.back();
      if (elseOf.back() >= 0) {
        flow_.match[static_cast<size_t>(elseOf.back())] = i;
      } else {
        flow_.match[static_cast<size_t>(ifIdx)] = i;
      }
      endifOf_.push_back({ifIdx, i});
      stack.pop_back();
      elseOf.pop_back();
    }
  }
}

void FileChecker::finishIfs(const OpenIfs& open) {
  for (int32_t idx : open.stack) {
    const Stmt& s = f_.stmts[static_cast<size_t>(idx)];
    diags_.report(Msg::IfWithoutEndif, s.loc, 2);
    flow_.match[static_cast<size_t>(idx)] = -1;
  }
  std::sort(endifOf_.begin(), endifOf_.end()); // inner IFs close first
}

/// E201 and the jumps in one walk over the statements (the labels are collected): each step
/// reads only what it keeps itself.
void FileChecker::matchIfsAndResolveJumps() {
  OpenIfs open;
  for (int32_t i = 0; i < n_; ++i) {
    Stmt& s = f_.stmts[static_cast<size_t>(i)];
    matchIf(open, i, s);
    resolveJumpsOf(i, s);
  }
  finishIfs(open);
}

} // namespace iso::frontend::checks
