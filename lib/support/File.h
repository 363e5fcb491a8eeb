//! @file File.h
//! @brief Files as the tools must treat them: read whole, identified by device and inode (any
//!        spelling), and written whole or not at all (a temporary file in the same folder,
//!        renamed over the target when complete; removed again on failure or interruption).
#pragma once

#include <cstdint>
#include <fstream>
#include <istream>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "support/Expected.h"

namespace iso::support {

/// The largest input the tools read: a program source or an image. A pipe or a device is read
/// up to one byte more, so that /dev/zero ends at once with a clear error.
inline constexpr size_t kMaxInputBytes = size_t{256} << 20;

/// Inputs that can be read only once — pipes, FIFOs, process substitutions (`<(cat p.mpf)`),
/// devices, standard input — are read once, as far as a reader of the functions below asks
/// (never more than kMaxInputBytes + 1 bytes), and every later read of the same path gets those
/// bytes (and reads on where the last one stopped). True
/// when `path` is such an input (read already, or an existing file that is neither a regular
/// file nor a directory).
bool isStreamInput(const std::string& path);
/// Registers the bytes of a stream read elsewhere (standard input, under a name such as
/// "<stdin>"): readFile(name) returns them from now on.
void setStreamInput(const std::string& name, std::string bytes);
/// Reads all of `in` once, at most kMaxInputBytes (the error names the limit), for
/// setStreamInput.
Expected<std::string> readStreamBounded(std::istream& in, const std::string& name);

/// Reads a whole file of at most kMaxInputBytes; an error's `where` is the path and its message a
/// short reason ("no such file or directory", "is a directory", "permission denied", "is larger
/// than 256 MiB, the limit of an input", ...).
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

  Status open();
  std::ostream& stream() { return out_; }
  bool isOpen() const { return direct_ || !tmp_.empty(); }
  Status commit();
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
Status writeFileAtomically(const std::string& path, std::string_view bytes);

/// Async-signal-safe: unlinks every temporary file of an AtomicFile not yet committed or
/// discarded. Returns how many were removed.
int removeRegisteredTemporaries();

} // namespace iso::support
