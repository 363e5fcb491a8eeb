//! @file Fix.cpp
//! @brief Fix-its applied to text; unified diffs of the changes.
#include "diag/Fix.h"

#include <algorithm>

#include <fmt/format.h>

namespace iso::diag {

namespace {

bool hasBom(std::string_view text) {
  return text.size() >= 3 && static_cast<unsigned char>(text[0]) == 0xEF &&
         static_cast<unsigned char>(text[1]) == 0xBB && static_cast<unsigned char>(text[2]) == 0xBF;
}

/// Offsets where each physical line starts (LF-separated).
std::vector<size_t> lineStartsOf(std::string_view text) {
  std::vector<size_t> starts{0};
  for (size_t p = text.find('\n'); p != std::string_view::npos; p = text.find('\n', p + 1))
    if (p + 1 < text.size()) starts.push_back(p + 1);
  return starts;
}

/// Two edits that must not both apply: they share bytes, or both insert at one place, or one
/// inserts inside the other's range.
bool overlaps(const ByteEdit& a, const ByteEdit& b) {
  if (a.begin == b.begin) return true;
  if (a.begin < b.end && b.begin < a.end) return true;
  if (a.begin == a.end && b.begin < a.begin && a.begin < b.end) return true;
  if (b.begin == b.end && a.begin < b.begin && b.begin < a.end) return true;
  return false;
}

} // namespace

bool offsetOf(std::string_view text, uint32_t line, uint32_t col, size_t& offset) {
  if (line == 0 || col == 0) return false;
  size_t start = line == 1 && hasBom(text) ? 3 : 0;
  for (uint32_t l = 1; l < line; ++l) {
    size_t nl = text.find('\n', start);
    if (nl == std::string_view::npos) return false;
    start = nl + 1;
  }
  size_t end = text.find('\n', start);
  if (end == std::string_view::npos)
    end = text.size();
  else if (end > start && text[end - 1] == '\r')
    --end; // an edit never touches the line end
  if (start + col - 1 > end) return false;
  offset = start + col - 1;
  return true;
}

FixResult applyFixes(std::string_view text, const std::vector<const Fix*>& fixes) {
  FixResult r;
  for (const Fix* fix : fixes) {
    std::vector<ByteEdit> mine;
    bool ok = !fix->edits.empty();
    for (const Edit& e : fix->edits) {
      ByteEdit b;
      if (!offsetOf(text, e.start.line, e.start.col, b.begin) || !offsetOf(text, e.endLine, e.endCol, b.end) ||
          b.end < b.begin) {
        ok = false;
        break;
      }
      b.replacement = e.replacement;
      for (const auto& o : mine)
        if (overlaps(o, b)) ok = false;
      for (const auto& o : r.edits)
        if (overlaps(o, b)) ok = false;
      if (!ok) break;
      mine.push_back(std::move(b));
    }
    if (!ok) {
      ++r.skipped;
      continue;
    }
    ++r.applied;
    for (auto& b : mine)
      r.edits.push_back(std::move(b));
  }
  std::sort(r.edits.begin(), r.edits.end(), [](const ByteEdit& a, const ByteEdit& b) { return a.begin < b.begin; });
  size_t at = 0;
  for (const auto& e : r.edits) {
    r.text.append(text.substr(at, e.begin - at));
    r.text += e.replacement;
    at = e.end;
  }
  r.text.append(text.substr(at));
  return r;
}

std::string unifiedDiff(std::string_view text, const std::vector<ByteEdit>& edits, const std::string& path,
                        size_t context) {
  const std::vector<size_t> starts = lineStartsOf(text);
  const size_t lines = starts.size();
  auto lineOf = [&](size_t offset) { // 0-based
    return static_cast<size_t>(std::upper_bound(starts.begin(), starts.end(), offset) - starts.begin()) - 1;
  };
  auto lineEnd = [&](size_t l) { return l + 1 < starts.size() ? starts[l + 1] : text.size(); };
  // Changes grouped by the lines they touch: old lines [first, last] become `replaced`.
  struct Chunk {
    size_t first, last;
    std::string replaced;
  };
  std::vector<Chunk> chunks;
  auto lastLineOf = [&](const ByteEdit& e) { return lineOf(e.end > e.begin ? e.end - 1 : e.begin); };
  for (size_t i = 0; i < edits.size();) {
    size_t first = lineOf(edits[i].begin);
    size_t last = lastLineOf(edits[i]);
    size_t j = i + 1;
    while (j < edits.size() && lineOf(edits[j].begin) <= last + 1) { // adjacent lines: one block
      last = std::max(last, lastLineOf(edits[j]));
      ++j;
    }
    Chunk c{first, last, {}};
    size_t at = starts[first];
    for (size_t k = i; k < j; ++k) {
      c.replaced.append(text.substr(at, edits[k].begin - at));
      c.replaced += edits[k].replacement;
      at = edits[k].end;
    }
    c.replaced.append(text.substr(at, lineEnd(last) - at));
    if (c.replaced != text.substr(starts[first], lineEnd(last) - starts[first])) chunks.push_back(std::move(c));
    i = j;
  }
  if (chunks.empty()) return {};
  auto splitLines = [](std::string_view s) {
    std::vector<std::string_view> out;
    size_t at = 0;
    while (at < s.size()) {
      size_t nl = s.find('\n', at);
      size_t end = nl == std::string_view::npos ? s.size() : nl + 1;
      out.push_back(s.substr(at, end - at));
      at = end;
    }
    return out;
  };
  auto emit = [](std::string& out, char mark, std::string_view line) {
    out.push_back(mark);
    out.append(line);
    if (line.empty() || line.back() != '\n') out += "\n\\ No newline at end of file\n";
  };
  std::string out = fmt::format("--- a/{}\n+++ b/{}\n", path, path);
  long delta = 0; // new line numbers minus old ones, before the current hunk
  for (size_t h = 0; h < chunks.size();) {
    size_t e = h + 1;
    while (e < chunks.size() && chunks[e].first - chunks[e - 1].last - 1 <= 2 * context)
      ++e;
    const size_t from = chunks[h].first >= context ? chunks[h].first - context : 0;
    const size_t to = std::min(lines - 1, chunks[e - 1].last + context);
    std::string body;
    size_t oldCount = 0, newCount = 0;
    size_t l = from;
    for (size_t c = h; c < e; ++c) {
      for (; l < chunks[c].first; ++l, ++oldCount, ++newCount)
        emit(body, ' ', text.substr(starts[l], lineEnd(l) - starts[l]));
      for (; l <= chunks[c].last; ++l, ++oldCount)
        emit(body, '-', text.substr(starts[l], lineEnd(l) - starts[l]));
      for (auto nl : splitLines(chunks[c].replaced)) {
        emit(body, '+', nl);
        ++newCount;
      }
    }
    for (; l <= to; ++l, ++oldCount, ++newCount)
      emit(body, ' ', text.substr(starts[l], lineEnd(l) - starts[l]));
    const long oldStart = static_cast<long>(from) + 1;
    const long newStart = oldStart + delta;
    out += fmt::format("@@ -{},{} +{},{} @@\n", oldCount == 0 ? oldStart - 1 : oldStart, oldCount,
                       newCount == 0 ? newStart - 1 : newStart, newCount);
    out += body;
    delta += static_cast<long>(newCount) - static_cast<long>(oldCount);
    h = e;
  }
  return out;
}

std::string colorDiff(std::string_view diff) {
  std::string out;
  out.reserve(diff.size() + diff.size() / 4);
  for (size_t at = 0; at < diff.size();) {
    size_t end = diff.find('\n', at);
    end = end == std::string_view::npos ? diff.size() : end;
    const std::string_view line = diff.substr(at, end - at);
    const char* color = line.starts_with("--- ") || line.starts_with("+++ ") ? "\x1b[1m"
                        : line.starts_with("@@")                             ? "\x1b[36m"
                        : line.starts_with("-")                              ? "\x1b[31m"
                        : line.starts_with("+")                              ? "\x1b[32m"
                                                                             : nullptr;
    if (color) {
      out += color;
      out += line;
      out += "\x1b[0m";
    } else {
      out += line;
    }
    if (end < diff.size()) out += '\n';
    at = end + 1;
  }
  return out;
}

} // namespace iso::diag
