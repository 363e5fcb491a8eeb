//! @file main.cpp
//! @brief isocc: wires the command line to driver::runCompile.
#include <iostream>

#include <unistd.h>

#include <CLI/CLI.hpp>

#include "driver/Compile.h"

using namespace iso::driver;

int main(int argc, char** argv) {
  Io io{std::cout, std::cerr, isatty(1) != 0, isatty(2) != 0, &std::cin};
  CompileOptions opts;
  CLI::App app{"isocc - compile a SIDAC ISO program set (.mpf/.spf) into a checked binary image for isosim\n"
               "  isocc PATH... -o OUT.isob [--strip]\n"
               "  isocc --disasm IMAGE\n"
               "  isocc --verify IMAGE\n"
               "  isocc --dump=hex IMAGE | PATH...",
               "isocc"};
  app.footer("Exit status: 0 success, 1 program errors, 2 usage error, unreadable file or invalid image,\n"
             "70 internal error. See isocc(1), and isoimage(5) for the image format.");
  addCommonOptions(app, opts.common, "isocc");
  addMaxDiagnosticsOption(app, opts.common);
  app.add_option("-o,--output", opts.output, "Write the image to OUT.isob (- is standard output)")
      ->type_name("OUT.isob");
  app.add_flag("--strip", opts.strip, "Leave out the line table (smaller image; no source lines in traces)");
  app.add_option("--disasm", opts.disasm, "Verify IMAGE and print a readable listing of it")->type_name("IMAGE");
  app.add_option("--verify", opts.verify, "Check IMAGE: exit 0 if valid, else 2 with the offset and the reason")
      ->type_name("IMAGE");
  app.add_option("--dump", opts.dump,
                 "Print every byte of the image with its meaning (of IMAGE, or of the compiled PATH...)")
      ->type_name("hex");
  app.add_option("paths", opts.paths, "Program files (.mpf/.spf) or directories")->type_name("PATH");
  if (int rc = parseCommandLine(app, argc, argv, io, "isocc"); rc >= 0) return rc;
  installInterruptHandler("isocc");
  return guarded(io, "isocc", [&] { return runCompile(opts, io); });
}
