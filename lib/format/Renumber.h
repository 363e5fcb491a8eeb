//! @file Renumber.h
//! @brief isofmt --renumber: the N numbers of a file rewritten in order (START, START+STEP, ...)
//!        and, in dialect z32, every GO target and GO range that names them, so that each GO
//!        still finds the line it found. A file where that cannot be promised is refused.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "frontend/Lexer.h"
#include "support/Expected.h"

namespace iso::format {

struct RenumberOptions {
  uint64_t start = 10;
  uint64_t step = 10;
  bool allLines = false; ///< also give an N number to every statement line without one
  frontend::LexOptions lex;
};

/// The largest N number written (9 digits).
inline constexpr uint64_t kMaxLineNumber = 999999999;

/// The renumbered text: the same physical lines and line ends, only N numbers (and GO targets)
/// changed or, with allLines, `N<number> ` put before a line's statement (after `%` and `/`).
/// An Error when the file has syntax errors, a number would pass 9 digits, a line would pass
/// 240 characters, or a GO target could change meaning: it names no line, an N number written
/// on more than one line, a line whose N number has blanks before it, or a line that does not
/// start with that N number; `where` is the line ("" for the file), `message` the reason.
support::Expected<std::string> renumber(std::string_view text, const RenumberOptions& opts);

} // namespace iso::format
