//! @file LexerTests.cpp
//! @brief SPEC §2: numbers, packed words vs identifiers, `$` continuation, the 240-character
//!        limit, comments, line ends, BOM, non-ASCII bytes, case-insensitivity.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <string>

#include <doctest/doctest.h>

#include "TestUtil.h"

using namespace iso;
using frontend::Tok;
using frontend::Token;
using test::count;
using test::dump;
using test::hasCode;
using test::lexText;
using test::lintText;

namespace {

/// "X" for a word with address X, else the token kind's name.
std::string addrOf(const Token& t) { return t.kind == Tok::Word ? std::string(t.addr) : frontend::tokName(t.kind); }

/// The value of the single word of a one-line source.
double wordValue(const std::string& text) {
  auto r = lexText(text);
  REQUIRE(r->lines.size() == 1);
  auto toks = r->tokens(0);
  REQUIRE(toks.size() == 1);
  REQUIRE(toks[0].kind == Tok::Word);
  return toks[0].value;
}

} // namespace

// ---- numbers (SPEC §2 "Numbers") ---------------------------------------------------------------

TEST_CASE("lexer: every number's value is the correctly rounded double of its digits (from_chars)") {
  // The lexer computes short numbers as mantissa / 10^k (exact operands, one rounding) and longer ones with
  // from_chars: both must give the double nearest to the decimal, for any digits and separator position.
  uint64_t state = 0x9E3779B97F4A7C15ULL;
  auto nextRandom = [&state] {
    state ^= state << 13;
    state ^= state >> 7;
    state ^= state << 17;
    return state;
  };
  for (int i = 0; i < 20000; ++i) {
    const size_t len = 1 + nextRandom() % 24;
    std::string digits;
    for (size_t k = 0; k < len; ++k)
      digits.push_back(static_cast<char>('0' + nextRandom() % 10));
    const size_t sepAt = nextRandom() % (len + 1); // len: no separator
    std::string number = digits;
    if (sepAt < len) number.insert(sepAt, 1, i % 2 == 0 ? '.' : ',');
    std::string plain = number;
    std::replace(plain.begin(), plain.end(), ',', '.');
    double expected = 0;
    std::from_chars(plain.data(), plain.data() + plain.size(), expected);
    CAPTURE(number);
    CHECK(wordValue("X" + number + "\n") == expected);
  }
}

TEST_CASE("lexer: X00000,1000 has 4 significant digits and is accepted") {
  auto r = lexText("X00000,1000\n");
  CHECK(r->diags.size() == 0);
  auto toks = r->tokens(0);
  REQUIRE(toks.size() == 1);
  CHECK(addrOf(toks[0]) == "X");
  CHECK(toks[0].value == doctest::Approx(0.1));
  CHECK(toks[0].hasSep);
}

TEST_CASE("lexer: 0,00000999999999 has 9 significant digits and is accepted") {
  auto r = lexText("R1 = 0,00000999999999\n");
  CHECK(r->diags.size() == 0);
  auto toks = r->tokens(0);
  REQUIRE(toks.size() == 3);
  CHECK(toks[2].kind == Tok::Number);
  CHECK(toks[2].value == doctest::Approx(0.00000999999999).epsilon(1e-12));
}

TEST_CASE("lexer: X000012345,67800000 has 13 significant digits (E101)") {
  auto d = lintText("G0 X000012345,67800000\nM30\n");
  INFO(dump(d));
  CHECK(hasCode(d, "E101", 1, 5));
  // The rejected number takes part in no other check (no soft-limit warning for 12345.678).
  CHECK(d.size() == 1);
}

TEST_CASE("lexer: X1,00000999999999 has 15 significant digits (E101)") {
  auto d = lintText("G0 X1,00000999999999\nM30\n");
  INFO(dump(d));
  CHECK(hasCode(d, "E101", 1, 5));
  CHECK(d.size() == 1);
}

TEST_CASE("lexer: 1000000000 is rejected, 999999999 is accepted") {
  auto bad = lintText("R1 = 1000000000\nM30\n");
  INFO(dump(bad));
  CHECK(hasCode(bad, "E101", 1, 6));
  CHECK(bad.size() == 1);
  CHECK(lintText("R1 = 999999999\nM30\n").empty());
  CHECK(lintText("R1 = 999999999,0\nM30\n").size() == 1); // trailing zeros count
  CHECK(lintText("R1 = 99999,9999\nM30\n").empty());
}

