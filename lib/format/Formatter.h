//! @file Formatter.h
//! @brief isofmt's layout of a source file: each logical line re-written from its tokens with
//!        the Style's case and blanks, comments and strings copied byte for byte. A line is
//!        kept as written when its new text would lex to other tokens, would pass 240
//!        characters, or is continued with `$`; a file with syntax errors is kept whole.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "diag/Fix.h"
#include "format/Style.h"
#include "frontend/Lexer.h"

namespace iso::format {

struct FormatOptions {
  Style style;
  frontend::LexOptions lex; ///< the dialect, the machine's axis letters and user parameters
};

/// One physical line of a text: [begin, end) is its content, `next` the start of the next line
/// (after "\n" or "\r\n"). Line 1 begins after a UTF-8 byte order mark.
struct PhysicalLine {
  size_t begin = 0;
  size_t end = 0;
  size_t next = 0;
};
std::vector<PhysicalLine> splitLines(std::string_view text);

/// What the formatter makes of one physical line.
struct LineOutput {
  bool removed = false; ///< a blank line dropped (a run of blank lines, or at the end of the file)
  std::string content;  ///< the new content (without the line end) when not removed
};

/// Why a line (or the file: line 0) was left as written.
struct FormatNote {
  uint32_t line = 0;
  std::string message;
};

struct FormatResult {
  std::vector<LineOutput> lines; ///< one per physical line of the input
  std::vector<FormatNote> notes;
  bool keptAsWritten = false; ///< the file has syntax errors: nothing was changed
};

/// Formats `text`. Never throws for any input (a file it cannot read as the language is kept).
FormatResult formatLines(std::string_view text, const FormatOptions& opts);

/// The text of `base` with its physical lines replaced by `lines` (one per line of `base`,
/// each keeping its line end), and the edits that make it (for diag::unifiedDiff).
struct Assembled {
  std::string text;
  std::vector<diag::ByteEdit> edits;
};
Assembled assemble(std::string_view base, const std::vector<LineOutput>& lines);

} // namespace iso::format
