//! @file RuleTests.cpp
//! @brief SPEC §7: for every diagnostic code, a program that triggers it (code, line, column)
//!        and a near-miss valid program that is entirely clean; notes; inline suppressions and
//!        --disable through driver::visibleDiagnostics.
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <doctest/doctest.h>
#include <fmt/format.h>

#include "TestUtil.h"
#include "driver/Lint.h"

using namespace iso;
using test::count;
using test::Diags;
using test::dump;
using test::hasCode;
using test::lintFiles;
using test::lintText;
using test::lintZ32;

namespace {

/// Checks that `d` holds `code` at line:col (0 = any column).
void fires(const Diags& d, const char* code, uint32_t line, uint32_t col) {
  INFO(dump(d));
  CHECK(hasCode(d, code, line, col));
}

/// Checks that a program has no diagnostic at all.
void clean(const Diags& d) {
  INFO(dump(d));
  CHECK(d.empty());
}

machine::Machine xyzMachine() {
  machine::Machine m = machine::builtinMachine();
  m.axes.resize(3); // X Y Z
  m.numInputs = 16;
  m.numOutputs = 8;
  return m;
}

/// A chain main -> Sub1 -> ... -> SubN as files (Sub_i in s<i>.spf).
std::vector<std::pair<std::string, std::string>> callChain(int n) {
  std::vector<std::pair<std::string, std::string>> files;
  files.push_back({"main.mpf", "G0 X0\nSub1\nM30\n"});
  for (int i = 1; i <= n; ++i) {
    std::string body = fmt::format("PROC Sub{} SAVE\n", i);
    if (i < n) body += fmt::format("Sub{}\n", i + 1);
    body += "M17\n";
    files.push_back({fmt::format("s{}.spf", i), body});
  }
  return files;
}

} // namespace

// ---- E1xx: lexical and syntax ------------------------------------------------------------------

TEST_CASE("rule E100: a block item that the grammar rejects fires") {
  fires(lintText("G1 X= F100\nM30\n"), "E100", 1, 7);
  auto d = lintText("G1 X10 )\nM30\n");
  fires(d, "E100", 1, 8);
  CHECK(test::find(d, "E100")->message.find("unexpected") != std::string::npos);
}

TEST_CASE("rule E100: a complete assignment item is clean") { clean(lintText("G1 X=10 F100\nM30\n")); }

TEST_CASE("rule E101: a number with 10 significant digits fires") {
  fires(lintText("R1 = 12345,67891\nM30\n"), "E101", 1, 6);
}

TEST_CASE("rule E101: 9 significant digits after leading zeros is clean") {
  clean(lintText("R1 = 0001234,56780\nR2 = 0,000123456789\nM30\n"));
}

TEST_CASE("rule E102: a 241-character logical line fires") {
  std::string line = "R1=1";
  while (line.size() < 240)
    line += "+1";
  fires(lintText(line + "1\nM30\n"), "E102", 1, 241);
}

TEST_CASE("rule E102: a 240-character line with a long ignored continuation tail is clean") {
  std::string a = "R1=1";
  while (a.size() < 120)
    a += "+1";
  std::string b;
  while (b.size() < 120)
    b += "+1";
  clean(lintText(a + "$ " + std::string(300, '-') + "\n" + b + "\nM30\n"));
}

TEST_CASE("rule E103: $ inside a comment fires") { fires(lintText("(prezzo $5)\nM30\n"), "E103", 1, 9); }

TEST_CASE("rule E103: $ after a semicolon is clean") { clean(lintText("(prezzo) ; $5\nM30\n")); }

TEST_CASE("rule E104: an unclosed comment line fires") { fires(lintText("N10 (senza fine\nM30\n"), "E104", 1, 5); }

TEST_CASE("rule E104: a closed comment line is clean") { clean(lintText("N10 (con fine)\nM30\n")); }

TEST_CASE("rule E105: an unknown system variable fires") { fires(lintText("R1 = $AA_VACTB[X]\nM30\n"), "E105", 1, 6); }

TEST_CASE("rule E105: every system variable of SPEC 3.3 is clean") {
  clean(lintText("R1 = $MAX_VELO[X]\nR2 = $POS_LIMIT_PLUS[Y]\nR3 = $POS_LIMIT_MINUS[Z]\n"
                 "R4 = $aa_iw[X] + $aa_fw[Y] + $aa_in[1] + $aa_out[2] + $aa_marker[3]\n"
                 "$aa_out[1] = 1\n$aa_marker[200] = 0\nM30\n"));
}

TEST_CASE("rule E106: a non-ASCII byte in code fires") { fires(lintText("G0 X1\xC2\xB0\nM30\n"), "E106", 1, 6); }

TEST_CASE("rule E106: non-ASCII bytes in comments and strings are clean") {
  clean(lintText("SEMI \"Perch\xC3\xA9\"\n; \xC3\xA8 qui\nG0 X1 (\xC2\xB0)\nM30\n"));
}

TEST_CASE("rule E107: = in a condition fires") {
  auto d = lintText("IF R1 = 1 GOTOF E\nE:\nM30\n");
  fires(d, "E107", 1, 7);
  CHECK(test::find(d, "E107")->message.find("==") != std::string::npos);
}

TEST_CASE("rule E107: == in a condition is clean") { clean(lintText("IF R1 == 1 GOTOF E\nE:\nM30\n")); }

TEST_CASE("rule E108: an unparenthesised AND operand fires") {
  fires(lintText("IF R1 > 1 AND R2 > 2 GOTOF E\nE:\nM30\n"), "E108", 1, 4);
  fires(lintText("IF R1 GOTOF E\nE:\nM30\n"), "E108", 1, 4);
  fires(lintText("WHEN $aa_in[1] DO $aa_out[1] = 1\nG0 X1\nM30\n"), "E108", 1, 6);
}

TEST_CASE("rule E108: parenthesised operands are clean") {
  clean(lintText("IF (R1 > 1) AND (R2 > 2) OR NOT (R3 > 3) GOTOF E\nE:\nM30\n"));
}

TEST_CASE("rule E109: a chained comparison fires") {
  fires(lintText("IF 1 < R1 < 5 GOTOF E\nE:\nM30\n"), "E109", 1, 11);
  fires(lintText("R1 = R2 == 3\nM30\n"), "E109", 1, 9);
}

TEST_CASE("rule E109: one comparison per parenthesis level is clean") {
  clean(lintText("IF (1 < R1) AND (R1 < 5) GOTOF E\nE:\nM30\n"));
}

TEST_CASE("rule E110: constructs of other dialects fire, each naming the construct") {
  auto d = lintText("DEF REAL A\nWHILE R1 < 3\nR1 = SIN(30)\nG54\nT1\nCYCLE81\nTRANS X10\nX=AC(10)\n#1 = 3\n"
                    "O100\nM98 P100\nG81 X1\nRET\nSTOPRE\nMSG(\"hi\")\nD1\nM99\nLOOP\nELSEIF R1 > 1\nM30\n");
  INFO(dump(d));
  const uint32_t cols[] = {1, 1, 6, 1, 1, 1, 1, 3, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1};
  for (uint32_t line = 1; line <= 19; ++line) {
    CAPTURE(line);
    CHECK(hasCode(d, "E110", line, cols[line - 1]));
  }
  CHECK(count(d, "E110") == 19); // one diagnostic per construct
  CHECK(d.size() == 19);
  CHECK(test::find(d, "E110")->message.find("DEF") != std::string::npos);
  auto ret = lintText("RET\nM30\n");
  REQUIRE(hasCode(ret, "E110", 1, 1));
  CHECK(test::find(ret, "E110")->message.find("M17") != std::string::npos);
}

TEST_CASE("rule E110: z32 S and T words are clean in dialect z32") { clean(lintZ32("S1000 M3\nT1 M6\nM30\n")); }

