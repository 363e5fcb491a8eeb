//! @file Crc32.h
//! @brief CRC-32 (IEEE 802.3, as in zlib and PNG) for the image checksum.
#pragma once

#include <cstddef>
#include <cstdint>

namespace iso::image {

/// CRC-32 with the reflected polynomial 0xEDB88320, initial value 0xFFFFFFFF and a final XOR
/// with 0xFFFFFFFF (zlib's crc32()). Incremental: pass the previous result as `crc` to continue;
/// start with 0. crc32("123456789") == 0xCBF43926.
uint32_t crc32(const uint8_t* data, size_t size, uint32_t crc = 0);

} // namespace iso::image
