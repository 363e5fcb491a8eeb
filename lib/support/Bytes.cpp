//! @file Bytes.cpp
//! @brief The byte cursor, strict LEB128 and the byte writer.
#include "support/Bytes.h"

#include <cstring>

namespace iso::support {

bool ByteCursor::f64(double& v) {
  if (left() < 8) return false;
  uint64_t bits = 0;
  for (int i = 7; i >= 0; --i)
    bits = bits << 8 | d_[pos_ + static_cast<size_t>(i)];
  std::memcpy(&v, &bits, sizeof v);
  pos_ += 8;
  return true;
}

LebError ByteCursor::ulebLong(uint64_t& v, size_t maxBytes) {
  uint64_t r = 0;
  unsigned shift = 0;
  size_t n = 0;
  uint8_t b = 0;
  do {
    if (n == left()) return LebError::Truncated;
    if (n == maxBytes) return LebError::TooLong;
    b = d_[pos_ + n++];
    const uint64_t bits = b & 0x7F;
    if (shift >= 64 || (shift > 0 && (bits >> (64 - shift)) != 0)) return LebError::TooLarge;
    r |= bits << shift;
    shift += 7;
  } while (b & 0x80);
  v = r;
  pos_ += n;
  return b == 0 && n > 1 ? LebError::NonMinimal : LebError::None;
}

LebError ByteCursor::slebLong(int64_t& v, size_t maxBytes) {
  uint64_t r = 0;
  unsigned shift = 0;
  size_t n = 0;
  uint8_t b = 0, prev = 0;
  do {
    if (n == left()) return LebError::Truncated;
    if (n == maxBytes) return LebError::TooLong;
    prev = b;
    b = d_[pos_ + n++];
    const uint64_t bits = b & 0x7F;
    // the 10th byte holds bit 63; its other bits must repeat it (the sign)
    if (shift >= 64 || (shift == 63 && bits != 0 && bits != 0x7F)) return LebError::TooLarge;
    r |= bits << shift;
    shift += 7;
  } while (b & 0x80);
  if (shift < 64 && (b & 0x40)) r |= ~uint64_t{0} << shift;
  v = static_cast<int64_t>(r);
  pos_ += n;
  const bool repeatsSign = (b == 0 && !(prev & 0x40)) || (b == 0x7F && (prev & 0x40));
  return n > 1 && repeatsSign ? LebError::NonMinimal : LebError::None;
}

void ByteWriter::u16(uint16_t v) {
  b_.push_back(static_cast<uint8_t>(v));
  b_.push_back(static_cast<uint8_t>(v >> 8));
}

void ByteWriter::u32(uint32_t v) {
  for (int i = 0; i < 4; ++i)
    b_.push_back(static_cast<uint8_t>(v >> (8 * i)));
}

void ByteWriter::f64(double v) {
  uint64_t bits;
  std::memcpy(&bits, &v, sizeof bits);
  for (int i = 0; i < 8; ++i)
    b_.push_back(static_cast<uint8_t>(bits >> (8 * i)));
}

void ByteWriter::uleb(uint64_t v) {
  do {
    uint8_t b = v & 0x7F;
    v >>= 7;
    if (v) b |= 0x80;
    b_.push_back(b);
  } while (v);
}

void ByteWriter::sleb(int64_t v) {
  bool more = true;
  while (more) {
    uint8_t b = v & 0x7F;
    v >>= 7; // arithmetic shift: the sign stays
    if ((v == 0 && !(b & 0x40)) || (v == -1 && (b & 0x40)))
      more = false;
    else
      b |= 0x80;
    b_.push_back(b);
  }
}

void ByteWriter::patchU32(size_t at, uint32_t v) {
  for (size_t i = 0; i < 4; ++i)
    b_[at + i] = static_cast<uint8_t>(v >> (8 * i));
}

size_t ulebLength(uint64_t v) {
  size_t n = 1;
  for (; v >= 0x80; v >>= 7)
    ++n;
  return n;
}

size_t slebLength(int64_t v) {
  size_t n = 1;
  for (; v < -64 || v > 63; v >>= 7)
    ++n;
  return n;
}

} // namespace iso::support
