//! @file BytesTests.cpp
//! @brief support/Bytes: the cursor stays in bounds, LEB128 is strict (minimal, limited),
//!        the writer and the cursor agree.
#include <doctest/doctest.h>

#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "support/Bytes.h"

using namespace iso::support;

namespace {

std::vector<uint8_t> uleb(uint64_t v) {
  std::vector<uint8_t> b;
  ByteWriter(b).uleb(v);
  return b;
}
std::vector<uint8_t> sleb(int64_t v) {
  std::vector<uint8_t> b;
  ByteWriter(b).sleb(v);
  return b;
}

LebError readU(const std::vector<uint8_t>& b, uint64_t& v, size_t& used, size_t maxBytes = kAnyLebLength) {
  ByteCursor c(b.data(), 0, b.size());
  LebError e = c.uleb(v, maxBytes);
  used = c.pos();
  return e;
}
LebError readS(const std::vector<uint8_t>& b, int64_t& v, size_t& used, size_t maxBytes = kAnyLebLength) {
  ByteCursor c(b.data(), 0, b.size());
  LebError e = c.sleb(v, maxBytes);
  used = c.pos();
  return e;
}

} // namespace

TEST_CASE("bytes: fixed-size reads are little-endian and never pass the end") {
  const std::vector<uint8_t> b = {0x01, 0x02, 0x03, 0x04, 0x05, 0x06, 0x07};
  ByteCursor c(b.data(), 1, b.size());
  uint16_t h = 0;
  uint32_t w = 0;
  uint8_t x = 0;
  REQUIRE(c.u16(h));
  CHECK(h == 0x0302);
  REQUIRE(c.u32(w));
  CHECK(w == 0x07060504);
  CHECK(c.left() == 0);
  CHECK_FALSE(c.u8(x));
  CHECK(c.pos() == 7);
  ByteCursor d(b.data(), 5, 7);
  CHECK_FALSE(d.u32(w)); // 2 bytes left
  CHECK(d.pos() == 5);
  CHECK_FALSE(d.skip(3));
  CHECK(d.skip(2));
  CHECK(d.left() == 0);
}

TEST_CASE("bytes: f64 round trips through the writer bit for bit") {
  std::vector<uint8_t> b;
  ByteWriter w(b);
  const double values[] = {0.0, -0.0, 1.5, -2.25e300, std::numeric_limits<double>::denorm_min()};
  for (double v : values)
    w.f64(v);
  CHECK(b.size() == 8 * std::size(values));
  ByteCursor c(b.data(), 0, b.size());
  for (double v : values) {
    double r = 1;
    REQUIRE(c.f64(r));
    CHECK(std::memcmp(&r, &v, sizeof v) == 0);
  }
  uint32_t at = 0;
  w.u32(0);
  w.patchU32(b.size() - 4, 0xA1B2C3D4);
  ByteCursor p(b.data(), b.size() - 4, b.size());
  REQUIRE(p.u32(at));
  CHECK(at == 0xA1B2C3D4);
}

TEST_CASE("bytes: uleb round trips and has the minimal length") {
  const uint64_t values[] = {0, 1, 127, 128, 255, 16383, 16384, 0xFFFFFFFFu, 1ull << 35, ~uint64_t{0}};
  for (uint64_t v : values) {
    CAPTURE(v);
    auto b = uleb(v);
    CHECK(b.size() == ulebLength(v));
    uint64_t r = 0;
    size_t used = 0;
    CHECK(readU(b, r, used) == LebError::None);
    CHECK(r == v);
    CHECK(used == b.size());
  }
  CHECK(uleb(127) == std::vector<uint8_t>{0x7F});
  CHECK(uleb(128) == std::vector<uint8_t>{0x80, 0x01});
}

TEST_CASE("bytes: sleb round trips and has the minimal length") {
  const int64_t values[] = {0,
                            1,
                            -1,
                            63,
                            64,
                            -64,
                            -65,
                            8191,
                            -8192,
                            8192,
                            1ll << 34,
                            -(1ll << 34),
                            std::numeric_limits<int64_t>::max(),
                            std::numeric_limits<int64_t>::min()};
  for (int64_t v : values) {
    CAPTURE(v);
    auto b = sleb(v);
    CHECK(b.size() == slebLength(v));
    int64_t r = 0;
    size_t used = 0;
    CHECK(readS(b, r, used) == LebError::None);
    CHECK(r == v);
    CHECK(used == b.size());
  }
  CHECK(sleb(-1) == std::vector<uint8_t>{0x7F});
  CHECK(sleb(64) == std::vector<uint8_t>{0xC0, 0x00});
  CHECK(sleb(-128) == std::vector<uint8_t>{0x80, 0x7F});
}

