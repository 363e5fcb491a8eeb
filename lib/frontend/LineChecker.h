//! @file LineChecker.h
//! @brief Private to the frontend: the per-line pass that parseAndCheckFile (FilePipeline.cpp)
//!        and the incremental checker (Incremental.cpp) share.
#pragma once

#include <cstddef>

#include "diag/Diagnostic.h"
#include "frontend/Ast.h"
#include "frontend/Lexer.h"
#include "frontend/Sema.h"
#include "frontend/checks/FileChecker.h"
#include "lang/Z32GCodes.h"

namespace iso::frontend::detail {

using checks::FileChecker;

/// `at` can split `text` (Lexer::isSplitPoint): not in a file of lone CRs (lexed whole), so
/// there is another LF before, and the BOM lies behind.
inline bool canSplitAt(std::string_view text, uint32_t at) {
  return at >= 2 && text.find('\n') < at - 1 && Lexer::isSplitPoint(text, at);
}

/// parseAndCheckFile's pass: each statement's values are checked once its line is parsed (in
/// order, as checkFile would: the unit kind is known at the first statement that is not
/// empty), then a top-level block keeps only its M items and gives back its expressions.
class LineChecker {
public:
  LineChecker(File& f, const SemaOptions& o, diag::DiagnosticList& d)
      : f_(f), blocks_(f, o, d), z32_(o.dialect == machine::Dialect::Z32) {}

  void finish() {
    if (!started_) start();
  }

  /// Checks the line just parsed (the file's last statement).
  void line() {
    Stmt& s = f_.stmts.back();
    if (started_) {
      blocks_.blockStmt(s);
      ++checked_;
    } else if (s.kind != StmtKind::Empty) {
      start();
    }
    if (started_) forget(s);
    itemMark_ = f_.items.size();
    exprMark_ = f_.exprs.size();
  }

  /// The unit kind is known (f_.kind), and the next statement starts from `state`: a later part
  /// of a file (parseAndCheckFile's second thread).
  void startWith(const FileChecker::BlockState& state) {
    started_ = true;
    blocks_.setBlockState(state);
  }
  bool started() const { return started_; }
  FileChecker::BlockState state() const { return blocks_.blockState(); }

private:
  void start() {
    f_.kind = classifyUnit(f_);
    blocks_.startBlocks();
    started_ = true;
    for (; checked_ < f_.stmts.size(); ++checked_)
      blocks_.blockStmt(f_.stmts[checked_]);
  }

  /// What later checks read of a checked line: the M items of its blocks (M30/M17 end the
  /// unit, special M call subprograms) and the axes they move (Stmt::movedAxes); a WHEN's
  /// axes are in File::whenAxes. The rest of its items and its expressions are given back.
  void forget(Stmt& s) {
    noteAxes();
    if (s.kind == StmtKind::Block) keepMItems(s);
    if (s.inner >= 0 && f_.inner[static_cast<size_t>(s.inner)].kind == StmtKind::Block)
      keepMItems(f_.inner[static_cast<size_t>(s.inner)]);
    if (s.kind == StmtKind::Invalid && s.inner < 0) f_.items.resize(itemMark_);
    f_.exprs.resize(exprMark_);
    s.cond = kNoExpr;
  }

  /// File::usedAxes: the letters the line's items and expressions name, before they go.
  void noteAxes() {
    uint32_t mask = 0;
    auto letter = [&](char c) {
      if (c >= 'A' && c <= 'Z') mask |= 1u << (c - 'A');
    };
    for (size_t k = itemMark_; k < f_.items.size(); ++k) {
      const Item& x = f_.items[k];
      if (x.kind == ItemKind::Move || x.kind == ItemKind::AxisFeed) letter(x.axis);
      if (x.kind == ItemKind::AxisControl) forEachControlledAxis(x, letter);
    }
    for (size_t k = exprMark_; k < f_.exprs.size(); ++k)
      if (f_.exprs[k].kind == ExprKind::SysAxis) letter(f_.exprs[k].axis);
    f_.usedAxes |= mask;
  }

  /// What later checks read of a block's items: its M items and, in z32, KG and G26 (they end
  /// the line's flow).
  bool keeps(const Item& x) const {
    if (x.kind == ItemKind::M) return true;
    return z32_ && (x.kind == ItemKind::Kg || (x.kind == ItemKind::G && x.code == lang::kG26Return));
  }

  /// Moves the kept items of block `b`, the last items of the file, to its front.
  void keepMItems(Stmt& b) {
    Item* first = f_.items.data() + b.firstItem;
    uint32_t kept = 0;
    for (uint32_t k = 0; k < b.itemCount; ++k)
      if (keeps(first[k])) {
        first[kept] = first[k];
        first[kept++].value = kNoExpr;
      }
    b.itemCount = kept;
    f_.items.resize(b.firstItem + kept);
  }

  File& f_;
  FileChecker blocks_;
  bool z32_;
  bool started_ = false;
  size_t checked_ = 0;  ///< statements whose values are checked
  size_t itemMark_ = 0; ///< items before the current line
  size_t exprMark_ = 0; ///< expressions before the current line
};

} // namespace iso::frontend::detail
