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

/// The text is held with a gap at the last edit, so that typing does not move the bytes after
/// it; text() closes the gap (once, until the next edit). Line starts are kept per block of
/// lines with an offset for the block, so that an edit that keeps the line count moves a few
/// blocks, not every line. Views returned by line() and prefix() stay valid until the next
/// call of edit, replace, text or prefix.
class TextDocument {
public:
  TextDocument() = default;
  TextDocument(std::string text, int64_t version) : text_(std::move(text)), version_(version) { index(); }

  /// The whole text (closes the gap).
  const std::string& text() const;
  size_t size() const { return text_.size() - gapLen_; }
  /// The bytes [0, n) of the text, or more (a view of at least min(n, size()) bytes that ends
  /// at a line start or at the end of the text).
  std::string_view prefix(size_t n) const;
  int64_t version() const { return version_; }
  void setVersion(int64_t v) { version_ = v; }
  uint32_t lineCount() const { return static_cast<uint32_t>(starts_.size()); }
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
  static constexpr size_t kBlock = 1024;    ///< lines per block of line starts
  static constexpr size_t kGap = 64 * 1024; ///< the gap opened at an edit
  void index();
  /// The line starts after the bytes [a, b) became `text` (the buffer holds it already).
  void relines(size_t a, size_t b, std::string_view text);
  size_t start(size_t line) const { return static_cast<size_t>(starts_[line] + shift_[line / kBlock]); }
  /// Moves the gap to logical offset `at` (opening one of at least `room` bytes).
  void moveGap(size_t at, size_t room = 0) const;
  char at(size_t logical) const { return text_[logical < gapAt_ ? logical : logical + gapLen_]; }
  mutable std::string text_; ///< the text, with gapLen_ unused bytes at gapAt_
  mutable size_t gapAt_ = 0, gapLen_ = 0;
  int64_t version_ = 0;
  /// line starts, less the shift of their block (without it, each is where the line started
  /// before the edits of the blocks before: under 4 GiB, as the documents the server keeps are)
  std::vector<uint32_t> starts_;
  std::vector<int64_t> shift_; ///< per block of kBlock lines
};

} // namespace iso::lsp
