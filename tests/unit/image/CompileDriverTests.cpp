//! @file CompileDriverTests.cpp
//! @brief isocc in-process: modes, exit codes, messages, determinism, no file on errors.
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <doctest/doctest.h>
#include <fmt/format.h>

#include "TestUtil.h"
#include "driver/Compile.h"
#include "image/ImageReader.h"
#include "image/ImageWriter.h"
#include "support/File.h"
#include "support/SourceText.h"

using namespace iso;
namespace fs = std::filesystem;

namespace {

struct Run {
  int rc = -1;
  std::string out, err;
};

Run isocc(driver::CompileOptions o) {
  std::ostringstream out, err;
  driver::Io io{out, err};
  o.common.color = "never";
  Run r;
  r.rc = driver::runCompile(o, io);
  r.out = out.str();
  r.err = err.str();
  return r;
}

driver::CompileOptions compileTo(std::vector<std::string> paths, std::string output) {
  driver::CompileOptions o;
  o.paths = std::move(paths);
  o.output = std::move(output);
  return o;
}

driver::CompileOptions verifyOf(std::string image) {
  driver::CompileOptions o;
  o.verify = std::move(image);
  return o;
}

std::vector<uint8_t> bytesOf(const std::string& path) {
  auto bytes = support::readFile(path);
  REQUIRE_MESSAGE(bytes, (bytes ? std::string() : bytes.error().message));
  return std::vector<uint8_t>(bytes->begin(), bytes->end());
}

const std::string kSamples = std::string(ISO_SOURCE_DIR) + "/samples/";

/// Restores the working directory at scope exit.
struct Cwd {
  fs::path saved = fs::current_path();
  explicit Cwd(const fs::path& p) { fs::current_path(p); }
  ~Cwd() { fs::current_path(saved); }
};

} // namespace

TEST_CASE("image: isocc compiles, verifies and disassembles a sample") {
  test::TempDir dir;
  std::string out = dir.path() + "/p.isob";
  Run r = isocc(compileTo({kSamples + "pallet_loader"}, out));
  CHECK_MESSAGE(r.rc == 0, r.err);
  CHECK(r.err.empty());
  CHECK(fs::exists(out));
  CHECK_FALSE(fs::exists(out + ".isocc-tmp"));
  r = isocc(verifyOf(out));
  CHECK(r.rc == 0);
  CHECK(r.out.empty());
  CHECK(r.err.empty());
  driver::CompileOptions d;
  d.disasm = out;
  r = isocc(d);
  CHECK(r.rc == 0);
  CHECK(r.out.find("; procedure 0: main pallettizzatore, file pallettizzatore.mpf") != std::string::npos);
  CHECK(r.out.find("call        Carica_pezzo (procedure") != std::string::npos);
  // --strip
  std::string stripped = dir.path() + "/s.isob";
  driver::CompileOptions s = compileTo({kSamples + "pallet_loader"}, stripped);
  s.strip = true;
  CHECK(isocc(s).rc == 0);
  CHECK(fs::file_size(stripped) < fs::file_size(out));
  d.disasm = stripped;
  r = isocc(d);
  CHECK(r.out.find("stripped (no line table)") != std::string::npos);
  CHECK(r.out.find("pallettizzatore.mpf:") == std::string::npos);
}

TEST_CASE("image: isocc output does not depend on path order, spelling or working directory") {
  test::TempDir dir;
  std::string set = kSamples + "semi_auto";
  std::vector<std::string> files;
  for (const auto& e : fs::directory_iterator(set))
    files.push_back(e.path().string());
  std::sort(files.begin(), files.end());
  REQUIRE(isocc(compileTo({set}, dir.path() + "/a.isob")).rc == 0);
  REQUIRE(isocc(compileTo(files, dir.path() + "/b.isob")).rc == 0);
  std::reverse(files.begin(), files.end());
  REQUIRE(isocc(compileTo(files, dir.path() + "/c.isob")).rc == 0);
  {
    Cwd cwd(set);
    REQUIRE(isocc(compileTo({"."}, dir.path() + "/d.isob")).rc == 0);
    REQUIRE(isocc(compileTo({"fresatura_cornice.mpf"}, dir.path() + "/e.isob")).rc == 0);
  }
  {
    Cwd cwd(dir.path());
    REQUIRE(isocc(compileTo({fs::relative(set, dir.path()).string() + "/"}, "f.isob")).rc == 0);
  }
  auto a = bytesOf(dir.path() + "/a.isob");
  for (std::string n : {"b", "c", "d", "e", "f"}) {
    CAPTURE(n);
    CHECK(bytesOf(dir.path() + "/" + n + ".isob") == a);
  }
}

