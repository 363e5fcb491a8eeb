//! @file FindingsTests.cpp
//! @brief Bugs found by the fuzz targets (tests/fuzz/findings/README.md), one test each.
#include <doctest/doctest.h>

#include "TestUtil.h"

using namespace iso;

namespace {
bool has(const std::vector<diag::Diagnostic>& ds, const char* code) {
  for (const auto& d : ds)
    if (std::string(diag::info(d.code).code) == code) return true;
  return false;
}
} // namespace

TEST_CASE("finding: z32 M2 in a WHEN body is E212, like M30 (isocc exited 70)") {
  auto d = test::lintZ32("WHEN $aa_iw[X] > 10 DO\nM2\nCANCEL\nG01 X100 F100\nM30\n");
  CHECK(has(d, "E212"));
  // sidac: M2 is a plain PLC sequence, allowed in a body
  auto s = test::lintText("WHEN $aa_iw[X] > 10 DO\nM2\nCANCEL\nG01 X100 F100\nM30\n");
  CHECK_FALSE(has(s, "E212"));
}

TEST_CASE("finding: a $ continuation right after a system variable or axis name joins cleanly") {
  CHECK(test::lintText("$aa_out$\n[0] = 1\nM30\n").empty());
  CHECK(test::lintText("R1 = $aa_iw$\n[X]\nM30\n").empty());
  CHECK(test::lintText("G01 Pos[X$\n]=5 F100\nM30\n").empty());
  CHECK(test::lintText("G01 X$\n=5 F100\nM30\n").empty());
  // and splits elsewhere keep working
  CHECK(test::lintText("$aa_o$\nut[0] = 1\nG01 X1$\n0 F100\nM30\n").empty());
}
