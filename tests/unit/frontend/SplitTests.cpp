//! @file SplitTests.cpp
//! @brief isolint checks a large file in two parts at once (parseAndCheckFile, SplitOptions):
//!        where a file may be split, the parts appended into one file, the statement array
//!        that lets the second part be written in place, and that every split gives the
//!        diagnostics of one pass. (Every lintText of the unit tests splits its source too:
//!        test::checkSplitLoads.)
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include <doctest/doctest.h>

#include "TestUtil.h"
#include "frontend/Lexer.h"
#include "frontend/Parser.h"
#include "frontend/ProgramSet.h"
#include "support/Memory.h"
#include "support/Text.h"

using namespace iso;

namespace {

/// One source loaded as isolint loads it (compact) with `jobs` threads and `splitting`.
std::unique_ptr<frontend::ProgramSet> loadSplit(const std::string& text, unsigned jobs,
                                                const frontend::SplitOptions& splitting = {},
                                                const std::string& path = "cam.mpf") {
  auto set = std::make_unique<frontend::ProgramSet>();
  frontend::LoadOptions lo;
  lo.machine = &test::builtin();
  lo.dialect = test::builtin().dialect;
  lo.compactTrees = true;
  lo.jobs = jobs;
  lo.splitting = splitting;
  frontend::loadSingleSource(path, text, lo, *set);
  return set;
}

/// A CAM-like program of about `bytes` bytes: N numbers, labels, backward jumps, IF blocks,
/// WHENs, arcs; the feed is set once at the top. With a few errors: a label written twice
/// (its first in the first half), an N number used twice, a jump to no label near the end.
std::string camProgram(size_t bytes) {
  std::string t = "; generated\nG90 G17\nF=250\nR1 = 0\n";
  int k = 0;
  while (t.size() < bytes) {
    ++k;
    t += "N" + std::to_string(10 * k) + " G1 X" + std::to_string(k % 97) + " Y" + std::to_string(k % 89) + "\n";
    t += "L" + std::to_string(k) + ": G0 Z5\n";
    t += "IF R1 > " + std::to_string(k % 50) + "\n  G1 X1 Y2\nELSE\n  M23\nENDIF\n";
    t += "IF R1 > 1000 GOTOB L" + std::to_string(k) + "\n";
    t += "WHEN $aa_iw[X] > 5 DO $aa_out[3] = 1\nG1 X" + std::to_string(k % 31 + 6) + "\n";
    t += "G2 X10 Y0 CR=5\n";
  }
  t += "L7: G0 X0\n";     // E203: L7 is in the first half
  t += "N10 G0 Y0\n";     // W411: N10 is the first block's number
  t += "GOTOF NOWHERE\n"; // E202
  t += "M30\n";
  return t;
}

/// The physical line starts of `text` after the first (where a split may be tried).
std::vector<uint32_t> lineStarts(const std::string& text) {
  std::vector<uint32_t> out;
  for (size_t p = text.find('\n'); p != std::string::npos && p + 1 < text.size(); p = text.find('\n', p + 1))
    out.push_back(static_cast<uint32_t>(p + 1));
  return out;
}

void checkSameStmt(const frontend::Stmt& a, const frontend::Stmt& b) {
  CHECK(a.kind == b.kind);
  CHECK(a.recoverAs == b.recoverAs);
  CHECK(a.part == b.part);
  CHECK(a.line == b.line);
  CHECK(a.lastLine == b.lastLine);
  CHECK(a.loc.line == b.loc.line);
  CHECK(a.loc.col == b.loc.col);
  CHECK(a.firstItem == b.firstItem);
  CHECK(a.itemCount == b.itemCount);
  CHECK(a.cond == b.cond);
  CHECK(a.inner == b.inner);
  CHECK(a.partIdx == b.partIdx);
  CHECK(a.movedAxes == b.movedAxes);
  CHECK(a.posaAxes == b.posaAxes);
  CHECK(a.hasN() == b.hasN());
  CHECK(a.hasLabel() == b.hasLabel());
}

} // namespace