TEST_CASE("lexer: digits may be omitted before or after the separator") {
  CHECK(*test::evalConst(".5") == 0.5);
  CHECK(*test::evalConst(",5") == 0.5);
  CHECK(*test::evalConst("53.") == 53.0);
  CHECK(*test::evalConst("53,") == 53.0);
  CHECK(*test::evalConst("0,25") == 0.25);
  CHECK(lintText("R1 = .5 + ,5 + 53.\nM30\n").empty());
}

TEST_CASE("lexer: a word's value may be signed and spaced from its address") {
  CHECK(wordValue("X-.5") == -0.5);
  CHECK(wordValue("X+2") == 2.0);
  CHECK(wordValue("X 0.1") == doctest::Approx(0.1));
  CHECK(wordValue("X -5") == -5.0);
  CHECK(wordValue("X - 5") == -5.0);
  CHECK(wordValue("x\t7") == 7.0); // tab counts as a space
}

TEST_CASE("lexer: no spaces inside the digits of a number") {
  auto d = lintText("G0 X1 000\nM30\n");
  INFO(dump(d));
  CHECK(hasCode(d, "E100", 1, 7));
}

TEST_CASE("lexer: z32 MA word takes a signed value") {
  auto r = lexText("MA-100\n", machine::Dialect::Z32);
  auto toks = r->tokens(0);
  REQUIRE(toks.size() == 1);
  CHECK(std::string(toks[0].addr) == "MA");
  CHECK(toks[0].value == -100.0);
}

// ---- words and identifiers ---------------------------------------------------------------------

TEST_CASE("lexer: N12G0X0 is the three words N12 G0 X0") {
  auto r = lexText("N12G0X0\n");
  auto toks = r->tokens(0);
  REQUIRE(toks.size() == 3);
  CHECK(addrOf(toks[0]) == "N");
  CHECK(toks[0].value == 12);
  CHECK(toks[0].col == 1);
  CHECK(addrOf(toks[1]) == "G");
  CHECK(toks[1].value == 0);
  CHECK(toks[1].col == 4);
  CHECK(addrOf(toks[2]) == "X");
  CHECK(toks[2].col == 6);
}

TEST_CASE("lexer: a token that does not read as words is an identifier") {
  for (const char* name : {"Alza_carrello", "X1Y", "X1_a", "Crea_pezzo", "G0X0Foo", "Uno"}) {
    CAPTURE(name);
    auto r = lexText(std::string(name) + "\n");
    auto toks = r->tokens(0);
    REQUIRE(toks.size() == 1);
    CHECK(toks[0].kind == Tok::Ident);
    CHECK(toks[0].text == name);
  }
}

TEST_CASE("lexer: CR5 is a radius word, CR= an identifier before '='") {
  auto r = lexText("CR5\nCR=5\n");
  auto a = r->tokens(0);
  REQUIRE(a.size() == 1);
  CHECK(std::string(a[0].addr) == "CR");
  auto b = r->tokens(1);
  REQUIRE(b.size() == 3);
  CHECK(b[0].kind == Tok::Ident);
  CHECK(b[1].kind == Tok::Assign);
}

TEST_CASE("lexer: A1: is a label, A1 alone a word") {
  auto r = lexText("A1:\nA1\nA1 : G0 X0\n");
  auto a = r->tokens(0);
  REQUIRE(a.size() == 2);
  CHECK(a[0].kind == Tok::Ident);
  CHECK(a[0].text == "A1");
  CHECK(a[1].kind == Tok::Colon);
  auto b = r->tokens(1);
  REQUIRE(b.size() == 1);
  CHECK(b[0].kind == Tok::Word);
  auto c = r->tokens(2);
  REQUIRE(c.size() >= 2);
  CHECK(c[0].kind == Tok::Ident);
  CHECK(c[1].kind == Tok::Colon);
}

TEST_CASE("lexer: the name after GOTOB is a label whatever it looks like") {
  auto r = lexText("GOTOB W\nGOTOF X10\n");
  auto a = r->tokens(0);
  REQUIRE(a.size() == 2);
  CHECK(a[1].kind == Tok::Ident);
  CHECK(a[1].text == "W");
  auto b = r->tokens(1);
  REQUIRE(b.size() == 2);
  CHECK(b[1].kind == Tok::Ident);
  CHECK(b[1].text == "X10");
}

TEST_CASE("lexer: a label after GOTOF never absorbs the following number") {
  auto r = lexText("CASE R1 OF 1 GOTOF X 2 GOTOF Y\n");
  auto t = r->tokens(0);
  REQUIRE(t.size() == 9);
  CHECK(t[5].kind == Tok::Ident);
  CHECK(t[5].text == "X");
  CHECK(t[6].kind == Tok::Number);
  CHECK(t[6].value == 2);
}

