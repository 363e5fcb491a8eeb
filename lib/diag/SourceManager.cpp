//! @file SourceManager.cpp
//! @brief Line tables for loaded sources.
#include "diag/SourceManager.h"

#include <cstring>

namespace iso::diag {

uint32_t SourceManager::add(std::string path, support::SourceText text) {
  SourceFile f;
  f.path = std::move(path);
  f.text = std::move(text);
  files_.push_back(std::move(f));
  return static_cast<uint32_t>(files_.size() - 1);
}

/// Extends the line index of `f` until it holds the start of line `line` + 1, or the file ends:
/// diagnostics are rendered in line order, so a file whose diagnostics all sit near its start is
/// never scanned to its end.
static void indexTo(const SourceFile& f, uint32_t line) {
  if (f.lineStarts.empty()) f.lineStarts.push_back(0);
  const char* base = f.text.data();
  const char* end = base + f.text.size();
  while (!f.indexed && f.lineStarts.size() <= line) {
    const char* p = base + f.lineStarts.back();
    const void* nl = std::memchr(p, '\n', static_cast<size_t>(end - p));
    const char* next = nl ? static_cast<const char*>(nl) + 1 : end;
    if (next >= end) {
      f.indexed = true; // a last line end starts no line
      break;
    }
    f.lineStarts.push_back(static_cast<uint32_t>(next - base));
  }
}

std::string_view SourceManager::lineText(uint32_t id, uint32_t line) const {
  const SourceFile& f = files_[id];
  if (line == 0) return {};
  indexTo(f, line);
  if (line > f.lineStarts.size()) return {};
  size_t b = f.lineStarts[line - 1];
  size_t e = line < f.lineStarts.size() ? f.lineStarts[line] : f.text.size();
  while (e > b && (f.text[e - 1] == '\n' || f.text[e - 1] == '\r'))
    --e;
  return f.text.view().substr(b, e - b);
}

} // namespace iso::diag
