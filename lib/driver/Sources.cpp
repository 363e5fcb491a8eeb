//! @file Sources.cpp
//! @brief Loading the program sources of isolint, isocc and isosim.
#include "driver/Sources.h"

#include <thread>

#include "compiler/Compiler.h"
#include "driver/Lint.h"
#include "image/ImageWriter.h"

namespace iso::driver {

frontend::LoadOptions loadOptionsFor(const machine::Machine& m, unsigned jobs, frontend::SiblingLoad siblings) {
  frontend::LoadOptions lo;
  lo.siblingLoad = siblings;
  lo.machine = &m;
  lo.dialect = m.dialect;
  lo.jobs = jobs;
  lo.imageMagic = std::string_view(reinterpret_cast<const char*>(image::kMagic.data()), image::kMagic.size());
  return lo;
}

unsigned hardwareJobs() { return std::max(1u, std::thread::hardware_concurrency()); }

bool loadSources(const std::vector<std::string>& paths, const machine::Machine& m, const SourceOptions& so,
                 frontend::ProgramSet& set) {
  frontend::LoadOptions lo = loadOptionsFor(m, so.jobs, so.siblings);
  lo.buffer = so.buffer;
  lo.compactTrees = so.compactTrees;
  frontend::SetError err;
  const bool read = frontend::loadProgramSet(paths, lo, set, err);
  if (so.filter) filterDiagnostics(set, so.filter(set));
  return read;
}

int loadToolSources(const std::vector<std::string>& paths, const machine::Machine& m, unsigned jobs,
                    const Settings& settings, frontend::ProgramSet& set, Io& io, const char* tool, bool compact) {
  SourceOptions so;
  so.jobs = jobs;
  so.compactTrees = compact;
  so.siblings = frontend::SiblingLoad::Linked;
  if (!loadSources(paths, m, so, set)) {
    printInputErrors(io, set.inputErrors);
    return kExitUsage;
  }
  // Every unit the image links is checked as a named file is: its diagnostics are shown and its
  // errors stop the compilation (a sibling that nothing links stays silent).
  compiler::CompileOptions co;
  co.dialect = m.dialect;
  co.specialM = &m.specialM;
  co.parameters = &m.parameters;
  compiler::CompileError ignored; // no main program: the compiler says so after the diagnostics
  for (size_t u : compiler::linkedUnits(set, co, ignored))
    set.reported[u] = 1;
  filterDiagnostics(set, settingsFilter(set, settings));
  if (reportedFiles(set) == 0) return usageError(io, tool, "no .mpf or .spf files found in the given directories");
  return kExitOk;
}

frontend::LexOptions sourceLexOptions(const machine::Machine& m) {
  return frontend::lexOptionsFor(loadOptionsFor(m, 1, frontend::SiblingLoad::Linked));
}

} // namespace iso::driver
