//! @file Rename.cpp
//! @brief textDocument/prepareRename and textDocument/rename: a label within its file, a
//!        subprogram across the program set (its PROC line, every call, and its file when the
//!        file is named after it and the editor can rename files). The places renamed are
//!        those textDocument/references finds.
#include <algorithm>
#include <filesystem>
#include <initializer_list>
#include <map>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include <fmt/format.h>

#include "frontend/Lexer.h"
#include "lang/Keywords.h"
#include "lang/Limits.h"
#include "lsp/Features.h"
#include "lsp/FeaturesInternal.h"
#include "lsp/Uri.h"
#include "support/CaseFold.h"

namespace iso::lsp {

using detail::Lexed;
using detail::NameSite;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

constexpr const char* kOnlyNames = "only labels and subprogram names can be renamed";

/// The name stands as it is on its line (a `$` continuation splits none of it), so an edit of
/// its range replaces it.
bool writtenWhole(const Analysis& a, const NameSite& s) {
  const std::string_view line = a.set.sources.lineText(s.file, s.loc.line);
  return s.len == s.text.size() && s.loc.col >= 1 && s.loc.col - 1 <= line.size() &&
         line.substr(s.loc.col - 1, s.len) == s.text;
}

std::string fileName(const Analysis& a, uint32_t file) { return fs::path(a.set.files[file].path).filename().string(); }

/// Whether `text` (one line) lexes as the tokens of `kinds`, the one at `index` being the
/// identifier `name`, without a diagnostic.
bool lexesAs(const Analysis& a, const std::string& text, std::initializer_list<frontend::Tok> kinds, size_t index,
             std::string_view name) {
  const std::string line = text + "\n"; // the tokens point into it
  Lexed lx;
  detail::lexText(a, line, 0, lx);
  if (lx.diags.size() != 0 || lx.lines.size() != 1) return false;
  const auto& t = lx.lines[0].tokens; // ends with End
  if (t.size() != kinds.size() + 1) return false;
  for (size_t i = 0; i < kinds.size(); ++i)
    if (t[i].kind != kinds.begin()[i]) return false;
  return t[index].text == name;
}

/// Why `name` cannot be the new name of a label (`label`) or of a subprogram, if it cannot: it
/// must be an identifier and no keyword, and the lexer must read it as one name where it would
/// be written (before a label's colon and after GOTOF; alone on a call's line and after PROC).
std::optional<std::string> invalidName(const Analysis& a, std::string_view name, bool label) {
  using frontend::Tok;
  const char* what = label ? "a label" : "a subprogram name";
  auto identStart = [](char c) { return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || c == '_'; };
  auto identChar = [&](char c) { return identStart(c) || (c >= '0' && c <= '9'); };
  if (name.empty()) return fmt::format("the new name is empty: {} needs one", what);
  if (!identStart(name[0]) || !std::all_of(name.begin(), name.end(), identChar))
    return fmt::format("'{}' cannot be {}: a name is letters, digits and '_', and starts with a letter or '_'",
                       frontend::printableBytes(name.substr(0, 60)), what);
  if (name.size() >= lang::kMaxLineLength)
    return fmt::format("the new name of {} characters cannot be {}: a line holds at most {} characters", name.size(),
                       what, lang::kMaxLineLength);
  if (lang::findKeyword(name)) return fmt::format("'{}' is a keyword and cannot be {}", name, what);
  const std::string n(name);
  if (label) {
    if (!lexesAs(a, n + ":", {Tok::Ident, Tok::Colon}, 0, name) ||
        !lexesAs(a, "GOTOF " + n, {Tok::KwGotof, Tok::Ident}, 1, name))
      return fmt::format("'{}' cannot be a label: it is not read as one name", name);
    return std::nullopt;
  }
  if (!lexesAs(a, n, {Tok::Ident}, 0, name) ||
      !lexesAs(a, "PROC " + n + " SAVE", {Tok::KwProc, Tok::Ident, Tok::KwSave}, 1, name))
    return fmt::format("'{}' cannot be a subprogram name: it reads as address words, not as a name", name);
  if (a.dialect == machine::Dialect::Z32 && (support::istartsWith(name, "GOP") || support::istartsWith(name, "KG")))
    return fmt::format("'{}' cannot be a subprogram name in dialect z32: a line that starts with {} is a {}", name,
                       support::istartsWith(name, "GOP") ? "GOP" : "KG",
                       support::istartsWith(name, "GOP") ? "GOP call" : "KG item");
  return std::nullopt;
}

/// Why a place already named `newName` forbids the rename: it would change what it means.
std::string clashMessage(const Analysis& a, const NameSite& s, bool label, std::string_view newName) {
  if (label && s.definition)
    return fmt::format("a label '{}' is already defined on line {} of this file", s.text, s.loc.line);
  if (label)
    return fmt::format("line {} already jumps to '{}': after the rename it would jump to the renamed label", s.loc.line,
                       s.text);
  if (s.definition)
    return fmt::format("'{}' already names the subprogram of {} (line {})", s.text, fileName(a, s.file), s.loc.line);
  return fmt::format("line {} of {} already calls '{}': after the rename it would call the renamed subprogram",
                     s.loc.line, fileName(a, s.file), newName);
}

/// The first line the rename would make longer than a line may be, if any.
std::optional<std::string> tooLong(const Analysis& a, const std::vector<NameSite>& sites, size_t oldSize,
                                   size_t newSize) {
  if (newSize <= oldSize) return std::nullopt;
  std::map<uint32_t, std::vector<uint32_t>> linesOf; // file: the lines of its sites
  for (const auto& s : sites)
    linesOf[s.file].push_back(s.loc.line);
  for (const auto& [file, lines] : linesOf) {
    Lexed lx;
    detail::lexFile(a, file, lx);
    for (const auto& l : lx.lines) {
      const auto n = static_cast<size_t>(
          std::count_if(lines.begin(), lines.end(), [&](uint32_t x) { return x >= l.firstLine && x <= l.lastLine; }));
      if (n > 0 && l.length + n * (newSize - oldSize) > lang::kMaxLineLength)
        return fmt::format("the new name would make line {} of {} longer than {} characters", l.firstLine,
                           fileName(a, file), lang::kMaxLineLength);
    }
  }
  return std::nullopt;
}

struct FileRename {
  std::string oldUri, newUri;
};

/// The files named after the subprogram `oldName` (stem, any case) that its rename renames too;
/// an error when the editor cannot rename files or the new name is taken.
support::Expected<std::vector<FileRename>> fileRenames(const Analysis& a, const std::vector<NameSite>& sites,
                                                       std::string_view oldName, std::string_view newName,
                                                       bool canRename) {
  std::vector<FileRename> out;
  if (support::iequals(oldName, newName)) return out; // the same name in another case: the file still fits
  for (const auto& s : sites) {
    if (!s.definition) continue;
    const auto path = uriToPath(a.uris[s.file]);
    if (!path || !support::iequals(fs::path(*path).stem().string(), oldName)) continue;
    const std::string file = fileName(a, s.file);
    if (!canRename)
      return support::Error{"", fmt::format("{} is named after the subprogram '{}', and this editor cannot rename "
                                            "files through the language server: rename the file too, by hand",
                                            file, oldName)};
    const fs::path to = fs::path(*path).parent_path() / (std::string(newName) + fs::path(*path).extension().string());
    std::error_code ec;
    bool taken = fs::exists(to, ec);
    for (const auto& f : a.set.files)
      taken =
          taken || (f.id != s.file && support::iequals(fs::path(f.path).filename().string(), to.filename().string()));
    if (taken)
      return support::Error{"", fmt::format("{} is named after the subprogram '{}', and {} already exists", file,
                                            oldName, to.filename().string())};
    out.push_back({a.uris[s.file], pathToUri(to.string())});
  }
  return out;
}

} // namespace

