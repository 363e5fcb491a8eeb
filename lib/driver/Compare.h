//! @file Compare.h
//! @brief `isosim NEW --compare OLD`: what a change did to the cycle time. Both programs run on
//!        the same machine with --profile; their cycle times, the difference, and the lines
//!        whose time changed most (matched by N number, else by text) are printed as text or
//!        JSON. The comparison itself is data: compareProfiles() and the renderers print
//!        nothing.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "driver/Common.h"
#include "image/Image.h"
#include "sim/TimeProfile.h"
#include "sim/Trace.h"

namespace iso::driver {

struct SimulateOptions;
struct Settings;

/// One run of a comparison.
struct CompareSide {
  std::string program; ///< as given on the command line
  sim::Summary summary;
  sim::TimeProfile profile;
  /// Per profile line (same order): the N number's text ("N30") or "", and the source text of
  /// the line ("" when the source cannot be read, e.g. an image without its sources).
  std::vector<std::string> n, text;
};

/// One line of either program, matched across the two.
struct LineChange {
  std::string key;  ///< the matching key: "N30", or the text of the line, or "file:line"
  std::string text; ///< the line's text (the new program's when both have it)
  struct Side {
    std::string file;
    uint32_t line = 0;
    uint64_t count = 0;
    double timeS = 0;
  };
  std::optional<Side> oldLine, newLine; ///< nullopt: the line is not in that program
  double changeS = 0;                   ///< new time - old time (a missing side counts 0)
};

/// --budget: how much longer than the old cycle time the new one may be: a share of the old
/// time ("2%") or seconds ("1.5s").
struct CycleBudget {
  std::string given; ///< as written
  double value = 0;
  bool percent = false;
  double allowedS(double oldCycleS) const { return percent ? oldCycleS * value / 100 : value; }
};
/// "2%", "0.5 %", "1.5s", "1.5 s" (a number >= 0 and finite); nullopt for anything else.
std::optional<CycleBudget> parseBudget(const std::string& text);

struct Comparison {
  const CompareSide* oldSide = nullptr;
  const CompareSide* newSide = nullptr;
  double differenceS = 0;            ///< new cycle time - old cycle time
  std::vector<LineChange> lines;     ///< the lines whose time changed most, largest |change| first
  size_t matched = 0;                ///< lines found in both programs
  size_t onlyOld = 0, onlyNew = 0;   ///< lines found in one program only
  size_t changed = 0;                ///< lines whose time changed (all of them, not only those listed)
  std::optional<CycleBudget> budget; ///< --budget, when given
  double allowedS = 0;               ///< with a budget: the growth it allows, in seconds
  bool overBudget = false;           ///< with a budget: the difference (µs-rounded) exceeds allowedS
};

/// Sets the budget of `c` and whether its difference exceeds it.
void applyBudget(Comparison& c, const CycleBudget& budget);

/// Matches the lines of two profiled runs. A line's key is its N number, else its text
/// (blanks collapsed), else file:line; lines of subprograms are matched within the file of the
/// same name, the main programs' lines with each other whatever their file names; a key seen
/// again in one program gets "#2", "#3"... Keeps the `maxLines` largest changes (ties: key).
Comparison compareProfiles(const CompareSide& oldSide, const CompareSide& newSide, size_t maxLines = 10);

/// "old  old.mpf  cycle time 12.5 s\nnew ...\ndifference -1.25 s (-10%)\n\nlines whose time changed most..."
std::string renderComparisonText(const Comparison& c);
/// {"format_version": 1, "old": {"program", "summary"}, "new": {...}, "difference_s", ...}
std::string renderComparisonJson(const Comparison& c);

/// GitHub Actions workflow commands: `::error` (over the budget) or `::notice` with the two
/// cycle times, then `::warning file=F,line=L` on each listed line whose time grew. `dir` is
/// the folder of the new program (line files are relative to it).
std::string renderComparisonGithub(const Comparison& c, const std::string& dir);

/// Fills `n` and `text` of a side from its image's line table and the sources next to
/// `program` (file names as stored in the image are relative to the main program's folder).
void describeLines(CompareSide& side, const image::Image& img);

/// The tool body of --compare: runs opts.program (NEW) and opts.compare (OLD) on `m` and prints
/// the comparison on stdout (or to -o FILE); exit 0 when both runs end ok, else the exit code of
/// the first that does not (new, then old).
int runCompare(const SimulateOptions& opts, const machine::Machine& m, const Settings& settings, Io& io);

} // namespace iso::driver
