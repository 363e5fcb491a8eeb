//! @file Format.h
//! @brief isofmt: formats (and renumbers) program files, printing, checking, diffing or
//!        rewriting them in place (man/isofmt.1).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "diag/Fix.h"
#include "driver/Common.h"
#include "support/Expected.h"

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

class LintPolicies;
struct Settings;

/// The physical lines (1-based, inclusive) that formatting may change; {0, 0}: all of them.
struct LineSpan {
  uint32_t first = 0;
  uint32_t last = 0;
  bool contains(uint32_t line) const { return first == 0 || (line >= first && line <= last); }
};

/// One buffer laid out as isofmt lays out a file (never renumbered: that changes jump targets).
struct FormattedBuffer {
  std::string text;                  ///< the new text (the buffer's own when nothing changed)
  std::vector<diag::ByteEdit> edits; ///< the edits of the buffer that make it: one per changed line, in order
  bool keptAsWritten = false;        ///< the text has syntax errors: nothing was changed
};

/// The layout of `text` under the `[format]` table of `settings` and the dialect, axes and user
/// parameters of `machine`; only the lines of `lines` change.
FormattedBuffer formatBuffer(std::string_view text, const Settings& settings, const machine::Machine& machine,
                             LineSpan lines = {});

/// The layout isofmt gives the file `path` when its text is `text`: the settings found for the
/// file (or --config), its machine file and dialect, as `policies` resolves them for isolint.
/// An error when the settings or machine file cannot be used (the reason is printed to the
/// policies' Io, as isofmt prints it).
support::Expected<FormattedBuffer> formatBuffer(std::string_view text, const std::string& path, LintPolicies& policies,
                                                LineSpan lines = {});

} // namespace iso::driver
