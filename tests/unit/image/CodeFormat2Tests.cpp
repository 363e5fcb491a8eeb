//! @file CodeFormat2Tests.cpp
//! @brief The format-2 code section: the decoder gives back exactly the code the encoder was
//!        given (any bytes), statements are recalled with their fields as changes or values,
//!        and every malformed unit is rejected at its offset.
#include <random>
#include <string>
#include <vector>

#include <doctest/doctest.h>

#include "BadImages.h"
#include "image/CodeFormat2.h"

using namespace iso;
using namespace iso::test;

namespace {

/// Encodes `code` (one procedure), decodes it again and checks that nothing changed.
std::vector<uint8_t> roundTrip(const std::vector<uint8_t>& code, std::vector<uint32_t> bounds = {}) {
  if (bounds.empty()) bounds = {0, static_cast<uint32_t>(code.size())};
  std::vector<image::CodeUnit> units;
  const std::vector<uint8_t> enc = image::encodeCode2(code, bounds, &units);
  std::vector<uint8_t> back;
  std::vector<image::CodeUnit> units2;
  const auto bad = image::decodeCode2(enc.data(), enc.size(), bounds, back, &units2);
  REQUIRE_MESSAGE(!bad, (bad ? bad->message : std::string()));
  CHECK(back == code);
  CHECK(units.size() == units2.size());
  return enc;
}

/// Decodes `enc` and returns the reason it is rejected ("" if it is not) and where.
std::string reject(const std::vector<uint8_t>& enc, uint32_t procSize, uint32_t* at = nullptr) {
  std::vector<uint8_t> out;
  const auto bad = image::decodeCode2(enc.data(), enc.size(), {0, procSize}, out);
  if (!bad) return "";
  if (at) *at = bad->at;
  return bad->message;
}

/// stmt; push.d<k> m (X); push.d0 f (F); set.f; move Pos[X] - the shape of "G01 X.. F.."
Asm& block(Asm& a, Op push, int64_t m, int64_t f) {
  return a.stmt().op(Op::G1).op(push).sleb(m).op(Op::PushD0).sleb(f).op(Op::SetF).op(Op::Move).byte(1).byte(0x00);
}

} // namespace

TEST_CASE("image: format 2 code gives back the very code it was given") {
  SUBCASE("statements of one shape are recalled: one byte for the unit, one per changed field") {
    Asm a;
    for (int i = 0; i < 100; ++i)
      block(a, Op::PushD1, 1003 + 10 * i, 200); // X100.3, X101.3, ...
    a.stmt().op(Op::End);
    const auto enc = roundTrip(a.b);
    // the first statement is written out (12 bytes), each other one takes 3: the unit code
    // and the two fields (X changes by +10 tenths, F by 0), then stmt, end
    CHECK(enc.size() == 12 + 99 * 3 + 2);
  }
  SUBCASE("a number with fewer places is recalled at the statement's places, one with more is not") {
    Asm a;
    block(a, Op::PushD1, 4503, 200); // X450.3
    block(a, Op::PushD0, 12, 200);   // X12: 120 tenths
    block(a, Op::PushD2, 1234, 200); // X12.34: written out again
    block(a, Op::PushD0, 0, 200);    // X0 (either statement)
    a.op(Op::End);
    roundTrip(a.b);
  }
  SUBCASE("jumps, WHENs and CASE keep their targets (relative)") {
    Asm a;
    for (int i = 0; i < 20; ++i) {
      const std::string n = std::to_string(i);
      a.label("top" + n).stmt().loadR(1).push(i).op(Op::CmpGt).jump(Op::JumpTrue, "top" + n);
      a.stmt().loadR(2).op(Op::Case).uleb(1).uleb(0).ref("top" + n).ref("next" + n);
      a.label("next" + n);
    }
    a.stmt().op(Op::End);
    image::Image img = mainOnly(std::move(a));
    img.constants = {1.0};
    roundTrip(img.code);
    Checked c = check(img);
    CHECK_MESSAGE(c.verified, c.err.message);
  }
  SUBCASE("bytes that are no instruction, and procedure boundaries") {
    std::vector<uint8_t> code = {0x40, 0x48, 0x40, 0xEE, 0x01, 0x02, 0x40, 0x02, 0x05, 0x62, 0x40, 0x02, 0x06, 0x62};
    roundTrip(code, {0, 2, 6, 14});
    roundTrip(code, {0, 3, 4, 20});
    roundTrip({});
  }
  SUBCASE("random bytes round trip") {
    std::mt19937 rng(7);
    for (int n = 0; n < 300; ++n) {
      std::vector<uint8_t> code(rng() % 64);
      for (auto& b : code) // mostly opcodes and small operands
        b = static_cast<uint8_t>(rng() % 3 == 0 ? rng() : 0x40 + rng() % 0x30);
      roundTrip(code, {0, static_cast<uint32_t>(code.size() / 2), static_cast<uint32_t>(code.size())});
    }
  }
}