TEST_CASE("rule E110: a subprogram whose name spells another dialect's word is clean") {
  // P1 and T1 read as Fanuc words in dialect sidac, but a subprogram of the set has the name.
  auto r =
      lintFiles({{"main.mpf", "P1\nT1\nM30\n"}, {"p1.spf", "PROC P1 SAVE\nM17\n"}, {"t1.spf", "PROC T1 SAVE\nM17\n"}});
  REQUIRE(r.loaded);
  clean(r.diags);
}

// ---- E2xx: structure ----------------------------------------------------------------------------

TEST_CASE("rule E201: ELSE/ENDIF without IF, IF without ENDIF, second ELSE fire") {
  auto d = lintText("ELSE\nENDIF\nIF R1 == 1\nELSE\nELSE\nENDIF\nIF R1 == 2\nM30\n");
  fires(d, "E201", 1, 1);
  fires(d, "E201", 2, 1);
  fires(d, "E201", 5, 1);
  fires(d, "E201", 7, 1);
  CHECK(count(d, "E201") == 4);
}

TEST_CASE("rule E201: nested IF/ELSE/ENDIF is clean") {
  clean(lintText("IF R1 == 1\nIF R2 == 1\nR3 = 1\nELSE\nR3 = 2\nENDIF\nELSE\nR3 = 3\nENDIF\nM30\n"));
}

TEST_CASE("rule E202: a jump to an unknown label fires") {
  fires(lintText("GOTOF Fine\nM30\n"), "E202", 1, 7);
  fires(lintText("IF R1 == 1 THEN GOTOB Inizio\nM30\n"), "E202", 1, 23);
}

TEST_CASE("rule E202: a jump to a label of the file is clean") { clean(lintText("GOTOF Fine\nFine:\nM30\n")); }

TEST_CASE("rule E203: a duplicate label fires with a note at the first definition") {
  auto d = lintText("Uno:\nR1 = 1\nUNO: R2 = 2\nM30\n");
  fires(d, "E203", 3, 1);
  const diag::Diagnostic* e = test::find(d, "E203");
  REQUIRE(e);
  REQUIRE(e->notes.size() == 1);
  CHECK(e->notes[0].loc.line == 1);
  CHECK(e->notes[0].loc.col == 1);
  CHECK(e->notes[0].message.find("first") != std::string::npos);
}

TEST_CASE("rule E203: distinct labels are clean") { clean(lintText("Uno:\nDue:\nM30\n")); }

TEST_CASE("rule E203, E202: a thousand labels in any case are each found, and only a repeat fires") {
  // Labels every other line, as CAM output writes them: backward jumps to each, in another
  // case; one name repeated near the end, one jump to a name that is not there.
  std::string text;
  for (int i = 0; i < 1000; ++i)
    text += fmt::format("Lbl{}_x:\nIF R1 > {} GOTOB lBL{}_X\n", i, i, i);
  text += "LBL500_X:\nGOTOF lbl1000_x\nM30\n";
  auto d = lintText(text);
  fires(d, "E203", 2001, 1);
  const diag::Diagnostic* e = test::find(d, "E203");
  REQUIRE(e);
  REQUIRE(e->notes.size() == 1);
  CHECK(e->notes[0].loc.line == 1001);
  fires(d, "E202", 2002, 7);
  CHECK(d.size() == 2);
}

TEST_CASE("rule E204: GOTOF backward, GOTOF to its own line and GOTOB forward fire") {
  auto d = lintText("Su:\nGOTOF Su\nQui: IF R1 == 1 GOTOF Qui\nGOTOB Giu\nGiu:\nM30\n");
  fires(d, "E204", 2, 1);
  fires(d, "E204", 3, 17);
  fires(d, "E204", 4, 1);
  const diag::Diagnostic* e = test::find(d, "E204");
  REQUIRE(e);
  REQUIRE(e->notes.size() == 1);
  CHECK(e->notes[0].loc.line == 1);
}

TEST_CASE("rule E204: the polling idiom GOTOB to its own line is clean") {
  clean(lintText("Attesa: IF $aa_in[3] == 0 GOTOB Attesa\nAvanti:\nGOTOF Fine\nFine:\nIF R1 < 3 GOTOB Avanti\n"
                 "M30\n"));
}

TEST_CASE("rule E205: backward CASE jump fires") {
  auto d = lintText("Prima:\nCASE R1 OF 1 GOTOB Prima 2 GOTOF Prima 3 GOTO Dopo 4 GOTOF Dopo\nDopo:\nM30\n");
  fires(d, "E205", 2, 14);
  fires(d, "E205", 2, 34);
  fires(d, "E205", 2, 42);
  CHECK(count(d, "E205") == 3);
  auto self = lintText("Qui: CASE R1 OF 1 GOTOF Qui\nM30\n");
  fires(self, "E205", 1, 25);
}

TEST_CASE("rule E205: forward CASE GOTOF is clean") {
  clean(lintText("CASE R1 OF 1 GOTOF Uno 2 GOTOF Due DEFAULT GOTOF Fine\nUno:\nR2 = 1\nDue:\nR2 = 2\nFine:\nM30\n"));
}

TEST_CASE("rule E206: a subprogram without M17 fires") {
  fires(lintText("PROC Sotto SAVE\nG0 X1\n", "sotto.spf"), "E206", 2, 1);
  fires(lintText("PROC Sotto SAVE\nIF R1 == 1 GOTOF Fine\nM17\nFine:\n", "sotto.spf"), "E206", 4, 1);
}

TEST_CASE("rule E206: a skippable M17 (a '/' line) leaves the end reachable") {
  // with block skip on, /M17 is skipped and the subprogram would run off its end (SPEC §1)
  fires(lintText("PROC Sotto SAVE\nG0 X1\n/M17\n", "sotto.spf"), "E206", 3, 1);
  clean(lintText("PROC Sotto SAVE\n/G0 X1\nM17\n", "sotto.spf"));
  // the same for M30 (W405), and the lines after a /M30 are reachable (no W404)
  fires(lintText("G0 X1\n/M30\n"), "W405", 2, 1);
  clean(lintText("G0 X1\n/M30\nG0 Y1\nM30\n"));
}

TEST_CASE("rule E206: a subprogram whose every path ends in M17 is clean") {
  clean(lintText("PROC Sotto SAVE\nIF R1 == 1 GOTOF Fine\nG0 X1\nM17\nFine:\nG0 X2\nM17\n", "sotto.spf"));
}

TEST_CASE("rule E207: M17 in a main program fires") {
  fires(lintText("G0 X1\nM17\n"), "E207", 2, 1);
  fires(lintText("SEMI \"Prova\"\nIF R1 == 1 THEN M17\nM30\n"), "E207", 2, 17);
}

TEST_CASE("rule E207: M17 in a subprogram is clean") { clean(lintText("PROC Uno SAVE\nM17\n", "uno.spf")); }

TEST_CASE("rule E208: a subprogram without PROC header fires") {
  fires(lintText("G0 X1\nM17\n", "sub.spf"), "E208", 1, 1);
  fires(lintText("PROC Uno\nM17\n", "uno.spf"), "E208", 1, 1);
  fires(lintText("PROC \"Uno\" SAVE\nM17\n", "uno.spf"), "E208", 1, 6);
  fires(lintText("G0 X1\nPROC Uno SAVE\nM30\n"), "E208", 2, 1);
  fires(lintText("G0 X1\nSEMI \"Due\"\nM30\n"), "E208", 2, 1);
  fires(lintText("PROC Uno SAVE\nM17\n", "uno.mpf"), "E208", 1, 1);
  fires(lintText("SEMI \"Due\"\nM17\n", "due.spf"), "E208", 1, 1);
}

TEST_CASE("rule E208: headers after comments and blank lines are clean") {
  clean(lintText("; sottoprogramma\n\n(alza)\nPROC Alza_carrello SAVE\nG0 Z100\nM17\n", "alza.spf"));
  clean(lintText("\n; semiautomatico\nSEMI \"Carico pezzo\"\nG0 X0\nM30\n", "carico.mpf"));
}

