//! @file JsonDepth.h
//! @brief How deep JSON text nests, found without parsing it: a guard to run before a
//!        recursive parser (nlohmann::json recurses once per `[` or `{`, so deep enough input
//!        overflows the stack).
#pragma once

#include <string_view>

namespace iso::support {

/// The nesting limit of structured input (JSON, TOML): deeper is refused.
inline constexpr unsigned kMaxNesting = 64;

/// True when no `[` or `{` of `text` is nested more than `maxDepth` deep (the outermost array
/// or object is depth 1; a scalar is depth 0). Brackets inside strings do not count (strings
/// end at an unescaped `"`; `\"` and `\\` are read as escapes). The text need not be valid
/// JSON: unbalanced closers are ignored and an unterminated string ends the scan, so the parser
/// still reports what is wrong. Linear in the size of `text`, no allocation.
bool jsonNestingWithin(std::string_view text, unsigned maxDepth = kMaxNesting);

} // namespace iso::support
