//! @file SingleBlock.h
//! @brief isosim --single-block: the controller's single-block mode on a terminal. Before each
//!        block (a line of the main program, a subprogram or a WHEN body) the run prints the
//!        time, the line, its source text and the axes, and waits for a command.
#pragma once

#include "driver/Simulate.h"

namespace iso::driver {

/// The isosim --single-block tool body. Prepares the run as isosim does (prepareRun), then runs
/// it with a debug hook that, before the first statement of each line a thread reaches, prints
///     t=0.460 s  foratura.spf:17  G01 Pos[Z] = R42 F=R43  X=120 Y=80 Z=-190
/// (the simulated time, the file and line as the image records them, the line as written,
/// trimmed and escaped for the terminal — left out when the source cannot be read, as for an
/// image without its sources beside it —, the machine position of each axis the program uses;
/// a WHEN body's lines say `[WHEN file:line]` after the line) on io.out, and reads a command
/// line from io.in: empty (Enter) runs the next block, `c` runs to the end without stopping
/// (and prints no more blocks), `q` ends the run; the end of the input is `c`. Any other line
/// prints the commands and asks again. On a terminal (`inIsTty`: standard input is one) the
/// block line ends with the prompt `  > ` and the echo of the command; otherwise (commands from
/// a pipe or a file) with a newline.
/// Then the summary, as --summary prints it (JSON with --format json) on io.out; a runtime
/// error or emergency also as `isosim: MESSAGE` on io.err.
/// Exit codes: those of --summary (0 ok, 1 runtime error or program with errors, 2 usage, 3
/// emergency), and 0 when `q` ended the run (the summary then has status error and says the
/// run was ended). Usage errors: with -o, --plot, --timeline, --report, --profile, --compare,
/// --print-machine, and with the program on standard input (the commands come from there).
int runSingleBlock(const SimulateOptions& opts, Io& io, bool inIsTty = false);

} // namespace iso::driver
