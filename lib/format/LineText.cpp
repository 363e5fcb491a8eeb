//! @file LineText.cpp
//! @brief One line written again from its tokens (LineText.h).
#include "format/LineText.h"

#include <cmath>
#include <deque>

#include <fmt/format.h>

#include "frontend/Parser.h"
#include "lang/Limits.h"
#include "support/CaseFold.h"

namespace iso::format {

using frontend::Tok;
using frontend::Token;

namespace {

bool isBlank(char c) { return c == ' ' || c == '\t'; }

std::string_view trim(std::string_view s) {
  while (!s.empty() && isBlank(s.front()))
    s.remove_prefix(1);
  while (!s.empty() && isBlank(s.back()))
    s.remove_suffix(1);
  return s;
}

bool hasNonBlank(std::string_view s) {
  for (char c : s)
    if (!isBlank(c)) return true;
  return false;
}

size_t tokStart(const Token& t) { return t.col - 1; }
size_t tokEnd(const Token& t) { return t.col - 1 + t.len; }

bool isPrefixSlash(const std::vector<Token>& toks, size_t k) {
  return toks[k].kind == Tok::Slash && (k == 0 || (k == 1 && toks[0].kind == Tok::Percent));
}

bool isSign(const Token& t) { return t.kind == Tok::Plus || t.kind == Tok::Minus; }

/// The token at `k` ends an operand: a sign after it is an operator, not a sign.
bool endsOperand(const std::vector<Token>& toks, size_t k) {
  switch (toks[k].kind) {
  case Tok::Number:
  case Tok::Word:
  case Tok::RParen:
  case Tok::RBracket:
  case Tok::SysVar:
  case Tok::String: return true;
  case Tok::Ident: return k == 0 || !frontend::isJumpTok(toks[k - 1].kind); // a label ends no operand
  default: return false;
  }
}

bool isUnary(const std::vector<Token>& toks, size_t k) { return k == 0 || !endsOperand(toks, k - 1); }

/// `=`, the comparisons and the arithmetic operators (a `/` or a sign may be something else).
bool isOperatorKind(Tok k) {
  switch (k) {
  case Tok::Assign:
  case Tok::Eq:
  case Tok::Ne:
  case Tok::Lt:
  case Tok::Gt:
  case Tok::Le:
  case Tok::Ge:
  case Tok::Star:
  case Tok::Slash:
  case Tok::Plus:
  case Tok::Minus: return true;
  default: return false;
  }
}

bool isOperator(const std::vector<Token>& toks, size_t k) {
  if (toks[k].kind == Tok::Slash) return !isPrefixSlash(toks, k);
  if (isSign(toks[k])) return !isUnary(toks, k);
  return isOperatorKind(toks[k].kind);
}

/// A `(` after this token groups an operand (a blank before it changes nothing).
bool opensOperand(const Token& t) {
  switch (t.kind) {
  case Tok::KwIf:
  case Tok::KwWhen:
  case Tok::KwCase:
  case Tok::KwNot:
  case Tok::KwAnd:
  case Tok::KwOr: return true;
  default: return isOperatorKind(t.kind);
  }
}

/// The `=` at `k` is a block item's (X=R20, F=40, CR=20, Posa[C]=90, M=NB(4)): written without
/// blanks, as the programs of the SIDAC manual write them. An assignment to a parameter or a
/// system variable (R1 = 5, R[R2] = 0, $aa_out[3] = 1, PAR[4] = 1) has blanks around it.
bool isItemAssign(const std::vector<Token>& toks, size_t k, const std::vector<std::string>& userParams) {
  if (k == 0 || toks[k].kind != Tok::Assign) return false;
  const Token& lhs = toks[k - 1];
  if (lhs.kind == Tok::Ident) {
    if (k >= 2 && toks[k - 2].kind == Tok::RBracket) return false;
    for (const auto& u : userParams)
      if (support::iequals(u, lhs.text)) return false;
    return lhs.text.size() <= 2;
  }
  if (lhs.kind != Tok::RBracket) return false;
  size_t depth = 0;
  for (size_t j = k - 1; j > 0; --j) {
    if (toks[j].kind == Tok::RBracket) ++depth;
    if (toks[j].kind == Tok::LBracket && --depth == 0) {
      const Tok before = toks[j - 1].kind;
      return before == Tok::KwPos || before == Tok::KwPosa || before == Tok::KwFa;
    }
  }
  return false;
}

bool isNumberText(std::string_view s) {
  if (s.empty()) return false;
  for (char c : s)
    if (!(c >= '0' && c <= '9') && c != '.' && c != ',') return false;
  return true;
}

bool sameValue(double a, double b) { return a == b && std::signbit(a) == std::signbit(b); }

bool sameToken(const Token& a, const Token& b, bool numbersMayDiffer) {
  if (a.kind != b.kind || a.joined || b.joined) return false;
  switch (a.kind) {
  case Tok::Word:
    if (a.addr[0] != b.addr[0] || a.addr[1] != b.addr[1] || a.hasSign != b.hasSign) return false;
    if (!numbersMayDiffer || a.addr[0] == 'N') return support::iequals(a.text, b.text);
    return sameValue(a.value, b.value) && a.hasSep == b.hasSep;
  case Tok::Number:
    if (!numbersMayDiffer) return a.text == b.text;
    return sameValue(a.value, b.value) && a.hasSep == b.hasSep;
  case Tok::SysVar: return a.sysvar == b.sysvar && support::iequals(a.text, b.text);
  case Tok::String:
  case Tok::GoTarget:
  case Tok::Other: return a.text == b.text;
  default: return !(frontend::isNameTok(a.kind)) || support::iequals(a.text, b.text);
  }
}

} // namespace

size_t prefixCount(const std::vector<Token>& toks) {
  size_t i = 0;
  if (i < toks.size() && toks[i].kind == Tok::Percent) ++i;
  if (i < toks.size() && toks[i].kind == Tok::Slash) ++i;
  if (i < toks.size() && toks[i].kind == Tok::Word && toks[i].addr[0] == 'N' && toks[i].addr[1] == 0) ++i;
  return i;
}

size_t statementStart(const std::vector<Token>& toks) {
  size_t p = prefixCount(toks);
  if (p + 1 < toks.size() && frontend::isNameTok(toks[p].kind) && toks[p + 1].kind == Tok::Colon) p += 2;
  return p;
}

bool sameTokens(const std::vector<Token>& a, const std::vector<Token>& b, bool numbersMayDiffer) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i)
    if (!sameToken(a[i], b[i], numbersMayDiffer)) return false;
  return true;
}