TEST_CASE("split: a large program is split near the middle, and gives one pass's diagnostics") {
  const std::string text = camProgram(size_t{1} << 20);
  auto one = loadSplit(text, 1);
  auto two = loadSplit(text, 2);
  const frontend::File& f = two->files.at(0);
  REQUIRE(f.splitAt > 0);
  CHECK(f.splitAt > text.size() * 2 / 5);
  CHECK(f.splitAt < text.size() * 3 / 5);
  CHECK(one->files.at(0).splitAt == 0);
  test::checkCompactLoad(*one, *two);
  CHECK(test::diagnosticsJson(*one) == test::diagnosticsJson(*two));
  // the errors of the program are found across the split
  const auto& d = two->diags.items();
  CHECK(test::hasCode(d, "E203"));
  CHECK(test::hasCode(d, "W411"));
  CHECK(test::hasCode(d, "E202"));
  CHECK_FALSE(test::hasCode(d, "W402")); // the feed set at the top holds in the second part too
  // the statements are those of one pass
  REQUIRE(f.stmts.size() == one->files.at(0).stmts.size());
  for (size_t i = 0; i < f.stmts.size(); i += 997)
    checkSameStmt(f.stmts[i], one->files.at(0).stmts[i]);
}

TEST_CASE("split: a smaller file, one thread, or no split point: one thread checks the file") {
  const std::string text = camProgram(200 * 1024);
  CHECK(loadSplit(text, 2)->files.at(0).splitAt == 0); // under SplitOptions::minBytes
  const frontend::SplitOptions anywhere{.minBytes = 0};
  CHECK(loadSplit(text, 2, anywhere)->files.at(0).splitAt > 0);
  CHECK(loadSplit(text, 1, anywhere)->files.at(0).splitAt == 0);
  // every line continued by `$`: no line start can be a split point
  std::string joined;
  for (int i = 0; i < 2000; ++i)
    joined += "G1 X" + std::to_string(i) + " $\n";
  joined += "M30\n";
  CHECK(loadSplit(joined, 2, anywhere)->files.at(0).splitAt == 0);
  // an offset that is no split point
  const frontend::SplitOptions inLine{.minBytes = 0, .at = 3};
  CHECK(loadSplit(text, 2, inLine)->files.at(0).splitAt == 0);
}

TEST_CASE("split: the first statement after the split point: one thread checks the file") {
  std::string text;
  for (int i = 0; i < 50; ++i)
    text += "; comment " + std::to_string(i) + "\n";
  const uint32_t at = lineStarts(text).at(24); // a line start among the comments
  REQUIRE(frontend::Lexer::isSplitPoint(text, at));
  text += "G1 X1 F100\nM30\n";
  auto one = loadSplit(text, 1);
  auto two = loadSplit(text, 2, {.minBytes = 0, .at = at, .guessAfter = 1});
  CHECK(two->files.at(0).splitAt == 0);
  test::checkCompactLoad(*one, *two);
}

TEST_CASE("split: a second part that starts from a wrong guess is checked again until the state agrees") {
  // The feed is set at the second statement; the guess is the state after the first (no feed).
  std::string text = "G0 X0\nF100\n";
  for (int i = 0; i < 400; ++i)
    text += "G1 X" + std::to_string(i % 50) + " Y" + std::to_string(i % 7) + "\n";
  text += "M30\n";
  auto one = loadSplit(text, 1);
  CHECK_FALSE(test::hasCode(one->diags.items(), "W402"));
  for (uint32_t at : lineStarts(text)) {
    INFO("split at ", at);
    auto two = loadSplit(text, 2, {.minBytes = 0, .at = at, .guessAfter = 1});
    test::checkCompactLoad(*one, *two);
  }
  // G18 set once at the top: an arc in the second part is checked in the XZ plane
  std::string plane = "G18\nG0 X0 Z0\nF100\n";
  for (int i = 0; i < 100; ++i)
    plane += "G1 X1 Z1\nG2 X0 Z2 CR=1\nL" + std::to_string(i) + ": G0 X0 Z0\n";
  plane += "G2 X1 Y1 CR=1\nM30\n"; // E-code: Y is no axis of the XZ plane
  auto onePlane = loadSplit(plane, 1);
  for (uint32_t at : lineStarts(plane)) {
    INFO("split at ", at);
    test::checkCompactLoad(*onePlane, *loadSplit(plane, 2, {.minBytes = 0, .at = at, .guessAfter = 1}));
  }
}

