//! @file main.cpp
//! @brief isofmt: wires the command line to driver::runFormat.
#include <iostream>

#include <unistd.h>

#include <CLI/CLI.hpp>

#include "driver/Format.h"

using namespace iso::driver;

int main(int argc, char** argv) {
  Io io{std::cout, std::cerr, isatty(1) != 0, isatty(2) != 0, &std::cin};
  FormatOptions opts;
  CLI::App app{"isofmt - lay out SIDAC ISO programs (.mpf/.spf) in one style and renumber their N lines, "
               "without changing what the machine runs\n"
               "  isofmt [--check] [--diff] [-i] [--renumber START[,STEP]] [--renumber-all] PATH...",
               "isofmt"};
  app.footer("Exit status: 0 success, 1 --check found files to change or a file cannot be renumbered,\n"
             "2 usage or input error, 70 internal error. See isofmt(1) for the style.");
  addCommonOptions(app, opts.common, "isofmt");
  app.add_option("--settings", opts.common.config, "The same as --config")->type_name("FILE");
  app.add_flag("--check", opts.check, "Print the files that would change (exit 1 if any); change nothing");
  app.add_flag("--diff", opts.diff, "Print a unified diff of the changes; change nothing");
  app.add_flag("-i,--in-place", opts.inPlace, "Rewrite each file that changes, atomically (- is printed)");
  app.add_option("--renumber", opts.renumber,
                 "Renumber the N lines START, START+STEP, ... (STEP default 10), and the GO targets naming them")
      ->type_name("START[,STEP]");
  app.add_flag("--renumber-all", opts.renumberAll,
               "Give every statement line an N number when renumbering (default numbering 10,10)");
  app.add_option("paths", opts.paths, "Program files (.mpf/.spf), directories, or - for standard input")
      ->type_name("PATH");
  if (int rc = parseCommandLine(app, argc, argv, io, "isofmt"); rc >= 0) return rc;
  installInterruptHandler("isofmt", "each file is formatted or as it was, none half-written");
  return guarded(io, "isofmt", [&] { return runFormat(opts, io); });
}
