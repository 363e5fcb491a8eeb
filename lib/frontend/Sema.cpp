//! @file Sema.cpp
//! @brief The unit kind of a file, constant folding, and checkFile: the per-file checker
//!        (checks/) run on a whole parsed tree.
#include "frontend/Sema.h"

#include <optional>
#include <string_view>

#include "frontend/checks/FileChecker.h"
#include "support/CaseFold.h"

namespace iso::frontend {

static std::string_view extensionOf(std::string_view path) {
  size_t slash = path.find_last_of('/');
  size_t dot = path.find_last_of('.');
  if (dot == std::string_view::npos || (slash != std::string_view::npos && dot < slash)) return {};
  return path.substr(dot + 1);
}

UnitKind classifyUnit(const File& f) {
  std::string_view ext = extensionOf(f.path);
  const Stmt* first = nullptr;
  for (const Stmt& s : f.stmts)
    if (s.kind != StmtKind::Empty) {
      first = &s;
      break;
    }
  if (support::iequals(ext, "spf")) return UnitKind::Sub;
  if (first && first->kind == StmtKind::Semi) return UnitKind::Semi;
  if (support::iequals(ext, "mpf")) return UnitKind::Main;
  if (first && first->kind == StmtKind::Proc) return UnitKind::Sub;
  return UnitKind::Main;
}

std::optional<double> constValue(const File& f, ExprId e) {
  if (e == kNoExpr) return std::nullopt;
  const Expr& x = f.expr(e);
  switch (x.kind) {
  case ExprKind::Number: return x.value;
  case ExprKind::Neg: {
    auto a = constValue(f, x.a);
    if (!a) return std::nullopt;
    return -*a;
  }
  case ExprKind::Binary: {
    auto a = constValue(f, x.a);
    auto b = constValue(f, x.b);
    if (!a || !b) return std::nullopt;
    switch (static_cast<BinOp>(x.op)) {
    case BinOp::Add: return *a + *b;
    case BinOp::Sub: return *a - *b;
    case BinOp::Mul: return *a * *b;
    case BinOp::Div:
      if (*b == 0) return std::nullopt;
      return *a / *b;
    }
    return std::nullopt;
  }
  default: return std::nullopt;
  }
}

FileFlow checkFile(File& f, const SemaOptions& opts, diag::DiagnosticList& diags) {
  checks::FileChecker c(f, opts, diags);
  return c.run();
}

} // namespace iso::frontend
