//! @file Baseline.h
//! @brief isolint --baseline FILE: the diagnostics a legacy code base already has, written once
//!        and then left out of later runs, so that CI reports only new findings. A finding is
//!        its file, code and fingerprint (the rule, the file and the line's text with blanks
//!        folded, and its occurrence on identical lines): it stays known when other lines of
//!        the file change, and a new one on an edited line is reported.
#pragma once

#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "diag/Diagnostic.h"
#include "diag/SourceManager.h"
#include "support/Expected.h"

namespace iso::driver {

struct Baseline {
  /// (file as named on the command line, code, fingerprint)
  std::set<std::tuple<std::string, std::string, std::string>> known;
};

/// Reads a baseline file written by writeBaseline. An Error (where: "FILE" or
/// "FILE:byte N") when it cannot be read or is not a baseline.
support::Expected<Baseline> readBaseline(const std::string& path);

/// The baseline text of `diags` (JSON: version, then one entry a finding with its file, line,
/// code, message and fingerprint; the line and message are for the reader).
std::string baselineText(const std::vector<diag::Diagnostic>& diags, const diag::SourceManager& sm);

/// Drops from `diags` the findings `baseline` knows; returns how many were dropped.
size_t applyBaseline(std::vector<diag::Diagnostic>& diags, const diag::SourceManager& sm, const Baseline& baseline);

} // namespace iso::driver
