//! @file CompactTreeTests.cpp
//! @brief isolint's one pass (LoadOptions::compactTrees, parseAndCheckFile): a checked line keeps
//!        only what the checks of the whole file read, and the diagnostics are those of the
//!        full tree. (Every lintText and lintFiles of the unit tests compares the two loads too.)
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <doctest/doctest.h>

#include "TestUtil.h"
#include "frontend/ProgramSet.h"
#include "support/File.h"

using namespace iso;
namespace fs = std::filesystem;

namespace {

/// The full and the compact load of one source, checked to agree.
std::pair<std::unique_ptr<frontend::ProgramSet>, std::unique_ptr<frontend::ProgramSet>>
loadBoth(const std::string& text, const machine::Machine& m = test::builtin(), const std::string& path = "t.mpf") {
  auto full = test::loadSource(text, path, m, std::nullopt, false);
  auto compact = test::loadSource(text, path, m, std::nullopt, true);
  frontend::LoadOptions lo;
  lo.machine = &m;
  lo.dialect = m.dialect;
  test::checkCompactLoad(*full, *compact, &lo);
  return {std::move(full), std::move(compact)};
}

machine::Machine z32Machine() {
  machine::Machine m = test::builtin();
  m.dialect = machine::Dialect::Z32;
  m.specialM = {{40, "PALLET"}};
  return m;
}

/// Programs up to this size are also split in compareAll.
constexpr size_t kSplitBytes = 16 * 1024;

/// Loads every program of `files` alone, full, compact and (up to kSplitBytes) split in two at
/// two places, on both dialects; returns how many.
size_t compareAll(const std::vector<fs::path>& files) {
  const machine::Machine z32 = z32Machine();
  size_t n = 0;
  for (const auto& p : files) {
    auto text = support::readFile(p.string());
    if (!text) continue;
    // .nc files are read as main programs
    const std::string name = p.extension() == ".nc" ? p.stem().string() + ".mpf" : p.filename().string();
    for (const machine::Machine* m : {&test::builtin(), &z32}) {
      INFO(p.string() << (m == &z32 ? " (z32)" : " (sidac)"));
      auto both = loadBoth(*text, *m, name);
      // (the unit tests run unoptimised: larger files are split by the split tests' own 1 MiB
      // program, the safety test's and the fuzz target's inputs)
      if (text->size() <= kSplitBytes) test::checkSplitLoads(*both.first, *text, name, *m, std::nullopt, 2, false);
    }
    ++n;
  }
  return n;
}

} // namespace

TEST_CASE("compact tree: a checked line keeps its M items and moved axes, no expression") {
  const std::string text = "G1 X10 Y20 F100\n"
                           "R1 = 2 + 3 * R2\n"
                           "M3 G1 X5\n"
                           "IF R1 > 2 THEN G1 X7 M8\n"
                           "WHEN $aa_iw[X] > 5 DO $aa_out[1] = 1\n"
                           "G1 X20\n"
                           "POSA[Z] = 4 G1 Y2\n"
                           "M30\n";
  auto [full, compact] = loadBoth(text);
  const frontend::File& f = compact->files.at(0);
  REQUIRE(f.stmts.size() == 8);
  // only M items are left: M3, M8 (the THEN block), M30
  std::vector<int> ms;
  for (const auto& it : f.items) {
    CHECK(it.kind == frontend::ItemKind::M);
    CHECK(it.value == frontend::kNoExpr);
    ms.push_back(it.code);
  }
  CHECK(ms == std::vector<int>{3, 8, 30});
  CHECK(f.stmts[0].itemCount == 0);
  CHECK(f.itemsOf(f.stmts[2])[0].code == 3);
  CHECK(f.itemsOf(f.inner.at(0))[0].code == 8);
  // the full tree holds every value, the compact one none; a WHEN's axes are a side table
  CHECK(full->files.at(0).exprs.size() > 10);
  CHECK(f.exprs.empty());
  CHECK(f.stmts[3].cond == frontend::kNoExpr);
  CHECK(f.stmts[4].cond == frontend::kNoExpr);
  CHECK(f.whenAxesOf(4) == "X");
  CHECK(f.whenAxesOf(3) == "");
  // the moved axes stay, as masks
  CHECK(f.stmts[0].movedAxes == ((1u << ('X' - 'A')) | (1u << ('Y' - 'A'))));
  CHECK(f.stmts[6].posaAxes == (1u << ('Z' - 'A')));
  CHECK(f.stmts[6].movedAxes == (1u << ('Y' - 'A')));
  CHECK(f.stmts[1].movedAxes == 0);
}

TEST_CASE("compact tree: WHEN triggers and chains are checked from the moved-axes masks") {
  // W-codes of the trigger checks fire the same way in both loads (checkCompactLoad) ...
  const std::string text = "WHEN $aa_iw[X] > 5 DO $aa_out[1] = 1\n"
                           "POSA[X] = 10\n"
                           "WHEN $aa_iw[Y] > 5 DO $aa_out[2] = 1\n"
                           "G1 X3 F100\n"
                           "WHEN $aa_iw[X] > 1 DO $aa_out[3] = 1\n"
                           "G1 X4\n"
                           "M30\n";
  auto [full, compact] = loadBoth(text);
  // ... and they do fire: a POSA trigger (line 1), a trigger that does not move Y (line 3);
  // line 5 is fine
  const auto& d = compact->diags.items();
  CHECK(test::hasCode(d, "E213", 1));
  CHECK(test::hasCode(d, "E213", 3));
  CHECK_FALSE(test::hasCode(d, "E213", 5));
}

TEST_CASE("WHEN axes: every $AA_IW axis of the condition, in the order written") {
  auto set = test::loadText("WHEN (($aa_iw[Y] > 1) AND ($aa_iw[X] < R1)) OR ($aa_iw[Y] == 2) DO $aa_out[1] = 1\n"
                            "G1 X1 Y1 F100\n"
                            "WHEN $aa_in[3] == 1 DO $aa_out[2] = 1\n"
                            "G1 X2\n"
                            "M30\n");
  const frontend::File& f = set->files.at(0);
  REQUIRE(f.whenAxes.size() == 2);
  CHECK(f.whenAxesOf(0) == "YXY");
  CHECK(f.whenAxesOf(2) == ""); // reads no axis: E213 "reads no axis"
  CHECK(f.whenAxesOf(1) == "");
  CHECK(test::hasCode(set->diags.items(), "E213", 3));
  CHECK_FALSE(test::hasCode(set->diags.items(), "E213", 1));
}

TEST_CASE("compact tree: z32 special M in a block still calls its subprogram") {
  const machine::Machine m = z32Machine();
  auto [full, compact] = loadBoth("G0 X1\nM40\nM30\n", m);
  CHECK(test::hasCode(compact->diags.items(), "E210", 2)); // PALLET is not loaded: an unknown call
}

TEST_CASE("compact tree: the project's programs give the same diagnostics") {
  const fs::path root = ISO_SOURCE_DIR;
  size_t n = compareAll(test::programsUnder(root / "tests")) + compareAll(test::programsUnder(root / "samples"));
  CHECK(n > 50);
}

TEST_CASE("compact tree: the shared corpus gives the same diagnostics") {
  const fs::path corpus = fs::path(ISO_SHARED_DIR) / "corpus";
  std::error_code ec;
  if (!fs::is_directory(corpus, ec)) {
    MESSAGE("skipped: " << corpus.string() << " is not there");
    return;
  }
  CHECK(compareAll(test::programsUnder(corpus)) > 10);
}
