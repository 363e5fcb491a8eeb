//! @file Folding.cpp
//! @brief The outline of programs: textDocument/foldingRange (the blocks of a program:
//!        IF/ELSE/ENDIF, WHEN/CANCEL, a subprogram's body, and runs of comment lines, from the
//!        statements the analysis holds) and workspace/symbol (the document symbols of every
//!        file of the open program sets).

#include <set>
#include <string_view>
#include <tuple>
#include <vector>

#include "support/CaseFold.h"

#include "lsp/Features.h"

namespace iso::lsp {

using nlohmann::json;

namespace {

/// A block opened and not yet closed: its kind and its first (1-based) line.
struct OpenBlock {
  frontend::StmtKind kind = frontend::StmtKind::If;
  uint32_t line = 0;
};

/// A range from 1-based line `from` to `to` (both shown folded into the first): none when it
/// would hold a single line.
void addFold(json& out, uint32_t from, uint32_t to, const char* kind) {
  if (to <= from) return;
  json r = {{"startLine", from - 1}, {"endLine", to - 1}};
  if (kind) r["kind"] = kind;
  out.push_back(std::move(r));
}

bool commentLine(std::string_view line) {
  size_t i = line.find_first_not_of(" \t");
  return i != std::string_view::npos && line[i] == ';';
}

} // namespace

json foldingRanges(const Analysis& a, uint32_t file, const TextDocument& doc) {
  using frontend::StmtKind;
  json out = json::array();
  const auto& f = a.set.files[file];
  std::vector<OpenBlock> open;
  uint32_t procLine = 0, lastLine = 0;
  for (const auto& s : f.stmts) {
    // A line with a syntax error keeps the role its keyword announced.
    const StmtKind k = s.kind == StmtKind::Invalid ? s.recoverAs : s.kind;
    const bool longForm = s.inner < 0 && s.part != frontend::StmtPart::Jump;
    if (k == StmtKind::If && longForm) {
      open.push_back({StmtKind::If, s.line});
    } else if (k == StmtKind::When && longForm) {
      open.push_back({StmtKind::When, s.line});
    } else if (k == StmtKind::Else && !open.empty() && open.back().kind == StmtKind::If) {
      addFold(out, open.back().line, s.line - 1, nullptr); // IF .. the line before ELSE
      open.back().line = s.line;
    } else if ((k == StmtKind::EndIf || k == StmtKind::Cancel) && !open.empty() &&
               open.back().kind == (k == StmtKind::EndIf ? StmtKind::If : StmtKind::When)) {
      addFold(out, open.back().line, s.line - 1, nullptr); // ENDIF and CANCEL stay visible
      open.pop_back();
    } else if (k == StmtKind::Proc && procLine == 0) {
      procLine = s.line;
    }
    if (s.kind != StmtKind::Empty) lastLine = s.lastLine;
  }
  if (procLine != 0) addFold(out, procLine, lastLine, nullptr);
  // Runs of two or more comment lines, from the buffer (comments are not statements).
  for (uint32_t l = 0, n = doc.lineCount(); l < n;) {
    if (!commentLine(doc.line(l))) {
      ++l;
      continue;
    }
    uint32_t end = l;
    while (end + 1 < n && commentLine(doc.line(end + 1)))
      ++end;
    addFold(out, l + 1, end + 1, "comment");
    l = end + 1;
  }
  return out;
}

json workspaceSymbols(const std::vector<const Analysis*>& analyses, std::string_view query, size_t limit) {
  json out = json::array();
  const std::string want = support::upperCopy(query);
  std::set<std::tuple<std::string, std::string, uint32_t>> seen; // a file in two sets: once
  for (const Analysis* a : analyses) {
    for (uint32_t file = 0; file < a->set.files.size() && file < a->uris.size(); ++file) {
      for (auto& sym : documentSymbols(*a, file)) {
        const std::string name = sym["name"].get<std::string>();
        if (support::upperCopy(name).find(want) == std::string::npos) continue;
        const uint32_t line = sym["selectionRange"]["start"]["line"].get<uint32_t>();
        if (!seen.insert({a->uris[file], name, line}).second) continue;
        if (out.size() >= limit) return out;
        out.push_back({{"name", name},
                       {"kind", sym["kind"]},
                       {"containerName", sym["detail"]},
                       {"location", {{"uri", a->uris[file]}, {"range", sym["selectionRange"]}}}});
      }
    }
  }
  return out;
}

} // namespace iso::lsp
