//! @file Fix.h
//! @brief Applying fix-its (Diagnostic::fixes) to the bytes of a file, and the unified diff of
//!        what they change (isolint --fix, --diff). Bytes outside the edits are kept as they
//!        are: line ends (LF, CR LF), encodings, a missing last line end.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "diag/Diagnostic.h"

namespace iso::diag {

/// An edit resolved to byte offsets of the original text: [begin, end) becomes `replacement`.
struct ByteEdit {
  size_t begin = 0;
  size_t end = 0;
  std::string replacement;
};

struct FixResult {
  std::string text;            ///< the text with the applied fixes
  size_t applied = 0;          ///< fixes applied
  size_t skipped = 0;          ///< fixes skipped: overlapping an earlier one, or out of range
  std::vector<ByteEdit> edits; ///< the applied edits, sorted, non-overlapping
};

/// The byte offset of a 1-based line and byte column in `text` (the column may be one past the
/// line's content, before its line end); false when there is no such place. Columns of line 1
/// count after a UTF-8 BOM, as the lexer's do.
bool offsetOf(std::string_view text, uint32_t line, uint32_t col, size_t& offset);

/// Applies `fixes` to `text` in the given order. A fix whose edits overlap an edit applied
/// before (or each other), or that point outside the text, is skipped whole: a second run
/// applies what it still finds.
FixResult applyFixes(std::string_view text, const std::vector<const Fix*>& fixes);

/// A unified diff (`--- a/PATH`, `+++ b/PATH`, hunks with `context` lines around each change)
/// of what `edits` (from applyFixes on `text`) change; empty when they change nothing.
std::string unifiedDiff(std::string_view text, const std::vector<ByteEdit>& edits, const std::string& path,
                        size_t context = 3);

/// `diff` (unifiedDiff's) with ANSI colours as git shows them: the file lines bold, hunk heads
/// cyan, removed lines red, added lines green. The lines themselves are unchanged.
std::string colorDiff(std::string_view diff);

} // namespace iso::diag