TEST_CASE("lexer: S and T are addresses only in dialect z32") {
  auto sidac = lexText("S1000\n");
  CHECK(sidac->tokens(0).at(0).kind == Tok::Ident);
  auto z32 = lexText("S1000 T1\n", machine::Dialect::Z32);
  auto t = z32->tokens(0);
  REQUIRE(t.size() == 2);
  CHECK(addrOf(t[0]) == "S");
  CHECK(addrOf(t[1]) == "T");
}

// ---- `$` continuation ----------------------------------------------------------------------------

TEST_CASE("lexer: the Z32 continuation example joins three physical lines") {
  auto r = lexText("N12G0X0$ AB12\nY0Z0$\nM6\nM30\n");
  CHECK(r->diags.size() == 0);
  REQUIRE(r->lines.size() == 2);
  CHECK(r->lines[0].firstLine == 1);
  CHECK(r->lines[0].lastLine == 3);
  auto t = r->tokens(0);
  REQUIRE(t.size() == 6);
  const char* addrs[] = {"N", "G", "X", "Y", "Z", "M"};
  const uint32_t lines[] = {1, 1, 1, 2, 2, 3};
  const uint32_t cols[] = {1, 4, 6, 1, 3, 1};
  for (size_t i = 0; i < 6; ++i) {
    CAPTURE(i);
    CHECK(addrOf(t[i]) == addrs[i]);
    CHECK(t[i].line == lines[i]);
    CHECK(t[i].col == cols[i]);
  }
  CHECK(t[5].value == 6);
  CHECK(r->lines[1].firstLine == 4);
}

TEST_CASE("lexer: a token split by a continuation is joined and keeps its first position") {
  auto r = lexText("R1 = 12$ ignored tail\n34\n");
  REQUIRE(r->lines.size() == 1);
  auto t = r->tokens(0);
  REQUIRE(t.size() == 3);
  CHECK(t[2].kind == Tok::Number);
  CHECK(t[2].value == 1234);
  CHECK(t[2].line == 1);
  CHECK(t[2].col == 6);
  CHECK(*test::evalConst("12$\n34") == 1234);

  auto n = lexText("Alza_$\ncarrello\n");
  auto nt = n->tokens(0);
  REQUIRE(nt.size() == 1);
  CHECK(nt[0].kind == Tok::Ident);
  CHECK(nt[0].text == "Alza_carrello");
}

TEST_CASE("lexer: the text after a continuation $ is ignored, whatever bytes it holds") {
  auto d = lintText("G0 X0$ \xC3\xA8 ( $ anything\nY0\nM30\n");
  INFO(dump(d));
  CHECK(d.empty());
}

TEST_CASE("lexer: a $ followed by a letter is a system variable") {
  auto r = lexText("R1 = $AA_IW[X]\n");
  auto t = r->tokens(0);
  REQUIRE(t.size() == 6);
  CHECK(t[2].kind == Tok::SysVar);
  CHECK(t[2].sysvar == frontend::SysVar::AaIw);
  CHECK(t[2].col == 6);
}

TEST_CASE("lexer: an unknown $name is E105 and the message mentions continuation") {
  auto d = lintText("G0 X0$AB12\nM30\n");
  INFO(dump(d));
  REQUIRE(hasCode(d, "E105", 1, 6));
  CHECK(test::find(d, "E105")->message.find("continuation") != std::string::npos);
  CHECK(hasCode(lintText("R1 = $_X\nM30\n"), "E105", 1, 6)); // '$' then '_' is no continuation
}

TEST_CASE("lexer: semicolon ends the content, a later $ does not continue the line") {
  auto r = lexText("R1 = 1 ; a $ b\nR2 = 2\n");
  CHECK(r->lines.size() == 2);
  CHECK(r->diags.size() == 0);
}

TEST_CASE("lexer: a $ on the last line of the file joins nothing") {
  auto r = lexText("G0 X0$");
  REQUIRE(r->lines.size() == 1);
  CHECK(r->diags.size() == 0);
  CHECK(r->tokens(0).size() == 2);
}

// ---- E102: 240 characters --------------------------------------------------------------------------

namespace {
/// "R1=1+1+...": an assignment of exactly n characters (n even, >= 4).
std::string assignmentOfLength(size_t n) {
  std::string s = "R1=1";
  while (s.size() < n)
    s += "+1";
  return s;
}
} // namespace

