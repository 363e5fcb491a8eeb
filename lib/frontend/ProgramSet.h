//! @file ProgramSet.h
//! @brief Loads a program set (SPEC §1): the named files and directories plus every .mpf/.spf
//!        beside the named files; parses and checks every file, then the set.
#pragma once

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "diag/Diagnostic.h"
#include "diag/SourceManager.h"
#include "frontend/Ast.h"
#include "frontend/FilePipeline.h"
#include "frontend/Lexer.h"
#include "frontend/Sema.h"
#include "machine/Machine.h"

namespace iso::frontend {

class IncrementalFile;

/// One source of an in-memory program set.
struct ProgramText {
  std::string path;     ///< how diagnostics name the file; its extension decides the unit kind
  std::string text;     ///< raw bytes
  bool reported = true; ///< diagnostics of this file are shown (else it only resolves calls)
};

/// Which of the siblings (the .mpf/.spf beside the named files) a program set reads whole.
enum class SiblingLoad : uint8_t {
  All, ///< every sibling (the language server, tests)
  /// isolint: a sibling only when a loaded file calls its PROC name (or defines a name that it
  /// defines too, for E209); what each sibling is comes from its first lines.
  Called,
  /// isocc and isosim: what an image links, besides Called: every semi-automatic sibling (and,
  /// when no named file is a main program, the sibling main programs, one of which is linked).
  Linked,
};

struct LoadOptions {
  const machine::Machine* machine = nullptr;
  machine::Dialect dialect = machine::Dialect::Sidac;
  unsigned jobs = 1;    ///< files parsed and checked in parallel
  bool siblings = true; ///< load .mpf/.spf beside named files to resolve calls
  /// Which siblings are read whole, parsed and checked (the others cost their first lines).
  SiblingLoad siblingLoad = SiblingLoad::All;
  /// isolint: each file is checked as it is parsed (parseAndCheckFile), and its tree keeps only
  /// what the set-level checks need. The diagnostics are the same; the files cannot be compiled.
  bool compactTrees = false;
  /// compactTrees with a file alone in its round and `jobs` >= 2: how a large file is split
  /// between two threads (parseAndCheckFile).
  SplitOptions splitting;
  /// The first bytes of a compiled image: such a file is reported as an image, not parsed.
  std::string_view imageMagic;
  /// A named input given by its text (isolint --stdin-filename): when `paths` names
  /// buffer->path, its text is this one, not the disk's (the file need not exist); its folder
  /// still gives the siblings.
  const ProgramText* buffer = nullptr;
  /// The language server: file `i` of loadProgramTexts is checked by `record[i]` when it is
  /// set (compactTrees only), which keeps what an edit needs to check the file again in part.
  std::vector<IncrementalFile*> record;
  /// Asked every few thousand lines while files are parsed: true gives the load up (it throws
  /// Cancelled, and the set is not to be used).
  std::function<bool()> cancel;
  /// When set, the diagnostics of the set-level checks are copied here too.
  std::vector<diag::Diagnostic>* setLevel = nullptr;
};

struct ProgramSet {
  diag::SourceManager sources;
  std::vector<File> files; ///< parallel to sources (file id == index)
  std::vector<FileFlow> flows;
  std::vector<uint8_t> reported;  ///< diagnostics of this file are shown to the user
  std::vector<uint8_t> named;     ///< the file was named on the command line (in order)
  std::vector<size_t> namedOrder; ///< file indices of the named files, as given
  /// Every diagnostic, sorted by file (in the order of the set's files as a load of every
  /// sibling has them, whatever order the siblings were read in), line, column.
  diag::DiagnosticList diags;
  std::vector<diag::InputError> inputErrors; ///< named inputs that could not be read
  /// Siblings of the set that were not read whole (SiblingLoad::Called and Linked): still files
  /// of the program set (an output must not overwrite them), but not in `files`.
  std::vector<std::string> unread;
};

struct SetError {
  std::string path;
  std::string message;
};

/// Loads, parses and checks. A path that is missing or unreadable is recorded in
/// `set.inputErrors` and the other paths are still loaded and checked; the return value is
/// false (with the first of them in `err`) when there is any. Program errors are diagnostics in
/// `set.diags`, not failures. A binary file (a NUL byte in its first 8 KiB, or an image) gets
/// one E100 diagnostic and is not parsed.
bool loadProgramSet(const std::vector<std::string>& paths, const LoadOptions& opts, ProgramSet& set, SetError& err);

/// How the files of a set loaded with `opts` are lexed: its dialect, the default axis letters
/// and those of the machine, and in z32 the machine's user parameters.
LexOptions lexOptionsFor(const LoadOptions& opts);

/// Parses and checks `texts` as one program set (file ids in the given order; every reported
/// text counts as named): an editor's buffers, tests. Nothing is read from disk; `set` must be
/// empty.
void loadProgramTexts(std::vector<ProgramText> texts, const LoadOptions& opts, ProgramSet& set);

/// Parses and checks one in-memory source as a set of one file (tests, fuzzing).
void loadSingleSource(const std::string& path, std::string text, const LoadOptions& opts, ProgramSet& set);

/// The .mpf/.spf files directly in `dir`, sorted, named as a program set names them ("p.mpf"
/// in ".", else "dir/p.mpf"). False when the folder cannot be read.
bool listProgramFiles(const std::string& dir, std::vector<std::string>& out);

/// True for the extensions .mpf and .spf (any case).
bool isProgramFileName(const std::string& name);

} // namespace iso::frontend
