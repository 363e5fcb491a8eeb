//! @file Features.h
//! @brief The language features on an analysed folder: diagnostics as LSP objects, hover,
//!        definition, references, rename, document symbols, completion and quick fixes.
//!        Results are LSP JSON values; `uri` names an open document of the analysis.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "diag/Fix.h"
#include "lsp/TextDocument.h"
#include "lsp/Workspace.h"
#include "support/Expected.h"

namespace iso::lsp {

/// The `diagnostics` array of textDocument/publishDiagnostics for one file.
/// The LSP diagnostics of `diags`, their ranges in the lines `text` gives, notes in the files
/// `uris` names.
nlohmann::json diagnosticsJson(const std::vector<diag::Diagnostic>& diags, const LineText& text,
                               const std::vector<std::string>& uris);

/// textDocument/hover: a Hover or null. `markdown`: the client renders Markdown.
nlohmann::json hover(const Analysis& a, uint32_t file, Position p, bool markdown);
/// textDocument/definition: Location[] (empty when nothing is defined there).
nlohmann::json definition(const Analysis& a, uint32_t file, Position p);
/// textDocument/references: Location[].
nlohmann::json references(const Analysis& a, uint32_t file, Position p, bool includeDeclaration);
/// What the client takes in a WorkspaceEdit (its workspace.workspaceEdit capabilities).
struct EditCapabilities {
  bool documentChanges = false; ///< TextDocumentEdit[] with versions, not `changes`
  bool renameFiles = false;     ///< RenameFile operations (then in documentChanges, whatever the flag above)
};
/// The version of an open document; nullopt for a file on disk.
using VersionOf = std::function<std::optional<int64_t>(const std::string& uri)>;
/// textDocument/prepareRename: {range, placeholder} of the label (its definition or a jump to
/// it) or subprogram name (after PROC, or a call) at `p`; an error saying why nothing there can
/// be renamed.
support::Expected<nlohmann::json> prepareRename(const Analysis& a, uint32_t file, Position p);
/// textDocument/rename: the WorkspaceEdit that renames the label at `p` in its file, or the
/// subprogram in every file of the set (and, with `caps.renameFiles`, the file named after it)
/// at the places references() finds. An error when `newName` is no valid name, already names
/// another label of the file or subprogram of the set, would make a line too long, or the
/// subprogram's file is named after it and the client cannot rename files.
support::Expected<nlohmann::json> rename(const Analysis& a, uint32_t file, Position p, std::string_view newName,
                                         EditCapabilities caps, const VersionOf& versionOf);
/// textDocument/documentSymbol: DocumentSymbol[] (PROC, SEMI, labels).
nlohmann::json documentSymbols(const Analysis& a, uint32_t file);
/// workspace/symbol: SymbolInformation[] of the PROC, SEMI and label symbols of every file of
/// the analyses whose name holds `query` (case-insensitive; "" matches all), at most `limit`.
nlohmann::json workspaceSymbols(const std::vector<const Analysis*>& analyses, std::string_view query, size_t limit);
/// textDocument/foldingRange: FoldingRange[] of IF/ELSE/ENDIF and WHEN/CANCEL blocks (the
/// closing line stays visible), a subprogram's body and runs of two or more comment lines.
/// `doc` is the buffer of the file.
nlohmann::json foldingRanges(const Analysis& a, uint32_t file, const TextDocument& doc);
/// textDocument/semanticTokens/full: SemanticTokens of the legend semanticTokenTypes()
/// (keywords, G/M codes, axes, R parameters, system variables, labels, numbers).
nlohmann::json semanticTokens(const Analysis& a, uint32_t file);
/// The token types of the semantic tokens legend, in index order.
nlohmann::json semanticTokenTypes();
/// textDocument/completion: a CompletionList. `doc` is the buffer (the analysis may lag it).
nlohmann::json completion(const Analysis& a, uint32_t file, const TextDocument& doc, Position p);
/// textDocument/codeAction: CodeAction[] of quick fixes for the diagnostics on the lines of
/// `range`.
nlohmann::json codeActions(const Analysis& a, uint32_t file, Range range);
/// The TextEdit[] of byte edits of `doc` (in order, not overlapping): the edits of consecutive
/// lines become one, so a run of changed lines is one edit; the line ends between them stay.
nlohmann::json textEdits(const TextDocument& doc, const std::vector<diag::ByteEdit>& edits);

} // namespace iso::lsp
