//! @file BoundsTests.cpp
//! @brief Input that the user controls bounds no recursion and no quadratic work: huge
//!        expressions and lines (E102 stops a line's analysis), deep IF nesting, long call
//!        chains; bytes are data (NUL, control bytes, CR-only files); a bad word keeps the
//!        valid words of its line; soft-limit tolerance.
#include <algorithm>
#include <deque>
#include <string>
#include <vector>

#include <doctest/doctest.h>
#include <fmt/format.h>

#include "TestUtil.h"
#include "frontend/Lexer.h"
#include "frontend/Parser.h"

using namespace iso;
using test::count;
using test::Diags;
using test::dump;
using test::hasCode;
using test::lintText;

namespace {

std::string repeat(const std::string& s, size_t n) {
  std::string r;
  r.reserve(s.size() * n);
  for (size_t i = 0; i < n; ++i)
    r += s;
  return r;
}

/// The line is too long: one E102 at its 241st character and nothing else from it.
void onlyTooLong(const Diags& d) {
  INFO(dump(d));
  CHECK(d.size() == 1);
  CHECK(hasCode(d, "E102", 1, 241));
}

} // namespace

// ---- 1. no recursion that input controls -------------------------------------------------------

TEST_CASE("bounds: 20,000 nested parentheses are E102, not a stack overflow") {
  onlyTooLong(lintText("R1 = " + repeat("(", 20000) + "1" + repeat(")", 20000) + "\nM30\n"));
}

TEST_CASE("bounds: 60,000 terms and 52,000 unary signs are E102") {
  onlyTooLong(lintText("R1 = 1" + repeat("+R2+1", 30000) + "\nM30\n"));
  onlyTooLong(lintText("R1 = " + repeat("-+", 26000) + "1\nM30\n"));
  onlyTooLong(lintText("IF " + repeat("(R1 > 0) AND ", 20000) + "(R1 > 0)\nENDIF\nM30\n"));
}

TEST_CASE("bounds: a 10 MB line is one E102 (its time is measured by bench/scaling.sh)") {
  Diags d = lintText("G0 X1 " + repeat("G1 Y2 ", 10'000'000 / 6) + "\nM30\n");
  onlyTooLong(d);
  // '$' in comments (E103 each) only up to the 241st character.
  Diags c = lintText("G0 X1 " + repeat("(comment $) G1 Y2 ", 1'000'000 / 18) + "\nM30\n");
  INFO(dump(c));
  CHECK(count(c, "E103") == 13);
  CHECK(count(c, "E102") == 1);
  CHECK(c.size() == 14);
}

TEST_CASE("bounds: E102 is reported where the 241st character is, across continuations") {
  // 200 characters, a `$` join, then 100 more: the 241st is column 41 of line 2.
  Diags d = lintText("R1 = 1" + repeat("+1", 97) + "$\n" + repeat("+1", 50) + "\nM30\n");
  INFO(dump(d));
  CHECK(d.size() == 1);
  CHECK(hasCode(d, "E102", 2, 41));
}

TEST_CASE("bounds: a truncated last line gives no missing-M30 follow-up") {
  Diags d = lintText("G0 X1\n" + repeat("G0 X1 ", 100) + "M30\n");
  INFO(dump(d));
  CHECK(d.size() == 1);
  CHECK(hasCode(d, "E102", 2, 241));
}

TEST_CASE("bounds: 100,000 nested IFs are legal") {
  std::string text = "R1 = 1\n" + repeat("IF R1 > 0\n", 100000) + "G0 X1\n" + repeat("ENDIF\n", 100000) + "M30\n";
  Diags d = lintText(text);
  INFO(dump(d));
  CHECK(d.empty());
}

TEST_CASE("bounds: a chain of 50,000 subprograms is E211 with notes, no stack overflow") {
  const int n = 50000;
  std::vector<frontend::ProgramText> files;
  files.push_back({"main.mpf", "G0 X0\nSub1\nM30\n", true});
  for (int i = 1; i <= n; ++i) {
    std::string body = fmt::format("PROC Sub{} SAVE\n", i);
    // The last one calls the first again: one W409 at the call that closes the cycle.
    body += fmt::format("Sub{}\nM17\n", i < n ? i + 1 : 1);
    files.push_back({fmt::format("s{}.spf", i), std::move(body), true});
  }
  frontend::ProgramSet set;
  frontend::LoadOptions lo;
  lo.machine = &test::builtin();
  frontend::loadProgramTexts(std::move(files), lo, set); // its time: bench/scaling.sh call-chain
  const Diags& d = set.diags.items();
  REQUIRE(count(d, "E211") == 1);
  const diag::Diagnostic* e = test::find(d, "E211");
  CHECK(e->message.find("depth 50000 exceeds the limit of 30") != std::string::npos);
  CHECK(e->notes.size() == 64);
  CHECK(count(d, "W409") == 1);
  CHECK(d.size() == 2);
}

