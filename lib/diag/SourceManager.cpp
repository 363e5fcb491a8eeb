//! @file SourceManager.cpp
//! @brief Line tables for loaded sources.
#include "diag/SourceManager.h"

#include <algorithm>
#include <cstring>

namespace iso::diag {

uint32_t SourceManager::add(std::string path, std::string text) {
  SourceFile f;
  f.path = std::move(path);
  f.text = std::move(text);
  files_.push_back(std::move(f));
  return static_cast<uint32_t>(files_.size() - 1);
}

static void indexLines(const SourceFile& f) {
  const char* base = f.text.data();
  const char* end = base + f.text.size();
  f.lineStarts.assign(1, 0);
  f.lineStarts.reserve(static_cast<size_t>(std::count(base, end, '\n')) + 1);
  for (const char* p = base; p < end;) {
    const void* nl = std::memchr(p, '\n', static_cast<size_t>(end - p));
    if (!nl) break;
    p = static_cast<const char*>(nl) + 1;
    if (p < end) f.lineStarts.push_back(static_cast<uint32_t>(p - base));
  }
  f.indexed = true;
}

std::string_view SourceManager::lineText(uint32_t id, uint32_t line) const {
  const SourceFile& f = files_[id];
  if (!f.indexed) indexLines(f);
  if (line == 0 || line > f.lineStarts.size()) return {};
  size_t b = f.lineStarts[line - 1];
  size_t e = line < f.lineStarts.size() ? f.lineStarts[line] : f.text.size();
  while (e > b && (f.text[e - 1] == '\n' || f.text[e - 1] == '\r'))
    --e;
  return std::string_view(f.text).substr(b, e - b);
}

} // namespace iso::diag
