//! @file SiblingLoadTests.cpp
//! @brief isocc and isosim read only the siblings an image links (SiblingLoad::Linked): the
//!        subprograms the loaded files call (and those defining a name twice, for E209), every
//!        semi-automatic program, and the main programs only when no named file is one. The
//!        others cost their first lines; images and diagnostics are those of a load of every
//!        sibling.
#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include <doctest/doctest.h>

#include "TestUtil.h"
#include "compiler/Compiler.h"
#include "diag/Render.h"
#include "driver/Compile.h"
#include "driver/Lint.h"
#include "driver/Settings.h"
#include "driver/Sources.h"
#include "image/ImageWriter.h"
#include "sim/SimToolRun.h"
#include "support/File.h"

using namespace iso;
namespace fs = std::filesystem;
using test::contains;
using test::TempDir;

namespace {

/// A program set loaded as isocc loads it (Linked) or with every sibling (All).
struct Loaded {
  frontend::ProgramSet set;
  std::vector<std::string> files;  ///< the file names read whole, sorted
  std::vector<std::string> unread; ///< the file names of set.unread, sorted
  std::string shown;               ///< what isocc prints of the diagnostics (its linked units reported)
  int rc = -1;                     ///< loadToolSources' exit code
};

std::vector<std::string> namesOf(const std::vector<std::string>& paths) {
  std::vector<std::string> out;
  for (const auto& p : paths)
    out.push_back(fs::path(p).filename().string());
  std::sort(out.begin(), out.end());
  return out;
}

compiler::CompileOptions compileOptions(const machine::Machine& m) {
  compiler::CompileOptions co;
  co.dialect = m.dialect;
  co.specialM = &m.specialM;
  co.parameters = &m.parameters;
  return co;
}

/// isosim PROGRAM --summary, in process.
driver::SimulateOptions summaryOf(const std::string& program) {
  driver::SimulateOptions s;
  s.program = program;
  s.summary = true;
  s.common.color = "never";
  return s;
}

void load(const std::vector<std::string>& paths, frontend::SiblingLoad how, Loaded& out,
          const machine::Machine& m = test::builtin()) {
  std::ostringstream os, es;
  driver::Io io{os, es};
  const driver::Settings settings;
  if (how == frontend::SiblingLoad::Linked) {
    out.rc = driver::loadToolSources(paths, m, 2, settings, out.set, io, "isocc");
  } else { // what isocc did before: every sibling, then the linked units reported
    driver::SourceOptions so;
    so.jobs = 2;
    driver::loadSources(paths, m, so, out.set);
    compiler::CompileError ignored;
    for (size_t u : compiler::linkedUnits(out.set, compileOptions(m), ignored))
      out.set.reported[u] = 1;
    driver::filterDiagnostics(out.set, driver::settingsFilter(out.set, settings));
    out.rc = driver::kExitOk;
  }
  std::vector<std::string> files;
  for (const auto& f : out.set.files)
    files.push_back(f.path);
  out.files = namesOf(files);
  out.unread = namesOf(out.set.unread);
  std::vector<diag::Diagnostic> shown;
  for (const auto& d : out.set.diags.items())
    if (out.set.reported[d.loc.file]) shown.push_back(d);
  out.shown = diag::renderText(shown, out.set.sources, false);
}

/// The image isocc writes for the loaded set ("" when it does not compile).
std::string imageOf(const Loaded& l, const machine::Machine& m = test::builtin()) {
  image::Image img;
  compiler::CompileError err;
  if (!compiler::compileProgramSet(l.set, compileOptions(m), img, err)) return "";
  const std::vector<uint8_t> bytes = image::writeImage(img);
  return std::string(bytes.begin(), bytes.end());
}

/// Both loads of `paths`: what isocc reads now and what a load of every sibling gives.
struct Both {
  Loaded linked, all;
};
void loadBoth(const std::vector<std::string>& paths, Both& b, const machine::Machine& m = test::builtin()) {
  load(paths, frontend::SiblingLoad::Linked, b.linked, m);
  load(paths, frontend::SiblingLoad::All, b.all, m);
}

/// A main program of about `bytes` bytes: valid first lines, then motion blocks.
std::string largeMain(size_t bytes) {
  std::string s = "; CAM program\nG90 G01 F1000\n";
  s.reserve(bytes + 32);
  while (s.size() < bytes)
    s += "X123.456 Y654.321 Z-1.5\n";
  return s + "M30\n";
}

} // namespace