TEST_CASE("bounds: the parser's depth guard reports E100 instead of recursing further") {
  frontend::File f;
  diag::DiagnosticList diags;
  frontend::LexOptions lo;
  frontend::Parser p(f, lo, diags);
  frontend::LogicalLine line;
  const int deep = frontend::Parser::kMaxExprDepth + 10;
  auto push = [&](frontend::Tok k) {
    frontend::Token t;
    t.kind = k;
    t.line = 1;
    t.col = static_cast<uint32_t>(line.tokens.size() + 1);
    t.value = 1;
    line.tokens.push_back(t);
  };
  for (int i = 0; i < deep; ++i)
    push(frontend::Tok::LParen);
  push(frontend::Tok::Number);
  for (int i = 0; i < deep; ++i)
    push(frontend::Tok::RParen);
  push(frontend::Tok::Gt);
  push(frontend::Tok::Number);
  push(frontend::Tok::End);
  CHECK(p.parseConditionAt(line, 0) == frontend::kNoExpr);
  REQUIRE(diags.size() == 1);
  CHECK(diags.items()[0].message == "expression nested too deeply (more than 256 levels)");
}

// ---- 2. bytes are data ---------------------------------------------------------------------

TEST_CASE("bytes: a NUL byte inside a comment is allowed, a file full of NULs is binary") {
  // SPEC §2: control bytes are E100 outside comments only; a few NULs do not make a file binary
  Diags c = lintText(std::string("G0 X1 ; a\0b\n(c\0d)\nM30\n", 22));
  INFO(dump(c));
  CHECK(c.empty());
  std::string binary;
  for (int i = 0; i < 100; ++i)
    binary += std::string("G0 X1\0\0\0\n", 10);
  Diags d = lintText(binary);
  REQUIRE(d.size() == 1);
  CHECK(d[0].message.find("binary file") != std::string::npos);
  // 7 NULs in a long text: still text, each NUL is E100 at its column
  std::string few = std::string(7, '\0') + "\n" + std::string(2000, ';') + "\nM30\n";
  Diags f = lintText(few);
  CHECK(count(f, "E100") == 7);
}

TEST_CASE("bytes: NUL and other control bytes in code are E100 at their column - the line goes on") {
  Diags d = lintText(std::string("G0 X1\0 Y2\nG0 X2 \x01\nM30\n", 22));
  INFO(dump(d));
  CHECK(hasCode(d, "E100", 1, 6));
  CHECK(hasCode(d, "E100", 2, 7));
  CHECK(d.size() == 2);
  CHECK(test::find(d, "E100")->message.find("control byte 0x00") != std::string::npos);
}

TEST_CASE("bytes: control bytes inside comments are allowed") {
  Diags d = lintText("G0 X1 (a\x01\x1F b)\n; \x02\nM30\n");
  INFO(dump(d));
  CHECK(d.empty());
}

TEST_CASE("bytes: messages quote source bytes as valid UTF-8") {
  CHECK(frontend::printableBytes("ab\x80\xFF\x01\t") == "ab\\x80\\xFF\\x01\\x09");
  CHECK(frontend::printableBytes("G01 X-1.5") == "G01 X-1.5");
}

TEST_CASE("bytes: a dangling '$' keeps its ignored tail out of the token") {
  auto r = test::lexText("G0 X12$ 34 \xC3\xA8");
  auto toks = r->tokens(0);
  REQUIRE(toks.size() == 2);
  CHECK(toks[1].text == "12");
  CHECK(toks[1].len == 3);
  CHECK(r->diags.size() == 0);
}

TEST_CASE("bytes: a line number has no sign") {
  Diags d = lintText("N-10 G00 X1\nN+11 G00 X2\nM30\n");
  INFO(dump(d));
  CHECK(hasCode(d, "E100", 1, 1));
  CHECK(hasCode(d, "E100", 2, 1));
  CHECK(test::find(d, "E100")->message == "a line number has no sign: write N10");
  CHECK(d.size() == 2);
}

// ---- 3. CR-only line ends ------------------------------------------------------------------

TEST_CASE("CR: a file with CR-only line ends gets one diagnostic") {
  Diags d = lintText("G0 X1\rG1 X2 F100\rM30\r");
  INFO(dump(d));
  REQUIRE(d.size() == 1);
  CHECK(hasCode(d, "E100", 1, 6));
  CHECK(d[0].message == "lone CR line ends: this file uses CR-only line ends; save it with LF or CRLF line ends");
  Diags big = lintText(repeat("G1 X1 Y2 Z3 (cut)\r", 20000) + "M30\r");
  INFO(dump(big));
  CHECK(big.size() == 1);
}