TEST_CASE("image: isocc with program errors prints isolint's diagnostics and writes nothing") {
  test::TempDir dir;
  std::string src = dir.write("bad.mpf", "G01 X10 F100\nGOTOF Nowhere\nM30\n");
  std::string out = dir.path() + "/bad.isob";
  Run r = isocc(compileTo({src}, out));
  CHECK(r.rc == 1);
  CHECK(r.err.find("bad.mpf:2:7: error:") != std::string::npos);
  CHECK(r.err.find("[E202 label-unknown]") != std::string::npos);
  CHECK(r.err.find("1 file checked: 1 error") != std::string::npos);
  CHECK(r.out.empty());
  CHECK_FALSE(fs::exists(out));
  // warnings alone: printed, the image is written
  std::string warn = dir.write("warn.mpf", "G01 X10\nM30\n");
  r = isocc(compileTo({warn}, out));
  CHECK(r.rc == 0);
  CHECK(r.err.find("[W402 feed-unset]") != std::string::npos);
  CHECK(fs::exists(out));
}

TEST_CASE("image: isocc set errors") {
  test::TempDir dir;
  dir.write("a.mpf", "M30\n");
  dir.write("b.mpf", "M30\n");
  Run r = isocc(compileTo({dir.path()}, dir.path() + "/x.isob"));
  CHECK(r.rc == 1);
  CHECK(r.err.find("isocc: error: several main programs and none named") != std::string::npos);
  // naming one picks it
  r = isocc(compileTo({dir.path() + "/b.mpf"}, dir.path() + "/x.isob"));
  CHECK_MESSAGE(r.rc == 0, r.err);
}

TEST_CASE("image: isocc usage errors exit 2") {
  test::TempDir dir;
  CHECK(isocc({}).rc == 2);
  Run r = isocc(compileTo({kSamples + "recipe_case"}, ""));
  CHECK(r.rc == 2);
  CHECK(r.err == "isocc: error: no output file (give -o OUT.isob) (run 'isocc --help')\n");
  r = isocc(compileTo({dir.path() + "/nope.mpf"}, dir.path() + "/x.isob"));
  CHECK(r.rc == 2);
  CHECK(r.err.find("nope.mpf: error: no such file or directory") != std::string::npos);
  driver::CompileOptions o = verifyOf("x.isob");
  o.paths = {"a.mpf"};
  CHECK(isocc(o).rc == 2);
  o = verifyOf("x.isob");
  o.disasm = "y.isob";
  CHECK(isocc(o).rc == 2);
  r = isocc(verifyOf(dir.path() + "/none.isob"));
  CHECK(r.rc == 2);
  CHECK(r.err == dir.path() + "/none.isob: error: no such file or directory\n");
  // an image given as a program
  REQUIRE(isocc(compileTo({kSamples + "recipe_case"}, dir.path() + "/r.isob")).rc == 0);
  r = isocc(compileTo({dir.path() + "/r.isob"}, dir.path() + "/x.isob"));
  CHECK(r.rc == 2);
  CHECK(r.err == dir.path() + "/r.isob: error: is an image, not a program (use --disasm, --verify or --dump=hex)\n");
  o = compileTo({kSamples + "recipe_case"}, dir.path() + "/no/such/dir/x.isob");
  r = isocc(o);
  CHECK(r.rc == 2);
  CHECK(r.err.find("error: cannot create the file: no such file or directory") != std::string::npos);
}

