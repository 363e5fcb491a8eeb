//! @file Workspace.h
//! @brief The open documents of an editor and their analyses. The program set of a document is
//!        its folder (SPEC §1): the .mpf/.spf files there, read from disk, with open buffers
//!        in place of their files. Only open documents are reported.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "diag/Diagnostic.h"
#include "diag/Fix.h"
#include "driver/Common.h"
#include "driver/Format.h"
#include "driver/Policy.h"
#include "frontend/Incremental.h"
#include "frontend/ProgramSet.h"
#include "lsp/TextDocument.h"
#include "machine/Machine.h"
#include "support/Expected.h"

namespace iso::lsp {

/// One analysed folder: the program set (diagnostics already filtered as isolint would show
/// them) and the URI of each file. Valid until the next call that changes the workspace.
struct Analysis {
  frontend::ProgramSet set;
  std::vector<std::string> uris; ///< per file id
  machine::Dialect dialect = machine::Dialect::Sidac;
  std::string axisLetters;             ///< the letters the lexer reads as axes (upper-case)
  std::vector<std::string> userParams; ///< z32: the machine's user parameter names (upper-case)
  std::map<int, std::string> specialM; ///< z32: the machine's special_m (M number: the subprogram it calls)
  std::string machineName;             ///< z32: the machine's name
  /// Why the folder's settings or machine file could not be used ("" when they could): the
  /// analysis then used the machine and rules of the command line alone.
  std::string policyError;

  /// The file id of a URI, if the set has it.
  std::optional<uint32_t> fileOf(const std::string& uri) const;
  /// The LSP range of a diagnostic location (1-based line, byte columns, exclusive end).
  Range range(uint32_t file, uint32_t line, uint32_t col, uint32_t endLine, uint32_t endCol) const;
  Range range(const diag::Loc& loc, uint32_t length) const;
  /// The byte location (1-based line and column) of an LSP position in a file.
  diag::Loc loc(uint32_t file, Position p) const;
};

/// The text of a line of a file (1-based), for LSP ranges (UTF-16 columns).
using LineText = std::function<std::string_view(uint32_t file, uint32_t line)>;
/// The LSP range of a place in a file whose lines `text` gives.
Range rangeIn(const LineText& text, uint32_t file, uint32_t line, uint32_t col, uint32_t endLine, uint32_t endCol);

/// What a folder's diagnostics are published from: isolint's load of its program set (compact
/// trees, the lint policy of the folder), with a record of each open document, so that an edit
/// checks again only what it reaches (frontend::IncrementalFile). The files keep only their
/// suppressions; `raw` holds every diagnostic before the policy's filter.
struct FolderLint {
  std::ostringstream policyOut, policyErr;
  driver::Io policyIo{policyOut, policyErr, false, false};
  std::optional<driver::LintPolicies> policies; ///< owns the machine the records check with
  const driver::Settings* settings = nullptr;   ///< nullptr: the command line's machine and rules alone
  const machine::Machine* machine = nullptr;    ///< the policy's, else the command line's
  frontend::ProgramSet set;
  std::vector<std::string> uris; ///< per file id
  std::vector<diag::Diagnostic> raw;
  std::vector<diag::Diagnostic> setLevel; ///< the set-level part of `raw`
  std::map<uint32_t, std::unique_ptr<frontend::IncrementalFile>> records;
  /// The unfiltered diagnostics of files edited since the load, each checked again in part.
  std::map<uint32_t, std::vector<diag::Diagnostic>> updated;
  std::string policyError; ///< as Analysis::policyError
  bool stale = true;
};

/// What the server holds at most, so that no client (or flood of messages) can make it run out
/// of memory. A real editor session stays far below each.
struct Limits {
  size_t maxMessageBytes = size_t{64} << 20;  ///< one JSON-RPC message body (kMaxMessageBytes)
  size_t maxDocumentBytes = size_t{64} << 20; ///< one open document's text
  size_t maxTotalBytes = size_t{256} << 20;   ///< the texts and URIs of all open documents
  size_t maxDocuments = 1000;                 ///< open documents at once
};

struct WorkspaceOptions {
  const machine::Machine* machine = nullptr; ///< with --dialect applied; the machine without a policy
  std::vector<diag::Code> disabled;          ///< --disable
  bool werror = false;
  Limits limits = {};
  /// isolint --lsp: --config, --machine and --dialect. Each folder then gets the lint policy
  /// isolint applies to it (the settings file found for it, its machine file and rules);
  /// nullptr: `machine` and `disabled` only.
  const driver::CommonOptions* policy = nullptr;
};

class Workspace {
public:
  explicit Workspace(WorkspaceOptions opts) : opts_(std::move(opts)) {}

