//! @file TextDocument.cpp
//! @brief UTF-16 columns and edits of open buffers.
#include "lsp/TextDocument.h"

#include <algorithm>
#include <cstring>

namespace iso::lsp {

namespace {
/// Length of the UTF-8 sequence at `s[i]` if it is well-formed, else 1 (one unit per bad byte).
size_t sequenceLength(std::string_view s, size_t i) {
  auto b = static_cast<unsigned char>(s[i]);
  size_t n = b < 0x80 ? 1 : (b & 0xE0) == 0xC0 ? 2 : (b & 0xF0) == 0xE0 ? 3 : (b & 0xF8) == 0xF0 ? 4 : 1;
  if (n == 1 || i + n > s.size()) return 1;
  for (size_t k = 1; k < n; ++k)
    if ((static_cast<unsigned char>(s[i + k]) & 0xC0) != 0x80) return 1;
  if (n == 2 && b < 0xC2) return 1; // overlong
  return n;
}
} // namespace

uint32_t utf16Column(std::string_view line, size_t bytes) {
  bytes = std::min(bytes, line.size());
  uint32_t units = 0;
  for (size_t i = 0; i < bytes;) {
    size_t n = sequenceLength(line, i);
    units += n == 4 ? 2 : 1;
    i += n;
  }
  return units;
}

size_t byteColumn(std::string_view line, uint32_t units) {
  size_t i = 0;
  uint32_t u = 0;
  while (i < line.size()) {
    size_t n = sequenceLength(line, i);
    uint32_t w = n == 4 ? 2 : 1;
    if (u + w > units) break;
    u += w;
    i += n;
  }
  return i;
}

void TextDocument::index() {
  const std::string& t = text();
  starts_.clear();
  starts_.reserve(static_cast<size_t>(std::count(t.begin(), t.end(), '\n')) + 1); // no room to spare
  starts_.push_back(0);
  for (size_t i = 0; i < t.size(); ++i)
    if (t[i] == '\n') starts_.push_back(static_cast<uint32_t>(i + 1));
  shift_.assign(starts_.size() / kBlock + 1, 0);
}

const std::string& TextDocument::text() const {
  if (gapLen_) {
    text_.erase(gapAt_, gapLen_);
    gapAt_ = gapLen_ = 0;
  }
  return text_;
}

void TextDocument::moveGap(size_t to, size_t room) const {
  if (gapLen_ == 0 || gapLen_ < room) {
    // a new gap, or a larger one: the bytes after it move once
    const size_t grow = std::max(kGap, room) - gapLen_;
    if (gapLen_ == 0) gapAt_ = to;
    text_.insert(gapAt_ + gapLen_, grow, '\0');
    gapLen_ += grow;
  }
  char* p = text_.data();
  if (to < gapAt_)
    std::memmove(p + to + gapLen_, p + to, gapAt_ - to);
  else if (to > gapAt_)
    std::memmove(p + gapAt_, p + gapAt_ + gapLen_, to - gapAt_);
  gapAt_ = to;
}

std::string_view TextDocument::prefix(size_t n) const {
  const size_t total = size();
  size_t e = std::min(n, total); // to the line start at or after n
  while (e > 0 && e < total && at(e - 1) != '\n')
    ++e;
  if (gapLen_ && gapAt_ < e) moveGap(e);
  return std::string_view(text_.data(), e);
}

std::string_view TextDocument::line(uint32_t l) const {
  if (l >= starts_.size()) return {};
  size_t b = start(l);
  size_t e = l + 1 < starts_.size() ? start(l + 1) - 1 : size();
  // a line across the gap: the gap moves to the line's end (after its LF)
  if (gapLen_ && b < gapAt_ && e + 1 > gapAt_ && !(e == gapAt_ && l + 1 < starts_.size()))
    moveGap(l + 1 < starts_.size() ? e + 1 : size());
  const size_t pb = b < gapAt_ || gapLen_ == 0 ? b : b + gapLen_;
  if (e > b && text_[pb + (e - b) - 1] == '\r') --e;
  return std::string_view(text_).substr(pb, e - b);
}

size_t TextDocument::offset(Position p) const {
  if (p.line >= starts_.size()) return size();
  return start(p.line) + byteColumn(line(p.line), p.character);
}

Position TextDocument::position(size_t offset) const {
  offset = std::min(offset, size());
  // the last line starting at or before offset
  size_t lo = 0, hi = starts_.size();
  while (hi - lo > 1) {
    const size_t mid = lo + (hi - lo) / 2;
    if (start(mid) <= offset)
      lo = mid;
    else
      hi = mid;
  }
  const auto l = static_cast<uint32_t>(lo);
  return {l, utf16Column(line(l), offset - start(l))};
}

void TextDocument::relines(size_t a, size_t b, std::string_view text) {
  // the first line that starts after a, and its block: from there the starts are written again
  // as they are now (the block shifts go to 0), without the lines that started in (a, b] and
  // with those the new text starts
  size_t lo = 0, hi = starts_.size();
  while (lo < hi) {
    const size_t mid = lo + (hi - lo) / 2;
    if (start(mid) <= a)
      lo = mid + 1;
    else
      hi = mid;
  }
  const size_t from = lo / kBlock * kBlock;
  const auto delta = static_cast<int64_t>(text.size()) - static_cast<int64_t>(b - a);
  std::vector<uint32_t> tail;
  tail.reserve(starts_.size() - from + static_cast<size_t>(std::count(text.begin(), text.end(), '\n')));
  for (size_t k = from; k < lo; ++k)
    tail.push_back(static_cast<uint32_t>(start(k)));
  for (size_t i = 0; i < text.size(); ++i)
    if (text[i] == '\n') tail.push_back(static_cast<uint32_t>(a + i + 1));
  for (size_t k = lo; k < starts_.size(); ++k)
    if (const size_t at = start(k); at > b) tail.push_back(static_cast<uint32_t>(static_cast<int64_t>(at) + delta));
  starts_.resize(from);
  starts_.insert(starts_.end(), tail.begin(), tail.end());
  shift_.resize(starts_.size() / kBlock + 1);
  std::fill(shift_.begin() + static_cast<std::ptrdiff_t>(from / kBlock), shift_.end(), 0);
}

void TextDocument::replace(std::string text) {
  text_ = std::move(text);
  gapAt_ = gapLen_ = 0;
  index();
}

size_t TextDocument::sizeAfterEdit(Range range, size_t textBytes) const {
  size_t a = offset(range.start), b = offset(range.end);
  if (a > b) std::swap(a, b);
  return size() - (b - a) + textBytes;
}

TextDocument::Change TextDocument::edit(Range range, std::string_view text) {
  size_t a = offset(range.start), b = offset(range.end);
  if (a > b) std::swap(a, b);
  size_t removedLf = 0;
  for (size_t i = a; i < b; ++i)
    removedLf += at(i) == '\n' ? 1u : 0u;
  const auto insertedLf = static_cast<size_t>(std::count(text.begin(), text.end(), '\n'));
  // the gap at b, then [a, b) joins it and the text fills it from a
  moveGap(b, text.size() + 1);
  gapAt_ = a;
  gapLen_ += b - a;
  std::memcpy(text_.data() + gapAt_, text.data(), text.size());
  gapAt_ += text.size();
  gapLen_ -= text.size();
  const Change change{a, b - a, text.size(), removedLf == insertedLf};
  if (removedLf != 0 || insertedLf != 0) { // lines come, go or move
    relines(a, b, text);
    return change;
  }
  // The same lines: the starts after the edit move by its size, those of the edit's own block
  // one by one, the later blocks by their shift.
  const auto delta = static_cast<int64_t>(text.size()) - static_cast<int64_t>(b - a);
  if (delta == 0) return change;
  size_t first = 0; // the first line starting after a
  {
    size_t lo = 0, hi = starts_.size();
    while (lo < hi) {
      const size_t mid = lo + (hi - lo) / 2;
      if (start(mid) <= a)
        lo = mid + 1;
      else
        hi = mid;
    }
    first = lo;
  }
  if (first >= starts_.size()) return change;
  const size_t block = first / kBlock;
  const size_t blockEnd = std::min(starts_.size(), (block + 1) * kBlock);
  for (size_t k = first; k < blockEnd; ++k)
    starts_[k] = static_cast<uint32_t>(static_cast<int64_t>(starts_[k]) + delta);
  for (size_t k = block + 1; k < shift_.size(); ++k)
    shift_[k] += delta;
  return change;
}

} // namespace iso::lsp
