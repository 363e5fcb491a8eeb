//! @file Diagnostic.h
//! @brief A diagnostic is data: a stable code, a location, a message and notes.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "diag/Code.h"
#include "diag/Messages.h"

namespace iso::diag {

/// A place in a source file: file id (of a SourceManager), 1-based line and byte column.
/// line == 0 means "the whole file".
struct Loc {
  uint32_t file = 0;
  uint32_t line = 0;
  uint32_t col = 0;
};

struct Note {
  Loc loc;
  std::string message;
};

/// A change to the text of a file: the bytes [start, endLine:endCol) are replaced by
/// `replacement` (columns are 1-based bytes of physical lines, like a diagnostic's; an
/// insertion has end == start). An edit never spans a `$` continuation join.
struct Edit {
  Loc start;
  uint32_t endLine = 0;
  uint32_t endCol = 0;
  std::string replacement;
};

/// A fix-it: edits that together remove the diagnostic, applied all or none.
struct Fix {
  std::string description; ///< "parenthesise each comparison"
  std::vector<Edit> edits;
};

struct Diagnostic {
  Code code = Code::Syntax;
  Severity severity = Severity::Error;
  Loc loc;
  uint32_t endLine = 0; ///< end of the primary range (inclusive line, exclusive column)
  uint32_t endCol = 0;
  std::string message;
  std::vector<Note> notes;
  std::vector<Fix> fixes; ///< safe, mechanical corrections (isolint --fix, LSP quick fixes)

  /// Adds a note (related information) at `at` with the text of `m`.
  template <class... A> void note(MsgRef<std::type_identity_t<A>...> m, Loc at, A&&... args) {
    notes.push_back({at, diag::message<A...>(m, std::forward<A>(args)...)});
  }
};

/// An input that could not be read (missing, unreadable): reported beside the diagnostics.
struct InputError {
  std::string path;
  std::string message;
};

/// An ordered bag of diagnostics. Library code appends here; it never prints.
class DiagnosticList {
public:
  /// Reports the message `m` (its code from the table) over `length` bytes from `loc`.
  template <class... A>
  Diagnostic& report(MsgRef<std::type_identity_t<A>...> m, Loc loc, uint32_t length, A&&... args) {
    return report(m.code(), loc, length, diag::message<A...>(m, std::forward<A>(args)...));
  }
  /// A text made elsewhere from the table (`message`), for helpers that pass it along.
  Diagnostic& report(Code code, Loc loc, uint32_t length, std::string text);
  const std::vector<Diagnostic>& items() const { return items_; }
  std::vector<Diagnostic>& items() { return items_; }
  size_t size() const { return items_.size(); }
  bool hasErrors() const;
  void append(DiagnosticList&& other);
  /// Sorts by file, line, column, code (stable), for deterministic output.
  void sort();

private:
  std::vector<Diagnostic> items_;
};

} // namespace iso::diag
