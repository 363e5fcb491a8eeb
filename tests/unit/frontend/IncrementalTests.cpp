//! @file IncrementalTests.cpp
//! @brief frontend::IncrementalFile: after any sequence of edits, the diagnostics of a file
//!        checked again in part equal those of a full check of its final text.
#include <algorithm>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include <doctest/doctest.h>

#include "TestUtil.h"
#include "frontend/Incremental.h"
#include "frontend/ProgramSet.h"
#include "machine/Machine.h"
#include "support/File.h"

using namespace iso;
namespace fs = std::filesystem;

namespace {

/// `text` loaded as the language server loads an open document: compact, through `rec`.
test::Diags loadWith(const std::string& text, const std::string& path, frontend::IncrementalFile* rec,
                     std::vector<diag::Diagnostic>* setLevel = nullptr, const machine::Machine* m = nullptr) {
  if (!m) m = &test::builtin();
  frontend::ProgramSet set;
  frontend::LoadOptions lo;
  lo.machine = m;
  lo.dialect = m->dialect;
  lo.compactTrees = true;
  lo.siblings = false;
  lo.record = {rec};
  lo.setLevel = setLevel;
  std::vector<frontend::ProgramText> one;
  one.push_back({path, text, true});
  frontend::loadProgramTexts(std::move(one), lo, set);
  if (rec && rec->valid()) rec->adopt(std::move(set.files[0])); // as the language server keeps it
  return set.diags.items();
}

/// The set-level diagnostics moved with the lines of the last update (false: a full check).
bool remapAll(const frontend::IncrementalFile& rec, std::vector<diag::Diagnostic>& setLevel) {
  for (auto& d : setLevel)
    if (!rec.remap(d)) return false;
  return true;
}

/// The file's diagnostics as the language server composes them: the record's, then the
/// set-level ones, in the order of a full check (stable by place).
test::Diags composed(const frontend::IncrementalFile& rec, const std::vector<diag::Diagnostic>& setLevel) {
  diag::DiagnosticList l;
  for (auto& d : rec.diagnostics())
    l.items().push_back(d);
  for (auto& d : setLevel)
    l.items().push_back(d);
  l.sort();
  return l.items();
}

size_t countLf(std::string_view s) { return static_cast<size_t>(std::count(s.begin(), s.end(), '\n')); }

struct Stats {
  size_t edits = 0, partial = 0, wholeFile = 0, linesMoved = 0;
};

/// Random edits of `text`: each is applied to the record (update), and the result compared
/// with a full check of the new text.
void editAtRandom(std::string text, const std::string& path, std::mt19937& rng, size_t edits, size_t every,
                  Stats& stats, const machine::Machine* m = nullptr) {
  static const std::string kBytes = "0123456789 .-XYZFGMNR=;:()$\n\tLABEL";
  frontend::IncrementalFile rec(every);
  std::vector<diag::Diagnostic> setLevel;
  loadWith(text, path, &rec, &setLevel, m);
  for (size_t e = 0; e < edits && !text.empty(); ++e) {
    const size_t at = rng() % (text.size() + 1);
    size_t removed = 0;
    std::string inserted;
    switch (rng() % 6) {
    case 0: inserted = std::string(1, kBytes[rng() % kBytes.size()]); break;
    case 4: inserted = "\n"; break; // a line added
    case 5: {                       // a line taken away
      const size_t lf = text.find('\n', at);
      removed = lf == std::string::npos ? 0 : lf - at + 1;
      break;
    }
    case 1: removed = at < text.size() ? 1 : 0; break;
    case 2:
      removed = at < text.size() ? 1 : 0;
      inserted = std::string(1, "0123456789"[rng() % 10]);
      break;
    default: inserted = " "; break;
    }
    const bool sameLines = countLf(std::string_view(text).substr(at, removed)) == countLf(inserted);
    text.replace(at, removed, inserted);
    ++stats.edits;
    std::vector<diag::Diagnostic> freshSet;
    frontend::IncrementalFile fresh(every);
    const test::Diags full = loadWith(text, path, &fresh, &freshSet, m);
    if (rec.update(text, at, removed, inserted.size()) && remapAll(rec, setLevel)) {
      ++stats.partial;
      stats.wholeFile += rec.lastRanWholeFile();
      stats.linesMoved += !sameLines;
      INFO(path, ": edit ", e, " at ", at, " (-", removed, " +'", inserted, "')");
      REQUIRE(test::sameDiagnostics(composed(rec, setLevel), full));
    } else {
      rec = std::move(fresh);
      setLevel = std::move(freshSet);
      if (rec.valid()) CHECK(test::sameDiagnostics(composed(rec, setLevel), full)); // (a binary file has no record)
    }
  }
}

} // namespace

