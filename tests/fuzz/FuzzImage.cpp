//! @file FuzzImage.cpp
//! @brief Fuzz target: bytes -> ImageReader -> ImageVerifier -> listings. Any input must be
//!        rejected with an offset inside the input, or verify; a verified format-1 image must
//!        re-encode to the same bytes (format 1 is canonical), a verified format-2 image to
//!        bytes that read back to the same code and re-encode to themselves (format 2 may code
//!        a statement in several ways; the writer always picks one); nothing may crash.
//!        Each input runs twice: as given, and with the total size and the CRC fixed up, so
//!        that the fuzzer gets past the checksum and explores the sections.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "image/Disassembler.h"
#include "image/ImageReader.h"
#include "image/ImageVerifier.h"
#include "image/ImageWriter.h"

namespace {

void one(const uint8_t* data, size_t size) {
  iso::image::Image img;
  iso::image::ImageError err;
  iso::image::Layout layout;
  if (!iso::image::readImage(data, size, img, err, &layout)) {
    if (err.offset > size || err.message.empty()) std::abort();
    return;
  }
  bool ok = iso::image::verifyImage(img, err, &layout);
  if (!ok && (err.offset >= size || err.message.empty())) std::abort();
  (void)iso::image::disassemble(img);
  (void)iso::image::hexDump(img);
  if (ok) {
    std::vector<uint8_t> again = iso::image::writeImage(img);
    if (img.formatVersion == 1) {
      // unknown optional sections are dropped on re-encoding; otherwise the bytes must agree
      if (again.size() == size && !std::equal(again.begin(), again.end(), data)) std::abort();
      return;
    }
    iso::image::Image back;
    if (!iso::image::readImage(again, back, err) || back.code != img.code) std::abort();
    if (iso::image::writeImage(back) != again) std::abort();
  }
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  one(data, size);
  if (size >= iso::image::kHeaderSize && size < (1u << 20)) {
    std::vector<uint8_t> fixed(data, data + size);
    iso::image::patchU32(fixed, iso::image::kOffTotalSize, static_cast<uint32_t>(size));
    iso::image::fixCrc(fixed);
    one(fixed.data(), fixed.size());
  }
  return 0;
}
