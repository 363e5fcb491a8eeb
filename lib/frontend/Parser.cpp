//! @file Parser.cpp
//! @brief Recursive descent over the tokens of one logical line.
#include "frontend/Parser.h"

#include <cmath>
#include <cstring>
#include <initializer_list>

#include <fmt/format.h>

namespace iso::frontend {

using diag::Code;

namespace {

inline char upper(char c) { return (c >= 'a' && c <= 'z') ? static_cast<char>(c - 32) : c; }

struct Unsupported {
  std::string_view name;
  std::string_view what;
};
// Constructs of Sinumerik and other ISO dialects that this language lacks (E110).
constexpr Unsupported kUnsupported[] = {
    {"DEF", "variable definitions (DEF); use R parameters"},
    {"WHILE", "WHILE loops; use IF ... GOTOB"},
    {"ENDWHILE", "WHILE loops; use IF ... GOTOB"},
    {"FOR", "FOR loops; use an R counter with IF ... GOTOB"},
    {"ENDFOR", "FOR loops; use an R counter with IF ... GOTOB"},
    {"REPEAT", "REPEAT loops; use IF ... GOTOB"},
    {"UNTIL", "REPEAT loops; use IF ... GOTOB"},
    {"LOOP", "LOOP; use GOTOB"},
    {"ENDLOOP", "LOOP; use GOTOB"},
    {"ELSEIF", "ELSEIF; nest IF ... ELSE ... ENDIF"},
    {"RET", "RET; end a subprogram with M17"},
    {"ENDPROC", "ENDPROC; end a subprogram with M17"},
    {"STOPRE", "STOPRE (preprocessing stop); real-time reads synchronise by themselves"},
    {"MSG", "MSG (operator messages)"},
    {"SETAL", "SETAL (alarms)"},
    {"SIN", "the function SIN"}, {"COS", "the function COS"}, {"TAN", "the function TAN"},
    {"ASIN", "the function ASIN"}, {"ACOS", "the function ACOS"}, {"ATAN", "the function ATAN"},
    {"ATAN2", "the function ATAN2"}, {"SQRT", "the function SQRT"}, {"ABS", "the function ABS"},
    {"POT", "the function POT"}, {"TRUNC", "the function TRUNC"}, {"ROUND", "the function ROUND"},
    {"LN", "the function LN"}, {"EXP", "the function EXP"}, {"MOD", "the operator MOD"},
    {"DIV", "the operator DIV"}, {"MINVAL", "the function MINVAL"}, {"MAXVAL", "the function MAXVAL"},
    {"TRANS", "frames (TRANS)"}, {"ATRANS", "frames (ATRANS)"}, {"ROT", "frames (ROT)"},
    {"AROT", "frames (AROT)"}, {"SCALE", "frames (SCALE)"}, {"ASCALE", "frames (ASCALE)"},
    {"MIRROR", "frames (MIRROR)"}, {"AMIRROR", "frames (AMIRROR)"},
    {"AC", "AC() absolute dimensions; use G90"}, {"IC", "IC() incremental dimensions; use G91"},
    {"DC", "DC() rotary positioning"}, {"ACP", "ACP() rotary positioning"}, {"ACN", "ACN() rotary positioning"},
    {"CALL", "CALL; a call is the subprogram name alone on its line"},
    {"PCALL", "PCALL; a call is the subprogram name alone on its line"},
    {"MCALL", "MCALL (modal calls)"},
    {"EXTERN", "EXTERN declarations"},
    {"GOTOC", "GOTOC; use GOTOF or GOTOB"}, {"GOTOS", "GOTOS"},
    {"SUPA", "SUPA"}, {"DIAMON", "DIAMON (diameter programming)"}, {"DIAMOF", "DIAMOF"},
    {"SPOS", "SPOS (spindle positioning)"}, {"SETMS", "SETMS"}, {"WAITM", "WAITM"},
    {"WAITE", "WAITE"}, {"CHF", "CHF (chamfers)"}, {"CHR", "CHR (chamfers)"},
    {"RND", "RND (roundings)"}, {"RNDM", "RNDM (roundings)"}, {"CIP", "CIP (circles through a point)"},
    {"CT", "CT (tangential circles)"}, {"SPLINE", "splines"}, {"OFFN", "OFFN"},
    {"SOFT", "SOFT"}, {"BRISK", "BRISK"}, {"INT", "typed variables (INT)"},
    {"REAL", "typed variables (REAL)"}, {"BOOL", "typed variables (BOOL)"}, {"CHAR", "typed variables (CHAR)"},
    {"STRING", "typed variables (STRING)"}, {"AXIS", "typed variables (AXIS)"}, {"FRAME", "frames (FRAME)"},
    {"VAR", "VAR parameters"}, {"EVERY", "synchronized actions (EVERY)"}, {"WHENEVER", "synchronized actions (WHENEVER)"},
    {"ID", "synchronized actions (ID=)"}, {"IDS", "synchronized actions (IDS=)"},
    {"TRAORI", "transformations (TRAORI)"}, {"TRAFOOF", "transformations (TRAFOOF)"},
    {"TRANSMIT", "transformations (TRANSMIT)"}, {"TRACYL", "transformations (TRACYL)"},
    {"DISPLON", "DISPLON"}, {"DISPLOF", "DISPLOF"}, {"SBLON", "SBLON"}, {"SBLOF", "SBLOF"},
    {"SETPIECE", "SETPIECE"}, {"SPCON", "SPCON"}, {"SPCOF", "SPCOF"}, {"TURN", "TURN (helix turns)"},
    {"LIMS", "LIMS (spindle speed limit)"}, {"CFC", "CFC"}, {"CFTCP", "CFTCP"}, {"G500", "G500 (work offsets)"},
};

constexpr std::string_view kUnsupportedPrefixes[][2] = {
    {"CYCLE", "machining cycles (CYCLExx)"}, {"POCKET", "machining cycles (POCKETx)"},
    {"SLOT", "machining cycles (SLOTx)"},   {"HOLES", "machining cycles (HOLESx)"},
    {"LONGHOLE", "machining cycles (LONGHOLE)"},
};

bool startsWithI(std::string_view s, std::string_view prefix) {
  return s.size() >= prefix.size() && iequals(s.substr(0, prefix.size()), prefix);
}

/// G codes of other ISO dialects: E110 with the construct named.
const char* otherDialectG(int g) {
  switch (g) {
  case 5: case 8: return "high-speed/look-ahead modes (G05/G08)";
  case 9: return "non-modal exact stop G09; use G60";
  case 10: case 11: return "data setting (G10/G11)";
  case 15: case 16: return "polar coordinates (G15/G16)";
  case 20: case 21: case 70: case 71: return "inch/metric selection (G20/G21/G70/G71); units are mm";
  case 28: case 29: case 30: return "reference point return (G28/G29/G30)";
  case 31: return "skip function (G31)";
  case 32: case 33: case 34: case 331: case 332: return "threading (G32/G33/G331)";
  case 40: case 41: case 42: return "cutter radius compensation (G40/G41/G42)";
  case 43: case 44: case 49: return "tool length compensation (G43/G44/G49)";
  case 50: case 51: return "scaling (G50/G51)";
  case 52: case 53: return "local/machine coordinates (G52/G53)";
  case 54: case 55: case 56: case 57: case 58: case 59: case 505: case 506: case 507: case 508: case 509:
    return "work offsets (G54...G59)";
  case 61: case 62: case 63: return "Fanuc cutting modes (G61/G62/G63); use G60/G64";
  case 65: case 66: case 67: return "macro calls (G65/G66/G67)";
  case 68: case 69: return "coordinate rotation (G68/G69)";
  case 73: case 74: case 76: case 80: case 81: case 82: case 83: case 84: case 85: case 86: case 87:
  case 88: case 89:
    return "canned cycles (G73...G89)";
  case 92: return "coordinate system setting (G92)";
  case 93: case 94: case 95: return "feed modes (G93/G94/G95); F is always mm/s";
  case 96: case 97: return "constant surface speed (G96/G97)";
  case 98: case 99: return "canned cycle return levels (G98/G99)";
  case 110: case 111: case 112: return "polar coordinates (G110...G112)";
  case 153: return "machine coordinates (G153)";
  case 641: case 642: case 643: case 644: case 645: return "Sinumerik blending modes (G641...); use G64";
  default: return nullptr;
  }
}

bool knownG(int g) {
  switch (g) {
  case 0: case 1: case 2: case 3: case 4: case 17: case 18: case 19: case 60: case 64: case 90: case 91:
    return true;
  default:
    return false;
  }
}

bool isFixedAddress(char c) { return std::strchr("GMNFRIJK", c) != nullptr; }

} // namespace

Parser::Parser(File& file, const LexOptions& opts, diag::DiagnosticList& diags)
    : file_(file), opts_(opts), diags_(diags) {}

void Parser::fail(const Token& t, Code code, std::string msg) { failAt(locOf(t), t.len, code, std::move(msg)); }

void Parser::failAt(const Loc& loc, uint32_t len, Code code, std::string msg) {
  if (!muted_) diags_.report(code, loc, len, std::move(msg));
  throw Abort{};
}

void Parser::failWithFix(const Loc& loc, uint32_t len, Code code, std::string msg, diag::Fix fix) {
  if (!muted_) {
    auto& d = diags_.report(code, loc, len, std::move(msg));
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
  case Tok::Ident: return fmt::format("'{}'", t.text);
  case Tok::Number: return fmt::format("number '{}'", t.text);
  case Tok::SysVar: return fmt::format("'{}'", t.text);
  case Tok::Other: return fmt::format("'{}'", printableBytes(t.text));
  default: return tokName(t.kind);
  }
}

void Parser::failExpected(const char* what) {
  checkErrorToken();
  fail(tok(), Code::Syntax, fmt::format("expected {}, found {}", what, describe(tok())));
}

void Parser::expect(Tok k, const char* what) {
  if (tok().kind != k) failExpected(what);
  ++i_;
}

void Parser::expectEnd(const char* after) {
  if (atEnd()) return;
  checkErrorToken();
  fail(tok(), Code::Syntax, fmt::format("unexpected {} after {}", describe(tok()), after));
}

/// The structural role announced by the keyword that starts a line that failed to parse.
static StmtKind structuralRole(const std::vector<Token>& toks, size_t start) {
  const Token& t = toks[start];
  if (t.kind != Tok::Ident) return StmtKind::Invalid;
  auto anyIdent = [&](std::initializer_list<std::string_view> words) {
    for (size_t k = start + 1; k < toks.size(); ++k)
      if (toks[k].kind == Tok::Ident)
        for (auto w : words)
          if (iequals(toks[k].text, w)) return true;
    return false;
  };
  size_t last = toks.size() >= 2 ? toks.size() - 2 : start; // the token before End
  auto endsWith = [&](std::string_view w) { return toks[last].kind == Tok::Ident && iequals(toks[last].text, w); };
  if (iequals(t.text, "IF")) // a block IF unless a statement or a jump follows the condition
    return endsWith("THEN") || !anyIdent({"THEN", "GOTOF", "GOTOB", "GOTO"}) ? StmtKind::If : StmtKind::Invalid;
  if (iequals(t.text, "WHEN")) // the long form: nothing after DO (or DO missing)
    return endsWith("DO") || !anyIdent({"DO"}) ? StmtKind::When : StmtKind::Invalid;
  if (iequals(t.text, "ELSE")) return StmtKind::Else;
  if (iequals(t.text, "ENDIF")) return StmtKind::EndIf;
  if (iequals(t.text, "CANCEL")) return StmtKind::Cancel;
  return StmtKind::Invalid;
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
      diags_.report(Code::Syntax, locOf(tok()), tok().len,
                    fmt::format("a line number has no sign: write N{}", tok().text));
      ++i_;
    } else if (tok().kind == Tok::Word && tok().addr[0] == 'N' && tok().addr[1] == 0) {
      s.hasN = true;
      s.nValue = tok().value;
      s.nLoc = locOf(tok());
      s.nLen = tok().len;
      ++i_;
    }
    if (tok().kind == Tok::Ident && peekTok().kind == Tok::Colon) {
      if (isKeyword(tok().text)) fail(tok(), Code::Syntax, fmt::format("keyword '{}' cannot be a label", tok().text));
      s.hasLabel = true;
      s.label = tok().text;
      s.labelLoc = locOf(tok());
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
  } catch (const Abort&) {
    s.kind = StmtKind::Invalid;
    s.itemCount = 0;
    s.recoverAs = stmtStart < line.tokens.size() ? structuralRole(line.tokens, stmtStart) : StmtKind::Invalid;
    if (notBlockIf_ && s.recoverAs == StmtKind::If) s.recoverAs = StmtKind::Invalid;
  }
  file_.stmts.push_back(s);
}