TEST_CASE("incremental: a record's diagnostics are the full check's") {
  const std::string text = "N10 G0 X0 Y0\nL1: G1 X10 F100\nGOTOB L1\nM30\n";
  frontend::IncrementalFile rec(1);
  std::vector<diag::Diagnostic> setLevel;
  const test::Diags full = loadWith(text, "a.mpf", &rec, &setLevel);
  CHECK(rec.valid());
  CHECK(test::sameDiagnostics(composed(rec, setLevel), full));
}

TEST_CASE("incremental: a value edited checks the lines near it, not the file") {
  std::string text;
  for (int k = 0; k < 6000; ++k)
    text += "G1 X" + std::to_string(k % 50) + " Y" + std::to_string(k % 7) + " F100\n";
  text += "M30\n";
  frontend::IncrementalFile rec(8);
  std::vector<diag::Diagnostic> setLevel;
  loadWith(text, "cam.mpf", &rec, &setLevel);
  // line 1001: "G1 X0 Y0 F100" -> F0 is E-worthy (a feed not positive)
  const size_t at = text.find("F100", text.find("G1 X0 Y6", 20000));
  text.replace(at + 1, 3, "0  ");
  REQUIRE(rec.update(text, at + 1, 3, 3));
  CHECK(rec.lastRechecked() < 40);
  const test::Diags full = loadWith(text, "cam.mpf", nullptr);
  CHECK(!full.empty());
  CHECK(test::sameDiagnostics(composed(rec, setLevel), full));
  // and back, given only the bytes it may read (up to a line start)
  text.replace(at + 1, 3, "100");
  size_t reach = rec.reach(text.size(), at + 1, 3, 3);
  CHECK(reach < text.size()); // not the whole text
  while (reach < text.size() && text[reach - 1] != '\n')
    ++reach;
  REQUIRE(rec.update(std::string_view(text).substr(0, reach), text.size(), at + 1, 3, 3));
  CHECK(test::sameDiagnostics(composed(rec, setLevel), loadWith(text, "cam.mpf", nullptr)));
  // too few bytes to agree again: a full check is asked for
  text.replace(at + 1, 3, "0  ");
  const size_t line = text.find('\n', at) + 1;
  CHECK_FALSE(rec.update(std::string_view(text).substr(0, line), text.size(), at + 1, 3, 3));
}

TEST_CASE("incremental: a changed label, jump or end of program runs the whole-file passes again") {
  std::string base;
  for (int k = 0; k < 40; ++k)
    base += "G0 X" + std::to_string(k) + "\n";
  base += "L1: G1 X10 F100\nG0 X2\nGOTOB L1\nG0 X3\nM30\n";
  for (const auto& [from, to] : std::vector<std::pair<std::string, std::string>>{
           {"L1:", "L2:"}, {"GOTOB L1", "GOTOB L2"}, {"M30", "M17"}, {"G0 X2\n", ""}, {"G0 X3", "G0 X3\n\nG0 X4"}}) {
    frontend::IncrementalFile rec(4);
    std::vector<diag::Diagnostic> setLevel;
    loadWith(base, "a.mpf", &rec, &setLevel);
    std::string text = base;
    const size_t at = text.find(from);
    text.replace(at, from.size(), to);
    INFO(from, " -> ", to);
    REQUIRE(rec.update(text, at, from.size(), to.size()));
    CHECK(rec.lastRanWholeFile());
    CHECK(rec.lastRechecked() < 12);
    const test::Diags full = loadWith(text, "a.mpf", nullptr);
    CHECK(!full.empty());
    CHECK(test::sameDiagnostics(composed(rec, setLevel), full));
    // and back
    text = base;
    REQUIRE(rec.update(text, at, to.size(), from.size()));
    CHECK(test::sameDiagnostics(composed(rec, setLevel), loadWith(text, "a.mpf", nullptr)));
  }
}

