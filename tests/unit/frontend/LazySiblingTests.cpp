//! @file LazySiblingTests.cpp
//! @brief isolint loads a sibling program only when a loaded file calls it (SiblingLoad::
//!        Called, with compact trees as isolint has them): the diagnostics of the named
//!        files are those of a full load.
#include <algorithm>
#include <string>
#include <vector>

#include <doctest/doctest.h>

#include "TestUtil.h"
#include "diag/Render.h"
#include "frontend/ProgramSet.h"

using namespace iso;

namespace {
struct Loaded {
  frontend::ProgramSet set;
  std::vector<std::string> files; ///< file names loaded
  std::string shown;              ///< the named files' diagnostics as text
};

void load(const std::string& main, bool lazy, Loaded& out, const machine::Machine& m = test::builtin()) {
  frontend::LoadOptions lo;
  lo.machine = &m;
  lo.dialect = m.dialect;
  lo.siblingLoad = lazy ? frontend::SiblingLoad::Called : frontend::SiblingLoad::All;
  lo.compactTrees = lazy; // as isolint loads: lazy siblings and compact trees together
  frontend::SetError err;
  REQUIRE(frontend::loadProgramSet({main}, lo, out.set, err));
  for (const auto& f : out.set.files)
    out.files.push_back(std::filesystem::path(f.path).filename().string());
  std::sort(out.files.begin(), out.files.end());
  std::vector<diag::Diagnostic> shown;
  for (const auto& d : out.set.diags.items())
    if (out.set.reported[d.loc.file]) shown.push_back(d);
  out.shown = diag::renderText(shown, out.set.sources, false);
}
} // namespace

TEST_CASE("lazy siblings: only the called chain is loaded, with the same diagnostics") {
  test::TempDir dir;
  const std::string main = dir.write("main.mpf", "G0 X10\nAlza\nGiu\nMissing\nM30\n");
  dir.write("alza.spf", "PROC Alza SAVE\nSotto\nM17\n");     // called
  dir.write("sotto.spf", "PROC Sotto SAVE\nG0 Z5\nM17\n");   // called by a sibling
  dir.write("giu.spf", "PROC Giu SAVE\nG0 Z0\nM17\n");       // called
  dir.write("giu2.spf", "PROC GIU SAVE\nM17\n");             // a duplicate of a called name (E209)
  dir.write("uncalled.spf", "PROC Nessuno SAVE\nGOTOF X\n"); // never called: never parsed
  dir.write("other.mpf", "G0 X1\nM30\n");                    // another main program
  dir.write("image.spf", std::string("ISOB\r\n\x1a\n", 8) + std::string(40, '\0'));
  Loaded lazy, full;
  load(main, true, lazy);
  load(main, false, full);
  CHECK(lazy.files == std::vector<std::string>{"alza.spf", "giu.spf", "giu2.spf", "main.mpf", "sotto.spf"});
  CHECK(full.files.size() == 8);
  CHECK(lazy.shown == full.shown);
  CHECK(lazy.shown.find("E210") != std::string::npos); // Missing is still unknown
}

TEST_CASE("lazy siblings: z32 special M subprograms are loaded too") {
  test::TempDir dir;
  machine::Machine m = test::builtin();
  m.dialect = machine::Dialect::Z32;
  m.specialM = {{40, "PALLET"}};
  const std::string main = dir.write("main.mpf", "M40\nM30\n");
  dir.write("pallet.spf", "PROC PALLET SAVE\nM17\n");
  dir.write("x.spf", "PROC X_UNUSED SAVE\nM17\n");
  Loaded lazy, full;
  load(main, true, lazy, m);
  load(main, false, full, m);
  CHECK(lazy.files == std::vector<std::string>{"main.mpf", "pallet.spf"});
  CHECK(lazy.shown == full.shown);
  CHECK(lazy.shown.empty());
}

TEST_CASE("lazy siblings: a PROC line after 64 KiB of comments is still found") {
  test::TempDir dir;
  const std::string main = dir.write("main.mpf", "Tardi\nM30\n");
  std::string late;
  for (int i = 0; i < 3000; ++i)
    late += "; a long comment block before the header of this subprogram\n";
  dir.write("tardi.spf", late + "PROC Tardi SAVE\nM17\n");
  Loaded lazy;
  load(main, true, lazy);
  CHECK(lazy.files == std::vector<std::string>{"main.mpf", "tardi.spf"});
  CHECK(lazy.shown.empty());
}
