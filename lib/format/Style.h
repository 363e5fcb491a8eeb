//! @file Style.h
//! @brief The layout isofmt writes: the case of the language's words, the blanks between items
//!        and around operators, the indentation of IF and WHEN bodies, the spelling of numbers
//!        and blank lines. The defaults are the style of isofmt(1).
#pragma once

#include <cstdint>

namespace iso::format {

/// The case of keywords, addresses, G and M words and system variables (names, labels,
/// comments and strings keep theirs).
enum class WordCase : uint8_t { Upper, Lower, Keep };

/// How constants are spelled: as written, or with a leading 0 before a leading separator and
/// `.` as the separator (`X.5` -> `X0.5`, `X1,5` -> `X1.5`); the value never changes.
enum class NumberStyle : uint8_t { AsWritten, Normalised };

struct Style {
  WordCase wordCase = WordCase::Upper;
  bool spaceBetweenWords = true;    ///< `N10 G01 X10` (false: `N10G01X10`)
  bool spaceAroundOperators = true; ///< `R1 = R2 + 5`, `IF R1 > 5` (false: `R1=R2+5`)
  uint32_t indent = 2;              ///< blanks per IF/ELSE/ENDIF and WHEN/CANCEL level (0: none)
  NumberStyle numbers = NumberStyle::AsWritten;
  uint32_t maxBlankLines = 1; ///< a run of blank lines keeps at most this many
};

} // namespace iso::format