TEST_CASE("rule E209: two subprograms with one name fire") {
  auto r =
      lintFiles({{"main.mpf", "Alza\nM30\n"}, {"a.spf", "PROC Alza SAVE\nM17\n"}, {"b.spf", "PROC ALZA SAVE\nM17\n"}});
  REQUIRE(r.loaded);
  fires(r.diags, "E209", 1, 6);
  const diag::Diagnostic* e = test::find(r.diags, "E209");
  REQUIRE(e);
  CHECK(r.fileName(e->loc.file) == "b.spf");
  REQUIRE(e->notes.size() == 1);
  CHECK(r.fileName(e->notes[0].loc.file) == "a.spf");
}

TEST_CASE("rule E209: distinct subprogram names are clean") {
  auto r = lintFiles({{"main.mpf", "Alza\nAbbassa\nM30\n"},
                      {"a.spf", "PROC Alza SAVE\nM17\n"},
                      {"b.spf", "PROC Abbassa SAVE\nM17\n"}});
  REQUIRE(r.loaded);
  clean(r.diags);
}

TEST_CASE("rule E210: a call to an unknown subprogram fires") {
  fires(lintText("G0 X0\n  Alza_carrello\nM30\n"), "E210", 2, 3);
  fires(lintText("IF R1 == 1 THEN Alza\nM30\n"), "E210", 1, 17);
}

TEST_CASE("rule E210: a call is resolved case-insensitively by PROC name, not file name") {
  auto r = lintFiles({{"main.mpf", "ALZA_CARRELLO\nM30\n"}, {"qualunque.spf", "PROC Alza_carrello SAVE\nM17\n"}});
  REQUIRE(r.loaded);
  clean(r.diags);
}

TEST_CASE("rule E211: a 31-deep call chain fires, notes show the chain") {
  auto r = lintFiles(callChain(31));
  REQUIRE(r.loaded);
  INFO(dump(r.diags));
  REQUIRE(count(r.diags, "E211") == 1);
  const diag::Diagnostic* e = test::find(r.diags, "E211");
  CHECK(r.fileName(e->loc.file) == "main.mpf");
  CHECK(e->loc.line == 2);
  CHECK(e->loc.col == 1);
  CHECK(e->message.find("31") != std::string::npos);
  CHECK(e->message.find("30") != std::string::npos);
  REQUIRE(e->notes.size() == 31);
  CHECK(r.fileName(e->notes[0].loc.file) == "main.mpf");
  CHECK(e->notes[0].message.find("Sub1") != std::string::npos);
  for (size_t i = 1; i < 31; ++i) {
    CAPTURE(i);
    CHECK(r.fileName(e->notes[i].loc.file) == fmt::format("s{}.spf", i));
    CHECK(e->notes[i].loc.line == 2);
    CHECK(e->notes[i].message.find(fmt::format("'Sub{}'", i + 1)) != std::string::npos);
  }
}

TEST_CASE("rule E211: a 30-deep call chain is clean") {
  auto r = lintFiles(callChain(30));
  REQUIRE(r.loaded);
  clean(r.diags);
}

TEST_CASE("rule E211: dialect z32 limits nesting to 10") {
  auto deep = lintFiles(callChain(11), test::builtin(), machine::Dialect::Z32);
  REQUIRE(deep.loaded);
  fires(deep.diags, "E211", 2, 1);
  CHECK(test::find(deep.diags, "E211")->notes.size() == 11);
  auto ok = lintFiles(callChain(10), test::builtin(), machine::Dialect::Z32);
  clean(ok.diags);
}

TEST_CASE("rule E212: a malformed WHEN fires") {
  fires(lintText("CANCEL\nM30\n"), "E212", 1, 1);
  // a jump in a body
  fires(lintText("F100\nWHEN $aa_iw[X] > 10 DO GOTOF L\nG1 X100\nL:\nM30\n"), "E212", 2, 24);
  // no trigger
  fires(lintText("F100\nWHEN $aa_iw[X] > 10 DO $aa_out[1] = 1\nR1 = 1\nM30\n"), "E212", 3, 1);
  // WHEN without CANCEL
  fires(lintText("F100\nWHEN $aa_iw[X] > 10 DO\n$aa_out[1] = 1\nG1 X100\nM30\n"), "E212", 2, 1);
  // label on the trigger
  fires(lintText("F100\nWHEN $aa_iw[X] > 10 DO $aa_out[1] = 1\nL: G1 X100\nM30\n"), "E212", 3, 1);
  // jump into a body from outside
  fires(lintText("F100\nIF R1 == 1 GOTOF Dentro\nWHEN $aa_iw[X] > 10 DO\nDentro: $aa_out[1] = 1\nCANCEL\n"
                 "G1 X100\nM30\n"),
        "E212", 2, 18);
  // forbidden statements in a body
  fires(lintText("F100\nWHEN $aa_iw[X] > 10 DO\nM30\nCANCEL\nG1 X100\nM30\n"), "E212", 3, 1);
  fires(lintText("F100\nWHEN $aa_iw[X] > 10 DO Alza\nG1 X100\nM30\n"), "E212", 2, 24);
  // a WHEN inside a body
  fires(lintText("F100\nWHEN $aa_iw[X] > 10 DO\nWHEN $aa_iw[X] > 20 DO\nCANCEL\nG1 X100\nM30\n"), "E212", 3, 1);
  // an inner body that is not one path instruction
  fires(lintText("F100\nWHEN $aa_iw[Y] > 10 DO\n$aa_out[1] = 1\nCANCEL\nWHEN $aa_iw[X] > 10 DO\nR1 = 1\nCANCEL\n"
                 "G1 X100\nM30\n"),
        "E212", 5, 1);
}

TEST_CASE("rule E212: a chain of four WHENs fires at the fourth") {
  auto d = lintText("F100\n"
                    "WHEN $aa_iw[Y] > 50 DO\n$aa_out[3] = 1\nCANCEL\n"
                    "WHEN $aa_iw[X] > 20 DO\nPos[Y]=100\nCANCEL\n"
                    "WHEN $aa_iw[Z] > 20 DO\nPos[X]=100\nCANCEL\n"
                    "WHEN $aa_iw[A] > 20 DO\nPos[Z]=100\nCANCEL\n"
                    "G1 A100\nM30\n");
  fires(d, "E212", 11, 1);
  CHECK(count(d, "E212") == 1);
  REQUIRE(test::find(d, "E212")->notes.size() == 1);
  CHECK(test::find(d, "E212")->notes[0].loc.line == 2); // the chain starts here
}

TEST_CASE("rule E212: long, short and chained (3) WHEN forms are clean") {
  clean(lintText("F100\n"
                 "WHEN $aa_iw[X] > 50 DO\n$aa_out[3] = 1\nR5 = 2\nM=NB(34)\nG04 F1\nCANCEL\n"
                 "G1 X100\n"
                 "WHEN $aa_iw[X] < 10 DO $aa_marker[4] = 1\n"
                 "X0\n"
                 "WHEN $aa_iw[Y] > 50 DO\n$aa_out[3] = 1\nCANCEL\n"
                 "; the chain continues\n"
                 "WHEN $aa_iw[X] > 20 DO\nPos[Y]=100\nCANCEL\n"
                 "WHEN $aa_iw[Z] > 20 DO\nPos[X]=100\nCANCEL\n"
                 "G1 Z100\n"
                 "M30\n"));
}

TEST_CASE("rule E213: a trigger that does not move the condition's axis fires") {
  auto d = lintText("F100\nWHEN $aa_iw[X] > 10 DO $aa_out[1] = 1\nG1 Y100\nM30\n");
  fires(d, "E213", 2, 1);
  REQUIRE(test::find(d, "E213")->notes.size() == 1);
  CHECK(test::find(d, "E213")->notes[0].loc.line == 3);
  fires(lintText("F100\nWHEN $aa_iw[X] > 10 DO $aa_out[1] = 1\nPosa[X]=100\nM30\n"), "E213", 2, 1);
  fires(lintText("F100\nWHEN $aa_in[1] == 1 DO $aa_out[1] = 1\nG1 X100\nM30\n"), "E213", 2, 1);
}

