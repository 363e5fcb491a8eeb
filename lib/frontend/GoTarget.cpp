//! @file GoTarget.cpp
//! @brief The z32 GO rule (SPEC §4.7): the shape of a target and the line it finds.
#include "frontend/GoTarget.h"

#include <cstddef>

namespace iso::frontend {
namespace {

bool isGoDigit(char c) { return c >= '0' && c <= '9'; }

/// True when `text` (one physical line, without its end) begins with `target` and the next
/// character does not continue the number.
bool lineMatches(std::string_view text, std::string_view target) {
  if (text.size() < target.size() || text.substr(0, target.size()) != target) return false;
  if (text.size() == target.size()) return true;
  char next = text[target.size()];
  return !isGoDigit(next) && next != '.' && next != ',';
}

/// Calls `f(lineNumber, text)` for each physical line of `source` until `f` returns true.
template <class F> void forEachLine(std::string_view source, F&& f) {
  uint32_t line = 1;
  size_t pos = 0;
  while (pos <= source.size()) {
    size_t end = source.find_first_of("\r\n", pos);
    size_t stop = end == std::string_view::npos ? source.size() : end;
    if (f(line, source.substr(pos, stop - pos)) || end == std::string_view::npos) return;
    pos = end + 1;
    if (source[end] == '\r' && pos < source.size() && source[pos] == '\n') ++pos;
    if (pos == source.size()) return; // the text ends with a line end: no further (empty) line
    ++line;
  }
}

} // namespace

bool isGoTargetText(std::string_view text) {
  size_t i = 0;
  if (i < text.size() && text[i] == '%') ++i;
  if (i < text.size() && text[i] == '/') ++i;
  if (i >= text.size() || text[i] != 'N') return false;
  ++i;
  bool digit = false, separator = false;
  for (; i < text.size(); ++i) {
    char c = text[i];
    if (isGoDigit(c)) {
      digit = true;
    } else if ((c == '.' || c == ',') && !separator) {
      separator = true;
    } else {
      return false;
    }
  }
  return digit;
}

GoLineMatch findGoLine(std::string_view source, std::string_view target) {
  GoLineMatch m;
  if (target.empty()) return m;
  forEachLine(source, [&](uint32_t line, std::string_view text) {
    if (lineMatches(text, target)) {
      m.line = line;
      return true;
    }
    if (m.blankCandidate == 0) {
      size_t b = text.find_first_not_of(" \t");
      if (b != 0 && b != std::string_view::npos && lineMatches(text.substr(b), target)) m.blankCandidate = line;
    }
    return false;
  });
  return m;
}

uint32_t findGoLineFrom(std::string_view source, std::string_view target, uint32_t fromLine) {
  uint32_t found = 0;
  if (target.empty()) return found;
  forEachLine(source, [&](uint32_t line, std::string_view text) {
    if (line >= fromLine && lineMatches(text, target)) {
      found = line;
      return true;
    }
    return false;
  });
  return found;
}

} // namespace iso::frontend
