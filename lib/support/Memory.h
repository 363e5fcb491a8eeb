//! @file Memory.h
//! @brief Hints about large buffers to the operating system.
#pragma once

#include <cstddef>

namespace iso::support {

/// Asks for transparent huge pages over the 2 MiB-aligned part of [p, p + bytes) before it is
/// first written (madvise(MADV_HUGEPAGE) on Linux), so that filling a large buffer takes a page
/// fault per 2 MiB instead of one per 4 KiB. Only a hint: nothing happens elsewhere, for
/// buffers under 4 MiB, or if the system says no.
void adviseHugePages(void* p, size_t bytes);

/// v.reserve(n), then adviseHugePages over the room it got: for a large vector filled once from
/// front to back whose final size is about known.
template <class Vector> void reserveHuge(Vector& v, size_t n) {
  v.reserve(n);
  adviseHugePages(v.data(), v.capacity() * sizeof(*v.data()));
}

/// Gives the whole pages inside [p, p + bytes) back to the system (madvise(MADV_DONTNEED) on
/// Linux): their bytes are gone (zero if read again). For a large buffer whose content was
/// copied elsewhere and that is about to be freed, so that the copy and the original are not
/// both resident. The first and last partial pages, and the page at `p` (where an allocator
/// may keep its records), stay. Nothing happens for buffers under 1 MiB, or elsewhere.
void releasePages(void* p, size_t bytes);

/// Gives the memory the allocator holds free back to the operating system (glibc: malloc_trim),
/// after a long-lived process has freed a large amount: a hint, nothing else changes.
void returnFreedMemory();

} // namespace iso::support