TEST_CASE("rule E213: a blocking trigger of the condition's axis is clean") {
  clean(lintText("F100\nWHEN $aa_iw[X] > 10 DO $aa_out[1] = 1\nPos[X]=100 Y10\n"
                 "WHEN ($aa_iw[X] < 50) AND ($aa_in[2] == 1) DO $aa_out[1] = 0\nX=0\nM30\n"));
}

TEST_CASE("rule E214: a PROC name that reads as words fires") {
  fires(lintText("PROC G10 SAVE\nM17\n", "g10.spf"), "E214", 1, 6);
  fires(lintText("PROC X5Y2 SAVE\nM17\n", "x.spf"), "E214", 1, 6);
  fires(lintText("PROC S1 SAVE\nM17\n", "s.spf", test::builtin(), machine::Dialect::Z32), "E214", 1, 6);
}

TEST_CASE("rule E214: PROC names that do not read as words are clean") {
  clean(lintText("PROC G10_piano SAVE\nM17\n", "g.spf"));
  clean(lintText("PROC Xy SAVE\nM17\n", "x.spf"));
  clean(lintText("PROC S1 SAVE\nM17\n", "s.spf")); // S is no address in dialect sidac
}

// ---- E3xx: values and blocks ------------------------------------------------------------------------

TEST_CASE("rule E215: a z32 GO whose target no line begins with fires") {
  fires(lintZ32("G0 X0\nGON10\n  N10 X1\nM30\n"), "E215", 2, 3); // blanks before N: never found
  fires(lintZ32("G0 X0\nN20 X1\nGON20-N30\nM30\n"), "E215", 3, 7);
}
TEST_CASE("rule E215: GO jumps and ranges to lines that begin with the target are clean") {
  clean(lintZ32("G0 X0\n!GON20!\nN10 X1\nN20 X2\nGON10-N20\nM30\n"));
}

TEST_CASE("rule E301: R0 and constant R indices outside 1..2880 fire") {
  auto d = lintText("R0 = 1\nR2881 = 1\nR1 = R[0]\nR1 = R[2880 + 1]\nR1 = R1,5\nR[3] = R0\nM30\n");
  fires(d, "E301", 1, 1);
  fires(d, "E301", 2, 1);
  fires(d, "E301", 3, 6);
  fires(d, "E301", 4, 6);
  fires(d, "E301", 5, 6);
  fires(d, "E301", 6, 8);
  CHECK(d.size() == 6);
}

TEST_CASE("rule E301: R1, R2880 and computed indices are clean") {
  clean(lintText("R1 = 1\nR2880 = R[2880] + R[R1]\nR[1 + 1] = 2\nM30\n"));
}

TEST_CASE("rule E302: an axis the machine does not have fires") {
  machine::Machine m = xyzMachine();
  fires(lintText("G0 A10\nM30\n", "t.mpf", m), "E302", 1, 4);
  fires(lintText("R1 = $aa_iw[B]\nM30\n", "t.mpf", m), "E302", 1, 6);
  fires(lintText("G0 Pos[U]=1\nM30\n", "t.mpf", m), "E302", 1, 4);
  // a name that is not a letter (found by the simulate fuzzer: isocc used to fail its image check)
  fires(lintText("G0 Pos[_]=1\nM30\n", "t.mpf", m), "E302", 1, 8);
  fires(lintText("R1 = $aa_iw[_]\nM30\n", "t.mpf", m), "E302", 1, 13);
  // and in the assignment form (found by the source fuzzer: isocc wrote axis '_' into the image and failed its check)
  fires(lintText("_ = 25\nM30\n", "t.mpf", m), "E302", 1, 1);
  fires(lintText("G01 _=25 F100\nM30\n", "t.mpf", m), "E302", 1, 5);
}

TEST_CASE("rule E302: the machine's axes are clean") {
  clean(lintText("G0 X10 Y10 Z10\nR1 = $aa_iw[z]\nM30\n", "t.mpf", xyzMachine()));
}

TEST_CASE("rule E303: one axis twice in a block fires") {
  auto d = lintText("G0 X1 Pos[x]=3\nM30\n");
  fires(d, "E303", 1, 7);
  REQUIRE(test::find(d, "E303")->notes.size() == 1);
  CHECK(test::find(d, "E303")->notes[0].loc.col == 4);
  // Fa for one axis twice
  fires(lintText("G01 X10 Fa[X]=5 Fa[X]=6 F10\nM30\n"), "E303", 1, 17);
}

TEST_CASE("rule E303: distinct axes are clean") { clean(lintText("G0 X1 Y2 Pos[Z]=3 Posa[A]=4\nM30\n")); }

TEST_CASE("rule E304: Fa for an axis that does not move fires") {
  fires(lintText("G1 Fa[Y]=10 X10\nM30\n"), "E304", 1, 4);
}

TEST_CASE("rule E304: Fa for a moving axis is clean") {
  clean(lintText("G1 Fa[X]=10 X10\nG1 Fa[X]=10 Fa[Y]=20 X0 Y10\nM30\n"));
}

TEST_CASE("rule E305: machine data not as the whole right side fires") {
  fires(lintText("R1 = $MAX_VELO[X] + 1\nM30\n"), "E305", 1, 6);
  fires(lintText("G0 X=$POS_LIMIT_PLUS[X]\nM30\n"), "E305", 1, 6);
  fires(lintText("IF $MAX_VELO[X] > 100 GOTOF E\nE:\nM30\n"), "E305", 1, 4);
  fires(lintText("R1 = ($MAX_VELO[X])\nM30\n"), "E305", 1, 7);
}

TEST_CASE("rule E305: machine data as the whole right side of R = is clean") {
  clean(lintText("R1 = $MAX_VELO[X]\nR2 = $POS_LIMIT_PLUS[Y]\nR3 = $POS_LIMIT_MINUS[Z]\nM30\n"));
}

TEST_CASE("rule E306: assignment to a read-only variable fires") {
  fires(lintText("$aa_in[1] = 1\nM30\n"), "E306", 1, 1);
  fires(lintText("$AA_IW[X] = 3\nM30\n"), "E306", 1, 1);
  fires(lintText("$aa_fw[X] = 3\nM30\n"), "E306", 1, 1);
  fires(lintText("$MAX_VELO[X] = 3\nM30\n"), "E306", 1, 1);
  fires(lintText("G0 X1 $POS_LIMIT_MINUS[X] = 3\nM30\n"), "E306", 1, 7);
}

TEST_CASE("rule E306: writing outputs and markers is clean") {
  clean(lintText("$aa_out[1] = 1\n$AA_MARKER[2] = 0\nG0 X1 $aa_out[3] = R1\nM30\n"));
}

TEST_CASE("rule E307: I/O indices out of range fire") {
  auto d =
      lintText("$aa_marker[201] = 1\n$aa_out[256] = 0\nR1 = $aa_in[256]\nR1 = $aa_in[-1]\nR1 = $aa_in[1.5]\nM30\n");
  fires(d, "E307", 1, 12);
  fires(d, "E307", 2, 9);
  fires(d, "E307", 3, 13);
  fires(d, "E307", 4, 13);
  fires(d, "E307", 5, 13);
  // the machine's own ranges
  auto m = lintText("$aa_out[8] = 0\nR1 = $aa_in[16]\nM30\n", "t.mpf", xyzMachine());
  fires(m, "E307", 1, 9);
  fires(m, "E307", 2, 13);
}

TEST_CASE("rule E307: I/O indices at the range ends are clean") {
  clean(lintText("$aa_marker[0] = 1\n$aa_marker[200] = 1\n$aa_out[255] = 0\nR1 = $aa_in[0] + $aa_in[255]\nM30\n"));
  clean(lintText("$aa_out[7] = 0\nR1 = $aa_in[15]\nM30\n", "t.mpf", xyzMachine()));
}

