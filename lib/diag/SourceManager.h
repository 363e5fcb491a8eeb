//! @file SourceManager.h
//! @brief Owns the text of every loaded source file; maps (file, line) to the line's text.
#pragma once

#include <cstdint>
#include <deque>
#include <string>
#include <string_view>
#include <vector>

#include "support/SourceText.h"

namespace iso::diag {

struct SourceFile {
  std::string path;         ///< as given (or as found in a directory)
  support::SourceText text; ///< raw bytes (a large file is mapped, not read)
  /// Byte offset of each physical line (LF-separated), extended by lineText as far as the line
  /// it is asked for: a file no diagnostic points into never costs a pass or the memory. (Not
  /// thread-safe: the renderers and the language server run after loading, on one thread.)
  mutable std::vector<uint32_t> lineStarts;
  mutable bool indexed = false; ///< lineStarts holds every line
};

/// File ids are dense indices in load order. References stay valid (deque storage).
class SourceManager {
public:
  uint32_t add(std::string path, support::SourceText text);
  const SourceFile& file(uint32_t id) const { return files_[id]; }
  SourceFile& file(uint32_t id) { return files_[id]; }
  size_t size() const { return files_.size(); }
  /// The physical line (1-based) without its line end; empty past the end.
  std::string_view lineText(uint32_t id, uint32_t line) const;
  const std::string& path(uint32_t id) const { return files_[id].path; }

private:
  std::deque<SourceFile> files_;
};

} // namespace iso::diag