TEST_CASE("incremental: lines added before a call move the set-level diagnostics") {
  std::string text;
  for (int k = 0; k < 40; ++k)
    text += "G0 X" + std::to_string(k) + "\n";
  text += "G1 X1 F100\nNOSUCH\nM30\n"; // E210: no subprogram NOSUCH
  frontend::IncrementalFile rec(4);
  std::vector<diag::Diagnostic> setLevel;
  loadWith(text, "a.mpf", &rec, &setLevel);
  REQUIRE(setLevel.size() == 1);
  CHECK(setLevel[0].loc.line == 42);
  const size_t at = text.find("G1 X1");
  text.insert(at, "G0 Y1\nG0 Y2\n");
  REQUIRE(rec.update(text, at, 0, 12));
  REQUIRE(remapAll(rec, setLevel));
  CHECK(setLevel[0].loc.line == 44);
  CHECK(test::sameDiagnostics(composed(rec, setLevel), loadWith(text, "a.mpf", nullptr)));
  // the call itself changed: the set-level checks must run again (a full check)
  const size_t call = text.find("NOSUCH");
  text.replace(call, 6, "OTHER1");
  CHECK_FALSE(rec.update(text, call, 6, 6));
  CHECK_FALSE(rec.valid());
}

TEST_CASE("incremental: random edits of the project's programs equal full checks") {
  const fs::path root = ISO_SOURCE_DIR;
  std::vector<fs::path> files = test::programsUnder(root / "samples");
  std::error_code ec;
  for (fs::directory_iterator it(root / "tests" / "fuzz" / "corpus" / "source", ec), end; !ec && it != end;
       it.increment(ec))
    files.push_back(it->path());
  std::sort(files.begin(), files.end());
  std::mt19937 rng(20261203);
  Stats stats;
  size_t n = 0;
  for (const auto& p : files) {
    auto text = support::readFile(p.string());
    if (!text || text->size() > 200000) continue;
    const std::string ext = p.extension().string();
    const std::string name = ext.empty() ? p.filename().string() + ".mpf" : p.filename().string();
    editAtRandom(*text, name, rng, 12, 1 + n % 4, stats);
    ++n;
  }
  // the samples with a machine file of their own (z32: special M functions, user parameters),
  // checked with it, alone (a special M's subprogram is then unknown: a set-level diagnostic)
  for (const char* folder : {"z32_toolchange", "z32_flow", "wait_input"}) {
    const fs::path dir = root / "samples" / folder;
    auto json = support::readFile((dir / "machine.json").string());
    REQUIRE(json);
    const machine::MachineResult m = machine::parseMachine(*json);
    REQUIRE(m);
    for (const auto& p : test::programsUnder(dir)) {
      auto text = support::readFile(p.string());
      REQUIRE(text);
      for (int round = 0; round < 4; ++round)
        editAtRandom(*text, p.filename().string(), rng, 12, 1 + static_cast<size_t>(round), stats, &*m);
      ++n;
    }
  }
  CHECK(n > 20);
  MESSAGE(stats.partial << " of " << stats.edits << " edits checked in part, " << stats.wholeFile
                        << " of them with the whole-file passes again, " << stats.linesMoved << " moving lines");
  CHECK(stats.partial * 4 > stats.edits); // the test reaches the partial path
  CHECK(stats.wholeFile * 10 > stats.partial);
  CHECK(stats.linesMoved * 20 > stats.partial);
}