TEST_CASE("rule E308: a constant other than 0 or 1 written to an output fires") {
  fires(lintText("$aa_out[1] = 2\nM30\n"), "E308", 1, 14);
  fires(lintText("$aa_marker[1] = 0.5\nM30\n"), "E308", 1, 17);
  fires(lintText("$aa_out[1] = -1\nM30\n"), "E308", 1, 14);
}

TEST_CASE("rule E308: 0, 1 and computed values are clean") {
  clean(lintText("$aa_out[1] = 0\n$aa_out[1] = 1\n$aa_out[1] = 2 - 1\n$aa_marker[1] = R5\nM30\n"));
}

TEST_CASE("rule E309: G04 without F or with motion fires") {
  fires(lintText("G04\nM30\n"), "E309", 1, 1);
  fires(lintText("G04 F1 X10\nM30\n"), "E309", 1, 8);
  fires(lintText("G04 F-1\nM30\n"), "E309", 1, 5);
}

TEST_CASE("rule E309: G04 with F seconds is clean") {
  clean(lintText("G04 F1\nG4 F=0.5\nR1 = 2\nG04 F=R1\nF2 G04\nG01 F100 G04\nM30\n"));
}

TEST_CASE("rule E310: an unknown G code fires") {
  fires(lintText("G7\nM30\n"), "E310", 1, 1);
  fires(lintText("G0 G1.5 X1\nM30\n"), "E310", 1, 4);
}

TEST_CASE("rule E310: every G code of SPEC 4.2 is clean") {
  clean(lintText("G00 G90 G60 G17\nG01 F100 G91 G64 G18\nG0 G19\nG4 F1\nM30\n"));
}

TEST_CASE("rule E311: malformed arcs fire") {
  fires(lintText("F100\nG2 X10 Y0\nM30\n"), "E311", 2, 1);            // no centre or radius
  fires(lintText("F100\nG2 X10 Y0 Z5 I5\nM30\n"), "E311", 2, 11);     // third axis
  fires(lintText("F100\nG2 X10 Y0 I5 K1\nM30\n"), "E311", 2, 14);     // K not in G17
  fires(lintText("F100\nG2 X10 Y1 I5\nM30\n"), "E311", 2, 11);        // end off the circle
  fires(lintText("F100\nG2 X0 Y0 CR=5\nM30\n"), "E311", 2, 10);       // CR full circle
  fires(lintText("F100\nG2 X10 Y0 CR=4\nM30\n"), "E311", 2, 11);      // radius too small
  fires(lintText("F100\nG2 X10 Y0 CR=5 I5\nM30\n"), "E311", 2, 11);   // both
  fires(lintText("F100\nG2 Fa[X]=1 X10 Y0 I5\nM30\n"), "E311", 2, 4); // Fa
  fires(lintText("F100\nG2 Posa[X]=10 Y0 I5\nM30\n"), "E311", 2, 4);  // Posa
  fires(lintText("F100\nG1 X10 I5\nM30\n"), "E311", 2, 8);            // centre without arc
  fires(lintText("F100\nG2 X0 Y0 J1 J0\nM30\n"), "E311", 2, 13);      // a centre word twice
  fires(lintText("F100\nG2 X10 Y0 CR=5 CR=6\nM30\n"), "E311", 2, 16); // CR twice
}

TEST_CASE("rule E311: well-formed arcs are clean") {
  clean(lintText("F100\nG17 G90\nG2 X10 Y0 I5 J0\nG3 X0 Y0 I-5\nG2 X0 Y0 I5\nG2 X10 Y0 CR=5\n"
                 "G3 X0 Y0 CR=-5\nG18 G2 Z10 X0 K5\nG19 G3 Y10 Z10 J5\nG91 G17 G2 X10 Y0 I5\nM30\n"));
}

TEST_CASE("rule E312: malformed M functions fire") {
  fires(lintText("M1.5\nM30\n"), "E312", 1, 1);
  fires(lintText("M=NB(R1)\nM30\n"), "E312", 1, 6);
  fires(lintText("M=NB(17)\nM30\n"), "E312", 1, 6);
  fires(lintText("M=NB(0)\nM30\n"), "E312", 1, 6);
  fires(lintText("M=NB(30)\nM30\n"), "E312", 1, 6);
  fires(lintText("M=34\nM30\n"), "E312", 1, 3);
  fires(lintText("G0 X0 M0 M30\n"), "E312", 1, 10);
  fires(lintText("M5 Alza\nM30\n"), "E312", 1, 4);
  // a call then M, the other order of SPEC §7 E312 (was E100)
  for (const char* line : {"Alza M23", "Alza M=NB(23)", "Alza M30"}) {
    CAPTURE(line);
    auto d = lintText(std::string(line) + "\nM30\n");
    fires(d, "E312", 1, 1);
    CHECK(test::find(d, "E312")->message == "a call ('Alza') must stand alone on its line, not with M functions");
    CHECK(!hasCode(d, "E100"));
  }
}

TEST_CASE("rule E312: well-formed M functions are clean") {
  clean(lintText("M=NB(34)\nM23 M24\nM00\nM35\nM30\n"));
  // any non-negative integer literal of up to 9 digits (SPEC §4.5, §2)
  clean(lintText("M1000000\nM=NB(999999999)\nM30\n"));
}

// ---- W4xx: warnings ------------------------------------------------------------------------------------

namespace {
machine::Machine z32Origins() {
  machine::Machine m = machine::builtinMachine();
  m.dialect = machine::Dialect::Z32;
  m.origins = {{1, {{'X', 100.0}}}, {2, {{'Z', -20.0}}}};
  m.builtin = false; // as read from a machine file
  return m;
}
} // namespace
TEST_CASE("rule E313: O with an origin the machine file lacks fires") {
  fires(lintText("G0 X0\nO5 X1\nM30\n", "t.mpf", z32Origins()), "E313", 2, 1);
}
TEST_CASE("rule E313: the machine's origins and O0 are clean") {
  clean(lintText("O1\nG0 X1\nO2 Z0\nO0\nM30\n", "t.mpf", z32Origins()));
}

TEST_CASE("rule W401: two G codes of one group fire") {
  auto d = lintText("G0 G1 X1 F10\nG90 G91 X1\nG60 G64\nG17 G18\nM30\n");
  fires(d, "W401", 1, 4);
  fires(d, "W401", 2, 5);
  fires(d, "W401", 3, 5);
  fires(d, "W401", 4, 5);
}

TEST_CASE("rule W401: G codes of different groups are clean") { clean(lintText("G1 G91 G64 G18 X1 F10\nM30\n")); }

TEST_CASE("rule W402: a feed move with no F fires") {
  fires(lintText("G1 X10\nM30\n"), "W402", 1, 4);
  fires(lintText("G04 F2\nG1 X10\nM30\n"), "W402", 2, 4); // a dwell time is no feed
  fires(lintText("G2 X10 Y0 I5\nM30\n"), "W402", 1, 4);
  fires(lintText("G1 Fa[X]=10 X10 Y5\nM30\n"), "W402", 1, 13); // Y has no feed
  fires(lintText("F0\nG1 X10\nM30\n"), "W402", 2, 4);          // F <= 0 (SPEC 4.3)
  fires(lintText("G1 X10 F=-5\nM30\n"), "W402", 1, 4);
}

TEST_CASE("rule W402: F earlier in the file or on the line is clean") {
  clean(lintText("F=100\nG1 X10\nM30\n"));
  clean(lintText("G1 X10 F100\nG2 X20 Y0 I5\nM30\n"));
  clean(lintText("G1 Fa[X]=10 X10\nG0 Y10\nM30\n"));
  clean(lintText("F=R1\nG1 X10\nM30\n"));                 // not a constant: checked at run time
  clean(lintText("IF R1 == 1 THEN F100\nG1 X10\nM30\n")); // an F earlier in the file
}

TEST_CASE("rule W403: Pos and Posa mixed in an interpolated block fires") {
  fires(lintText("G1 Pos[X]=1 Posa[Y]=2 F100\nM30\n"), "W403", 1, 1);
}

