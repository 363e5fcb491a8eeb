//! @file Lexer.h
//! @brief Turns a source file into logical lines of tokens (SPEC §2): `;` comments, `$`
//!        continuation, `( … )` comments, numbers, packed words vs identifiers, system
//!        variables. Every token keeps its physical line and column.
#pragma once

#include <cstdint>
#include <exception>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "diag/Diagnostic.h"
#include "frontend/Ast.h"
#include "lang/Axes.h"
#include "lang/Keywords.h"
#include "lang/Limits.h"
#include "machine/Machine.h"

namespace iso::frontend {

enum class Tok : uint8_t {
  End,
  Word,   ///< address + number: addr, value, numText
  Ident,  ///< text
  Number, ///< value, numText (unsigned)
  SysVar, ///< sysvar (alias flagged)
  String, ///< text (without quotes)
  Plus,
  Minus,
  Star,
  Slash,
  Assign, ///< =
  Eq,
  Ne,
  Lt,
  Gt,
  Le,
  Ge,
  LParen,
  RParen,
  LBracket,
  RBracket,
  Colon,
  Percent,
  Hash,
  GoTarget, ///< z32: a GO target: text = the target as written ("N12", "%N1"); the token spans `GO` too unless it ends
            ///< a range
  Other,    ///< any other character (text)
  Error,    ///< a lexical error already reported
// One kind per keyword of lang/Keywords.def (text keeps the spelling as written).
#define ISO_KEYWORD(Name, spelling, reserved) Kw##Name,
#include "lang/Keywords.def"
};
const char* tokName(Tok t);

constexpr Tok kFirstKeywordTok = Tok::KwIf;
constexpr bool isKeywordTok(Tok t) { return t >= kFirstKeywordTok; }
constexpr Tok keywordTok(lang::Keyword k) {
  return static_cast<Tok>(static_cast<unsigned>(kFirstKeywordTok) + static_cast<unsigned>(k));
}
constexpr lang::Keyword keywordOf(Tok t) {
  return static_cast<lang::Keyword>(static_cast<unsigned>(t) - static_cast<unsigned>(kFirstKeywordTok));
}
/// A reserved keyword (IF, GOTOF, ...): never a label or a subprogram name.
constexpr bool isReservedTok(Tok t) { return isKeywordTok(t) && lang::keywordInfo(keywordOf(t)).reserved; }
constexpr bool isJumpTok(Tok t) { return t == Tok::KwGotof || t == Tok::KwGotob || t == Tok::KwGoto; }
/// A name as written: an identifier, or a keyword (which the grammar may reject as a name).
constexpr bool isNameTok(Tok t) { return t == Tok::Ident || isKeywordTok(t); }

struct Token {
  Tok kind = Tok::End;
  char addr[3] = {0, 0, 0};   ///< Word: upper-case address ("X", "CR", "MA")
  bool hasSep = false;        ///< number has a decimal separator
  bool tooManyDigits = false; ///< E101 already reported
  bool hasSign = false;       ///< Word: a sign was written before the number
  bool joined = false;        ///< the token crosses a `$` continuation join
  SysVar sysvar = SysVar::AaIw;
  uint32_t line = 0, col = 0; ///< physical position of the first character
  uint32_t len = 1;           ///< bytes on the first physical line
  double value = 0;
  std::string_view text; ///< Ident/String/Other text; Word/Number: the digits as written
};

struct LogicalLine {
  uint32_t firstLine = 0;
  uint32_t lastLine = 0;
  bool hadError = false;     ///< a lexical error was reported on this line
  bool truncated = false;    ///< not lexed to its end: E102, or a lone CR of a CR-only file
  uint32_t length = 0;       ///< characters after joining (SPEC §2), `;` comment excluded
  std::vector<Token> tokens; ///< ends with Tok::End
};

struct LexOptions {
  machine::Dialect dialect = machine::Dialect::Sidac;
  std::string axisLetters{lang::kDefaultAxisLetters}; ///< letters read as axis addresses (upper-case)
  /// Words on lines without `$` are read by a shorter path (the same tokens and diagnostics;
  /// tests and the fuzz targets compare the two).
  bool fastPaths = true;
  /// z32: the machine's user parameter names (upper-case, one or two letters): addresses like
  /// an axis (HA12.5) and names in expressions.
  std::vector<std::string> userParams;
  /// Asked every few thousand lines by LineParser (from any thread that parses): true throws
  /// Cancelled. The language server abandons a check when the editor sends more.
  const std::function<bool()>* cancel = nullptr;
};

/// A parse given up because LexOptions::cancel said so.
struct Cancelled : std::exception {
  const char* what() const noexcept override { return "the check was cancelled"; }
};

class Lexer {
public:
  /// `owned` receives text that had to be copied (identifiers split by a continuation).
  Lexer(std::string_view text, uint32_t fileId, const LexOptions& opts, diag::DiagnosticList& diags,
        std::vector<Suppression>& suppressions, std::deque<std::string>& owned);

