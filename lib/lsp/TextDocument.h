//! @file TextDocument.h
//! @brief An open editor buffer and the position arithmetic of LSP: lines are LF-separated
//!        (as isolint counts them; a CR before the LF is part of the line end), characters
//!        are UTF-16 code units; bytes that are not UTF-8 count as one unit each.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace iso::lsp {

/// An LSP position: 0-based line, 0-based UTF-16 column.
struct Position {
  uint32_t line = 0;
  uint32_t character = 0;
  bool operator==(const Position&) const = default;
};

struct Range {
  Position start;
  Position end;
};

/// UTF-16 code units of the first `bytes` bytes of `line` (clamped to its size).
uint32_t utf16Column(std::string_view line, size_t bytes);
/// The byte offset in `line` of the UTF-16 column `units` (clamped to the line; a column inside
/// a surrogate pair goes to the character's start).
size_t byteColumn(std::string_view line, uint32_t units);

class TextDocument {
public:
  TextDocument() = default;
  TextDocument(std::string text, int64_t version) : text_(std::move(text)), version_(version) { index(); }

  const std::string& text() const { return text_; }
  int64_t version() const { return version_; }
  void setVersion(int64_t v) { version_ = v; }
  uint32_t lineCount() const { return static_cast<uint32_t>(lineStarts_.size()); }
  /// The 0-based line without its line end; empty past the end.
  std::string_view line(uint32_t line) const;
  /// The byte offset of a position (lines past the end clamp to the end of the text,
  /// columns past the end of a line to its end).
  size_t offset(Position p) const;
  /// The position of a byte offset (clamped to the end of the text; an offset inside a line's
  /// end goes to the end of the line).
  Position position(size_t offset) const;
  /// Replaces the whole text.
  void replace(std::string text);
  /// The size of the text after `edit(range, text)` with a text of `textBytes` bytes.
  size_t sizeAfterEdit(Range range, size_t textBytes) const;
  /// What an edit changed: the bytes [at, at + removed) became `inserted` bytes.
  struct Change {
    size_t at = 0, removed = 0, inserted = 0;
    bool sameLines = true; ///< as many line ends as before
  };
  /// Replaces `range` by `text` (LSP incremental sync). A reversed range is read forwards.
  Change edit(Range range, std::string_view text);

private:
  void index();
  std::string text_;
  int64_t version_ = 0;
  std::vector<size_t> lineStarts_;
};

} // namespace iso::lsp
