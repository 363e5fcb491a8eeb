//! @file Image.cpp
//! @brief Look-ups on the in-memory image.
#include "image/Image.h"

#include <algorithm>
#include <bit>

#include <fmt/format.h>

#include "support/Bytes.h"

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

uint64_t lineTableHash(const std::vector<LineEntry>& lines) {
  support::Fnv1a h;
  h.word(lines.size());
  for (const LineEntry& e : lines) {
    h.word(e.offset | (uint64_t{e.file} << 32));
    h.word(e.line | (uint64_t{e.hasN} << 32));
    h.word(std::bit_cast<uint64_t>(e.n));
  }
  return h.value();
}

bool sameImage(const Image& a, const Image& b, uint64_t bLines) {
  return a.formatVersion == b.formatVersion && a.flags == b.flags && a.strings == b.strings &&
         std::equal(a.constants.begin(), a.constants.end(), b.constants.begin(), b.constants.end(),
                    [](double x, double y) { return std::bit_cast<uint64_t>(x) == std::bit_cast<uint64_t>(y); }) &&
         a.code == b.code && a.procs == b.procs && a.entries == b.entries && a.axes == b.axes &&
         lineTableHash(a.lines) == bLines;
}

} // namespace iso::image
