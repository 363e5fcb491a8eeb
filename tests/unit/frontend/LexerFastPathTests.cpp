//! @file LexerFastPathTests.cpp
//! @brief The lexer reads words on lines without `$` by a shorter path (LexOptions::fastPaths):
//!        it must give exactly the tokens and diagnostics of the general path.
#include <cstring>
#include <deque>
#include <filesystem>
#include <string>
#include <vector>

#include <doctest/doctest.h>
#include <fmt/format.h>

#include "TestUtil.h"
#include "support/File.h"

using namespace iso;
namespace fs = std::filesystem;

namespace {

/// Every token and diagnostic of `text`, one per line, with all their fields.
std::string lexDump(const std::string& text, machine::Dialect dialect, bool fast) {
  frontend::LexOptions lo;
  lo.dialect = dialect;
  lo.fastPaths = fast;
  diag::DiagnosticList diags;
  std::vector<frontend::Suppression> sup;
  std::deque<std::string> owned;
  frontend::Lexer lexer(text, 0, lo, diags, sup, owned);
  frontend::LogicalLine line;
  std::string out;
  while (lexer.next(line)) {
    out += fmt::format("line {}-{} len {} err {} trunc {}\n", line.firstLine, line.lastLine, line.length, line.hadError,
                       line.truncated);
    for (const auto& t : line.tokens)
      out +=
          fmt::format("  {} '{}' {}:{} len {} value {} sep {} digits {} sign {} joined {} sysvar {} '{}'\n",
                      static_cast<int>(t.kind), std::string(t.addr, strnlen(t.addr, 3)), t.line, t.col, t.len, t.value,
                      t.hasSep, t.tooManyDigits, t.hasSign, t.joined, static_cast<int>(t.sysvar), std::string(t.text));
  }
  for (const auto& d : diags.items())
    out += fmt::format("diag {} {}:{} {}\n", static_cast<int>(d.code), d.loc.line, d.loc.col, d.message);
  return out;
}

void compareBoth(const std::string& text) {
  for (auto dialect : {machine::Dialect::Sidac, machine::Dialect::Z32}) {
    INFO(text.substr(0, 200));
    CHECK(lexDump(text, dialect, true) == lexDump(text, dialect, false));
  }
}

size_t compareFiles(const std::vector<fs::path>& files) {
  size_t n = 0;
  for (const auto& p : files)
    if (auto text = support::readFile(p.string())) {
      compareBoth(*text);
      ++n;
    }
  return n;
}

} // namespace

TEST_CASE("lexer fast path: the tokens and diagnostics of the general path") {
  // words, signs, blanks inside words, separators, two-letter addresses, labels, numbers with
  // too many digits, NUL bytes, line ends, names that start like words, continuations nearby
  const char* cases[] = {
      "N10G0X4Y3Z5\n",
      "G01 X358.2 Y-23.8 F200\n",
      "X - 5 Y + .5 Z 1. A,5 B5,\n",
      "X1Y2:\nL4: G1 X1\nA1 :\n",
      "CR=5 CR5 cr 5 MA1 MB 2 MC-3 M A5\n",
      "X1234567890 Y0.0000000001 Z000000000012 F1234567890123456789\n",
      "G1 X1\r\nG1 X2\rG1 X3\n",
      "GOTOF X1\nPOSA[X]=1 Fa[X]=2\nXYZ1 X1Y Q1 Ä1\n",
      "G1 X1 $\nY2\nG1 X$\n1\nG1 $aa_iw[X] X1\n",
      "N10 G1 X1 ; comment X2\n( X3 ) G1 X4 (inline) Y5\n",
      "X\nX-\nX+ \nX.\nX,\n1X2\n",
  };
  for (const char* c : cases)
    compareBoth(c);
  compareBoth(std::string("G1 X1\0\0Y2\n", 10));
  compareBoth(std::string(300, 'X') + "1\n" + "G1" + std::string(250, ' ') + "X1\n");
  // Groups of words after blanks are read in one go: what ends them, and the E102 column
  const char* groups[] = {
      "G1 X1 Y2 Z3 F100\n",
      "G1\tX1  \t Y2\n",
      "G1 X1 Y2:\n",
      "G1 X1 Lift\n",
      "G1 X1 _x\n",
      "G1 X1 Y2 = 3\n",
      "G1 X1 Y2;c\n",
      "G1 X1 Y2 (c) Z3\n",
      "G1 X1 Y\n",
      "G1 X1 1\n",
      "G1 $\nX1 Y2 Z3\n",
      "G1 X1 Y2 $\n",
      "G1 X1 Y2 \r\n",
      "G1 X1 Y\xC4 Z1\n",
      // a `$` that starts a system variable joins nothing: such lines take the fast path too
      // a later group that fails is tried once (its E101 reported once), then read as a name
      " X0 M7777777723u\n",
      "G1 X1 Y1234567890:\n",
      "G1 X1 Y12345678901Z\n",
      "G1 X1 N1234567890 Q1\n",
      "G1 X1 Y12345678901 1\n",
      "G1 X1 Y2 GOTOF L1\n",
      "G1 X1 $aa_out[1]=1 Y2.5\n",
      "R1=$AA_IW[X]+2.5 $\nX1\n",
      "G1 X$1\n",
      "G1 X1 $_a Y2 $\n",
      "$X1 Y2\n",
  };
  for (const char* g : groups)
    compareBoth(g);
  for (size_t at = 236; at <= 244; ++at) { // the second group starts at column at + 1
    compareBoth("X1" + std::string(at - 2, ' ') + "Y2 Z3\n");
    compareBoth(std::string(at, ' ') + "X1 Y2\n");
  }
}

TEST_CASE("lexer fast path: the project's programs and the shared corpus lex the same") {
  const fs::path root = ISO_SOURCE_DIR;
  CHECK(compareFiles(test::programsUnder(root / "tests")) + compareFiles(test::programsUnder(root / "samples")) > 50);
  compareFiles(test::programsUnder(fs::path(ISO_SHARED_DIR) / "corpus")); // when it is there
}
