//! @file FilePipeline.h
//! @brief isolint's one pass over a file: parsing and checking together, in parts for two threads.
//!
//! parseAndCheckFile runs this sequence on one file:
//!   1. read: the caller has the whole text (`text`, in memory or mapped) and keeps it alive.
//!   2. split: a file of SplitOptions::minBytes or more, when two threads are allowed, is cut at
//!      split points (line starts that no logical line crosses) into parts; otherwise it is one.
//!   3. lex, parse and check per part: each line is parsed and its values are checked at once in
//!      the modal state that runs through the lines (checks::FileChecker::blockStmt); the line
//!      then keeps only what the whole-file passes read (its M items, the axes it moves, a
//!      WHEN's $AA_IW axes). The first part starts from the true initial state; the others,
//!      each taken by the thread that comes to it first (a second thread, then the first once
//!      it reaches its part's end), from a guess (the state the first had after
//!      SplitOptions::guessAfter statements), and record checkpoints of their state as they go.
//!   4. join: part after part, each is checked again from the true state at its start until
//!      its state agrees with one of its checkpoints; from there on its own statements and
//!      diagnostics are kept (its statements were written in place into the file's arrays).
//!      No checkpoint agreeing, it is checked again whole. The result is that of one pass.
//!   5. whole-file passes: headers, labels, IF blocks, jumps, WHEN, control flow, N numbers
//!      (checks::FileChecker::run), two at a time when the file was split.
//!
//! Thread contract: parseAndCheckFile may be called at once on different files, each with its
//! own File and DiagnosticList; `text`, `lex` and `opts` (and the machine it points to) are
//! only read, and may be shared. With `threads` >= 2 it starts at most one thread for the parts
//! and, for the whole-file passes, one more at a time; every thread it starts has ended when it
//! returns, and an exception thrown on one comes out of parseAndCheckFile on the caller's thread.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>

#include "diag/Diagnostic.h"
#include "frontend/Ast.h"
#include "frontend/Sema.h"

namespace iso::frontend {

struct LexOptions;

/// How parseAndCheckFile splits a file into parts for two threads. isolint uses the defaults;
/// tests and the fuzz targets split small sources anywhere, to compare the result with one pass.
struct SplitOptions {
  size_t minBytes = size_t{1} << 20; ///< a smaller file is checked by one thread
  /// Two parts that meet at this offset, which must be a split point (Lexer::isSplitPoint, in
  /// a file with another LF before), or the file is checked by one thread. 0: `parts` parts.
  uint32_t at = 0;
  /// The parts start near equal fractions of the file, at the first split point from there.
  /// 0: two (more parts keep a slow core from holding up the join, but each part's tables stay
  /// until the join: 14 parts of the 30 MB CAM program took 142 MiB instead of 134).
  size_t parts = 0;
  /// The parts after the first start from the modal state the first had after this many
  /// statements (or at its end, if that comes first): a guess, checked when they are joined.
  size_t guessAfter = 1000;
  /// A mapped text's pages behind the reader leave memory every this many bytes (they are read
  /// again from the file when something needs them).
  size_t dropEvery = size_t{4} << 20;
};

/// isolint's one pass: parseFile, classifyUnit and checkFile with the same diagnostics, but
/// each line's values are checked as soon as it is parsed, and a block line then keeps only
/// its M items (no expressions): a program of millions of lines never holds its whole tree.
/// The File is then for the set-level checks only, not for the compiler. With `threads` >= 2, a
/// large file is checked in parts at once, with the same result (SplitOptions, above).
FileFlow parseAndCheckFile(File& f, std::string_view text, const LexOptions& lex, const SemaOptions& opts,
                           diag::DiagnosticList& diags, unsigned threads = 1, const SplitOptions& splitting = {});

} // namespace iso::frontend
