//! @file BitSet.h
//! @brief Compact sets of indices for linear-time passes over large inputs: one bit per index,
//!        with rank/select (RankedBits) or predecessor queries (PrevBits) in a few word steps.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace iso::support {

constexpr size_t kNoBit = SIZE_MAX;

/// A plain bit per index.
class Bits {
public:
  Bits() = default;
  explicit Bits(size_t n) : w_((n + 63) / 64, 0) {}
  void set(size_t i) { w_[i >> 6] |= uint64_t{1} << (i & 63); }
  bool test(size_t i) const { return (w_[i >> 6] >> (i & 63)) & 1; }
  /// The smallest set index >= i, or kNoBit.
  size_t next(size_t i) const;
  size_t bytes() const { return w_.capacity() * sizeof(uint64_t); }

protected:
  std::vector<uint64_t> w_;
};

/// Bits that are set first, then frozen: rank (set bits below an index) takes a directory
/// entry and at most 8 popcounts; select (the index of the k-th set bit) a binary search.
class RankedBits : public Bits {
public:
  RankedBits() = default;
  explicit RankedBits(size_t n) : Bits(n) {}
  /// Builds the rank directory; no set() afterwards.
  void freeze();
  /// Set bits at indices below i (i <= size).
  size_t rank(size_t i) const;
  /// Index of the set bit of rank k (k < count()).
  size_t select(size_t k) const;
  size_t count() const { return count_; }
  size_t bytes() const { return Bits::bytes() + dir_.capacity() * sizeof(uint32_t); }

private:
  static constexpr size_t kWordsPerBlock = 8;
  std::vector<uint32_t> dir_; ///< set bits before each block of 8 words
  size_t count_ = 0;
};

/// Bits with "the largest set index at or before i": a bit per index plus summary levels (one
/// bit per non-zero word of the level below), so a query takes a few word steps whatever the gaps.
class PrevBits {
public:
  PrevBits() = default;
  explicit PrevBits(size_t n);
  void set(size_t i);
  bool test(size_t i) const { return (levels_[0][i >> 6] >> (i & 63)) & 1; }
  /// The largest set index <= i, or kNoBit.
  size_t prev(size_t i) const { return prevAt(0, i); }
  size_t bytes() const;

private:
  size_t prevAt(size_t level, size_t i) const;
  std::vector<std::vector<uint64_t>> levels_;
};

} // namespace iso::support
