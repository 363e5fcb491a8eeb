//! @file Sources.h
//! @brief Loading the program sources of a run: the one way of isolint, isocc and isosim,
//!        with their differences (threads, which siblings, standard input, filter) as options.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "diag/DiagnosticEngine.h"
#include "driver/Common.h"
#include "frontend/ProgramSet.h"
#include "machine/Machine.h"

namespace iso::driver {

struct Settings;

/// The LoadOptions of a tool: from the machine, the threads, the image magic.
frontend::LoadOptions loadOptionsFor(const machine::Machine& m, unsigned jobs,
                                     frontend::SiblingLoad siblings = frontend::SiblingLoad::All);

/// The threads of this computer (at least 1).
unsigned hardwareJobs();

/// Where the tools differ in loading their sources.
struct SourceOptions {
  unsigned jobs = 1;                                           ///< threads that read and check the files
  frontend::SiblingLoad siblings = frontend::SiblingLoad::All; ///< which siblings are read whole
  bool compactTrees = false;                                   ///< isolint: LoadOptions::compactTrees
  const frontend::ProgramText* buffer = nullptr;               ///< isolint: standard input, read as buffer->path
  /// What the user sees of the diagnostics (the filter may refer to the set it is given).
  std::function<diag::DiagnosticPolicy(const frontend::ProgramSet&)> filter;
};

/// Loads the program set of `paths` on `m` into `set` and applies `so.filter` to its
/// diagnostics. False when an input could not be read (set.inputErrors says which).
bool loadSources(const std::vector<std::string>& paths, const machine::Machine& m, const SourceOptions& so,
                 frontend::ProgramSet& set);

/// isocc and isosim: loadSources with `jobs`, the siblings an image links (SiblingLoad::Linked)
/// and the settings' filter (errors always stay).
/// Inputs that cannot be read are printed (`PATH: error: MESSAGE`) and a set without a file to
/// report is a usage error of `tool`. Returns kExitOk or kExitUsage.
/// `compact`: the set is loaded as isolint loads it (SourceOptions::compactTrees), to be compiled
/// with CompileOptions::reparse = sourceLexOptions(m).
int loadToolSources(const std::vector<std::string>& paths, const machine::Machine& m, unsigned jobs,
                    const Settings& settings, frontend::ProgramSet& set, Io& io, const char* tool,
                    bool compact = false);

/// The lexer's options of the sources loaded on `m`.
frontend::LexOptions sourceLexOptions(const machine::Machine& m);

} // namespace iso::driver
