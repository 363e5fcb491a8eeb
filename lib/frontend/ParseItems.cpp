//! @file ParseItems.cpp
//! @brief The items of a block: address words (G, M, F, R1=, I J K, CR, axis words),
//!        assignments (X=, F=, R[]=), Pos[]= Posa[]= Fa[]=, M=NB(), written system variables,
//!        and where parsing resumes after a bad item (see ParserInternal.h for the split).
#include <algorithm>
#include <cstring>

#include "frontend/Parser.h"
#include "frontend/ParserInternal.h"
#include "lang/Addresses.h"
#include "lang/GCodes.h"
#include "lang/Limits.h"
#include "lang/MFunctions.h"
#include "lang/Unsupported.h"
#include "lang/Z32GCodes.h"
#include "support/CaseFold.h"
#include <fmt/format.h>

namespace iso::frontend {

using diag::Msg;
using parser_detail::describe;
using parser_detail::reportRIndex;

void parser_detail::reportRIndex(diag::DiagnosticList& diags, const Loc& loc, const Token& t) {
  if (t.value == 0 && !t.hasSep)
    diags.report(Msg::RZero, loc, t.len, lang::kMinRIndex, lang::kMaxRIndex);
  else
    diags.report(Msg::ROutside, loc, t.len, t.text, lang::kMinRIndex, lang::kMaxRIndex);
}

void Parser::parseBlock(Stmt& s) {
  s.kind = StmtKind::Block;
  s.firstItem = static_cast<uint32_t>(file_.items.size());
  while (!atEnd()) {
    size_t itemStart = i_;
    try {
      checkErrorToken();
      if (!parseItem()) failNonItem(s);
    } catch (const Abort&) {
      // Keep the valid items of the line: a bad word must not hide the F or G beside it from
      // the lines below. The first error is reported; later ones are likely its follow-ups.
      s.partial = true;
      muted_ = true;
      depth_ = 0;
      i_ = resumePoint(itemStart);
    }
  }
  s.itemCount = static_cast<uint32_t>(file_.items.size()) - s.firstItem;
  for (uint32_t k = s.firstItem; k < file_.items.size(); ++k) {
    const Item& x = file_.items[k];
    if (x.kind != ItemKind::Move || x.axis < 'A' || x.axis > 'Z') continue;
    (x.mode == MoveMode::Posa ? s.posaAxes : s.movedAxes) |= uint32_t{1} << (x.axis - 'A');
  }
}

bool Parser::parseItem() {
  const Token& t = tok();
  Item it;
  it.loc = locOf(t);
  it.len = t.len;
  if (t.kind == Tok::Word) return parseWordItem(t, it);
  if (t.kind == Tok::SysVar)
    parseSysVarItem(t, it);
  else if (!isNameTok(t.kind))
    return false;
  else if (!parseNamedItem(t, it))
    return false;
  file_.items.push_back(it);
  return true;
}

bool Parser::parseWordItem(const Token& t, Item& it) {
  char a = t.addr[0];
  if (const int up = userParamIndex(t.addr); up >= 0) { // z32: HA12.5 assigns
    Expr& p = newExpr();
    p.kind = ExprKind::UserParam;
    p.rIndex = up;
    p.loc = locOf(t);
    p.len = clampLen(static_cast<uint32_t>(std::strlen(t.addr)));
    it.kind = ItemKind::AssignP;
    it.target = lastExpr();
    it.value = constExpr(t);
    ++i_;
    file_.items.push_back(it);
    return true;
  }
  if (t.addr[1] != 0) {
    if (a == 'C') { // CR<number>
      it.kind = ItemKind::ArcCR;
      it.value = constExpr(t);
    } else { // z32 MA/MB/MC
      it.kind = ItemKind::ZWord;
      std::memcpy(it.zaddr, t.addr, 3);
      it.value = constExpr(t);
    }
    ++i_;
    file_.items.push_back(it);
    return true;
  }
  switch (a) {
  case 'G': {
    if (t.hasSep || t.value < 0 || t.value > lang::kMaxGNumber) fail(t, Msg::GNotWhole, describe(t));
    it.kind = ItemKind::G;
    it.code = static_cast<int32_t>(t.value);
    if (z32() && lang::findZ32G(it.code))
      parseZ32G(t, it);
    else
      checkGCode(t, it.code);
    break;
  }
  case 'O': { // z32 only (an address there): an origin number
    if (t.hasSep || t.value < 0 || t.value > lang::kMaxOrigin) fail(t, Msg::OriginNumber, describe(t));
    it.kind = ItemKind::ZWord;
    it.zaddr[0] = 'O';
    it.value = constExpr(t);
    break;
  }
  case 'M': {
    if (t.hasSep || t.value < 0 || t.value > lang::kMaxMNumber) fail(t, Msg::MNotWhole, describe(t));
    it.kind = ItemKind::M;
    it.code = static_cast<int32_t>(t.value);
    if (z32() && it.code > lang::kMaxMNumberZ32) fail(t, Msg::MTwoDigits, it.code);
    if (const auto* u = lang::findUnsupportedM(it.code)) fail(t, Msg::UnsupportedM, it.code, u->construct, u->way);
    break;
  }
  case 'N': fail(t, Msg::NNotAtStart);
  case 'F':
    it.kind = ItemKind::Feed;
    it.value = constExpr(t);
    break;
  case 'R': {
    // R1 = expr
    if (peekTok().kind != Tok::Assign) {
      ++i_;
      failExpected(Msg::ExpectedRAssign);
    }
    Expr r;
    r.kind = ExprKind::RParam;
    r.loc = locOf(t);
    r.len = clampLen(t.len);
    if (t.value < 0) fail(t, Msg::RNegative, t.text, lang::kMinRIndex, lang::kMaxRIndex);
    r.rIndex = t.hasSep || t.tooManyDigits ? -1 : static_cast<int32_t>(std::min(t.value, 1e9));
    if (!t.tooManyDigits && (t.hasSep || !lang::isRIndex(t.value))) reportRIndex(diags_, locOf(t), t);
    it.kind = ItemKind::AssignR;
    it.target = addExpr(r);
    i_ += 2;
    it.value = parseArith();
    file_.items.push_back(it);
    return true;
  }
  case 'I':
    it.kind = ItemKind::ArcI;
    it.value = constExpr(t);
    break;
  case 'J':
    it.kind = ItemKind::ArcJ;
    it.value = constExpr(t);
    break;
  case 'K':
    it.kind = ItemKind::ArcK;
    it.value = constExpr(t);
    break;
  case 'S':
  case 'T':
    if (opts_.dialect == machine::Dialect::Z32) {
      it.kind = ItemKind::ZWord;
      it.zaddr[0] = a;
      it.value = constExpr(t);
      break;
    }
    [[fallthrough]];
  default:
    it.kind = ItemKind::Move;
    it.mode = MoveMode::Word;
    it.axis = a;
    it.value = constExpr(t);
    break;
  }
  ++i_;
  file_.items.push_back(it);
  return true;
}

void Parser::parseZ32G(const Token& t, Item& it) {
  if (it.code != 28 && it.code != 29) return; // G26 and the not-modelled codes: plain G items
  it.kind = ItemKind::AxisControl;
  uint32_t mask = 0;
  for (char c : t.text)
    if (c >= 'A' && c <= 'Z')
      mask |= uint32_t{1} << (c - 'A');
    else if (c >= 'a' && c <= 'z')
      mask |= uint32_t{1} << (c - 'a');
  it.target = static_cast<ExprId>(mask);
}

int Parser::userParamIndex(std::string_view name) const {
  for (size_t k = 0; k < opts_.userParams.size(); ++k)
    if (support::iequals(opts_.userParams[k], name)) return static_cast<int>(k);
  return -1;
}

ExprId Parser::parseParAccess(const Token& t) {
  const bool pal = support::iequals(t.text, "PAL");
  Expr e;
  e.kind = pal ? ExprKind::Pal : ExprKind::Par;
  e.loc = locOf(t);
  ++i_;
  if (tok().kind != Tok::LBracket) fail(tok(), Msg::ParIndexBracket, pal ? "PAL" : "PAR", describe(tok()));
  ++i_;
  const Token& first = tok();
  e.a = parseArith();
  expect(Tok::RBracket, Msg::ExpectedRBracket);
  e.len = clampLen(spanLen(e.loc));
  const Expr& ix = file_.expr(e.a);
  const int max = pal ? lang::kMaxPalIndex : lang::kMaxParIndex;
  double v = ix.kind == ExprKind::Number                                             ? ix.value
             : ix.kind == ExprKind::Neg && file_.expr(ix.a).kind == ExprKind::Number ? -file_.expr(ix.a).value
                                                                                     : 0;
  if ((ix.kind == ExprKind::Number || ix.kind == ExprKind::Neg) && (v < 0 || v > max || v != static_cast<int>(v)))
    diags_.report(Msg::ParIndexOutside, locOf(first), spanLen(locOf(first)), pal ? "PAL" : "PAR", fmt::format("{}", v),
                  0, max);
  return addExpr(e);
}

void Parser::checkGCode(const Token& t, int code) {
  if (lang::findG(code)) return;
  // z32 is a controller of its own: no code is described there with another controller's meaning.
  if (const auto* u = z32() ? nullptr : lang::findUnsupportedG(code)) fail(t, Msg::UnsupportedG, u->text(), t.text);
  diags_.report(Msg::GUnknown, locOf(t), t.len, t.text);
}

void Parser::parseSysVarItem(const Token& t, Item& it) {
  SysVar v = t.sysvar;
  if (lang::sysVarInfo(v).writable) { // $aa_out, $aa_marker
    ++i_;
    expect(Tok::LBracket, Msg::ExpectedIndexBracket);
    it.kind = ItemKind::AssignIo;
    it.sysvar = v;
    it.target = parseArith();
    expect(Tok::RBracket, Msg::ExpectedRBracket);
    expect(Tok::Assign, Msg::ExpectedIoAssign);
    it.value = parseArith();
    return;
  }
  // Read-only variables: find whether this is an attempted assignment.
  size_t k = i_ + 1;
  int depth = 0;
  for (; k < toks_->size(); ++k) {
    Tok kk = (*toks_)[k].kind;
    if (kk == Tok::LBracket)
      ++depth;
    else if (kk == Tok::RBracket && --depth == 0) {
      ++k;
      break;
    } else if (depth == 0)
      break;
  }
  if (k < toks_->size() && (*toks_)[k].kind == Tok::Assign) fail(t, Msg::ReadOnlySysvar, t.text);
  fail(t, Msg::ReadOnlyStart, t.text);
}

bool Parser::parseNamedItem(const Token& t, Item& it) {
  std::string_view n = t.text;
  bool isAssign = peekTok().kind == Tok::Assign;
  if (t.kind == Tok::KwPos || t.kind == Tok::KwPosa) {
    it.kind = ItemKind::Move;
    it.mode = t.kind == Tok::KwPos ? MoveMode::Pos : MoveMode::Posa;
    ++i_;
    it.axis = parseAxisInBrackets();
    it.len = spanLen(it.loc); // Pos[X]: diagnostics about the axis underline it too
    expect(Tok::Assign, Msg::ExpectedAxisAssign);
    it.value = parseArith();
  } else if (t.kind == Tok::KwFa) {
    it.kind = ItemKind::AxisFeed;
    ++i_;
    it.axis = parseAxisInBrackets();
    it.len = spanLen(it.loc);
    expect(Tok::Assign, Msg::ExpectedFaAssign);
    it.value = parseArith();
  } else if (support::iequals(n, "F") && isAssign) {
    it.kind = ItemKind::Feed;
    i_ += 2;
    it.value = parseArith();
  } else if (opts_.dialect == machine::Dialect::Z32 && isAssign && lang::isZ32WordName(n)) {
    // z32 words with an expression: S=R1*2, MA=R5 (SPEC §4.6)
    it.kind = ItemKind::ZWord;
    it.zaddr[0] = support::upperAscii(n[0]);
    it.zaddr[1] = n.size() > 1 ? support::upperAscii(n[1]) : '\0';
    i_ += 2;
    it.value = parseArith();
  } else if (startsMItem(i_)) { // M=NB(n)
    i_ += 2;
    if (!is(Tok::KwNb)) {
      checkErrorToken();
      fail(tok(), Msg::NbExpected);
    }
    ++i_;
    if (tok().kind != Tok::LParen) fail(tok(), Msg::NbParen);
    ++i_;
    checkErrorToken();
    if (tok().kind != Tok::Number || tok().hasSep || tok().value > lang::kMaxMNumber)
      fail(tok(), Msg::NbNumber, lang::kMaxMNumber);
    it.kind = ItemKind::M;
    it.nb = true;
    it.code = static_cast<int32_t>(tok().value);
    if (lang::isFinal(lang::mRole(it.code, lang::Dialect::Sidac))) fail(tok(), Msg::NbSpecial, it.code);
    if (const auto* u = lang::findUnsupportedM(it.code)) fail(tok(), Msg::UnsupportedMNb, it.code, u->construct);
    ++i_;
    if (tok().kind != Tok::RParen) fail(tok(), Msg::NbClose);
    ++i_;
  } else if (z32() && (support::iequals(n, "PAR") || support::iequals(n, "PAL")) && peekTok().kind == Tok::LBracket) {
    it.kind = ItemKind::AssignP; // PAR[i]=expr, PAL[i]=expr
    it.target = parseParAccess(t);
    if (tok().kind != Tok::Assign) fail(tok(), Msg::ParAssign, n, describe(tok()));
    ++i_;
    it.value = parseArith();
  } else if (z32() && isAssign && userParamIndex(n) >= 0) { // HA=expr
    Expr& p = newExpr();
    p.kind = ExprKind::UserParam;
    p.rIndex = userParamIndex(n);
    p.loc = locOf(t);
    p.len = clampLen(t.len);
    it.kind = ItemKind::AssignP;
    it.target = lastExpr();
    i_ += 2;
    it.value = parseArith();
  } else if (z32() && !isAssign && n.size() > 2 && support::istartsWith(n, "KG") &&
             peekTok().kind != Tok::LBracket) { // KG<name>: continue in the subprogram
    it.kind = ItemKind::Kg;
    it.code = static_cast<int32_t>(file_.names.size());
    file_.names.push_back({n.substr(2), Loc{file_.id, t.line, t.col + 2}, t.len > 2 ? t.len - 2 : 1, t.joined});
    ++i_;
  } else if (support::iequals(n, "M")) {
    fail(t, Msg::MMalformed);
  } else if (support::iequals(n, "R") && peekTok().kind == Tok::LBracket) {
    it.kind = ItemKind::AssignR;
    Expr r;
    r.kind = ExprKind::RIndirect;
    r.loc = locOf(t);
    ++i_;
    ++i_;
    r.a = parseArith();
    expect(Tok::RBracket, Msg::ExpectedRBracket);
    it.target = addExpr(r);
    expect(Tok::Assign, Msg::ExpectedRIndirectAssign);
    it.value = parseArith();
  } else if ((support::iequals(n, "CR") || support::iequals(n, "I") || support::iequals(n, "J") ||
              support::iequals(n, "K")) &&
             isAssign) {
    char c = support::upperAscii(n[0]);
    it.kind = n.size() == 2 ? ItemKind::ArcCR : c == 'I' ? ItemKind::ArcI : c == 'J' ? ItemKind::ArcJ : ItemKind::ArcK;
    i_ += 2;
    it.value = parseArith();
  } else if (n.size() == 1 && isAssign) {
    char c = support::upperAscii(n[0]);
    if (c < 'A' || c > 'Z') fail(t, Msg::NotAnAxisLetter, n); // `_ = 1` (a fuzzing finding)
    if (lang::isFixedAddress(c)) fail(t, Msg::NotBlockItem, n);
    it.kind = ItemKind::Move;
    it.mode = MoveMode::Assign;
    it.axis = c;
    i_ += 2;
    it.value = parseArith();
  } else if (support::iequals(n, "G04F") ||
             (n.size() > 1 && (support::upperAscii(n[0]) == 'F') && support::iequals(n.substr(0, 2), "FR"))) {
    fail(t, Msg::DwellForm, n, lang::gNumber(lang::kDwell), lang::gNumber(lang::kDwell));
  } else {
    return false;
  }
  return true;
}

bool Parser::startsMItem(size_t k) const {
  const Token& w = (*toks_)[k];
  if (w.kind == Tok::Word) return w.addr[0] == 'M' && w.addr[1] == 0;
  return isNameTok(w.kind) && support::iequals(w.text, "M") && k + 1 < toks_->size() &&
         (*toks_)[k + 1].kind == Tok::Assign;
}

char Parser::parseAxisInBrackets() {
  expect(Tok::LBracket, Msg::ExpectedAxisBracket);
  checkErrorToken();
  const Token& a = tok();
  if (a.kind != Tok::Ident || a.text.size() != 1) failExpected(Msg::ExpectedAxisName);
  char axis = support::upperAscii(a.text[0]);
  if (axis < 'A' || axis > 'Z') fail(a, Msg::NotAnAxisLetter, a.text);
  if (lang::isFixedAddress(axis) && axis != 'N') fail(a, Msg::AddressNotAxis, a.text);
  ++i_;
  expect(Tok::RBracket, Msg::ExpectedRBracket);
  return axis;
}

void Parser::failNonItem(const Stmt& s) {
  const Token& t = tok();
  if (z32() && t.kind == Tok::Ident && support::upperAscii(t.text[0]) == 'O' &&
      std::all_of(t.text.begin(), t.text.end(), [](char c) { return (c | 0x20) >= 'a' && (c | 0x20) <= 'z'; }))
    fail(t, Msg::OriginLetters, t.text); // OA: origins named by letters
  if (z32() && t.kind == Tok::Ident && support::iequals(t.text, "KG")) fail(t, Msg::KgName);
  if (z32() && userParamIndex(t.text) >= 0) fail(t, Msg::UserParamAssign, t.text, describe(peekTok()));
  if (isNameTok(t.kind)) {
    if (unsupportedIdent(t)) throw Abort{};
    bool hasM = false;
    for (size_t k = s.firstItem; k < file_.items.size() && !hasM; ++k)
      hasM = file_.items[k].kind == ItemKind::M;
    // M with a call, in either order (SPEC §7 E312): `M23 Lift` and `Lift M23`, `Lift M=NB(23)`
    bool mAfter = false;
    for (size_t k = i_ + 1; k + 1 < toks_->size() && !mAfter; ++k)
      mAfter = startsMItem(k);
    if ((hasM && peekTok().kind == Tok::End) || (mAfter && file_.items.size() == s.firstItem))
      fail(t, Msg::CallWithM, t.text);
    if (isReservedTok(t.kind)) fail(t, Msg::ControlAfterItems, t.text);
    fail(t, Msg::NameInBlock, t.text);
  }
  if (t.kind == Tok::Hash) fail(t, Msg::UnsupportedMacro);
  if (t.kind == Tok::String) fail(t, Msg::UnsupportedString);
  fail(t, Msg::UnexpectedInBlock, describe(t));
}

size_t Parser::resumePoint(size_t itemStart) const {
  // The first token at or after the failure that can start an item and is not inside the
  // brackets or parentheses of the bad item.
  const std::vector<Token>& toks = *toks_;
  int depth = 0;
  for (size_t k = itemStart; k + 1 < toks.size(); ++k) {
    const Token& t = toks[k];
    bool startsItem = t.kind == Tok::Word || t.kind == Tok::SysVar ||
                      (isNameTok(t.kind) && (toks[k + 1].kind == Tok::Assign || toks[k + 1].kind == Tok::LBracket));
    if (k > itemStart && k >= i_ && depth == 0 && startsItem) return k;
    if (t.kind == Tok::LParen || t.kind == Tok::LBracket) ++depth;
    if ((t.kind == Tok::RParen || t.kind == Tok::RBracket) && depth > 0) --depth;
  }
  return toks.size() - 1; // End
}

} // namespace iso::frontend
