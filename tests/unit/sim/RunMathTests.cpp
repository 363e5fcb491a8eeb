//! @file RunMathTests.cpp
//! @brief The pure run math of isosim: arithmetic, §3.2 comparisons, integer indexes.
#include <cmath>
#include <limits>
#include <stdexcept>

#include <doctest/doctest.h>

#include "sim/FaultOf.h"
#include "sim/RunMath.h"
#include "sim/TraceWriter.h"

using namespace iso::sim;
using iso::image::Op;

using iso::sim::test::faultOf;

TEST_CASE("run math: arithmetic") {
  CHECK(arith(Op::Add, 2, 3) == 5);
  CHECK(arith(Op::Sub, 2, 3) == -1);
  CHECK(arith(Op::Mul, 2, 3) == 6);
  CHECK(arith(Op::Div, 3, 2) == 1.5);
  CHECK(faultOf([] { arith(Op::Div, 1, 0); }) == "division by zero (1 / 0)");
  CHECK(faultOf([] { arith(Op::Mul, 1e300, 1e300); }).rfind("arithmetic overflow: ", 0) == 0);
  const double inf = std::numeric_limits<double>::infinity();
  CHECK(faultOf([&] { arith(Op::Sub, inf, inf); }).rfind("arithmetic gives no number (NaN): ", 0) == 0);
  CHECK_THROWS_AS(arith(Op::CmpEq, 1, 2), std::logic_error);
}

TEST_CASE("run math: comparisons are equal within a relative 1e-12") {
  CHECK(cmpEqual(1.0, 1.0 + 1e-13));
  CHECK_FALSE(cmpEqual(1.0, 1.0 + 1e-11));
  CHECK(cmpEqual(0.0, 0.0));
  CHECK(cmpClass(1, 2) == -1);
  CHECK(cmpClass(2, 1) == 1);
  CHECK(cmpClass(0.1 + 0.2, 0.3) == 0);
  CHECK(compare(Op::CmpEq, 0.1 + 0.2, 0.3) == 1.0);
  CHECK(compare(Op::CmpNe, 0.1 + 0.2, 0.3) == 0.0);
  CHECK(compare(Op::CmpGe, 1, 1) == 1.0);
  CHECK(compare(Op::CmpGt, 1, 1) == 0.0);
  CHECK(compare(Op::CmpLe, 1, 2) == 1.0);
  CHECK(compare(Op::CmpLt, 2, 1) == 0.0);
  CHECK_THROWS_AS(compare(Op::Add, 1, 2), std::logic_error);
}

TEST_CASE("run math: integer indexes") {
  CHECK(intIndex(3, 1, 10, "R") == 3);
  CHECK(intIndex(3 + 1e-10, 1, 10, "R") == 3);
  CHECK(faultOf([] { intIndex(2.5, 1, 10, "R"); }) == "R index 2.5 is not an integer");
  CHECK(faultOf([] { intIndex(11, 1, 10, "R"); }) == "R index 11 is outside 1..10");
  CHECK(faultOf([] { intIndex(std::nan(""), 1, 10, "E"); }).rfind("E index ", 0) == 0);
}

TEST_CASE("run math: faults carry their status") {
  try {
    emergency("stop");
  } catch (const Fault& f) {
    CHECK(f.status == Status::Emergency);
    CHECK(f.what == "stop");
  }
  CHECK_THROWS_AS(internal("x"), std::logic_error);
}

TEST_CASE("sim: readNumber reads formatNumber's text back without the C library's locale") {
  CHECK(readNumber("1.5") == 1.5);
  CHECK(readNumber("-0.000001") == -0.000001);
  CHECK(readNumber("4294967296.000001") == 4294967296.000001);
  CHECK(readNumber("inf") == std::numeric_limits<double>::infinity());
  CHECK(readNumber("-inf") == -std::numeric_limits<double>::infinity());
  CHECK(std::isnan(readNumber("nan")));
  CHECK(std::isnan(readNumber("")));
  CHECK(std::isnan(readNumber("-")));
  CHECK(std::isnan(readNumber("x1")));
  CHECK(std::signbit(readNumber("-0")));
  for (double v : {0.1, 2.000003, -7.25, 123456.789012, 1e-6})
    CHECK(readNumber(formatNumber(v)) == v);
}