std::optional<std::string> unsupportedNameMessage(std::string_view name, machine::Dialect dialect) {
  for (const auto& u : kUnsupported)
    if (iequals(name, u.name)) return fmt::format("unsupported: {}", u.what);
  for (const auto& p : kUnsupportedPrefixes)
    if (startsWithI(name, p[0])) return fmt::format("unsupported: {} ('{}')", p[1], name);
  // Address words of other dialects that read as identifiers here: S1000, T1, D1, H1, O100.
  if (name.size() >= 2) {
    char a = upper(name[0]);
    bool digits = true;
    for (size_t k = 1; k < name.size(); ++k)
      if (!(name[k] >= '0' && name[k] <= '9')) digits = false;
    if (digits && std::strchr("STDHOPQE", a)) {
      const char* what = a == 'O'   ? "program numbers (O words); the file name names the program"
                         : a == 'S' ? "spindle speed words (S)"
                         : a == 'T' ? "tool words (T)"
                         : a == 'D' ? "tool offset words (D)"
                         : a == 'H' ? "tool length offset words (H)"
                                    : "address words of other ISO dialects";
      return fmt::format("unsupported: {} in the {} dialect ('{}')", what, machine::dialectName(dialect), name);
    }
  }
  return std::nullopt;
}

bool Parser::unsupportedIdent(const Token& t) {
  auto msg = unsupportedNameMessage(t.text, opts_.dialect);
  if (!msg) return false;
  if (!muted_) diags_.report(Code::Unsupported, locOf(t), t.len, std::move(*msg));
  return true;
}