TEST_CASE("split: where a file may be split") {
  using frontend::Lexer;
  const std::string cont = "G1 X1 $\nY2\nM30\n";
  CHECK_FALSE(Lexer::isSplitPoint(cont, 8)); // "Y2" continues "G1 X1"
  CHECK(Lexer::isSplitPoint(cont, 11));      // "M30"
  const std::string sysvar = "WHEN $AA_IW[X] > 1 DO $aa_out[1] = 1\nG1 X1\n";
  CHECK(Lexer::isSplitPoint(sysvar, static_cast<uint32_t>(sysvar.find('\n') + 1))); // `$` of a system variable
  const std::string comment = "G1 X1 ; costs $\nG1 X2\n";
  CHECK_FALSE(Lexer::isSplitPoint(comment, static_cast<uint32_t>(comment.find('\n') + 1))); // any `$` that may continue
  const std::string crlf = "G1 X1\r\nG1 X2\r\n";
  CHECK(Lexer::isSplitPoint(crlf, 7));
  CHECK_FALSE(Lexer::isSplitPoint(crlf, 6)); // between CR and LF
  CHECK_FALSE(Lexer::isSplitPoint(crlf, 0));
  CHECK_FALSE(Lexer::isSplitPoint(crlf, static_cast<uint32_t>(crlf.size()))); // nothing after
  CHECK_FALSE(Lexer::isSplitPoint(crlf, 3));                                  // inside a line
  const std::string dollarEnd = "G1 X1$\r\nG1 X2\n";
  CHECK_FALSE(Lexer::isSplitPoint(dollarEnd, 8));
}

