//! @file Incremental.h
//! @brief A file checked again after an edit from what the edit can reach, not whole: the
//!        language server's check of an open document as it is typed.
//!
//! IncrementalFile::check is parseAndCheckFile on one thread that also keeps, for each
//! statement, a fingerprint of everything the whole-file passes and the set-level checks read
//! of it (its kind, lines and columns, M items, moved axes, N number, label, jump, name, CASE
//! arms, WHEN axes, suppressions), and every `markEvery` statements a mark: the offset, line
//! and modal state the next statement starts from, and how many of the file's per-line
//! diagnostics came before.
//!
//! IncrementalFile::update, after an edit, parses and checks the lines again from the last
//! mark before the edit, in the modal state recorded there, until, past the edit, a mark is
//! reached (at its offset moved by the edit) in the state it recorded. If the same statements
//! on the same lines have their old fingerprints, the whole-file and set-level results cannot
//! have changed: only the per-line diagnostics of those statements are replaced. Otherwise (a
//! label, a jump or an M30 changed; lines were added or taken away) the statements checked
//! again replace the old ones in the file kept in its compact form (adopt), the lines after
//! move, and the whole-file passes run again over the file's records: no line outside the
//! edit's reach is lexed or parsed again. The set-level results stand when what the set-level
//! checks read of the file (its kind, name and calls, in order) is unchanged; their places are
//! moved with remap. The file's diagnostics are then exactly those of a full check of the new
//! text. It answers false, and the caller checks the file in full, when the calls changed, for
//! a z32 GO (its rule reads the raw text), or for an edit before the first mark.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string_view>
#include <vector>

#include "diag/Diagnostic.h"
#include "frontend/Ast.h"
#include "frontend/Lexer.h"
#include "frontend/Sema.h"

namespace iso::frontend {

class IncrementalFile {
public:
  explicit IncrementalFile(size_t markEvery = 128);
  ~IncrementalFile();
  IncrementalFile(IncrementalFile&&) noexcept;
  IncrementalFile& operator=(IncrementalFile&&) noexcept;

  /// parseAndCheckFile(f, text, lex, opts, diags) with one thread, recording what update
  /// needs. `opts.machine` must outlive this object (update checks lines with it).
  FileFlow check(File& f, std::string_view text, const LexOptions& lex, const SemaOptions& opts,
                 diag::DiagnosticList& diags);
  /// Keeps `f`, the file check was given, once the set-level checks have read it: updates
  /// change it as they change the text. Its texts are copied (ownTexts): the text it was
  /// parsed from may go. Until then, update answers false.
  void adopt(File&& f);
  /// The file as the last check or update left it (its suppressions, for the filter).
  const File& file() const;

  /// The text last checked had the bytes [at, at + removed) replaced by `inserted` bytes,
  /// which gave `text` (the caller keeps it alive only during the call). True: diagnostics()
  /// are now those of a full check of `text`. False: a full check (check) is needed; until
  /// then this record is invalid and every later update answers false.
  bool update(std::string_view text, size_t at, size_t removed, size_t inserted);
  /// The same with only the first bytes of the new text, `text` (they end at a line start),
  /// out of `size`: update gives up rather than read past them. reach() says how many it may
  /// read at most.
  bool update(std::string_view text, size_t size, size_t at, size_t removed, size_t inserted);
  /// The bytes of the new text an update of this edit may read (at most the new text's size).
  size_t reach(size_t size, size_t at, size_t removed, size_t inserted) const;

  bool valid() const;
  /// The file's diagnostics as a full check reports them: those of its lines, in order, then
  /// those of the whole-file passes (not the set-level ones; not sorted).
  std::vector<diag::Diagnostic> diagnostics() const;
  /// Statements checked again by the last update that answered true (for tests and benches).
  size_t lastRechecked() const;
  /// The last update that answered true ran the whole-file passes again.
  bool lastRanWholeFile() const;
  /// Moves a diagnostic of the set-level checks (or one whose notes point into this file) from
  /// the text before the last update that answered true to the text after it: its place, end,
  /// notes and fix edits in this file. False when a place lies in the lines checked again and
  /// is not a call that is still there (the caller then checks the file in full).
  bool remap(diag::Diagnostic& d) const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

} // namespace iso::frontend
