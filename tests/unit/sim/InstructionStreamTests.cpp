//! @file InstructionStreamTests.cpp
//! @brief The interpreter's instructions decoded window by window: any window size and any
//!        order of access give the instructions of one window holding the whole program.
#include <algorithm>
#include <random>

#include <doctest/doctest.h>

#include "SimTestUtil.h"
#include "sim/InstructionStream.h"

using namespace iso;
using namespace iso::test;
using sim::Ins;
using sim::InstructionStream;

namespace {

/// Three procedures with jumps both ways, a CASE, a WHEN, calls and statements of every size.
image::VerifiedImage programImage() {
  std::string main = "R1 = 0\nL: R1 = R1 + 1\nG01 F100 X=R1 Y=2*R1\nIF R1 < 5 GOTOB L\n"
                     "WHEN $aa_iw[X] > 3 DO $aa_out[1] = 1\nG01 X9\n"
                     "CASE R1 OF 4 GOTOF Four 5 GOTOF Five DEFAULT GOTOF Other\nFour: G00 Y4\nFive: G00 Y5\n"
                     "GOTOF Done\nOther: G00 Y9\nDone: SubA\nSubB\n";
  for (int i = 0; i < 40; ++i)
    main += "X" + std::to_string(i) + " Y" + std::to_string(i % 7) + "\n";
  main += "M30\n";
  SetResult sr = lintFiles({{"main.mpf", main},
                            {"suba.spf", "PROC SubA SAVE\nR2 = 0\nA: R2 = R2 + 1\nIF R2 < 3 GOTOB A\nM17\n"},
                            {"subb.spf", "PROC SubB SAVE\nCASE R1 OF 1 GOTOF One\nX7\nOne: M17\n"}},
                           builtin(), builtin().dialect);
  REQUIRE(sr.loaded);
  std::string diags;
  image::Image img = compileSet(*sr.set, builtin(), &diags);
  REQUIRE_MESSAGE(diags.empty(), diags);
  image::ImageError err;
  std::optional<image::VerifiedImage> v = image::verifyImage(std::move(img), err);
  REQUIRE_MESSAGE(v.has_value(), err.message);
  return std::move(*v);
}

void checkSame(const Ins& a, const Ins& b, uint32_t i) {
  INFO("instruction " << i);
  CHECK(a.op == b.op);
  CHECK(a.a8 == b.a8);
  CHECK(a.b8 == b.b8);
  if (a.op != image::Op::Case) CHECK(a.a == b.a); // a case's: the place of its arms in its window
  CHECK(a.b == b.b);
  CHECK(a.c == b.c);
}

} // namespace

TEST_CASE("instruction stream: small windows, read in any order, hold the instructions of one whole window") {
  const image::VerifiedImage img = programImage();
  const InstructionStream whole(img, 1u << 20, 1);
  REQUIRE(img->procs.size() == 3);
  REQUIRE(whole.size() == img.instructions() + 3); // and a fall-off sentinel per procedure
  // each procedure ends with its sentinel, just before the next one's entry
  for (size_t p = 0; p < 3; ++p) {
    const uint32_t last = p + 1 < 3 ? whole.procEntry[p + 1] - 1 : static_cast<uint32_t>(whole.size() - 1);
    CHECK(static_cast<uint8_t>(whole[last].op) == sim::kOpFallOff);
    CHECK(whole[whole.procEntry[p]].op != static_cast<image::Op>(sim::kOpFallOff));
  }
  std::vector<uint32_t> order(whole.size());
  for (uint32_t i = 0; i < order.size(); ++i)
    order[i] = i;
  std::mt19937 rng(7);
  for (const uint32_t window : {1u, 3u, 7u, 64u}) {
    for (const size_t slots : {size_t{1}, size_t{2}, size_t{5}}) {
      CAPTURE(window);
      CAPTURE(slots);
      const InstructionStream small(img, window, slots);
      CHECK(small.procEntry == whole.procEntry);
      for (int pass = 0; pass < 2; ++pass) {
        for (uint32_t i : order) {
          const Ins a = small[i];
          const Ins b = whole[i];
          checkSame(a, b, i);
          if (a.op == image::Op::Case)
            for (uint32_t k = 0; k < a.b; ++k) {
              const sim::CaseArm x = small.arms(i)[a.a + k];
              const sim::CaseArm y = whole.arms(i)[b.a + k];
              CHECK(x.value == y.value);
              CHECK(x.target == y.target);
            }
        }
        std::shuffle(order.begin(), order.end(), rng);
      }
    }
  }
}

TEST_CASE("instruction stream: jump targets are statement or instruction indices inside their procedure") {
  const image::VerifiedImage img = programImage();
  const InstructionStream prog(img, 5, 2);
  size_t jumps = 0, cases = 0;
  for (uint32_t i = 0; i < prog.size(); ++i) {
    const Ins in = prog[i];
    const uint32_t p = prog.procOf(i);
    const uint32_t end = p + 1 < prog.procEntry.size() ? prog.procEntry[p + 1] : static_cast<uint32_t>(prog.size());
    auto inside = [&](uint32_t t) { return t >= prog.procEntry[p] && t < end; };
    if (in.op == image::Op::Jump || in.op == image::Op::JumpFalse || in.op == image::Op::JumpTrue) {
      ++jumps;
      CHECK(inside(in.a));
    }
    if (in.op == image::Op::Case) {
      ++cases;
      for (uint32_t k = 0; k < in.b; ++k) {
        const uint32_t t = prog.arms(i)[in.a + k].target;
        CHECK(inside(t));
        CHECK(prog[t].op == image::Op::Stmt); // a label's statement
      }
    }
  }
  CHECK(jumps >= 2); // the two loops
  CHECK(cases == 2);
}
