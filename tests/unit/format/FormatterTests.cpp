//! @file FormatterTests.cpp
//! @brief isofmt's library: the default style, what is kept byte for byte, the z32 line
//!        starts, renumbering with GO targets and its refusals, the [format] settings.
#include <doctest/doctest.h>

#include <string>

#include "driver/Settings.h"
#include "format/Formatter.h"
#include "format/LineText.h"
#include "format/Renumber.h"

using namespace iso;

namespace {

format::FormatOptions options(machine::Dialect d = machine::Dialect::Sidac) {
  format::FormatOptions o;
  o.lex.dialect = d;
  return o;
}

std::string formatted(std::string_view text, const format::FormatOptions& o = options()) {
  return format::assemble(text, format::formatLines(text, o).lines).text;
}

format::RenumberOptions numbering(uint64_t start, uint64_t step, machine::Dialect d = machine::Dialect::Z32) {
  format::RenumberOptions r;
  r.start = start;
  r.step = step;
  r.lex.dialect = d;
  return r;
}

} // namespace

TEST_CASE("format: the default style") {
  CHECK(formatted("n10g01x10 y 20f100\n") == "N10 G01 X10 Y20 F100\n");
  CHECK(formatted("r1=r2*2+1\n") == "R1 = R2 * 2 + 1\n");
  CHECK(formatted("g1 x=-r1 f=40\n") == "G1 X=-R1 F=40\n");
  CHECK(formatted("$aa_out[3]=1\n") == "$AA_OUT[3] = 1\n");
  CHECK(formatted("if(r1>5)and($aa_in[2]==0)\nm30\nendif\n") == "IF (R1 > 5) AND ($AA_IN[2] == 0)\n  M30\nENDIF\n");
  CHECK(formatted("pos[x]=100 m=nb(34)\n") == "POS[X]=100 M=NB(34)\n");
  CHECK(formatted("wait: if $aa_in[3]==0 gotob wait\n") == "wait: IF $AA_IN[3] == 0 GOTOB wait\n");
  CHECK(formatted("case r1 of 1 gotof Uno -2 gotof Due\nUno: m30\nDue: m30\n") ==
        "CASE R1 OF 1 GOTOF Uno -2 GOTOF Due\nUno: M30\nDue: M30\n");
}

TEST_CASE("format: indentation of IF and WHEN bodies, after the prefixes") {
  const std::string in = "if r1>0\nN20 x1\nelse\n( comment )\nwhen $aa_iw[x]>5 do\n$aa_out[1]=1\ncancel\n"
                         "g1 x10 f1\nendif\n";
  CHECK(formatted(in) == "IF R1 > 0\nN20   X1\nELSE\n  ( comment )\n  WHEN $AA_IW[X] > 5 DO\n    $AA_OUT[1] = 1\n"
                         "  CANCEL\n  G1 X10 F1\nENDIF\n");
}

TEST_CASE("format: comments, strings, line ends and blank lines are kept") {
  // a Latin-1 comment byte, CR LF line ends, a `(` comment, a string
  const std::string in = "semi \"Prova  ciao\"\r\ng1 x1   (TAGLIO)   y2 ; perch\xe8\r\n\r\n\r\n\r\nm30\r\n\r\n";
  CHECK(formatted(in) == "SEMI \"Prova  ciao\"\r\nG1 X1 (TAGLIO) Y2     ; perch\xe8\r\n\r\nM30\r\n");
  CHECK(formatted("g0 x1   \nm30") == "G0 X1\nM30"); // trailing blanks; no line end added
  CHECK(formatted("r1=5      ; kept column\n") == "R1 = 5    ; kept column\n");
}

TEST_CASE("format: what is left as written") {
  auto r = format::formatLines("g01 x=(1\nm30\n", options());
  CHECK(r.keptAsWritten);
  REQUIRE(r.notes.size() == 1);
  CHECK(r.notes[0].line == 1);
  CHECK(formatted("g1 x1 $\ny2 f1\nm30\n") == "g1 x1 $\ny2 f1\nM30\n"); // continued lines
  std::string longLine;
  for (int i = 0; i < 81; ++i)
    longLine += "x1";
  CHECK(formatted(longLine + "\n") == longLine + "\n");
}

TEST_CASE("format: the numbers of the normalised style keep their value") {
  CHECK(format::normaliseNumber(".5") == "0.5");
  CHECK(format::normaliseNumber("1,25") == "1.25");
  CHECK(format::normaliseNumber("53.") == "53.");
  auto o = options();
  o.style.numbers = format::NumberStyle::Normalised;
  CHECK(formatted("N1,5 G01 X.5 Y-,25 M03\n", o) == "N1,5 G01 X0.5 Y-0.25 M03\n");
}