TEST_CASE("rule W403: a mix in rapid or independent blocks is clean") {
  clean(lintText("G0 Pos[X]=1 Posa[Y]=2\nG1 F100 X0 Y0 Z0 Posa[A]=1\nG1 Pos[X]=1 Posa[Y]=2 Fa[X]=100\nM30\n"));
}

TEST_CASE("rule W404: code after M30 or an unconditional jump fires") {
  fires(lintText("M30\nR1 = 1\nR2 = 2\n"), "W404", 2, 1);
  fires(lintText("GOTOF Fine\nN10 R1 = 1\nFine:\nM30\n"), "W404", 2, 1);
  fires(lintText("CASE R1 OF 1 GOTOF A DEFAULT GOTOF B\nR2 = 1\nA:\nB:\nM30\n"), "W404", 2, 1);
  auto d = lintText("M30\nR1 = 1\nR2 = 2\n");
  CHECK(count(d, "W404") == 1); // one diagnostic per run of lines
}

TEST_CASE("rule W404: IF bodies ending in M30 or a jump leave no dead ELSE/ENDIF") {
  clean(lintText("IF R1 == 1\nM30\nELSE\nR2 = 1\nENDIF\nIF R2 == 1\nGOTOF Fine\nENDIF\nR3 = 1\nFine:\nM30\n"));
}

TEST_CASE("rule W405: a main program whose end is reachable without M30 fires") {
  fires(lintText("G0 X1\nG0 X2\n"), "W405", 2, 1);
  fires(lintText("SEMI \"Prova\"\nIF R1 == 1 GOTOF Fine\nM30\nFine:\n"), "W405", 4, 1);
}

TEST_CASE("rule W405: a main program ending in M30 on every path is clean") {
  clean(lintText("IF R1 == 1 GOTOF Fine\nM30\nFine:\nG0 X0 M30\n"));
  clean(lintText("S1 M3\nM2\n", "t.mpf", test::builtin(), machine::Dialect::Z32)); // z32: M2 ends the program
}

TEST_CASE("rule W406: division by a constant zero fires") {
  fires(lintText("R1 = 1 / 0\nM30\n"), "W406", 1, 10);
  fires(lintText("R1 = R2 / (3 - 3)\nM30\n"), "W406", 1, 12);
}

TEST_CASE("rule W406: division by a non-zero or unknown value is clean") {
  clean(lintText("R1 = 1 / 2\nR2 = 1 / R1\nM30\n"));
}

TEST_CASE("rule W407: $MAX_LIMIT_PLUS fires") {
  fires(lintText("R1 = $MAX_LIMIT_PLUS[X]\nM30\n"), "W407", 1, 6);
  fires(lintText("R1 = $max_limit_minus[X]\nM30\n"), "W407", 1, 6);
}

TEST_CASE("rule W407: $POS_LIMIT_PLUS is clean") { clean(lintText("R1 = $POS_LIMIT_PLUS[X]\nM30\n")); }

TEST_CASE("rule W408: GOTO without direction fires") {
  auto d = lintText("GOTO Fine\nFine:\nIF R1 < 3 GOTO Fine\nM30\n");
  fires(d, "W408", 1, 1);
  fires(d, "W408", 3, 11);
  CHECK(test::find(d, "W408")->message.find("GOTOF") != std::string::npos);
}

TEST_CASE("rule W408: GOTOF and GOTOB are clean") { clean(lintText("GOTOF Fine\nFine:\nIF R1 < 3 GOTOB Fine\nM30\n")); }

TEST_CASE("rule W409: a recursive call chain fires") {
  auto r = lintFiles({{"main.mpf", "Uno\nM30\n"},
                      {"uno.spf", "PROC Uno SAVE\nIF R1 < 3 THEN Due\nM17\n"},
                      {"due.spf", "PROC Due SAVE\nR1 = R1 + 1\nUno\nM17\n"}});
  REQUIRE(r.loaded);
  INFO(dump(r.diags));
  REQUIRE(count(r.diags, "W409") == 1);
  CHECK(count(r.diags, "E211") == 0);
  const diag::Diagnostic* w = test::find(r.diags, "W409");
  CHECK(w->loc.line == 3);
  CHECK(r.fileName(w->loc.file) == "due.spf");
  auto self = lintFiles({{"main.mpf", "Uno\nM30\n"}, {"uno.spf", "PROC Uno SAVE\nIF R1 < 3 THEN Uno\nM17\n"}});
  fires(self.diags, "W409", 2, 16);
}

TEST_CASE("rule W409: a subprogram called twice (no cycle) is clean") {
  auto r = lintFiles(
      {{"main.mpf", "Uno\nDue\nM30\n"}, {"uno.spf", "PROC Uno SAVE\nDue\nM17\n"}, {"due.spf", "PROC Due SAVE\nM17\n"}});
  REQUIRE(r.loaded);
  clean(r.diags);
}

TEST_CASE("rule W410: a constant absolute target outside the soft limits fires") {
  fires(lintText("G0 X3000.001\nM30\n"), "W410", 1, 4);
  fires(lintText("G0 Pos[Y]=-1001\nM30\n"), "W410", 1, 4);
  fires(lintText("G90 G1 F100 Z=4000\nM30\n"), "W410", 1, 13);
}

TEST_CASE("rule W410: targets at the limits and incremental moves are clean") {
  clean(lintText("G0 X3000 Y-1000\nG91 X5000\nG90 X=R1 * 10000\nM30\n"));
}

TEST_CASE("rule W423: a constant absolute end point inside a forbidden zone fires") {
  machine::Machine m = test::builtin();
  m.zones.push_back(machine::Zone{"morsa", true, {{'X', 40, 60}, {'Y', -5, 5}}});
  auto d = lintText("G0 X50 Y0\nM30\n", "t.mpf", m);
  fires(d, "W423", 1, 4);
  CHECK(test::find(d, "W423")->message.find("'morsa'") != std::string::npos);
  fires(lintText("G90 G1 F100 X=60 Y=-5\nM30\n", "t.mpf", m), "W423", 1, 13);
}

TEST_CASE("rule W423: end points outside, not all axes programmed, incremental or warn zones are clean") {
  machine::Machine m = test::builtin();
  m.zones.push_back(machine::Zone{"morsa", true, {{'X', 40, 60}, {'Y', -5, 5}}});
  m.zones.push_back(machine::Zone{"probe", false, {{'Z', -10, 10}}});
  clean(lintText("G0 X50 Y6\nG0 X50\nG91 X50 Y0\nG90 X=R1 Y0\nG0 Z0\nM30\n", "t.mpf", m));
}

TEST_CASE("rule W411: a duplicate line number fires") {
  auto d = lintText("N10 G0 X0\nN20 G0 X1\nN10 G0 X2\nN132,5 G0 X3\nN132,5 M30\n");
  fires(d, "W411", 3, 1);
  fires(d, "W411", 5, 1);
  REQUIRE(test::find(d, "W411")->notes.size() == 1);
  CHECK(test::find(d, "W411")->notes[0].loc.line == 1);
  // the number as written, with its separator
  const diag::Diagnostic* last = nullptr;
  for (const auto& x : d)
    if (x.loc.line == 5) last = &x;
  REQUIRE(last != nullptr);
  CHECK(last->message == "line number N132,5 is used twice in this file");
}

TEST_CASE("rule W411: distinct line numbers are clean") { clean(lintText("N10 G0 X0\nN10.5 G0 X1\nN20 M30\n")); }

TEST_CASE("rule W411: numbers are compared as written (SPEC §2): N132,5 is not N132.5, N10 is not N010") {
  clean(lintText("N132,5 G0 X0\nN132.5 G0 X1\nN10 G0 X2\nN010 G0 X3\nN10.0 M30\n"));
}

TEST_CASE("rule W412: a jump into an IF body from outside fires") {
  fires(lintText("GOTOF Dentro\nIF R1 == 1\nDentro:\nR2 = 1\nENDIF\nM30\n"), "W412", 1, 7);
  fires(lintText("CASE R1 OF 1 GOTOF Dentro\nIF R1 == 1\nR2 = 2\nELSE\nDentro: R2 = 1\nENDIF\nM30\n"), "W412", 1, 20);
}

