//! @file GoTargetTests.cpp
//! @brief The z32 GO rule (SPEC §4.7): target shapes and the line a target finds, with the
//!        examples of seed 001.
#include <string_view>

#include <doctest/doctest.h>

#include "frontend/GoTarget.h"

using iso::frontend::findGoLine;
using iso::frontend::findGoLineFrom;
using iso::frontend::isGoTargetText;

TEST_CASE("GO target: the shape [%][/]N<number as written>") {
  for (std::string_view ok : {"N12", "%N1", "/N12", "%/N3", "N132,5", "N132.5", "N0", "N.5", "N7."})
    CHECK_MESSAGE(isGoTargetText(ok), ok);
  for (std::string_view bad : {"", "N", "12", "LOOP", "GON12", "N1,2,3", "N1.2.3", "N12X", "/%N1", "%%N1", "n12",
                               " N12", "N12 ", "N1-N2", "N,"})
    CHECK_MESSAGE(!isGoTargetText(bad), bad);
}

TEST_CASE("GO target: the seed's examples find their lines") {
  CHECK(findGoLine("G0X0\nN12 G41 X1\n", "N12").line == 2);
  CHECK(findGoLine("G0X0\n%N1G41\n", "%N1").line == 2);
  CHECK(findGoLine("G0X0\n/N12G41\n", "/N12").line == 2);
  std::string_view comma = "G0\nN132,5HA=1\n";
  CHECK(findGoLine(comma, "N132,5").line == 2);
  CHECK(findGoLine(comma, "N132.5").line == 0);
  std::string_view dot = "G0\nN132.5M3\n";
  CHECK(findGoLine(dot, "N132.5").line == 2);
  CHECK(findGoLine(dot, "N132,5").line == 0);
}

TEST_CASE("GO target: the next character may not continue the number") {
  CHECK(findGoLine("N12 X1\nN1.5 X2\nN1,5\n", "N1").line == 0);
  CHECK(findGoLine("N12 X1\nN1.5 X2\nN1X3\n", "N1").line == 3);
  CHECK(findGoLine("N1", "N1").line == 1); // the line is exactly the target, no line end
  CHECK(findGoLine("N1;x\n", "N1").line == 1);
  CHECK(findGoLine("N1 \n", "N1").line == 1);
  // %N1 is not found by N1: the line must begin with the target's characters.
  CHECK(findGoLine("%N1 X1\n", "N1").line == 0);
  CHECK(findGoLine("n12 X1\n", "N12").line == 0); // characters compare exactly
}

TEST_CASE("GO target: the first line from the top wins") {
  std::string_view src = "G0\nN5 X1\nN6\nN5 X2\n";
  CHECK(findGoLine(src, "N5").line == 2);
  CHECK(findGoLineFrom(src, "N5", 3) == 4);
  CHECK(findGoLineFrom(src, "N5", 2) == 2);
  CHECK(findGoLineFrom(src, "N5", 5) == 0);
  CHECK(findGoLineFrom(src, "N6", 1) == 3);
}

TEST_CASE("GO target: blanks before N are never found, the first such line is reported") {
  auto m = findGoLine("G0\n  N12 X1\n\tN12\n", "N12");
  CHECK(m.line == 0);
  CHECK(m.blankCandidate == 2);
  m = findGoLine("G0\n  N12 X1\nN12 X2\n", "N12");
  CHECK(m.line == 3);
  CHECK(m.blankCandidate == 2);
  m = findGoLine("N12\n", "N12");
  CHECK(m.blankCandidate == 0);
  CHECK(findGoLine("   \n", "N1").blankCandidate == 0);
}

TEST_CASE("GO target: line ends \\n, \\r\\n and a lone \\r count one line each") {
  CHECK(findGoLine("G0\r\nG1\r\nN3\r\n", "N3").line == 3);
  CHECK(findGoLine("G0\rG1\rN3", "N3").line == 3);
  CHECK(findGoLine("\n\nN3", "N3").line == 3);
  CHECK(findGoLine("N3\n", "").line == 0);
  CHECK(findGoLine("", "N3").line == 0);
}