TEST_CASE("format: z32 keeps the start of a line a GO target could find") {
  const auto z = options(machine::Dialect::Z32);
  CHECK(formatted("n10 g0 x1\nGON20\nN20 m30\n", z) == "n10 G0 X1\nGON20\nN20 M30\n");
  CHECK(formatted("  N30 x1\n%n5 x2\nN1: x3\n", z) == "  N30 X1\n%n5 X2\nN1: X3\n");
  CHECK(formatted("if r1>0\nN40 x4\nendif\n", z) == "IF R1 > 0\nN40   X4\nENDIF\n");
  CHECK(formatted("N10 goN20-N30\nN20 x1\nN30 x2\n", z) == "N10 GON20-N30\nN20 X1\nN30 X2\n");
}

TEST_CASE("format: formatting twice changes nothing") {
  const std::string in = "n10 g90 g01 x10 f100 ; c\nif r1>3\ng1 x=r1+2 (c) y-.5\nelse\nx1\nendif\n\n\nm30\n";
  const std::string once = formatted(in);
  CHECK(formatted(once) == once);
}

TEST_CASE("renumber: N numbers and the GO targets that name them") {
  const std::string in = "N10 GO/N30 ; far\nN20 X1\n/N30 X2\nN40 GON20-/N30\nN50 GO/N30\nN60 M30\n";
  auto r = format::renumber(in, numbering(100, 10));
  REQUIRE(r.ok());
  CHECK(*r == "N100 GO/N120 ; far\nN110 X1\n/N120 X2\nN130 GON110-/N120\nN140 GO/N120\nN150 M30\n");
}

TEST_CASE("renumber: every statement line with allLines, never PROC") {
  auto o = numbering(5, 5, machine::Dialect::Sidac);
  o.allLines = true;
  auto r = format::renumber("PROC P SAVE\nG0 X1\n; c\n/X2\nN99 M17\n", o);
  REQUIRE(r.ok());
  CHECK(*r == "PROC P SAVE\nN5 G0 X1\n; c\n/N10 X2\nN15 M17\n");
}

TEST_CASE("renumber: refusals name the line and the reason") {
  auto dup = format::renumber("N10 GON20\nN20 X1\nN20 X2\nM30\n", numbering(10, 10));
  REQUIRE_FALSE(dup.ok());
  CHECK(dup.error().where == "1");
  CHECK(dup.error().message.find("lines 2 and 3") != std::string::npos);
  auto blank = format::renumber("N10 GON20\n  N20 X1\nN20 X2\nM30\n", numbering(10, 10));
  REQUIRE_FALSE(blank.ok());
  CHECK(blank.error().message.find("after blanks") != std::string::npos);
  auto label = format::renumber("N10 GON1\nN1: X1\nM30\n", numbering(10, 10));
  REQUIRE_FALSE(label.ok());
  CHECK(label.error().message.find("does not start with that N number") != std::string::npos);
  auto big = format::renumber("N1 X1\nN2 X2\n", numbering(999999999, 10, machine::Dialect::Sidac));
  REQUIRE_FALSE(big.ok());
  CHECK(big.error().where == "2");
  auto bad = format::renumber("N1 X=(1\n", numbering(10, 10));
  CHECK_FALSE(bad.ok());
}

TEST_CASE("settings: the [format] table") {
  driver::Settings s;
  std::string error;
  REQUIRE(driver::parseSettings("[format]\ncase = \"lower\"\nspaces = false\nindent = 4\nnumbers = \"normalised\"\n"
                                "blank-lines = 0\nrenumber = \"100,5\"\nrenumber-all = true\n",
                                "isotools.toml", s, error));
  CHECK(*s.format.wordCase == "lower");
  CHECK(*s.format.spaceBetweenWords == false);
  CHECK(*s.format.indent == 4);
  CHECK(*s.format.numbers == "normalised");
  CHECK(*s.format.blankLines == 0);
  CHECK(*s.format.renumber == "100,5");
  CHECK(*s.format.renumberAll);
  CHECK_FALSE(driver::parseSettings("[format]\ncase = \"title\"\n", "isotools.toml", s, error));
  CHECK(error.find("'format.case' must be \"upper\" or \"lower\" or \"keep\"") != std::string::npos);
  CHECK_FALSE(driver::parseSettings("[format]\nindnet = 2\n", "isotools.toml", s, error));
  CHECK(error.find("did you mean 'indent'") != std::string::npos);
  CHECK_FALSE(driver::parseSettings("[format]\nindent = 99\n", "isotools.toml", s, error));
}
