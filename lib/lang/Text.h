//! @file Text.h
//! @brief ASCII case folding for the tables of lib/lang (the language is case-insensitive
//!        outside comments and strings, SPEC §2). Header-only, no dependencies.
#pragma once

#include <cstddef>
#include <string_view>

namespace iso::lang {

constexpr char upperAscii(char c) { return (c >= 'a' && c <= 'z') ? static_cast<char>(c - 32) : c; }

/// Case-insensitive equality of two spellings (ASCII).
constexpr bool iequalsAscii(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i)
    if (upperAscii(a[i]) != upperAscii(b[i])) return false;
  return true;
}

} // namespace iso::lang