uint32_t firstSyntaxErrorLine(std::string_view text, const frontend::LexOptions& lex) {
  diag::DiagnosticList diags;
  frontend::File file;
  file.source = text;
  frontend::parseFile(file, text, lex, diags);
  uint32_t first = 0;
  for (const auto& d : diags.items())
    if (d.severity == diag::Severity::Error && (first == 0 || d.loc.line < first)) first = d.loc.line;
  if (first == 0 && diags.hasErrors()) first = 1;
  return first;
}

std::string normaliseNumber(std::string_view digits) {
  std::string s;
  s.reserve(digits.size() + 1);
  if (!digits.empty() && (digits[0] == '.' || digits[0] == ',')) s.push_back('0');
  for (char c : digits)
    s.push_back(c == ',' ? '.' : c);
  return s;
}

std::string LineWriter::cased(std::string_view s) const {
  switch (opts_.style.wordCase) {
  case WordCase::Upper: return support::upperCopy(s);
  case WordCase::Lower: return support::lowerCopy(s);
  case WordCase::Keep: break;
  }
  return std::string(s);
}

std::string LineWriter::tokenText(const std::vector<Token>& toks, size_t i, std::string_view raw) const {
  const Token& t = toks[i];
  const std::string_view slice = raw.substr(tokStart(t), t.len);
  const bool normalise = opts_.style.numbers == NumberStyle::Normalised;
  switch (t.kind) {
  case Tok::Word: {
    const size_t letters = t.addr[1] != 0 ? 2 : 1;
    std::string s = cased(slice.substr(0, letters));
    std::string_view rest = slice.substr(letters);
    while (!rest.empty() && isBlank(rest.front()))
      rest.remove_prefix(1);
    if (!rest.empty() && (rest.front() == '+' || rest.front() == '-')) {
      s.push_back(rest.front());
      rest.remove_prefix(1);
      while (!rest.empty() && isBlank(rest.front()))
        rest.remove_prefix(1);
    }
    const char a = t.addr[0];
    const bool plain = t.addr[1] != 0 || (a != 'N' && a != 'G' && a != 'M');
    if (normalise && plain && isNumberText(rest)) return s + normaliseNumber(rest);
    return s + (isNumberText(rest) ? std::string(rest) : cased(rest)); // G29ab: axis letters
  }
  case Tok::Number: return normalise ? normaliseNumber(slice) : std::string(slice);
  case Tok::Ident: {
    const size_t n = toks.size();
    const bool assigned = i + 1 < n && (toks[i + 1].kind == Tok::Assign || toks[i + 1].kind == Tok::LBracket);
    const bool axis = i > 0 && toks[i - 1].kind == Tok::LBracket && i + 1 < n && toks[i + 1].kind == Tok::RBracket;
    bool param = false;
    for (const auto& u : opts_.lex.userParams)
      param = param || support::iequals(u, t.text);
    return assigned || axis || param ? cased(slice) : std::string(slice);
  }
  case Tok::SysVar: return cased(slice);
  case Tok::GoTarget:
    if (t.len == t.text.size() + 2) return cased(slice.substr(0, 2)) + std::string(slice.substr(2));
    return std::string(slice);
  default: return frontend::isKeywordTok(t.kind) ? cased(slice) : std::string(slice);
  }
}

