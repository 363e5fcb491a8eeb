//! @file File.cpp
#include "support/File.h"
#include "support/Memory.h"

#include <algorithm>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <map>
#include <mutex>

#include <fmt/format.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace iso::support {

namespace fs = std::filesystem;

namespace {

/// Names of the live temporary files, for removeRegisteredTemporaries() in a signal handler.
/// Fixed storage: a handler may neither allocate nor lock.
constexpr size_t kSlots = 16;
constexpr size_t kPathMax = 4096;
struct Slot {
  std::atomic<bool> used{false};
  char path[kPathMax];
};
Slot gSlots[kSlots];

/// Blocks SIGINT and SIGTERM while a temporary file is created or renamed, so that its name is
/// always registered while it exists.
class SignalBlock {
public:
  SignalBlock() {
    sigset_t s;
    sigemptyset(&s);
    sigaddset(&s, SIGINT);
    sigaddset(&s, SIGTERM);
    sigaddset(&s, SIGHUP);
    pthread_sigmask(SIG_BLOCK, &s, &old_);
  }
  ~SignalBlock() { pthread_sigmask(SIG_SETMASK, &old_, nullptr); }
  SignalBlock(const SignalBlock&) = delete;
  SignalBlock& operator=(const SignalBlock&) = delete;

private:
  sigset_t old_;
};

bool registerTemp(const std::string& path) {
  if (path.size() >= kPathMax) return false;
  for (auto& s : gSlots) {
    bool expected = false;
    if (s.used.load() || !s.used.compare_exchange_strong(expected, true)) continue;
    std::memcpy(s.path, path.c_str(), path.size() + 1);
    return true;
  }
  return false;
}

void unregisterTemp(const std::string& path) {
  for (auto& s : gSlots)
    if (s.used.load() && path == s.path) {
      s.path[0] = 0;
      s.used.store(false);
      return;
    }
}

std::string reason(int err) {
  switch (err) {
  case ENOENT: return "no such file or directory";
  case EACCES: return "permission denied";
  case EISDIR: return "is a directory";
  case ENOSPC: return "no space left on the device";
  case EROFS: return "read-only file system";
  default: return std::strerror(err);
  }
}

mode_t newFileMode() {
  static const mode_t mode = [] {
    mode_t mask = ::umask(0);
    ::umask(mask);
    return static_cast<mode_t>(0666 & ~mask);
  }();
  return mode;
}

/// A stream input (isStreamInput) as far as it has been read: its descriptor stays open until
/// its end, so that a first look at a few bytes (is it an image?) loses nothing for the read
/// of the whole that follows.
struct StreamEntry {
  std::string bytes;
  int fd = -1;       ///< open while there is more to read
  bool end = false;  ///< the whole stream is in `bytes`
  std::string error; ///< a read failed (then `bytes` is all there will be)
};
struct StreamCache {
  std::mutex mutex;
  std::map<std::string, StreamEntry> byPath;
};
StreamCache& streams() {
  static StreamCache cache;
  return cache;
}

std::string tooLarge() { return fmt::format("is larger than {} MiB, the limit of an input", kMaxInputBytes >> 20); }

/// Reads more of `e` until it holds `want` bytes or its end (never more than kMaxInputBytes + 1:
/// enough for readFile to tell that it is too large).
void fill(StreamEntry& e, size_t want) {
  want = std::min(want, kMaxInputBytes + 1);
  char buf[1 << 16];
  while (!e.end && e.error.empty() && e.bytes.size() < want) {
    ssize_t n = ::read(e.fd, buf, std::min(sizeof buf, want - e.bytes.size()));
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) e.error = reason(errno);
    if (n <= 0) e.end = true;
    if (n > 0) e.bytes.append(buf, static_cast<size_t>(n));
  }
  if ((e.end || !e.error.empty()) && e.fd >= 0) {
    ::close(e.fd);
    e.fd = -1;
  }
}

