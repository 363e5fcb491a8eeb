//! @file BitSet.cpp
//! @brief Rank/select and predecessor queries on bit sets.
#include "support/BitSet.h"

#include <algorithm>
#include <bit>

namespace iso::support {

namespace {
/// Bits 0..b of a word.
uint64_t upTo(size_t b) { return b >= 63 ? ~uint64_t{0} : (uint64_t{2} << b) - 1; }
size_t top(uint64_t w) { return 63 - static_cast<size_t>(std::countl_zero(w)); }
} // namespace

size_t Bits::next(size_t i) const {
  size_t w = i >> 6;
  if (w >= w_.size()) return kNoBit;
  uint64_t m = w_[w] & (~uint64_t{0} << (i & 63));
  while (m == 0) {
    if (++w == w_.size()) return kNoBit;
    m = w_[w];
  }
  return (w << 6) + static_cast<size_t>(std::countr_zero(m));
}

void RankedBits::freeze() {
  dir_.assign(w_.size() / kWordsPerBlock + 1, 0);
  size_t n = 0;
  for (size_t i = 0; i < w_.size(); ++i) {
    if (i % kWordsPerBlock == 0) dir_[i / kWordsPerBlock] = static_cast<uint32_t>(n);
    n += static_cast<size_t>(std::popcount(w_[i]));
  }
  if (w_.size() % kWordsPerBlock == 0) dir_.back() = static_cast<uint32_t>(n);
  count_ = n;
}

size_t RankedBits::rank(size_t i) const {
  const size_t word = i >> 6, block = word / kWordsPerBlock;
  size_t n = dir_[block];
  for (size_t k = block * kWordsPerBlock; k < word; ++k)
    n += static_cast<size_t>(std::popcount(w_[k]));
  if ((i & 63) != 0) n += static_cast<size_t>(std::popcount(w_[word] & ((uint64_t{1} << (i & 63)) - 1)));
  return n;
}

size_t RankedBits::select(size_t k) const {
  // the last block with fewer than k + 1 set bits before it
  const auto it = std::upper_bound(dir_.begin(), dir_.end(), static_cast<uint32_t>(k));
  size_t word = static_cast<size_t>(it - dir_.begin() - 1) * kWordsPerBlock;
  size_t left = k - dir_[word / kWordsPerBlock];
  for (;; ++word) {
    const auto c = static_cast<size_t>(std::popcount(w_[word]));
    if (left < c) break;
    left -= c;
  }
  uint64_t w = w_[word];
  for (; left > 0; --left)
    w &= w - 1; // drop the lowest set bits
  return (word << 6) + static_cast<size_t>(std::countr_zero(w));
}

PrevBits::PrevBits(size_t n) {
  size_t words = (n + 63) / 64;
  levels_.emplace_back(std::max<size_t>(words, 1), 0);
  while (words > 64) {
    words = (words + 63) / 64;
    levels_.emplace_back(words, 0);
  }
}

void PrevBits::set(size_t i) {
  for (auto& level : levels_) {
    level[i >> 6] |= uint64_t{1} << (i & 63);
    i >>= 6;
  }
}

size_t PrevBits::prevAt(size_t level, size_t i) const {
  const auto& v = levels_[level];
  const size_t w = i >> 6;
  if (const uint64_t m = v[w] & upTo(i & 63)) return (w << 6) + top(m);
  if (w == 0) return kNoBit;
  size_t pw = kNoBit; // the last non-zero word before w
  if (level + 1 < levels_.size()) {
    pw = prevAt(level + 1, w - 1);
  } else {
    for (size_t j = w; j-- > 0;)
      if (v[j]) {
        pw = j;
        break;
      }
  }
  return pw == kNoBit ? kNoBit : (pw << 6) + top(v[pw]);
}

size_t PrevBits::bytes() const {
  size_t n = 0;
  for (const auto& l : levels_)
    n += l.capacity() * sizeof(uint64_t);
  return n;
}

} // namespace iso::support
