//! @file TomlDepth.cpp
//! @brief The nesting depth of TOML text by one scan.
#include "support/TomlDepth.h"

#include <vector>

namespace iso::support {

namespace {

constexpr size_t kNone = std::string_view::npos;

/// The offset just past the string that starts at `i` (a quote), or kNone when it does not end.
size_t skipString(std::string_view t, size_t i) {
  const char q = t[i];
  const bool multi = t.substr(i, 3) == std::string_view(q == '"' ? "\"\"\"" : "'''");
  size_t k = i + (multi ? 3 : 1);
  while (k < t.size()) {
    const char c = t[k];
    if (c == '\\' && q == '"') {
      k += 2;
      continue;
    }
    if (!multi && c == '\n') return kNone; // a one-line string cannot go on
    if (c == q) {
      if (!multi) return k + 1;
      if (t.substr(k, 3) == std::string_view(q == '"' ? "\"\"\"" : "'''")) {
        k += 3;
        while (k < t.size() && t[k] == q) // up to two quotes of the content end it too
          ++k;
        return k;
      }
    }
    ++k;
  }
  return kNone;
}

/// One open array or inline table, and the dotted-key levels of the key it is now reading.
struct Frame {
  bool inlineTable;
  unsigned keyLevels;
};

class Scanner {
public:
  Scanner(std::string_view t, unsigned maxDepth) : t_(t), max_(maxDepth) {}

  size_t run() {
    lineStart();
    for (size_t i = 0; i < t_.size(); ++i) {
      const char c = t_[i];
      if (c == '"' || c == '\'') {
        const size_t end = skipString(t_, i);
        if (end == kNone) return kNone;
        i = end - 1;
      } else if (c == '#') {
        while (i + 1 < t_.size() && t_[i + 1] != '\n')
          ++i;
      } else if (c == '\n') {
        if (frames_.empty()) lineStart();
      } else if (atLineStart_ && c == '[') {
        if (!header(i)) return i;
      } else if (c != ' ' && c != '\t' && c != '\r' && !step(c)) {
        return i;
      }
      if (c != ' ' && c != '\t' && c != '\r' && c != '\n') atLineStart_ = false;
    }
    return kNone;
  }

private:
  void lineStart() {
    depth_ = base_;
    inKey_ = true;
    keyLevels_ = 0;
    atLineStart_ = true;
  }

  /// A table header at t_[i]: `[a.b.c]` or `[[a.b.c]]`; false when it is too deep. Leaves i
  /// on the last byte it read (the rest of the line is read as a value, which holds nothing).
  bool header(size_t& i) {
    const bool array = i + 1 < t_.size() && t_[i + 1] == '[';
    if (array) ++i;
    unsigned level = 2 + (array ? 1 : 0); // the document, the first part (and the array)
    for (size_t k = i + 1; k < t_.size() && t_[k] != '\n' && t_[k] != ']'; ++k) {
      i = k;
      if (t_[k] == '"' || t_[k] == '\'') {
        const size_t end = skipString(t_, k);
        if (end == kNone) break;
        i = k = end - 1;
      } else if (t_[k] == '.' && ++level > max_) {
        return false;
      }
    }
    if (level > max_) return false;
    base_ = level; // the keys below it are in this table
    inKey_ = false;
    return true;
  }

  bool deeper(unsigned by) {
    depth_ += by;
    return depth_ <= max_;
  }

  /// One byte that is neither blank, nor a comment, nor in a string.
  bool step(char c) {
    if (inKey_) {
      if (c == '.') {
        ++keyLevels_;
        return depth_ + keyLevels_ <= max_;
      }
      if (c == '=') {
        inKey_ = false;
        if (!frames_.empty()) frames_.back().keyLevels = keyLevels_; // a line's key ends with it
        return deeper(keyLevels_);
      }
      if (c == '}' && !frames_.empty() && frames_.back().inlineTable) return close(); // `{}`
      return true;
    }
    switch (c) {
    case '[':
    case '{':
      frames_.push_back(Frame{c == '{', 0});
      if (c == '{') startKey();
      return deeper(1);
    case ']':
      if (!frames_.empty() && !frames_.back().inlineTable) return close();
      return true;
    case '}':
      if (!frames_.empty() && frames_.back().inlineTable) return close();
      return true;
    case ',':
      if (!frames_.empty() && frames_.back().inlineTable) {
        depth_ -= frames_.back().keyLevels;
        frames_.back().keyLevels = 0;
        startKey();
      }
      return true;
    default: return true;
    }
  }

  void startKey() {
    inKey_ = true;
    keyLevels_ = 0;
  }

  bool close() {
    depth_ -= 1 + frames_.back().keyLevels;
    frames_.pop_back();
    inKey_ = false;
    return true;
  }

  std::string_view t_;
  unsigned max_;
  unsigned base_ = 1;      ///< the level of a key in the current table
  unsigned depth_ = 1;     ///< the level of what is read now
  unsigned keyLevels_ = 0; ///< dots seen so far in the key being read
  bool inKey_ = true;
  bool atLineStart_ = true;
  std::vector<Frame> frames_; ///< at most maxDepth + 1
};

} // namespace

size_t tomlNestingBeyond(std::string_view text, unsigned maxDepth) { return Scanner(text, maxDepth).run(); }

} // namespace iso::support