void Parser::parseStatement(Stmt& s, bool inner) {
  checkErrorToken();
  const Token& t = tok();
  if (t.kind == Tok::Ident) {
    if (isIdent("IF") && !inner) return parseIf(s);
    if (isIdent("WHEN") && !inner) return parseWhen(s);
    if (isIdent("CASE") && !inner) return parseCase(s);
    if (isIdent("ELSE") || isIdent("ENDIF") || isIdent("CANCEL")) {
      if (inner) fail(t, Code::Syntax, fmt::format("'{}' must stand alone on its line", t.text));
      s.kind = isIdent("ELSE") ? StmtKind::Else : isIdent("ENDIF") ? StmtKind::EndIf : StmtKind::Cancel;
      ++i_;
      expectEnd(t.text.data() == nullptr ? "keyword" : "this keyword");
      return;
    }
    if (isIdent("GOTOF") || isIdent("GOTOB") || isIdent("GOTO")) {
      s.kind = StmtKind::Jump;
      s.hasJump = true;
      parseJump(s.jump);
      expectEnd("the jump label");
      return;
    }
    if (isIdent("PROC")) {
      if (inner) fail(t, Code::Syntax, "PROC must stand alone on the first line");
      return parseProc(s);
    }
    if (isIdent("SEMI")) {
      if (inner) fail(t, Code::Syntax, "SEMI must stand alone on the first line");
      return parseSemi(s);
    }
    if (isIdent("IF") || isIdent("WHEN") || isIdent("CASE"))
      fail(t, Code::Syntax, fmt::format("'{}' cannot follow THEN or DO; only a block, a jump or a call", t.text));
    if (isIdent("THEN") || isIdent("DO") || isIdent("OF") || isIdent("DEFAULT") || isIdent("AND") ||
        isIdent("OR") || isIdent("NOT") || isIdent("NB") || isIdent("SAVE"))
      fail(t, Code::Syntax, fmt::format("unexpected keyword '{}'", t.text));
    // A name alone on its line is a call; names that start items are blocks.
    bool startsItem = peekTok().kind == Tok::Assign || peekTok().kind == Tok::LBracket;
    if (!startsItem) {
      // A name alone is a call even if it spells a construct of another dialect (RET, T1,
      // P1): a subprogram of the set may have that name. checkSet reports E110 otherwise.
      if (peekTok().kind == Tok::End) {
        s.kind = StmtKind::Call;
        s.name = t.text;
        s.nameLoc = locOf(t);
        s.nameLen = t.len;
        s.nameJoined = t.joined;
        ++i_;
        return;
      }
      if (unsupportedIdent(t)) throw Abort{};
      if (peekTok().kind == Tok::LParen)
        fail(t, Code::Unsupported, fmt::format("unsupported: calls and functions with arguments ('{}(...)')", t.text));
    }
  } else if (t.kind == Tok::Hash) {
    fail(t, Code::Unsupported, "unsupported: '#' macro variables (Fanuc); use R parameters");
  } else if (t.kind == Tok::String) {
    fail(t, Code::Unsupported, "unsupported: strings (only SEMI takes a string)");
  }
  parseBlock(s);
}

void Parser::parseSimple(Stmt& s) {
  checkErrorToken();
  if (isIdent("GOTOF") || isIdent("GOTOB") || isIdent("GOTO")) {
    s.kind = StmtKind::Jump;
    s.hasJump = true;
    parseJump(s.jump);
    expectEnd("the jump label");
    return;
  }
  parseStatement(s, true);
}

