//! @file Parser.cpp
//! @brief Recursive descent over the tokens of one logical line: the line, its statements,
//!        a block's items in turn, the condition of IF/WHEN, errors; LineParser and
//!        parseFile. Items and expressions have files of their own (ParserInternal.h).
#include "frontend/Parser.h"

#include <initializer_list>

#include <fmt/format.h>

#include "frontend/GoTarget.h"
#include "frontend/ParserInternal.h"
#include "lang/Unsupported.h"
#include "support/CaseFold.h"
#include "support/Memory.h"

namespace iso::frontend {

using diag::Msg;
using parser_detail::describe;

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

std::string parser_detail::describe(const Token& t) {
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
  case Tok::KwWhen: // the long form: nothing after DO (or DO missing, and no one-line CANCEL)
    if (!anyOf({Tok::KwDo}) && endsWith(Tok::KwCancel) && last > start + 1) return StmtKind::Invalid;
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
      file_.labels.push_back({static_cast<uint32_t>(file_.stmts.size()), keep(tok().text), locOf(tok())});
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
  if (z32()) {
    const bool bang = tok().kind == Tok::Other && tok().text == "!";
    const Token& w = bang ? peekTok() : tok();
    const bool gop = w.kind == Tok::Ident && w.text.size() >= 3 && support::istartsWith(w.text, "GOP");
    if (w.kind == Tok::GoTarget || gop) {
      if (inner) fail(w, Msg::GoStandAlone, w.kind == Tok::GoTarget ? "GO" : "GOP");
      if (bang) ++i_;
      return w.kind == Tok::GoTarget ? parseGo(s, bang) : parseGop(s, bang);
    }
  }
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
    if (z32() && t.text.size() > 2 && support::istartsWith(t.text, "KG")) startsItem = true; // KG<name>
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

void Parser::closeBang(bool bang, const Token& what) {
  if (!bang) return;
  checkErrorToken();
  if (!(tok().kind == Tok::Other && tok().text == "!")) fail(tok(), Msg::GoBangClose, describe(what), describe(tok()));
  ++i_;
}

void Parser::parseGo(Stmt& s, bool bang) {
  s.kind = StmtKind::Go;
  const Token& t = tok();
  GoJump g;
  g.from = t.text;
  g.fromLoc = Loc{file_.id, t.line, t.col + 2};
  g.fromLen = t.len > 2 ? t.len - 2 : 1;
  if (!isGoTargetText(g.from)) failAt(g.fromLoc, g.fromLen, Msg::GoTargetShape, printableBytes(g.from));
  ++i_;
  if (tok().kind == Tok::Minus) {
    ++i_;
    checkErrorToken();
    if (tok().kind != Tok::GoTarget) fail(tok(), Msg::GoRangeEnd, describe(tok()));
    const Token& e = tok();
    g.range = true;
    g.to = e.text;
    g.toLoc = locOf(e);
    g.toLen = e.len;
    if (!isGoTargetText(g.to)) fail(e, Msg::GoTargetShape, printableBytes(g.to));
    ++i_;
  }
  closeBang(bang, t);
  if (!atEnd()) fail(tok(), Msg::GoStandAlone, "GO");
  s.part = StmtPart::Go;
  s.partIdx = static_cast<uint32_t>(file_.gos.size());
  file_.gos.push_back(g);
}

void Parser::parseGop(Stmt& s, bool bang) {
  const Token& t = tok();
  if (t.text.size() == 3) fail(t, Msg::GopName);
  s.kind = StmtKind::Call;
  setName(s, {t.text.substr(3), Loc{file_.id, t.line, t.col + 3}, t.len > 3 ? t.len - 3 : 1, t.joined});
  ++i_;
  closeBang(bang, t);
  if (!atEnd()) fail(tok(), Msg::GoStandAlone, "GOP");
}

std::string_view Parser::keep(std::string_view name) {
  if (!ownNames_) return name;
  return file_.ownedText.emplace_back(name); // (a deque: the strings already there stay put)
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

void Parser::parseInner(Stmt& s, bool skippable) {
  Stmt in;
  in.isInner = true;
  in.firstItem = static_cast<uint32_t>(file_.items.size());
  in.line = s.line;
  in.lastLine = s.lastLine;
  in.loc = locOf(tok());
  in.skippable = skippable;
  // A jump, a block or a call: parseStatement(inner) accepts exactly these and rejects the rest.
  parseStatement(in, true);
  file_.inner.push_back(in);
  s.inner = static_cast<int32_t>(file_.inner.size() - 1);
}

void Parser::parseJump(Jump& j) {
  const Token& kw = tok();
  j.kind = is(Tok::KwGotof) ? JumpKind::Gotof : is(Tok::KwGotob) ? JumpKind::Gotob : JumpKind::Goto;
  j.kwLoc = locOf(kw);
  ++i_;
  checkErrorToken();
  if (!isNameTok(tok().kind)) failExpected(Msg::ExpectedLabelName);
  j.label = keep(tok().text);
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
    parseInner(s, s.skippable);
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
  const size_t last = toks_->size() >= 2 ? toks_->size() - 2 : 0; // the token before End
  if (!is(Tok::KwDo) && !atEnd() && last > i_ && (*toks_)[last].kind == Tok::KwCancel) {
    // `WHEN cond statement CANCEL` on one line: the short form `WHEN cond DO statement`
    std::vector<Token> body(toks_->begin(), toks_->begin() + static_cast<std::ptrdiff_t>(last));
    body.push_back(toks_->back()); // End
    const std::vector<Token>* whole = toks_;
    struct Restore {
      const std::vector<Token>*& toks;
      const std::vector<Token>* was;
      ~Restore() { toks = was; }
    } restore{toks_, whole};
    toks_ = &body;
    parseInner(s, false);
    return;
  }
  if (!is(Tok::KwDo)) failExpected(Msg::ExpectedDo);
  ++i_;
  if (atEnd()) return;  // long form
  parseInner(s, false); // the WHEN line's own `/` covers its body
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

template <class F> ExprId Parser::parseAt(const LogicalLine& line, size_t start, F&& parse) {
  toks_ = &line.tokens;
  i_ = start;
  muted_ = false;
  depth_ = 0;
  try {
    return parse();
  } catch (const Abort&) {
    return kNoExpr;
  }
}

ExprId Parser::parseConditionAt(const LogicalLine& line, size_t start) {
  return parseAt(line, start, [&] { return parseCondition(); });
}

ExprId Parser::parseExpressionAt(const LogicalLine& line, size_t start) {
  return parseAt(line, start, [&] {
    checkErrorToken();
    const ExprId e = parseLogicSeq();
    expectEnd(Msg::UnexpectedAfterExpression);
    return e;
  });
}

namespace {
constexpr size_t kReserveUpTo = size_t{1} << 30; ///< larger files grow as they are parsed
} // namespace

LineParser::LineParser(File& file, std::string_view text, const LexOptions& opts, diag::DiagnosticList& diags,
                       bool reserve)
    : lexer_(text, file.id, opts, diags, file.suppressions, file.ownedText), parser_(file, opts, diags),
      cancel_(opts.cancel) {
  file.bytes = text.size();
  file.source = text;
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
