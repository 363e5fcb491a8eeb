//! @file TomlDepth.h
//! @brief How deep TOML text nests, found without parsing it: a guard to run before a
//!        recursive parser (toml++ recurses once per level of tables, arrays, inline tables and
//!        dotted-key parts, so deep enough input overflows the stack).
#pragma once

#include <cstddef>
#include <string_view>

#include "support/JsonDepth.h"

namespace iso::support {

/// The byte offset in `text` at which its nesting first goes deeper than `maxDepth`, or
/// std::string_view::npos when it never does. Depth is counted as for the same data in JSON:
/// the document is level 1, each part of a dotted key but its last and each `[` of an array or
/// `{` of an inline table adds one; a table header `[a.b]` sets the level of the keys below it
/// (`[[a.b]]` one more, for the array). Comments and strings (basic, literal, multi-line) are
/// skipped. The text need not be valid TOML: what does not fit is passed over and an
/// unterminated string ends the scan, so the parser still reports what is wrong. Linear in the
/// size of `text`; a fixed amount of memory.
size_t tomlNestingBeyond(std::string_view text, unsigned maxDepth = kMaxNesting);

} // namespace iso::support
