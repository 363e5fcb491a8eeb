//! @file Report.h
//! @brief `isosim --report FILE.html`: one self-contained HTML page of a run: summary,
//!        warnings, the plot (inline SVG), the profile sorted by time, spindle and tool
//!        figures when the summary has them. No script, no network: it reads in any browser,
//!        offline, and prints. The library builds the text; the driver writes it.
#pragma once

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
};

/// The most profile rows the page lists (the slowest); the rest are counted in one line.
inline constexpr size_t kReportMaxRows = 500;

/// The page: sections with the ids summary, warnings, plot, profile (and machine-state when
/// the summary has spindle_on_s, tool_changes or tool). Deterministic bytes.
std::string renderReport(const ReportInput& in);

} // namespace iso::driver
