//! @file Workspace.cpp
//! @brief Open documents, folders as program sets, analyses on demand.
#include "lsp/Workspace.h"

#include <algorithm>
#include <filesystem>
#include <optional>
#include <sstream>

#include "driver/Format.h"
#include "driver/Lint.h"
#include "driver/Policy.h"
#include "driver/Settings.h"
#include "frontend/ProgramSet.h"
#include "lang/Axes.h"
#include "lsp/Uri.h"
#include "support/File.h"

namespace iso::lsp {

namespace fs = std::filesystem;

std::optional<uint32_t> Analysis::fileOf(const std::string& uri) const {
  for (size_t i = 0; i < uris.size(); ++i)
    if (uris[i] == uri) return static_cast<uint32_t>(i);
  return std::nullopt;
}

Range rangeIn(const LineText& text, uint32_t file, uint32_t line, uint32_t col, uint32_t endLine, uint32_t endCol) {
  if (line == 0) return {};
  auto at = [&](uint32_t l, uint32_t c) { return Position{l - 1, utf16Column(text(file, l), c > 0 ? c - 1 : 0)}; };
  Position start = at(line, col);
  Position end = endLine == 0 ? start : at(endLine, endCol);
  if (end.line < start.line || (end.line == start.line && end.character < start.character)) end = start;
  return {start, end};
}

Range Analysis::range(uint32_t file, uint32_t line, uint32_t col, uint32_t endLine, uint32_t endCol) const {
  if (line == 0 || file >= set.sources.size()) return {};
  return rangeIn([this](uint32_t f, uint32_t l) { return set.sources.lineText(f, l); }, file, line, col, endLine,
                 endCol);
}

Range Analysis::range(const diag::Loc& l, uint32_t length) const {
  return range(l.file, l.line, l.col, l.line, l.col + length);
}

diag::Loc Analysis::loc(uint32_t file, Position p) const {
  std::string_view line = set.sources.lineText(file, p.line + 1);
  return {file, p.line + 1, static_cast<uint32_t>(byteColumn(line, p.character) + 1)};
}

namespace {
std::string mib(size_t bytes) {
  return bytes % (size_t{1} << 20) == 0 ? std::to_string(bytes >> 20) + " MiB" : std::to_string(bytes) + " bytes";
}
} // namespace

size_t Workspace::heldBytes(const std::string& except) const {
  size_t n = 0;
  for (const auto& [uri, o] : docs_)
    if (uri != except) n += uri.size() + o.doc.size();
  return n;
}

std::optional<std::string> Workspace::admitsSize(const std::string& uri, size_t newSize) const {
  const Limits& l = opts_.limits;
  if (newSize > l.maxDocumentBytes)
    return "its text of " + std::to_string(newSize) + " bytes is over the limit of " + mib(l.maxDocumentBytes) +
           " for one document";
  if (!docs_.count(uri) && docs_.size() >= l.maxDocuments)
    return "the limit of " + std::to_string(l.maxDocuments) + " open documents is reached";
  if (heldBytes(uri) + uri.size() + newSize > l.maxTotalBytes)
    return "the open documents would hold more than the limit of " + mib(l.maxTotalBytes) + " in all";
  return std::nullopt;
}

std::optional<std::string> Workspace::open(const std::string& uri, std::string text, int64_t version) {
  if (auto refused = admitsSize(uri, text.size())) {
    close(uri); // the editor no longer shows what was open under this URI
    return refused;
  }
  Open o;
  o.doc = TextDocument(std::move(text), version);
  if (auto p = uriToPath(uri)) {
    o.path = fs::path(*p).lexically_normal().string();
    o.folder = fs::path(o.path).parent_path().string();
  } else {
    o.folder = uri; // not a file: a set of its own
  }
  std::string folder = o.folder;
  docs_[uri] = std::move(o);
  invalidate(folder);
  return std::nullopt;
}

TextDocument* Workspace::document(const std::string& uri) {
  auto it = docs_.find(uri);
  return it == docs_.end() ? nullptr : &it->second.doc;
}

void Workspace::invalidate(const std::string& folder) {
  Folder& f = folders_[folder];
  f.stale = true;
  if (f.lint) f.lint->stale = true;
  staleFolders_.insert(folder);
}

void Workspace::touch(const std::string& uri) {
  auto it = docs_.find(uri);
  if (it != docs_.end()) invalidate(it->second.folder);
}

void Workspace::close(const std::string& uri) {
  auto it = docs_.find(uri);
  if (it == docs_.end()) return;
  std::string folder = it->second.folder;
  docs_.erase(it);
  closed_.insert(uri);
  if (documentsIn(folder).empty()) {
    folders_.erase(folder);
    staleFolders_.erase(folder);
  } else {
    invalidate(folder);
  }
}

std::vector<std::string> Workspace::takeStaleFolders() {
  std::vector<std::string> out(staleFolders_.begin(), staleFolders_.end());
  staleFolders_.clear();
  return out;
}

std::vector<std::string> Workspace::takeClosed() {
  std::vector<std::string> out(closed_.begin(), closed_.end());
  closed_.clear();
  // A document closed and opened again keeps its diagnostics.
  out.erase(std::remove_if(out.begin(), out.end(), [&](const std::string& u) { return docs_.count(u) > 0; }),
            out.end());
  return out;
}

std::vector<std::string> Workspace::documentsIn(const std::string& folder) const {
  std::vector<std::string> out;
  for (const auto& [uri, o] : docs_)
    if (o.folder == folder) out.push_back(uri);
  return out;
}

const Analysis* Workspace::analysis(const std::string& uri) {
  auto it = docs_.find(uri);
  if (it == docs_.end()) return nullptr;
  return analyseFolder(it->second.folder);
}

support::Expected<std::vector<diag::ByteEdit>> Workspace::format(const std::string& uri, driver::LineSpan lines) {
  auto it = docs_.find(uri);
  if (it == docs_.end()) return std::vector<diag::ByteEdit>{};
  const Open& o = it->second;
  // A document that is no file (untitled) has no folder to find settings in: --config, else none.
  if (!opts_.policy || (o.path.empty() && opts_.policy->config.empty()))
    return driver::formatBuffer(o.doc.text(), driver::Settings{}, *opts_.machine, lines).edits;
  // Read afresh, as for an analysis: an edit of the settings or machine file counts now.
  std::ostringstream policyOut, policyErr;
  driver::Io policyIo{policyOut, policyErr, false, false};
  driver::LintPolicies policies(*opts_.policy, opts_.disabled, opts_.werror, policyIo);
  auto r = driver::formatBuffer(o.doc.text(), o.path, policies, lines);
  if (!r) {
    std::string why = policyErr.str();
    why = why.substr(0, why.find_last_not_of('\n') + 1);
    return support::Error{o.path, why.empty() ? r.error().message : why};
  }
  return std::move(r->edits);
}

std::vector<std::string> Workspace::folders() const {
  std::vector<std::string> out;
  for (const auto& [folder, f] : folders_)
    out.push_back(folder);
  return out;
}

std::vector<Workspace::Source> Workspace::sourcesOf(const std::string& folder, const FolderLint* read) const {
  std::vector<Source> sources;
  std::set<std::string> openPaths;
  for (const auto& [uri, o] : docs_) {
    if (o.folder != folder) continue;
    sources.push_back({{o.path.empty() ? uri : o.path, o.doc.text(), true}, uri});
    if (!o.path.empty()) openPaths.insert(o.path);
  }
  std::error_code ec;
  if (!openPaths.empty() && fs::is_directory(folder, ec)) {
    for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
      std::error_code ec2;
      if (!it->is_regular_file(ec2) || !frontend::isProgramFileName(it->path().filename().string())) continue;
      std::string path = it->path().lexically_normal().string();
      if (openPaths.count(path)) continue; // the buffer wins over the disk
      const std::string uri = pathToUri(path);
      if (read) // the check read it: the same text
        if (auto at = std::find(read->uris.begin(), read->uris.end(), uri); at != read->uris.end()) {
          const auto id = static_cast<uint32_t>(at - read->uris.begin());
          if (id < read->set.sources.size() && !read->set.sources.file(id).text.empty()) {
            sources.push_back({{path, std::string(read->set.sources.file(id).text.view()), false}, uri});
            continue;
          }
        }
      auto text = support::readFile(path);
      if (!text) continue; // unreadable siblings only matter if called
      sources.push_back({{path, std::move(*text), false}, uri});
    }
  }
  std::sort(sources.begin(), sources.end(), [](const Source& a, const Source& b) { return a.text.path < b.text.path; });
  return sources;
}