  /// Reads the next logical line; false at the end of the file (or of the range).
  bool next(LogicalLine& out);

  /// Lexes only the physical lines from offset `begin` (a line start, numbered `firstLine`) up
  /// to offset `end` (a line start, or the text's size): one part of a file split where no
  /// logical line crosses (isSplitPoint). Called before the first next().
  void setRange(uint32_t begin, uint32_t firstLine, uint32_t end);
  /// The offset of the next physical line to read.
  uint32_t nextOffset() const { return cur_.next; }
  /// Offset `at` starts a physical line, and the line before it ends its logical line whatever
  /// it holds (no `$` that could continue it), so lexing from `at` gives the lines a whole-file
  /// lex gives from there. `at` must be past a BOM and in a file that has more than one LF (a
  /// file of lone CRs is lexed whole).
  static bool isSplitPoint(std::string_view text, uint32_t at);

  static constexpr uint32_t kMaxLineLength = lang::kMaxLineLength;

private:
  struct Cursor {
    uint32_t p = 0;         ///< byte offset
    uint32_t line = 1;      ///< physical line
    uint32_t lineStart = 0; ///< offset of the physical line start
    uint32_t lineEnd = 0;   ///< offset of the content end (before CR LF / LF)
    uint32_t next = 0;      ///< offset of the next physical line
    bool dangling = false;  ///< a `$` on the last line of the file
    bool plain = false;     ///< the physical line holds no continuation `$`: nothing joins it to the next
  };

  /// The character at `c`, 0 at the logical end (or a NUL byte). A `$` that continues the line
  /// moves `c` to the next physical line (peekDollar): the one slow case, kept out of line.
  char peek(Cursor& c) {
    if (c.p >= c.lineEnd) return 0;
    const char ch = src_[c.p];
    return ch == '$' ? peekDollar(c) : ch;
  }
  char peekDollar(Cursor& c);                                         ///< peek at a `$`
  static bool atLineEnd(const Cursor& c) { return c.p >= c.lineEnd; } ///< after peek: the end, not a NUL
  void advance(Cursor& c) { ++c.p; }
  bool startPhysicalLine(Cursor& c, uint32_t at, uint32_t lineNo);
  void continueLine(Cursor& c); ///< at a continuation `$`: go to the next line
  uint32_t col(const Cursor& c) const { return c.p - c.lineStart + 1; }
  /// A fresh token, emplaced where it stays, becomes one of `kind` starting at `c` (its text and
  /// length are set when it ends).
  void setPosition(Token& t, Tok kind, const Cursor& c) const {
    t.kind = kind;
    t.line = c.line;
    t.col = col(c);
  }
  Loc loc(const Cursor& c) const { return Loc{fileId_, c.line, col(c)}; }