TEST_CASE("rule W412: jumps inside one body or past ENDIF are clean") {
  clean(lintText("IF R1 == 1\nIF R3 == 1 GOTOF Dentro\nR2 = 2\nDentro:\nR2 = 1\nENDIF\n"
                 "IF R4 == 1 GOTOF Dopo\nIF R1 == 2\nR3 = 1\nENDIF\nDopo:\nM30\n"));
}

TEST_CASE("rule W413: a duplicate CASE value fires") {
  auto d = lintText("CASE R1 OF 1 GOTOF A 2 GOTOF B 1,0 GOTOF B\nA:\nB:\nM30\n");
  fires(d, "W413", 1, 32);
  REQUIRE(test::find(d, "W413")->notes.size() == 1);
  CHECK(test::find(d, "W413")->notes[0].loc.col == 12);
}

TEST_CASE("rule W413: distinct CASE values are clean") {
  clean(lintText("CASE R1 OF 1 GOTOF A -1 GOTOF B 1.5 GOTOF B\nA:\nB:\nM30\n"));
}

TEST_CASE("rule W414: Fa on a G00 line fires") { fires(lintText("G0 Fa[X]=10 X10\nM30\n"), "W414", 1, 4); }

TEST_CASE("rule W414: Fa on a G01 line is clean") { clean(lintText("G1 Fa[X]=10 X10\nM30\n")); }

TEST_CASE("rule W422: a constant F above every axis' max_velocity on a feed move fires") {
  // the built-in machine: every axis 500 mm/s
  auto d = lintText("G1 X100 F6000\nM30\n");
  fires(d, "W422", 1, 9); // at the F word
  REQUIRE(count(d, "W422") == 1);
  CHECK(test::find(d, "W422")->message ==
        "F6000 mm/s is above the fastest axis' max_velocity (500 mm/s, axis X): the axes' limits set the speed; F is "
        "in mm/s, so 6000 mm/min is F100");
  CHECK(test::find(d, "W422")->notes.empty());
  // F on a line of its own: the warning at the F, a note at the first feed move, once per F word
  auto later = lintText("F=1000\nG0 X10\nG2 X20 CR=5\nG1 X30\nF1000\nG1 X40\nM30\n");
  fires(later, "W422", 1, 1);
  fires(later, "W422", 5, 1);
  CHECK(count(later, "W422") == 2);
  REQUIRE(test::find(later, "W422")->notes.size() == 1);
  CHECK(test::find(later, "W422")->notes[0].loc.line == 3);
  CHECK(test::find(later, "W422")->message.find("so 1000 mm/min is F16.667") != std::string::npos);
  // the fastest axis of the machine decides
  machine::Machine m = xyzMachine();
  m.axes[1].maxVelocity = 2000;
  auto fast = lintText("G1 X10 F2500\nM30\n", "t.mpf", m);
  fires(fast, "W422", 1, 8);
  REQUIRE(count(fast, "W422") == 1);
  CHECK(test::find(fast, "W422")->message.find("(2000 mm/s, axis Y)") != std::string::npos);
}

TEST_CASE("rule W422: F within max_velocity, F on rapid moves and F not a constant are clean") {
  clean(lintText("G1 X100 F500\nM30\n"));
  clean(lintText("G0 X100 F6000\nF100\nG1 X0\nM30\n"));         // replaced before a feed move uses it
  clean(lintText("R1 = 6000\nG1 X100 F=R1\nM30\n"));            // not a constant
  clean(lintText("G1 Fa[X]=10 X10 F6000\nF100\nG1 X0\nM30\n")); // X runs at its own Fa
  clean(lintText("G4 F6000\nG1 X10 F100\nM30\n"));              // a dwell time
  machine::Machine m = xyzMachine();
  m.axes[1].maxVelocity = 2000;
  clean(lintText("G1 X10 F1500\nM30\n", "t.mpf", m));
}

namespace {
/// The built-in machine in dialect z32 with special M6 -> CAMBIO and M40 -> PALLET.
machine::Machine z32Special() {
  machine::Machine m = machine::builtinMachine();
  m.dialect = machine::Dialect::Z32;
  m.specialM = {{6, "CAMBIO"}, {40, "PALLET"}};
  return m;
}
const std::vector<std::pair<std::string, std::string>> kSpecialSubs = {{"cambio.spf", "PROC CAMBIO SAVE\nM17\n"},
                                                                       {"pallet.spf", "PROC PALLET SAVE\nM17\n"}};
test::SetResult lintSpecial(const std::string& main) {
  auto files = kSpecialSubs;
  files.push_back({"main.mpf", main});
  return lintFiles(files, z32Special());
}
} // namespace

TEST_CASE("rule W415: a special M with motion and M8 after it on its line fires") {
  auto r = lintSpecial("G0 X10\nM40 X5 M8\nM30\n");
  REQUIRE(r.loaded);
  fires(r.diags, "W415", 2, 1);
  CHECK(test::find(r.diags, "W415")->message.find("the move of X and M8 never run") != std::string::npos);
  CHECK(!hasCode(r.diags, "I501", 2, 0)); // the motion never runs: no "M first" note
}
TEST_CASE("rule W415: a special M alone, or M3 before it, is clean") {
  auto r = lintSpecial("S100 M3 M40\nT1 M6\nM30\n");
  REQUIRE(r.loaded);
  clean(r.diags);
}
TEST_CASE("rule W415: a special M6 fires for the final M after it") {
  auto r = lintSpecial("T2 X1 M6 M30\nM30\n");
  REQUIRE(r.loaded);
  fires(r.diags, "W415", 1, 7);
  CHECK(test::find(r.diags, "W415")->message.find("M30 never runs") != std::string::npos);
}

TEST_CASE("rule W416: a constant MA whose sent value is clamped fires") {
  fires(lintZ32("MA12345\nMB-5000\nM30\n"), "W416", 1, 1);
  fires(lintZ32("MA12345\nMB-5000\nM30\n"), "W416", 2, 1);
}
TEST_CASE("rule W416: MA values that fit (seed 004 table) are clean") {
  clean(lintZ32("MA-100\nMA8100\nMA-1\nMB-1040\nMA-0\nMA9999\nMC-1999.9\nMA=R1*1000\nM30\n"));
}

TEST_CASE("rule W417: M3 with no S earlier fires") { fires(lintZ32("M3\nS100\nM4\nM30\n"), "W417", 1, 1); }
TEST_CASE("rule W417: M3 with S on its line or earlier is clean") { clean(lintZ32("M3 S500\nM5\nM4\nM30\n")); }

TEST_CASE("rule W418: M6 with no T earlier fires") { fires(lintZ32("M6\nT1\nM30\n"), "W418", 1, 1); }
TEST_CASE("rule W418: M6 with T on its line is clean") { clean(lintZ32("M6 T3\nM6\nM30\n")); }

TEST_CASE("rule W419: an unknown code or name in an inline suppression fires") {
  auto d = lintText("G1 X10 F100 ; isolint: disable=W999\nR1 = 1 ; isolint: disable=feed-unset,no-such-rule\nM30\n");
  fires(d, "W419", 1, 32);
  fires(d, "W419", 2, 38);
  CHECK(count(d, "W419") == 2);
}

TEST_CASE("rule W419: known codes and names in suppressions are clean") {
  clean(lintText("G1 X10 F100 ; isolint: disable=W402,g-conflict\n; isolint: disable-file=E301\nM30\n"));
}

TEST_CASE("rule W420: a z32 function that is not modelled fires, once per code") {
  auto d = lintZ32("G84 X10\nG84 X20\nG0 X0\nM30\n");
  fires(d, "W420", 1, 1);
  CHECK(count(d, "W420") == 1);
}
TEST_CASE("rule W420: the modelled z32 G codes are clean") { clean(lintZ32("G29X\nG28X\nG0 X1\nM30\n")); }