std::string LineWriter::separator(const std::vector<Token>& toks, size_t i, std::string_view raw) const {
  const Token& a = toks[i - 1];
  const Token& b = toks[i];
  const std::string_view gap = raw.substr(tokEnd(a), tokStart(b) - tokEnd(a));
  if (hasNonBlank(gap)) return fmt::format(" {} ", trim(gap)); // `( … )` comments
  const std::string keep = gap.empty() ? "" : " ";
  const std::string op = opts_.style.spaceAroundOperators ? " " : "";
  if ((a.kind == Tok::Percent && i == 1) || isPrefixSlash(toks, i - 1)) return "";
  if (b.kind == Tok::Colon) return "";
  if (a.kind == Tok::LBracket || b.kind == Tok::RBracket || b.kind == Tok::LBracket) return "";
  if (a.kind == Tok::LParen || b.kind == Tok::RParen) return "";
  if (b.kind == Tok::LParen) {
    if (a.kind == Tok::KwNb) return "";
    return opensOperand(a) ? " " : keep; // NAME(...) stays NAME(...)
  }
  auto verbatim = [](const Token& t) { return t.kind == Tok::Other || t.kind == Tok::Hash || t.kind == Tok::Error; };
  if (verbatim(a) || verbatim(b)) return keep;
  // a GO range keeps its separator as written: GON10-N20, GON10 - N20
  if ((b.kind == Tok::Minus && a.kind == Tok::GoTarget) ||
      (a.kind == Tok::Minus && i >= 2 && toks[i - 2].kind == Tok::GoTarget))
    return keep;
  const auto& params = opts_.lex.userParams;
  if (isItemAssign(toks, i - 1, params) || isItemAssign(toks, i, params)) return "";
  if (isSign(a) && isUnary(toks, i - 1)) return "";
  if (isSign(b) && isUnary(toks, i)) return isOperator(toks, i - 1) ? op : " ";
  if (isOperator(toks, i - 1) || isOperator(toks, i)) return op;
  if (a.kind == Tok::Word && b.kind == Tok::Word && !opts_.style.spaceBetweenWords) return "";
  return " ";
}

