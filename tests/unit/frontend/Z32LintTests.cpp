//! @file Z32LintTests.cpp
//! @brief Dialect z32 in isolint (SPEC §4.6, §7): the per-line limits (E312), S T MA MB MC
//!        words and expressions, special M as calls (E210, E211 with the chain, E212 in a
//!        WHEN body), I501 in the z32 order, and that none of it applies in dialect sidac.
#include <string>
#include <vector>

#include <doctest/doctest.h>
#include <fmt/format.h>

#include "TestUtil.h"

using namespace iso;
using test::dump;
using test::hasCode;
using test::lintFiles;
using test::lintText;
using test::lintZ32;

namespace {
machine::Machine specialMachine() {
  machine::Machine m = machine::builtinMachine();
  m.dialect = machine::Dialect::Z32;
  m.specialM = {{6, "CAMBIO"}, {40, "PALLET"}};
  return m;
}
} // namespace

TEST_CASE("z32 lint: per-line limits of seed 004 (E312)") {
  struct Case {
    const char* line;
    uint32_t col;
    const char* what;
  } bad[] = {
      {"M23 M24", 5, "at most one M function that is neither managed nor final"},
      // M=NB of a plain sequence is an other M too (SPEC §4.6)
      {"M=NB(23) M24", 10, "at most one M function that is neither managed nor final"},
      {"M24 M=NB(23)", 5, "at most one M function that is neither managed nor final"},
      {"M=NB(23) M=NB(24)", 10, "at most one M function that is neither managed nor final"},
      {"S100 M3 M4", 9, "M3 and M4 on one line"},
      {"M0 M2", 4, "two end functions"},
      {"M1 M30", 4, "two end functions"},
      {"M=NB(3)", 1, "managed by the control"},
      {"M=NB(2)", 1, "a final M function"},
      {"M=NB(1)", 1, "a final M function"},
  };
  for (const Case& c : bad) {
    CAPTURE(c.line);
    auto d = lintZ32(std::string(c.line) + "\nM30\n");
    INFO(dump(d));
    REQUIRE(hasCode(d, "E312", 1, c.col));
    CHECK(test::find(d, "E312")->message.find(c.what) != std::string::npos);
  }
  // seed 004: all managed M, one final M and one other M on one line are legal
  auto ok = lintZ32("S100 T1 M3 M5 M6 M7 M8 M9 M19 M23 M2\n");
  INFO(dump(ok));
  CHECK(test::errorCount(ok) == 0);
  CHECK(!hasCode(ok, "E312"));
}

TEST_CASE("z32 lint: M=NB of a special M is E312 - the special M is a call (E210 when missing)") {
  auto r =
      lintFiles({{"main.mpf", "M=NB(40)\nM40\nM30\n"}, {"pallet.spf", "PROC PALLET SAVE\nM17\n"}}, specialMachine());
  REQUIRE(r.loaded);
  INFO(dump(r.diags));
  CHECK(hasCode(r.diags, "E312", 1, 1));
  CHECK(test::find(r.diags, "E312")->message.find("a special M (it calls 'PALLET')") != std::string::npos);
  CHECK(!hasCode(r.diags, "E210"));

  auto missing = lintFiles({{"main.mpf", "G0 X1\nM40\nM30\n"}}, specialMachine());
  REQUIRE(missing.loaded);
  REQUIRE(hasCode(missing.diags, "E210", 2, 1));
  CHECK(
      test::find(missing.diags, "E210")->message.find("M40 is a special M of machine 'default' that calls 'PALLET'") ==
      0);
  // without the map (or in sidac) M40 is a plain PLC sequence
  auto plain = lintFiles({{"main.mpf", "G0 X1\nM40\nM30\n"}}, test::builtin(), machine::Dialect::Z32);
  REQUIRE(plain.loaded);
  CHECK(test::errorCount(plain.diags) == 0);
}

