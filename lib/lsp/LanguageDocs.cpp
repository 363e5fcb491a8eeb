//! @file LanguageDocs.cpp
//! @brief Hover and completion texts from LanguageDocs.def.
#include "lsp/LanguageDocs.h"

#include <fmt/format.h>

#include "frontend/Lexer.h"
#include "lang/Limits.h"
#include "support/CaseFold.h"

namespace iso::lsp {

namespace {
struct GRow {
  int number;
  const char* name;
  const char* group;
  const char* meaning;
};
struct MRow {
  int number;
  const char* name;
  const char* meaning;
};
struct SysVarRow {
  const char* name;
  const char* index;
  const char* meaning;
  const char* access;
};
struct WordRow {
  const char* word;
  const char* syntax;
  const char* meaning;
  bool keyword;
};

#define LSP_G(n, name, group, meaning) {n, name, group, meaning},
#define LSP_M(n, name, meaning)
#define LSP_SYSVAR(name, index, meaning, access)
#define LSP_KEYWORD(word, syntax, meaning)
#define LSP_ITEM(word, syntax, meaning)
constexpr GRow kG[] = {
#include "lsp/LanguageDocs.def"
};
#undef LSP_G
#undef LSP_M
#define LSP_G(n, name, group, meaning)
#define LSP_M(n, name, meaning) {n, name, meaning},
constexpr MRow kM[] = {
#include "lsp/LanguageDocs.def"
};
#undef LSP_M
#undef LSP_SYSVAR
#define LSP_M(n, name, meaning)
#define LSP_SYSVAR(name, index, meaning, access) {name, index, meaning, access},
constexpr SysVarRow kSysVars[] = {
#include "lsp/LanguageDocs.def"
};
#undef LSP_SYSVAR
#undef LSP_KEYWORD
#undef LSP_ITEM
#define LSP_SYSVAR(name, index, meaning, access)
#define LSP_KEYWORD(word, syntax, meaning) {word, syntax, meaning, true},
#define LSP_ITEM(word, syntax, meaning) {word, syntax, meaning, false},
constexpr WordRow kWords[] = {
#include "lsp/LanguageDocs.def"
};
#undef LSP_G
#undef LSP_M
#undef LSP_SYSVAR
#undef LSP_KEYWORD
#undef LSP_ITEM

std::string gText(const GRow& g) { return fmt::format("**{}** — {}  \ngroup: {}", g.name, g.meaning, g.group); }
std::string sysVarText(const SysVarRow& v) {
  return fmt::format("**{}{}** — {}  \naccess: {}", v.name, v.index, v.meaning, v.access);
}
std::string wordText(const WordRow& w) { return fmt::format("**{}** — {}  \n`{}`", w.word, w.meaning, w.syntax); }
} // namespace

std::optional<std::string> hoverG(int n) {
  for (const auto& g : kG)
    if (g.number == n) return gText(g);
  return std::nullopt;
}

std::string hoverM(int n) {
  for (const auto& m : kM)
    if (m.number == n) return fmt::format("**{}** — {}", m.name, m.meaning);
  return fmt::format("**M{}** — PLC sequence {}: starts it and waits for it to end (`M=NB({})` does not wait); "
                     "its duration and effects come from the machine file",
                     n, n, n);
}

std::string hoverR(long n) {
  if (n < 0)
    return fmt::format("**R[expr]** — R parameter with a computed index ({}..{} at run time)", lang::kMinRIndex,
                       lang::kMaxRIndex);
  if (n == 0) return "**R0** — reserved for the system: using it is an error (E301)";
  return fmt::format("**R{}** — R parameter {} (a double, 0.0 at program start; its value is not known "
                     "statically)",
                     n, n);
}

std::optional<std::string> hoverSysVar(std::string_view name) {
  for (const auto& v : kSysVars)
    if (support::iequals(name, v.name)) return sysVarText(v);
  return std::nullopt;
}

std::optional<std::string> hoverWord(std::string_view word) {
  for (const auto& w : kWords)
    if (support::iequals(word, w.word)) return wordText(w);
  return std::nullopt;
}

const std::vector<LanguageEntry>& languageEntries() {
  static const std::vector<LanguageEntry> entries = [] {
    std::vector<LanguageEntry> e;
    for (const auto& w : kWords)
      e.push_back({w.keyword ? EntryKind::Keyword : EntryKind::Item, w.word, w.syntax, wordText(w)});
    for (const auto& g : kG)
      e.push_back({EntryKind::GCode, g.name, g.group, gText(g)});
    for (const auto& m : kM)
      e.push_back({EntryKind::MCode, m.name, "M function", hoverM(m.number)});
    for (const auto& v : kSysVars)
      e.push_back({EntryKind::SysVar, v.name, fmt::format("{}{}", v.name, v.index), sysVarText(v)});
    return e;
  }();
  return entries;
}

} // namespace iso::lsp
