//! @file Ast.cpp
//! @brief Names for AST enums.
#include "frontend/Ast.h"

#include "lang/Keywords.h"

namespace iso::frontend {

const char* unitKindName(UnitKind k) {
  switch (k) {
  case UnitKind::Main: return "main program";
  case UnitKind::Semi: return "semi-automatic program";
  case UnitKind::Sub: return "subprogram";
  }
  return "program";
}

const char* sysVarName(SysVar v) {
  // the spellings are string literals of lang/SysVars.def: NUL-terminated
  return lang::isSysVarId(static_cast<uint8_t>(v)) ? lang::sysVarInfo(v).name.data() : "$?";
}

const char* cmpOpText(CmpOp op) {
  switch (op) {
  case CmpOp::Gt: return ">";
  case CmpOp::Lt: return "<";
  case CmpOp::Eq: return "==";
  case CmpOp::Ge: return ">=";
  case CmpOp::Le: return "<=";
  case CmpOp::Ne: return "<>";
  }
  return "?";
}

std::string_view File::whenAxesOf(uint32_t stmt) const {
  const uint32_t i = byStmtIndex(whenAxes, stmt);
  if (i == kNoIndex) return {};
  return std::string_view(whenAxisLetters).substr(whenAxes[i].first, whenAxes[i].count);
}

const char* jumpKindName(JumpKind k) {
  switch (k) {
  // the spellings are string literals of lang/Keywords.def: NUL-terminated
  case JumpKind::Gotof: return lang::keywordInfo(lang::Keyword::Gotof).spelling.data();
  case JumpKind::Gotob: return lang::keywordInfo(lang::Keyword::Gotob).spelling.data();
  case JumpKind::Goto: break;
  }
  return lang::keywordInfo(lang::Keyword::Goto).spelling.data();
}

} // namespace iso::frontend

namespace iso::frontend {
// The records a CAM program of millions of lines holds one or several of per line.
static_assert(sizeof(Stmt) <= 52 && sizeof(Expr) <= 40 && sizeof(Item) <= 36);
} // namespace iso::frontend
