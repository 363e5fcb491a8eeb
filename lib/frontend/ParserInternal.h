//! @file ParserInternal.h
//! @brief What the parser's source files share (not part of the library's interface).
//!
//! The members of Parser are defined in three files, cut along the grammar: Parser.cpp owns
//! the logical line and its statements (labels and line numbers, IF/WHEN/CASE, jumps, PROC,
//! SEMI, a block's loop over its items, the condition of IF/WHEN, the error reporting and
//! LineParser); ParseItems.cpp owns the items of a block (address words, assignments, Pos[]=,
//! M=NB(), system variables written, recovery after a bad item); ParseExpressions.cpp owns
//! expressions (operators, operands, the E108 fix that parenthesises comparisons). The split
//! keeps each file readable; the small helpers every part calls on its hot paths (tok,
//! checkErrorToken, spanLen, addExpr, newExpr) are inline in Parser.h, so no call that was
//! inlined before the split became an out-of-line one.
#pragma once

#include <string>

#include "diag/Diagnostic.h"
#include "frontend/Lexer.h"

namespace iso::frontend::parser_detail {

/// The current token as a message quotes it ("'X10'", "number '5'", "end of line").
std::string describe(const Token& t);

/// E301 for an R parameter whose index is not in 1..<max> (R0 has its own message).
void reportRIndex(diag::DiagnosticList& diags, const Loc& loc, const Token& t);

} // namespace iso::frontend::parser_detail
