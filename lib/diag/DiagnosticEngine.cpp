//! @file DiagnosticEngine.cpp
//! @brief Disable, suppress, map severities, limit and count diagnostics (one place).
#include "diag/DiagnosticEngine.h"

#include <algorithm>

namespace iso::diag {

Counts countOf(const std::vector<Diagnostic>& diags) {
  Counts c;
  for (const auto& d : diags) {
    if (d.severity == Severity::Error)
      ++c.errors;
    else if (d.severity == Severity::Warning)
      ++c.warnings;
    else
      ++c.infos;
  }
  return c;
}

void DiagnosticEngine::addSuppression(const SuppressionRange& s) {
  if (s.line == 0) {
    fileSup_.insert(key(s.file, 0, s.code));
    return;
  }
  for (uint32_t l = s.line; l <= s.lastLine && l >= s.line; ++l)
    lineSup_.insert(key(s.file, l, s.code));
}

bool DiagnosticEngine::suppressed(const Diagnostic& d) const {
  return (!fileSup_.empty() && fileSup_.count(key(d.loc.file, 0, d.code)) != 0) ||
         (!lineSup_.empty() && lineSup_.count(key(d.loc.file, d.loc.line, d.code)) != 0);
}

void DiagnosticEngine::apply(std::vector<Diagnostic>& items) const {
  const auto& off = policy_.disabled;
  const auto& only = policy_.selected;
  size_t out = 0;
  for (size_t i = 0; i < items.size(); ++i) {
    Diagnostic& d = items[i];
    if (!shown(d.loc.file)) continue;
    if (std::find(off.begin(), off.end(), d.code) != off.end()) continue;
    if (!only.empty() && std::find(only.begin(), only.end(), d.code) == only.end()) continue;
    if (policy_.disabledFor && policy_.disabledFor(d.loc.file, d.code)) continue;
    if (suppressed(d)) {
      if (!policy_.keepSilencedErrors || d.severity != Severity::Error) continue;
      d.notes.push_back({d.loc, "silenced for isolint by an inline 'isolint: disable', but it still prevents "
                                "compiling"});
    }
    if (policy_.werror && d.severity == Severity::Warning) d.severity = Severity::Error;
    if (out != i) items[out] = std::move(d);
    ++out;
  }
  items.resize(out);
}

void DiagnosticEngine::limitPerFile(std::vector<Diagnostic>& items, size_t n) {
  size_t out = 0, inFile = 0;
  uint32_t file = UINT32_MAX;
  for (size_t i = 0; i < items.size(); ++i) {
    if (items[i].loc.file != file) {
      file = items[i].loc.file;
      inFile = 0;
    }
    if (inFile++ >= n) continue;
    if (out != i) items[out] = std::move(items[i]);
    ++out;
  }
  items.resize(out);
}

} // namespace iso::diag