TEST_CASE("z32 lint: nesting over 10 counts special M, with the chain in the notes (E211)") {
  // main -M40-> PALLET -> S1 -> ... -> S10: 11 levels
  std::vector<std::pair<std::string, std::string>> files = {{"main.mpf", "M40\nM30\n"},
                                                            {"pallet.spf", "PROC PALLET SAVE\nS1\nM17\n"}};
  // S1 is a subprogram name here, not a spindle speed: a call stands alone on its line
  for (int i = 1; i <= 10; ++i)
    files.push_back({fmt::format("s{}.spf", i),
                     fmt::format("PROC Sub{} SAVE\n{}M17\n", i, i < 10 ? fmt::format("Sub{}\n", i + 1) : "")});
  files[1].second = "PROC PALLET SAVE\nSub1\nM17\n";
  auto r = lintFiles(files, specialMachine());
  REQUIRE(r.loaded);
  INFO(dump(r.diags));
  REQUIRE(hasCode(r.diags, "E211", 1, 1));
  const diag::Diagnostic* d = test::find(r.diags, "E211");
  CHECK(d->message == "call nesting depth 11 exceeds the limit of 10");
  REQUIRE(d->notes.size() == 11);
  CHECK(d->notes[0].message == "level 1: M40 (special) calls 'PALLET'");
  CHECK(d->notes[1].message == "level 2: calls 'Sub1'");
  // one level less is clean
  files.pop_back();
  files.back().second = "PROC Sub9 SAVE\nM17\n";
  auto ok = lintFiles(files, specialMachine());
  REQUIRE(ok.loaded);
  CHECK(!hasCode(ok.diags, "E211"));
}

TEST_CASE("z32 lint: a special M in a WHEN body is E212 - a special M ends reachability only for its line") {
  auto r = lintFiles(
      {{"main.mpf", "WHEN $aa_iw[X] > 5 DO M40\nG1 F100 X10\nM30\n"}, {"pallet.spf", "PROC PALLET SAVE\nM17\n"}},
      specialMachine());
  REQUIRE(r.loaded);
  INFO(dump(r.diags));
  CHECK(hasCode(r.diags, "E212", 1, 0));
  // 'M40 M30': the M30 never runs, so the end of the program is still reachable (W405)
  auto w = lintFiles({{"main.mpf", "G0 X1\nM40 M30\n"}, {"pallet.spf", "PROC PALLET SAVE\nM17\n"}}, specialMachine());
  REQUIRE(w.loaded);
  INFO(dump(w.diags));
  CHECK(hasCode(w.diags, "W415", 2, 1));
  CHECK(hasCode(w.diags, "W405"));
}

TEST_CASE("z32 lint: S T MA MB MC take numbers and expressions - bad constants are errors") {
  auto ok = lintZ32("R1=2\nS=R1*500 T=R1 MA=R1+1 MB-3 MC0.5\nS1000 T12 M3 M6\nM30\n");
  INFO(dump(ok));
  CHECK(ok.empty());
  auto bad = lintZ32("S-5\nT1.5\nT-2\nM30\n");
  INFO(dump(bad));
  CHECK(hasCode(bad, "E100", 1, 1));
  CHECK(hasCode(bad, "E100", 2, 1));
  CHECK(hasCode(bad, "E100", 3, 1));
  // an undefined R in an MA expression is checked like any expression
  CHECK(hasCode(lintZ32("MA=R0\nM30\n"), "E301"));
}

TEST_CASE("z32 lint: I501 only for M that run before the motion in the z32 order") {
  // M5, M6, M19 and the final M run after the motion: no note
  auto after = lintZ32("T1 S1 G0 X10 M5 M19 M6 M30\n");
  INFO(dump(after));
  CHECK(!hasCode(after, "I501"));
  CHECK(hasCode(lintZ32("S1 G0 X10 M3\nM30\n"), "I501", 1, 11));
  CHECK(hasCode(lintZ32("G0 X10 M23\nM30\n"), "I501", 1, 8));
  CHECK(hasCode(lintZ32("G0 X10 M8\nM30\n"), "I501", 1, 8));
}

TEST_CASE("z32 lint: nothing of z32 applies in dialect sidac") {
  auto d = lintText("S100 M3\nMA5\nM2\nM30\n");
  INFO(dump(d));
  CHECK(hasCode(d, "E110", 1, 1)); // S words are another dialect's
  CHECK(!hasCode(d, "W417"));
  CHECK(!hasCode(d, "W416"));
  CHECK(!hasCode(d, "E312"));
}