TEST_CASE("image: isocc --verify reports the offset and the reason") {
  test::TempDir dir;
  std::string img = dir.path() + "/r.isob";
  REQUIRE(isocc(compileTo({kSamples + "recipe_case"}, img)).rc == 0);
  auto b = bytesOf(img);
  b[b.size() / 2] ^= 0x10;
  std::ofstream(img, std::ios::binary).write(reinterpret_cast<const char*>(b.data()), static_cast<long>(b.size()));
  Run r = isocc(verifyOf(img));
  CHECK(r.rc == 2);
  CHECK(r.err.find(img + "+0x0014: error: CRC-32 mismatch: the header says 0x") == 0);
  // a source file is not an image
  r = isocc(verifyOf(kSamples + "recipe_case/dosatrice.mpf"));
  CHECK(r.rc == 2);
  CHECK(r.err.find("dosatrice.mpf+0x0000: error: not an isotools image (bad magic") != std::string::npos);
  // an image that reads but breaks a rule: --disasm still lists it, and exits 2
  b[b.size() / 2] ^= 0x10;
  image::Image good;
  image::ImageError err;
  REQUIRE(image::readImage(b, good, err));
  good.axes.push_back('X'); // listed twice
  auto bad = image::writeImage(good);
  std::ofstream(img, std::ios::binary).write(reinterpret_cast<const char*>(bad.data()), static_cast<long>(bad.size()));
  driver::CompileOptions d;
  d.disasm = img;
  r = isocc(d);
  CHECK(r.rc == 2);
  CHECK_MESSAGE(r.err.find("X' is listed twice") != std::string::npos, r.err);
  CHECK(r.out.find("; procedure 0: main dosatrice") != std::string::npos);
}

TEST_CASE("image: isocc --dump=hex of sources and of an image") {
  test::TempDir dir;
  driver::CompileOptions o = compileTo({kSamples + "five_axis"}, "");
  o.dump = "hex";
  Run a = isocc(o);
  CHECK_MESSAGE(a.rc == 0, a.err);
  CHECK(a.out.find("0000: 49 53 4F 42 0D 0A 1A 0A  # magic") != std::string::npos);
  std::string img = dir.path() + "/f.isob";
  REQUIRE(isocc(compileTo({kSamples + "five_axis"}, img)).rc == 0);
  driver::CompileOptions h;
  h.dump = "hex";
  h.paths = {img};
  Run b = isocc(h);
  CHECK(b.rc == 0);
  CHECK(b.out == a.out);
}

namespace {

/// A valid main program of about `lines` lines that has every structure the compiler links:
/// N numbers, labels and jumps both ways, IF/ELSE/ENDIF, IF..THEN, CASE, short and long WHEN.
std::string largeProgram(size_t lines) {
  std::string t = "; a large program\nG90 G60\nF=250\nR1 = 0\n";
  for (size_t k = 0; t.size() < lines * 28; ++k) {
    t += fmt::format("N{} G01 X{}.5 Y-{} F200\n", 10 + k, k % 900, k % 77);
    t += fmt::format("L{}: G01 Pos[X] = R1 + {} Pos[Y] = {}.25 F = 120\n", k, k % 99, k % 500);
    t += fmt::format("IF (R1 > {}) AND ($aa_in[{}] == 1)\n  G01 Posa[Z] = {} Fa[Z] = 50\nELSE\n  M{}\nENDIF\n", k % 50,
                     k % 20, k % 300, 10 + (k % 8) * 11);
    t += fmt::format("IF R1 > 1000 GOTOB L{}\n", k);
    t += fmt::format("IF R1 > 2000 GOTOF F{}\n", k);
    t += fmt::format("CASE R2 OF 1 GOTOF F{0} 2 GOTOF F{0} DEFAULT GOTOF F{0}\n", k);
    t += fmt::format("F{}: IF R3 == {} THEN R4 = R4 + 0.125\n", k, k % 7);
    t += fmt::format("WHEN $aa_iw[X] > {} DO $aa_out[{}] = 1\n", 10 + k % 190, k % 50);
    if (k % 5 == 0)
      t += fmt::format("G01 X5 F300\nWHEN $aa_iw[Y] < {} DO\n  $aa_out[3] = 0\n  $aa_marker[30] = 1\nCANCEL\n", k % 90);
    t += fmt::format("N{}G0X{}Y{}Z5 ; rapid\nG04 F0.{}\n", 100000 + k, k % 100, k % 37, 1 + k % 9);
  }
  return t + "M30\n";
}

} // namespace