void Parser::parseJump(Jump& j) {
  const Token& kw = tok();
  j.kind = isIdent("GOTOF") ? JumpKind::Gotof : isIdent("GOTOB") ? JumpKind::Gotob : JumpKind::Goto;
  j.kwLoc = locOf(kw);
  ++i_;
  checkErrorToken();
  if (tok().kind != Tok::Ident) failExpected("a label name after the jump");
  j.label = tok().text;
  j.loc = locOf(tok());
  j.len = tok().len;
  ++i_;
  if (tok().kind == Tok::Colon) {
    // The fix drops this colon and those of the other jumps of the line (a CASE has several).
    diag::Fix fix{"remove the ':' after the label name", {}};
    const std::vector<Token>& t = *toks_;
    for (size_t k = 2; k < t.size(); ++k)
      if (t[k].kind == Tok::Colon && t[k - 1].kind == Tok::Ident && t[k - 2].kind == Tok::Ident &&
          (iequals(t[k - 2].text, "GOTOF") || iequals(t[k - 2].text, "GOTOB") || iequals(t[k - 2].text, "GOTO")))
        fix.edits.push_back({locOf(t[k]), t[k].line, t[k].col + 1, ""});
    failWithFix(locOf(tok()), tok().len, Code::Syntax,
                fmt::format("unexpected ':' after the label name; write '{} {}' without the colon",
                            jumpKindName(j.kind), j.label),
                std::move(fix));
  }
}

void Parser::parseIf(Stmt& s) {
  s.kind = StmtKind::If;
  ++i_;
  s.cond = parseCondition();
  if (atEnd()) return; // block IF
  if (isIdent("THEN")) {
    ++i_;
    if (atEnd()) failExpected("a statement after THEN");
    Stmt in;
    in.isInner = true;
    in.line = s.line;
    in.lastLine = s.lastLine;
    in.loc = locOf(tok());
    in.skippable = s.skippable;
    parseSimple(in);
    file_.inner.push_back(in);
    s.inner = static_cast<int32_t>(file_.inner.size() - 1);
    return;
  }
  if (isIdent("GOTOF") || isIdent("GOTOB") || isIdent("GOTO")) {
    s.hasJump = true;
    parseJump(s.jump);
    expectEnd("the jump label");
    return;
  }
  checkErrorToken();
  notBlockIf_ = true; // something follows the condition: not a block IF (no ENDIF expected)
  fail(tok(), Code::Syntax, fmt::format("expected THEN, a jump or the end of the line after the IF condition, found {}",
                                        describe(tok())));
}

void Parser::parseWhen(Stmt& s) {
  s.kind = StmtKind::When;
  ++i_;
  s.cond = parseCondition();
  if (!isIdent("DO")) failExpected("DO after the WHEN condition");
  ++i_;
  if (atEnd()) return; // long form
  Stmt in;
  in.isInner = true;
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
  if (!isIdent("OF")) failExpected("OF after the CASE expression");
  ++i_;
  s.firstArm = static_cast<uint32_t>(file_.arms.size());
  bool sawDefault = false;
  while (!atEnd()) {
    checkErrorToken();
    CaseArm arm;
    arm.valueLoc = locOf(tok());
    if (sawDefault) fail(tok(), Code::Syntax, "nothing may follow the DEFAULT branch of a CASE");
    if (isIdent("DEFAULT")) {
      arm.isDefault = true;
      sawDefault = true;
      ++i_;
    } else {
      double sign = 1;
      if (tok().kind == Tok::Minus || tok().kind == Tok::Plus) {
        sign = tok().kind == Tok::Minus ? -1 : 1;
        ++i_;
      }
      if (tok().kind != Tok::Number) failExpected("a numeric constant (CASE value) or DEFAULT");
      arm.value = sign * tok().value;
      ++i_;
    }
    checkErrorToken();
    if (!(isIdent("GOTOF") || isIdent("GOTOB") || isIdent("GOTO"))) failExpected("GOTOF after the CASE value");
    parseJump(arm.jump);
    file_.arms.push_back(arm);
  }
  s.armCount = static_cast<uint32_t>(file_.arms.size()) - s.firstArm;
  if (s.armCount == 0) failExpected("at least one 'value GOTOF label' after OF");
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
    diags_.report(Code::ProcNameIsWord, locOf(first), first.len,
                  fmt::format("subprogram name '{}' reads as address words; choose a name that starts with a "
                              "letter that is not an address (e.g. P_{})",
                              name, name));
    file_.ownedText.push_back(name);
    s.name = file_.ownedText.back();
    s.nameLoc = locOf(first);
    s.nameLen = first.len;
  } else if (tok().kind == Tok::Ident) {
    s.name = tok().text;
    s.nameLoc = locOf(tok());
    s.nameLen = tok().len;
    if (isKeyword(s.name)) fail(tok(), Code::ProcHeader, fmt::format("keyword '{}' cannot be a subprogram name", s.name));
    ++i_;
  } else if (tok().kind == Tok::String) {
    fail(tok(), Code::ProcHeader, "the subprogram name is written without quotes: PROC Name SAVE");
  } else {
    fail(atEnd() ? kw : tok(), Code::ProcHeader, "expected a subprogram name after PROC");
  }
  if (tok().kind == Tok::LParen) fail(tok(), Code::Unsupported, "unsupported: PROC parameters (Sinumerik)");
  if (!isIdent("SAVE")) {
    checkErrorToken();
    fail(atEnd() ? kw : tok(), Code::ProcHeader, "expected SAVE after the subprogram name: PROC Name SAVE");
  }
  s.procSave = true;
  ++i_;
  if (tok().kind == Tok::Ident && (isIdent("DISPLOF") || isIdent("SBLOF") || isIdent("ACTBLOCNO")))
    fail(tok(), Code::Unsupported, fmt::format("unsupported: PROC attribute '{}'", tok().text));
  expectEnd("PROC name SAVE");
}

