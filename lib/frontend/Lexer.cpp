//! @file Lexer.cpp
//! @brief The lexer of SPEC §2. One pass over the bytes; continuation is resolved by the
//!        cursor (peek), so tokens may span a `$` join and still know their physical place.
//!        Comments, long numbers and token names have files of their own (LexerInternal.h).
#include "frontend/Lexer.h"

#include <algorithm>
#include <cstdint>
#include <cstring>

#include "frontend/LexerInternal.h"
#include "lang/Addresses.h"
#include "lang/SysVars.h"
#include "support/CaseFold.h"
#include "support/SourceText.h"

namespace iso::frontend {

using diag::Msg;
using namespace lexer_detail;

Lexer::Lexer(std::string_view text, uint32_t fileId, const LexOptions& opts, diag::DiagnosticList& diags,
             std::vector<Suppression>& suppressions, std::deque<std::string>& owned)
    : src_(text), fileId_(fileId), opts_(opts), diags_(diags), suppressions_(suppressions), owned_(owned) {
  for (char a : opts_.axisLetters)
    if (isAlpha(a)) isAddress_[support::upperAscii(a) - 'A'] = true;
  for (char a = 'A'; a <= 'Z'; ++a)
    if (lang::isFixedAddress(a, opts_.dialect)) isAddress_[a - 'A'] = true;
  for (const std::string& u : opts_.userParams)
    if (u.size() == 1 && isAlpha(u[0])) isAddress_[support::upperAscii(u[0]) - 'A'] = true;
  uint32_t start = 0;
  if (src_.size() >= 3 && static_cast<unsigned char>(src_[0]) == 0xEF && static_cast<unsigned char>(src_[1]) == 0xBB &&
      static_cast<unsigned char>(src_[2]) == 0xBF)
    start = 3; // UTF-8 BOM
  cur_.next = start;
  cur_.line = 0;
  end_ = static_cast<uint32_t>(src_.size());
}

void Lexer::setRange(uint32_t begin, uint32_t firstLine, uint32_t end) {
  cur_.next = std::max(cur_.next, begin);
  cur_.line = firstLine - 1;
  end_ = std::min(end, static_cast<uint32_t>(src_.size()));
  crScanned_ = true; // a part of a split file: no file of lone CRs is split
}

void Lexer::scanLoneCrs() {
  crScanned_ = true;
  const uint32_t start = cur_.next;
  // A lone CR (not followed by LF) is an error at its place (lexToken, lexComment). A file
  // whose line ends are lone CRs (old Mac editors: no LF, or one at the very end) gets one
  // diagnostic instead.
  // (In steps: a mapped text's pages ahead of the reader leave memory again once scanned.)
  constexpr size_t kStep = size_t{4} << 20;
  const bool mapped = support::isMappedSource(src_);
  size_t loneCr = 0, firstLoneCr = std::string_view::npos;
  for (size_t from = start; from < src_.size(); from += kStep) {
    const size_t to = std::min(src_.size(), from + kStep);
    const std::string_view step = src_.substr(0, to);
    for (size_t p = step.find('\r', from); p != std::string_view::npos; p = step.find('\r', p + 1))
      if (p + 1 >= src_.size() || src_[p + 1] != '\n')
        if (loneCr++ == 0) firstLoneCr = p;
    if (mapped && from > start) support::dropMappedPages(src_, from, to);
  }
  const size_t lf = loneCr == 0 ? 0 : static_cast<size_t>(std::count(src_.begin() + start, src_.end(), '\n'));
  if (loneCr > lf && lf <= 1) {
    crOnly_ = true;
    size_t lineStart = src_.rfind('\n', firstLoneCr);
    lineStart = lineStart == std::string_view::npos ? 0 : lineStart + 1;
    auto line = static_cast<uint32_t>(
        1 + std::count(src_.begin(), src_.begin() + static_cast<std::ptrdiff_t>(lineStart), '\n'));
    diags_.report(Msg::LoneCrFile, Loc{fileId_, line, static_cast<uint32_t>(firstLoneCr - lineStart + 1)}, 1);
  }
}

/// A `$` in [b, e) that continues the line (peekDollar): one not followed by a name's first
/// character ($AA_IW is a system variable).
static bool hasContinuation(const char* b, const char* e) {
  for (const char* p = b; p < e; ++p) {
    p = static_cast<const char*>(std::memchr(p, '$', static_cast<size_t>(e - p)));
    if (!p) return false;
    if (p + 1 >= e || !isIdentStart(p[1])) return true;
  }
  return false;
}

bool Lexer::isSplitPoint(std::string_view text, uint32_t at) {
  if (at == 0 || at >= text.size() || text[at - 1] != '\n') return false;
  const void* prev = at >= 2 ? memrchr(text.data(), '\n', at - 1) : nullptr;
  const char* b = prev ? static_cast<const char*>(prev) + 1 : text.data();
  return !hasContinuation(b, text.data() + at - 1);
}

bool Lexer::startPhysicalLine(Cursor& c, uint32_t at, uint32_t lineNo) {
  if (at >= src_.size()) return false;
  c.p = at;
  c.lineStart = at;
  c.line = lineNo;
  const void* nl = std::memchr(src_.data() + at, '\n', src_.size() - at);
  uint32_t e =
      nl ? static_cast<uint32_t>(static_cast<const char*>(nl) - src_.data()) : static_cast<uint32_t>(src_.size());
  c.next = nl ? e + 1 : e;
  if (e > at && src_[e - 1] == '\r') --e;
  c.lineEnd = e;
  c.plain = opts_.fastPaths && !hasContinuation(src_.data() + at, src_.data() + e);
  return true;
}

void Lexer::continueLine(Cursor& c) {
  size_t idx = c.line - firstLine_;
  if (joinedBefore_.size() < idx + 2) joinedBefore_.resize(idx + 2, 0);
  joinedBefore_[idx + 1] = joinedBefore_[idx] + (c.p - c.lineStart); // the text before the `$`
  uint32_t lineNo = c.line + 1;
  uint32_t dollar = c.p;
  if (!startPhysicalLine(c, c.next, lineNo)) {
    // `$` on the last line: nothing to join; the content ends at the `$`.
    c.p = dollar;
    c.lineEnd = dollar;
    c.dangling = true;
  }
}

char Lexer::peekDollar(Cursor& c) {
  for (;;) {
    if (c.p >= c.lineEnd) return 0;
    char ch = src_[c.p];
    if (ch == '$') {
      char n = c.p + 1 < c.lineEnd ? src_[c.p + 1] : 0;
      if (!isIdentStart(n)) {
        continueLine(c);
        if (c.dangling) return 0;
        continue;
      }
    }
    return ch;
  }
}

std::string_view Lexer::spanText(const Cursor& from, const Cursor& to) {
  if (from.line == to.line) return src_.substr(from.p, to.p - from.p);
  // The token crosses a `$` join: copy its characters without the continuation.
  std::string s;
  Cursor c = from;
  for (;;) {
    char ch = peek(c); // may move c past a continuation: check the end after it
    if (ch == 0 || (c.line == to.line && c.p >= to.p)) break;
    s.push_back(ch);
    advance(c);
  }
  owned_.push_back(std::move(s));
  return owned_.back();
}

bool Lexer::next(LogicalLine& out) {
  out.tokens.clear();
  out.hadError = false;
  out.truncated = false;
  errorOnLine_ = false;
  truncated_ = false;
  if (!crScanned_) scanLoneCrs();
  if (cur_.next >= end_ || !startPhysicalLine(cur_, cur_.next, cur_.line + 1)) return false;
  cur_.dangling = false;
  firstLine_ = cur_.line;
  joinedBefore_.assign(1, 0);
  out.firstLine = cur_.line;
  lineEnded_ = false;
  size_t suppressionsAtStart = suppressions_.size();
  semicolonAt_ = UINT32_MAX;
  while (!lineEnded_) {
    char c = peek(cur_);
    if (isBlank(c)) { // between tokens; a blank past the 240th character counts at the next token or the end
      advance(cur_);
      continue;
    }
    if (c == 0 && atLineEnd(cur_)) break;
    // Analysis of a logical line stops at its 241st character (E102): the tokens of a line
    // are bounded, and so is every recursion over them.
    // A ';' here starts a comment, which is no part of the logical line: it never is the 241st.
    // (On the first physical line the joined offset is the column: most lines end far earlier.)
    const bool mayBeTooLong = truncated_ || cur_.line != firstLine_ || cur_.p - cur_.lineStart >= kMaxLineLength;
    if ((c != ';' && mayBeTooLong && reportTooLong(joinedOffset(cur_) + 1)) || (c == '\r' && crOnly_)) {
      truncated_ = true; // a CR-only file is reported once, its first line is analysed to the CR
      skipRestOfLine();
      break;
    }
    lexToken(out);
  }
  out.lastLine = cur_.line;
  // A suppression comment covers its whole logical line.
  for (size_t k = suppressionsAtStart; k < suppressions_.size(); ++k)
    if (suppressions_[k].line != 0) {
      suppressions_[k].line = out.firstLine;
      suppressions_[k].lastLine = out.lastLine;
    }
  // A ';' comment ends the content (SPEC §2): its text is not part of the logical line.
  out.length = joinedBefore_[cur_.line - firstLine_] + std::min(cur_.lineEnd, semicolonAt_) - cur_.lineStart;
  reportTooLong(out.length);
  Token& end = out.tokens.emplace_back();
  end.kind = Tok::End;
  end.line = cur_.line;
  end.col = (cur_.p < cur_.lineEnd ? cur_.p : cur_.lineEnd) - cur_.lineStart + 1;
  out.hadError = errorOnLine_;
  out.truncated = truncated_;
  return true;
}

bool Lexer::reportTooLong(uint32_t length) {
  if (truncated_) return true;
  if (length <= kMaxLineLength) return false;
  // The 241st character lies on the last physical line whose text starts at or before it.
  size_t idx = 0;
  while (idx + 1 < joinedBefore_.size() && idx + firstLine_ < cur_.line && joinedBefore_[idx + 1] <= kMaxLineLength)
    ++idx;
  diags_.report(Msg::LineTooLong,
                Loc{fileId_, firstLine_ + static_cast<uint32_t>(idx), kMaxLineLength - joinedBefore_[idx] + 1}, 1,
                kMaxLineLength);
  errorOnLine_ = true;
  truncated_ = true;
  return true;
}

void Lexer::skipRestOfLine() {
  for (;;) {
    char c = peek(cur_);
    if (c == 0 && atLineEnd(cur_)) return;
    if (c == ';') {
      lexSemicolonComment(); // inline suppressions still apply to the line
      return;
    }
    advance(cur_);
  }
}

void Lexer::reportControlByte(uint32_t line, uint32_t col, unsigned char byte) {
  if (byte == '\r') {
    if (crOnly_) return; // reported once for the file
    diags_.report(Msg::LoneCr, Loc{fileId_, line, col}, 1);
  } else {
    diags_.report(Msg::ControlByte, Loc{fileId_, line, col}, 1, byte);
  }
  errorOnLine_ = true;
}

bool Lexer::parenIsGroup(const LogicalLine& out) const {
  if (out.tokens.empty()) return false;
  const Token& t = out.tokens.back();
  switch (t.kind) {
  case Tok::Assign:
  case Tok::Plus:
  case Tok::Minus:
  case Tok::Star:
  case Tok::Eq:
  case Tok::Ne:
  case Tok::Lt:
  case Tok::Gt:
  case Tok::Le:
  case Tok::Ge:
  case Tok::LParen:
  case Tok::LBracket: return true;
  case Tok::Slash:
    // "/" as the skip prefix is not an operator.
    return !(out.tokens.size() == 1 || (out.tokens.size() == 2 && out.tokens[0].kind == Tok::Percent));
  case Tok::KwIf:
  case Tok::KwWhen:
  case Tok::KwCase:
  case Tok::KwNot:
  case Tok::KwAnd:
  case Tok::KwOr:
  case Tok::KwNb: return true;
  default: return false;
  }
}

bool Lexer::identAdjacent(const LogicalLine& out) const {
  // NAME( with no space: a Sinumerik call with arguments or PROC parameters, never a comment.
  if (out.tokens.empty()) return false;
  const Token& t = out.tokens.back();
  if (!isNameTok(t.kind)) return false;
  if (isReservedTok(t.kind)) return false; // ELSE(commento), ENDIF(fine): a comment after a keyword
  if (out.tokens.size() >= 2 && out.tokens[out.tokens.size() - 2].kind == Tok::KwProc) return true;
  return t.line == cur_.line && t.col + t.len == col(cur_);
}

static bool onlyPrefixes(const std::vector<Token>& toks) {
  size_t i = 0;
  if (i < toks.size() && toks[i].kind == Tok::Percent) ++i;
  if (i < toks.size() && toks[i].kind == Tok::Slash) ++i;
  if (i < toks.size() && toks[i].kind == Tok::Word && toks[i].addr[0] == 'N' && toks[i].addr[1] == 0) ++i;
  return i == toks.size();
}

bool Lexer::isAddressAt(Cursor c, char* addr, Cursor& after) {
  char a = support::upperAscii(peek(c));
  if (!isAlpha(a)) return false;
  advance(c);
  {
    Cursor c2 = c;
    char b = support::upperAscii(peek(c2));
    if (twoLetter(a, b)) { // CR; z32: MA MB MC TA TB, user parameters
      advance(c2);
      addr[0] = a;
      addr[1] = b;
      addr[2] = 0;
      after = c2;
      return true;
    }
  }
  if (!isAddress_[a - 'A']) return false;
  addr[0] = a;
  addr[1] = 0;
  addr[2] = 0;
  after = c;
  return true;
}

bool Lexer::lexNumber(Cursor& c, Token& t) {
  if (c.plain) return lexNumberPlain(c.p, c.lineEnd, c.line, c.lineStart, t);
  Cursor start = c;
  NumberScan n;
  for (;;) {
    char ch = peek(c);
    if (isDigit(ch)) {
      n.digit(ch);
      advance(c);
    } else if (isSep(ch) && !n.sep) {
      Cursor c2 = c;
      advance(c2);
      if (n.digits == 0 && !isDigit(peek(c2))) break; // a lone separator is no number
      n.sep = true;
      advance(c);
    } else {
      break;
    }
  }
  if (n.digits == 0) {
    c = start;
    return false;
  }
  t.text = spanText(start, c);
  finishNumber(n, start.line, start.p - start.lineStart + 1, start.line == c.line, t);
  return true;
}

inline bool Lexer::lexNumberPlain(uint32_t& p, uint32_t end, uint32_t line, uint32_t lineStart, Token& t) {
  // No continuation `$` on the line: by offsets, the digits in tight loops, and a number of at most kDigits
  // digits (nearly all) is finished here. The mantissa is only read when there are at most
  // kExactDigits digits (it wraps harmlessly beyond); leading zeros only matter past kDigits.
  const char* const s = src_.data();
  uint32_t q = p;
  uint64_t mantissa = 0;
  while (q < end && isDigit(s[q]))
    mantissa = mantissa * 10 + static_cast<uint64_t>(s[q++] - '0');
  const uint32_t intDigits = q - p;
  uint32_t fraction = 0;
  const bool sep = q < end && isSep(s[q]);
  if (sep) {
    if (intDigits == 0 && !(q + 1 < end && isDigit(s[q + 1]))) return false; // a lone separator is no number
    const uint32_t fracStart = ++q;
    while (q < end && isDigit(s[q]))
      mantissa = mantissa * 10 + static_cast<uint64_t>(s[q++] - '0');
    fraction = q - fracStart;
  } else if (intDigits == 0) {
    return false;
  }
  t.text = std::string_view(s + p, q - p);
  const uint32_t digits = intDigits + fraction;
  if (digits <= kDigits) {
    t.hasSep = sep;
    t.value = static_cast<double>(mantissa) / kPow10[fraction];
  } else {
    NumberScan n;
    n.sep = sep;
    n.digits = digits;
    n.mantissa = mantissa;
    n.fraction = fraction;
    for (uint32_t k = p; k < q && (isSep(s[k]) || s[k] == '0'); ++k)
      n.leadZeros += s[k] == '0';
    finishNumber(n, line, p - lineStart + 1, true, t);
  }
  p = q;
  return true;
}

bool Lexer::tryWordsPlain(LogicalLine& out) {
  // What tryWords does, with offsets into the physical line: no `$` can join it to the next.
  const char* const s = src_.data();
  const uint32_t end = cur_.lineEnd;
  auto at = [&](uint32_t q) { return q < end ? s[q] : '\0'; };
  size_t mark = out.tokens.size();
  uint32_t p = cur_.p;
  // Groups of words separated by blanks are read in one call, as long as next() would do
  // nothing between them but skip the blanks: the line started on this physical line, and the
  // next group starts before the column where E102 is checked. A group that does not come off
  // is left to next(), after the groups before it.
  const bool readOn = cur_.line == firstLine_;
  bool someRead = false;
  uint32_t group = p; // where the current group starts
  for (;;) {
    const char a = support::upperAscii(at(p));
    if (!isAlpha(a)) break;
    // Built where it stays (a token copied right after its fields were written costs a stall
    // on every line); a word that does not come off is dropped below with the others.
    Token& t = out.tokens.emplace_back();
    t.kind = Tok::Word;
    t.line = cur_.line;
    t.col = p - cur_.lineStart + 1;
    uint32_t q = p + 1;
    if (twoLetter(a, support::upperAscii(at(q)))) { // CR; z32: MA MB MC TA TB, user parameters
      t.addr[0] = a;
      t.addr[1] = support::upperAscii(at(q));
      ++q;
    } else if (isAddress_[a - 'A']) {
      t.addr[0] = a;
    } else {
      break;
    }
    while (isBlank(at(q)))
      ++q;
    const char sign = at(q);
    if (sign == '+' || sign == '-') {
      t.hasSign = true;
      ++q;
      while (isBlank(at(q)))
        ++q;
    }
    if (!lexNumberPlain(q, end, cur_.line, cur_.lineStart, t)) break;
    if (sign == '-') t.value = -t.value;
    takeAxisTail(t, q, end);
    t.len = q - p;
    p = q;
    const char nx = at(q);
    if (isIdentStart(nx)) continue; // packed words: N12G0X0
    if (isDigit(nx)) break;
    // "A1:" is a label: the colon decides.
    while (isBlank(at(q)))
      ++q;
    if (at(q) == ':') break;
    cur_.p = p;
    someRead = true;
    if (!readOn || q == p || q - cur_.lineStart >= kMaxLineLength || !isAlpha(at(q))) return true;
    // z32: a GO target after the line number (N30 GON40-N50) is next()'s to lex
    if (opts_.dialect == machine::Dialect::Z32 && support::upperAscii(at(q)) == 'G' &&
        support::upperAscii(at(q + 1)) == 'O')
      return true;
    mark = out.tokens.size(); // the group is read: on to the next one, after the blanks
    p = group = q;
  }
  out.tokens.resize(mark);
  if (!someRead) return false;
  // A later group that does not come off is a name, as next() would find it (lexToken: tryWords
  // fails, then lexIdent). It is lexed here: tried again, its numbers would report E101 twice.
  cur_.p = group;
  lexIdent(out);
  return true;
}

bool Lexer::tryWords(LogicalLine& out) {
  if (cur_.plain) return tryWordsPlain(out);
  Cursor c = cur_;
  size_t mark = out.tokens.size();
  for (;;) {
    Token& t = out.tokens.emplace_back(); // in place, as in tryWordsPlain
    setPosition(t, Tok::Word, c);
    Cursor after;
    if (!isAddressAt(c, t.addr, after)) break;
    c = after;
    while (isBlank(peek(c)))
      advance(c);
    bool neg = false;
    char s = peek(c);
    if (s == '+' || s == '-') {
      neg = s == '-';
      t.hasSign = true;
      advance(c);
      while (isBlank(peek(c)))
        advance(c);
    }
    if (!lexNumber(c, t)) break;
    if (neg) t.value = -t.value;
    if (c.line == t.line) takeAxisTail(t, c.p, c.lineEnd);
    t.len = c.line == t.line ? c.p - (t.col - 1 + c.lineStart) : 1;
    t.joined = c.line != t.line;
    char nx = peek(c);
    if (isIdentStart(nx)) continue; // packed words: N12G0X0
    if (isDigit(nx)) break;
    // "A1:" is a label: the colon decides.
    Cursor c2 = c;
    while (isBlank(peek(c2)))
      advance(c2);
    if (peek(c2) == ':') break;
    cur_ = c;
    return true;
  }
  out.tokens.resize(mark);
  return false;
}

bool Lexer::twoLetter(char a, char b) const {
  if (lang::startsTwoLetterAddress(a, opts_.dialect) && lang::isTwoLetterAddress(a, b, opts_.dialect)) return true;
  for (const std::string& u : opts_.userParams)
    if (u.size() == 2 && u[0] == a && u[1] == b) return true;
  return false;
}

uint32_t Lexer::userParamAt(uint32_t p, uint32_t end) const {
  for (const std::string& u : opts_.userParams) {
    auto n = static_cast<uint32_t>(u.size());
    if (p + n > end || (p + n < end && isIdentChar(src_[p + n]))) continue;
    if (support::iequals(src_.substr(p, n), u)) return n;
  }
  return 0;
}

void Lexer::takeAxisTail(Token& t, uint32_t& q, uint32_t end) const {
  if (opts_.dialect != machine::Dialect::Z32 || t.addr[0] != 'G' || t.addr[1] != 0 || t.hasSep || t.hasSign ||
      (t.value != 28 && t.value != 29))
    return;
  uint32_t r = q;
  while (r < end && isAlpha(src_[r]))
    ++r;
  if (r == q || t.text.data() + t.text.size() != src_.data() + q) return;
  uint32_t k = r;
  while (k < end && isBlank(src_[k]))
    ++k;
  // Letters followed by a number are words (G29X100, G29X 100): no tail then.
  if (k < end && (isDigit(src_[k]) || isSep(src_[k]) || src_[k] == '+' || src_[k] == '-' || src_[k] == '=' ||
                  src_[k] == '[' || src_[k] == '_'))
    return;
  t.text = std::string_view(t.text.data(), t.text.size() + (r - q));
  q = r;
}

bool Lexer::tryGoTarget(LogicalLine& out) {
  const uint32_t p = cur_.p, end = cur_.lineEnd;
  auto at = [&](uint32_t q) { return q < end ? src_[q] : '\0'; };
  auto stops = [&](char ch) {
    return ch == 0 || isBlank(ch) || ch == '!' || ch == ';' || ch == '-' || ch == '$' ||
           isControl(static_cast<unsigned char>(ch));
  };
  const size_t n = out.tokens.size();
  const bool rangeEnd = n >= 2 && out.tokens[n - 1].kind == Tok::Minus && out.tokens[n - 2].kind == Tok::GoTarget;
  uint32_t from = p;
  if (!rangeEnd) {
    if (support::upperAscii(at(p)) != 'G' || support::upperAscii(at(p + 1)) != 'O') return false;
    const char c3 = at(p + 2);
    const char c4 = at(p + 3);
    bool shape = c3 == '%' || c3 == '/' || (support::upperAscii(c3) == 'N' && (isDigit(c4) || isSep(c4)));
    if (!shape) return false;
    from = p + 2;
  }
  uint32_t stop = from;
  while (!stops(at(stop)))
    ++stop;
  if (stop == from) return false;
  Token& t = out.tokens.emplace_back();
  setPosition(t, Tok::GoTarget, cur_);
  t.text = src_.substr(from, stop - from);
  t.len = stop - p;
  cur_.p = stop;
  return true;
}

void Lexer::lexIdent(LogicalLine& out) {
  Cursor start = cur_;
  Token& t = out.tokens.emplace_back();
  setPosition(t, Tok::Ident, cur_);
  while (isIdentChar(peek(cur_)))
    advance(cur_);
  t.text = spanText(start, cur_);
  t.len = cur_.line == start.line ? cur_.p - start.p : static_cast<uint32_t>(start.lineEnd - start.p);
  t.joined = cur_.line != start.line;
  if (auto kw = lang::findKeyword(t.text)) t.kind = keywordTok(*kw); // the one keyword lookup
}

void Lexer::lexSysVar(LogicalLine& out) {
  Cursor start = cur_;
  Token& t = out.tokens.emplace_back(); // in place, as every token (see tryWordsPlain)
  setPosition(t, Tok::SysVar, cur_);
  advance(cur_); // '$'
  while (isIdentChar(peek(cur_)))
    advance(cur_);
  t.text = spanText(start, cur_);
  t.len = cur_.line == start.line ? cur_.p - start.p : 1;
  t.joined = cur_.line != start.line;
  if (auto sv = lang::findSysVar(t.text)) {
    t.sysvar = sv->id;
    if (sv->alias) {
      auto& d = diags_.report(Msg::SysvarAlias, Loc{fileId_, t.line, t.col}, t.len, t.text, sysVarName(sv->id));
      if (!t.joined)
        d.fixes.push_back({diag::message(Msg::SysvarAliasFix, t.text, sysVarName(sv->id)),
                           {{d.loc, t.line, t.col + t.len, sysVarName(sv->id)}}});
    }
    return;
  }
  diags_.report(Msg::UnknownSysvar, Loc{fileId_, t.line, t.col}, t.len, printableBytes(t.text));
  errorOnLine_ = true;
  t.kind = Tok::Error;
}

void Lexer::lexString(LogicalLine& out) {
  Token& t = out.tokens.emplace_back();
  setPosition(t, Tok::String, cur_);
  uint32_t p = cur_.p + 1;
  while (p < cur_.lineEnd && src_[p] != '"')
    ++p;
  if (p >= cur_.lineEnd) {
    diags_.report(Msg::StringUnclosed, Loc{fileId_, t.line, t.col}, 1);
    errorOnLine_ = true;
    t.kind = Tok::Error;
    cur_.p = cur_.lineEnd;
    lineEnded_ = true;
    return;
  }
  t.text = src_.substr(cur_.p + 1, p - cur_.p - 1);
  t.len = p + 1 - cur_.p;
  cur_.p = p + 1;
}

void Lexer::lexToken(LogicalLine& out) {
  char c = peek(cur_);
  if (opts_.dialect == machine::Dialect::Z32 && (isIdentStart(c) || c == '%' || c == '/' || c == 'N') &&
      tryGoTarget(out))
    return;
  if (isIdentStart(c) && !opts_.userParams.empty() && parenIsGroup(out) && userParamAt(cur_.p, cur_.lineEnd) > 0) {
    lexIdent(out); // a user parameter read in an expression: R1=HA+1 is HA plus 1, not the word HA+1
    return;
  }
  if (isIdentStart(c)) {
    const Token* prev = out.tokens.empty() ? nullptr : &out.tokens.back();
    bool labelNext = prev && (prev->kind == Tok::KwGotof || prev->kind == Tok::KwGotob || prev->kind == Tok::KwGoto);
    if (labelNext || !tryWords(out)) lexIdent(out);
    return;
  }
  switch (c) { // what makes no token here, or one of its own
  case ';': lexSemicolonComment(); return;
  case '(':
    if (!parenIsGroup(out) && !identAdjacent(out)) {
      lexComment(onlyPrefixes(out.tokens));
      return;
    }
    break;
  case '$': lexSysVar(out); return;
  case '"': lexString(out); return;
  default: break;
  }
  // Every other way ends in exactly one token, built in place (see tryWordsPlain).
  Token& t = out.tokens.emplace_back();
  setPosition(t, Tok::Other, cur_);
  auto single = [&](Tok k) {
    t.kind = k;
    advance(cur_);
  };
  auto other = [&] { // one byte that starts no token: the parser reports it
    t.text = src_.substr(cur_.p, 1);
    single(Tok::Other);
  };
  auto maybeTwo = [&](char second, Tok one, Tok two) {
    Cursor c2 = cur_;
    advance(c2);
    if (peek(c2) == second) {
      t.kind = two;
      t.len = 2;
      t.joined = c2.line != t.line;
      advance(c2);
      cur_ = c2;
    } else {
      single(one);
    }
  };
  if (isDigit(c) || (isSep(c))) {
    t.kind = Tok::Number;
    Cursor start = cur_;
    if (lexNumber(cur_, t)) {
      t.len = cur_.line == start.line ? cur_.p - start.p : 1;
      t.joined = cur_.line != start.line;
      return;
    }
    other();
    return;
  }
  switch (c) {
  case '(': single(Tok::LParen); return;
  case ')': single(Tok::RParen); return;
  case '[': single(Tok::LBracket); return;
  case ']': single(Tok::RBracket); return;
  case '+': single(Tok::Plus); return;
  case '-': single(Tok::Minus); return;
  case '*': single(Tok::Star); return;
  case '/': single(Tok::Slash); return;
  case ':': single(Tok::Colon); return;
  case '%': single(Tok::Percent); return;
  case '#': single(Tok::Hash); return;
  case '=': maybeTwo('=', Tok::Assign, Tok::Eq); return;
  case '>': maybeTwo('=', Tok::Gt, Tok::Ge); return;
  case '<': {
    Cursor c2 = cur_;
    advance(c2);
    if (peek(c2) == '>') {
      t.kind = Tok::Ne;
      t.len = 2;
      t.joined = c2.line != t.line;
      advance(c2);
      cur_ = c2;
      return;
    }
    maybeTwo('=', Tok::Lt, Tok::Le);
    return;
  }
  default: break;
  }
  if (isControl(static_cast<unsigned char>(c))) {
    reportControlByte(t.line, t.col, static_cast<unsigned char>(c));
    advance(cur_);
    t.kind = Tok::Error;
    return;
  }
  if (static_cast<unsigned char>(c) >= 0x80) {
    diags_.report(Msg::NonAsciiByte, Loc{fileId_, t.line, t.col}, 1, static_cast<unsigned char>(c));
    errorOnLine_ = true;
    advance(cur_);
    while (cur_.p < cur_.lineEnd && (static_cast<unsigned char>(src_[cur_.p]) & 0xC0) == 0x80)
      advance(cur_);
    t.kind = Tok::Error;
    return;
  }
  other();
}

} // namespace iso::frontend
