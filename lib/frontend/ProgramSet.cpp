//! @file ProgramSet.cpp
//! @brief Program set loading, parallel parsing and checking.
#include "frontend/ProgramSet.h"

#include <algorithm>
#include <atomic>
#include <deque>
#include <filesystem>
#include <fstream>
#include <thread>
#include <unordered_map>
#include <unordered_set>

#include "frontend/Lexer.h"
#include "frontend/Parser.h"
#include "lang/Axes.h"
#include "support/CaseFold.h"
#include "support/File.h"
#include "support/SourceText.h"

namespace iso::frontend {

namespace fs = std::filesystem;

bool isProgramFileName(const std::string& name) {
  if (name.size() < 4) return false;
  std::string ext = support::upperCopy(name.substr(name.size() - 4));
  return ext == ".MPF" || ext == ".SPF";
}

/// What makes a file binary: an image's magic, or NUL bytes near its start (None: text).
enum class Binary : uint8_t { None, Image, NulBytes };
constexpr size_t kBinaryProbeBytes = 8192;
constexpr size_t kBinaryMinNuls = 8;

static Binary binaryKind(std::string_view text, std::string_view imageMagic) {
  if (!imageMagic.empty() && text.substr(0, imageMagic.size()) == imageMagic) return Binary::Image;
  // Binary: NUL bytes are at least 8 and 1/64 of the first 8 KiB. A program with a stray NUL
  // or a few is text: each is E100 at its column (SPEC §2), and NULs in comments are allowed.
  const std::string_view probe = text.substr(0, kBinaryProbeBytes);
  const size_t nuls = static_cast<size_t>(std::count(probe.begin(), probe.end(), '\0'));
  if (nuls >= kBinaryMinNuls && nuls * 64 >= probe.size()) return Binary::NulBytes;
  return Binary::None;
}

static LexOptions lexOptionsFor(const LoadOptions& opts) {
  LexOptions lo;
  lo.dialect = opts.dialect;
  std::string letters(lang::kDefaultAxisLetters);
  if (opts.machine)
    for (const auto& a : opts.machine->axes)
      if (letters.find(a.letter) == std::string::npos) letters.push_back(a.letter);
  lo.axisLetters = letters;
  if (opts.machine && opts.dialect == machine::Dialect::Z32) lo.userParams = opts.machine->parameters;
  return lo;
}

/// The bytes of a sibling read to find its PROC line (more only when its first line is later).
constexpr size_t kHeaderBytes = 64 * 1024;

/// Parses and checks files [first, set.files.size()) in parallel (no set-level checks).
static void processFiles(ProgramSet& set, const LoadOptions& opts, size_t first) {
  LexOptions lo = lexOptionsFor(opts);
  SemaOptions so{opts.machine, opts.dialect};
  size_t n = set.files.size() - first;
  std::vector<diag::DiagnosticList> perFile(n);
  set.flows.resize(set.files.size());
  auto work = [&](size_t k) {
    const size_t i = first + k;
    File& f = set.files[i];
    const diag::SourceFile& src = set.sources.file(static_cast<uint32_t>(i));
    const Binary binary = binaryKind(src.text, opts.imageMagic);
    if (binary != Binary::None) {
      if (binary == Binary::Image)
        perFile[k].report(diag::Msg::BinaryImage, diag::Loc{f.id, 0, 0}, 1);
      else
        perFile[k].report(diag::Msg::BinaryNulBytes, diag::Loc{f.id, 0, 0}, 1, kBinaryProbeBytes / 1024);
      f.kind = UnitKind::Main;
      f.binary = true;
      return;
    }
    if (opts.compactTrees) {
      // one file alone in this round: the threads go to its parts
      set.flows[i] = parseAndCheckFile(f, src.text, lo, so, perFile[k], n == 1 ? opts.jobs : 1, opts.splitting);
      return;
    }
    parseFile(f, src.text, lo, perFile[k]);
    f.kind = classifyUnit(f);
    set.flows[i] = checkFile(f, so, perFile[k]);
  };
  unsigned jobs = std::max(1u, std::min<unsigned>(opts.jobs, static_cast<unsigned>(n)));
  if (jobs <= 1) {
    for (size_t k = 0; k < n; ++k)
      work(k);
  } else {
    std::atomic<size_t> next{0};
    std::vector<std::thread> pool;
    for (unsigned t = 0; t < jobs; ++t)
      pool.emplace_back([&] {
        for (size_t k = next++; k < n; k = next++)
          work(k);
      });
    for (auto& th : pool)
      th.join();
  }
  for (auto& d : perFile)
    set.diags.append(std::move(d));
}

/// The set-level checks, then diagnostics in their order.
static void finishSet(ProgramSet& set, const LoadOptions& opts) {
  SemaOptions so{opts.machine, opts.dialect};
  checkSet(set.files, so, set.diags);
  set.diags.sort();
}

static void processFiles(ProgramSet& set, const LoadOptions& opts) {
  processFiles(set, opts, 0);
  finishSet(set, opts);
}

/// The upper-case name after PROC on the first statement of `text` in `proc` ("" when the
/// file is no subprogram, or its header is one the parser rejects). Only the first logical
/// line is parsed. False when `text` is a prefix that ends before that line does.
static bool headerProcName(std::string_view text, bool whole, const LoadOptions& opts, std::string& proc) {
  proc.clear();
  LexOptions lo = lexOptionsFor(opts);
  diag::DiagnosticList ignored;
  std::vector<Suppression> sup;
  std::deque<std::string> owned;
  Lexer lexer(text, 0, lo, ignored, sup, owned);
  LogicalLine line;
  uint32_t last = 0;
  while (lexer.next(line)) {
    if (line.tokens.size() > 1) {
      last = line.lastLine;
      break;
    }
  }
  size_t end = 0;
  for (uint32_t l = 0; l < last && end != std::string_view::npos; ++l) {
    end = text.find('\n', end);
    if (end != std::string_view::npos) ++end;
  }
  if (!whole && (last == 0 || end == std::string_view::npos)) return false; // the prefix is too short
  if (last == 0) return true;
  File f;
  diag::DiagnosticList diags;
  parseFile(f, text.substr(0, end == std::string_view::npos ? text.size() : end), lo, diags);
  for (const Stmt& s : f.stmts) {
    if (s.kind == StmtKind::Empty) continue;
    if (s.kind == StmtKind::Proc) proc = support::upperCopy(f.nameOf(s).text);
    break;
  }
  return true;
}

/// The subprogram names `f` calls (calls, and z32 special M of the machine).
static void calledNames(const File& f, const LoadOptions& opts, std::vector<std::string>& out) {
  const SemaOptions so{opts.machine, opts.dialect};
  forEachCall(
      f, so.specialMap(), [&](const Stmt& s) { out.push_back(support::upperCopy(f.nameOf(s).text)); },
      [&](const Item&, const std::string& name) { out.push_back(support::upperCopy(name)); });
}

bool listProgramFiles(const std::string& dir, std::vector<std::string>& out) {
  std::error_code ec;
  fs::directory_iterator it(dir, ec);
  if (ec) return false;
  for (; it != fs::directory_iterator(); it.increment(ec)) {
    if (ec) return false;
    std::error_code ec2;
    if (!it->is_regular_file(ec2)) continue;
    std::string name = it->path().filename().string();
    if (isProgramFileName(name)) out.push_back(dir == "." ? name : it->path().string());
  }
  std::sort(out.begin(), out.end());
  return true;
}

/// A sibling not loaded yet (isolint): its path and the upper-case PROC name of its header.
struct LazySibling {
  std::string path;
  std::string proc;
  bool loaded = false;
};

/// The siblings of `paths` that are subprograms, with their PROC names. Only the start of each
/// file is read (all of it only when its first statement lies further on).
static std::vector<LazySibling> readSiblingHeaders(const std::vector<std::string>& paths, const LoadOptions& opts) {
  std::vector<LazySibling> lazy;
  for (const auto& path : paths) {
    bool whole = false;
    std::string proc;
    auto head = support::readFilePrefix(path, kHeaderBytes, whole);
    if (!head || binaryKind(*head, opts.imageMagic) != Binary::None) continue;
    if (!headerProcName(*head, whole, opts, proc)) {
      auto all = support::readFile(path);
      if (!all || !headerProcName(*all, true, opts, proc)) continue;
    }
    if (!proc.empty()) lazy.push_back({path, std::move(proc)});
  }
  return lazy;
}

/// isolint: loads the siblings (`siblings`, paths not read yet) that the loaded files call (or
/// whose name they define too), then what those call, until nothing more is needed. The
/// siblings' headers are read the first time a name is wanted: a main program that calls
/// nothing reads no other file. `addFile(path, text)` adds one.
template <class AddFile>
static void loadCalledSiblings(ProgramSet& set, const LoadOptions& opts, const std::vector<std::string>& siblings,
                               AddFile&& addFile) {
  std::vector<LazySibling> lazy;
  bool headersRead = false;
  for (size_t done = 0; !siblings.empty();) {
    std::unordered_set<std::string> wanted;
    for (size_t i = done; i < set.files.size(); ++i) {
      std::vector<std::string> names;
      calledNames(set.files[i], opts, names);
      wanted.insert(names.begin(), names.end());
      if (!set.files[i].procName.empty()) wanted.insert(support::upperCopy(set.files[i].procName));
    }
    done = set.files.size();
    if (wanted.empty()) break;
    if (!headersRead) {
      lazy = readSiblingHeaders(siblings, opts);
      headersRead = true;
    }
    for (auto& l : lazy) {
      if (l.loaded || !wanted.count(l.proc)) continue;
      if (auto text = support::readSource(l.path)) addFile(l.path, std::move(*text));
      l.loaded = true;
    }
    if (set.files.size() == done) break;
    processFiles(set, opts, done);
  }
}

bool loadProgramSet(const std::vector<std::string>& paths, const LoadOptions& opts, ProgramSet& set, SetError& err) {
  struct Entry {
    std::string path;
    bool reported;
    bool named;
  };
  std::vector<Entry> entries;
  std::unordered_map<std::string, size_t> seen; // canonical path -> index in entries
  auto add = [&](const std::string& p, bool reported, bool named) {
    std::error_code ec;
    fs::path c = fs::weakly_canonical(p, ec); // once per path: a set of thousands of files stays linear
    auto [it, inserted] = seen.emplace(ec ? p : c.string(), entries.size());
    if (!inserted) {
      Entry& e = entries[it->second];
      e.reported = e.reported || reported;
      e.named = e.named || named;
      return;
    }
    entries.push_back({p, reported, named});
  };
  std::vector<std::string> siblingDirs;
  std::string bufferKey; // the canonical path of opts.buffer
  if (opts.buffer) {
    std::error_code ec;
    fs::path c = fs::weakly_canonical(opts.buffer->path, ec);
    bufferKey = ec ? opts.buffer->path : c.string();
  }
  for (const std::string& p : paths) {
    std::error_code ec;
    if (opts.buffer && p == opts.buffer->path) { // read from the buffer: it need not exist on disk
      add(p, true, true);
      if (support::isStreamInput(p)) continue; // standard input without a file name: no siblings
      fs::path parent = fs::path(p).parent_path();
      siblingDirs.push_back(parent.empty() ? std::string(".") : parent.string());
      continue;
    }
    if (support::isStreamInput(p)) { // a pipe or standard input: read once, a set of its own (no siblings)
      add(p, true, true);
      continue;
    }
    if (fs::is_directory(p, ec)) {
      std::vector<std::string> files;
      if (!listProgramFiles(p, files)) {
        set.inputErrors.push_back({p, "cannot read directory"});
        continue;
      }
      for (auto& f : files)
        add(f, true, false);
      continue;
    }
    if (!fs::exists(p, ec)) {
      set.inputErrors.push_back({p, "no such file or directory"});
      continue;
    }
    add(p, true, true);
    fs::path parent = fs::path(p).parent_path();
    siblingDirs.push_back(parent.empty() ? std::string(".") : parent.string());
  }
  if (opts.siblings) {
    std::sort(siblingDirs.begin(), siblingDirs.end());
    siblingDirs.erase(std::unique(siblingDirs.begin(), siblingDirs.end()), siblingDirs.end());
    for (const auto& d : siblingDirs) {
      std::vector<std::string> files;
      if (!listProgramFiles(d, files)) continue;
      for (auto& f : files)
        add(f, false, false);
    }
  }
  auto addFile = [&](const Entry& e, support::SourceText text) {
    uint32_t id = set.sources.add(e.path, std::move(text));
    File f;
    f.id = id;
    f.path = e.path;
    set.files.push_back(std::move(f));
    set.reported.push_back(e.reported ? 1 : 0);
    set.named.push_back(e.named ? 1 : 0);
    if (e.named) set.namedOrder.push_back(id);
  };
  std::vector<std::string> lazy; // siblings read only when a name is wanted (their header first)
  for (const auto& e : entries) {
    support::SourceText text;
    if (opts.lazySiblings && !e.reported) {
      lazy.push_back(e.path);
      continue;
    }
    if (opts.buffer && seen.count(bufferKey) && entries[seen[bufferKey]].path == e.path) {
      text = opts.buffer->text;
    } else if (auto read = support::readSource(e.path)) {
      text = std::move(*read);
    } else {
      if (!e.reported) continue; // an unreadable sibling only matters if called
      set.inputErrors.push_back({e.path, read.error().message});
      continue;
    }
    addFile(e, std::move(text));
  }
  processFiles(set, opts, 0);
  loadCalledSiblings(set, opts, lazy, [&](const std::string& path, support::SourceText text) {
    addFile(Entry{path, false, false}, std::move(text));
  });
  finishSet(set, opts);
  if (set.inputErrors.empty()) return true;
  err = {set.inputErrors.front().path, set.inputErrors.front().message};
  return false;
}

void loadProgramTexts(std::vector<ProgramText> texts, const LoadOptions& opts, ProgramSet& set) {
  for (auto& t : texts) {
    uint32_t id = set.sources.add(t.path, std::move(t.text));
    File f;
    f.id = id;
    f.path = std::move(t.path);
    set.files.push_back(std::move(f));
    set.reported.push_back(t.reported ? 1 : 0);
    set.named.push_back(t.reported ? 1 : 0);
    if (t.reported) set.namedOrder.push_back(id);
  }
  processFiles(set, opts);
}

void loadSingleSource(const std::string& path, std::string text, const LoadOptions& opts, ProgramSet& set) {
  std::vector<ProgramText> one;
  one.push_back({path, std::move(text), true});
  loadProgramTexts(std::move(one), opts, set);
}

} // namespace iso::frontend
