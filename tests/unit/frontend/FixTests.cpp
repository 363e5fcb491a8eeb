//! @file FixTests.cpp
//! @brief Fix-its of the frontend (E101, E108, E110, W407, the colon of `GOTOF Label:`): the
//!        text they make, that applying them removes the diagnostic, that none is offered
//!        where a mechanical change is unsafe, and `$` continuation lines.
#include <doctest/doctest.h>

#include "TestUtil.h"
#include "diag/Fix.h"

using namespace iso;
using iso::test::Diags;

namespace {

/// The first diagnostic with `code` in the lint of `text`, or nullptr.
const diag::Diagnostic* find(const Diags& ds, const char* code) {
  for (const auto& d : ds)
    if (std::string(diag::info(d.code).code) == code) return &d;
  return nullptr;
}

bool has(const Diags& ds, const char* code) { return find(ds, code) != nullptr; }

/// `text` with the fixes of every diagnostic applied (the first fix of each).
std::string fixed(const std::string& text, const std::string& path = "t.mpf") {
  Diags ds = test::lintText(text, path);
  std::vector<const diag::Fix*> fixes;
  for (const auto& d : ds)
    if (!d.fixes.empty()) fixes.push_back(&d.fixes.front());
  return diag::applyFixes(text, fixes).text;
}

} // namespace

TEST_CASE("fix: roundToNineDigits keeps the separator and never makes more than 9 digits") {
  using frontend::roundToNineDigits;
  CHECK(roundToNineDigits("123.4567891") == "123.456789");
  CHECK(roundToNineDigits("123,4567896") == "123,45679");
  CHECK(roundToNineDigits("1,00000999999999") == "1,00001");
  CHECK(roundToNineDigits("000012345,67800000") == "000012345,678");
  CHECK(roundToNineDigits("0.9999999999") == "1.");
  CHECK(roundToNineDigits(".12345678949") == ".123456789");
  CHECK(roundToNineDigits("123456789.5") == "123456790.");
  CHECK_FALSE(roundToNineDigits("999999999.5").has_value()); // would be 1000000000
  CHECK_FALSE(roundToNineDigits("1000000000").has_value());
  CHECK_FALSE(roundToNineDigits("12345678901").has_value());
  CHECK_FALSE(roundToNineDigits("123.456789").has_value()); // nothing to do
  CHECK_FALSE(roundToNineDigits("0,00000999999999").has_value());
}

TEST_CASE("fix: E101 rounds the number in place, sign and address untouched") {
  const std::string src = "G1 X-123.4567891 F100\nM30\n";
  Diags ds = test::lintText(src);
  const diag::Diagnostic* d = find(ds, "E101");
  REQUIRE(d);
  REQUIRE(d->fixes.size() == 1);
  REQUIRE(d->fixes[0].edits.size() == 1);
  const diag::Edit& e = d->fixes[0].edits[0];
  CHECK(e.start.line == 1);
  CHECK(e.start.col == 6);
  CHECK(e.endCol == 17);
  CHECK(e.replacement == "123.456789");
  CHECK(d->fixes[0].description == "round the number to 9 significant digits: '123.456789'");
  const std::string out = fixed(src);
  CHECK(out == "G1 X-123.456789 F100\nM30\n");
  CHECK_FALSE(has(test::lintText(out), "E101"));
}

TEST_CASE("fix: E101 has no fix for 1000000000 and above, nor across a $ join") {
  Diags big = test::lintText("R1 = 1000000000\nM30\n");
  REQUIRE(find(big, "E101"));
  CHECK(find(big, "E101")->fixes.empty());
  Diags split = test::lintText("G1 X12345$\n6.7891234 F100\nM30\n");
  REQUIRE(find(split, "E101"));
  CHECK(find(split, "E101")->fixes.empty());
}

TEST_CASE("fix: E108 parenthesises each comparison") {
  const std::string src = "IF R1 > 2 AND R2 < 3 GOTOF Fine\nFine: M30\n";
  Diags ds = test::lintText(src);
  const diag::Diagnostic* d = find(ds, "E108");
  REQUIRE(d);
  REQUIRE(d->fixes.size() == 1);
  CHECK(d->fixes[0].description == "parenthesise each comparison");
  CHECK(d->fixes[0].edits.size() == 4);
  const std::string out = fixed(src);
  CHECK(out == "IF (R1 > 2) AND (R2 < 3) GOTOF Fine\nFine: M30\n");
  CHECK(test::lintText(out).empty());
}