void Parser::parseSemi(Stmt& s) {
  s.kind = StmtKind::Semi;
  const Token& kw = tok();
  ++i_;
  checkErrorToken();
  if (tok().kind != Tok::String) fail(atEnd() ? kw : tok(), Code::ProcHeader, "expected a quoted name: SEMI \"name\"");
  s.name = tok().text;
  s.nameLoc = locOf(tok());
  s.nameLen = tok().len;
  ++i_;
  expectEnd("SEMI \"name\"");
}

void Parser::checkGCode(const Token& t, int code) {
  if (knownG(code)) return;
  if (const char* what = otherDialectG(code))
    fail(t, Code::Unsupported, fmt::format("unsupported: {} ('G{}')", what, t.text));
  diags_.report(Code::GUnknown, locOf(t), t.len, fmt::format("unknown G function 'G{}'", t.text));
}

char Parser::parseAxisInBrackets() {
  expect(Tok::LBracket, "'[' and an axis name");
  checkErrorToken();
  const Token& a = tok();
  if (a.kind != Tok::Ident || a.text.size() != 1) failExpected("an axis name (one letter)");
  char axis = upper(a.text[0]);
  if (axis < 'A' || axis > 'Z') fail(a, Code::AxisUnknown, fmt::format("'{}' is not an axis name (a letter)", a.text));
  if (isFixedAddress(axis) && axis != 'N')
    fail(a, Code::AxisUnknown, fmt::format("'{}' is an address, not an axis name", a.text));
  ++i_;
  expect(Tok::RBracket, "']'");
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
}

size_t Parser::resumePoint(size_t itemStart) const {
  // The first token at or after the failure that can start an item and is not inside the
  // brackets or parentheses of the bad item.
  const std::vector<Token>& toks = *toks_;
  int depth = 0;
  for (size_t k = itemStart; k + 1 < toks.size(); ++k) {
    const Token& t = toks[k];
    bool startsItem = t.kind == Tok::Word || t.kind == Tok::SysVar ||
                      (t.kind == Tok::Ident && (toks[k + 1].kind == Tok::Assign || toks[k + 1].kind == Tok::LBracket));
    if (k > itemStart && k >= i_ && depth == 0 && startsItem) return k;
    if (t.kind == Tok::LParen || t.kind == Tok::LBracket) ++depth;
    if ((t.kind == Tok::RParen || t.kind == Tok::RBracket) && depth > 0) --depth;
  }
  return toks.size() - 1; // End
}

void Parser::failNonItem(const Stmt& s) {
  const Token& t = tok();
  if (t.kind == Tok::Ident) {
    if (unsupportedIdent(t)) throw Abort{};
    bool hasM = false;
    for (size_t k = s.firstItem; k < file_.items.size(); ++k)
      if (file_.items[k].kind == ItemKind::M) hasM = true;
    if (hasM && peekTok().kind == Tok::End)
      fail(t, Code::MForm, fmt::format("a call ('{}') must stand alone on its line, not with M functions", t.text));
    if (isKeyword(t.text))
      fail(t, Code::Syntax,
           fmt::format("'{}' cannot follow items of a block: control statements stand alone on their line "
                       "(a conditional jump is written IF cond GOTOF label)",
                       t.text));
    fail(t, Code::Syntax, fmt::format("unexpected name '{}' in a block; a call must stand alone on its line", t.text));
  }
  if (t.kind == Tok::Hash) fail(t, Code::Unsupported, "unsupported: '#' macro variables (Fanuc); use R parameters");
  if (t.kind == Tok::String) fail(t, Code::Unsupported, "unsupported: strings (only SEMI takes a string)");
  fail(t, Code::Syntax, fmt::format("unexpected {} in a block", describe(t)));
}

