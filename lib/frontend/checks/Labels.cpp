//! @file Labels.cpp
//! @brief E203: the labels of a file, each name once in any case; label lookup for jumps.
#include "frontend/checks/FileChecker.h"

namespace iso::frontend::checks {

using diag::Msg;

void FileChecker::collectLabels() {
  // File::labels is in statement order: one entry per labelled statement
  labels_.clear();
  for (uint32_t j = 0; j < f_.labels.size(); ++j) {
    const StmtLabel& label = f_.labels[j];
    const uint32_t first = labels_.add(j);
    if (first != kNoIndex) {
      auto& d = diags_.report(Msg::LabelTwice, label.loc, static_cast<uint32_t>(label.text.size()), label.text);
      d.note(Msg::LabelTwiceNote, f_.labels[first].loc);
    }
  }
}

int32_t FileChecker::findLabel(std::string_view name) const {
  const uint32_t j = labels_.find(name);
  return j == kNoIndex ? -1 : static_cast<int32_t>(f_.labels[j].stmt);
}

} // namespace iso::frontend::checks