TEST_CASE("isocc's siblings: a called subprogram and a semi-automatic program are read, the rest is not") {
  TempDir dir;
  const std::string main = dir.write("main.mpf", "G0 X10\nAlza\nM30\n");
  dir.write("alza.spf", "PROC Alza SAVE\nSotto\nM17\n");         // called
  dir.write("sotto.spf", "PROC Sotto SAVE\nG0 Z5\nM17\n");       // called by a called one
  dir.write("semi.mpf", "SEMI \"Carico\"\nUsata\nG0 Y1\nM30\n"); // linked into every image
  dir.write("usata.spf", "PROC Usata SAVE\nG0 Y2\nM17\n");       // called by the semi program
  dir.write("nessuno.spf", "PROC Nessuno SAVE\nGOTOF X\n");      // called by nobody (and broken)
  dir.write("cam.mpf", largeMain(1 << 20));                      // another main program
  Both b;
  loadBoth({main}, b);
  REQUIRE(b.linked.rc == driver::kExitOk);
  CHECK(b.linked.files == std::vector<std::string>{"alza.spf", "main.mpf", "semi.mpf", "sotto.spf", "usata.spf"});
  CHECK(b.linked.unread == std::vector<std::string>{"cam.mpf", "nessuno.spf"});
  CHECK(b.all.files.size() == 7);
  CHECK(b.linked.shown == b.all.shown);
  const std::string img = imageOf(b.linked);
  REQUIRE(!img.empty());
  CHECK(img == imageOf(b.all)); // the very same bytes
  CHECK(contains(img, "Carico"));
  CHECK(contains(img, "Usata"));
}

TEST_CASE("isocc's siblings: a large main program beside the named one is never read whole") {
  TempDir dir;
  const std::string main = dir.write("main.mpf", "G0 X10\nM30\n");
  // beyond its first lines the sibling is not a program at all: read whole it would be binary
  std::string cam = "; CAM program\nG90 G01 F1000\n";
  cam += std::string(128 * 1024, '\0');
  dir.write("cam.mpf", cam);
  Loaded l;
  load({main}, frontend::SiblingLoad::Linked, l);
  REQUIRE(l.rc == driver::kExitOk);
  CHECK(l.files == std::vector<std::string>{"main.mpf"});
  CHECK(l.unread == std::vector<std::string>{"cam.mpf"});
  CHECK(l.set.diags.items().empty());
  CHECK(l.set.sources.size() == 1);
}

TEST_CASE("isocc's siblings: a SEMI line after 64 KiB of comments is still found") {
  TempDir dir;
  const std::string main = dir.write("main.mpf", "G0 X1\nM30\n");
  std::string late;
  for (int i = 0; i < 3000; ++i)
    late += "; a long comment block before the header of this semi-automatic program\n";
  dir.write("tardi.mpf", late + "SEMI \"Tardi\"\nG0 X2\nM30\n");
  Both b;
  loadBoth({main}, b);
  CHECK(b.linked.files == std::vector<std::string>{"main.mpf", "tardi.mpf"});
  CHECK(imageOf(b.linked) == imageOf(b.all));
  CHECK(contains(imageOf(b.linked), "Tardi"));
}