const Analysis* Workspace::analyseFolder(const std::string& folder) {
  Folder& f = folders_[folder];
  if (!f.stale && f.analysis) return f.analysis.get();
  // The policy of the folder's check (read afresh when the check is stale), and its texts.
  FolderLint& lint = lintFolder(folder);
  std::vector<Source> sources = sourcesOf(folder, &lint);
  const machine::Machine* m = lint.machine;
  auto a = std::make_unique<Analysis>();
  a->policyError = lint.policyError;
  a->dialect = m->dialect;
  a->axisLetters = std::string(lang::kDefaultAxisLetters);
  for (const auto& axis : m->axes)
    if (a->axisLetters.find(axis.letter) == std::string::npos) a->axisLetters.push_back(axis.letter);
  if (a->dialect == machine::Dialect::Z32) {
    a->userParams = m->parameters;
    a->specialM = m->specialM;
    a->machineName = m->name;
  }
  std::vector<frontend::ProgramText> texts;
  for (auto& s : sources) {
    a->uris.push_back(s.uri);
    texts.push_back(std::move(s.text));
  }
  frontend::loadProgramTexts(std::move(texts), driver::loadOptionsFor(*m, 1), a->set);
  applyPolicy(lint, a->set);
  f.analysis = std::move(a);
  f.stale = false;
  return f.analysis.get();
}

} // namespace iso::lsp
