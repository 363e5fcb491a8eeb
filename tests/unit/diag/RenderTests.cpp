//! @file RenderTests.cpp
//! @brief Diagnostic rendering details: SARIF columns are UTF-16 code units (columnKind), while
//!        the diagnostics themselves count bytes.
#include <doctest/doctest.h>

#include "diag/Render.h"

using iso::diag::utf16Column;

TEST_CASE("sarif: byte columns become UTF-16 columns") {
  // ASCII: the same column
  CHECK(utf16Column("G01 X10", 5) == 5);
  CHECK(utf16Column("G01 X10", 1) == 1);
  // "è" is 2 bytes and 1 unit: the X after "; caffè " is byte column 10, unit column 9
  CHECK(utf16Column("; caff\xC3\xA8 X", 10) == 9);
  // a 4-byte code point (U+1F600) is 2 units
  CHECK(utf16Column("\xF0\x9F\x98\x80X", 5) == 3);
  // Latin-1 bytes that are not UTF-8 count one unit each
  CHECK(utf16Column("caff\xE8 X", 7) == 7);
  // a column just past the end of the line (an end column) keeps its distance
  CHECK(utf16Column("\xC3\xA8", 3) == 2);
  CHECK(utf16Column("ab", 5) == 5);
}
