//! @file ProgramTexts.h
//! @brief Loads a program set from texts already in memory (an editor's open buffers and the
//!        files of their folder), with the same parsing and checks as loadProgramSet.
#pragma once

#include <string>
#include <vector>

#include "frontend/ProgramSet.h"

namespace iso::frontend {

/// One source of an in-memory program set.
struct ProgramText {
  std::string path;      ///< how diagnostics name the file; its extension decides the unit kind
  std::string text;      ///< raw bytes
  bool reported = true;  ///< diagnostics of this file are shown (else it only resolves calls)
};

/// Parses and checks `texts` as one program set (file ids in the given order; every reported
/// text counts as named). Nothing is read from disk. Program errors are diagnostics in
/// `set.diags`; `set` must be empty.
void loadProgramTexts(std::vector<ProgramText> texts, const LoadOptions& opts, ProgramSet& set);

/// The parsing and checking of loadProgramSet, once set.sources and set.files are filled.
void processFiles(ProgramSet& set, const LoadOptions& opts);

} // namespace iso::frontend