TEST_CASE("lexer: a logical line of 240 characters is accepted, 241 is E102 at the 241st") {
  std::string ok = assignmentOfLength(240);
  REQUIRE(ok.size() == 240);
  CHECK(lintText(ok + "\nM30\n").empty());
  std::string bad = assignmentOfLength(240) + "1"; // "+11": still a valid expression
  REQUIRE(bad.size() == 241);
  auto d = lintText(bad + "\nM30\n");
  INFO(dump(d));
  CHECK(hasCode(d, "E102", 1, 241));
  CHECK(d.size() == 1);
}

TEST_CASE("lexer: the 240 limit counts the joined text without $, its tail and line ends") {
  std::string first = assignmentOfLength(124);    // 124 characters, then '$' and a long tail
  std::string tail = " " + std::string(200, 'x'); // "$x..." would be a system variable
  std::string second;
  while (second.size() < 116)
    second += "+1";
  // 124 + 116 = 240: accepted although the physical lines hold far more bytes.
  CHECK(lintText(first + "$" + tail + "\n" + second + "\nM30\n").empty());
  // 124 + 117: the 241st character is column 117 of the second physical line.
  auto d = lintText(first + "$" + tail + "\n" + second + "1\nM30\n");
  INFO(dump(d));
  CHECK(hasCode(d, "E102", 2, 117));
}

TEST_CASE("lexer: a semicolon comment does not count toward the 240 characters, a ( ) comment does") {
  // Decision: ';' ends the content (SPEC §2 step 1), so its text is no part of the logical line;
  // a ( ... ) comment stands inside the content and counts.
  std::string code = assignmentOfLength(240);
  CHECK(lintText(code + "; " + std::string(300, '=') + "\nM30\n").empty());
  CHECK(lintText("; " + std::string(400, '=') + "\nM30\n").empty());
  auto d = lintText(assignmentOfLength(230) + " (" + std::string(20, 'c') + ")\nM30\n");
  CHECK(hasCode(d, "E102", 1, 241));
}

// ---- comments ----------------------------------------------------------------------------------------

TEST_CASE("lexer: a ( ... ) comment line holds no tokens") {
  auto r = lexText("(comment line)\n  (indented)\nN10 (after a line number)\n");
  CHECK(r->diags.size() == 0);
  CHECK(r->tokens(0).empty());
  CHECK(r->tokens(1).empty());
  auto t = r->tokens(2);
  REQUIRE(t.size() == 1);
  CHECK(addrOf(t[0]) == "N");
}

TEST_CASE("lexer: a ( after a complete item is an inline comment") {
  auto r = lexText("N6 G1 X138.79 (CUT) F100\n");
  CHECK(r->diags.size() == 0);
  auto t = r->tokens(0);
  REQUIRE(t.size() == 4);
  CHECK(addrOf(t[3]) == "F");
  CHECK(t[3].col == 21);
  CHECK(lintText("G1 X1 F100 (taglio)\nR1 = R2 (commento)\nR1 = (R2) (commento)\nM30\n").empty());
}

TEST_CASE("lexer: an inline comment ends at the first ')' (no nesting)") {
  auto d = lintText("G1 X1 (a (b) c)\nM30\n");
  CHECK(hasCode(d, "E100", 1, 14));
  CHECK(lintText("G1 X1 (a (b) F100\nM30\n").empty());
}

TEST_CASE("lexer: a ( where an operand is expected groups") {
  for (const char* src :
       {"R1 = (2 + 3) * 4", "R1 = 2 * (3 + 4)", "R1 = -(2)", "R1 = R[(1 + 2)]", "IF (R1 > 2) OR (R2 < 1) GOTOF E",
        "IF NOT (R1 > 2) GOTOF E", "M=NB(34)", "IF ((R1 > 2)) AND (R2 > 1) GOTOF E", "CASE (R1 + 1) OF 1 GOTOF E"}) {
    CAPTURE(src);
    auto r = lexText(std::string(src) + "\n");
    CHECK(r->diags.size() == 0);
    bool sawParen = false;
    for (const auto& t : r->tokens(0))
      sawParen = sawParen || t.kind == Tok::LParen;
    CHECK(sawParen);
  }
}

TEST_CASE("lexer: a keyword followed directly by ( takes a comment") {
  CHECK(lintText("IF R1 == 1\nR2 = 1\nELSE(altrimenti)\nR2 = 2\nENDIF(fine)\nM30\n").empty());
}

TEST_CASE("lexer: semicolon starts a comment anywhere, also inside an expression line") {
  auto r = lexText("G1 X10 ; feed (not closed $\n; whole line\n");
  CHECK(r->diags.size() == 0);
  CHECK(r->tokens(0).size() == 2);
  CHECK(r->tokens(1).empty());
}

