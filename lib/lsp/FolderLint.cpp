//! @file FolderLint.cpp
//! @brief The diagnostics the server publishes: a folder checked as isolint checks it, and an
//!        open document's edits checked again in part (frontend::IncrementalFile).
#include <algorithm>

#include "diag/DiagnosticEngine.h"
#include "driver/Lint.h"
#include "lsp/Workspace.h"
#include "support/Memory.h"
#include "support/SourceText.h"

namespace iso::lsp {

void Workspace::applyPolicy(FolderLint& lint, frontend::ProgramSet& set) const {
  if (lint.settings) {
    driver::filterDiagnostics(set, lint.policies->filterFor(set, *lint.settings));
    if (long long limit = lint.policies->maxDiagnostics(-1, *lint.settings); limit > 0)
      diag::DiagnosticEngine::limitPerFile(set.diags.items(), static_cast<size_t>(limit));
  } else {
    driver::filterDiagnostics(set, {opts_.disabled, opts_.werror, false, {}});
  }
}

FolderLint& Workspace::lintFolder(const std::string& folder) {
  Folder& f = folders_[folder];
  if (f.lint && !f.lint->stale) return *f.lint;
  f.lint = std::make_unique<FolderLint>();
  FolderLint& l = *f.lint;
  // The lint policy isolint would apply to this folder, read afresh: an edit of the settings
  // or machine file counts at the next check.
  l.machine = opts_.machine;
  if (opts_.policy) {
    l.policies.emplace(*opts_.policy, opts_.disabled, opts_.werror, l.policyIo);
    l.settings = l.policies->settingsFor(folder);
    const machine::Machine* pm = l.settings ? l.policies->machineFor(*l.settings) : nullptr;
    if (pm)
      l.machine = pm;
    else
      l.settings = nullptr;
    l.policyError = l.policyErr.str();
  }
  std::vector<Source> sources = sourcesOf(folder);
  frontend::LoadOptions lo = driver::loadOptionsFor(*l.machine, 2);
  lo.compactTrees = true;
  lo.setLevel = &l.setLevel;
  lo.cancel = cancel_; // Cancelled leaves `l` stale: the next call checks the folder again
  std::vector<frontend::ProgramText> texts;
  for (auto& s : sources) {
    const bool open = docs_.count(s.uri) > 0;
    lo.record.push_back(nullptr);
    if (open) {
      auto rec = std::make_unique<frontend::IncrementalFile>();
      lo.record.back() = rec.get();
      l.records[static_cast<uint32_t>(l.uris.size())] = std::move(rec);
    }
    l.uris.push_back(s.uri);
    texts.push_back(std::move(s.text));
  }
  frontend::loadProgramTexts(std::move(texts), lo, l.set);
  l.raw = l.set.diags.items();
  // What the filter reads of a file is its suppressions: the rest of the trees is given back,
  // but for an open document's, which its record keeps in the compact form (for the edits
  // that change what the whole-file passes read). Its text there is the document's now.
  for (frontend::File& file : l.set.files) {
    frontend::File kept;
    kept.id = file.id;
    kept.path = file.path;
    kept.kind = file.kind;
    kept.suppressions = file.suppressions;
    if (auto rec = l.records.find(file.id); rec != l.records.end() && rec->second->valid()) {
      rec->second->adopt(std::move(file));
      diag::SourceFile& src = l.set.sources.file(kept.id);
      src.text = support::SourceText{};
      std::vector<uint32_t>().swap(src.lineStarts);
      src.indexed = false;
    }
    file = std::move(kept);
  }
  for (auto it = l.records.begin(); it != l.records.end();)
    it = it->second->valid() ? std::next(it) : l.records.erase(it);
  std::vector<frontend::FileFlow>().swap(l.set.flows); // for the compiler, not the filter
  l.stale = false;
  // the trees and the load's buffers are freed: the server stays at what it keeps
  support::returnFreedMemory();
  return l;
}

namespace {

/// After an update that ran the whole-file passes again (lines may have moved): the set-level
/// diagnostics, and the notes of the other files' diagnostics, follow the places they point
/// to in file `id`; its suppressions are the record's. False when one cannot be placed.
bool movePlaces(FolderLint& l, uint32_t id, const frontend::IncrementalFile& rec) {
  if (!rec.lastRanWholeFile()) return true;
  auto pointsInto = [id](const diag::Diagnostic& d) {
    if (d.loc.file == id) return true;
    for (const auto& n : d.notes)
      if (n.loc.file == id) return true;
    for (const auto& f : d.fixes)
      for (const auto& e : f.edits)
        if (e.start.file == id) return true;
    return false;
  };
  for (auto& d : l.setLevel)
    if (pointsInto(d) && !rec.remap(d)) return false;
  for (auto& d : l.raw)
    if (d.loc.file != id && pointsInto(d) && !rec.remap(d)) return false;
  for (auto& [file, items] : l.updated)
    if (file != id)
      for (auto& d : items)
        if (pointsInto(d) && !rec.remap(d)) return false;
  if (id < l.set.files.size()) l.set.files[id].suppressions = rec.file().suppressions;
  return true;
}

} // namespace

void Workspace::edited(const std::string& uri, const TextDocument::Change& change) {
  auto it = docs_.find(uri);
  if (it == docs_.end()) return;
  const std::string folder = it->second.folder;
  Folder& f = folders_[folder];
  f.stale = true; // the analysis of the features is built again when asked for
  staleFolders_.insert(folder);
  if (!f.lint || f.lint->stale) return; // checked in full anyway
  FolderLint& l = *f.lint;
  const auto file = std::find(l.uris.begin(), l.uris.end(), uri);
  const auto id = static_cast<uint32_t>(file - l.uris.begin());
  auto rec = l.records.find(id);
  // only the bytes the update may read are made contiguous (TextDocument::prefix)
  const TextDocument& doc = it->second.doc;
  auto partial = [&](frontend::IncrementalFile& r) {
    const size_t reach = r.reach(doc.size(), change.at, change.removed, change.inserted);
    return r.update(doc.prefix(reach), doc.size(), change.at, change.removed, change.inserted);
  };
  if (rec == l.records.end() || !partial(*rec->second) || !movePlaces(l, id, *rec->second)) {
    l.stale = true;
    return;
  }
  // The file's diagnostics as a full check orders them: its own, then the set's, by place.
  diag::DiagnosticList list;
  list.items() = rec->second->diagnostics();
  for (const auto& d : l.setLevel)
    if (d.loc.file == id) list.items().push_back(d);
  list.sort();
  l.updated[id] = std::move(list.items());
}

std::vector<diag::Diagnostic> Workspace::diagnostics(const std::string& uri, const FolderLint*& lint) {
  lint = nullptr;
  auto it = docs_.find(uri);
  if (it == docs_.end()) return {};
  FolderLint& l = lintFolder(it->second.folder);
  lint = &l;
  const auto file = std::find(l.uris.begin(), l.uris.end(), uri);
  if (file == l.uris.end()) return {};
  const auto id = static_cast<uint32_t>(file - l.uris.begin());
  // The policy filters the file's diagnostics as they are now (its inline suppressions, W421,
  // the limit per file).
  std::vector<diag::Diagnostic>& items = l.set.diags.items();
  items.clear();
  if (auto u = l.updated.find(id); u != l.updated.end())
    items = u->second;
  else
    for (const auto& d : l.raw)
      if (d.loc.file == id) items.push_back(d);
  applyPolicy(l, l.set);
  std::vector<diag::Diagnostic> out;
  for (auto& d : items)
    if (d.loc.file == id) out.push_back(std::move(d));
  items.clear();
  return out;
}

LineText Workspace::lineText(const FolderLint& lint) {
  return [this, &lint](uint32_t file, uint32_t line) -> std::string_view {
    if (file >= lint.uris.size()) return {};
    if (const TextDocument* doc = document(lint.uris[file])) return doc->line(line - 1);
    return lint.set.sources.lineText(file, line);
  };
}

} // namespace iso::lsp
