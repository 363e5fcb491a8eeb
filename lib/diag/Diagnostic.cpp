//! @file Diagnostic.cpp
//! @brief The code table and the diagnostic list.
#include "diag/Diagnostic.h"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <numeric>
#include <vector>

#include "support/CaseFold.h"

namespace iso::diag {

namespace {
constexpr CodeInfo kInfos[] = {
#define DIAG(e, code, name, sev, desc) {code, name, Severity::sev, desc},
#include "diag/Diagnostics.def"
};
static_assert(sizeof(kInfos) / sizeof(kInfos[0]) == static_cast<size_t>(Code::Count_));

} // namespace

const CodeInfo& info(Code code) { return kInfos[static_cast<size_t>(code)]; }

std::optional<Code> findCode(std::string_view s) {
  for (size_t i = 0; i < codeCount(); ++i)
    if (support::iequals(s, kInfos[i].code) || support::iequals(s, kInfos[i].name)) return static_cast<Code>(i);
  return std::nullopt;
}

const char* severityName(Severity s) {
  switch (s) {
  case Severity::Info: return "info";
  case Severity::Warning: return "warning";
  case Severity::Error: return "error";
  }
  return "error";
}

Diagnostic& DiagnosticList::report(Code code, Loc loc, uint32_t length, std::string message) {
  Diagnostic d;
  d.code = code;
  d.severity = info(code).severity;
  d.loc = loc;
  d.endLine = loc.line;
  d.endCol = loc.col + (length == 0 ? 1 : length);
  d.message = std::move(message);
  items_.push_back(std::move(d));
  return items_.back();
}

bool DiagnosticList::hasErrors() const {
  return std::any_of(items_.begin(), items_.end(), [](const Diagnostic& d) { return d.severity == Severity::Error; });
}

void DiagnosticList::append(DiagnosticList&& other) {
  items_.insert(items_.end(), std::make_move_iterator(other.items_.begin()),
                std::make_move_iterator(other.items_.end()));
  other.items_.clear();
}

void DiagnosticList::sort() {
  // by file, line, column and code, stable; the diagnostics themselves (message, notes, fixes) move once: an index is
  // sorted, not the records
  const auto before = [this](uint32_t i, uint32_t j) {
    const Diagnostic& a = items_[i];
    const Diagnostic& b = items_[j];
    if (a.loc.file != b.loc.file) return a.loc.file < b.loc.file;
    if (a.loc.line != b.loc.line) return a.loc.line < b.loc.line;
    if (a.loc.col != b.loc.col) return a.loc.col < b.loc.col;
    return a.code < b.code;
  };
  std::vector<uint32_t> order(items_.size());
  std::iota(order.begin(), order.end(), 0u);
  if (std::is_sorted(order.begin(), order.end(), before)) return;
  std::stable_sort(order.begin(), order.end(), before);
  std::vector<Diagnostic> sorted;
  sorted.reserve(items_.size());
  for (uint32_t i : order)
    sorted.push_back(std::move(items_[i]));
  items_ = std::move(sorted);
}

} // namespace iso::diag
