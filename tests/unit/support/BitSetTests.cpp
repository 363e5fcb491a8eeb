//! @file BitSetTests.cpp
//! @brief support/BitSet: rank, select and predecessor agree with a plain scan.
#include <doctest/doctest.h>

#include <random>
#include <vector>

#include "support/BitSet.h"

using namespace iso::support;

TEST_CASE("bitset: rank and select agree with counting, over sparse and dense sets") {
  for (size_t n : {size_t{1}, size_t{63}, size_t{64}, size_t{512}, size_t{513}, size_t{5000}}) {
    for (unsigned density : {1u, 10u, 90u}) {
      CAPTURE(n);
      CAPTURE(density);
      std::mt19937 rng(static_cast<unsigned>(n * 100 + density));
      RankedBits b(n);
      std::vector<size_t> members;
      for (size_t i = 0; i < n; ++i)
        if (rng() % 100 < density) {
          b.set(i);
          members.push_back(i);
        }
      b.freeze();
      CHECK(b.count() == members.size());
      size_t below = 0;
      for (size_t i = 0; i <= n; ++i) {
        CHECK(b.rank(i) == below);
        if (i < n && b.test(i)) ++below;
      }
      for (size_t k = 0; k < members.size(); ++k)
        CHECK(b.select(k) == members[k]);
    }
  }
}

TEST_CASE("bitset: prev finds the nearest set index at or before, across empty stretches") {
  const size_t n = 300000; // three summary levels
  PrevBits b(n);
  std::vector<size_t> members = {5, 64, 65, 4095, 4096, 70000, 262143, 262144, 299999};
  for (size_t m : members)
    b.set(m);
  CHECK(b.prev(4) == kNoBit);
  std::mt19937 rng(3);
  for (int q = 0; q < 20000; ++q) {
    const size_t i = rng() % n;
    size_t expect = kNoBit;
    for (size_t m : members)
      if (m <= i) expect = m;
    CAPTURE(i);
    CHECK(b.prev(i) == expect);
  }
  for (size_t m : members) {
    CHECK(b.test(m));
    CHECK(b.prev(m) == m);
  }
  CHECK_FALSE(b.test(6));
}
