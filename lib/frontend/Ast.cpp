//! @file Ast.cpp
//! @brief Names for AST enums.
#include "frontend/Ast.h"

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
  switch (v) {
#define X(e, s, a) \
  case SysVar::e: return s;
    ISO_SYSVARS(X)
#undef X
  }
  return "$?";
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

const char* jumpKindName(JumpKind k) {
  switch (k) {
  case JumpKind::Gotof: return "GOTOF";
  case JumpKind::Gotob: return "GOTOB";
  case JumpKind::Goto: return "GOTO";
  }
  return "GOTO";
}

} // namespace iso::frontend