TEST_CASE("fix: E108 leaves groups alone and goes into them") {
  CHECK(fixed("IF (R1 > 2) OR R2 + 1 >= R3 * 2 THEN R4 = 1\nM30\n") ==
        "IF (R1 > 2) OR (R2 + 1 >= R3 * 2) THEN R4 = 1\nM30\n");
  CHECK(fixed("IF ((R1 > 2) AND R2 < 3) OR (R5 == 1) THEN R4 = 1\nM30\n") ==
        "IF ((R1 > 2) AND (R2 < 3)) OR (R5 == 1) THEN R4 = 1\nM30\n");
  CHECK(fixed("IF NOT (R1 > 2) AND R[R2] <> $aa_in[1] THEN R4 = 1\nM30\n") ==
        "IF NOT (R1 > 2) AND (R[R2] <> $aa_in[1]) THEN R4 = 1\nM30\n");
}

TEST_CASE("fix: no E108 fix for a bare value or NOT of a comparison") {
  for (const char* src : {"IF R1 GOTOF Fine\nFine: M30\n", "IF R1 AND (R2 > 1) GOTOF Fine\nFine: M30\n",
                          "IF NOT R1 > 2 GOTOF Fine\nFine: M30\n"}) {
    Diags ds = test::lintText(src);
    const diag::Diagnostic* d = find(ds, "E108");
    REQUIRE_MESSAGE(d, src);
    CHECK_MESSAGE(d->fixes.empty(), src);
  }
}

TEST_CASE("fix: E108 on a $-continued line puts each edit on its physical line") {
  const std::string src = "IF R1 > 2 AND $\nR2 < 3 GOTOF Fine\nFine: M30\n";
  Diags ds = test::lintText(src);
  const diag::Diagnostic* d = find(ds, "E108");
  REQUIRE(d);
  REQUIRE(d->fixes.size() == 1);
  for (const auto& e : d->fixes[0].edits)
    CHECK(e.start.line == e.endLine);
  const std::string out = fixed(src);
  CHECK(out == "IF (R1 > 2) AND $\n(R2 < 3) GOTOF Fine\nFine: M30\n");
  CHECK(test::lintText(out).empty());
}

TEST_CASE("fix: E108 has no fix when a comparison's last token is split by a $ join") {
  Diags ds = test::lintText("IF R1 > 2 AND R2 < 3$\n4 GOTOF Fine\nFine: M30\n");
  const diag::Diagnostic* d = find(ds, "E108");
  REQUIRE(d);
  CHECK(d->fixes.empty());
}

TEST_CASE("fix: E110 RET and ENDPROC become M17 in a subprogram") {
  const std::string src = "PROC Sub SAVE\nG1 X10 F100\nRET\n";
  Diags ds = test::lintText(src, "sub.spf");
  const diag::Diagnostic* d = find(ds, "E110");
  REQUIRE(d);
  REQUIRE(d->fixes.size() == 1);
  CHECK(d->fixes[0].description == "replace 'RET' with 'M17'");
  const std::string out = fixed(src, "sub.spf");
  CHECK(out == "PROC Sub SAVE\nG1 X10 F100\nM17\n");
  CHECK(test::lintText(out, "sub.spf").empty());
  CHECK(fixed("PROC Sub SAVE\nG1 X10 F100\nendproc\n", "sub.spf") == "PROC Sub SAVE\nG1 X10 F100\nM17\n");
}

TEST_CASE("fix: no E110 fix in a main program, after THEN, or for constructs without a SIDAC twin") {
  for (const char* src : {"G1 X10 F100\nRET\nM30\n", "STOPRE\nM30\n", "DEF REAL A\nM30\n"}) {
    Diags ds = test::lintText(src);
    const diag::Diagnostic* d = find(ds, "E110");
    REQUIRE_MESSAGE(d, src);
    CHECK_MESSAGE(d->fixes.empty(), src);
  }
  Diags inner = test::lintText("PROC Sub SAVE\nIF R1 > 0 THEN RET\nM17\n", "sub.spf");
  REQUIRE(find(inner, "E110"));
  CHECK(find(inner, "E110")->fixes.empty());
}

