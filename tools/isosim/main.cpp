//! @file main.cpp
//! @brief isosim: wires the command line to driver::runSimulate.
#include <iostream>

#include <unistd.h>

#include <CLI/CLI.hpp>

#include "dap/DebugAdapter.h"
#include "driver/Calibrate.h"
#include "driver/SingleBlock.h"
#include "driver/Sweep.h"

using namespace iso::driver;

int main(int argc, char** argv) {
  std::ios::sync_with_stdio(false);
  Io io{std::cout, std::cerr, isatty(1) != 0, isatty(2) != 0, &std::cin};
  SimulateOptions opts;
  CLI::App app{"isosim - dry-run a SIDAC ISO program on a modelled machine: cycle time, timed trace, events\n"
               "  isosim PROGRAM [PATH...] [-o FILE] [--format csv|json] [--dt S] [--summary] ...\n"
               "PROGRAM is an image from isocc or a .mpf source (compiled in memory with its program set).\n"
               "Without -o the trace goes to stdout and the summary to stderr (on a terminal: the summary\n"
               "and a hint instead of the trace); with -o FILE the trace goes to FILE and the summary (with\n"
               "the cycle time) to stdout; --summary prints only the summary. Files are replaced whole.",
               "isosim"};
  app.footer("Exit status: 0 ok, 1 runtime error or program with errors, 2 usage error, unreadable file,\n"
             "invalid machine file or image, axis missing on the machine, 3 emergency, 70 internal error.\n"
             "See isosim(1) for the timing model and the trace formats.");
  addCommonOptions(app, opts.common, "isosim");
  addMaxDiagnosticsOption(app, opts.common);
  app.add_option("program", opts.program, "Image from isocc, or a .mpf main/semi-automatic program")
      ->type_name("PROGRAM");
  app.add_option("paths", opts.paths, "More files or directories of the program set (sources only)")
      ->type_name("PATH...");
  app.add_option("--entry", opts.entry, "Run the semi-automatic program with this SEMI name (or file stem)")
      ->type_name("NAME");
  app.add_option("--format", opts.format,
                 "Trace (and summary) format (default: json if FILE ends in .json, else csv); with --compare: text "
                 "(default), json or github")
      ->type_name("csv|json|github");
  app.add_option("-o,--output", opts.output,
                 "Write the trace to FILE (the summary then goes to stdout); - is standard output")
      ->type_name("FILE");
  app.add_option("--plot", opts.plot,
                 "Also write an SVG plot of the run (position, velocity against time; the tool path) to FILE")
      ->type_name("FILE");
  app.add_option("--plot-plane", opts.plotPlane,
                 "Plane of the plot's tool path view (default: a panel per plane the moves use)")
      ->check(CLI::IsMember({"xy", "zx", "yz"}, CLI::ignore_case).description(""))
      ->type_name("xy|zx|yz");
  app.add_option("--timeline", opts.timeline,
                 "Also write the run as Chrome/Perfetto trace-event JSON (lines, WHEN bodies, PLC, axes, I/O) to FILE")
      ->type_name("FILE");
  app.add_option("--report", opts.report,
                 "Also write a self-contained HTML page of the run (summary, warnings, plot, profile) to FILE")
      ->type_name("FILE");
  app.add_option("--compare", opts.compare,
                 "Run OLD too and print both cycle times, the difference and the lines that changed most")
      ->type_name("OLD");
  app.add_option("--set", opts.sets,
                 "Change a machine-file key for this run only, by its path: axes.X.max_accel=3000, "
                 "m_sequences.23.duration_s=1.2, block_time_s=0.004 (repeatable)")
      ->type_name("KEY=VALUE")
      ->allow_extra_args(false);
  app.add_option("--m0-wait", opts.m0Wait, "Seconds an M0 stop waits for the operator in this run (m0_wait_s)")
      ->type_name("S");
  app.add_option("--feed-override", opts.feedOverride,
                 "Run feed moves at P percent of the programmed feed, 1 to 1000 (the axes' max_velocity still caps "
                 "them; rapids, dwells and M times unchanged)")
      ->type_name("P");
  app.add_option("--rapid-override", opts.rapidOverride,
                 "Run rapids (G00) at P percent of each axis's max_velocity, 1 to 100 (accelerations unchanged)")
      ->type_name("P");
  app.add_option("--optional-stop", opts.optionalStop,
                 "z32: whether M1 stops like M0 (on) or is ignored (off) in this run (optional_stop)")
      ->type_name("on|off");
  app.add_option("--budget", opts.budget,
                 "With --compare: exit 1 when the new cycle time exceeds the old one by more than this share (2%) or "
                 "time (1.5s)")
      ->type_name("P%|Ss");
  app.add_option("--dt", opts.dt, "Sample period of the trace in seconds (default 0.01, at least 0.000001)")
      ->type_name("S")
      ->check(positiveSeconds());
  app.add_flag("--summary", opts.summary, "Print only the summary (status, cycle time, final position, ...)");
  app.add_flag("--quiet", opts.quiet,
               "No progress line and no hint on a terminal (errors, warnings and the summary still print)");
  app.add_flag("--profile", opts.profile,
               "Print where the time goes: per line, program and M number, split into motion phases and waits");
  app.add_option("--profile-lines", opts.profileLines,
                 "With --profile: show the N slowest lines in the text table (default 50; 0 = all)")
      ->type_name("N")
      ->check(wholeNumberAtLeast(0));
  app.add_flag("--block-skip", opts.blockSkip, "Skip the lines marked with / (block skip on)");
  std::string searchText;
  CLI::Option* searchOpt =
      app.add_option("--search", searchText,
                     "Block search: start the cycle at the label TEXT of the entry program (z32: or at the line a GO "
                     "target such as N20 finds); the lines before it run in zero time")
          ->type_name("TEXT");
  app.add_option("--max-steps", opts.maxSteps, "Stop with an error after N statements (default 100000000)")
      ->type_name("N")
      ->check(wholeNumberAtLeast(1));
  app.add_option("--max-time", opts.maxTime, "Stop with an error at S simulated seconds (default 86400)")
      ->type_name("S")
      ->check(positiveSeconds());
  app.add_option("--max-rows", opts.maxRows,
                 "Stop with an error when the trace would get more than N rows (default 20000000)")
      ->type_name("N")
      ->check(wholeNumberAtLeast(1));
  bool dap = false;
  app.add_flag("--dap", dap,
               "Serve the Debug Adapter Protocol on standard input/output (an editor's debugger: breakpoints, "
               "single block, variables); the program comes with the launch request");
  SweepOptions sweep;
  CLI::Option* sweepOpt =
      app.add_option("--sweep", sweep.file,
                     "Run a grid of programs x machine variants from a sweep file (.toml) and write one table (csv "
                     "or json: -o FILE or standard output; the best and worst runs on a terminal)")
          ->type_name("FILE");
  CalibrateOptions calibrate;
  CLI::Option* calibrateOpt =
      app.add_option("--calibrate", calibrate.file,
                     "Fit machine keys (--fit) to the cycle times measured on the real machine: FILE is a CSV of "
                     "program,cycle_time_s (.csv); prints the fitted values and each program's residual")
          ->type_name("FILE");
  CLI::Option* fitOpt = app.add_option("--fit", calibrate.fit,
                                       "With --calibrate: a machine key to fit (axes.X.max_accel, axes.Y.max_velocity, "
                                       "block_time_s, m_sequences.23.duration_s; repeatable or a comma list); -o FILE "
                                       "writes the fitted machine")
                            ->type_name("KEY")
                            ->delimiter(',')
                            ->allow_extra_args(false);
  CLI::Option* jobsOpt = app.add_option("-j,--jobs", sweep.jobs,
                                        "With --sweep or --calibrate: run N simulations at once (default: all cores)")
                             ->type_name("N")
                             ->check(wholeNumberAtLeast(1))
                             ->check(CLI::Range(1u, 256u).description(""));
  CLI::Option* sweepJobsOpt = app.add_flag(
      "--sweep-jobs", sweep.printJobs,
      "With --sweep: print one isosim command per run instead of running them (for GNU parallel, a CI matrix, ...)");
  bool singleBlock = false;
  app.add_flag("--single-block", singleBlock,
               "Single block: print each block before it runs (time, line, text, axes) and wait for a command on "
               "standard input: Enter runs it, c continues to the end, q stops the run; then the summary");
  app.add_flag("--print-machine", opts.printMachine,
               "Print the machine (the built-in one, or --machine FILE) as JSON and exit");
  if (int rc = parseCommandLine(app, argc, argv, io, "isosim"); rc >= 0) return rc;
  if (searchOpt->count() > 0) opts.search = searchText;
  if (singleBlock && (dap || sweepOpt->count() > 0))
    return usageError(io, "isosim",
                      std::string("--single-block cannot be combined with ") + (dap ? "--dap" : "--sweep"));
  if (dap) // while the program runs the session polls standard input's descriptor (and cin's buffer)
    return guarded(io, "isosim",
                   [&] { return iso::dap::runDebugAdapter(std::cin, std::cout, {.pollFd = 0, .baseDir = {}}); });
  if (calibrateOpt->count() > 0 || fitOpt->count() > 0) {
    if (calibrateOpt->count() == 0) return usageError(io, "isosim", "--fit applies to --calibrate FILE");
    if (singleBlock || sweepOpt->count() > 0 || sweepJobsOpt->count() > 0)
      return usageError(io, "isosim", "--calibrate cannot be combined with --single-block or --sweep");
    installInterruptHandler("isosim");
    calibrate.run = opts;
    calibrate.jobs = sweep.jobs;
    return guarded(io, "isosim", [&] { return runCalibrate(calibrate, io); });
  }
  if (sweepOpt->count() == 0 && (jobsOpt->count() > 0 || sweepJobsOpt->count() > 0))
    return usageError(io, "isosim",
                      std::string(jobsOpt->count() > 0 ? "-j" : "--sweep-jobs") + " applies to --sweep FILE");
  installInterruptHandler("isosim");
  if (sweepOpt->count() > 0) {
    sweep.run = opts;
    return guarded(io, "isosim", [&] { return runSweep(sweep, io); });
  }
  if (singleBlock) return guarded(io, "isosim", [&] { return runSingleBlock(opts, io, isatty(0) != 0); });
  return guarded(io, "isosim", [&] { return runSimulate(opts, io); });
}
