//! @file Parser.h
//! @brief Parses logical lines into statements (SPEC §3–§4, §10). One statement per line; on a
//!        syntax error the line becomes an Invalid statement and parsing resumes at the next.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>

#include "diag/Diagnostic.h"
#include "frontend/Ast.h"
#include "frontend/Lexer.h"

namespace iso::frontend {

class Parser {
public:
  Parser(File& file, const LexOptions& opts, diag::DiagnosticList& diags);
  /// Parses one logical line and appends its statement to the file.
  void parseLine(const LogicalLine& line);
  /// Labels and GOTO targets keep copies of their names (in File::ownedText) instead of views
  /// into the text: for a mapped text whose pages leave memory behind the reader, so that the
  /// label checks do not read every page of it again.
  void ownNames() { ownNames_ = true; }

  // Expression entry points (also used by tests).
  ExprId parseConditionAt(const LogicalLine& line, size_t start);
  /// A value or a condition from token `start` to the end of the line (the debugger's
  /// expressions); kNoExpr after a syntax error (reported).
  ExprId parseExpressionAt(const LogicalLine& line, size_t start);

private:
  struct Abort {};
  /// Parses from token `start` of `line` with `parse`; kNoExpr when it aborts.
  template <class F> ExprId parseAt(const LogicalLine& line, size_t start, F&& parse);

  const Token& tok() const { return (*toks_)[i_]; }
  const Token& peekTok(size_t k = 1) const {
    size_t j = i_ + k;
    return j < toks_->size() ? (*toks_)[j] : toks_->back();
  }
  bool atEnd() const { return tok().kind == Tok::End; }
  bool is(Tok k) const { return tok().kind == k; }
  Loc locOf(const Token& t) const { return Loc{file_.id, t.line, t.col}; }
  /// Reports `m` at the token (unless muted) and aborts the line.
  template <class... A>
  [[noreturn]] void fail(const Token& t, diag::MsgRef<std::type_identity_t<A>...> m, A&&... args) {
    failText(locOf(t), t.len, m.code(), diag::message<A...>(m, std::forward<A>(args)...));
  }
  template <class... A>
  [[noreturn]] void failAt(const Loc& loc, uint32_t len, diag::MsgRef<std::type_identity_t<A>...> m, A&&... args) {
    failText(loc, len, m.code(), diag::message<A...>(m, std::forward<A>(args)...));
  }
  [[noreturn]] void failText(const Loc& loc, uint32_t len, diag::Code code, std::string text);
  /// "expected ..., found <the current token>": `m` takes the token's description.
  [[noreturn]] void failExpected(diag::MsgRef<std::string> m);
  /// Reports `m` (unless muted) with a fix-it when `fix` has edits, then aborts the line.
  template <class... A>
  [[noreturn]] void failWithFix(const Loc& loc, uint32_t len, diag::Fix fix, diag::MsgRef<std::type_identity_t<A>...> m,
                                A&&... args) {
    failTextWithFix(loc, len, m.code(), diag::message<A...>(m, std::forward<A>(args)...), std::move(fix));
  }
  [[noreturn]] void failTextWithFix(const Loc& loc, uint32_t len, diag::Code code, std::string text, diag::Fix fix);
  /// E108's fix for the condition being parsed: each comparison operand of AND/OR put in
  /// parentheses; no edits where that is not enough (a bare value, NOT of a comparison, a
  /// token split by a `$` join, a line that would grow past 240 characters).
  diag::Fix parenthesiseComparisons() const;
  bool wrapOperands(size_t from, size_t to, std::vector<diag::Edit>& edits) const;
  size_t matchingParen(size_t open, size_t to) const;
  void expect(Tok k, diag::MsgRef<std::string> expected) { ///< `expected` takes the token found
    if (tok().kind != k) failExpected(expected);
    ++i_;
  }
  void expectEnd(diag::MsgRef<std::string> after); ///< "unexpected {} after ...": the token found
  void checkErrorToken() {
    if (tok().kind == Tok::Error) throw Abort{}; // the lexer has reported it
  }

  void parseStatement(Stmt& s, bool inner);
  /// After THEN / DO: the statement (a block, a jump or a call) that ends `s`'s line, as
  /// s.inner in File::inner. It takes the line's `/` as told: the inner statement of an IF does,
  /// that of a WHEN does not (nothing reads it there: the WHEN line's own skip covers its body).
  void parseInner(Stmt& s, bool skippable);
  void parseIf(Stmt& s);
  void parseWhen(Stmt& s);
  void collectIwAxes(ExprId e, std::string& axes) const; ///< File::whenAxes
  void parseCase(Stmt& s);
  void parseJump(Jump& j);
  void startJump(Stmt& s); ///< s's jump, in the file's side table
  void setName(Stmt& s, const StmtName& name);
  void parseProc(Stmt& s);
  void parseSemi(Stmt& s);
  void parseBlock(Stmt& s);
  /// z32: a GO jump or range at the current GoTarget token (after an optional `!`).
  void parseGo(Stmt& s, bool bang);
  /// z32: GOP<name> alone on its line (a call); `bang`: written between `!`.
  void parseGop(Stmt& s, bool bang);
  void closeBang(bool bang, const Token& what); ///< the closing `!` of `!GON12!`
  bool z32() const { return opts_.dialect == machine::Dialect::Z32; }
  /// The index of user parameter `name` (any case) in LexOptions::userParams, or -1.
  int userParamIndex(std::string_view name) const;
  /// z32: PAR[i] / PAL[i] at the current name token: the expression (index checked when constant).
  ExprId parseParAccess(const Token& t);
  /// z32: G25..G110 of dialect z32 at word `t` into `it` (G26, G28/G29 with their axis letters).
  void parseZ32G(const Token& t, Item& it);
  /// Token k starts an M item: an M word (M23) or `M =` (M=NB(23)).
  bool startsMItem(size_t k) const;
  bool parseItem();                               ///< false if the token does not start an item
  bool parseWordItem(const Token& t, Item& it);   ///< G, M, F, R1=, I J K, CR, S T MA.., axis words
  void parseSysVarItem(const Token& t, Item& it); ///< $aa_out[i]= / $aa_marker[i]= (others fail)
  bool parseNamedItem(const Token& t, Item& it);  ///< Pos[]= Posa[]= Fa[]= F= M=NB() R[]= X= ...
  ExprId constExpr(const Token& t);               ///< the token's number as a constant expression
  void failNonItem(const Stmt& s);                ///< the current token cannot be an item of the block
  size_t resumePoint(size_t itemStart) const;     ///< after a bad item: the next item start or End
  char parseAxisInBrackets();
  bool unsupportedIdent(const Token& t);
  void checkGCode(const Token& t, int code);

