//! @file SourceText.h
//! @brief The bytes of a source file: held in memory, or, for a large regular file, mapped
//!        read-only from the file (no copy, no fresh pages to fault in and zero).
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

#include "support/Expected.h"

namespace iso::support {

/// A source's bytes, read-only. Copies hold their bytes in memory; a move keeps the mapping.
/// Like a std::string, the byte after the last one reads as NUL (readSource maps only files
/// whose last page has room for it).
class SourceText {
public:
  SourceText() = default;
  SourceText(std::string text) : owned_(std::move(text)) {} // NOLINT(google-explicit-constructor)
  SourceText(const char* text) : owned_(text) {}            // NOLINT(google-explicit-constructor)
  ~SourceText() { unmap(); }
  SourceText(const SourceText& o) : owned_(o.view()) {}
  SourceText& operator=(const SourceText& o);
  SourceText(SourceText&& o) noexcept { *this = std::move(o); }
  SourceText& operator=(SourceText&& o) noexcept;

  const char* data() const { return mapped_ ? mapped_ : owned_.data(); }
  size_t size() const { return mapped_ ? mappedSize_ : owned_.size(); }
  bool empty() const { return size() == 0; }
  std::string_view view() const { return {data(), size()}; }
  operator std::string_view() const { return view(); } // NOLINT(google-explicit-constructor)
  char operator[](size_t i) const { return data()[i]; }
  /// Mapped from its file (readSource), not held in memory.
  bool isMapped() const { return mapped_ != nullptr; }
  /// A mapped text's pages leave memory (madvise(MADV_DONTNEED)): the bytes stay readable, and
  /// the pages touched again are read again from the file. For a text read once and kept for
  /// rare later reads. A text held in memory: nothing.
  void dropPages() const;
  /// dropPages for the whole pages inside [begin, end) only: the part of a text read once
  /// from front to back that lies behind the reader.
  void dropPages(size_t begin, size_t end) const;
  /// A mapped text whose file `path` was written over in place since it was mapped (the same
  /// file, another size or modification time): a second reading of it may see other bytes
  /// than the first. False for a text held in memory, or a file replaced by another one (the
  /// mapping keeps the old one's bytes).
  bool changedOnDisk(const std::string& path) const;
  friend bool operator==(const SourceText& a, std::string_view b) { return a.view() == b; }

private:
  friend Expected<SourceText> readSource(const std::string& path, size_t mapFrom);
  void unmap();
  std::string owned_;
  const char* mapped_ = nullptr;
  size_t mappedSize_ = 0;
  int slot_ = -1;       ///< its entry for mappedSourceAt
  uint64_t inode_ = 0;  ///< mapped: the file's inode when it was mapped
  int64_t mtimeNs_ = 0; ///< and its modification time
};

/// Files of this size or more are mapped by readSource: below it, reading costs little.
constexpr size_t kMapSourcesFrom = size_t{1} << 20;

/// Reads a whole file as readFile does; a regular file of `mapFrom` bytes or more is mapped
/// instead (when the system allows it). A mapped file that shrinks while it is read raises
/// SIGBUS on the bytes it lost: mappedSourceAt tells a handler which file that was.
Expected<SourceText> readSource(const std::string& path, size_t mapFrom = kMapSourcesFrom);

/// SourceText::dropPages(begin, end) for a text known by its view only: `text` a mapped
/// source's whole view (readSource's), or nothing happens (a text held in memory keeps its
/// bytes). For a reader that passes a large text once from front to back.
void dropMappedPages(std::string_view text, size_t begin, size_t end);
/// `text` is a mapped source's whole view (readSource's).
bool isMappedSource(std::string_view text);

/// Async-signal-safe: the path of the mapped source whose bytes include `addr`, or nullptr.
const char* mappedSourceAt(const void* addr);

} // namespace iso::support
