//! @file Memory.cpp
//! @brief Hints about large buffers to the operating system.
#include "support/Memory.h"

#include <cstdint>

#if defined(__GLIBC__)
#include <malloc.h>
#endif
#if defined(__linux__)
#include <sys/mman.h>
#include <unistd.h>
#endif

namespace iso::support {

void adviseHugePages([[maybe_unused]] void* p, [[maybe_unused]] size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  constexpr uintptr_t kHugePage = uintptr_t{2} << 20;
  if (bytes < 2 * kHugePage) return;
  const auto begin = reinterpret_cast<uintptr_t>(p);
  const uintptr_t first = (begin + kHugePage - 1) & ~(kHugePage - 1);
  const uintptr_t last = (begin + bytes) & ~(kHugePage - 1);
  if (last > first) ::madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);
#endif
}

void releasePages([[maybe_unused]] void* p, [[maybe_unused]] size_t bytes) {
#if defined(__linux__) && defined(MADV_DONTNEED)
  const long pageSize = ::sysconf(_SC_PAGESIZE);
  if (pageSize <= 0) return;
  const auto kPage = static_cast<uintptr_t>(pageSize);
  if (bytes < (uintptr_t{1} << 20)) return;
  const auto begin = reinterpret_cast<uintptr_t>(p);
  const uintptr_t first = ((begin + kPage - 1) & ~(kPage - 1)) + kPage;
  const uintptr_t last = (begin + bytes) & ~(kPage - 1);
  if (last > first) ::madvise(reinterpret_cast<void*>(first), last - first, MADV_DONTNEED);
#endif
}

void returnFreedMemory() {
#if defined(__GLIBC__)
  ::malloc_trim(0);
#endif
}

} // namespace iso::support
