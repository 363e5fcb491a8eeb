//! @file File.h
//! @brief Files as the tools must treat them: read whole, identified by device and inode (any
//!        spelling), and written whole or not at all (a temporary file in the same folder,
//!        renamed over the target when complete; removed again on failure or interruption).
#pragma once

#include <cstdint>
#include <fstream>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "support/Expected.h"

namespace iso::support {

/// Reads a whole file; an error's `where` is the path and its message a short reason ("no such
/// file or directory", "is a directory", "permission denied", ...).
Expected<std::string> readFile(const std::string& path);
/// The first `maxBytes` bytes of a file (all of it when shorter: `whole` tells which).
Expected<std::string> readFilePrefix(const std::string& path, size_t maxBytes, bool& whole);

/// The identity of an existing file (device and inode, after following links).
struct FileId {
  uint64_t dev = 0;
  uint64_t ino = 0;
  bool operator==(const FileId&) const = default;
};
std::optional<FileId> fileId(const std::string& path);

/// An output file written atomically. open() creates `.NAME.tmp-XXXXXX` beside the target
/// (a target that exists and is not a regular file, such as /dev/null or a FIFO, is written in
/// place instead);
/// commit() closes it, gives it the target's permissions (or the umask's for a new file) and
/// renames it over the target. A file not committed is removed by discard() or the destructor;
/// while it exists its name is registered for removeRegisteredTemporaries() (signal handlers).
class AtomicFile {
public:
  explicit AtomicFile(std::string target) : target_(std::move(target)) {}
  ~AtomicFile() { discard(); }
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  bool open(std::string& why);
  std::ostream& stream() { return out_; }
  bool isOpen() const { return direct_ || !tmp_.empty(); }
  bool commit(std::string& why);
  void discard();
  const std::string& target() const { return target_; }

private:
  std::string target_;
  std::string tmp_;
  bool direct_ = false; ///< the target is a device or a pipe: written in place
  std::ofstream out_;
  std::vector<char> buffer_;
};

/// Writes `bytes` to `path` through an AtomicFile.
bool writeFileAtomically(const std::string& path, std::string_view bytes, std::string& why);

/// Async-signal-safe: unlinks every temporary file of an AtomicFile not yet committed or
/// discarded. Returns how many were removed.
int removeRegisteredTemporaries();

} // namespace iso::support