TEST_CASE("split: two parts parsed apart and appended are the file parsed at once") {
  // Full trees (expressions kept): every index of the second part moves past the first's.
  const std::string text = "; head\n"
                           "PROC SUB1 SAVE\n"
                           "N10 G1 X1 Y2 F100\n"
                           "R1 = 2 + 3 * R2\n"
                           "L1: IF R1 > 2 GOTOF L2\n"
                           "IF (R1 > 1) AND ($aa_in[3] == 1) THEN G1 X5\n"
                           "CASE R1 OF 1 GOTOF L1 2 GOTOF L2 DEFAULT GOTOF L3\n"
                           "WHEN $aa_iw[X] > 5 DO $aa_out[3] = 1\n"
                           "G1 X3 ; isolint: disable=W402\n"
                           "CALL SU$\n"
                           "B2\n"
                           "L2: N20 M23\n"
                           "IF R1 > 1\n"
                           "  G1 Posa[Z] = 71 Fa[Z] = 50\n"
                           "ENDIF\n"
                           "WHEN $aa_iw[Y] > 5 DO $aa_out[4] = 1\n"
                           "G1 Y3\n"
                           "L3: CALL SUB3\n"
                           "M17\n";
  frontend::LexOptions lo;
  diag::DiagnosticList wholeDiags;
  frontend::File whole;
  frontend::parseFile(whole, text, lo, wholeDiags);
  size_t splits = 0;
  for (uint32_t at : lineStarts(text)) {
    if (!frontend::Lexer::isSplitPoint(text, at)) continue;
    ++splits;
    INFO("split at ", at);
    const auto line = static_cast<uint32_t>(1 + std::count(text.begin(), text.begin() + at, '\n'));
    diag::DiagnosticList d1, d2;
    frontend::File first, second;
    {
      frontend::LineParser p(first, text, lo, d1);
      p.setRange(0, 1, at);
      while (p.parseLine()) {
      }
    }
    {
      frontend::LineParser p(second, text, lo, d2, false);
      p.setRange(at, line, static_cast<uint32_t>(text.size()));
      while (p.parseLine()) {
      }
    }
    CHECK(d1.size() + d2.size() == wholeDiags.size());
    frontend::appendPart(first, std::move(second));
    const frontend::File& f = first;
    REQUIRE(f.stmts.size() == whole.stmts.size());
    for (size_t i = 0; i < f.stmts.size(); ++i)
      checkSameStmt(f.stmts[i], whole.stmts[i]);
    REQUIRE(f.inner.size() == whole.inner.size());
    for (size_t i = 0; i < f.inner.size(); ++i)
      checkSameStmt(f.inner[i], whole.inner[i]);
    REQUIRE(f.items.size() == whole.items.size());
    for (size_t i = 0; i < f.items.size(); ++i) {
      CHECK(f.items[i].kind == whole.items[i].kind);
      CHECK(f.items[i].code == whole.items[i].code);
      CHECK(f.items[i].target == whole.items[i].target);
      CHECK(f.items[i].value == whole.items[i].value);
    }
    REQUIRE(f.exprs.size() == whole.exprs.size());
    for (size_t i = 0; i < f.exprs.size(); ++i) {
      CHECK(f.exprs[i].kind == whole.exprs[i].kind);
      CHECK(f.exprs[i].a == whole.exprs[i].a);
      CHECK(f.exprs[i].b == whole.exprs[i].b);
      CHECK(f.exprs[i].loc.line == whole.exprs[i].loc.line);
    }
    REQUIRE(f.armRanges.size() == whole.armRanges.size());
    for (size_t i = 0; i < f.armRanges.size(); ++i)
      CHECK(f.armRanges[i].first == whole.armRanges[i].first);
    REQUIRE(f.arms.size() == whole.arms.size());
    for (size_t i = 0; i < f.arms.size(); ++i)
      CHECK(f.arms[i].jump.label == whole.arms[i].jump.label);
    REQUIRE(f.numbers.size() == whole.numbers.size());
    for (size_t i = 0; i < f.numbers.size(); ++i)
      CHECK(f.numbers[i].stmt == whole.numbers[i].stmt);
    REQUIRE(f.labels.size() == whole.labels.size());
    for (size_t i = 0; i < f.labels.size(); ++i) {
      CHECK(f.labels[i].stmt == whole.labels[i].stmt);
      CHECK(f.labels[i].text == whole.labels[i].text);
    }
    REQUIRE(f.jumps.size() == whole.jumps.size());
    for (size_t i = 0; i < f.jumps.size(); ++i)
      CHECK(f.jumps[i].label == whole.jumps[i].label);
    REQUIRE(f.names.size() == whole.names.size());
    for (size_t i = 0; i < f.names.size(); ++i)
      CHECK(f.names[i].text == whole.names[i].text); // SUB2, joined across `$`: a text the part owned
    REQUIRE(f.whenAxes.size() == whole.whenAxes.size());
    for (size_t i = 0; i < f.whenAxes.size(); ++i)
      CHECK(f.whenAxesOf(f.whenAxes[i].stmt) == whole.whenAxesOf(whole.whenAxes[i].stmt));
    REQUIRE(f.suppressions.size() == whole.suppressions.size());
    for (size_t i = 0; i < f.suppressions.size(); ++i)
      CHECK(f.suppressions[i].line == whole.suppressions[i].line);
  }
  CHECK(splits == 17); // every line start but the one continued by `$`
}