  void lexToken(LogicalLine& out); ///< at a character that is no blank (next() skips those)
  void lexComment(bool wholeLine);
  void lexSemicolonComment();
  bool tryWords(LogicalLine& out);
  bool tryWordsPlain(LogicalLine& out); ///< tryWords on a plain line (Cursor::plain), by offsets
  void lexIdent(LogicalLine& out);
  struct NumberScan;
  bool lexNumber(Cursor& c, Token& t); ///< at a digit or separator; false if not a number
  /// lexNumber on a plain line (Cursor::plain) at offset `p`, which moves past the number.
  bool lexNumberPlain(uint32_t& p, uint32_t end, uint32_t line, uint32_t lineStart, Token& t);
  /// The value and the E101 check of a scanned number whose text is t.text, at line:col.
  void finishNumber(const NumberScan& n, uint32_t line, uint32_t col, bool oneLine, Token& t);
  void lexSysVar(LogicalLine& out);
  void lexString(LogicalLine& out);
  bool isAddressAt(Cursor c, char* addr, Cursor& after);
  /// `a b` (upper-case) starts a two-letter address: the dialect's, or a user parameter's.
  bool twoLetter(char a, char b) const;
  /// The length of the user parameter name at offset `p` (not followed by a name character), 0 if none.
  uint32_t userParamAt(uint32_t p, uint32_t end) const;
  /// z32: a GO target at the cursor (`GO%N1`, or the end of a range after `-`); false if none.
  bool tryGoTarget(LogicalLine& out);
  /// z32: the axis letters written right after G28/G29 (G29AB), taken into the word's text.
  void takeAxisTail(Token& t, uint32_t& q, uint32_t end) const;
  bool parenIsGroup(const LogicalLine& out) const;
  bool identAdjacent(const LogicalLine& out) const;
  std::string_view spanText(const Cursor& from, const Cursor& to);
  uint32_t joinedOffset(const Cursor& c) const; ///< offset of `c` in the joined logical line
  bool reportTooLong(uint32_t length);          ///< E102 if `length` joined characters exceed the limit
  void skipRestOfLine();                        ///< after E102: to the end of the logical line
  void reportControlByte(uint32_t line, uint32_t col, unsigned char byte);

  std::string_view src_;
  uint32_t fileId_;
  LexOptions opts_;
  bool isAddress_[26] = {}; ///< the dialect's fixed addresses and the machine's axis letters
  diag::DiagnosticList& diags_;
  std::vector<Suppression>& suppressions_;
  std::deque<std::string>& owned_;
  Cursor cur_;
  bool lineEnded_ = false; ///< `;` or end of the logical line reached
  bool crOnly_ = false;    ///< the file uses lone CRs as line ends (reported once)
  // logical-line length bookkeeping (E102): joined characters before each physical line
  uint32_t firstLine_ = 0;
  uint32_t end_ = 0;       ///< lines start before this offset (setRange)
  bool crScanned_ = false; ///< scanLoneCrs ran (or is not needed: setRange)
  /// Before the first line: is this a file of lone CRs (crOnly_, reported once)?
  void scanLoneCrs();
  std::vector<uint32_t> joinedBefore_;
  bool errorOnLine_ = false;
  bool truncated_ = false;
  uint32_t semicolonAt_ = UINT32_MAX; ///< offset of the ';' that ended the line, if any
};

/// `text` for a message: bytes >= 0x80 and control bytes become `\xNN`, so that a message
/// quoting source bytes is always valid UTF-8 and printable.
std::string printableBytes(std::string_view text);

/// A number as written (digits with at most one separator `.`/`,`, no sign) rounded half up to
/// 9 significant digits (SPEC §2), keeping its separator and its leading zeros; trailing zeros
/// of the fraction are dropped. nullopt when it has at most 9 already, or has no 9-digit
/// spelling (1000000000 and above).
std::optional<std::string> roundToNineDigits(std::string_view number);

/// True when `s` is a reserved keyword of the language (case-insensitive).
bool isKeyword(std::string_view s);

} // namespace iso::frontend