TEST_CASE("lexer: $ inside a ( ... ) comment is E103, a semicolon comment and strings may hold it") {
  auto d = lintText("(costo $ 5)\nG0 X1 (c $)\nM30\n");
  CHECK(hasCode(d, "E103", 1, 8));
  CHECK(hasCode(d, "E103", 2, 10));
  CHECK(lintText("SEMI \"Prezzo $ 5\"\nM30 ; $ here is fine\n").empty());
}

TEST_CASE("lexer: code after a comment line's ) is E104, another comment may follow") {
  // Decision: a line that starts with ( is a comment line and must end with ) (Z32): on the
  // control the code after it would not run, so a dry run must not run it either.
  auto d = lintText("(avvicinamento) G0 X0\nN10 (x) R1 = 1\n(a) (b)\n(a) ; c\n(a (b) c)\nM30\n");
  INFO(dump(d));
  CHECK(hasCode(d, "E104", 1, 17));
  CHECK(hasCode(d, "E104", 2, 9));
  CHECK(d.size() == 2);
}

TEST_CASE("lexer: a comment line without ) is E104") {
  auto d = lintText("( non chiuso\nM30\n");
  CHECK(hasCode(d, "E104", 1, 1));
  CHECK(d.size() == 1);
}

// ---- line ends, BOM, bytes -----------------------------------------------------------------------------

TEST_CASE("lexer: CRLF line ends are accepted and not part of the columns") {
  auto r = lexText("R1 = 1\r\nG0 X5\r\n");
  CHECK(r->diags.size() == 0);
  REQUIRE(r->lines.size() == 2);
  auto t = r->tokens(1);
  REQUIRE(t.size() == 2);
  CHECK(t[1].col == 4);
  CHECK(lintText("R1 = 1\r\nM30\r\n").empty());
}

TEST_CASE("lexer: a lone CR is an error") {
  auto d = lintText("R1 = 1\rR2 = 2\nM30\n");
  INFO(dump(d));
  CHECK(hasCode(d, "E100", 1, 7));
}

TEST_CASE("lexer: a leading UTF-8 BOM is ignored") {
  auto r = lexText("\xEF\xBB\xBFR1 = 1\n");
  CHECK(r->diags.size() == 0);
  auto t = r->tokens(0);
  REQUIRE(t.size() == 3);
  CHECK(addrOf(t[0]) == "R");
  CHECK(t[0].col == 1);
  CHECK(lintText("\xEF\xBB\xBFR1 = 1\nM30\n").empty());
}

TEST_CASE("lexer: bytes >= 0x80 are allowed in comments and strings, E106 in code") {
  CHECK(lintText("; perch\xC3\xA9 \xC3\xA8 cos\xC3\xAC\n(pi\xC3\xB9 avanti)\nG0 X1 (gi\xC3\xB9)\nM30\n").empty());
  CHECK(lintText("SEMI \"Perch\xC3\xA9\"\nM30\n").empty());
  auto d = lintText("R2 = \xC3\xA8\nM30\n");
  INFO(dump(d));
  CHECK(hasCode(d, "E106", 1, 6));
  CHECK(count(d, "E106") == 1); // one diagnostic per character, not per byte
}

// ---- case-insensitivity ----------------------------------------------------------------------------------

TEST_CASE("lexer: addresses, system variables and keywords are case-insensitive") {
  auto r = lexText("g01 x10\n$AA_IW[z]\n$aa_iw[Z]\n");
  auto a = r->tokens(0);
  REQUIRE(a.size() == 2);
  CHECK(addrOf(a[0]) == "G");
  CHECK(a[0].value == 1);
  CHECK(addrOf(a[1]) == "X");
  CHECK(r->tokens(1).at(0).sysvar == frontend::SysVar::AaIw);
  CHECK(r->tokens(2).at(0).sysvar == frontend::SysVar::AaIw);
  CHECK(lintText("g01 pos[x]=10 f=100\nr1 = $AA_IW[z] + $aa_fw[Y]\nif (r1 > 2) or (r1 < 1) gotof fine\n"
                 "fine:\nm30\n")
            .empty());
}

TEST_CASE("lexer: % and / and N are line prefixes") {
  auto r = lexText("%\n/N10 G0 X0\n");
  CHECK(r->tokens(0).size() == 1);
  auto t = r->tokens(1);
  REQUIRE(t.size() == 4);
  CHECK(t[0].kind == Tok::Slash);
  CHECK(addrOf(t[1]) == "N");
}