  /// Opens (or replaces) a document. Refused when it would exceed a limit: then the document
  /// is not kept (one of that URI open before is closed) and the result says which limit.
  std::optional<std::string> open(const std::string& uri, std::string text, int64_t version);
  /// Whether the open document `uri` may grow (or shrink) to `newSize` bytes: nullopt, or the
  /// limit it would exceed.
  std::optional<std::string> admitsSize(const std::string& uri, size_t newSize) const;
  /// nullptr when the document is not open.
  TextDocument* document(const std::string& uri);
  /// Marks the document's folder for a new analysis and a new check (after a save, a whole
  /// new text).
  void touch(const std::string& uri);
  /// The open document `uri` was edited (`change`, TextDocument::edit): its folder's analysis
  /// is stale; its diagnostics are checked again in part when the edit allows, else in full.
  void edited(const std::string& uri, const TextDocument::Change& change);
  /// The diagnostics to publish for the open document `uri`: isolint's for it under the
  /// folder's policy, checked again in full when stale. The folder's check is in `lint`.
  std::vector<diag::Diagnostic> diagnostics(const std::string& uri, const FolderLint*& lint);
  /// The text of a line of file `file` of `lint`'s set: an open document's buffer as it is now.
  LineText lineText(const FolderLint& lint);
  void close(const std::string& uri);
  /// Asked every few thousand lines while a folder is checked (diagnostics): true gives the
  /// check up (frontend::Cancelled comes out of diagnostics), and the folder stays to check.
  void setCancel(std::function<bool()> cancel) { cancel_ = std::move(cancel); }
  /// The folder is checked again at the next takeStaleFolders (its check was given up).
  void checkLater(const std::string& folder) { staleFolders_.insert(folder); }

  /// The analysis of the document's folder, rebuilt when stale; nullptr when it is not open.
  const Analysis* analysis(const std::string& uri);
  /// The folders whose analysis is stale, and the URIs closed since the last call (whose
  /// diagnostics must be cleared); both are reset.
  std::vector<std::string> takeStaleFolders();
  std::vector<std::string> takeClosed();
  /// The open documents of a folder, in URI order.
  std::vector<std::string> documentsIn(const std::string& folder) const;
  const Analysis* analyseFolder(const std::string& folder);
  /// The folders with open documents (the keys analyseFolder takes), in order.
  std::vector<std::string> folders() const;
  /// The edits that lay out the open document `uri` as isofmt lays out its file (the settings
  /// file found for it or --config, its machine file and dialect; never renumbered), changing
  /// only `lines`. None when it is not open or has syntax errors; an error (isofmt's message)
  /// when its settings or machine file cannot be used.
  support::Expected<std::vector<diag::ByteEdit>> format(const std::string& uri, driver::LineSpan lines);

private:
  struct Open {
    TextDocument doc;
    std::string path;   ///< "" when the URI is not a file: URI
    std::string folder; ///< the key of its program set
  };
  struct Folder {
    std::unique_ptr<Analysis> analysis;
    bool stale = true;
    std::unique_ptr<FolderLint> lint;
  };
  /// The program texts of a folder: its open documents (first, with `open`), then the other
  /// programs of the folder from disk, sorted by path.
  struct Source {
    frontend::ProgramText text;
    std::string uri;
  };
  /// `read`: a current check of the folder, whose texts of the files not open are taken
  /// instead of reading them from disk again.
  std::vector<Source> sourcesOf(const std::string& folder, const FolderLint* read = nullptr) const;
  FolderLint& lintFolder(const std::string& folder);
  /// Filters `set.diags` as isolint does under the folder's policy (`lint`).
  void applyPolicy(FolderLint& lint, frontend::ProgramSet& set) const;
  /// Marks the folder's analysis and check stale, to be published.
  void invalidate(const std::string& folder);
  /// The bytes `limits.maxTotalBytes` counts for the open documents, without `except`.
  size_t heldBytes(const std::string& except) const;
  std::function<bool()> cancel_;
  WorkspaceOptions opts_;
  std::map<std::string, Open> docs_;
  std::map<std::string, Folder> folders_;
  std::set<std::string> staleFolders_;
  std::set<std::string> closed_;
};

} // namespace iso::lsp
