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
  const auto index = static_cast<uint32_t>(ranges_.size());
  ranges_.push_back(s);
  used_.push_back(0);
  if (s.line == 0) {
    fileSup_.emplace(key(s.file, 0, s.code), index); // a second one for the same code stays unused
    return;
  }
  for (uint32_t l = s.line; l <= s.lastLine && l >= s.line; ++l)
    lineSup_.emplace(key(s.file, l, s.code), index);
}

bool DiagnosticEngine::suppressed(const Diagnostic& d) {
  bool hit = false;
  if (!fileSup_.empty())
    if (auto it = fileSup_.find(key(d.loc.file, 0, d.code)); it != fileSup_.end()) {
      used_[it->second] = 1;
      hit = true;
    }
  if (!lineSup_.empty())
    if (auto it = lineSup_.find(key(d.loc.file, d.loc.line, d.code)); it != lineSup_.end()) {
      used_[it->second] = 1;
      hit = true;
    }
  return hit;
}

std::vector<SuppressionRange> DiagnosticEngine::unusedSuppressions() const {
  std::vector<SuppressionRange> out;
  for (size_t i = 0; i < ranges_.size(); ++i)
    if (used_[i] == 0) out.push_back(ranges_[i]);
  return out;
}

void DiagnosticEngine::apply(std::vector<Diagnostic>& items) {
  const auto& off = policy_.disabled;
  const auto& only = policy_.selected;
  size_t out = 0;
  for (size_t i = 0; i < items.size(); ++i) {
    Diagnostic& d = items[i];
    if (!shown(d.loc.file)) continue;
    const bool silenced = suppressed(d); // first: a suppression of a rule also disabled is used
    if (std::find(off.begin(), off.end(), d.code) != off.end()) continue;
    if (!only.empty() && std::find(only.begin(), only.end(), d.code) == only.end()) continue;
    if (policy_.disabledFor && policy_.disabledFor(d.loc.file, d.code)) continue;
    if (silenced) {
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
