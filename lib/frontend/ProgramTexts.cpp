//! @file ProgramTexts.cpp
//! @brief Program sets from in-memory texts (the language server's buffers).
#include "frontend/ProgramTexts.h"

namespace iso::frontend {

void loadProgramTexts(std::vector<ProgramText> texts, const LoadOptions& opts, ProgramSet& set) {
  for (auto& t : texts) {
    uint32_t id = set.sources.add(t.path, std::move(t.text));
    File f;
    f.id = id;
    f.path = std::move(t.path);
    set.files.push_back(std::move(f));
    set.reported.push_back(t.reported ? 1 : 0);
    set.named.push_back(t.reported ? 1 : 0);
    if (t.reported) set.namedOrder.push_back(id);
  }
  processFiles(set, opts);
}

} // namespace iso::frontend
