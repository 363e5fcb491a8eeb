//! @file TextDocument.cpp
//! @brief UTF-16 columns and edits of open buffers.
#include "lsp/TextDocument.h"

#include <algorithm>

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
  lineStarts_.assign(1, 0);
  for (size_t i = 0; i < text_.size(); ++i)
    if (text_[i] == '\n') lineStarts_.push_back(i + 1);
}

std::string_view TextDocument::line(uint32_t l) const {
  if (l >= lineStarts_.size()) return {};
  size_t b = lineStarts_[l];
  size_t e = l + 1 < lineStarts_.size() ? lineStarts_[l + 1] - 1 : text_.size();
  if (e > b && text_[e - 1] == '\r') --e;
  return std::string_view(text_).substr(b, e - b);
}

size_t TextDocument::offset(Position p) const {
  if (p.line >= lineStarts_.size()) return text_.size();
  return lineStarts_[p.line] + byteColumn(line(p.line), p.character);
}

Position TextDocument::position(size_t offset) const {
  offset = std::min(offset, text_.size());
  const auto next = std::upper_bound(lineStarts_.begin(), lineStarts_.end(), offset);
  const auto l = static_cast<uint32_t>(next - lineStarts_.begin() - 1);
  return {l, utf16Column(line(l), offset - lineStarts_[l])};
}

void TextDocument::replace(std::string text) {
  text_ = std::move(text);
  index();
}

size_t TextDocument::sizeAfterEdit(Range range, size_t textBytes) const {
  size_t a = offset(range.start), b = offset(range.end);
  if (a > b) std::swap(a, b);
  return text_.size() - (b - a) + textBytes;
}

TextDocument::Change TextDocument::edit(Range range, std::string_view text) {
  size_t a = offset(range.start), b = offset(range.end);
  if (a > b) std::swap(a, b);
  const auto removedLf = static_cast<size_t>(
      std::count(text_.begin() + static_cast<std::ptrdiff_t>(a), text_.begin() + static_cast<std::ptrdiff_t>(b), '\n'));
  const auto insertedLf = static_cast<size_t>(std::count(text.begin(), text.end(), '\n'));
  text_.replace(a, b - a, text);
  // The line starts after the edit move by its size; those inside it are found again.
  const auto first = static_cast<size_t>(std::upper_bound(lineStarts_.begin(), lineStarts_.end(), a) -
                                         lineStarts_.begin()); // the first start after a
  std::vector<size_t> inside;
  for (size_t i = 0; i < text.size(); ++i)
    if (text[i] == '\n') inside.push_back(a + i + 1);
  const auto removedStarts = static_cast<std::ptrdiff_t>(removedLf);
  lineStarts_.erase(lineStarts_.begin() + static_cast<std::ptrdiff_t>(first),
                    lineStarts_.begin() + static_cast<std::ptrdiff_t>(first) + removedStarts);
  lineStarts_.insert(lineStarts_.begin() + static_cast<std::ptrdiff_t>(first), inside.begin(), inside.end());
  for (size_t k = first + inside.size(); k < lineStarts_.size(); ++k)
    lineStarts_[k] = lineStarts_[k] - (b - a) + text.size();
  return {a, b - a, text.size(), removedLf == insertedLf};
}

} // namespace iso::lsp