TEST_CASE("bytes: non-minimal LEB128 is reported with its value") {
  uint64_t u = 9;
  int64_t s = 9;
  size_t used = 0;
  CHECK(readU({0x80, 0x00}, u, used) == LebError::NonMinimal);
  CHECK(u == 0);
  CHECK(used == 2);
  CHECK(readU({0xFF, 0x80, 0x00}, u, used) == LebError::NonMinimal);
  CHECK(u == 127);
  CHECK(readU({0x00}, u, used) == LebError::None);
  CHECK(readS({0xFF, 0x7F}, s, used) == LebError::NonMinimal); // -1 in two bytes
  CHECK(s == -1);
  CHECK(readS({0x80, 0x00}, s, used) == LebError::NonMinimal);
  CHECK(readS({0xC0, 0x00}, s, used) == LebError::None); // +64 needs the second byte
  CHECK(readS({0x80, 0x7F}, s, used) == LebError::None); // -128 too
  CHECK(s == -128);
}

TEST_CASE("bytes: truncated, too long and too large LEB128 leave the cursor in place") {
  uint64_t u = 0;
  int64_t s = 0;
  size_t used = 9;
  CHECK(readU({}, u, used) == LebError::Truncated);
  CHECK(used == 0);
  CHECK(readU({0x80, 0x80}, u, used) == LebError::Truncated);
  CHECK(used == 0);
  CHECK(readS({0xFF}, s, used) == LebError::Truncated);
  // the limit counts bytes; the end of the data is found first
  CHECK(readU({0x80, 0x80, 0x80, 0x80, 0x80, 0x01}, u, used, 5) == LebError::TooLong);
  CHECK(readU({0x80, 0x80, 0x80, 0x80, 0x80}, u, used, 5) == LebError::Truncated);
  CHECK(readU({0x80, 0x80, 0x80, 0x80, 0x01}, u, used, 5) == LebError::None);
  CHECK(u == 1ull << 28);
  CHECK(readS({0x80, 0x80, 0x80, 0x80, 0x80, 0x01}, s, used, 5) == LebError::TooLong);
  CHECK(used == 0);
  // 64 bits at most
  std::vector<uint8_t> big(9, 0xFF);
  big.push_back(0x01);
  CHECK(readU(big, u, used) == LebError::None);
  CHECK(u == ~uint64_t{0});
  big.back() = 0x02;
  CHECK(readU(big, u, used) == LebError::TooLarge);
  std::vector<uint8_t> eleven(10, 0x80);
  eleven.push_back(0x00);
  CHECK(readU(eleven, u, used) == LebError::TooLarge);
  std::vector<uint8_t> sbig(9, 0x80);
  sbig.push_back(0x3F);
  CHECK(readS(sbig, s, used) == LebError::TooLarge);
}

TEST_CASE("bytes: LEB128 of up to 5 bytes is minimal exactly when the writer gives its length") {
  std::mt19937 rng(7);
  for (int i = 0; i < 20000; ++i) {
    const size_t n = 1 + rng() % 5;
    std::vector<uint8_t> b(n);
    for (size_t k = 0; k < n; ++k)
      b[k] = static_cast<uint8_t>(rng() | (k + 1 < n ? 0x80 : 0));
    b[n - 1] &= 0x7F;
    if (rng() % 4 == 0) b[n - 1] = rng() % 2 ? 0x00 : 0x7F; // often a sign byte
    uint64_t u = 0;
    int64_t s = 0;
    size_t used = 0;
    LebError eu = readU(b, u, used, 5);
    CHECK(used == n);
    CHECK((eu == LebError::NonMinimal) == (uleb(u).size() != n));
    LebError es = readS(b, s, used, 5);
    CHECK(used == n);
    CHECK((es == LebError::NonMinimal) == (sleb(s).size() != n));
  }
}
