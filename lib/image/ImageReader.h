//! @file ImageReader.h
//! @brief Bytes -> Image. The bytes are untrusted: every structural rule of man/isoimage.5 is
//!        checked (magic, version, sizes, CRC, the section table, each section's encoding)
//!        before anything is allocated from a count. Meaning is checked by ImageVerifier.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "image/Image.h"
#include "image/ImageWriter.h"

namespace iso::image {

/// Why an image was rejected: the byte offset in the image and the reason.
struct ImageError {
  uint32_t offset = 0;
  std::string message;
};

/// Decodes an image of format 1 or 2 (out.formatVersion says which). On failure returns false
/// with `err` set; `out` is then unspecified. Accepts exactly the canonical encoding the writer
/// produces (minimal LEB128, sections in id order without gaps), plus unknown sections marked
/// optional, which are skipped; in format 2 any coding of the code section that decodes
/// (CodeFormat2.h), whose decoded code goes to out.code. Fills `layout` (file offsets of
/// sections and records) when given. Never reads outside [data, data + size).
bool readImage(const uint8_t* data, size_t size, Image& out, ImageError& err, Layout* layout = nullptr);

inline bool readImage(const std::vector<uint8_t>& bytes, Image& out, ImageError& err, Layout* layout = nullptr) {
  return readImage(bytes.data(), bytes.size(), out, err, layout);
}

} // namespace iso::image
