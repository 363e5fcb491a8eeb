//! @file Bytes.h
//! @brief Binary data: a bounded cursor that reads little-endian integers, f64 and strict
//!        LEB128 (minimal encodings only, with a byte limit), and a writer that appends them.
//!        The image reader, the instruction decoder and the image writer share these.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace iso::support {

/// The outcome of reading a LEB128 number.
enum class LebError : uint8_t {
  None,
  Truncated,  ///< the data ends inside the number
  TooLong,    ///< the number has more bytes than the limit allows
  TooLarge,   ///< the value does not fit in 64 bits
  NonMinimal, ///< a shorter encoding of the same value exists (value and position are set)
};

/// Little-endian value of 4 bytes at p.
inline uint32_t loadU32(const uint8_t* p) {
  return static_cast<uint32_t>(p[0]) | static_cast<uint32_t>(p[1]) << 8 | static_cast<uint32_t>(p[2]) << 16 |
         static_cast<uint32_t>(p[3]) << 24;
}
inline uint16_t loadU16(const uint8_t* p) { return static_cast<uint16_t>(p[0] | p[1] << 8); }

/// A 64-bit FNV-1a hash, fed a byte or a little-endian word at a time: the fingerprints of
/// SARIF findings and of image line tables, and the label index's slots.
class Fnv1a {
public:
  void byte(uint8_t b) { h_ = (h_ ^ b) * 0x100000001b3u; }
  void word(uint64_t v) {
    for (int k = 0; k < 8; ++k, v >>= 8)
      byte(static_cast<uint8_t>(v));
  }
  uint64_t value() const { return h_; }

private:
  uint64_t h_ = 0xcbf29ce484222325u;
};

/// No limit on the bytes of a LEB128 number but the 64 bits of its value.
constexpr size_t kAnyLebLength = SIZE_MAX;

/// Reads [begin, end) of `data` front to back; never reads outside it. A failed read leaves
/// the position where it was (except NonMinimal, which reads the number).
class ByteCursor {
public:
  ByteCursor(const uint8_t* data, size_t begin, size_t end) : d_(data), pos_(begin), end_(end) {}

  size_t pos() const { return pos_; }
  size_t end() const { return end_; }
  size_t left() const { return end_ - pos_; }
  const uint8_t* data() const { return d_; }
  /// Skips n bytes; false (position unchanged) if fewer are left.
  bool skip(size_t n) {
    if (left() < n) return false;
    pos_ += n;
    return true;
  }

  bool u8(uint8_t& v) {
    if (pos_ >= end_) return false;
    v = d_[pos_++];
    return true;
  }
  bool u16(uint16_t& v) {
    if (left() < 2) return false;
    v = loadU16(d_ + pos_);
    pos_ += 2;
    return true;
  }
  bool u32(uint32_t& v) {
    if (left() < 4) return false;
    v = loadU32(d_ + pos_);
    pos_ += 4;
    return true;
  }
  bool f64(double& v);
  /// An unsigned LEB128 number of at most `maxBytes` bytes. Checks in this order, byte after
  /// byte: Truncated, TooLong, TooLarge; then NonMinimal (the last byte is 0x00 after others).
  LebError uleb(uint64_t& v, size_t maxBytes = kAnyLebLength) {
    if (pos_ < end_ && maxBytes > 0 && d_[pos_] < 0x80) { // one byte: the common case
      v = d_[pos_++];
      return LebError::None;
    }
    return ulebLong(v, maxBytes);
  }
  /// A signed LEB128 number of at most `maxBytes` bytes, sign-extended from the last one.
  /// NonMinimal: the last byte only repeats the sign of the one before.
  LebError sleb(int64_t& v, size_t maxBytes = kAnyLebLength) {
    if (pos_ < end_ && maxBytes > 0 && d_[pos_] < 0x80) {
      const uint8_t b = d_[pos_++];
      v = b & 0x40 ? static_cast<int64_t>(b) - 0x80 : b;
      return LebError::None;
    }
    if (end_ - pos_ >= 2 && maxBytes >= 2 && d_[pos_ + 1] < 0x80) { // two bytes
      const uint8_t b0 = d_[pos_], b1 = d_[pos_ + 1];
      const int64_t r = (b0 & 0x7F) | static_cast<int64_t>(b1) << 7;
      pos_ += 2;
      v = b1 & 0x40 ? r - (int64_t{1} << 14) : r;
      const bool repeatsSign = (b1 == 0 && !(b0 & 0x40)) || (b1 == 0x7F && (b0 & 0x40));
      return repeatsSign ? LebError::NonMinimal : LebError::None;
    }
    return slebLong(v, maxBytes);
  }

private:
  LebError ulebLong(uint64_t& v, size_t maxBytes);
  LebError slebLong(int64_t& v, size_t maxBytes);

  const uint8_t* d_;
  size_t pos_;
  size_t end_;
};

/// Appends to a byte vector; every number in the encoding ByteCursor reads (LEB128 minimal).
class ByteWriter {
public:
  explicit ByteWriter(std::vector<uint8_t>& out) : b_(out) {}

  size_t pos() const { return b_.size(); }
  void u8(uint8_t v) { b_.push_back(v); }
  void u16(uint16_t v);
  void u32(uint32_t v);
  void f64(double v);
  void uleb(uint64_t v);
  void sleb(int64_t v);
  void bytes(const uint8_t* p, size_t n) { b_.insert(b_.end(), p, p + n); }
  /// Overwrites the 4 bytes at `at` (written before) with v.
  void patchU32(size_t at, uint32_t v);

private:
  std::vector<uint8_t>& b_;
};

/// Bytes of the minimal LEB128 encodings.
size_t ulebLength(uint64_t v);
size_t slebLength(int64_t v);

} // namespace iso::support
