//! @file Keywords.h
//! @brief The keywords (Keywords.def) as an enum and a table, with the texts editors show.
//!        Header-only, no dependencies.
#pragma once

#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string_view>

#include "support/CaseFold.h"

namespace iso::lang {

enum class Keyword : uint8_t {
#define ISO_KEYWORD(Name, spelling, reserved) Name,
#include "lang/Keywords.def"
};

struct KeywordInfo {
  Keyword id;
  std::string_view spelling;
  bool reserved;
  std::string_view syntax; ///< how it is written, for editors (one line)
  std::string_view doc;    ///< what it does, for editors (Markdown)
};
constexpr KeywordInfo kKeywords[] = {
#define ISO_KEYWORD_DOC(Name, spelling, reserved, syntax, doc) {Keyword::Name, spelling, reserved != 0, syntax, doc},
#include "lang/Keywords.def"
};
constexpr size_t kKeywordCount = sizeof(kKeywords) / sizeof(kKeywords[0]);

constexpr const KeywordInfo& keywordInfo(Keyword k) { return kKeywords[static_cast<size_t>(k)]; }

/// Bit k of entry i: keyword k is spelled with the letter 'A' + i first (any case).
inline constexpr std::array<uint32_t, 26> kKeywordsByFirstLetter = [] {
  static_assert(kKeywordCount <= 32);
  std::array<uint32_t, 26> m{};
  for (const KeywordInfo& k : kKeywords)
    m[static_cast<size_t>(support::upperAscii(k.spelling[0]) - 'A')] |= uint32_t{1} << static_cast<unsigned>(k.id);
  return m;
}();

/// The keyword spelled `text` (any case), reserved or not.
constexpr std::optional<Keyword> findKeyword(std::string_view text) {
  // The lexer asks this of every name: only the keywords of its first letter are compared.
  if (text.empty()) return std::nullopt;
  const char first = support::upperAscii(text[0]);
  if (first < 'A' || first > 'Z') return std::nullopt;
  for (uint32_t m = kKeywordsByFirstLetter[static_cast<size_t>(first - 'A')]; m != 0; m &= m - 1) {
    const KeywordInfo& k = kKeywords[static_cast<size_t>(std::countr_zero(m))];
    if (k.spelling.size() == text.size() && support::iequals(text, k.spelling)) return k.id;
  }
  return std::nullopt;
}
/// True when `text` (any case) is a reserved keyword: not a label, not a subprogram name.
constexpr bool isReservedKeyword(std::string_view text) {
  auto k = findKeyword(text);
  return k && keywordInfo(*k).reserved;
}

} // namespace iso::lang
