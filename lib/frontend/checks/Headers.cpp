//! @file Headers.cpp
//! @brief E208: PROC and SEMI lines, and the unit names they give the file.
#include "frontend/checks/FileChecker.h"

#include <string>

namespace iso::frontend::checks {

using diag::Msg;

void FileChecker::checkHeaders() {
  const Stmt* first = nullptr;
  for (const Stmt& s : f_.stmts)
    if (s.kind != StmtKind::Empty) {
      first = &s;
      break;
    }
  if (f_.kind == UnitKind::Sub) {
    if (!first || (first->kind != StmtKind::Proc && first->kind != StmtKind::Invalid && !first->partial)) {
      diags_.report(Msg::ProcNotFirst, first ? first->loc : L(1), 1);
    } else if (first->kind == StmtKind::Proc) {
      f_.procName = f_.nameOf(*first).text;
    }
  }
  if (f_.kind == UnitKind::Semi && first) f_.semiName = std::string(f_.nameOf(*first).text);
  for (const Stmt& s : f_.stmts) {
    if (&s == first) continue;
    if (s.kind == StmtKind::Proc) diags_.report(Msg::ProcLater, s.loc, 1);
    if (s.kind == StmtKind::Semi) diags_.report(Msg::SemiLater, s.loc, 1);
  }
  if (first && first->kind == StmtKind::Proc && f_.kind != UnitKind::Sub) diags_.report(Msg::ProcInMain, first->loc, 1);
  if (first && first->kind == StmtKind::Semi && f_.kind == UnitKind::Sub) diags_.report(Msg::SemiInSub, first->loc, 1);
}

} // namespace iso::frontend::checks