/// The first `maxBytes` bytes of a stream input, read as far as needed.
Expected<std::string> prefixOf(StreamEntry& e, const std::string& path, size_t maxBytes, bool& whole) {
  fill(e, maxBytes == SIZE_MAX ? SIZE_MAX : maxBytes + 1);
  if (!e.error.empty()) return Error{path, e.error};
  whole = e.end && e.bytes.size() <= maxBytes;
  return e.bytes.size() <= maxBytes ? e.bytes : e.bytes.substr(0, maxBytes);
}

} // namespace

bool isStreamInput(const std::string& path) {
  {
    std::lock_guard<std::mutex> lock(streams().mutex);
    if (streams().byPath.count(path)) return true;
  }
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0 && !S_ISREG(st.st_mode) && !S_ISDIR(st.st_mode);
}

void setStreamInput(const std::string& name, std::string bytes) {
  std::lock_guard<std::mutex> lock(streams().mutex);
  StreamEntry& e = streams().byPath[name];
  if (e.fd >= 0) ::close(e.fd);
  e = StreamEntry{std::move(bytes), -1, true, {}};
}

Expected<std::string> readStreamBounded(std::istream& in, const std::string& name) {
  std::string out;
  char buf[1 << 16];
  while (in) {
    in.read(buf, sizeof buf);
    const auto n = static_cast<size_t>(in.gcount());
    if (out.size() + n > kMaxInputBytes) return Error{name, tooLarge()};
    out.append(buf, n);
  }
  if (in.bad()) return Error{name, "cannot read standard input"};
  return out;
}

Expected<std::string> readFilePrefix(const std::string& path, size_t maxBytes, bool& whole) {
  std::string out;
  std::unique_lock<std::mutex> lock(streams().mutex);
  if (auto it = streams().byPath.find(path); it != streams().byPath.end())
    return prefixOf(it->second, path, maxBytes, whole);
  lock.unlock();
  int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    return Error{path, reason(errno)};
  }
  struct stat st {};
  if (::fstat(fd, &st) != 0 || S_ISDIR(st.st_mode)) {
    const std::string why = S_ISDIR(st.st_mode) ? "is a directory" : reason(errno);
    ::close(fd);
    return Error{path, why};
  }
  if (!S_ISREG(st.st_mode)) { // a pipe or a device: read once, as far as needed, and kept
    lock.lock();
    auto [it, inserted] = streams().byPath.try_emplace(path);
    if (inserted)
      it->second.fd = fd;
    else
      ::close(fd); // another thread opened it first: its bytes are the stream's
    return prefixOf(it->second, path, maxBytes, whole);
  }
  whole = false;
  if (S_ISREG(st.st_mode) && st.st_size > 0) {
    // The size is known: the text is read straight into, not through a buffer.
    const size_t size = std::min(static_cast<size_t>(st.st_size), maxBytes);
    out.reserve(size);
    adviseHugePages(out.data(), size); // before the first write
    out.resize(size);
  }
  // One loop: into the text while its known size lasts, then through a buffer (a file of
  // unknown size, or one that grew meanwhile). One that shrank ends short.
  char buf[1 << 16];
  size_t got = 0;
  while (got < maxBytes) {
    const bool inText = got < out.size();
    char* to = inText ? out.data() + got : buf;
    const size_t room = inText ? out.size() - got : std::min(sizeof buf, maxBytes - got);
    ssize_t n = ::read(fd, to, room);
    if (n < 0) {
      if (errno == EINTR) continue;
      const std::string why = reason(errno);
      ::close(fd);
      return Error{path, why};
    }
    if (n == 0) {
      whole = true;
      break;
    }
    if (!inText) out.append(buf, static_cast<size_t>(n));
    got += static_cast<size_t>(n);
  }
  ::close(fd);
  out.resize(got);
  return out;
}

