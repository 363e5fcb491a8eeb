//! @file Format.h
//! @brief isofmt: formats (and renumbers) program files, printing, checking, diffing or
//!        rewriting them in place (man/isofmt.1).
#pragma once

#include <string>
#include <vector>

#include "driver/Common.h"

namespace iso::driver {

struct FormatOptions {
  CommonOptions common;
  std::vector<std::string> paths; ///< files, folders (their .mpf/.spf), "-" for standard input
  bool check = false;             ///< --check: name the files that would change, exit 1 if any
  bool diff = false;              ///< --diff: print a unified diff of the changes
  bool inPlace = false;           ///< -i: rewrite each changed file atomically
  std::string renumber;           ///< --renumber START[,STEP] ("" = the settings', else none)
  bool renumberAll = false;       ///< --renumber-all: number every statement line
};

/// Runs isofmt; returns 0, 1 (--check found changes, or a file could not be renumbered: then
/// nothing is written), or 2 (usage, an unreadable input, an invalid settings or machine file).
int runFormat(const FormatOptions& opts, Io& io);

} // namespace iso::driver
