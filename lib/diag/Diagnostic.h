//! @file Diagnostic.h
//! @brief A diagnostic is data: a stable code, a location, a message and notes.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace iso::diag {

enum class Severity : uint8_t { Info, Warning, Error };

/// Every diagnostic code of SPEC §7, in table order.
enum class Code : uint16_t {
#define DIAG(e, code, name, sev, desc) e,
#include "diag/Diagnostics.def"
  Count_
};

struct CodeInfo {
  const char* code;        ///< "E205"
  const char* name;        ///< "case-backward-jump"
  Severity severity;       ///< default severity
  const char* description; ///< one line, for rule tables (SARIF, man page)
};

const CodeInfo& info(Code code);
/// Finds a code by its code ("E205", case-insensitive) or its name ("case-backward-jump").
std::optional<Code> findCode(std::string_view codeOrName);
constexpr size_t codeCount() { return static_cast<size_t>(Code::Count_); }
const char* severityName(Severity s);

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
};

/// An input that could not be read (missing, unreadable): reported beside the diagnostics.
struct InputError {
  std::string path;
  std::string message;
};

/// An ordered bag of diagnostics. Library code appends here; it never prints.
class DiagnosticList {
public:
  Diagnostic& report(Code code, Loc loc, uint32_t length, std::string message);
  Diagnostic& report(Code code, Loc loc, std::string message) { return report(code, loc, 1, std::move(message)); }
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
