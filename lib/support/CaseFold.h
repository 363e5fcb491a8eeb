//! @file CaseFold.h
//! @brief ASCII case folding: the language is case-insensitive outside comments and strings,
//!        and so are file extensions, header names and option words. Header-only.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace iso::support {

constexpr char upperAscii(char c) { return (c >= 'a' && c <= 'z') ? static_cast<char>(c - 'a' + 'A') : c; }
constexpr char lowerAscii(char c) { return (c >= 'A' && c <= 'Z') ? static_cast<char>(c - 'A' + 'a') : c; }

/// Case-insensitive equality of two spellings (ASCII letters only; other bytes compare as they are).
constexpr bool iequals(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i)
    if (upperAscii(a[i]) != upperAscii(b[i])) return false;
  return true;
}

constexpr bool istartsWith(std::string_view s, std::string_view prefix) {
  return s.size() >= prefix.size() && iequals(s.substr(0, prefix.size()), prefix);
}

constexpr bool iendsWith(std::string_view s, std::string_view suffix) {
  return s.size() >= suffix.size() && iequals(s.substr(s.size() - suffix.size()), suffix);
}

inline std::string upperCopy(std::string_view s) {
  std::string r(s);
  for (char& c : r)
    c = upperAscii(c);
  return r;
}

inline std::string lowerCopy(std::string_view s) {
  std::string r(s);
  for (char& c : r)
    c = lowerAscii(c);
  return r;
}

} // namespace iso::support
