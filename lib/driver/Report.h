//! @file Report.h
//! @brief `isosim --report FILE.html`: one self-contained HTML page of a run: summary,
//!        warnings, the plot (inline SVG), the profile sorted by time, spindle and tool
//!        figures when the summary has them. Its one inline script links the views: a click on
//!        a path segment or a profile row marks that line everywhere and shows its source; a
//!        click on a column heading sorts the profile. No external file, no network: it reads
//!        in any browser, offline, and prints. The library builds the text; the driver writes it.
#pragma once

#include <map>
#include <string>

#include "sim/TimeProfile.h"
#include "sim/Trace.h"

namespace iso::driver {

struct ReportInput {
  std::string title;   ///< "prog.mpf - cycle time 2.25 s"
  std::string program; ///< the program as given
  const sim::Summary* summary = nullptr;
  /// The summary as JSON text, read for the keys other work adds to it (z32: spindle_on_s,
  /// tool_changes, tool); "" = sim::summaryValue of `summary`.
  std::string summaryJson;
  const sim::TimeProfile* profile = nullptr; ///< null: no profile section rows
  std::string plotSvg;                       ///< the plot (sim/SvgPlot.h), inlined as is
  /// The program's source texts by file name as the run names them (profile rows, path
  /// segments): the page embeds the lines it links to, two either side. A file not here shows
  /// "source not available".
  std::map<std::string, std::string> sources{};
};

/// The most profile rows the page lists (the slowest); the rest are counted in one line.
inline constexpr size_t kReportMaxRows = 500;

/// The page: sections with the ids summary, warnings, plot, profile (and machine-state when
/// the summary has spindle_on_s, tool_changes or tool), the source box (id source-view) and
/// the script. Profile rows and path segments carry data-file and data-line; the page opened
/// with "#line=FILE:N" shows that line, with "#sort=K" (K from 0, "-K" descending) sorts the
/// profile by column K. Deterministic bytes.
std::string renderReport(const ReportInput& in);

} // namespace iso::driver
