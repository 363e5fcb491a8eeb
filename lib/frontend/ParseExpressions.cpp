//! @file ParseExpressions.cpp
//! @brief Expressions: AND/OR chains, comparisons, arithmetic, unary operators, operands (R
//!        parameters, system variables, groups), and E108's fix that parenthesises the
//!        comparisons of a condition (see ParserInternal.h for the split).
#include <string_view>
#include <utility>
#include <vector>

#include "frontend/Parser.h"
#include "frontend/ParserInternal.h"
#include "lang/Limits.h"
#include "support/CaseFold.h"

namespace iso::frontend {

using diag::Msg;
using parser_detail::describe;
using parser_detail::reportRIndex;

ExprId Parser::constExpr(const Token& t) {
  Expr& e = newExpr();
  // A number rejected by E101 has no trustworthy value: keep it out of the value checks.
  e.kind = t.tooManyDigits ? ExprKind::Error : ExprKind::Number;
  e.value = t.value;
  e.loc = locOf(t);
  e.len = clampLen(t.len);
  return lastExpr();
}

void Parser::requireLogicOperand(ExprId e, std::string_view op) {
  const Expr& x = ex(e);
  if ((x.paren && x.isBool) || x.kind == ExprKind::Not) return;
  if (op == "NOT") failWithFix(x.loc, x.len, parenthesiseComparisons(), Msg::NotOperandGroup);
  failWithFix(x.loc, x.len, parenthesiseComparisons(), Msg::LogicOperandGroup, op, op);
}

size_t Parser::matchingParen(size_t open, size_t to) const {
  const std::vector<Token>& t = *toks_;
  int depth = 0;
  for (size_t k = open; k < to; ++k) {
    if (t[k].kind == Tok::LParen || t[k].kind == Tok::LBracket) ++depth;
    if ((t[k].kind == Tok::RParen || t[k].kind == Tok::RBracket) && --depth == 0) return k;
  }
  return SIZE_MAX;
}

bool Parser::wrapOperands(size_t from, size_t to, std::vector<diag::Edit>& edits) const {
  // The operands of a chain of AND/OR at this level, each a comparison, a group or NOT group.
  const std::vector<Token>& t = *toks_;
  std::vector<std::pair<size_t, size_t>> operands;
  int depth = 0;
  size_t start = from;
  for (size_t k = from; k < to; ++k) {
    if (t[k].kind == Tok::LParen || t[k].kind == Tok::LBracket) ++depth;
    if (t[k].kind == Tok::RParen || t[k].kind == Tok::RBracket) --depth;
    if (depth < 0) return false;
    if (depth == 0 && (t[k].kind == Tok::KwAnd || t[k].kind == Tok::KwOr)) {
      operands.emplace_back(start, k);
      start = k + 1;
    }
  }
  if (depth != 0) return false;
  operands.emplace_back(start, to);
  const bool chain = operands.size() > 1;
  for (auto [a, b] : operands) {
    if (a >= b) return false;
    if (t[a].kind == Tok::KwNot) {
      // NOT applies to the group that follows; NOT R1 > 2 is left to the programmer.
      if (a + 1 >= b || t[a + 1].kind != Tok::LParen || matchingParen(a + 1, b) != b - 1) return false;
      if (!wrapOperands(a + 2, b - 1, edits)) return false;
      continue;
    }
    if (t[a].kind == Tok::LParen && matchingParen(a, b) == b - 1) {
      if (!wrapOperands(a + 1, b - 1, edits)) return false;
      continue;
    }
    // one comparison at this level, nothing else of a condition in it
    int comparisons = 0;
    depth = 0;
    for (size_t k = a; k < b; ++k) {
      const Tok kk = t[k].kind;
      if (kk == Tok::LParen || kk == Tok::LBracket) ++depth;
      if (kk == Tok::RParen || kk == Tok::RBracket) --depth;
      if (depth == 0 &&
          (kk == Tok::Gt || kk == Tok::Lt || kk == Tok::Eq || kk == Tok::Ge || kk == Tok::Le || kk == Tok::Ne))
        ++comparisons;
      if (kk == Tok::Assign || kk == Tok::Error || kk == Tok::End || kk == Tok::KwNot || kk == Tok::KwAnd ||
          kk == Tok::KwOr)
        return false;
    }
    if (comparisons != 1) return false; // a bare value (or two comparisons) has no safe fix
    if (!chain) continue;
    const Token& last = t[b - 1];
    if (last.joined) return false;
    edits.push_back({locOf(t[a]), t[a].line, t[a].col, "("});
    edits.push_back({Loc{file_.id, last.line, last.col + last.len}, last.line, last.col + last.len, ")"});
  }
  return true;
}

diag::Fix Parser::parenthesiseComparisons() const {
  diag::Fix fix{"parenthesise each comparison", {}};
  if (condStart_ == SIZE_MAX) return fix;
  const std::vector<Token>& t = *toks_;
  size_t end = condStart_;
  int depth = 0;
  for (; end < t.size() && t[end].kind != Tok::End; ++end) {
    const Token& k = t[end];
    if (depth == 0 && (k.kind == Tok::KwThen || k.kind == Tok::KwDo || isJumpTok(k.kind))) break;
    if (k.kind == Tok::LParen || k.kind == Tok::LBracket) ++depth;
    if (k.kind == Tok::RParen || k.kind == Tok::RBracket) --depth;
  }
  std::vector<diag::Edit> edits;
  if (!wrapOperands(condStart_, end, edits) || lineLength_ + edits.size() > Lexer::kMaxLineLength) return fix;
  fix.edits = std::move(edits);
  return fix;
}

void Parser::requireNumeric(ExprId e, diag::MsgRef<> where) {
  const Expr& x = ex(e);
  if (!x.isBool) return;
  failAt(x.loc, x.len, where);
}

ExprId Parser::binaryTail(ExprId a, ExprKind kind, uint8_t op, ExprId (Parser::*operand)(), diag::MsgRef<> where) {
  requireNumeric(a, where);
  ++i_;
  ExprId b = (this->*operand)();
  requireNumeric(b, where);
  const Loc loc = ex(a).loc; // before newExpr, which may move the records
  Expr& e = newExpr();
  e.kind = kind;
  e.op = op;
  e.isBool = kind == ExprKind::Compare;
  e.a = a;
  e.b = b;
  e.loc = loc;
  e.len = clampLen(spanLen(loc));
  return lastExpr();
}

ExprId Parser::parseLogicSeq() {
  ExprId a = parseRelation();
  bool first = true;
  while (is(Tok::KwAnd) || is(Tok::KwOr)) {
    const Token& opTok = tok();
    LogicOp op = is(Tok::KwAnd) ? LogicOp::And : LogicOp::Or;
    const char* opName = op == LogicOp::And ? "AND" : "OR";
    // Only the written operands must be groups: after the first operator, `a` is the
    // left-to-right result so far ((A) OR (B) AND (C) is ((A) OR (B)) AND (C), SPEC §3.2).
    if (first) requireLogicOperand(a, opName);
    first = false;
    ++i_;
    ExprId b = parseRelation();
    requireLogicOperand(b, opName);
    const Loc loc = ex(a).loc; // before newExpr, which may move the records
    Expr& e = newExpr();
    e.kind = ExprKind::Logic;
    e.op = static_cast<uint8_t>(op);
    e.isBool = true;
    e.a = a;
    e.b = b;
    e.loc = loc;
    e.len = clampLen(spanLen(loc));
    (void)opTok;
    a = lastExpr();
  }
  return a;
}

static bool relop(Tok k, CmpOp& op) {
  switch (k) {
  case Tok::Gt: op = CmpOp::Gt; return true;
  case Tok::Lt: op = CmpOp::Lt; return true;
  case Tok::Eq: op = CmpOp::Eq; return true;
  case Tok::Ge: op = CmpOp::Ge; return true;
  case Tok::Le: op = CmpOp::Le; return true;
  case Tok::Ne: op = CmpOp::Ne; return true;
  default: return false;
  }
}

ExprId Parser::parseRelation() {
  ExprId a = parseSum();
  CmpOp op;
  if (relop(tok().kind, op)) {
    a = binaryTail(a, ExprKind::Compare, static_cast<uint8_t>(op), &Parser::parseSum, Msg::BoolInComparison);
    CmpOp op2;
    if (relop(tok().kind, op2))
      fail(tok(), Msg::TwoComparisons, cmpOpText(op), cmpOpText(op2), cmpOpText(op), cmpOpText(op2));
  }
  if (tok().kind == Tok::Assign) failAt(locOf(tok()), 1, Msg::AssignInCondition);
  return a;
}

ExprId Parser::parseArith() {
  ExprId e = parseSum();
  requireNumeric(e, Msg::BoolInArithmeticTop);
  CmpOp op;
  if (relop(tok().kind, op)) fail(tok(), Msg::ComparisonInArithmetic, cmpOpText(op));
  return e;
}

ExprId Parser::parseSum() {
  ExprId a = parseUnary();
  for (;;) {
    BinOp op;
    switch (tok().kind) {
    case Tok::Plus: op = BinOp::Add; break;
    case Tok::Minus: op = BinOp::Sub; break;
    case Tok::Star: op = BinOp::Mul; break;
    case Tok::Slash: op = BinOp::Div; break;
    default: return a;
    }
    a = binaryTail(a, ExprKind::Binary, static_cast<uint8_t>(op), &Parser::parseUnary, Msg::BoolInArithmetic);
  }
}

ExprId Parser::parseUnary() {
  // Every nested group and unary operator passes here: the recursion depth is bounded.
  if (depth_ >= kMaxExprDepth) fail(tok(), Msg::NestedTooDeeply, kMaxExprDepth);
  ++depth_;
  ExprId e = parseSignedOperand();
  --depth_;
  return e;
}

ExprId Parser::parseSignedOperand() {
  checkErrorToken();
  const Token& t = tok();
  if (t.kind == Tok::Minus) {
    ++i_;
    ExprId a = parseUnary();
    requireNumeric(a, Msg::BoolAfterMinus);
    if (ex(a).kind == ExprKind::Number && !ex(a).paren) {
      ex(a).value = -ex(a).value;
      ex(a).loc = locOf(t);
      return a;
    }
    Expr& e = newExpr();
    e.kind = ExprKind::Neg;
    e.a = a;
    e.loc = locOf(t);
    return lastExpr();
  }
  if (t.kind == Tok::Plus) {
    ++i_;
    ExprId a = parseUnary();
    requireNumeric(a, Msg::BoolAfterPlus);
    return a;
  }
  if (is(Tok::KwNot)) {
    ++i_;
    ExprId a = parseUnary();
    requireLogicOperand(a, "NOT");
    Expr& e = newExpr();
    e.kind = ExprKind::Not;
    e.isBool = true;
    e.a = a;
    e.loc = locOf(t);
    e.len = clampLen(t.len);
    return lastExpr();
  }
  return parsePrimary();
}

ExprId Parser::parsePrimary() {
  checkErrorToken();
  const Token& t = tok();
  switch (t.kind) { // the common operands are built where they stay (see newExpr)
  case Tok::Number: ++i_; return constExpr(t);
  case Tok::Word:
    if (t.addr[0] == 'R' && t.addr[1] == 0) {
      if (t.value < 0) fail(t, Msg::NegatedR);
      int32_t index = -1; // when E101 was reported, or E301 is now
      if (!t.tooManyDigits) {
        if (t.hasSep || !lang::isRIndex(t.value))
          reportRIndex(diags_, locOf(t), t);
        else
          index = static_cast<int32_t>(t.value);
      }
      Expr& e = newExpr();
      e.kind = ExprKind::RParam;
      e.rIndex = index;
      e.loc = locOf(t);
      e.len = clampLen(t.len);
      ++i_;
      return lastExpr();
    }
    break;
  default: break;
  }
  Expr e;
  e.loc = locOf(t);
  e.len = clampLen(t.len);
  switch (t.kind) {
  case Tok::Word: fail(t, Msg::ExpectedOperand, describe(t));
  case Tok::Ident:
#define ISO_KEYWORD(Name, spelling, reserved) case Tok::Kw##Name:
#include "lang/Keywords.def"
    if (support::iequals(t.text, "R") && peekTok().kind == Tok::LBracket) {
      i_ += 2;
      e.kind = ExprKind::RIndirect;
      e.a = parseArith();
      expect(Tok::RBracket, Msg::ExpectedRIndirectClose);
      return addExpr(e);
    }
    if (z32() && (support::iequals(t.text, "PAR") || support::iequals(t.text, "PAL")) &&
        peekTok().kind == Tok::LBracket)
      return parseParAccess(t);
    if (const int up = userParamIndex(t.text); up >= 0) {
      e.kind = ExprKind::UserParam;
      e.rIndex = up;
      ++i_;
      return addExpr(e);
    }
    if (unsupportedIdent(t)) throw Abort{};
    fail(t, Msg::ExpectedOperand, describe(t));
  case Tok::SysVar: {
    e.sysvar = t.sysvar;
    ++i_;
    if (sysVarTakesAxis(t.sysvar)) {
      e.kind = ExprKind::SysAxis;
      e.axis = parseAxisInBrackets();
      e.len = clampLen(spanLen(e.loc)); // $aa_iw[X] whole
    } else {
      e.kind = ExprKind::SysIndex;
      expect(Tok::LBracket, Msg::ExpectedIndexBracket);
      e.a = parseArith();
      expect(Tok::RBracket, Msg::ExpectedRBracket);
    }
    return addExpr(e);
  }
  case Tok::LParen: {
    ++i_;
    ExprId inner = parseLogicSeq();
    if (tok().kind != Tok::RParen) failExpected(Msg::ExpectedRParen);
    ++i_;
    Expr& in = ex(inner);
    if (in.paren) {
      return inner; // ((x)) is (x)
    }
    in.paren = true;
    return inner;
  }
  case Tok::Hash: fail(t, Msg::UnsupportedMacro);
  case Tok::String: fail(t, Msg::UnsupportedStringExpr);
  default: failExpected(Msg::ExpectedOperand);
  }
}

} // namespace iso::frontend
