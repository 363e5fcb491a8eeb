//! @file Parser.cpp
//! @brief Recursive descent over the tokens of one logical line.
#include "frontend/Parser.h"

#include <cmath>
#include <cstring>
#include <initializer_list>

#include <fmt/format.h>

#include "lang/Addresses.h"
#include "lang/GCodes.h"
#include "lang/Limits.h"
#include "lang/MFunctions.h"
#include "lang/Unsupported.h"
#include "support/CaseFold.h"
#include "support/Memory.h"

namespace iso::frontend {

using diag::Msg;

namespace {

/// E301 for an R parameter whose index is not in 1..<max> (R0 has its own message).
void reportRIndex(diag::DiagnosticList& diags, const Loc& loc, const Token& t) {
  if (t.value == 0 && !t.hasSep)
    diags.report(Msg::RZero, loc, t.len, lang::kMinRIndex, lang::kMaxRIndex);
  else
    diags.report(Msg::ROutside, loc, t.len, t.text, lang::kMinRIndex, lang::kMaxRIndex);
}

} // namespace

Parser::Parser(File& file, const LexOptions& opts, diag::DiagnosticList& diags)
    : file_(file), opts_(opts), diags_(diags) {}

void Parser::failText(const Loc& loc, uint32_t len, diag::Code code, std::string text) {
  if (!muted_) diags_.report(code, loc, len, std::move(text));
  throw Abort{};
}

void Parser::failTextWithFix(const Loc& loc, uint32_t len, diag::Code code, std::string text, diag::Fix fix) {
  if (!muted_) {
    auto& d = diags_.report(code, loc, len, std::move(text));
    if (!fix.edits.empty()) d.fixes.push_back(std::move(fix));
  }
  throw Abort{};
}

void Parser::checkErrorToken() {
  if (tok().kind == Tok::Error) throw Abort{}; // the lexer has reported it
}

static std::string describe(const Token& t) {
  switch (t.kind) {
  case Tok::Word: return fmt::format("'{}{}{}'", t.addr, t.value < 0 ? "-" : "", t.text);
  case Tok::Ident:
#define ISO_KEYWORD(Name, spelling, reserved) case Tok::Kw##Name:
#include "lang/Keywords.def"
    return fmt::format("'{}'", t.text);
  case Tok::Number: return fmt::format("number '{}'", t.text);
  case Tok::SysVar: return fmt::format("'{}'", t.text);
  case Tok::Other: return fmt::format("'{}'", printableBytes(t.text));
  default: return tokName(t.kind);
  }
}

void Parser::failExpected(diag::MsgRef<std::string> m) {
  checkErrorToken();
  fail(tok(), m, describe(tok()));
}

void Parser::expect(Tok k, diag::MsgRef<std::string> expected) {
  if (tok().kind != k) failExpected(expected);
  ++i_;
}

void Parser::expectEnd(diag::MsgRef<std::string> after) {
  if (atEnd()) return;
  checkErrorToken();
  fail(tok(), after, describe(tok()));
}

/// The structural role announced by the keyword that starts a line that failed to parse.
static StmtKind structuralRole(const std::vector<Token>& toks, size_t start) {
  const Token& t = toks[start];
  auto anyOf = [&](std::initializer_list<Tok> kinds) {
    for (size_t k = start + 1; k < toks.size(); ++k)
      for (Tok w : kinds)
        if (toks[k].kind == w) return true;
    return false;
  };
  size_t last = toks.size() >= 2 ? toks.size() - 2 : start; // the token before End
  auto endsWith = [&](Tok w) { return toks[last].kind == w; };
  switch (t.kind) {
  case Tok::KwIf: // a block IF unless a statement or a jump follows the condition
    return endsWith(Tok::KwThen) || !anyOf({Tok::KwThen, Tok::KwGotof, Tok::KwGotob, Tok::KwGoto}) ? StmtKind::If
                                                                                                   : StmtKind::Invalid;
  case Tok::KwWhen: // the long form: nothing after DO (or DO missing)
    return endsWith(Tok::KwDo) || !anyOf({Tok::KwDo}) ? StmtKind::When : StmtKind::Invalid;
  case Tok::KwElse: return StmtKind::Else;
  case Tok::KwEndIf: return StmtKind::EndIf;
  case Tok::KwCancel: return StmtKind::Cancel;
  default: return StmtKind::Invalid;
  }
}

void Parser::parseLine(const LogicalLine& line) {
  toks_ = &line.tokens;
  i_ = 0;
  size_t stmtStart = line.tokens.size();
  notBlockIf_ = false;
  muted_ = false;
  depth_ = 0;
  condStart_ = SIZE_MAX;
  lineLength_ = line.length;
  Stmt s;
  s.firstItem = static_cast<uint32_t>(file_.items.size()); // every statement's: appendPart moves it
  s.line = line.firstLine;
  s.lastLine = line.lastLine;
  s.truncated = line.truncated;
  try {
    if (tok().kind == Tok::Percent) ++i_;
    if (tok().kind == Tok::Slash) {
      s.skippable = true;
      ++i_;
    }
    if (tok().kind == Tok::Word && tok().addr[0] == 'N' && tok().addr[1] == 0 && tok().hasSign) {
      diags_.report(Msg::LineNumberSign, locOf(tok()), tok().len, tok().text);
      ++i_;
    } else if (tok().kind == Tok::Word && tok().addr[0] == 'N' && tok().addr[1] == 0) {
      s.numbered = true;
      file_.numbers.push_back(
          {static_cast<uint32_t>(file_.stmts.size()), tok().text, locOf(tok()), tok().len, tok().value});
      ++i_;
    }
    if (isNameTok(tok().kind) && peekTok().kind == Tok::Colon) {
      if (isReservedTok(tok().kind)) fail(tok(), Msg::KeywordLabel, tok().text);
      s.labelled = true;
      file_.labels.push_back({static_cast<uint32_t>(file_.stmts.size()), tok().text, locOf(tok())});
      i_ += 2;
    }
    s.loc = locOf(tok());
    if (line.truncated) { // E102: the rest of the line was not lexed
      stmtStart = i_;
      throw Abort{};
    }
    if (atEnd()) {
      s.kind = StmtKind::Empty;
    } else {
      stmtStart = i_;
      parseStatement(s, false);
    }
    if (s.kind == StmtKind::When) {
      WhenAxes w{static_cast<uint32_t>(file_.stmts.size()), static_cast<uint32_t>(file_.whenAxisLetters.size()), 0};
      collectIwAxes(s.cond, file_.whenAxisLetters);
      w.count = static_cast<uint32_t>(file_.whenAxisLetters.size()) - w.first;
      file_.whenAxes.push_back(w);
    }
  } catch (const Abort&) {
    s.kind = StmtKind::Invalid;
    s.itemCount = 0;
    s.recoverAs = stmtStart < line.tokens.size() ? structuralRole(line.tokens, stmtStart) : StmtKind::Invalid;
    if (notBlockIf_ && s.recoverAs == StmtKind::If) s.recoverAs = StmtKind::Invalid;
  }
  file_.stmts.push_back(s);
}

std::optional<std::string> unsupportedNameMessage(std::string_view name, machine::Dialect dialect) {
  if (const auto* u = lang::findUnsupportedName(name)) return diag::message(Msg::UnsupportedName, u->text());
  if (const auto* p = lang::findUnsupportedPrefix(name)) return diag::message(Msg::UnsupportedPrefix, p->text(), name);
  // Address words of other dialects that read as identifiers here: S1000, T1, D1, H1, O100.
  if (name.size() >= 2) {
    char a = support::upperAscii(name[0]);
    bool digits = true;
    for (size_t k = 1; k < name.size(); ++k)
      if (!(name[k] >= '0' && name[k] <= '9')) digits = false;
    const auto* u = digits ? lang::findUnsupportedAddress(a) : nullptr;
    if (u) return diag::message(Msg::UnsupportedAddress, u->text(), machine::dialectName(dialect), name);
  }
  return std::nullopt;
}

bool Parser::unsupportedIdent(const Token& t) {
  auto msg = unsupportedNameMessage(t.text, opts_.dialect);
  if (!msg) return false;
  if (!muted_) diags_.report(diag::codeOf(Msg::UnsupportedName), locOf(t), t.len, std::move(*msg));
  return true;
}

void Parser::parseStatement(Stmt& s, bool inner) {
  checkErrorToken();
  const Token& t = tok();
  if (isNameTok(t.kind)) {
    if (is(Tok::KwIf) && !inner) return parseIf(s);
    if (is(Tok::KwWhen) && !inner) return parseWhen(s);
    if (is(Tok::KwCase) && !inner) return parseCase(s);
    if (is(Tok::KwElse) || is(Tok::KwEndIf) || is(Tok::KwCancel)) {
      if (inner) fail(t, Msg::StandAlone, t.text);
      s.kind = is(Tok::KwElse) ? StmtKind::Else : is(Tok::KwEndIf) ? StmtKind::EndIf : StmtKind::Cancel;
      ++i_;
      if (t.text.data() == nullptr)
        expectEnd(Msg::UnexpectedAfterKeyword);
      else
        expectEnd(Msg::UnexpectedAfterThisKeyword);
      return;
    }
    if (is(Tok::KwGotof) || is(Tok::KwGotob) || is(Tok::KwGoto)) {
      s.kind = StmtKind::Jump;
      startJump(s);
      expectEnd(Msg::UnexpectedAfterLabel);
      return;
    }
    if (is(Tok::KwProc)) {
      if (inner) fail(t, Msg::ProcStandAlone);
      return parseProc(s);
    }
    if (is(Tok::KwSemi)) {
      if (inner) fail(t, Msg::SemiStandAlone);
      return parseSemi(s);
    }
    if (is(Tok::KwIf) || is(Tok::KwWhen) || is(Tok::KwCase)) fail(t, Msg::NotAfterThen, t.text);
    if (is(Tok::KwThen) || is(Tok::KwDo) || is(Tok::KwOf) || is(Tok::KwDefault) || is(Tok::KwAnd) || is(Tok::KwOr) ||
        is(Tok::KwNot) || is(Tok::KwNb) || is(Tok::KwSave))
      fail(t, Msg::UnexpectedKeyword, t.text);
    // A name alone on its line is a call; names that start items are blocks.
    bool startsItem = peekTok().kind == Tok::Assign || peekTok().kind == Tok::LBracket;
    if (!startsItem) {
      // A name alone is a call even if it spells a construct of another dialect (RET, T1,
      // P1): a subprogram of the set may have that name. checkSet reports E110 otherwise.
      if (peekTok().kind == Tok::End) {
        s.kind = StmtKind::Call;
        setName(s, {t.text, locOf(t), t.len, t.joined});
        ++i_;
        return;
      }
      if (unsupportedIdent(t)) throw Abort{};
      if (peekTok().kind == Tok::LParen) fail(t, Msg::UnsupportedCallArgs, t.text);
    }
  } else if (t.kind == Tok::Hash) {
    fail(t, Msg::UnsupportedMacro);
  } else if (t.kind == Tok::String) {
    fail(t, Msg::UnsupportedString);
  }
  parseBlock(s);
}

void Parser::setName(Stmt& s, const StmtName& name) {
  s.part = StmtPart::Name;
  s.partIdx = static_cast<uint32_t>(file_.names.size());
  file_.names.push_back(name);
}

void Parser::startJump(Stmt& s) {
  s.part = StmtPart::Jump;
  s.partIdx = static_cast<uint32_t>(file_.jumps.size());
  file_.jumps.emplace_back();
  parseJump(file_.jumps.back());
}

// A jump, a block or a call: parseStatement(inner) accepts exactly these and rejects the rest.
void Parser::parseSimple(Stmt& s) { parseStatement(s, true); }

void Parser::parseJump(Jump& j) {
  const Token& kw = tok();
  j.kind = is(Tok::KwGotof) ? JumpKind::Gotof : is(Tok::KwGotob) ? JumpKind::Gotob : JumpKind::Goto;
  j.kwLoc = locOf(kw);
  ++i_;
  checkErrorToken();
  if (!isNameTok(tok().kind)) failExpected(Msg::ExpectedLabelName);
  j.label = tok().text;
  j.loc = locOf(tok());
  j.len = tok().len;
  ++i_;
  if (tok().kind == Tok::Colon) {
    // The fix drops this colon and those of the other jumps of the line (a CASE has several).
    diag::Fix fix{diag::message(Msg::LabelColonFix), {}};
    const std::vector<Token>& t = *toks_;
    for (size_t k = 2; k < t.size(); ++k)
      if (t[k].kind == Tok::Colon && isNameTok(t[k - 1].kind) && isJumpTok(t[k - 2].kind))
        fix.edits.push_back({locOf(t[k]), t[k].line, t[k].col + 1, ""});
    failWithFix(locOf(tok()), tok().len, std::move(fix), Msg::LabelColon, jumpKindName(j.kind), j.label);
  }
}

void Parser::parseIf(Stmt& s) {
  s.kind = StmtKind::If;
  ++i_;
  s.cond = parseCondition();
  if (atEnd()) return; // block IF
  if (is(Tok::KwThen)) {
    ++i_;
    if (atEnd()) failExpected(Msg::ExpectedStatementAfterThen);
    Stmt in;
    in.isInner = true;
    in.firstItem = static_cast<uint32_t>(file_.items.size());
    in.line = s.line;
    in.lastLine = s.lastLine;
    in.loc = locOf(tok());
    in.skippable = s.skippable;
    parseSimple(in);
    file_.inner.push_back(in);
    s.inner = static_cast<int32_t>(file_.inner.size() - 1);
    return;
  }
  if (is(Tok::KwGotof) || is(Tok::KwGotob) || is(Tok::KwGoto)) {
    startJump(s);
    expectEnd(Msg::UnexpectedAfterLabel);
    return;
  }
  checkErrorToken();
  notBlockIf_ = true; // something follows the condition: not a block IF (no ENDIF expected)
  fail(tok(), Msg::ExpectedIfTail, describe(tok()));
}

void Parser::collectIwAxes(ExprId e, std::string& axes) const {
  if (e == kNoExpr) return;
  const Expr& x = file_.expr(e);
  if (x.kind == ExprKind::SysAxis && x.sysvar == SysVar::AaIw) axes.push_back(x.axis);
  collectIwAxes(x.a, axes);
  collectIwAxes(x.b, axes);
}

void Parser::parseWhen(Stmt& s) {
  s.kind = StmtKind::When;
  ++i_;
  s.cond = parseCondition();
  if (!is(Tok::KwDo)) failExpected(Msg::ExpectedDo);
  ++i_;
  if (atEnd()) return; // long form
  Stmt in;
  in.isInner = true;
  in.firstItem = static_cast<uint32_t>(file_.items.size());
  in.line = s.line;
  in.lastLine = s.lastLine;
  in.loc = locOf(tok());
  parseSimple(in);
  file_.inner.push_back(in);
  s.inner = static_cast<int32_t>(file_.inner.size() - 1);
}

void Parser::parseCase(Stmt& s) {
  s.kind = StmtKind::Case;
  ++i_;
  s.cond = parseArith();
  if (!is(Tok::KwOf)) failExpected(Msg::ExpectedOf);
  ++i_;
  const auto firstArm = static_cast<uint32_t>(file_.arms.size());
  bool sawDefault = false;
  while (!atEnd()) {
    checkErrorToken();
    CaseArm arm;
    arm.valueLoc = locOf(tok());
    if (sawDefault) fail(tok(), Msg::CaseAfterDefault);
    if (is(Tok::KwDefault)) {
      arm.isDefault = true;
      sawDefault = true;
      ++i_;
    } else {
      double sign = 1;
      if (tok().kind == Tok::Minus || tok().kind == Tok::Plus) {
        sign = tok().kind == Tok::Minus ? -1 : 1;
        ++i_;
      }
      if (tok().kind != Tok::Number) failExpected(Msg::ExpectedCaseValue);
      arm.value = sign * tok().value;
      ++i_;
    }
    checkErrorToken();
    if (!(is(Tok::KwGotof) || is(Tok::KwGotob) || is(Tok::KwGoto))) failExpected(Msg::ExpectedCaseGotof);
    parseJump(arm.jump);
    file_.arms.push_back(arm);
  }
  const auto armCount = static_cast<uint32_t>(file_.arms.size()) - firstArm;
  if (armCount == 0) failExpected(Msg::ExpectedCaseArm);
  s.part = StmtPart::Arms;
  s.partIdx = static_cast<uint32_t>(file_.armRanges.size());
  file_.armRanges.push_back({firstArm, armCount});
}

void Parser::parseProc(Stmt& s) {
  s.kind = StmtKind::Proc;
  const Token& kw = tok();
  ++i_;
  checkErrorToken();
  if (tok().kind == Tok::Word) {
    // PROC G10 / PROC X5Y2: the name reads as address words.
    const Token& first = tok();
    std::string name;
    while (tok().kind == Tok::Word) {
      name += tok().addr;
      name += tok().text;
      ++i_;
    }
    diags_.report(Msg::ProcNameIsWord, locOf(first), first.len, name, name);
    file_.ownedText.push_back(name);
    setName(s, {file_.ownedText.back(), locOf(first), first.len, false});
  } else if (isNameTok(tok().kind)) {
    setName(s, {tok().text, locOf(tok()), tok().len, false});
    if (isReservedTok(tok().kind)) fail(tok(), Msg::KeywordProcName, tok().text);
    ++i_;
  } else if (tok().kind == Tok::String) {
    fail(tok(), Msg::ProcNameQuoted);
  } else {
    fail(atEnd() ? kw : tok(), Msg::ExpectedProcName);
  }
  if (tok().kind == Tok::LParen) fail(tok(), Msg::UnsupportedProcParams);
  if (!is(Tok::KwSave)) {
    checkErrorToken();
    fail(atEnd() ? kw : tok(), Msg::ExpectedSave);
  }
  s.procSave = true;
  ++i_;
  if (tok().kind == Tok::Ident && lang::isUnsupportedProcAttribute(tok().text))
    fail(tok(), Msg::UnsupportedProcAttribute, tok().text);
  expectEnd(Msg::UnexpectedAfterProc);
}

void Parser::parseSemi(Stmt& s) {
  s.kind = StmtKind::Semi;
  const Token& kw = tok();
  ++i_;
  checkErrorToken();
  if (tok().kind != Tok::String) fail(atEnd() ? kw : tok(), Msg::ExpectedSemiName);
  setName(s, {tok().text, locOf(tok()), tok().len, false});
  ++i_;
  expectEnd(Msg::UnexpectedAfterSemi);
}

void Parser::checkGCode(const Token& t, int code) {
  if (lang::findG(code)) return;
  if (const auto* u = lang::findUnsupportedG(code)) fail(t, Msg::UnsupportedG, u->text(), t.text);
  diags_.report(Msg::GUnknown, locOf(t), t.len, t.text);
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

bool Parser::startsMItem(size_t k) const {
  const Token& w = (*toks_)[k];
  if (w.kind == Tok::Word) return w.addr[0] == 'M' && w.addr[1] == 0;
  return isNameTok(w.kind) && support::iequals(w.text, "M") && k + 1 < toks_->size() &&
         (*toks_)[k + 1].kind == Tok::Assign;
}

void Parser::failNonItem(const Stmt& s) {
  const Token& t = tok();
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

ExprId Parser::constExpr(const Token& t) {
  Expr& e = newExpr();
  // A number rejected by E101 has no trustworthy value: keep it out of the value checks.
  e.kind = t.tooManyDigits ? ExprKind::Error : ExprKind::Number;
  e.value = t.value;
  e.loc = locOf(t);
  e.len = clampLen(t.len);
  return lastExpr();
}

bool Parser::parseWordItem(const Token& t, Item& it) {
  char a = t.addr[0];
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
    checkGCode(t, it.code);
    break;
  }
  case 'M': {
    if (t.hasSep || t.value < 0 || t.value > lang::kMaxMNumber) fail(t, Msg::MNotWhole, describe(t));
    it.kind = ItemKind::M;
    it.code = static_cast<int32_t>(t.value);
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

// ---- expressions -------------------------------------------------------------------------

uint32_t Parser::spanLen(const Loc& start) const {
  // From `start` to the end of the last token consumed, when both are on one physical line.
  if (i_ == 0) return 1;
  const Token& last = (*toks_)[i_ - 1];
  if (last.line != start.line || last.col + last.len <= start.col) return 1;
  return last.col + last.len - start.col;
}

ExprId Parser::addExpr(const Expr& e) {
  file_.exprs.push_back(e);
  return static_cast<ExprId>(file_.exprs.size() - 1);
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

ExprId Parser::parseCondition() {
  checkErrorToken();
  const Token& first = tok();
  condStart_ = i_;
  ExprId e = parseLogicSeq();
  condStart_ = SIZE_MAX;
  if (!ex(e).isBool) failAt(locOf(first), first.len, Msg::BareCondition);
  if (tok().kind == Tok::Assign) failAt(locOf(tok()), 1, Msg::AssignInCondition);
  return e;
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

ExprId Parser::parseConditionAt(const LogicalLine& line, size_t start) {
  toks_ = &line.tokens;
  i_ = start;
  muted_ = false;
  depth_ = 0;
  try {
    return parseCondition();
  } catch (const Abort&) {
    return kNoExpr;
  }
}

namespace {
constexpr size_t kReserveUpTo = size_t{1} << 30; ///< larger files grow as they are parsed
} // namespace

LineParser::LineParser(File& file, std::string_view text, const LexOptions& opts, diag::DiagnosticList& diags,
                       bool reserve)
    : lexer_(text, file.id, opts, diags, file.suppressions, file.ownedText), parser_(file, opts, diags) {
  file.bytes = text.size();
  // Room for a typical program at once (CAM output: a statement per ~20 bytes, an item and an
  // expression per ~6): no copy on growth, and no old and new array alive together. Memory
  // reserved and not used is never touched, so it costs address space, not resident memory.
  if (reserve && text.size() <= kReserveUpTo) {
    file.stmts.reserve(text.size() / 20 + 16);
    file.numbers.reserve(text.size() / 20 + 16); // CAM output numbers every line: no regrowth
    file.items.reserve(text.size() / 6 + 16);
    file.exprs.reserve(text.size() / 6 + 16);
    // The statements of a large program fill tens of MiB front to back (a compact tree keeps
    // them all): in huge pages where the system gives them.
    support::adviseHugePages(file.stmts.data(), file.stmts.capacity() * sizeof(Stmt));
  }
  line_.tokens.reserve(64);
}

void parseFile(File& file, std::string_view text, const LexOptions& opts, diag::DiagnosticList& diags) {
  LineParser lines(file, text, opts, diags);
  while (lines.parseLine()) {
  }
}

} // namespace iso::frontend
