//! @file ProgramSet.cpp
//! @brief Program set loading, parallel parsing and checking.
#include "frontend/ProgramSet.h"

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <deque>
#include <exception>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <thread>
#include <unordered_map>
#include <unordered_set>

#include "frontend/Incremental.h"
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

LexOptions lexOptionsFor(const LoadOptions& opts) {
  LexOptions lo;
  lo.dialect = opts.dialect;
  std::string letters(lang::kDefaultAxisLetters);
  if (opts.machine)
    for (const auto& a : opts.machine->axes)
      if (letters.find(a.letter) == std::string::npos) letters.push_back(a.letter);
  lo.axisLetters = letters;
  if (opts.machine && opts.dialect == machine::Dialect::Z32) lo.userParams = opts.machine->parameters;
  if (opts.cancel) lo.cancel = &opts.cancel;
  return lo;
}

/// The bytes of a sibling first read to learn what it is (more only when its first statement
/// is later).
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
      if (i < opts.record.size() && opts.record[i])
        set.flows[i] = opts.record[i]->check(f, src.text, lo, so, perFile[k]);
      else
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
    std::exception_ptr error; // the first a thread met (a cancelled load): the others stop
    std::mutex errorLock;
    std::vector<std::thread> pool;
    for (unsigned t = 0; t < jobs; ++t)
      pool.emplace_back([&] {
        try {
          for (size_t k = next++; k < n; k = next++)
            work(k);
        } catch (...) {
          next = n;
          const std::lock_guard<std::mutex> hold(errorLock);
          if (!error) error = std::current_exception();
        }
      });
    for (auto& th : pool)
      th.join();
    if (error) std::rethrow_exception(error);
  }
  for (auto& d : perFile)
    set.diags.append(std::move(d));
}

/// The set-level checks, then diagnostics in their order.
static void finishSet(ProgramSet& set, const LoadOptions& opts, const std::vector<size_t>* rank = nullptr) {
  SemaOptions so{opts.machine, opts.dialect};
  const size_t before = set.diags.size();
  checkSet(set.files, so, set.diags, {&set.reported, rank});
  if (opts.setLevel)
    opts.setLevel->assign(set.diags.items().begin() + static_cast<std::ptrdiff_t>(before), set.diags.items().end());
  set.diags.sort();
}

static void processFiles(ProgramSet& set, const LoadOptions& opts) {
  processFiles(set, opts, 0);
  finishSet(set, opts);
}

/// What the first lines of a sibling say: its unit kind and, for a subprogram, its PROC name.
struct SiblingHeader {
  std::string path;
  size_t rank = 0; ///< its place among the files of a full load
  UnitKind kind = UnitKind::Main;
  std::string proc; ///< the upper-case name after PROC ("" when the file has none)
  bool loaded = false;
};