TEST_CASE("rule I501: a line with M functions and motion fires") {
  auto d = lintText("G0 X10 M5\nM30\n");
  fires(d, "I501", 1, 8);
  CHECK(d.at(0).severity == diag::Severity::Info);
}

TEST_CASE("rule I501: M and motion on separate lines, and the end functions, are clean") {
  clean(lintText("M5\nG0 X10\nM=NB(34)\nG0 X0\nM30\n"));
  // M30 is ordered after the motion: the statement is the common "G00 X0 M30".
  CHECK(count(lintText("G0 X0 M30\n"), "I501") == 0);
}

// ---- the table is covered ------------------------------------------------------------------------------

TEST_CASE("rules: every code of Diagnostics.def has a firing and a clean test") {
  std::ifstream in(std::string(ISO_SOURCE_DIR) + "/tests/unit/frontend/RuleTests.cpp");
  REQUIRE(in);
  std::stringstream ss;
  ss << in.rdbuf();
  std::string src = ss.str();
  std::set<std::string> fired, cleaned;
  std::regex name(R"re(TEST_CASE\("rule ([EWI][0-9]{3}): ([^"]*)"\))re");
  for (auto it = std::sregex_iterator(src.begin(), src.end(), name); it != std::sregex_iterator(); ++it) {
    std::string text = (*it)[2];
    if (text.find("fire") != std::string::npos)
      fired.insert((*it)[1]);
    else
      cleaned.insert((*it)[1]);
  }
  for (size_t i = 0; i < diag::codeCount(); ++i) {
    std::string code = diag::info(static_cast<diag::Code>(i)).code;
    CAPTURE(code);
    CHECK(fired.count(code) == 1);
    CHECK(cleaned.count(code) == 1);
  }
  CHECK(fired.size() == diag::codeCount());
}

// ---- suppressions and --disable ------------------------------------------------------------------------

namespace {
std::vector<diag::Diagnostic> visible(const std::string& text, const std::vector<diag::Code>& disabled = {},
                                      bool werror = false) {
  auto set = test::loadText(text);
  driver::filterDiagnostics(*set, {disabled, werror, false, {}});
  return set->diags.items();
}
} // namespace

TEST_CASE("suppress: comment 'isolint: disable=W402' hides that line only") {
  auto d = visible("G1 X10 ; isolint: disable=W402\nG1 X20\nM30\n");
  INFO(dump(d));
  CHECK_FALSE(hasCode(d, "W402", 1));
  CHECK(hasCode(d, "W402", 2));
}

TEST_CASE("suppress: a comment on the last line of a $ continuation covers the whole logical line") {
  auto d = visible("G1 X10 $\nY20 ; isolint: disable=W402\nG1 X20\nM30\n");
  INFO(dump(d));
  CHECK_FALSE(hasCode(d, "W402", 1));
  CHECK(hasCode(d, "W402", 3));
}

TEST_CASE("suppress: a list of codes and names, other codes stay") {
  auto d = visible("G1 X10 R1 = 1/0 ; isolint: disable=W402,div-zero\nG0 G1 X1 ; isolint: disable=W402\nM30\n");
  INFO(dump(d));
  CHECK(count(d, "W402") == 0);
  CHECK(count(d, "W406") == 0);
  CHECK(hasCode(d, "W401", 2));
}

TEST_CASE("suppress: comment 'isolint: disable-file=W402' hides the whole file") {
  auto d = visible("; isolint: disable-file=W402\nG1 X10\nG1 X20\nM30\n");
  CHECK(count(d, "W402") == 0);
  auto late = visible("G1 X10\nG1 X20\nM30 ; isolint: disable-file=feed-unset\n");
  CHECK(count(late, "W402") == 0);
}

TEST_CASE("suppress: errors can be suppressed too, unknown names suppress nothing (W419)") {
  auto d = visible("R0 = 1 ; isolint: disable=E301\nR0 = 2 ; isolint: disable=no-such-rule\nM30\n");
  INFO(dump(d));
  CHECK_FALSE(hasCode(d, "E301", 1));
  CHECK(hasCode(d, "E301", 2));
  CHECK(hasCode(d, "W419", 2));
}

TEST_CASE("rule W421: a suppression with nothing to suppress on its line or in its file fires") {
  auto d = visible("G0 X10 ; isolint: disable=W402\nG1 X20 ; isolint: disable=W402,div-zero\n"
                   "; isolint: disable-file=case-backward-jump\nM30\n");
  INFO(dump(d));
  fires(d, "W421", 1, 27);
  fires(d, "W421", 2, 32); // div-zero: no division on the line; the W402 is used
  fires(d, "W421", 3, 25);
  CHECK(count(d, "W421") == 3);
  CHECK(test::find(d, "W421")->message.find("W402 feed-unset") != std::string::npos);
  // the warning is under the policy like any other: --disable W421 (or a selection without it)
  CHECK(count(visible("G1 X10 F100 ; isolint: disable=W402\nM30\n", {diag::Code::SuppressionUnused}), "W421") == 0);
}

TEST_CASE("rule W421: suppressions that hide a finding are clean, even of a rule --disable also turns off") {
  clean(visible("G1 X10 ; isolint: disable=W402\nR1 = 1/0 ; isolint: disable=div-zero\nM30\n"));
  clean(visible("; isolint: disable-file=W402\nG1 X10\nM30\n"));
  clean(visible("G1 X10 ; isolint: disable=W402\nM30\n", {diag::Code::FeedUnset}));
  clean(visible("G1 X10 $\nY20 ; isolint: disable=W402\nM30\n"));
}

TEST_CASE("suppress: for the compilers an error silenced inline stays, with a note") {
  auto set = test::loadText("R0 = 1 ; isolint: disable=E301\nG1 X1 ; isolint: disable=W402\nM30\n");
  driver::filterDiagnostics(*set, {{}, false, true, {}});
  const auto& d = set->diags.items();
  INFO(dump(d));
  REQUIRE(hasCode(d, "E301", 1));
  CHECK_FALSE(hasCode(d, "W402", 2)); // a silenced warning stays silent
  REQUIRE(test::find(d, "E301")->notes.size() == 1);
  CHECK(test::find(d, "E301")->notes[0].message.find("still prevents compiling") != std::string::npos);
}

TEST_CASE("suppress: without suppressions every diagnostic is visible") {
  auto set = test::loadText("G1 X10\nR1 = 1/0\n");
  const size_t before = set->diags.size();
  driver::filterDiagnostics(*set, {});
  CHECK(set->diags.size() == before);
}

TEST_CASE("disable: --disable by code and by name") {
  std::ostringstream out, err;
  driver::Io io{out, err};
  std::vector<diag::Code> codes;
  REQUIRE(driver::resolveCodes({"W402", "div-zero,e301"}, codes, io, "isolint"));
  REQUIRE(codes.size() == 3);
  CHECK(codes[0] == diag::Code::FeedUnset);
  CHECK(codes[1] == diag::Code::DivZero);
  CHECK(codes[2] == diag::Code::RIndex);
  auto d = visible("G1 X10\nR1 = 1/0\nR0 = 1\nG0 G1 X1\nM30\n", codes);
  INFO(dump(d));
  CHECK(count(d, "W402") == 0);
  CHECK(count(d, "W406") == 0);
  CHECK(count(d, "E301") == 0);
  CHECK(count(d, "W401") == 1);
}

TEST_CASE("disable: an unknown --disable value is reported") {
  std::ostringstream out, err;
  driver::Io io{out, err};
  std::vector<diag::Code> codes;
  CHECK_FALSE(driver::resolveCodes({"W999"}, codes, io, "isolint"));
  CHECK(err.str().find("W999") != std::string::npos);
}

TEST_CASE("disable: --werror turns warnings into errors, infos stay") {
  auto d = visible("G1 X10\nG0 X1 M5\nM30\n", {}, true);
  INFO(dump(d));
  REQUIRE(hasCode(d, "W402", 1));
  CHECK(test::find(d, "W402")->severity == diag::Severity::Error);
  CHECK(test::find(d, "I501")->severity == diag::Severity::Info);
}
