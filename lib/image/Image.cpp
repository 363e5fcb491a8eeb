//! @file Image.cpp
//! @brief Look-ups on the in-memory image.
#include "image/Image.h"

#include <algorithm>

#include <fmt/format.h>

#include "support/Text.h"

namespace iso::image {

const char* kindName(UnitKind k) {
  switch (k) {
  case UnitKind::Main: return "main";
  case UnitKind::Semi: return "semi";
  case UnitKind::Sub: return "sub";
  }
  return "?";
}

std::string printableName(std::string_view s, bool quoteEscapes) {
  std::string r;
  r.reserve(s.size());
  for (size_t i = 0; i < s.size();) {
    const auto c = static_cast<unsigned char>(s[i]);
    if (c >= 0x80) {
      if (const size_t len = support::utf8SequenceLength(s, i)) {
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