/// The kind and PROC name (upper case) of `h.path` from the first statement of `text` (a binary
/// file is a main program, as a full load makes it). Only the first logical line is parsed.
/// False when `text` is a prefix that ends before that line does.
static bool readHeader(std::string_view text, bool whole, const LoadOptions& opts, SiblingHeader& h) {
  h.proc.clear();
  h.kind = UnitKind::Main;
  if (binaryKind(text, opts.imageMagic) != Binary::None) return true;
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
  File f;
  f.path = h.path;
  if (last > 0) {
    diag::DiagnosticList diags;
    parseFile(f, text.substr(0, end == std::string_view::npos ? text.size() : end), lo, diags);
  }
  h.kind = classifyUnit(f);
  for (const Stmt& s : f.stmts) {
    if (s.kind == StmtKind::Empty) continue;
    if (s.kind == StmtKind::Proc) h.proc = support::upperCopy(f.nameOf(s).text);
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

/// The siblings of a set that are not read yet (SiblingLoad::Called, Linked), in the order of
/// a full load, and what their first lines say once they are wanted.
struct LazySiblings {
  std::vector<SiblingHeader> headers; ///< path and rank of each; the rest once headersRead
  bool headersRead = false;

  /// Reads the start of each sibling (16 times more each time its first statement lies
  /// further on); a sibling that cannot be read is dropped, as a full load drops it.
  void readHeaders(const LoadOptions& opts) {
    if (headersRead) return;
    headersRead = true;
    std::erase_if(headers, [&](SiblingHeader& h) {
      for (size_t bytes = kHeaderBytes;; bytes *= 16) {
        bool whole = false;
        auto head = support::readFilePrefix(h.path, bytes, whole);
        if (!head) return true;
        if (readHeader(*head, whole, opts, h)) return false; // always so once `whole`
      }
    });
  }
};

/// Loads the siblings that the set needs: with SiblingLoad::Linked first what an image links
/// without a call (the semi-automatic programs; the main programs when no named file is one),
/// then those that the loaded files call (or whose name they define too), then what those
/// call, until nothing more is needed. The headers are read the first time a sibling is
/// wanted: in isolint a main program that calls nothing reads no other file. `addFile(h, text)`
/// adds one to the set.
template <class AddFile>
static void loadSiblings(ProgramSet& set, const LoadOptions& opts, LazySiblings& lazy, AddFile&& addFile) {
  if (lazy.headers.empty()) return;
  auto load = [&](SiblingHeader& h) {
    if (auto text = support::readSource(h.path)) addFile(h, std::move(*text));
    h.loaded = true;
  };
  size_t done = 0; // the files whose calls are followed
  if (opts.siblingLoad == SiblingLoad::Linked) {
    lazy.readHeaders(opts);
    const bool namedMain = std::any_of(set.namedOrder.begin(), set.namedOrder.end(),
                                       [&](size_t id) { return set.files[id].kind == UnitKind::Main; });
    const size_t before = set.files.size();
    for (auto& h : lazy.headers)
      if (h.kind == UnitKind::Semi || (h.kind == UnitKind::Main && !namedMain)) load(h);
    if (set.files.size() > before) processFiles(set, opts, before);
  }
  for (;;) {
    std::unordered_set<std::string> wanted;
    for (size_t i = done; i < set.files.size(); ++i) {
      std::vector<std::string> names;
      calledNames(set.files[i], opts, names);
      wanted.insert(names.begin(), names.end());
      if (!set.files[i].procName.empty()) wanted.insert(support::upperCopy(set.files[i].procName));
    }
    done = set.files.size();
    if (wanted.empty()) break;
    lazy.readHeaders(opts);
    for (auto& h : lazy.headers)
      if (!h.loaded && !h.proc.empty() && wanted.count(h.proc)) load(h);
    if (set.files.size() == done) break;
    processFiles(set, opts, done);
  }
}

/// The diagnostics in the order of a full load: by the place of their file in it (`rank`, per
/// file id), then as they are (line, column, code).
static void sortByRank(ProgramSet& set, const std::vector<size_t>& rank) {
  if (std::is_sorted(rank.begin(), rank.end())) return;
  auto of = [&](const diag::Diagnostic& d) { return d.loc.file < rank.size() ? rank[d.loc.file] : SIZE_MAX; };
  auto& items = set.diags.items();
  std::stable_sort(items.begin(), items.end(),
                   [&](const diag::Diagnostic& a, const diag::Diagnostic& b) { return of(a) < of(b); });
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
  std::vector<size_t> rank; // per file id: the index of its entry
  auto addFile = [&](const Entry& e, size_t entry, support::SourceText text) {
    uint32_t id = set.sources.add(e.path, std::move(text));
    rank.push_back(entry);
    File f;
    f.id = id;
    f.path = e.path;
    set.files.push_back(std::move(f));
    set.reported.push_back(e.reported ? 1 : 0);
    set.named.push_back(e.named ? 1 : 0);
    if (e.named) set.namedOrder.push_back(id);
  };
  LazySiblings lazy; // siblings read only when they are wanted (their header first)
  for (size_t k = 0; k < entries.size(); ++k) {
    const Entry& e = entries[k];
    support::SourceText text;
    if (opts.siblingLoad != SiblingLoad::All && !e.reported) {
      SiblingHeader h;
      h.path = e.path;
      h.rank = k;
      lazy.headers.push_back(std::move(h));
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
    addFile(e, k, std::move(text));
  }
  processFiles(set, opts, 0);
  loadSiblings(set, opts, lazy, [&](const SiblingHeader& h, support::SourceText text) {
    addFile(Entry{h.path, false, false}, h.rank, std::move(text));
  });
  finishSet(set, opts, &rank);
  sortByRank(set, rank);
  for (const auto& h : lazy.headers)
    if (!h.loaded) set.unread.push_back(h.path);
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
