//! @file Text.h
//! @brief Text helpers for what reaches a user: bytes of untrusted origin (sources, file
//!        names, image names) made safe for a terminal and valid for JSON; counting bytes.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace iso::support {

/// Length of the valid UTF-8 sequence at s[i] (1-4), or 0 when the byte there starts none
/// (a stray continuation byte, an overlong form, a surrogate, a truncated sequence).
size_t utf8SequenceLength(std::string_view s, size_t i);

/// True when `s` is well-formed UTF-8.
bool isValidUtf8(std::string_view s);

/// For a terminal: control bytes (C0 but TAB, DEL), bytes that are not valid UTF-8, C1
/// controls and the bidirectional formatting characters (U+200E/F, U+202A-E, U+2066-9) are
/// written as `\xNN` (one escape per byte); printable UTF-8 and TAB are kept.
std::string escapeForTerminal(std::string_view s);
/// Appends escapeForTerminal(s) to out.
void appendEscaped(std::string& out, std::string_view s);

/// For JSON and SARIF: valid UTF-8 is kept; every byte that is not part of valid UTF-8 becomes
/// the four characters `\xNN`, so that the result is always valid UTF-8.
std::string toValidUtf8(std::string_view s);

/// For HTML and XML (SVG) text and attribute values: `& < > " '` become entities; a control
/// byte other than TAB and LF, and each byte that is not part of valid UTF-8, becomes `?` (a
/// file name can hold anything), so that the document stays well-formed.
std::string escapeMarkup(std::string_view s);

/// The edit distance of two words: the fewest insertions, deletions, substitutions and swaps
/// of two neighbouring characters that turn one into the other (optimal string alignment),
/// ASCII letters compared without case. Stops counting past `limit`: any distance above it
/// is returned as `limit + 1`.
size_t editDistance(std::string_view a, std::string_view b, size_t limit = SIZE_MAX);

/// For "did you mean ...?": the candidate nearest to `word` when it is near enough to be a typo
/// of it (a distance of at most 2, and at most a third of the length of `word`, but 1 is
/// always allowed), and no other candidate is as near; "" otherwise.
std::string_view closestMatch(std::string_view word, const std::vector<std::string_view>& candidates);

/// How many bytes of `s` are `c` (sixteen at a time: counting the lines of a large file).
size_t countByte(std::string_view s, char c);

} // namespace iso::support
