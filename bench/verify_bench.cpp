//! @file verify_bench.cpp
//! @brief How long verifying an image takes and how much memory it needs, against references
//!        measured in the same run (bench/verify_bench.sh runs it on a 1M-block image).
//!
//! Usage: iso_verify_bench IMAGE [RUNS]
//! Prints CPU times (best of RUNS, default 5) of: reading the file; one pass over its bytes
//! (CRC-32: the floor of any check that looks at every byte); the reader (bytes -> Image); the
//! verifier; and the verifier's memory: the heap it allocates at its peak (counted by this
//! program's operator new) and the growth of the peak resident set, both beside the image
//! size. Exit 1 when the image does not verify.
#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <new>
#include <string>

#include "image/Crc32.h"
#include "image/ImageReader.h"
#include "image/ImageVerifier.h"
#include "support/File.h"

namespace {

std::atomic<size_t> gLive{0}, gPeak{0};

void noteAlloc(size_t n) {
  const size_t now = gLive += n;
  size_t peak = gPeak.load();
  while (now > peak && !gPeak.compare_exchange_weak(peak, now)) {
  }
}

double cpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + static_cast<double>(ts.tv_nsec) * 1e-9;
}

/// Peak resident set (VmHWM) in KiB; resettable through /proc/self/clear_refs.
long peakRssKiB() {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("VmHWM:", 0) == 0) return std::strtol(line.c_str() + 6, nullptr, 10);
  return -1;
}
bool resetPeakRss() {
  std::ofstream out("/proc/self/clear_refs");
  out << "5";
  return static_cast<bool>(out.flush());
}

template <class F> double best(int runs, F&& f) {
  double b = 1e30;
  for (int i = 0; i < runs; ++i) {
    const double t0 = cpuSeconds();
    f();
    b = std::min(b, cpuSeconds() - t0);
  }
  return b;
}

} // namespace

// Heap accounting: every allocation of this program carries its size in front.
void* operator new(size_t n) {
  auto* p = static_cast<size_t*>(std::malloc(n + sizeof(std::max_align_t)));
  if (!p) throw std::bad_alloc();
  *p = n;
  noteAlloc(n);
  return reinterpret_cast<char*>(p) + sizeof(std::max_align_t);
}
void operator delete(void* p) noexcept {
  if (!p) return;
  auto* h = reinterpret_cast<size_t*>(static_cast<char*>(p) - sizeof(std::max_align_t));
  gLive -= *h;
  std::free(h);
}
void operator delete(void* p, size_t) noexcept { operator delete(p); }

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: iso_verify_bench IMAGE [RUNS]\n");
    return 2;
  }
  const std::string path = argv[1];
  const int runs = argc > 2 ? std::max(1, std::atoi(argv[2])) : 5;
  std::string text;
  const double tRead = best(runs, [&] {
    auto read = iso::support::readFile(path);
    if (!read) {
      std::fprintf(stderr, "%s: %s\n", path.c_str(), read.error().message.c_str());
      std::exit(2);
    }
    text = std::move(*read);
  });
  const auto* bytes = reinterpret_cast<const uint8_t*>(text.data());
  uint32_t crc = 0;
  const double tCrc = best(runs, [&] { crc = iso::image::crc32(bytes, text.size()); });
  iso::image::Image img;
  iso::image::ImageError err;
  iso::image::Layout layout;
  bool read = false;
  const double tReader = best(runs, [&] { read = iso::image::readImage(bytes, text.size(), img, err, &layout); });
  if (!read) {
    std::fprintf(stderr, "%s+0x%04X: %s\n", path.c_str(), err.offset, err.message.c_str());
    return 1;
  }
  bool ok = false;
  const double tVerify = best(runs, [&] { ok = iso::image::verifyImage(img, err, &layout); });
  if (!ok) {
    std::fprintf(stderr, "%s+0x%04X: %s\n", path.c_str(), err.offset, err.message.c_str());
    return 1;
  }
  // memory of one more verification: heap above what is live now, and peak RSS growth
  const bool rssReset = resetPeakRss();
  const long rssBefore = peakRssKiB();
  const size_t heapBefore = gLive.load();
  gPeak = heapBefore;
  (void)iso::image::verifyImage(img, err, &layout);
  const size_t heapPeak = gPeak.load() - heapBefore;
  const long rssGrowth = peakRssKiB() - rssBefore;

  const double mib = 1024.0 * 1024.0;
  std::printf("image: %s, %.1f MiB (code %.1f MiB, %zu line entries), CRC 0x%08X\n", path.c_str(),
              static_cast<double>(text.size()) / mib, static_cast<double>(img.code.size()) / mib, img.lines.size(),
              crc);
  std::printf("cpu seconds, best of %d:\n", runs);
  std::printf("  read the file      %8.4f\n", tRead);
  std::printf("  CRC-32 of it       %8.4f  (reference: one pass over the bytes)\n", tCrc);
  std::printf("  reader             %8.4f  = %5.2f x the reference\n", tReader, tReader / tCrc);
  std::printf("  verifier           %8.4f  = %5.2f x the reference\n", tVerify, tVerify / tCrc);
  std::printf("verifier memory: heap peak %.2f MiB = %.3f x the image size", static_cast<double>(heapPeak) / mib,
              static_cast<double>(heapPeak) / static_cast<double>(text.size()));
  if (rssReset) std::printf("; peak RSS growth %.2f MiB", static_cast<double>(rssGrowth) / 1024.0);
  std::printf("\n");
  return 0;
}
