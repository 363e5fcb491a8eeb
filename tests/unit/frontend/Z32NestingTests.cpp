//! @file Z32NestingTests.cpp
//! @brief Dialect z32 in the checks of a program set: KG names (E210, sibling loading, KG edges
//!        that add no nesting level for E211 and close cycles for W409) and GO ranges and GOP as
//!        nesting levels of E211, with the chain in the notes.
#include <string>
#include <utility>
#include <vector>

#include <doctest/doctest.h>
#include <fmt/format.h>

#include "TestUtil.h"

using namespace iso;
using test::dump;
using test::hasCode;
using test::lintFiles;

namespace {
using Files = std::vector<std::pair<std::string, std::string>>;

test::SetResult lintZ32Files(const Files& files) { return lintFiles(files, test::builtin(), machine::Dialect::Z32); }

/// Sub1 -> Sub2 -> ... -> SubN, each in s<i>.spf; Sub<kg> continues in Sub<kg+1> with KG
/// instead of calling it (0: none).
void addChain(Files& files, int n, int kg = 0) {
  for (int i = 1; i <= n; ++i) {
    std::string body = fmt::format("PROC Sub{} SAVE\n", i);
    if (i < n && i == kg)
      body += fmt::format("G0 X{} KGSub{}\n", i, i + 1); // KG ends the subprogram's flow
    else
      body += fmt::format("{}M17\n", i < n ? fmt::format("Sub{}\n", i + 1) : "");
    files.push_back({fmt::format("s{}.spf", i), body});
  }
}

size_t notesWith(const diag::Diagnostic& d, const std::string& text) {
  size_t n = 0;
  for (const auto& note : d.notes)
    n += note.message.find(text) != std::string::npos;
  return n;
}
} // namespace

TEST_CASE("z32 KG: an unknown name is E210, a sibling .spf is loaded for it") {
  auto unknown = lintZ32Files({{"main.mpf", "G0 X1 KGNONE\n"}});
  REQUIRE(unknown.loaded);
  INFO(dump(unknown.diags));
  CHECK(hasCode(unknown.diags, "E210", 1, 9));
  auto found = lintZ32Files({{"main.mpf", "G0 X1 KGCAMBIO\n"}, {"cambio.spf", "PROC CAMBIO SAVE\nG0 X2\nM17\n"}});
  REQUIRE(found.loaded);
  INFO(dump(found.diags));
  CHECK(found.set->files.size() == 2);
  CHECK(found.diags.empty());
  // dialect sidac: KGCAMBIO is no KG (as before)
  auto sidac = lintFiles({{"main.mpf", "G0 X1 KGCAMBIO\nM30\n"}, {"cambio.spf", "PROC CAMBIO SAVE\nM17\n"}});
  CHECK(!hasCode(sidac.diags, "E210"));
}

TEST_CASE("z32 KG: a KG edge adds no nesting level (E211 counts the calls around it)") {
  // main -> Sub1 -> ... -> Sub11 with Sub5 KG'ing Sub6: 10 levels
  Files ok = {{"main.mpf", "Sub1\nM30\n"}};
  addChain(ok, 11, 5);
  auto r = lintZ32Files(ok);
  REQUIRE(r.loaded);
  INFO(dump(r.diags));
  CHECK(!hasCode(r.diags, "E211"));
  CHECK(!hasCode(r.diags, "E210"));
  // one more: 11 levels
  Files deep = {{"main.mpf", "Sub1\nM30\n"}};
  addChain(deep, 12, 5);
  auto d = lintZ32Files(deep);
  REQUIRE(d.loaded);
  INFO(dump(d.diags));
  REQUIRE(hasCode(d.diags, "E211", 1, 1));
  const diag::Diagnostic* e = test::find(d.diags, "E211");
  CHECK(e->message == "call nesting depth 11 exceeds the limit of 10");
  REQUIRE(e->notes.size() == 12);
  CHECK(e->notes[5].message == "level 5: KG continues in 'Sub6' (no new level: it replaces the running frame)");
  CHECK(e->notes[11].message == "level 11: calls 'Sub12'");
}

TEST_CASE("z32 KG: a KG cycle is W409") {
  auto r = lintZ32Files({{"main.mpf", "SubA\nM30\n"},
                         {"a.spf", "PROC SubA SAVE\nG0 X1 KGSubB\n"},
                         {"b.spf", "PROC SubB SAVE\nG0 X2 KGSubA\n"}});
  REQUIRE(r.loaded);
  INFO(dump(r.diags));
  CHECK(test::count(r.diags, "W409") == 1);
  CHECK(!hasCode(r.diags, "E211"));
}

TEST_CASE("z32 E211: a GO range is a nesting level, with the range in the notes") {
  // main -> range N10-N20 -> Sub1 -> ... -> Sub<n>: n + 1 levels
  auto withChain = [](int n) {
    Files files = {{"main.mpf", "GON10-N20\nM30\nN10 G0 X0\nSub1\nN20 G0 X1\nM30\n"}};
    addChain(files, n);
    return lintZ32Files(files);
  };
  auto ok = withChain(9);
  REQUIRE(ok.loaded);
  INFO(dump(ok.diags));
  CHECK(!hasCode(ok.diags, "E211"));
  auto deep = withChain(10);
  REQUIRE(deep.loaded);
  INFO(dump(deep.diags));
  REQUIRE(hasCode(deep.diags, "E211", 1, 1));
  const diag::Diagnostic* e = test::find(deep.diags, "E211");
  CHECK(e->message == "call nesting depth 11 exceeds the limit of 10");
  REQUIRE(e->notes.size() == 11);
  CHECK(e->notes[0].message == "level 1: GON10-N20 runs the lines of the range");
  CHECK(e->notes[0].loc.line == 1);
  CHECK(e->notes[1].message == "level 2: calls 'Sub1'");
  CHECK(e->notes[1].loc.line == 4);
}

TEST_CASE("z32 E211: a GO range inside a range counts each, GOP counts as a call") {
  // main -> N10-N40 -> N30-N40 -> GOPSub1 -> ... -> Sub<n>: n + 2 levels
  auto withChain = [](int n) {
    Files files = {{"main.mpf", "GON10-N40\nM30\nN10 G0 X0\nGON30-N40\nN30 G0 X1\nGOPSub1\nN40 G0 X2\nM30\n"}};
    addChain(files, n);
    return lintZ32Files(files);
  };
  auto ok = withChain(8); // exactly 10
  REQUIRE(ok.loaded);
  INFO(dump(ok.diags));
  CHECK(!hasCode(ok.diags, "E211"));
  auto deep = withChain(9);
  REQUIRE(deep.loaded);
  INFO(dump(deep.diags));
  REQUIRE(hasCode(deep.diags, "E211", 1, 1));
  const diag::Diagnostic* e = test::find(deep.diags, "E211");
  REQUIRE(e->notes.size() == 11);
  CHECK(notesWith(*e, "runs the lines of the range") == 2);
  CHECK(e->notes[1].message == "level 2: GON30-N40 runs the lines of the range");
  CHECK(e->notes[2].message == "level 3: calls 'Sub1'");
  CHECK(e->notes[2].loc.line == 6);
  // the calls outside the range run at the main program's level: a chain of 10 there is clean
  Files flat = {{"main.mpf", "GON10-N20\nM30\nN10 G0 X0\nN20 G0 X1\nSub1\nM30\n"}};
  addChain(flat, 10);
  auto f = lintZ32Files(flat);
  INFO(dump(f.diags));
  CHECK(!hasCode(f.diags, "E211"));
}
