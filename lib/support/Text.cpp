//! @file Text.cpp
#include "support/Text.h"

#include <algorithm>
#include <cstring>

namespace iso::support {

namespace {

void appendHex(std::string& out, unsigned char c) {
  static const char* kDigits = "0123456789abcdef";
  out += "\\x";
  out.push_back(kDigits[c >> 4]);
  out.push_back(kDigits[c & 15]);
}

/// Code point of the valid sequence of `len` bytes at s[i].
char32_t decode(std::string_view s, size_t i, size_t len) {
  auto b = [&](size_t k) { return static_cast<char32_t>(static_cast<unsigned char>(s[i + k])); };
  switch (len) {
  case 1: return b(0);
  case 2: return ((b(0) & 0x1F) << 6) | (b(1) & 0x3F);
  case 3: return ((b(0) & 0x0F) << 12) | ((b(1) & 0x3F) << 6) | (b(2) & 0x3F);
  default: return ((b(0) & 0x07) << 18) | ((b(1) & 0x3F) << 12) | ((b(2) & 0x3F) << 6) | (b(3) & 0x3F);
  }
}

bool unsafeForTerminal(char32_t cp) {
  if (cp < 0x20) return cp != '\t';
  if (cp == 0x7F) return true;
  if (cp >= 0x80 && cp <= 0x9F) return true;     // C1 controls
  if (cp == 0x200E || cp == 0x200F) return true; // LRM, RLM
  if (cp >= 0x202A && cp <= 0x202E) return true; // embeddings and overrides
  return cp >= 0x2066 && cp <= 0x2069;           // isolates
}

} // namespace

size_t utf8SequenceLength(std::string_view s, size_t i) {
  const auto c0 = static_cast<unsigned char>(s[i]);
  if (c0 < 0x80) return 1;
  size_t len;
  unsigned char lo = 0x80, hi = 0xBF; // allowed range of the second byte
  if (c0 >= 0xC2 && c0 <= 0xDF)
    len = 2;
  else if (c0 >= 0xE0 && c0 <= 0xEF) {
    len = 3;
    if (c0 == 0xE0) lo = 0xA0;
    if (c0 == 0xED) hi = 0x9F; // no surrogates
  } else if (c0 >= 0xF0 && c0 <= 0xF4) {
    len = 4;
    if (c0 == 0xF0) lo = 0x90;
    if (c0 == 0xF4) hi = 0x8F;
  } else {
    return 0;
  }
  if (i + len > s.size()) return 0;
  const auto c1 = static_cast<unsigned char>(s[i + 1]);
  if (c1 < lo || c1 > hi) return 0;
  for (size_t k = 2; k < len; ++k) {
    const auto ck = static_cast<unsigned char>(s[i + k]);
    if (ck < 0x80 || ck > 0xBF) return 0;
  }
  return len;
}

bool isValidUtf8(std::string_view s) {
  for (size_t i = 0; i < s.size();) {
    if (static_cast<unsigned char>(s[i]) < 0x80) { // ASCII: one byte each, the common case
      ++i;
      continue;
    }
    size_t n = utf8SequenceLength(s, i);
    if (n == 0) return false;
    i += n;
  }
  return true;
}

void appendEscaped(std::string& out, std::string_view s) {
  for (size_t i = 0; i < s.size();) {
    // a run of printable ASCII (and tabs) is appended at once
    size_t e = i;
    while (e < s.size() && ((s[e] >= 0x20 && s[e] < 0x7F) || s[e] == '\t'))
      ++e;
    if (e > i) {
      out.append(s.substr(i, e - i));
      i = e;
      continue;
    }
    size_t n = utf8SequenceLength(s, i);
    if (n == 0) {
      appendHex(out, static_cast<unsigned char>(s[i++]));
      continue;
    }
    if (unsafeForTerminal(decode(s, i, n))) {
      for (size_t k = 0; k < n; ++k)
        appendHex(out, static_cast<unsigned char>(s[i + k]));
    } else {
      out.append(s.substr(i, n));
    }
    i += n;
  }
}

std::string escapeForTerminal(std::string_view s) {
  std::string out;
  out.reserve(s.size());
  appendEscaped(out, s);
  return out;
}

std::string toValidUtf8(std::string_view s) {
  if (isValidUtf8(s)) return std::string(s);
  std::string out;
  out.reserve(s.size() + 8);
  for (size_t i = 0; i < s.size();) {
    size_t n = utf8SequenceLength(s, i);
    if (n == 0) {
      appendHex(out, static_cast<unsigned char>(s[i++]));
    } else {
      out.append(s.substr(i, n));
      i += n;
    }
  }
  return out;
}

size_t countByte(std::string_view s, char c) {
  // GCC/Clang vector extensions: 16 lanes compared at once on any target. A lane's count (a
  // byte, wrapping as unsigned) takes at most 255 blocks before the lanes are added up.
  using V = unsigned char __attribute__((vector_size(16)));
  constexpr size_t kLanes = sizeof(V);
  const char* p = s.data();
  size_t left = s.size();
  size_t n = 0;
  V key;
  for (size_t k = 0; k < kLanes; ++k)
    key[k] = static_cast<unsigned char>(c);
  while (left >= kLanes) {
    V acc{};
    const size_t blocks = std::min<size_t>(left / kLanes, 255);
    for (size_t b = 0; b < blocks; ++b, p += kLanes) {
      V v;
      std::memcpy(&v, p, kLanes);
      acc -= reinterpret_cast<V>(v == key); // 0xFF where equal: one more
    }
    for (size_t k = 0; k < kLanes; ++k)
      n += acc[k];
    left -= blocks * kLanes;
  }
  for (; left > 0; --left, ++p)
    n += *p == c;
  return n;
}

namespace {
char foldCase(char c) { return c >= 'A' && c <= 'Z' ? static_cast<char>(c - 'A' + 'a') : c; }
} // namespace

std::string escapeMarkup(std::string_view s) {
  std::string o;
  o.reserve(s.size());
  for (size_t i = 0; i < s.size();) {
    const auto c = static_cast<unsigned char>(s[i]);
    if (c >= 0x80) {
      const size_t n = utf8SequenceLength(s, i);
      if (n == 0) {
        o.push_back('?');
        ++i;
      } else {
        o.append(s, i, n);
        i += n;
      }
      continue;
    }
    switch (c) {
    case '&': o += "&amp;"; break;
    case '<': o += "&lt;"; break;
    case '>': o += "&gt;"; break;
    case '"': o += "&quot;"; break;
    case '\'': o += "&#39;"; break;
    default: o.push_back((c < 0x20 && c != '\t' && c != '\n') || c == 0x7F ? '?' : static_cast<char>(c));
    }
    ++i;
  }
  return o;
}

size_t editDistance(std::string_view a, std::string_view b, size_t limit) {
  if (a.size() < b.size()) std::swap(a, b);
  if (a.size() - b.size() > limit) return limit == SIZE_MAX ? limit : limit + 1;
  // three rows of the dynamic programme: two back (for swaps), one back, this one
  std::vector<size_t> before(b.size() + 1), prev(b.size() + 1), row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j)
    prev[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    row[0] = i;
    size_t best = row[0];
    for (size_t j = 1; j <= b.size(); ++j) {
      const bool same = foldCase(a[i - 1]) == foldCase(b[j - 1]);
      size_t d = std::min({prev[j] + 1, row[j - 1] + 1, prev[j - 1] + (same ? 0 : 1)});
      if (i > 1 && j > 1 && foldCase(a[i - 1]) == foldCase(b[j - 2]) && foldCase(a[i - 2]) == foldCase(b[j - 1]))
        d = std::min(d, before[j - 2] + 1);
      row[j] = d;
      best = std::min(best, d);
    }
    if (best > limit) return limit + 1; // every later row is at least as far
    std::swap(before, prev);
    std::swap(prev, row);
  }
  return prev[b.size()] > limit ? limit + 1 : prev[b.size()];
}

std::string_view closestMatch(std::string_view word, const std::vector<std::string_view>& candidates) {
  const size_t limit = std::max<size_t>(1, std::min<size_t>(2, word.size() / 3));
  std::string_view best;
  size_t bestDistance = limit + 1;
  bool tie = false;
  for (std::string_view c : candidates) {
    const size_t d = editDistance(word, c, limit);
    if (d < bestDistance) {
      best = c;
      bestDistance = d;
      tie = false;
    } else if (d == bestDistance && d <= limit && c != best) {
      tie = true;
    }
  }
  return bestDistance <= limit && !tie ? best : std::string_view();
}

} // namespace iso::support