namespace {
/// The lexer's diagnostics for `text` alone (a large text costs no parse).
Diags lexDiags(const std::string& text) {
  diag::DiagnosticList diags;
  std::vector<frontend::Suppression> suppressions;
  std::deque<std::string> owned;
  frontend::Lexer lexer(text, 0, frontend::LexOptions{}, diags, suppressions, owned);
  frontend::LogicalLine line;
  while (lexer.next(line)) {
  }
  return diags.items();
}
} // namespace

TEST_CASE("CR: the scan for lone CRs goes through a large file in steps: a CRLF across a step is a line end") {
  constexpr size_t kStep = size_t{4} << 20; // the scan's step
  std::string t;
  while (t.size() + 40 < kStep)
    t += "G1 X1 Y2 Z3 (cut)\n";
  t += "; " + std::string(kStep - 1 - t.size() - 2, 'x');
  REQUIRE(t.size() == kStep - 1);
  t += "\r\n"; // the CR ends one step, its LF starts the next
  while (t.size() < kStep + kStep / 2)
    t += "G1 X1 Y2 Z3 (cut)\n";
  const auto line = static_cast<uint32_t>(std::count(t.begin(), t.end(), '\n') + 1);
  t += "G0 X1\rY2\nM30\n"; // a lone CR in the second step
  Diags d = lexDiags(t);
  INFO(dump(d));
  CHECK(d.size() == 1);
  CHECK(hasCode(d, "E100", line, 6));
  // CR-only line ends over more than one step: still one diagnostic for the file
  Diags crOnly = lexDiags(repeat("G1 X1 Y2 Z3 (cut)\r", kStep / 18 + 1000) + "M30\r");
  INFO(dump(crOnly));
  CHECK(crOnly.size() == 1);
  CHECK(hasCode(crOnly, "E100", 1, 18));
  // the same when the first step holds no CR at all (one long comment line, then CR-only lines)
  Diags late = lexDiags("; " + std::string(kStep, 'x') + "\n" + repeat("G1 X1\r", 100000) + "M30\r");
  INFO(dump(late));
  CHECK(std::count_if(late.begin(), late.end(),
                      [](const diag::Diagnostic& x) { return x.message.rfind("lone CR line ends", 0) == 0; }) == 1);
  CHECK(count(late, "E100") == 1);
}

TEST_CASE("CR: lone CRs in an LF file are an error each, bounded by the line length") {
  Diags d = lintText("G0 X1\rY2\nG0 X1 (a\rb)\nM30\n");
  INFO(dump(d));
  CHECK(hasCode(d, "E100", 1, 6));
  CHECK(hasCode(d, "E100", 2, 9));
  CHECK(d.size() == 2);
  Diags many = lintText("G0 X1 " + repeat("\r", 5000) + "\nM30\n");
  CHECK(count(many, "E100") == 234);
  CHECK(count(many, "E102") == 1);
}

// ---- 4. error recovery keeps valid words ---------------------------------------------------------

TEST_CASE("recovery: a bad word keeps the F of its line (no W402 below)") {
  Diags d = lintText("G94 F100\nG01 X10\nM30\n");
  INFO(dump(d));
  CHECK(d.size() == 1);
  CHECK(hasCode(d, "E110", 1, 1));
  Diags d2 = lintText("G1 X10 TRANS F100\nG1 X20\nM30\n");
  INFO(dump(d2));
  CHECK(d2.size() == 1);
  CHECK(hasCode(d2, "E110", 1, 8));
  Diags d3 = lintText("G1 X= F100\nX2\nM30\n");
  INFO(dump(d3));
  CHECK(d3.size() == 1);
  CHECK(hasCode(d3, "E100", 1, 7));
}

TEST_CASE("recovery: G modal words of a bad line count, later errors of the line are not repeated") {
  Diags d = lintText("G1 F50\nG00 X1 ) Y=( Z2\nX5 Fa[X]=1\nM30\n"); // G00 kept: Fa on a rapid
  INFO(dump(d));
  CHECK(count(d, "E100") == 1);
  CHECK(hasCode(d, "W414", 3, 4));
}

// ---- 6. soft limit tolerance -----------------------------------------------------------------------

TEST_CASE("soft limits: a target within 1e-9 of a limit is on it - others print every digit") {
  Diags on = lintText("G90 X=3000+.0000000005\nM30\n");
  INFO(dump(on));
  CHECK(on.empty());
  Diags off = lintText("G90 X=3000+.000000002\nM30\n");
  INFO(dump(off));
  REQUIRE(count(off, "W410") == 1);
  CHECK(test::find(off, "W410")->message.find("X=3000.000000002 ") != std::string::npos);
}
