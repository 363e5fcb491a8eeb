//! @file main.cpp
//! @brief isolint: wires the command line to driver::runLint.
#include <iostream>

#include <unistd.h>

#include <CLI/CLI.hpp>

#include "driver/Lint.h"
#include "lsp/Server.h"

using namespace iso::driver;

int main(int argc, char** argv) {
  Io io{std::cout, std::cerr, isatty(1) != 0, isatty(2) != 0, &std::cin};
  LintOptions opts;
  CLI::App app{"isolint - check SIDAC ISO programs (.mpf/.spf) for errors before they reach a machine", "isolint"};
  app.footer("Exit status: 0 no errors, 1 errors found, 2 usage or input error, 70 internal error.\n"
             "See isolint(1) for the rules and iso(7) for the language.");
  addCommonOptions(app, opts.common, "isolint");
  app.add_option("--format", opts.format, "Output format")
      ->check(CLI::IsMember({"text", "json", "sarif", "github"}).description(""))
      ->type_name("text|json|sarif|github");
  app.add_option("--disable", opts.disable,
                 "Disable rules by code (W402) or name (feed-unset); a comma list, repeatable")
      ->type_name("CODE|NAME[,...]")
      ->allow_extra_args(false);
  app.add_option("--select", opts.select,
                 "Show only these rules, by code (W402) or name (feed-unset); a comma list, repeatable")
      ->type_name("CODE|NAME[,...]")
      ->allow_extra_args(false);
  app.add_flag("--werror", opts.werror, "Treat warnings as errors");
  app.add_flag("--statistics", opts.statistics,
               "Print the number of diagnostics of each code (most frequent first) instead of the diagnostics");
  app.add_option("--baseline", opts.baseline,
                 "Known findings: when FILE does not exist, write the diagnostics found to it; when it does, "
                 "report only the diagnostics it does not list")
      ->type_name("FILE");
  app.add_option("-j,--jobs", opts.jobs,
                 "Lint files in parallel with N threads; a file of 1 MiB or more alone uses two (default: all cores)")
      ->type_name("N")
      ->check(wholeNumberAtLeast(1))
      ->check(CLI::Range(1u, 256u).description(""));
  app.add_option("--max-diagnostics", opts.maxDiagnostics,
                 "Show at most N diagnostics per file (default: 50 in text, all in json/sarif; 0 = all)")
      ->type_name("N")
      ->check(wholeNumberAtLeast(0));
  app.add_option("--explain", opts.explain, "Print the documentation of a rule (code or name) and exit")
      ->type_name("CODE|NAME");
  bool lsp = false;
  app.add_flag("--lsp", lsp,
               "Run as a Language Server (LSP 3.17) on standard input and output, for editors; takes no PATH");
  app.add_option("--stdin-filename", opts.stdinFilename,
                 "Read the program from standard input (give - as PATH), as the file PATH (its folder gives the "
                 "program set)")
      ->type_name("PATH");
  app.add_flag("--fix", opts.fix,
               "Apply the fixes of the diagnostics shown to the files (atomically), then report what remains; with "
               "--stdin-filename, print the fixed text");
  app.add_flag("--diff", opts.diff, "Print a unified diff of what --fix would change; change nothing");
  app.add_option("paths", opts.paths, "Program files (.mpf/.spf) or directories")->type_name("PATH");
  if (int rc = parseCommandLine(app, argc, argv, io, "isolint"); rc >= 0) return rc;
  installInterruptHandler("isolint", opts.fix && opts.stdinFilename.empty()
                                         ? "each file is fixed or as it was, none half-written"
                                         : "no file was changed");
  if (lsp) {
    std::ios::sync_with_stdio(false); // buffered stdin: the server sees when input is pending
    return guarded(io, "isolint", [&] { return iso::lsp::runLspServer(opts, std::cin, io); });
  }
  return guarded(io, "isolint", [&] { return runLint(opts, io, &std::cin); });
}