TEST_CASE("image: a large program compiled a line at a time gives the full tree's image, with its mapped text and "
          "its statements given back as they are passed") {
  test::TempDir dir;
  const std::string path = dir.write("large.mpf", largeProgram(60000)); // mapped: 1 MiB or more
  REQUIRE(fs::file_size(path) > (size_t{1} << 20));
  frontend::LoadOptions lo;
  lo.machine = &test::builtin();
  lo.siblings = false;
  frontend::ProgramSet full, compact;
  frontend::SetError err;
  REQUIRE(frontend::loadProgramSet({path}, lo, full, err));
  REQUIRE_FALSE(full.diags.hasErrors());
  lo.compactTrees = true;
  lo.jobs = 2;                        // split in two parts, as isocc does
  lo.splitting.dropEvery = 64 * 1024; // and the text's pages given back behind the reader
  REQUIRE(frontend::loadProgramSet({path}, lo, compact, err));
  CHECK(compact.files.at(0).splitAt > 0);
  compiler::CompileOptions co;
  image::Image a, b;
  compiler::CompileError ea, eb;
  REQUIRE(compiler::compileProgramSet(full, co, a, ea));
  const frontend::LexOptions lex = frontend::lexOptionsFor(lo);
  co.reparse = &lex;
  co.releaseSet = true;
  co.releaseEvery = 64 * 1024; // many times over the program
  REQUIRE(compiler::compileProgramSet(compact, co, b, eb));
  CHECK(compact.files.at(0).stmts.size() * sizeof(frontend::Stmt) > (size_t{2} << 20)); // pages to give back
  CHECK(image::writeImage(a) == image::writeImage(b));
}

TEST_CASE("image: isocc on a large program (its image checked on a second thread while it is written) writes the "
          "full tree's image") {
  test::TempDir dir;
  const std::string path = dir.write("large.mpf", largeProgram(60000));
  frontend::LoadOptions lo;
  lo.machine = &test::builtin();
  lo.siblings = false;
  frontend::ProgramSet full;
  frontend::SetError err;
  REQUIRE(frontend::loadProgramSet({path}, lo, full, err));
  image::Image a;
  compiler::CompileError ea;
  REQUIRE(compiler::compileProgramSet(full, compiler::CompileOptions{}, a, ea));
  CHECK(a.code.size() > (size_t{256} << 10)); // large enough for the check beside the writer
  for (bool strip : {false, true}) {
    CAPTURE(strip);
    driver::CompileOptions o = compileTo({path}, dir.path() + "/large.isob");
    o.strip = strip;
    const Run r = isocc(o);
    CHECK(r.rc == 0);
    CHECK(r.err.empty());
    image::Image want = a;
    if (strip) {
      want.lines.clear();
      want.flags |= image::Image::kFlagStripped;
    }
    CHECK(bytesOf(o.output) == image::writeImage(want));
  }
}