bool LineWriter::writeHead(std::string_view raw, const std::vector<Token>& toks, uint32_t depth, std::string& out,
                           size_t& next) const {
  // z32: a GO target finds a line by its first characters, exactly as written: the prefixes
  // and N number (or a name such as the label N1:) at the start of a line stay byte for byte,
  // with whatever stands before them.
  const size_t p = prefixCount(toks);
  size_t h = 0;
  if (opts_.lex.dialect == machine::Dialect::Z32) {
    if (p > 0)
      h = p;
    else if (frontend::isNameTok(toks[0].kind) && !toks[0].text.empty() && support::upperAscii(toks[0].text[0]) == 'N')
      h = 1;
  }
  for (size_t k = 1; k < h; ++k)
    if (hasNonBlank(raw.substr(tokEnd(toks[k - 1]), tokStart(toks[k]) - tokEnd(toks[k - 1])))) return false;
  if (h > 0) {
    out.assign(raw.substr(0, tokEnd(toks[h - 1])));
  } else {
    for (size_t k = 0; k < p; ++k) {
      if (k > 0) out += separator(toks, k, raw);
      out += tokenText(toks, k, raw);
    }
  }
  next = std::max(h, p);
  if (next >= toks.size()) return true;
  if (next > 0) out += separator(toks, next, raw);
  const std::string indent(static_cast<size_t>(depth) * opts_.style.indent, ' ');
  if (!indent.empty() && !out.empty() && out.back() != ' ') out += ' ';
  out += indent;
  out += tokenText(toks, next, raw);
  ++next;
  return true;
}

void LineWriter::writeTail(std::string_view raw, const std::vector<Token>& toks, std::string& out,
                           size_t& commentAt) const {
  const size_t from = tokEnd(toks.back());
  const std::string_view rest = trim(raw.substr(from));
  commentAt = out.size();
  if (rest.empty()) return;
  if (rest.front() == ';') {
    // A trailing comment keeps its column while the text before it fits, else one blank.
    const size_t col = static_cast<size_t>(rest.data() - raw.data());
    out += out.size() < col ? std::string(col - out.size(), ' ') : " ";
    commentAt = out.size();
    out += rest;
    return;
  }
  out += ' ';
  int paren = 0;
  size_t semicolon = std::string_view::npos;
  for (size_t k = 0; k < rest.size() && semicolon == std::string_view::npos; ++k) {
    if (rest[k] == '(') ++paren;
    if (rest[k] == ')') paren = 0;
    if (rest[k] == ';' && paren == 0) semicolon = k;
  }
  commentAt = semicolon == std::string_view::npos ? out.size() + rest.size() : out.size() + semicolon;
  out += rest;
}

bool LineWriter::relexes(std::string_view line, const std::vector<Token>& toks) const {
  diag::DiagnosticList diags;
  std::vector<frontend::Suppression> suppressions;
  std::deque<std::string> owned;
  frontend::Lexer lexer(line, 0, opts_.lex, diags, suppressions, owned);
  frontend::LogicalLine l;
  if (!lexer.next(l) || l.hadError || l.truncated) return false;
  l.tokens.pop_back();
  frontend::LogicalLine more;
  if (lexer.next(more)) return false;
  return sameTokens(toks, l.tokens, opts_.style.numbers == NumberStyle::Normalised);
}

WrittenLine LineWriter::write(std::string_view raw, const std::vector<Token>& toks, uint32_t depth) const {
  WrittenLine asWritten{false, {}, {}};
  const std::string indent(static_cast<size_t>(depth) * opts_.style.indent, ' ');
  std::string out;
  size_t commentAt = 0;
  if (toks.empty()) { // blank, or a comment line
    const std::string_view text = trim(raw);
    out = text.empty() ? "" : indent + std::string(text);
    commentAt = text.empty() || text.front() == ';' ? 0 : out.size();
  } else {
    if (hasNonBlank(raw.substr(0, tokStart(toks[0])))) return asWritten;
    for (const Token& t : toks)
      if (t.joined || tokEnd(t) > raw.size()) return asWritten;
    size_t next = 0;
    if (!writeHead(raw, toks, depth, out, next)) return asWritten;
    for (size_t i = next; i < toks.size(); ++i) {
      out += separator(toks, i, raw);
      out += tokenText(toks, i, raw);
    }
    writeTail(raw, toks, out, commentAt);
  }
  if (commentAt > lang::kMaxLineLength && out != raw) {
    asWritten.why = "left as written: formatted, the line would be longer than 240 characters";
    return asWritten;
  }
  if (!toks.empty() && !relexes(out, toks)) {
    asWritten.why = "left as written: its formatted text would not read as the same words";
    return asWritten;
  }
  return WrittenLine{true, std::move(out), {}};
}

} // namespace iso::format
