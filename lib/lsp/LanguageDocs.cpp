//! @file LanguageDocs.cpp
//! @brief Hover and completion texts from the documentation columns of the lib/lang tables.
#include "lsp/LanguageDocs.h"

#include <fmt/format.h>

#include "lang/Addresses.h"
#include "lang/GCodes.h"
#include "lang/Keywords.h"
#include "lang/Limits.h"
#include "lang/MFunctions.h"
#include "lang/SysVars.h"
#include "lang/Z32GCodes.h"
#include "support/CaseFold.h"

namespace iso::lsp {

namespace {
/// A word an editor documents: a keyword or item name of lang/Keywords.def, or an address.
struct Word {
  std::string_view word;
  std::string_view syntax;
  std::string_view doc;
  bool keyword;
};
/// The items that are an address, not a keyword (no lang table documents them).
constexpr Word kAddressItems[] = {
    {lang::kRadiusAddress, "CR=r", "arc radius (negative: an arc over 180 degrees)", false},
};

/// Dialect z32's words (SPEC §4.7).
constexpr Word kZ32Words[] = {
    {"GO", "GON12  GON10-N20",
     "z32: jump without return to the first line that begins with the target (GON12, "
     "GO%N1, GO/N12); GON10-N20 runs lines N10 through N20 and returns (one nesting level)",
     false},
    {"GOP", "GOPname", "z32: call subprogram `name` with return (one nesting level), alone on its line", false},
    {"KG", "KGname", "z32: after everything else on its line, continue in subprogram `name` without return", false},
    {"O", "O<n>", "z32: select origin n (1..99) of the machine file, O0 none: absolute targets add its offsets", false},
    {"TA", "TA<n>", "z32: the actual tool: mounts tool n at once", false},
    {"TB", "TB<n>", "z32: the next tool (reported only)", false},
    {"PAR", "PAR[i]", "z32: numeric parameter i (0..999), 0.0 at start; PAR[i]=expr assigns", false},
    {"PAL", "PAL[i]", "z32: parameter i (0..255) shared with the PLC; a write is a real-time access", false},
};

std::vector<Word> makeWords() {
  std::vector<Word> w;
  for (const auto& k : lang::kKeywords)
    w.push_back({k.spelling, k.syntax, k.doc, k.reserved});
  w.insert(w.end(), std::begin(kAddressItems), std::end(kAddressItems));
  return w;
}
const std::vector<Word>& words() {
  static const std::vector<Word> w = makeWords();
  return w;
}

std::string gLabel(const lang::GInfo& g) { return fmt::format("G{:02}", g.code); }
std::string gGroupText(const lang::GInfo& g) {
  if (g.group == lang::GGroup::None) return fmt::format("{} (non-modal)", lang::gGroupName(g.group));
  return fmt::format("{} (modal{})", lang::gGroupName(g.group), g.initial ? ", initial" : "");
}
std::string gText(const lang::GInfo& g) {
  return fmt::format("**{}** — {}  \ngroup: {}", gLabel(g), g.doc, gGroupText(g));
}
std::string sysVarIndex(const lang::SysVarInfo& v) { return v.takesAxis ? "[axis]" : "[n]"; }
std::string sysVarText(const lang::SysVarInfo& v) {
  return fmt::format("**{}{}** — {}  \naccess: {}", v.name, sysVarIndex(v), v.doc, v.access);
}
std::string wordText(const Word& w) { return fmt::format("**{}** — {}  \n`{}`", w.word, w.doc, w.syntax); }
} // namespace

std::optional<std::string> hoverG(int n) {
  for (const auto& g : lang::kGCodes)
    if (g.code == n) return gText(g);
  return std::nullopt;
}

std::string hoverM(int n) {
  for (const auto& m : lang::kMFunctionDocs)
    if (m.number == n) return fmt::format("**M{}** — {}", m.number, m.doc);
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
  for (const auto& v : lang::kSysVars)
    if (support::iequals(name, v.name)) return sysVarText(v);
  return std::nullopt;
}

std::optional<std::string> hoverWord(std::string_view word) {
  for (const auto& w : words())
    if (support::iequals(word, w.word)) return wordText(w);
  return std::nullopt;
}

std::optional<std::string> hoverZ32G(int n) {
  const lang::Z32GCode* g = lang::findZ32G(n);
  if (!g) return std::nullopt;
  return fmt::format("**G{}** — z32: {}{}", n, g->doc, g->modelled ? "" : "  \nnot modelled by isotools (W420)");
}

std::optional<std::string> hoverZ32Word(std::string_view word) {
  const Word* best = nullptr;
  for (const Word& w : kZ32Words) // the longest prefix: GOPPALLET is GOP, GON12 is GO
    if (support::istartsWith(word, w.word) && (!best || w.word.size() > best->word.size()) &&
        (word.size() == w.word.size() || w.word == "GO" || w.word == "GOP" || w.word == "KG"))
      best = &w;
  if (!best) return std::nullopt;
  return wordText(*best);
}

std::string hoverUserParam(std::string_view name) {
  return fmt::format("**{}** — z32: user parameter of the machine file (0.0 at start); `{}=expr` or `{}12.5` "
                     "assigns, `{}` in an expression reads it",
                     name, name, name, name);
}

const std::vector<LanguageEntry>& z32Entries() {
  static const std::vector<LanguageEntry> entries = [] {
    std::vector<LanguageEntry> e;
    for (const Word& w : kZ32Words)
      e.push_back({EntryKind::Item, std::string(w.word), std::string(w.syntax), wordText(w)});
    for (const lang::Z32GCode& g : lang::kZ32GCodes)
      e.push_back({EntryKind::GCode, fmt::format("G{}", g.code), "z32", *hoverZ32G(g.code)});
    return e;
  }();
  return entries;
}

const std::vector<LanguageEntry>& languageEntries() {
  static const std::vector<LanguageEntry> entries = [] {
    std::vector<LanguageEntry> e;
    for (const auto& w : words())
      e.push_back(
          {w.keyword ? EntryKind::Keyword : EntryKind::Item, std::string(w.word), std::string(w.syntax), wordText(w)});
    for (const auto& g : lang::kGCodes)
      e.push_back({EntryKind::GCode, gLabel(g), gGroupText(g), gText(g)});
    for (const auto& m : lang::kMFunctionDocs)
      e.push_back({EntryKind::MCode, fmt::format("M{}", m.number), "M function", hoverM(m.number)});
    // the variables a program reads while it runs first, then machine data
    for (bool machineData : {false, true})
      for (const auto& v : lang::kSysVars)
        if (v.machineData == machineData)
          e.push_back(
              {EntryKind::SysVar, std::string(v.name), fmt::format("{}{}", v.name, sysVarIndex(v)), sysVarText(v)});
    return e;
  }();
  return entries;
}

} // namespace iso::lsp