TEST_CASE("image: a large program written over while it is compiled is not compiled from its second reading") {
  test::TempDir dir;
  const std::string text = largeProgram(50000);
  const std::string path = dir.write("large.mpf", text); // mapped: 1 MiB or more
  frontend::LoadOptions lo;
  lo.machine = &test::builtin();
  lo.siblings = false;
  lo.compactTrees = true;
  frontend::ProgramSet set;
  frontend::SetError err;
  REQUIRE(frontend::loadProgramSet({path}, lo, set, err));
  REQUIRE_FALSE(set.diags.hasErrors());
  REQUIRE(set.sources.file(0).text.isMapped());
  CHECK_FALSE(set.sources.file(0).text.changedOnDisk(path));
  {
    // the same size, another value on the first line: in place, as an editor's save may do
    std::string other = text;
    other.replace(other.find("G90 G60"), 7, "G91 G60");
    std::fstream out(path, std::ios::in | std::ios::out | std::ios::binary);
    out.write(other.data(), static_cast<std::streamsize>(other.size()));
  }
  fs::last_write_time(path, fs::last_write_time(path) + std::chrono::seconds(2)); // (a coarse clock)
  CHECK(set.sources.file(0).text.changedOnDisk(path));
  compiler::CompileOptions co;
  const frontend::LexOptions lex = frontend::lexOptionsFor(lo);
  co.reparse = &lex;
  image::Image img;
  compiler::CompileError cerr;
  CHECK_FALSE(compiler::compileProgramSet(set, co, img, cerr));
  CHECK(cerr.message == path + " was written while it was compiled: compile it again");
}

TEST_CASE("image: a large program replaced by another file keeps the bytes that were checked") {
  test::TempDir dir;
  const std::string path = dir.write("large.mpf", largeProgram(50000));
  auto text = support::readSource(path, 0);
  REQUIRE(text);
  REQUIRE(text->isMapped());
  const std::string before(text->view().substr(0, 64));
  dir.write("new.mpf", "M30\n");
  fs::rename(dir.path() + "/new.mpf", path);
  CHECK_FALSE(text->changedOnDisk(path)); // the mapping holds the old file, whole
  CHECK(text->view().substr(0, 64) == before);
}

TEST_CASE("load: a large mapped program whose pages leave memory behind the reader checks and compiles as one "
          "held in memory") {
  test::TempDir dir;
  std::string text = largeProgram(60000);
  text.insert(text.size() - 4, "L7: G01 X1 F100\nIF R1 > 1 GOTOF NOWHERE\n"); // a label twice, a missing one
  const std::string path = dir.write("large.mpf", text);
  frontend::LoadOptions lo;
  lo.machine = &test::builtin();
  lo.siblings = false;
  lo.compactTrees = true;
  lo.jobs = 2;
  lo.splitting.dropEvery = 64 * 1024; // many times over the program
  frontend::ProgramSet mapped, held;
  frontend::SetError err;
  REQUIRE(frontend::loadProgramSet({path}, lo, mapped, err));
  REQUIRE(mapped.sources.file(0).text.isMapped());
  CHECK(mapped.files.at(0).splitAt > 0);
  const std::string_view source = mapped.sources.file(0).text.view();
  auto inSource = [&](std::string_view name) {
    return name.data() >= source.data() && name.data() < source.data() + source.size();
  };
  REQUIRE(mapped.files.at(0).labels.size() > 1000);
  for (const auto& l : mapped.files.at(0).labels) // copies: the label checks read no page again
    REQUIRE_FALSE(inSource(l.text));
  for (const auto& j : mapped.files.at(0).jumps)
    REQUIRE_FALSE(inSource(j.label));
  const frontend::ProgramText buffer{path, text}; // the same bytes, held in memory
  lo.buffer = &buffer;
  REQUIRE(frontend::loadProgramSet({path}, lo, held, err));
  REQUIRE_FALSE(held.sources.file(0).text.isMapped());
  const auto& a = mapped.diags.items();
  const auto& b = held.diags.items();
  REQUIRE(a.size() == b.size());
  CHECK(a.size() == 2);
  for (size_t k = 0; k < a.size(); ++k) {
    CHECK(a[k].code == b[k].code);
    CHECK(a[k].loc.line == b[k].loc.line);
    CHECK(a[k].loc.col == b[k].loc.col);
    CHECK(a[k].message == b[k].message);
  }
}