TEST_CASE("isocc's siblings: E209 fires where it fired") {
  TempDir dir;
  const std::string main = dir.write("main.mpf", "Giu\nM30\n");
  const std::string giu = dir.write("giu.spf", "PROC Giu SAVE\nG0 Z0\nM17\n");
  const std::string giu2 = dir.write("giu2.spf", "PROC GIU SAVE\nM17\n"); // the same name again
  dir.write("uno.spf", "PROC Uno SAVE\nM17\n");                           // a name defined twice that nobody calls
  dir.write("uno2.spf", "PROC UNO SAVE\nM17\n");
  // both read, as a full load has them (the second one is reported where it is shown)
  Both b;
  loadBoth({main}, b);
  CHECK(b.linked.files == std::vector<std::string>{"giu.spf", "giu2.spf", "main.mpf"});
  CHECK(b.linked.unread == std::vector<std::string>{"uno.spf", "uno2.spf"});
  CHECK(b.linked.shown == b.all.shown);
  CHECK(imageOf(b.linked) == imageOf(b.all));

  // the second definition named: E209 is shown and stops the compilation
  Both named;
  loadBoth({main, giu, giu2}, named);
  CHECK(named.linked.shown == named.all.shown);
  CHECK(contains(named.linked.shown, "giu2.spf:1:6: error"));
  CHECK(contains(named.linked.shown, "E209"));
  CHECK(diag::countOf(named.linked.set.diags.items()).errors > 0); // isocc writes nothing

  // a named subprogram whose name a sibling defines too: that sibling is read for E209
  Both uno;
  loadBoth({main, dir.path() + "/uno2.spf"}, uno);
  CHECK(uno.linked.files == std::vector<std::string>{"giu.spf", "giu2.spf", "main.mpf", "uno.spf", "uno2.spf"});
  CHECK(uno.linked.shown == uno.all.shown);

  // the folder: every file is named, E209 in uno2.spf and giu2.spf
  Both folder;
  loadBoth({dir.path()}, folder);
  CHECK(folder.linked.shown == folder.all.shown);
  CHECK(contains(folder.linked.shown, "uno2.spf:1:6: error"));
  CHECK(contains(folder.linked.shown, "giu2.spf:1:6: error"));
}

TEST_CASE("isocc's siblings: the diagnostics of linked siblings come in the order of a full load") {
  TempDir dir;
  // the semi-automatic program is read before the subprograms it is sorted after, and the
  // subprograms after it: the diagnostics still follow the files' order in the folder
  const std::string main = dir.write("b_main.mpf", "Zeta\nAlfa\nG01 X1\nM30\n"); // W402 feed-unset
  dir.write("a_semi.mpf", "SEMI \"S\"\nG01 X2\nM30\n");                          // W402
  dir.write("alfa.spf", "PROC Alfa SAVE\nG01 Y1\nM17\n");                        // W402
  dir.write("zeta.spf", "PROC Zeta SAVE\nG01 Z1\nM17\n");                        // W402
  dir.write("c_semi.mpf", "SEMI \"T\"\nG01 Y2\nM30\n");                          // W402
  Both b;
  loadBoth({main}, b);
  CHECK(b.linked.unread.empty());
  REQUIRE(!b.linked.shown.empty());
  CHECK(b.linked.shown == b.all.shown);
  const size_t semi = b.linked.shown.find("a_semi.mpf:");
  const size_t alfa = b.linked.shown.find("alfa.spf:");
  const size_t mainAt = b.linked.shown.find("b_main.mpf:");
  CHECK(mainAt < semi); // named first, then the siblings in their order
  CHECK(semi < alfa);
  CHECK(alfa < b.linked.shown.find("c_semi.mpf:")); // read before alfa.spf, sorted after it
}

TEST_CASE("isocc's siblings: with no named main program the sibling main programs are read") {
  TempDir dir;
  const std::string sub = dir.write("giu.spf", "PROC Giu SAVE\nG0 Z0\nM17\n");
  dir.write("main.mpf", "Giu\nM30\n");
  Both one;
  loadBoth({sub}, one);
  CHECK(one.linked.files == std::vector<std::string>{"giu.spf", "main.mpf"});
  CHECK(!imageOf(one.linked).empty());
  CHECK(imageOf(one.linked) == imageOf(one.all));

  dir.write("other.mpf", "G0 X5\nM30\n");
  Loaded two;
  load({sub}, frontend::SiblingLoad::Linked, two);
  compiler::CompileOptions co;
  image::Image img;
  compiler::CompileError err;
  CHECK_FALSE(compiler::compileProgramSet(two.set, co, img, err));
  CHECK(contains(err.message, "several main programs and none named"));
  CHECK(contains(err.message, "main.mpf"));
  CHECK(contains(err.message, "other.mpf"));
}

