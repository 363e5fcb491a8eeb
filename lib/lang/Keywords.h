//! @file Keywords.h
//! @brief The keywords (Keywords.def) as an enum and a table. Header-only, no dependencies.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string_view>

#include "lang/Text.h"

namespace iso::lang {

enum class Keyword : uint8_t {
#define ISO_KEYWORD(Name, spelling, reserved) Name,
#include "lang/Keywords.def"
};

struct KeywordInfo {
  Keyword id;
  std::string_view spelling;
  bool reserved;
};
constexpr KeywordInfo kKeywords[] = {
#define ISO_KEYWORD(Name, spelling, reserved) {Keyword::Name, spelling, reserved != 0},
#include "lang/Keywords.def"
};
constexpr size_t kKeywordCount = sizeof(kKeywords) / sizeof(kKeywords[0]);

constexpr const KeywordInfo& keywordInfo(Keyword k) { return kKeywords[static_cast<size_t>(k)]; }

/// The keyword spelled `text` (any case), reserved or not.
constexpr std::optional<Keyword> findKeyword(std::string_view text) {
  // The lexer asks this of every name: length and first letter reject most entries cheaply.
  if (text.empty()) return std::nullopt;
  const char first = upperAscii(text[0]);
  for (const KeywordInfo& k : kKeywords)
    if (k.spelling.size() == text.size() && upperAscii(k.spelling[0]) == first && iequalsAscii(text, k.spelling))
      return k.id;
  return std::nullopt;
}
/// True when `text` (any case) is a reserved keyword: not a label, not a subprogram name.
constexpr bool isReservedKeyword(std::string_view text) {
  auto k = findKeyword(text);
  return k && keywordInfo(*k).reserved;
}

} // namespace iso::lang
