//! @file TestUtil.h
//! @brief Shared helpers of the unit tests: lint in-memory sources (one file or a program set
//!        written to a fresh temporary directory), query diagnostics, fold constant expressions.
#pragma once

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <deque>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <doctest/doctest.h>

#include "compiler/Compiler.h"
#include "diag/Diagnostic.h"
#include "diag/Render.h"
#include "frontend/Lexer.h"
#include "frontend/ProgramSet.h"
#include "frontend/Sema.h"
#include "image/ImageWriter.h"
#include "machine/Machine.h"
#include "support/CaseFold.h"

namespace iso::test {

using Diags = std::vector<diag::Diagnostic>;

/// The built-in machine of SPEC §5.1 (one instance for all tests).
inline const machine::Machine& builtin() {
  static const machine::Machine m = machine::builtinMachine();
  return m;
}

/// Everything a set's diagnostics say (messages, notes, fixes), for comparing two loads.
inline std::string diagnosticsJson(const frontend::ProgramSet& set) {
  return diag::renderJson(set.diags.items(), set.sources, set.files.size()).dump();
}

/// The same diagnostics in the same order: codes, places, messages, notes and fixes.
inline bool sameDiagnostics(const Diags& a, const Diags& b) {
  auto sameLoc = [](const diag::Loc& x, const diag::Loc& y) {
    return x.file == y.file && x.line == y.line && x.col == y.col;
  };
  auto sameNote = [&](const diag::Note& x, const diag::Note& y) {
    return sameLoc(x.loc, y.loc) && x.message == y.message;
  };
  auto sameEdit = [&](const diag::Edit& x, const diag::Edit& y) {
    return sameLoc(x.start, y.start) && x.endLine == y.endLine && x.endCol == y.endCol &&
           x.replacement == y.replacement;
  };
  auto sameFix = [&](const diag::Fix& x, const diag::Fix& y) {
    return x.description == y.description &&
           std::equal(x.edits.begin(), x.edits.end(), y.edits.begin(), y.edits.end(), sameEdit);
  };
  auto same = [&](const diag::Diagnostic& x, const diag::Diagnostic& y) {
    return x.code == y.code && x.severity == y.severity && sameLoc(x.loc, y.loc) && x.endLine == y.endLine &&
           x.endCol == y.endCol && x.message == y.message &&
           std::equal(x.notes.begin(), x.notes.end(), y.notes.begin(), y.notes.end(), sameNote) &&
           std::equal(x.fixes.begin(), x.fixes.end(), y.fixes.begin(), y.fixes.end(), sameFix);
  };
  return std::equal(a.begin(), a.end(), b.begin(), b.end(), same);
}

/// isolint checks each line as it parses it and keeps a compact tree (LoadOptions::
/// compactTrees). Every test that lints a source through this file also loads it that way and
/// checks that the diagnostics and the control flow facts are the same as the full load's.
/// isocc compiles the compact load, each line parsed again (CompileOptions::reparse): the image
/// must be the full tree's, byte for byte (or both fail alike). `lo`: how both were loaded.
inline void checkCompactCompile(const frontend::ProgramSet& full, const frontend::ProgramSet& compact,
                                const frontend::LoadOptions& lo) {
  if (full.diags.hasErrors()) return;
  compiler::CompileOptions co;
  co.dialect = lo.dialect;
  co.specialM = lo.machine ? &lo.machine->specialM : nullptr;
  co.parameters = lo.machine ? &lo.machine->parameters : nullptr;
  image::Image a, b;
  compiler::CompileError ea, eb;
  const bool okA = compiler::compileProgramSet(full, co, a, ea);
  const frontend::LexOptions lex = frontend::lexOptionsFor(lo);
  co.reparse = &lex;
  const bool okB = compiler::compileProgramSet(compact, co, b, eb);
  REQUIRE(okA == okB);
  CHECK(ea.message == eb.message);
  if (okA) CHECK_MESSAGE(image::writeImage(a) == image::writeImage(b), "the compact load compiles to another image");
}

inline void checkCompactLoad(const frontend::ProgramSet& full, const frontend::ProgramSet& compact,
                             const frontend::LoadOptions* lo = nullptr) {
  if (lo) checkCompactCompile(full, compact, *lo);
  // Field by field first: the JSON (which also holds the source lines) is rendered only when
  // they differ, as rendering it for every load took most of the corpus tests' time.
  CHECK_MESSAGE(
      (sameDiagnostics(compact.diags.items(), full.diags.items()) || diagnosticsJson(compact) == diagnosticsJson(full)),
      "isolint's compact load differs");
  REQUIRE(compact.flows.size() == full.flows.size());
  for (size_t i = 0; i < full.flows.size(); ++i) {
    CHECK(compact.flows[i].match == full.flows[i].match);
    CHECK(compact.flows[i].reachable == full.flows[i].reachable);
    CHECK(compact.flows[i].endReachable == full.flows[i].endReachable);
    CHECK(compact.files[i].kind == full.files[i].kind);
    CHECK(compact.files[i].procName == full.files[i].procName);
  }
}

/// One in-memory source loaded as a set of one file, with the full tree or, as isolint loads,
/// with a compact one. The set owns the text: the AST's string views live as long as it does.
inline std::unique_ptr<frontend::ProgramSet> loadSource(const std::string& text, const std::string& path,
                                                        const machine::Machine& m,
                                                        std::optional<machine::Dialect> dialect, bool compact) {
  auto set = std::make_unique<frontend::ProgramSet>();
  frontend::LoadOptions lo;
  lo.machine = &m;
  lo.dialect = dialect.value_or(m.dialect);
  lo.compactTrees = compact;
  frontend::loadSingleSource(path, text, lo, *set);
  return set;
}

/// isolint splits a large file between two threads (frontend::SplitOptions). Every test that
/// lints a source through this file also splits it at its line starts (at most `maxSplits` of
/// them, spread over the file), the second part starting once from a wrong guess of the modal
/// state (the state after the first statement: checked again until it agrees) and once from the
/// true one; with `inParts`, also in 3 and in 5 parts from the wrong guess. Each must give what
/// one pass gives.
inline void checkSplitLoads(const frontend::ProgramSet& full, const std::string& text, const std::string& path,
                            const machine::Machine& m, std::optional<machine::Dialect> dialect, size_t maxSplits = 24,
                            bool inParts = true) {
  auto checkSplit = [&](const frontend::SplitOptions& splitting) {
    frontend::ProgramSet split;
    frontend::LoadOptions lo;
    lo.machine = &m;
    lo.dialect = dialect.value_or(m.dialect);
    lo.compactTrees = true;
    lo.jobs = 2;
    lo.splitting = splitting;
    frontend::loadSingleSource(path, text, lo, split);
    INFO("split at offset ", splitting.at, " in ", splitting.parts, " parts (0: 2), guess after ", splitting.guessAfter,
         " statements");
    checkCompactLoad(full, split, &lo);
  };
  std::vector<uint32_t> starts;
  for (size_t p = text.find('\n'); p != std::string::npos && p + 1 < text.size(); p = text.find('\n', p + 1))
    starts.push_back(static_cast<uint32_t>(p + 1));
  const size_t step = starts.size() <= maxSplits ? 1 : starts.size() / maxSplits;
  for (size_t k = 0; k < starts.size(); k += step)
    for (size_t guessAfter : {size_t{1}, SIZE_MAX})
      checkSplit({.minBytes = 0, .at = starts[k], .guessAfter = guessAfter});
  if (inParts)
    for (size_t parts : {size_t{3}, size_t{5}})
      checkSplit({.minBytes = 0, .parts = parts, .guessAfter = 1});
}

/// Parses and checks one in-memory source as a set of one file (the full tree; the compact
/// load and the split ones are checked to agree).
inline std::unique_ptr<frontend::ProgramSet> loadText(const std::string& text, const std::string& path = "t.mpf",
                                                      const machine::Machine& m = builtin(),
                                                      std::optional<machine::Dialect> dialect = std::nullopt) {
  auto set = loadSource(text, path, m, dialect, false);
  frontend::LoadOptions lo;
  lo.machine = &m;
  lo.dialect = dialect.value_or(m.dialect);
  checkCompactLoad(*set, *loadSource(text, path, m, dialect, true), &lo);
  checkSplitLoads(*set, text, path, m, dialect);
  return set;
}

/// The program files (.mpf, .spf, .nc in any case) under `dir`, recursively, sorted; none when
/// `dir` is not there.
inline std::vector<std::filesystem::path> programsUnder(const std::filesystem::path& dir) {
  namespace fs = std::filesystem;
  std::vector<fs::path> out;
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return out;
  for (auto it = fs::recursive_directory_iterator(dir, ec); !ec && it != fs::recursive_directory_iterator();
       it.increment(ec)) {
    if (!it->is_regular_file(ec)) continue;
    const std::string ext = iso::support::lowerCopy(it->path().extension().string());
    if (ext == ".mpf" || ext == ".spf" || ext == ".nc") out.push_back(it->path());
  }
  std::sort(out.begin(), out.end());
  return out;
}

/// The logical lines of one source as the lexer produces them (tokens end with Tok::End).
/// The struct owns the text that the tokens' string views point into: keep it alive.
struct LexResult {
  std::string text;
  std::deque<std::string> owned;
  std::vector<frontend::Suppression> suppressions;
  diag::DiagnosticList diags;
  std::vector<frontend::LogicalLine> lines;
  /// Tokens of logical line i without the final End token.
  std::vector<frontend::Token> tokens(size_t i) const {
    std::vector<frontend::Token> t = lines.at(i).tokens;
    if (!t.empty() && t.back().kind == frontend::Tok::End) t.pop_back();
    return t;
  }
};

inline std::unique_ptr<LexResult> lexText(std::string text, machine::Dialect dialect = machine::Dialect::Sidac) {
  auto r = std::make_unique<LexResult>();
  r->text = std::move(text);
  frontend::LexOptions lo;
  lo.dialect = dialect;
  frontend::Lexer lexer(r->text, 0, lo, r->diags, r->suppressions, r->owned);
  frontend::LogicalLine line;
  while (lexer.next(line))
    r->lines.push_back(line);
  return r;
}

/// Every diagnostic of one in-memory source (sorted by line, column, code).
inline Diags lintText(const std::string& text, const std::string& path = "t.mpf", const machine::Machine& m = builtin(),
                      std::optional<machine::Dialect> dialect = std::nullopt) {
  return loadText(text, path, m, dialect)->diags.items();
}

inline Diags lintZ32(const std::string& text, const std::string& path = "t.mpf") {
  return lintText(text, path, builtin(), machine::Dialect::Z32);
}

/// The bytes of the file `path` ("" when it cannot be read).
inline std::string readFileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// A fresh directory under the system temp directory, removed with its content at scope exit.
class TempDir {
public:
  TempDir() {
    std::string tmpl = (std::filesystem::temp_directory_path() / "iso_unit_XXXXXX").string();
    if (char* p = ::mkdtemp(tmpl.data())) path_ = p;
  }
  ~TempDir() {
    std::error_code ec;
    if (!path_.empty()) std::filesystem::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::string& path() const { return path_; }
  std::string write(const std::string& name, const std::string& text) const {
    std::string p = path_ + "/" + name;
    std::ofstream out(p, std::ios::binary);
    out << text;
    return p;
  }

private:
  std::string path_;
};

/// A program set loaded from files, with every diagnostic.
struct SetResult {
  std::unique_ptr<frontend::ProgramSet> set;
  Diags diags;
  bool loaded = false;
  /// File name (without directory) of the file a diagnostic or note points into.
  std::string fileName(uint32_t fileId) const {
    return std::filesystem::path(set->sources.path(fileId)).filename().string();
  }
};

/// Writes the files into a fresh temporary directory and loads the directory as a program set
/// (every file reported). Files are read before the directory is removed.
inline SetResult lintFiles(const std::vector<std::pair<std::string, std::string>>& files,
                           const machine::Machine& m = builtin(),
                           std::optional<machine::Dialect> dialect = std::nullopt) {
  TempDir dir;
  for (const auto& [name, text] : files)
    dir.write(name, text);
  SetResult r;
  r.set = std::make_unique<frontend::ProgramSet>();
  frontend::LoadOptions lo;
  lo.machine = &m;
  lo.dialect = dialect.value_or(m.dialect);
  frontend::SetError err;
  r.loaded = frontend::loadProgramSet({dir.path()}, lo, *r.set, err);
  r.diags = r.set->diags.items();
  frontend::ProgramSet compact;
  lo.compactTrees = true;
  if (frontend::loadProgramSet({dir.path()}, lo, compact, err) == r.loaded)
    checkCompactLoad(*r.set, compact, &lo);
  else
    FAIL("the compact load read the files differently");
  return r;
}

/// True when a diagnostic with this code is at line (0 = any) and column (0 = any).
inline bool hasCode(const Diags& diags, const std::string& code, uint32_t line = 0, uint32_t col = 0) {
  for (const auto& d : diags)
    if (code == diag::info(d.code).code && (line == 0 || d.loc.line == line) && (col == 0 || d.loc.col == col))
      return true;
  return false;
}

/// The first diagnostic with this code, or nullptr.
inline const diag::Diagnostic* find(const Diags& diags, const std::string& code) {
  for (const auto& d : diags)
    if (code == diag::info(d.code).code) return &d;
  return nullptr;
}

inline size_t count(const Diags& diags, const std::string& code) {
  size_t n = 0;
  for (const auto& d : diags)
    if (code == diag::info(d.code).code) ++n;
  return n;
}

inline size_t errorCount(const Diags& diags) {
  size_t n = 0;
  for (const auto& d : diags)
    if (d.severity == diag::Severity::Error) ++n;
  return n;
}

/// One line per diagnostic ("3:5 E205 message"), for failure messages (doctest INFO).
inline std::string dump(const Diags& diags) {
  std::ostringstream os;
  for (const auto& d : diags) {
    os << d.loc.line << ':' << d.loc.col << ' ' << diag::info(d.code).code << ' ' << d.message << '\n';
    for (const auto& n : d.notes)
      os << "    note " << n.loc.line << ':' << n.loc.col << ' ' << n.message << '\n';
  }
  return os.str();
}

/// Folds `<expr>` with frontend::constValue after parsing `R1 = <expr>`; nullopt if the line
/// does not parse into one assignment or the value does not fold.
inline std::optional<double> evalConst(const std::string& exprText) {
  auto set = loadText("R1 = " + exprText + "\nM30\n");
  const frontend::File& f = set->files.at(0);
  if (f.stmts.empty() || f.stmts[0].kind != frontend::StmtKind::Block || f.stmts[0].itemCount != 1) return std::nullopt;
  const frontend::Item& it = f.items[f.stmts[0].firstItem];
  if (it.kind != frontend::ItemKind::AssignR) return std::nullopt;
  return frontend::constValue(f, it.value);
}

} // namespace iso::test