bool Parser::parseItem() {
  const Token& t = tok();
  Item it;
  it.loc = locOf(t);
  it.len = t.len;
  auto constExpr = [&](double v) {
    Expr e;
    // A number rejected by E101 has no trustworthy value: keep it out of the value checks.
    e.kind = t.tooManyDigits ? ExprKind::Error : ExprKind::Number;
    e.value = v;
    e.loc = locOf(t);
    e.len = t.len;
    return addExpr(e);
  };
  if (t.kind == Tok::Word) {
    char a = t.addr[0];
    if (t.addr[1] != 0) {
      if (a == 'C') { // CR<number>
        it.kind = ItemKind::ArcCR;
        it.value = constExpr(t.value);
      } else { // z32 MA/MB/MC
        it.kind = ItemKind::ZWord;
        std::memcpy(it.zaddr, t.addr, 3);
        it.value = constExpr(t.value);
      }
      ++i_;
      file_.items.push_back(it);
      return true;
    }
    switch (a) {
    case 'G': {
      if (t.hasSep || t.value < 0 || t.value > 999999)
        fail(t, Code::GUnknown, fmt::format("G function number must be a whole number, found {}", describe(t)));
      it.kind = ItemKind::G;
      it.code = static_cast<int32_t>(t.value);
      checkGCode(t, it.code);
      break;
    }
    case 'M': {
      if (t.hasSep || t.value < 0 || t.value > 999999)
        fail(t, Code::MForm, fmt::format("M function number must be a non-negative whole number, found {}", describe(t)));
      it.kind = ItemKind::M;
      it.code = static_cast<int32_t>(t.value);
      if (it.code == 98 || it.code == 99)
        fail(t, Code::Unsupported,
             fmt::format("unsupported: M{} (Fanuc subprogram call/return); call a subprogram by its name and end it "
                         "with M17",
                         it.code));
      break;
    }
    case 'N':
      fail(t, Code::Syntax, "a line number N must stand at the start of the line");
    case 'F':
      it.kind = ItemKind::Feed;
      it.value = constExpr(t.value);
      break;
    case 'R': {
      // R1 = expr
      if (peekTok().kind != Tok::Assign) {
        ++i_;
        failExpected("'=' after the R parameter (an R parameter alone is not a statement)");
      }
      Expr r;
      r.kind = ExprKind::RParam;
      r.loc = locOf(t);
      r.len = t.len;
      if (t.value < 0) fail(t, Code::RIndex, fmt::format("R index '-{}' is outside 1..2880", t.text));
      r.rIndex = t.hasSep || t.tooManyDigits ? -1 : static_cast<int32_t>(std::min(t.value, 1e9));
      if (!t.tooManyDigits && (t.hasSep || t.value < 1 || t.value > 2880))
        diags_.report(Code::RIndex, locOf(t), t.len,
                      t.value == 0 && !t.hasSep ? std::string("R0 is reserved for the system; use R1..R2880")
                                                : fmt::format("R index '{}' is outside 1..2880", t.text));
      it.kind = ItemKind::AssignR;
      it.target = addExpr(r);
      i_ += 2;
      it.value = parseArith();
      file_.items.push_back(it);
      return true;
    }
    case 'I': it.kind = ItemKind::ArcI; it.value = constExpr(t.value); break;
    case 'J': it.kind = ItemKind::ArcJ; it.value = constExpr(t.value); break;
    case 'K': it.kind = ItemKind::ArcK; it.value = constExpr(t.value); break;
    case 'S':
    case 'T':
      if (opts_.dialect == machine::Dialect::Z32) {
        it.kind = ItemKind::ZWord;
        it.zaddr[0] = a;
        it.value = constExpr(t.value);
        break;
      }
      [[fallthrough]];
    default:
      it.kind = ItemKind::Move;
      it.mode = MoveMode::Word;
      it.axis = a;
      it.value = constExpr(t.value);
      break;
    }
    ++i_;
    file_.items.push_back(it);
    return true;
  }
  if (t.kind == Tok::SysVar) {
    SysVar v = t.sysvar;
    if (v == SysVar::AaOut || v == SysVar::AaMarker) {
      ++i_;
      expect(Tok::LBracket, "'[' and an index");
      it.kind = ItemKind::AssignIo;
      it.sysvar = v;
      it.target = parseArith();
      expect(Tok::RBracket, "']'");
      expect(Tok::Assign, "'=' (an output or marker is written with '=')");
      it.value = parseArith();
      file_.items.push_back(it);
      return true;
    }
    // Read-only variables: find whether this is an attempted assignment.
    size_t k = i_ + 1;
    int depth = 0;
    for (; k < toks_->size(); ++k) {
      Tok kk = (*toks_)[k].kind;
      if (kk == Tok::LBracket) ++depth;
      else if (kk == Tok::RBracket && --depth == 0) { ++k; break; }
      else if (depth == 0) break;
    }
    if (k < toks_->size() && (*toks_)[k].kind == Tok::Assign)
      fail(t, Code::ReadOnly, fmt::format("'{}' is read-only", t.text));
    fail(t, Code::Syntax, fmt::format("'{}' can only be read; a statement cannot start with it", t.text));
  }
  if (t.kind != Tok::Ident) return false;
  std::string_view n = t.text;
  bool isAssign = peekTok().kind == Tok::Assign;
  if (iequals(n, "Pos") || iequals(n, "Posa")) {
    it.kind = ItemKind::Move;
    it.mode = iequals(n, "Pos") ? MoveMode::Pos : MoveMode::Posa;
    ++i_;
    it.axis = parseAxisInBrackets();
    it.len = spanLen(it.loc); // Pos[X]: diagnostics about the axis underline it too
    expect(Tok::Assign, "'=' after the axis");
    it.value = parseArith();
  } else if (iequals(n, "Fa")) {
    it.kind = ItemKind::AxisFeed;
    ++i_;
    it.axis = parseAxisInBrackets();
    it.len = spanLen(it.loc);
    expect(Tok::Assign, "'=' after Fa[axis]");
    it.value = parseArith();
  } else if (iequals(n, "F") && isAssign) {
    it.kind = ItemKind::Feed;
    i_ += 2;
    it.value = parseArith();
  } else if (opts_.dialect == machine::Dialect::Z32 && isAssign &&
             (iequals(n, "S") || iequals(n, "T") || iequals(n, "MA") || iequals(n, "MB") || iequals(n, "MC"))) {
    // z32 words with an expression: S=R1*2, MA=R5 (SPEC §4.6)
    it.kind = ItemKind::ZWord;
    it.zaddr[0] = upper(n[0]);
    it.zaddr[1] = n.size() > 1 ? upper(n[1]) : '\0';
    i_ += 2;
    it.value = parseArith();
  } else if (iequals(n, "M") && isAssign) {
    i_ += 2;
    if (!isIdent("NB")) {
      checkErrorToken();
      fail(tok(), Code::MForm, "expected NB(n) after 'M=': write M=NB(34) for a non-blocking M");
    }
    ++i_;
    if (tok().kind != Tok::LParen) fail(tok(), Code::MForm, "expected '(' after M=NB");
    ++i_;
    checkErrorToken();
    if (tok().kind != Tok::Number || tok().hasSep || tok().value > 999999)
      fail(tok(), Code::MForm, "the M number in M=NB(n) must be a whole-number literal (at most 999999)");
    it.kind = ItemKind::M;
    it.nb = true;
    it.code = static_cast<int32_t>(tok().value);
    if (it.code == 0 || it.code == 17 || it.code == 30)
      fail(tok(), Code::MForm, fmt::format("M{} is a special M function and runs only in blocking mode", it.code));
    if (it.code == 98 || it.code == 99)
      fail(tok(), Code::Unsupported, fmt::format("unsupported: M{} (Fanuc subprogram call/return)", it.code));
    ++i_;
    if (tok().kind != Tok::RParen) fail(tok(), Code::MForm, "expected ')' to close M=NB(");
    ++i_;
  } else if (iequals(n, "M")) {
    fail(t, Code::MForm, "malformed M function: write M<number> or M=NB(<number>)");
  } else if (iequals(n, "R") && peekTok().kind == Tok::LBracket) {
    it.kind = ItemKind::AssignR;
    Expr r;
    r.kind = ExprKind::RIndirect;
    r.loc = locOf(t);
    ++i_;
    ++i_;
    r.a = parseArith();
    expect(Tok::RBracket, "']'");
    it.target = addExpr(r);
    expect(Tok::Assign, "'=' after R[...]");
    it.value = parseArith();
  } else if ((iequals(n, "CR") || iequals(n, "I") || iequals(n, "J") || iequals(n, "K")) && isAssign) {
    char c = upper(n[0]);
    it.kind = n.size() == 2 ? ItemKind::ArcCR : c == 'I' ? ItemKind::ArcI : c == 'J' ? ItemKind::ArcJ : ItemKind::ArcK;
    i_ += 2;
    it.value = parseArith();
  } else if (n.size() == 1 && isAssign) {
    char c = upper(n[0]);
    if (isFixedAddress(c)) fail(t, Code::Syntax, fmt::format("'{}=' is not an item of a block", n));
    it.kind = ItemKind::Move;
    it.mode = MoveMode::Assign;
    it.axis = c;
    i_ += 2;
    it.value = parseArith();
  } else if (iequals(n, "G04F") || (n.size() > 1 && (upper(n[0]) == 'F') && iequals(n.substr(0, 2), "FR"))) {
    fail(t, Code::Syntax, fmt::format("'{}': write the dwell time as G04 F=<expression> (e.g. G04 F=R1)", n));
  } else {
    return false;
  }
  file_.items.push_back(it);
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

void Parser::requireLogicOperand(ExprId e, const char* op) {
  const Expr& x = ex(e);
  if ((x.paren && x.isBool) || x.kind == ExprKind::Not) return;
  failWithFix(x.loc, x.len, Code::LogicOperand,
              std::string_view(op) == "NOT"
                  ? std::string("the operand of NOT must be a parenthesised group: write NOT ( ... )")
                  : fmt::format("every operand of {} must be a parenthesised group: write ( ... ) {} ( ... )", op,
                                op),
              parenthesiseComparisons());
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
    if (depth == 0 && t[k].kind == Tok::Ident && (iequals(t[k].text, "AND") || iequals(t[k].text, "OR"))) {
      operands.emplace_back(start, k);
      start = k + 1;
    }
  }
  if (depth != 0) return false;
  operands.emplace_back(start, to);
  const bool chain = operands.size() > 1;
  for (auto [a, b] : operands) {
    if (a >= b) return false;
    if (t[a].kind == Tok::Ident && iequals(t[a].text, "NOT")) {
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
      if (depth == 0 && (kk == Tok::Gt || kk == Tok::Lt || kk == Tok::Eq || kk == Tok::Ge || kk == Tok::Le ||
                         kk == Tok::Ne))
        ++comparisons;
      if (kk == Tok::Assign || kk == Tok::Error || kk == Tok::End ||
          (kk == Tok::Ident && (iequals(t[k].text, "NOT") || iequals(t[k].text, "AND") || iequals(t[k].text, "OR"))))
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
    if (depth == 0 && k.kind == Tok::Ident &&
        (iequals(k.text, "THEN") || iequals(k.text, "DO") || iequals(k.text, "GOTOF") || iequals(k.text, "GOTOB") ||
         iequals(k.text, "GOTO")))
      break;
    if (k.kind == Tok::LParen || k.kind == Tok::LBracket) ++depth;
    if (k.kind == Tok::RParen || k.kind == Tok::RBracket) --depth;
  }
  std::vector<diag::Edit> edits;
  if (!wrapOperands(condStart_, end, edits) || lineLength_ + edits.size() > Lexer::kMaxLineLength) return fix;
  fix.edits = std::move(edits);
  return fix;
}

void Parser::requireNumeric(ExprId e, const char* where) {
  const Expr& x = ex(e);
  if (!x.isBool) return;
  failAt(x.loc, x.len, Code::ChainedComparison,
         fmt::format("a comparison or logical expression cannot be used {}", where));
}

ExprId Parser::parseCondition() {
  checkErrorToken();
  const Token& first = tok();
  condStart_ = i_;
  ExprId e = parseLogicSeq();
  condStart_ = SIZE_MAX;
  if (!ex(e).isBool)
    failAt(locOf(first), first.len, Code::LogicOperand,
           "a condition must be a comparison (e.g. R1 <> 0); a bare value is not a condition");
  if (tok().kind == Tok::Assign)
    failAt(locOf(tok()), 1, Code::AssignInCondition, "'=' is assignment; did you mean '=='?");
  return e;
}

ExprId Parser::parseLogicSeq() {
  ExprId a = parseRelation();
  bool first = true;
  while (isIdent("AND") || isIdent("OR")) {
    const Token& opTok = tok();
    LogicOp op = isIdent("AND") ? LogicOp::And : LogicOp::Or;
    const char* opName = op == LogicOp::And ? "AND" : "OR";
    // Only the written operands must be groups: after the first operator, `a` is the
    // left-to-right result so far ((A) OR (B) AND (C) is ((A) OR (B)) AND (C), SPEC §3.2).
    if (first) requireLogicOperand(a, opName);
    first = false;
    ++i_;
    ExprId b = parseRelation();
    requireLogicOperand(b, opName);
    Expr e;
    e.kind = ExprKind::Logic;
    e.op = static_cast<uint8_t>(op);
    e.isBool = true;
    e.a = a;
    e.b = b;
    e.loc = ex(a).loc;
    e.len = spanLen(e.loc);
    (void)opTok;
    a = addExpr(e);
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
    const Token& opTok = tok();
    requireNumeric(a, "as an operand of a comparison");
    ++i_;
    ExprId b = parseSum();
    requireNumeric(b, "as an operand of a comparison");
    Expr e;
    e.kind = ExprKind::Compare;
    e.op = static_cast<uint8_t>(op);
    e.isBool = true;
    e.a = a;
    e.b = b;
    e.loc = ex(a).loc;
    e.len = spanLen(e.loc);
    a = addExpr(e);
    CmpOp op2;
    if (relop(tok().kind, op2))
      fail(tok(), Code::ChainedComparison,
           fmt::format("two comparisons at one level ('{}' then '{}'); write (a {} b) AND (b {} c)", cmpOpText(op),
                       cmpOpText(op2), cmpOpText(op), cmpOpText(op2)));
    (void)opTok;
  }
  if (tok().kind == Tok::Assign)
    failAt(locOf(tok()), 1, Code::AssignInCondition, "'=' is assignment; did you mean '=='?");
  return a;
}

ExprId Parser::parseArith() {
  ExprId e = parseSum();
  requireNumeric(e, "in arithmetic (comparisons belong in IF and WHEN conditions)");
  CmpOp op;
  if (relop(tok().kind, op))
    fail(tok(), Code::ChainedComparison,
         fmt::format("comparison '{}' inside arithmetic; comparisons belong in IF and WHEN conditions", cmpOpText(op)));
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
    requireNumeric(a, "in arithmetic");
    ++i_;
    ExprId b = parseUnary();
    requireNumeric(b, "in arithmetic");
    Expr e;
    e.kind = ExprKind::Binary;
    e.op = static_cast<uint8_t>(op);
    e.a = a;
    e.b = b;
    e.loc = ex(a).loc;
    e.len = spanLen(e.loc);
    a = addExpr(e);
  }
}