TEST_CASE("isocc's siblings: z32 special M and KG subprograms are read") {
  machine::Machine m = test::builtin();
  m.dialect = machine::Dialect::Z32;
  m.specialM = {{40, "PALLET"}};
  TempDir dir;
  const std::string main = dir.write("main.mpf", "M40\nM30\n");
  dir.write("pallet.spf", "PROC PALLET SAVE\nKGFINE\nM17\n");
  dir.write("fine.spf", "PROC FINE SAVE\nG0 X1\nM17\n");
  dir.write("x.spf", "PROC X_UNUSED SAVE\nM17\n");
  Both b;
  loadBoth({main}, b, m);
  CHECK(b.linked.files == std::vector<std::string>{"fine.spf", "main.mpf", "pallet.spf"});
  CHECK(b.linked.shown == b.all.shown);
  CHECK(imageOf(b.linked, m) == imageOf(b.all, m));
}

TEST_CASE("isocc's siblings: every sample compiles to the same image from its main program as from its folder") {
  const fs::path samples = fs::path(ISO_SOURCE_DIR) / "samples";
  for (const auto& entry : fs::directory_iterator(samples)) {
    if (!entry.is_directory()) continue;
    CAPTURE(entry.path().string());
    machine::Machine m = test::builtin();
    if (fs::exists(entry.path() / "machine.json")) {
      auto text = support::readFile((entry.path() / "machine.json").string());
      REQUIRE(text);
      machine::MachineErrors errors;
      auto parsed = machine::parseMachine(*text, errors);
      REQUIRE(parsed);
      m = std::move(*parsed);
    }
    Loaded folder;
    load({entry.path().string()}, frontend::SiblingLoad::All, folder, m);
    const std::string expected = imageOf(folder, m);
    REQUIRE(!expected.empty());
    for (const auto& f : fs::directory_iterator(entry.path())) {
      if (f.path().extension() != ".mpf") continue;
      Loaded one;
      load({f.path().string()}, frontend::SiblingLoad::Linked, one, m);
      CAPTURE(f.path().string());
      if (one.set.files[one.set.namedOrder.front()].kind != frontend::UnitKind::Main) continue;
      CHECK(imageOf(one, m) == expected);
    }
  }
}

TEST_CASE("isocc and isosim: an output onto a sibling that was not read is refused") {
  TempDir dir;
  const std::string main = dir.write("main.mpf", "G0 X10\nM30\n");
  const std::string other = dir.write("other.mpf", "G0 X1\nM30\n");
  driver::CompileOptions o;
  o.paths = {main};
  o.output = other;
  o.common.color = "never";
  std::ostringstream out, err;
  driver::Io io{out, err};
  CHECK(driver::runCompile(o, io) == driver::kExitUsage);
  CHECK(contains(err.str(), "would overwrite the input"));
  CHECK(support::readFile(other).value() == "G0 X1\nM30\n");

  driver::SimulateOptions s = summaryOf(main);
  s.output = other;
  const test::ToolRun r = test::runSim(s);
  CHECK(r.rc == driver::kExitUsage);
  CHECK(contains(r.err, "would overwrite the input"));
  CHECK(support::readFile(other).value() == "G0 X1\nM30\n");
}

TEST_CASE("isosim --search: a label only in a sibling that the run does not read is still named") {
  TempDir dir;
  const std::string main = dir.write("main.mpf", "G0 X10\nM30\n");
  dir.write("other.mpf", "G0 X1\nAltrove: G0 X2\nM30\n");
  driver::SimulateOptions s = summaryOf(main);
  s.search = "Altrove";
  const test::ToolRun r = test::runSim(s);
  CHECK(r.rc == driver::kExitUsage);
  CHECK(contains(r.err, "other.mpf:2"));
  CHECK(contains(r.err, "not in the entry program"));
}

TEST_CASE("isosim: a source beside a large uncalled main program runs as alone") {
  TempDir dir;
  const std::string main = dir.write("main.mpf", "SottoP\nG0 X10\nM30\n");
  dir.write("sotto.spf", "PROC SottoP SAVE\nG0 Y5\nM17\n");
  dir.write("cam.mpf", largeMain(2 << 20));
  driver::SimulateOptions s = summaryOf(main);
  s.format = "json";
  const test::ToolRun r = test::runSim(s);
  CHECK(r.rc == driver::kExitOk);
  CHECK(contains(r.out, "\"status\": \"ok\""));
  Loaded l;
  load({main}, frontend::SiblingLoad::Linked, l);
  CHECK(l.files == std::vector<std::string>{"main.mpf", "sotto.spf"});
  CHECK(l.unread == std::vector<std::string>{"cam.mpf"});
}
