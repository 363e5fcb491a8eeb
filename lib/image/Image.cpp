//! @file Image.cpp
//! @brief Look-ups on the in-memory image.
#include "image/Image.h"

#include <algorithm>

namespace iso::image {

const char* kindName(UnitKind k) {
  switch (k) {
  case UnitKind::Main: return "main";
  case UnitKind::Semi: return "semi";
  case UnitKind::Sub: return "sub";
  }
  return "?";
}

const LineEntry* Image::lineAt(uint32_t offset) const {
  auto it = std::upper_bound(lines.begin(), lines.end(), offset,
                             [](uint32_t o, const LineEntry& e) { return o < e.offset; });
  if (it == lines.begin()) return nullptr;
  return &*(it - 1);
}

const Proc* Image::procAt(uint32_t offset) const {
  for (const Proc& p : procs)
    if (offset >= p.entry && offset < p.entry + p.size) return &p;
  return nullptr;
}

} // namespace iso::image