support::Expected<json> prepareRename(const Analysis& a, uint32_t file, Position p) {
  Lexed lx;
  detail::lexFile(a, file, lx);
  const detail::SiteAt t = detail::siteAt(a, file, p, lx);
  if (t.kind == detail::SiteAt::None) return support::Error{"", kOnlyNames};
  if (!writtenWhole(a, t.site))
    return support::Error{"", fmt::format("'{}' is not written on one line (a $ continuation splits it)", t.site.text)};
  return json{{"range", detail::toJson(a.range(t.site.loc, t.site.len))}, {"placeholder", std::string(t.site.text)}};
}

support::Expected<json> rename(const Analysis& a, uint32_t file, Position p, std::string_view newName,
                               EditCapabilities caps, const VersionOf& versionOf) {
  Lexed lx;
  detail::lexFile(a, file, lx);
  const detail::SiteAt t = detail::siteAt(a, file, p, lx);
  if (t.kind == detail::SiteAt::None) return support::Error{"", kOnlyNames};
  const bool label = t.kind == detail::SiteAt::Label;
  if (auto why = invalidName(a, newName, label)) return support::Error{"", *why};
  const std::string oldName(t.site.text);
  std::vector<NameSite> sites;
  std::optional<NameSite> clash;
  auto collect = [&](const NameSite& s) {
    if (support::iequals(s.text, oldName))
      sites.push_back(s);
    else if (support::iequals(s.text, newName) && !clash)
      clash = s;
  };
  if (label)
    detail::forEachLabelSite(a, file, lx, collect);
  else
    detail::forEachSubprogramSite(a, collect);
  if (clash) return support::Error{"", clashMessage(a, *clash, label, newName)};
  for (const auto& [m, proc] : label || support::iequals(oldName, newName) ? std::map<int, std::string>{} : a.specialM)
    if (support::iequals(proc, oldName) || support::iequals(proc, newName))
      return support::Error{"", fmt::format("M{} of machine '{}' calls the subprogram '{}': a rename here would "
                                            "change what it calls (change the machine file first)",
                                            m, a.machineName, proc)};
  for (const auto& s : sites)
    if (!writtenWhole(a, s))
      return support::Error{"", fmt::format("'{}' on line {} of {} is not written on one line (a $ continuation "
                                            "splits it): rename it there by hand first",
                                            s.text, s.loc.line, fileName(a, s.file))};
  if (auto why = tooLong(a, sites, oldName.size(), newName.size())) return support::Error{"", *why};
  auto files = label ? std::vector<FileRename>{} : fileRenames(a, sites, oldName, newName, caps.renameFiles);
  if (!files) return files.error();

  std::sort(sites.begin(), sites.end(), [](const NameSite& x, const NameSite& y) {
    return std::tie(x.file, x.loc.line, x.loc.col) < std::tie(y.file, y.loc.line, y.loc.col);
  });
  std::map<uint32_t, json> edits; // file id: TextEdit[]
  for (size_t i = 0; i < sites.size(); ++i) {
    const NameSite& s = sites[i];
    if (i > 0 && s.file == sites[i - 1].file && s.loc.line == sites[i - 1].loc.line &&
        s.loc.col == sites[i - 1].loc.col)
      continue;
    auto& list = edits.try_emplace(s.file, json::array()).first->second;
    list.push_back({{"range", detail::toJson(a.range(s.loc, s.len))}, {"newText", std::string(newName)}});
  }
  if (!caps.documentChanges && files->empty()) {
    json changes = json::object();
    for (auto& [f, list] : edits)
      changes[a.uris[f]] = std::move(list);
    return json{{"changes", std::move(changes)}};
  }
  json changes = json::array();
  for (auto& [f, list] : edits) {
    const auto version = versionOf(a.uris[f]);
    changes.push_back({{"textDocument", {{"uri", a.uris[f]}, {"version", version ? json(*version) : json(nullptr)}}},
                       {"edits", std::move(list)}});
  }
  for (const auto& r : *files) // after the edits, which name the files as they are
    changes.push_back({{"kind", "rename"}, {"oldUri", r.oldUri}, {"newUri", r.newUri}});
  return json{{"documentChanges", std::move(changes)}};
}

} // namespace iso::lsp