ExprId Parser::parseUnary() {
  // Every nested group and unary operator passes here: the recursion depth is bounded.
  if (depth_ >= kMaxExprDepth)
    fail(tok(), Code::Syntax, fmt::format("expression nested too deeply (more than {} levels)", kMaxExprDepth));
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
    requireNumeric(a, "after unary '-'");
    if (ex(a).kind == ExprKind::Number && !ex(a).paren) {
      ex(a).value = -ex(a).value;
      ex(a).loc = locOf(t);
      return a;
    }
    Expr e;
    e.kind = ExprKind::Neg;
    e.a = a;
    e.loc = locOf(t);
    return addExpr(e);
  }
  if (t.kind == Tok::Plus) {
    ++i_;
    ExprId a = parseUnary();
    requireNumeric(a, "after unary '+'");
    return a;
  }
  if (isIdent("NOT")) {
    ++i_;
    ExprId a = parseUnary();
    requireLogicOperand(a, "NOT");
    Expr e;
    e.kind = ExprKind::Not;
    e.isBool = true;
    e.a = a;
    e.loc = locOf(t);
    e.len = t.len;
    return addExpr(e);
  }
  return parsePrimary();
}

ExprId Parser::parsePrimary() {
  checkErrorToken();
  const Token& t = tok();
  Expr e;
  e.loc = locOf(t);
  e.len = t.len;
  switch (t.kind) {
  case Tok::Number:
    e.kind = t.tooManyDigits ? ExprKind::Error : ExprKind::Number;
    e.value = t.value;
    ++i_;
    return addExpr(e);
  case Tok::Word:
    if (t.addr[0] == 'R' && t.addr[1] == 0) {
      e.kind = ExprKind::RParam;
      if (t.value < 0) fail(t, Code::Syntax, "write a negated R parameter as -R1, not R-1");
      if (t.tooManyDigits) {
        e.rIndex = -1; // E101 already reported
      } else if (t.hasSep || t.value < 1 || t.value > 2880) {
        diags_.report(Code::RIndex, locOf(t), t.len,
                      t.value == 0 && !t.hasSep ? std::string("R0 is reserved for the system; use R1..R2880")
                                                : fmt::format("R index '{}' is outside 1..2880", t.text));
        e.rIndex = -1;
      } else {
        e.rIndex = static_cast<int32_t>(t.value);
      }
      ++i_;
      return addExpr(e);
    }
    fail(t, Code::Syntax, fmt::format("expected an operand (number, R parameter, system variable or '('), found {}",
                                      describe(t)));
  case Tok::Ident:
    if (iequals(t.text, "R") && peekTok().kind == Tok::LBracket) {
      i_ += 2;
      e.kind = ExprKind::RIndirect;
      e.a = parseArith();
      expect(Tok::RBracket, "']' to close R[");
      return addExpr(e);
    }
    if (unsupportedIdent(t)) throw Abort{};
    fail(t, Code::Syntax, fmt::format("expected an operand (number, R parameter, system variable or '('), found {}",
                                      describe(t)));
  case Tok::SysVar: {
    e.sysvar = t.sysvar;
    ++i_;
    if (sysVarTakesAxis(t.sysvar)) {
      e.kind = ExprKind::SysAxis;
      e.axis = parseAxisInBrackets();
      e.len = spanLen(e.loc); // $aa_iw[X] whole
    } else {
      e.kind = ExprKind::SysIndex;
      expect(Tok::LBracket, "'[' and an index");
      e.a = parseArith();
      expect(Tok::RBracket, "']'");
    }
    return addExpr(e);
  }
  case Tok::LParen: {
    ++i_;
    ExprId inner = parseLogicSeq();
    if (tok().kind != Tok::RParen) failExpected("')'");
    ++i_;
    Expr& in = ex(inner);
    if (in.paren) {
      return inner; // ((x)) is (x)
    }
    in.paren = true;
    return inner;
  }
  case Tok::Hash:
    fail(t, Code::Unsupported, "unsupported: '#' macro variables (Fanuc); use R parameters");
  case Tok::String:
    fail(t, Code::Unsupported, "unsupported: strings in expressions");
  default:
    failExpected("an operand (number, R parameter, system variable or '(')");
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

void parseFile(File& file, std::string_view text, const LexOptions& opts, diag::DiagnosticList& diags) {
  file.bytes = text.size();
  Lexer lexer(text, file.id, opts, diags, file.suppressions, file.ownedText);
  Parser parser(file, opts, diags);
  LogicalLine line;
  line.tokens.reserve(64);
  while (lexer.next(line)) parser.parseLine(line);
}

} // namespace iso::frontend