TEST_CASE("image: format 2 code rejects malformed units at their offset") {
  // stmt; push.d0 5; dwell written out (statement 0), then a unit under test
  const std::vector<uint8_t> head = {0x40, 0x02, 0x05, 0x62};
  auto with = [&](std::vector<uint8_t> tail) {
    std::vector<uint8_t> v = head;
    v.insert(v.end(), tail.begin(), tail.end());
    return v;
  };
  uint32_t at = 0;
  CHECK(reject(with({0x80, 0x02, 0x48}), 9).empty());
  CHECK(reject(with({0xC0}), 9, &at).find("unit code 0xC0 is not used") != std::string::npos);
  CHECK(at == 4);
  CHECK(reject(with({0x81, 0x02}), 9).find("recalls statement 1") != std::string::npos);
  CHECK(reject(with({0x80}), 9).find("truncated varint (field)") != std::string::npos);
  CHECK(reject(with({0x80, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0x01}), 9)
            .find("varint too large") != std::string::npos);
  CHECK(reject(with({0x80, 0x82, 0x00}), 9).find("non-minimal varint") != std::string::npos);
  CHECK(reject(with({0xA0, 0x02}), 9).find("field mask 0x2") != std::string::npos);
  // a change that takes the mantissa out of range; a value far out of range
  CHECK(reject(with({0x80, 0x80, 0x80, 0x80, 0x80, 0x80, 0x02}), 9).find("outside -2^33..2^33") != std::string::npos);
  CHECK(reject(with({0x80, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0x7F}), 9).find("outside") !=
        std::string::npos);
  CHECK(reject(with({0x80, 0x02}), 6).find("crosses the procedure boundary at 0x0006") != std::string::npos);
  CHECK(reject(with({0x00, 0x05, 0x48}), 9).find("raw length 5") != std::string::npos);
  CHECK(reject(with({0x00, 0x00}), 9).find("raw length 0") != std::string::npos);
  CHECK(reject(with({0x7F}), 9).find("0x7F is no opcode") != std::string::npos);
  CHECK(reject(with({0x02}), 9).find("truncated") != std::string::npos);
  // relative jumps: before the code, beyond 4 GiB; a case with a bad default flag
  CHECK(reject(with({0x42, 0x40}), 9).find("jump distance -64") != std::string::npos);
  CHECK(reject(with({0x42, 0x80, 0x80, 0x80, 0x80, 0x20}), 9).find("jump distance") != std::string::npos);
  // the largest distance a sleb holds: rejected before it is added (fuzz finding, session 12)
  CHECK(reject(with({0x42, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0x00}), 9)
            .find("jump distance 9223372036854775807 leads outside") != std::string::npos);
  CHECK(reject(with({0x45, 0x01, 0x00, 0x00, 0x02}), 9).find("case default flag 2") != std::string::npos);
  CHECK(reject(with({0x45, 0x00}), 9).find("case with 0 arms") != std::string::npos);
}

TEST_CASE("image: format 2 images are much smaller than their code") {
  // 1,000 motion blocks G01 X.. Y.. with one decimal: a unit code, a mask and two changes
  Asm a;
  std::mt19937 rng(42);
  for (int i = 0; i < 1000; ++i)
    a.stmt()
        .op(Op::G1)
        .op(Op::PushD1)
        .sleb(static_cast<int64_t>(rng() % 4000) + 1)
        .op(Op::PushD1)
        .sleb(static_cast<int64_t>(rng() % 4000) + 1)
        .op(Op::Move)
        .byte(2)
        .byte(0x00)
        .byte(0x01);
  a.op(Op::End);
  const auto enc = roundTrip(a.b);
  CHECK(enc.size() < 6 * 1000 + 32);
}
