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
#include "driver/ImageFile.h"
#include "driver/Lint.h"
#include "driver/Settings.h"
#include "driver/Sources.h"
#include "frontend/ProgramSet.h"
#include "image/Disassembler.h"
#include "image/ImageReader.h"
#include "image/ImageVerifier.h"
#include "image/ImageWriter.h"
#include "support/File.h"
#include "support/Memory.h"
#include "support/Text.h"

namespace iso::driver {

namespace fs = std::filesystem;

std::vector<std::string> inputPaths(const frontend::ProgramSet& set, const CommonOptions& common) {
  std::vector<std::string> in;
  for (size_t i = 0; i < set.sources.size(); ++i)
    in.push_back(set.sources.path(static_cast<uint32_t>(i)));
  in.insert(in.end(), set.unread.begin(), set.unread.end()); // siblings are inputs, read or not
  if (!common.machinePath.empty()) in.push_back(common.machinePath);
  if (!common.settingsFile.empty()) in.push_back(common.settingsFile);
  return in;
}

namespace {

/// The code size from which isocc verifies an image on a second thread while it writes it.
constexpr size_t kOverlapCheckBytes = 256 * 1024;

/// Loads an image file for --verify, --disasm and --dump=hex: kExitOk, or kExitUsage after
/// printing why. `listing`, when given, is called with the image whenever it reads, verified
/// or not, so that a listing can show what is wrong with it.
template <class Listing> int loadImage(const std::string& path, Io& io, Listing&& listing) {
  LoadedImage loaded = loadImageFile(path);
  if (!loaded.verified) io.err << loaded.error << "\n";
  if (loaded.image()) listing(*loaded.image());
  return loaded.verified ? kExitOk : kExitUsage;
}

int compileMode(const CompileOptions& optsIn, Io& io) {
  CompileOptions opts = optsIn;
  if (!readStandardInput(opts.paths, io, "isocc")) return kExitUsage;
  if (opts.paths.empty())
    return usageError(io, "isocc", "no input files (give .mpf/.spf files or directories, or --disasm/--verify IMAGE)");
  if (opts.output.empty() && opts.dump.empty()) return usageError(io, "isocc", "no output file (give -o OUT.isob)");
  for (const auto& p : opts.paths)
    if (isImageFile(p)) {
      io.err << fmt::format("{}: error: is an image, not a program (use --disasm, --verify or --dump=hex)\n",
                            support::escapeForTerminal(p));
      return kExitUsage;
    }
  CommonOptions common = opts.common;
  Settings settings;
  if (!applySettings(common, opts.paths.front(), settings, io)) return kExitUsage;
  auto m = loadMachine(common, io);
  if (!m) return kExitUsage;
  frontend::ProgramSet set;
  if (int rc = loadToolSources(opts.paths, *m, hardwareJobs(), settings, set, io, "isocc", /*compact=*/true);
      rc != kExitOk)
    return rc;
  if (opts.output == "-" && !opts.dump.empty())
    return usageError(io, "isocc", "-o - and --dump both write to standard output; give -o a file");
  if (opts.output == "-" && io.outIsTty)
    return usageError(io, "isocc", "-o - would write a binary image to the terminal; redirect standard output");
  if (int rc = checkOutputs(io, "isocc", {{"-o", opts.output}}, inputPaths(set, common)); rc != kExitOk) return rc;
  printToolDiagnostics(set, opts.common, settings, io);
  if (diag::countOf(set.diags.items()).errors > 0) return kExitErrors;

  compiler::CompileOptions co;
  co.strip = opts.strip;
  co.dialect = m->dialect;
  co.specialM = &m->specialM;
  co.parameters = &m->parameters;
  const frontend::LexOptions lex = sourceLexOptions(*m);
  co.reparse = &lex;    // a line at a time: no unit's tree is held whole
  co.releaseSet = true; // and what is compiled leaves memory: the set is not read again
  image::Image img;
  compiler::CompileError cerr;
  if (!compiler::compileProgramSet(set, co, img, cerr)) {
    io.err << fmt::format("isocc: error: {}\n", cerr.message);
    return kExitErrors;
  }
  // the program set is not read again: its trees go before the image is written and checked
  set = frontend::ProgramSet{};
  support::returnFreedMemory();
  // Self-check: what isosim will load must pass the reader and the verifier. A large image is
  // verified on a second thread while it is written; read back, it must then be the same image
  // (and the verifier is run on what was read only when it is not).
  const bool overlap = hardwareJobs() > 1 && img.code.size() >= kOverlapCheckBytes;
  bool verified = false;
  uint64_t lines = 0;
  std::jthread verifier;
  if (overlap)
    verifier = std::jthread([&] {
      image::ImageError unused;
      const image::Layout offsets; // (only a failure's message needs the file's offsets)
      verified = image::verifyImage(img, unused, &offsets);
      lines = image::lineTableHash(img.lines);
    });
  std::vector<uint8_t> bytes = image::writeImage(img);
  if (overlap) verifier.join();
  // the line table is in `bytes` now, and the check reads it back: one copy at a time
  if (opts.dump.empty()) std::vector<image::LineEntry>().swap(img.lines);
  image::Image back;
  image::ImageError ierr;
  image::Layout layout;
  if (!image::readImage(bytes, back, ierr, &layout) ||
      (!(verified && image::sameImage(back, img, lines)) && !image::verifyImage(back, ierr, &layout))) {
    io.err << fmt::format("isocc: internal error: the compiled image fails its check at +0x{:04X}: {} (please report "
                          "this bug)\n",
                          ierr.offset, ierr.message);
    return kExitInternal;
  }
  if (back.code != img.code) { // format 2 codes the code: it must decode to the very same bytes
    io.err << "isocc: internal error: the compiled image's code section does not decode to its code (please report "
              "this bug)\n";
    return kExitInternal;
  }
  if (opts.dump == "hex") io.out << image::hexDump(img);
  if (opts.output == "-") {
    io.out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    io.out.flush(); // a failed write is reported (exit 2) when the run ends
  } else if (!opts.output.empty()) {
    const std::string_view text(reinterpret_cast<const char*>(bytes.data()), bytes.size());
    if (support::Status w = support::writeFileAtomically(opts.output, text); !w) {
      io.err << fmt::format("{}: error: {}\n", support::escapeForTerminal(opts.output), w.why());
      return kExitUsage;
    }
  }
  return kExitOk;
}

} // namespace

int runCompile(const CompileOptions& optsIn, Io& io) {
  CompileOptions opts = optsIn;
  for (std::string* image : {&opts.verify, &opts.disasm}) { // - is standard input
    std::vector<std::string> one{*image};
    if (*image == "-" && !readStandardInput(one, io, "isocc")) return kExitUsage;
    *image = one.front();
  }
  int modes = !opts.disasm.empty() + !opts.verify.empty();
  if (modes > 1 || (modes == 1 && (!opts.paths.empty() || !opts.output.empty() || opts.strip)))
    return usageError(io, "isocc",
                      "--disasm and --verify take one IMAGE and exclude each other, PATH..., -o and --strip");
  if (!opts.dump.empty() && opts.dump != "hex")
    return usageError(io, "isocc", fmt::format("unknown dump format '{}' (only hex)", opts.dump));
  if (!opts.verify.empty()) {
    if (!opts.dump.empty()) return usageError(io, "isocc", "--dump cannot be combined with --verify");
    return loadImage(opts.verify, io, [](const image::Image&) {});
  }
  if (!opts.disasm.empty()) {
    if (!opts.dump.empty())
      return usageError(io, "isocc", "--dump cannot be combined with --disasm (use --dump=hex IMAGE)");
    return loadImage(opts.disasm, io, [&](const image::Image& img) { io.out << image::disassemble(img); });
  }
  // --dump=hex IMAGE: one path that is an image
  if (opts.dump == "hex" && opts.paths.size() == 1 && opts.output.empty() && isImageFile(opts.paths[0]))
    return loadImage(opts.paths[0], io, [&](const image::Image& img) { io.out << image::hexDump(img); });
  return compileMode(opts, io);
}

} // namespace iso::driver
