//! @file Compile.cpp
//! @brief The isocc driver.
#include "driver/Compile.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <ostream>
#include <thread>

#include <fmt/format.h>

#include "compiler/Compiler.h"
#include "diag/Render.h"
#include "driver/Lint.h"
#include "frontend/ProgramSet.h"
#include "image/Disassembler.h"
#include "image/ImageReader.h"
#include "image/ImageVerifier.h"
#include "image/ImageWriter.h"

namespace iso::driver {

namespace fs = std::filesystem;

bool readBinaryFile(const std::string& path, std::vector<uint8_t>& out, std::string& why) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) {
    why = "is a directory";
    return false;
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    why = "cannot open file";
    return false;
  }
  in.seekg(0, std::ios::end);
  std::streamoff size = in.tellg();
  if (size < 0) {
    why = "cannot read file";
    return false;
  }
  if (static_cast<uint64_t>(size) > 0xFFFFFFFFu) {
    why = "larger than 4 GiB: not an image";
    return false;
  }
  in.seekg(0, std::ios::beg);
  out.resize(static_cast<size_t>(size));
  if (size > 0 && !in.read(reinterpret_cast<char*>(out.data()), size)) {
    why = "read error";
    return false;
  }
  return true;
}

namespace {

void printImageError(Io& io, const std::string& path, const image::ImageError& e) {
  io.err << fmt::format("{}+0x{:04X}: error: {}\n", path, e.offset, e.message);
}

/// Reads and verifies an image file. Returns kExitOk, or kExitUsage after printing the reason.
/// An image that reads but fails verification is still in `img` (`readable` true), so that
/// --disasm and --dump can show what is wrong with it.
int loadImage(const std::string& path, Io& io, image::Image& img, bool& readable) {
  std::vector<uint8_t> bytes;
  std::string why;
  readable = false;
  if (!readBinaryFile(path, bytes, why)) {
    io.err << fmt::format("{}: error: {}\n", path, why);
    return kExitUsage;
  }
  image::ImageError err;
  image::Layout layout;
  if (!image::readImage(bytes, img, err, &layout)) {
    printImageError(io, path, err);
    return kExitUsage;
  }
  readable = true;
  if (!image::verifyImage(img, err, &layout)) {
    printImageError(io, path, err);
    return kExitUsage;
  }
  return kExitOk;
}

bool looksLikeImage(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char m[8] = {};
  if (!in.read(m, 8)) return false;
  return std::equal(image::kMagic.begin(), image::kMagic.end(), reinterpret_cast<const uint8_t*>(m));
}

/// Writes `bytes` to `path` through a temporary file in the same directory, so that a failed
/// write never leaves a partial image behind.
bool writeFileAtomically(const std::string& path, const std::vector<uint8_t>& bytes, std::string& why) {
  std::string tmp = path + ".isocc-tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) {
      why = "cannot create file";
      return false;
    }
    out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    out.close();
    if (!out) {
      std::error_code ec;
      fs::remove(tmp, ec);
      why = "write error";
      return false;
    }
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) {
    fs::remove(tmp, ec);
    why = "cannot replace the file";
    return false;
  }
  return true;
}

int compileMode(const CompileOptions& opts, Io& io) {
  if (opts.paths.empty()) {
    io.err << "isocc: error: no input files (give .mpf/.spf files or directories, or --disasm/--verify IMAGE)\n";
    return kExitUsage;
  }
  if (opts.output.empty() && opts.dump.empty()) {
    io.err << "isocc: error: no output file (give -o OUT.isob)\n";
    return kExitUsage;
  }
  for (const auto& p : opts.paths)
    if (looksLikeImage(p)) {
      io.err << fmt::format("{}: error: is an image, not a program (use --disasm, --verify or --dump=hex)\n", p);
      return kExitUsage;
    }
  auto m = loadMachine(opts.common, io);
  if (!m) return kExitUsage;
  frontend::LoadOptions lo;
  lo.machine = &*m;
  lo.dialect = m->dialect;
  lo.jobs = std::max(1u, std::thread::hardware_concurrency());
  frontend::ProgramSet set;
  frontend::SetError serr;
  if (!frontend::loadProgramSet(opts.paths, lo, set, serr)) {
    io.err << fmt::format("{}: error: {}\n", serr.path, serr.message);
    return kExitUsage;
  }
  size_t files = 0;
  for (auto r : set.reported) files += r;
  if (files == 0) {
    io.err << "isocc: error: no .mpf or .spf files found in the given directories\n";
    return kExitUsage;
  }
  auto diags = visibleDiagnostics(set, {}, false);
  if (!diags.empty()) printTextDiagnostics(diags, set, io.err, useColor(opts.common, io.errIsTty), true);
  if (diag::countOf(diags).errors > 0) return kExitErrors;

  compiler::CompileOptions co;
  co.strip = opts.strip;
  co.dialect = m->dialect;
  image::Image img;
  compiler::CompileError cerr;
  if (!compiler::compileProgramSet(set, co, img, cerr)) {
    io.err << fmt::format("isocc: error: {}\n", cerr.message);
    return kExitErrors;
  }
  std::vector<uint8_t> bytes = image::writeImage(img);
  // Self-check: what isosim will load must pass the reader and the verifier.
  image::Image back;
  image::ImageError ierr;
  image::Layout layout;
  if (!image::readImage(bytes, back, ierr, &layout) || !image::verifyImage(back, ierr, &layout)) {
    io.err << fmt::format("isocc: internal error: the compiled image fails its check at +0x{:04X}: {} (please report "
                          "this bug)\n",
                          ierr.offset, ierr.message);
    return kExitInternal;
  }
  if (opts.dump == "hex") io.out << image::hexDump(img);
  if (!opts.output.empty()) {
    std::string why;
    if (!writeFileAtomically(opts.output, bytes, why)) {
      io.err << fmt::format("{}: error: {}\n", opts.output, why);
      return kExitUsage;
    }
  }
  return kExitOk;
}

} // namespace

int runCompile(const CompileOptions& opts, Io& io) {
  int modes = !opts.disasm.empty() + !opts.verify.empty();
  if (modes > 1 || (modes == 1 && (!opts.paths.empty() || !opts.output.empty() || opts.strip))) {
    io.err << "isocc: error: --disasm and --verify take one IMAGE and exclude each other, PATH..., -o and --strip\n";
    return kExitUsage;
  }
  if (!opts.dump.empty() && opts.dump != "hex") {
    io.err << fmt::format("isocc: error: unknown dump format '{}' (only hex)\n", opts.dump);
    return kExitUsage;
  }
  image::Image img;
  bool readable = false;
  if (!opts.verify.empty()) {
    if (!opts.dump.empty()) {
      io.err << "isocc: error: --dump cannot be combined with --verify\n";
      return kExitUsage;
    }
    return loadImage(opts.verify, io, img, readable);
  }
  if (!opts.disasm.empty()) {
    if (!opts.dump.empty()) {
      io.err << "isocc: error: --dump cannot be combined with --disasm (use --dump=hex IMAGE)\n";
      return kExitUsage;
    }
    int rc = loadImage(opts.disasm, io, img, readable);
    if (readable) io.out << image::disassemble(img);
    return rc;
  }
  // --dump=hex IMAGE: one path that is an image
  if (opts.dump == "hex" && opts.paths.size() == 1 && opts.output.empty() && looksLikeImage(opts.paths[0])) {
    int rc = loadImage(opts.paths[0], io, img, readable);
    if (readable) io.out << image::hexDump(img);
    return rc;
  }
  return compileMode(opts, io);
}

} // namespace iso::driver
