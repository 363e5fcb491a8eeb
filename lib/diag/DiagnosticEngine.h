//! @file DiagnosticEngine.h
//! @brief What the user asked to see, in one place for all tools: rules disabled (by the
//!        command line, by settings per file), inline suppressions, warnings as errors, errors
//!        that must stay (isocc/isosim), the per-file limit and the counts.
#pragma once

#include <cstdint>
#include <functional>
#include <unordered_map>
#include <vector>

#include "diag/Diagnostic.h"

namespace iso::diag {

/// The user's choices (isolint --disable/--werror, isotools.toml, the isocc/isosim policy).
struct DiagnosticPolicy {
  std::vector<Code> disabled; ///< rules off everywhere
  bool werror = false;        ///< warnings become errors
  /// isocc/isosim: an error silenced inline stays, with a note (it still prevents compiling).
  bool keepSilencedErrors = false;
  /// More rules off per file (the settings' disable/enable and per-path overrides).
  std::function<bool(uint32_t file, Code code)> disabledFor;
  std::vector<Code> selected{}; ///< when not empty, only these rules are shown (isolint --select)
};

/// An inline suppression: `code` off on lines [line, lastLine] of `file` (line 0: the file).
struct SuppressionRange {
  uint32_t file = 0;
  uint32_t line = 0;
  uint32_t lastLine = 0;
  Code code = Code::Syntax;
  uint32_t commentLine = 0; ///< where the code is written in the comment (W421): line, column (1-based)
  uint32_t col = 0;
  uint32_t length = 0;
};

class DiagnosticEngine {
public:
  explicit DiagnosticEngine(DiagnosticPolicy policy) : policy_(std::move(policy)) {}

  void addSuppression(const SuppressionRange& s);
  /// Only diagnostics of these files are shown (index = file id; empty = every file).
  void setShownFiles(std::vector<uint8_t> shown) { shown_ = std::move(shown); }

  /// Applies the policy to `items` in place, keeping their order: drops what is disabled,
  /// suppressed or in a file not shown, maps severities (werror). A suppression that meets a
  /// diagnostic of its code and lines (before any other rule drops it) is used.
  void apply(std::vector<Diagnostic>& items);

  /// The suppressions no diagnostic applied so far has used, in the order they were added.
  std::vector<SuppressionRange> unusedSuppressions() const;

  /// Keeps at most `n` diagnostics of each file (the list must be sorted by file).
  static void limitPerFile(std::vector<Diagnostic>& items, size_t n);

private:
  bool shown(uint32_t file) const { return shown_.empty() || (file < shown_.size() && shown_[file] != 0); }
  bool suppressed(const Diagnostic& d);
  static uint64_t key(uint64_t file, uint64_t line, Code code) {
    return (file << 40) ^ (line << 12) ^ static_cast<uint64_t>(code);
  }

  DiagnosticPolicy policy_;
  std::vector<uint8_t> shown_;
  std::unordered_map<uint64_t, uint32_t> lineSup_, fileSup_; ///< key -> index in ranges_
  std::vector<SuppressionRange> ranges_;
  std::vector<uint8_t> used_;
};

/// Counts of errors, warnings and infos (the count line, JSON, exit codes).
struct Counts {
  size_t errors = 0, warnings = 0, infos = 0;
};
Counts countOf(const std::vector<Diagnostic>& diags);

} // namespace iso::diag
