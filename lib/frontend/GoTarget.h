//! @file GoTarget.h
//! @brief The z32 GO rule: how a GO target, a GO range end or a block search text finds its line
//!        (SPEC §4.7, §4.8). One function for isolint, isocc and isosim --search.
#pragma once

#include <cstdint>
#include <string_view>

namespace iso::frontend {

/// True when `text` has the shape of a GO target: [%][/]N<number as written> (N12, %N1, /N12,
/// N132,5). The number has digits and at most one '.' or ',' (at least one digit).
bool isGoTargetText(std::string_view text);

struct GoLineMatch {
  uint32_t line = 0;           ///< 1-based physical line found, 0 when none
  uint32_t blankCandidate = 0; ///< a line that would match but for blanks before it (E215's note), 0 if none
};

/// The first line of `source` (from the top) whose text begins with exactly `target`, the next
/// character not being a digit, '.' or ','. Characters compare exactly (case included); lines
/// end at "\n", "\r\n" or a lone "\r". A line with blanks (spaces, tabs) before the target is
/// never found: the first such line is `blankCandidate`.
GoLineMatch findGoLine(std::string_view source, std::string_view target);

/// The first line at or after `fromLine` (1-based) that findGoLine's rule accepts, 0 when none.
/// A repeated line number is never a GO target; this finds one to explain the error.
uint32_t findGoLineFrom(std::string_view source, std::string_view target, uint32_t fromLine);

} // namespace iso::frontend
