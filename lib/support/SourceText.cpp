//! @file SourceText.cpp
#include "support/SourceText.h"

#include <atomic>
#include <cstdint>
#include <cstring>

#include "support/File.h"

#if defined(__linux__)
#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>
#define ISO_MAP_SOURCES 1
#else
#define ISO_MAP_SOURCES 0
#endif

namespace iso::support {

namespace {

/// The mapped sources, for mappedSourceAt in a SIGBUS handler: fixed storage, since a handler
/// may neither allocate nor lock. A source that finds no free entry is read, not mapped.
constexpr int kMapSlots = 64;
constexpr size_t kMapPathMax = 4096;
struct MapSlot {
  std::atomic<bool> used{false};
  std::atomic<uintptr_t> begin{0};
  std::atomic<size_t> size{0};
  char path[kMapPathMax];
};
MapSlot gMapSlots[kMapSlots];

int registerMapping(const std::string& path, const char* begin, size_t size) {
  if (path.size() >= kMapPathMax) return -1;
  for (int i = 0; i < kMapSlots; ++i) {
    MapSlot& s = gMapSlots[i];
    bool expected = false;
    if (s.used.load() || !s.used.compare_exchange_strong(expected, true)) continue;
    std::memcpy(s.path, path.c_str(), path.size() + 1);
    s.size.store(size);
    s.begin.store(reinterpret_cast<uintptr_t>(begin));
    return i;
  }
  return -1;
}

void unregisterMapping(int slot) {
  MapSlot& s = gMapSlots[slot];
  s.begin.store(0);
  s.size.store(0);
  s.used.store(false);
}

#if ISO_MAP_SOURCES
/// The whole pages inside [begin, end) of the mapping [base, base + size) leave memory.
void dropRange(const char* base, size_t size, size_t begin, size_t end) {
  if (end > size || begin >= end) return;
  const auto page = static_cast<size_t>(::sysconf(_SC_PAGESIZE));
  const size_t first = (begin + page - 1) / page * page, last = end / page * page;
  if (first < last) ::madvise(const_cast<char*>(base) + first, last - first, MADV_DONTNEED);
}
#endif

} // namespace

SourceText& SourceText::operator=(const SourceText& o) {
  if (this != &o) {
    std::string copy(o.view());
    unmap();
    owned_ = std::move(copy);
  }
  return *this;
}

SourceText& SourceText::operator=(SourceText&& o) noexcept {
  if (this != &o) {
    unmap();
    std::string().swap(owned_); // its storage goes: a move from a short string would keep it
    owned_ = std::move(o.owned_);
    mapped_ = o.mapped_;
    mappedSize_ = o.mappedSize_;
    slot_ = o.slot_;
    inode_ = o.inode_;
    mtimeNs_ = o.mtimeNs_;
    o.mapped_ = nullptr;
    o.mappedSize_ = 0;
    o.slot_ = -1;
    o.owned_.clear();
  }
  return *this;
}

void SourceText::dropPages() const {
#if ISO_MAP_SOURCES
  if (mapped_) ::madvise(const_cast<char*>(mapped_), mappedSize_, MADV_DONTNEED);
#endif
}

void SourceText::dropPages(size_t begin, size_t end) const {
#if ISO_MAP_SOURCES
  if (mapped_) dropRange(mapped_, mappedSize_, begin, end);
#else
  (void)begin;
  (void)end;
#endif
}

bool isMappedSource(std::string_view text) {
#if ISO_MAP_SOURCES
  if (text.empty()) return false;
  for (const MapSlot& s : gMapSlots)
    if (s.used.load() && s.begin.load() == reinterpret_cast<uintptr_t>(text.data()) && s.size.load() == text.size())
      return true;
#else
  (void)text;
#endif
  return false;
}

void dropMappedPages(std::string_view text, size_t begin, size_t end) {
#if ISO_MAP_SOURCES
  if (isMappedSource(text)) dropRange(text.data(), text.size(), begin, end);
#else
  (void)text;
  (void)begin;
  (void)end;
#endif
}

bool SourceText::changedOnDisk(const std::string& path) const {
#if ISO_MAP_SOURCES
  struct stat st {};
  if (!mapped_ || ::stat(path.c_str(), &st) != 0 || static_cast<uint64_t>(st.st_ino) != inode_) return false;
  return static_cast<size_t>(st.st_size) != mappedSize_ ||
         static_cast<int64_t>(st.st_mtim.tv_sec) * 1000000000 + st.st_mtim.tv_nsec != mtimeNs_;
#else
  (void)path;
  return false;
#endif
}

void SourceText::unmap() {
#if ISO_MAP_SOURCES
  if (!mapped_) return;
  if (slot_ >= 0) unregisterMapping(slot_);
  ::munmap(const_cast<char*>(mapped_), mappedSize_);
  mapped_ = nullptr;
  mappedSize_ = 0;
  slot_ = -1;
#endif
}

Expected<SourceText> readSource(const std::string& path, size_t mapFrom) {
#if ISO_MAP_SOURCES
  struct stat st {};
  const long page = ::sysconf(_SC_PAGESIZE);
  // (A file over kMaxInputBytes is not mapped: readFile refuses it.)
  if (::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode) && page > 0 &&
      static_cast<uint64_t>(st.st_size) >= mapFrom && static_cast<uint64_t>(st.st_size) <= kMaxInputBytes &&
      static_cast<uint64_t>(st.st_size) % static_cast<uint64_t>(page) != 0) {
    // (A size that fills its last page leaves no NUL after the last byte: such a file is read.)
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    struct stat now {};
    if (fd >= 0 && ::fstat(fd, &now) == 0 && now.st_ino == st.st_ino && now.st_size == st.st_size) {
      const auto size = static_cast<size_t>(now.st_size);
      // MAP_POPULATE: the pages of the page cache are mapped at once, not faulted in one by one.
      void* p = ::mmap(nullptr, size, PROT_READ, MAP_PRIVATE | MAP_POPULATE, fd, 0);
      ::close(fd);
      if (p != MAP_FAILED) {
        SourceText t;
        t.mapped_ = static_cast<const char*>(p);
        t.mappedSize_ = size;
        t.inode_ = static_cast<uint64_t>(now.st_ino);
        t.mtimeNs_ = static_cast<int64_t>(now.st_mtim.tv_sec) * 1000000000 + now.st_mtim.tv_nsec;
        t.slot_ = registerMapping(path, t.mapped_, size);
        if (t.slot_ >= 0) return t;
        // no entry left for the handler: read instead (t unmaps itself)
      }
    } else if (fd >= 0) {
      ::close(fd);
    }
  }
#else
  (void)mapFrom;
#endif
  auto read = readFile(path);
  if (!read) return read.error();
  return SourceText(std::move(*read));
}

const char* mappedSourceAt(const void* addr) {
  const auto a = reinterpret_cast<uintptr_t>(addr);
  for (MapSlot& s : gMapSlots) {
    if (!s.used.load()) continue;
    const uintptr_t b = s.begin.load();
    const size_t n = s.size.load();
    if (b != 0 && a >= b && a - b < n) return s.path;
  }
  return nullptr;
}

} // namespace iso::support
