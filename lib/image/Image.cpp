//! @file Image.cpp
//! @brief Look-ups on the in-memory image.
#include "image/Image.h"

#include <algorithm>

#include <fmt/format.h>

namespace iso::image {

const char* kindName(UnitKind k) {
  switch (k) {
  case UnitKind::Main: return "main";
  case UnitKind::Semi: return "semi";
  case UnitKind::Sub: return "sub";
  }
  return "?";
}

namespace {

/// The length of the valid UTF-8 sequence at s[i] (RFC 3629: no overlong forms, no
/// surrogates, nothing above U+10FFFF), or 0.
size_t utf8Length(std::string_view s, size_t i) {
  const auto c = static_cast<unsigned char>(s[i]);
  size_t len = 0;
  unsigned char lo = 0x80, hi = 0xBF; // the range of the second byte
  if (c >= 0xC2 && c <= 0xDF)
    len = 2;
  else if (c >= 0xE0 && c <= 0xEF) {
    len = 3;
    if (c == 0xE0) lo = 0xA0;
    if (c == 0xED) hi = 0x9F;
  } else if (c >= 0xF0 && c <= 0xF4) {
    len = 4;
    if (c == 0xF0) lo = 0x90;
    if (c == 0xF4) hi = 0x8F;
  }
  if (len == 0 || len > s.size() - i) return 0;
  for (size_t k = 1; k < len; ++k) {
    const auto b = static_cast<unsigned char>(s[i + k]);
    if (b < (k == 1 ? lo : 0x80) || b > (k == 1 ? hi : 0xBF)) return 0;
  }
  return len;
}

} // namespace

std::string printableName(std::string_view s, bool quoteEscapes) {
  std::string r;
  r.reserve(s.size());
  for (size_t i = 0; i < s.size();) {
    const auto c = static_cast<unsigned char>(s[i]);
    if (c >= 0x80) {
      if (const size_t len = utf8Length(s, i)) {
        r.append(s.substr(i, len));
        i += len;
        continue;
      }
    }
    if (c < 0x20 || c >= 0x7F)
      r += fmt::format("\\x{:02X}", c);
    else {
      if (quoteEscapes && (c == '"' || c == '\\')) r += '\\';
      r += static_cast<char>(c);
    }
    ++i;
  }
  return r;
}

const LineEntry* Image::lineAt(uint32_t offset) const {
  auto it =
      std::upper_bound(lines.begin(), lines.end(), offset, [](uint32_t o, const LineEntry& e) { return o < e.offset; });
  if (it == lines.begin()) return nullptr;
  return &*(it - 1);
}

const Proc* Image::procAt(uint32_t offset) const {
  for (const Proc& p : procs)
    if (offset >= p.entry && offset < p.entry + p.size) return &p;
  return nullptr;
}

} // namespace iso::image