  ExprId parseCondition();
  ExprId parseLogicSeq();
  ExprId parseRelation();
  ExprId parseSum();
  ExprId parseUnary(); ///< counts the nesting depth (kMaxExprDepth)
  ExprId parseSignedOperand();
  ExprId parsePrimary();
  ExprId parseArith(); ///< an arithmetic expression (no comparison at its top level)
  ExprId addExpr(const Expr& e) {
    file_.exprs.push_back(e);
    return static_cast<ExprId>(file_.exprs.size() - 1);
  }
  /// A new record at the end of File::exprs, filled where it stays (lastExpr is its id): a
  /// record built aside and copied right after its fields were written stalls the copy (the
  /// wide loads cannot take their bytes from the narrow stores still in flight).
  Expr& newExpr() { return file_.exprs.emplace_back(); }
  ExprId lastExpr() const { return static_cast<ExprId>(file_.exprs.size() - 1); }
  Expr& ex(ExprId id) { return file_.exprs[static_cast<size_t>(id)]; }
  void requireLogicOperand(ExprId e, std::string_view op);
  void requireNumeric(ExprId e, diag::MsgRef<> where); ///< E109 `where` if `e` is a comparison
  /// After `a` and a binary operator: the right operand (by `operand`), both numeric.
  ExprId binaryTail(ExprId a, ExprKind kind, uint8_t op, ExprId (Parser::*operand)(), diag::MsgRef<> where);
  uint32_t spanLen(const Loc& start) const {
    // From `start` to the end of the last token consumed, when both are on one physical line.
    if (i_ == 0) return 1;
    const Token& last = (*toks_)[i_ - 1];
    if (last.line != start.line || last.col + last.len <= start.col) return 1;
    return last.col + last.len - start.col;
  }

  File& file_;
  LexOptions opts_;
  diag::DiagnosticList& diags_;
  const std::vector<Token>* toks_ = nullptr;
  size_t i_ = 0;
  bool notBlockIf_ = false;     ///< the line's IF had something after its condition
  bool muted_ = false;          ///< a block item failed: later errors of the line are follow-ups
  int depth_ = 0;               ///< nesting of unary operators and groups in the current expression
  size_t condStart_ = SIZE_MAX; ///< first token of the IF/WHEN condition being parsed
  uint32_t lineLength_ = 0;     ///< joined length of the current logical line
  bool ownNames_ = false;       ///< ownNames
  /// `name`, or with ownNames its copy in File::ownedText.
  std::string_view keep(std::string_view name);

public:
  /// Deepest nesting of groups and unary operators in one expression. A logical line of 240
  /// characters cannot reach it; it guards the recursion when tokens come from elsewhere.
  static constexpr int kMaxExprDepth = 256;
};

/// The E110 message for a name that spells a construct of another dialect (RET, STOPRE,
/// CYCLE81, T1, O100, ...), or nullopt.
std::optional<std::string> unsupportedNameMessage(std::string_view name, machine::Dialect dialect);

/// Lexes and parses a file, or a range of its lines, one logical line at a time (parseFile's
/// loop, for callers that check each line as it comes and may stop early).
class LineParser {
public:
  /// Reserves `file`'s arrays for `text` (a statement per ~20 bytes, an item and an
  /// expression per ~6) unless `reserve` is false.
  LineParser(File& file, std::string_view text, const LexOptions& opts, diag::DiagnosticList& diags,
             bool reserve = true);
  /// Lexer::setRange: only the lines from `begin` (numbered `firstLine`) to `end`.
  void setRange(uint32_t begin, uint32_t firstLine, uint32_t end) { lexer_.setRange(begin, firstLine, end); }
  /// Parses the next logical line into file.stmts.back(); false at the end.
  bool parseLine() {
    if (cancel_ && (++lines_ & 4095) == 0 && (*cancel_)()) throw Cancelled{};
    if (!lexer_.next(line_)) return false;
    parser_.parseLine(line_);
    return true;
  }
  /// The offset of the next physical line.
  uint32_t nextOffset() const { return lexer_.nextOffset(); }
  /// Parser::ownNames.
  void ownNames() { parser_.ownNames(); }

private:
  Lexer lexer_;
  Parser parser_;
  LogicalLine line_;
  const std::function<bool()>* cancel_;
  uint32_t lines_ = 0;
};

/// Lexes and parses a whole file into `file` (stmts, items, exprs). `file.id` and the text
/// must be set by the caller.
void parseFile(File& file, std::string_view text, const LexOptions& opts, diag::DiagnosticList& diags);

} // namespace iso::frontend