TEST_CASE("StmtArray: grows, copies and moves like a vector, and fills another array's storage until it outgrows it") {
  frontend::StmtArray a;
  CHECK(a.empty());
  for (uint32_t i = 0; i < 1000; ++i)
    a.emplace_back().line = i;
  REQUIRE(a.size() == 1000);
  CHECK(a.ownsStorage());
  CHECK(a.front().line == 0);
  CHECK(a.back().line == 999);
  CHECK(a.at(500).line == 500);
  CHECK_THROWS_AS((void)a.at(1000), std::out_of_range);
  a.push_back(a[3]); // an element of its own, while it grows
  CHECK(a.back().line == 3);
  frontend::StmtArray copy = a;
  CHECK(copy.size() == a.size());
  CHECK(copy.data() != a.data());
  CHECK(copy[999].line == 999);
  frontend::StmtArray moved = std::move(copy);
  CHECK(moved.size() == 1001);
  CHECK(copy.empty()); // NOLINT(bugprone-use-after-move): moved-from is empty
  uint32_t sum = 0;
  for (const frontend::Stmt& s : moved)
    sum += s.line;
  CHECK(sum == 999 * 1000 / 2 + 3);

  frontend::StmtArray host;
  host.reserve(100);
  auto in = frontend::StmtArray::inside(host.data() + 60, 40);
  CHECK_FALSE(in.ownsStorage());
  for (uint32_t i = 0; i < 40; ++i)
    in.emplace_back().line = 100 + i;
  CHECK(in.data() == host.data() + 60); // written in the host's storage
  CHECK(host.data()[60].line == 100);
  in.emplace_back().line = 140; // outgrows its room: moves to storage of its own
  CHECK(in.ownsStorage());
  CHECK(in.data() != host.data() + 60);
  REQUIRE(in.size() == 41);
  CHECK(in[0].line == 100);
  CHECK(in[40].line == 140);
  host.setSize(61); // the host takes what was written in it
  CHECK(host[60].line == 100);
  CHECK_THROWS_AS(host.setSize(101), std::length_error);
}

TEST_CASE("support: countByte counts a byte at any length and alignment") {
  std::mt19937 rng(7);
  std::string buf(5000, '\0');
  for (char& c : buf)
    c = static_cast<char>(rng() % 4 == 0 ? '\n' : rng() % 256);
  for (size_t from : {size_t{0}, size_t{1}, size_t{7}, size_t{15}})
    for (size_t len :
         {size_t{0}, size_t{1}, size_t{15}, size_t{16}, size_t{17}, size_t{255 * 16}, size_t{4097}, size_t{4980}}) {
      const std::string_view s = std::string_view(buf).substr(from, len);
      for (char c : {'\n', '\0', '\xff'})
        CHECK(support::countByte(s, c) == static_cast<size_t>(std::count(s.begin(), s.end(), c)));
    }
  const std::string all(300 * 16 + 5, '\n'); // more than 255 blocks of one lane
  CHECK(support::countByte(all, '\n') == all.size());
}

TEST_CASE("support: releasePages gives back whole pages inside a buffer and keeps its edges") {
  std::vector<char> buf(size_t{4} << 20, 'x');
  char* p = buf.data() + 100;
  const size_t n = (size_t{3} << 20) + 123;
  support::releasePages(p, n);
  // the first page at p, and the bytes before it and after the last whole page, stay
  CHECK(std::all_of(buf.data(), p + 4096, [](char c) { return c == 'x'; }));
  const char* lastPage = reinterpret_cast<const char*>(reinterpret_cast<uintptr_t>(p + n) & ~uintptr_t{4095});
  CHECK(std::all_of(lastPage, static_cast<const char*>(buf.data() + buf.size()), [](char c) { return c == 'x'; }));
#if defined(__linux__)
  // the pages given back read as zero
  CHECK(p[n / 2] == 0);
#endif
  std::vector<char> small(1000, 'y'); // under 1 MiB: untouched
  support::releasePages(small.data(), small.size());
  CHECK(std::all_of(small.begin(), small.end(), [](char c) { return c == 'y'; }));
}
