//! @file LanguageDocs.h
//! @brief Hover texts (Markdown) and completion entries, written from the documentation
//!        columns of the lib/lang tables (G codes, M functions, system variables, keywords).
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace iso::lsp {

/// `G<n>` (any number of leading zeros): its group and meaning; nullopt for unknown codes.
std::optional<std::string> hoverG(int n);
/// `M<n>`: the special functions, else "PLC sequence n".
std::string hoverM(int n);
/// `R<n>`, or an indirect `R[...]` when `n` < 0.
std::string hoverR(long n);
/// A system variable by its canonical spelling (case-insensitive).
std::optional<std::string> hoverSysVar(std::string_view name);
/// A keyword (IF, GOTOF, ...) or item name (Pos, Posa, Fa, CR), case-insensitive.
std::optional<std::string> hoverWord(std::string_view word);

/// Dialect z32: G26, G28, G29 and the not-modelled codes; nullopt for the others.
std::optional<std::string> hoverZ32G(int n);
/// Dialect z32: GO, GOP, KG (alone or with their target: GON12, GOPPALLET, KGCAMBIO), O, TA, TB,
/// PAR, PAL, case-insensitive; nullopt for other words.
std::optional<std::string> hoverZ32Word(std::string_view word);
/// Dialect z32: a user parameter address of the machine file.
std::string hoverUserParam(std::string_view name);

enum class EntryKind { Keyword, GCode, MCode, SysVar, Item };
struct LanguageEntry {
  EntryKind kind;
  std::string label;  ///< what is inserted: GOTOF, G01, $aa_iw
  std::string detail; ///< one line: the group, the syntax
  std::string doc;    ///< Markdown
};
/// Every keyword and item name (the CR address last), G code, M function and system variable
/// (those a program reads while it runs, then machine data), each in its lang table's order.
const std::vector<LanguageEntry>& languageEntries();
/// Dialect z32's own words and G codes, added to the completion of a z32 program.
const std::vector<LanguageEntry>& z32Entries();

} // namespace iso::lsp