Expected<std::string> readFile(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode) && static_cast<uint64_t>(st.st_size) > kMaxInputBytes)
    return Error{path, tooLarge()}; // refused before a byte is read
  bool whole = false;
  auto read = readFilePrefix(path, kMaxInputBytes, whole);
  if (read && !whole) return Error{path, tooLarge()}; // a stream, or a file that grew meanwhile
  return read;
}

std::optional<FileId> fileId(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return std::nullopt;
  return FileId{static_cast<uint64_t>(st.st_dev), static_cast<uint64_t>(st.st_ino)};
}

Status AtomicFile::open() {
  discard();
  fs::path target(target_);
  std::string dir = target.parent_path().string();
  std::string name = target.filename().string();
  if (name.empty() || name == "." || name == "..") {
    return Status::failure("is a directory");
  }
  struct stat st {};
  if (::stat(target_.c_str(), &st) == 0 && S_ISDIR(st.st_mode)) {
    return Status::failure("is a directory");
  }
  if (::stat(target_.c_str(), &st) == 0 && !S_ISREG(st.st_mode)) {
    // a device or a pipe (/dev/null, a FIFO): written directly, never replaced by a file
    direct_ = true;
    out_.open(target_, std::ios::binary);
    if (!out_) {
      direct_ = false;
      return Status::failure("cannot open the file for writing");
    }
    return {};
  }
  std::string pattern = (dir.empty() ? std::string() : dir + "/") + "." + name + ".tmp-XXXXXX";
  {
    SignalBlock block;
    std::vector<char> buf(pattern.begin(), pattern.end());
    buf.push_back(0);
    int fd = ::mkstemp(buf.data());
    if (fd < 0) {
      return Status::failure("cannot create the file: " + reason(errno));
    }
    ::close(fd);
    tmp_ = buf.data();
    if (!registerTemp(tmp_)) {
      ::unlink(tmp_.c_str());
      tmp_.clear();
      return Status::failure("cannot create the file: too many output files");
    }
  }
  buffer_.resize(1 << 16);
  out_.rdbuf()->pubsetbuf(buffer_.data(), static_cast<std::streamsize>(buffer_.size()));
  out_.open(tmp_, std::ios::binary | std::ios::trunc);
  if (!out_) {
    discard();
    return Status::failure("cannot create the file");
  }
  return {};
}

Status AtomicFile::commit() {
  if (direct_) {
    direct_ = false;
    out_.close();
    if (out_.fail()) return Status::failure("write error");
    return {};
  }
  if (tmp_.empty()) {
    return Status::failure("the file was not created");
  }
  out_.close();
  if (out_.fail()) {
    discard();
    return Status::failure("write error");
  }
  struct stat st {};
  mode_t mode = ::stat(target_.c_str(), &st) == 0 ? (st.st_mode & 07777) : newFileMode();
  ::chmod(tmp_.c_str(), mode);
  SignalBlock block;
  if (::rename(tmp_.c_str(), target_.c_str()) != 0) {
    Status failed = Status::failure("cannot replace the file: " + reason(errno));
    ::unlink(tmp_.c_str());
    unregisterTemp(tmp_);
    tmp_.clear();
    return failed;
  }
  unregisterTemp(tmp_);
  tmp_.clear();
  return {};
}

void AtomicFile::discard() {
  if (direct_) {
    direct_ = false;
    out_.close();
    return;
  }
  if (tmp_.empty()) return;
  if (out_.is_open()) out_.close();
  SignalBlock block;
  ::unlink(tmp_.c_str());
  unregisterTemp(tmp_);
  tmp_.clear();
}

Status writeFileAtomically(const std::string& path, std::string_view bytes) {
  AtomicFile f(path);
  if (Status opened = f.open(); !opened) return opened;
  f.stream().write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  return f.commit();
}

int removeRegisteredTemporaries() {
  int n = 0;
  for (auto& s : gSlots)
    if (s.used.load() && s.path[0] != 0) {
      if (::unlink(s.path) == 0) ++n;
      s.path[0] = 0;
      s.used.store(false);
    }
  return n;
}

} // namespace iso::support
