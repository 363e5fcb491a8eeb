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
  bool skip(size_t n);

  bool u8(uint8_t& v);
  bool u16(uint16_t& v);
  bool u32(uint32_t& v);
  bool f64(double& v);
  /// An unsigned LEB128 number of at most `maxBytes` bytes. Checks in this order, byte after
  /// byte: Truncated, TooLong, TooLarge; then NonMinimal (the last byte is 0x00 after others).
  LebError uleb(uint64_t& v, size_t maxBytes = kAnyLebLength);
  /// A signed LEB128 number of at most `maxBytes` bytes, sign-extended from the last one.
  /// NonMinimal: the last byte only repeats the sign of the one before.
  LebError sleb(int64_t& v, size_t maxBytes = kAnyLebLength);

private:
  const uint8_t* d_;
  size_t pos_;
  size_t end_;
};

/// Little-endian value of 4 bytes at p.
inline uint32_t loadU32(const uint8_t* p) {
  return static_cast<uint32_t>(p[0]) | static_cast<uint32_t>(p[1]) << 8 | static_cast<uint32_t>(p[2]) << 16 |
         static_cast<uint32_t>(p[3]) << 24;
}
inline uint16_t loadU16(const uint8_t* p) { return static_cast<uint16_t>(p[0] | p[1] << 8); }

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