TEST_CASE("fix: W407 writes the canonical system variable") {
  const std::string src = "R1 = $max_limit_plus[X]\nR2 = $MAX_LIMIT_MINUS[Y]\nM30\n";
  Diags ds = test::lintText(src);
  const diag::Diagnostic* d = find(ds, "W407");
  REQUIRE(d);
  REQUIRE(d->fixes.size() == 1);
  CHECK(d->fixes[0].description == "replace '$max_limit_plus' with '$POS_LIMIT_PLUS'");
  const std::string out = fixed(src);
  CHECK(out == "R1 = $POS_LIMIT_PLUS[X]\nR2 = $POS_LIMIT_MINUS[Y]\nM30\n");
  CHECK_FALSE(has(test::lintText(out), "W407"));
}

TEST_CASE("fix: the colon after a jump's label is deleted, every one of the line") {
  const std::string src = "CASE R1 OF 1 GOTOF Fine: 2 GOTOF Altro:\nFine: M30\nAltro: M30\n";
  Diags ds = test::lintText(src);
  const diag::Diagnostic* d = find(ds, "E100");
  REQUIRE(d);
  REQUIRE(d->fixes.size() == 1);
  CHECK(d->fixes[0].description == "remove the ':' after the label name");
  CHECK(d->fixes[0].edits.size() == 2);
  const std::string out = fixed(src);
  CHECK(out == "CASE R1 OF 1 GOTOF Fine 2 GOTOF Altro\nFine: M30\nAltro: M30\n");
  CHECK_FALSE(has(test::lintText(out), "E100"));
}

TEST_CASE("fix: applyFixes keeps CR LF and other bytes, skips overlapping fixes") {
  const std::string src = "G1 X-123.4567891 F100 ; caf\xE9\r\nM30\r\n";
  CHECK(fixed(src) == "G1 X-123.456789 F100 ; caf\xE9\r\nM30\r\n");
  diag::Fix a{"a", {{{0, 1, 1}, 1, 3, "xx"}}};
  diag::Fix b{"b", {{{0, 1, 2}, 1, 4, "yy"}}};
  diag::Fix c{"c", {{{0, 1, 5}, 1, 5, "!"}}};
  diag::FixResult r = diag::applyFixes("abcdef\n", {&a, &b, &c});
  CHECK(r.text == "xxcd!ef\n");
  CHECK(r.applied == 2);
  CHECK(r.skipped == 1);
  diag::Fix far{"far", {{{0, 3, 1}, 3, 2, ""}}};
  CHECK(diag::applyFixes("abc\n", {&far}).skipped == 1);
}

TEST_CASE("fix: unifiedDiff shows the changed lines with 3 lines of context") {
  std::string text;
  for (int i = 1; i <= 12; ++i) {
    text += 'L';
    text += std::to_string(i);
    text += '\n';
  }
  diag::Fix f1{"", {{{0, 2, 1}, 2, 2, "l"}}};
  diag::Fix f2{"", {{{0, 11, 1}, 11, 2, "l"}}};
  diag::FixResult r = diag::applyFixes(text, {&f1, &f2});
  CHECK(diag::unifiedDiff(text, r.edits, "p.mpf") == "--- a/p.mpf\n+++ b/p.mpf\n"
                                                     "@@ -1,5 +1,5 @@\n L1\n-L2\n+l2\n L3\n L4\n L5\n"
                                                     "@@ -8,5 +8,5 @@\n L8\n L9\n L10\n-L11\n+l11\n L12\n");
  CHECK(diag::unifiedDiff(text, {}, "p.mpf").empty());
  diag::Fix last{"", {{{0, 1, 1}, 1, 2, "B"}}};
  diag::FixResult r2 = diag::applyFixes("a", {&last});
  CHECK(diag::unifiedDiff("a", r2.edits, "q") ==
        "--- a/q\n+++ b/q\n@@ -1,1 +1,1 @@\n-a\n\\ No newline at end of file\n+B\n"
        "\\ No newline at end of file\n");
}
