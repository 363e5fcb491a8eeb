//! @file FilePipeline.cpp
//! @brief parseAndCheckFile: the lines parsed and checked together, a large file in parts on two
//!        threads and joined (the sequence is told in FilePipeline.h).
#include "frontend/FilePipeline.h"

#include "lang/Z32GCodes.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <thread>
#include <utility>
#include <vector>

#include "frontend/Lexer.h"
#include "frontend/LineChecker.h"
#include "frontend/Parser.h"
#include "frontend/checks/FileChecker.h"
#include "support/Memory.h"
#include "support/SourceText.h"
#include "support/Text.h"

namespace iso::frontend {

using checks::FileChecker;
using detail::canSplitAt;
using detail::LineChecker;

namespace {

// A large file is checked in parts by two threads when two threads are allowed (SplitOptions).
// The parts end at split points, line starts that no logical line crosses. The first thread
// checks the first part; once it has checked SplitOptions::guessAfter statements, the second
// thread starts on the next part, from the modal state the first has then: a guess of the state
// at the part's start. Each thread then takes the next part nobody took, from the same guess,
// until none is left (a slower thread takes fewer). At the join, part after part, the first
// thread checks the part again from the true state at its start (the state at the end of the
// part before) until the state equals the guess's at one of the checkpoints the part recorded:
// from there on both give the same diagnostics, so the part's are kept. The statements come out
// as a single pass would make them (the parser keeps nothing from line to line), and so do the
// diagnostics. If no checkpoint agrees, the part is checked again whole, as one thread would.
constexpr size_t kCheckEvery = 8;     ///< statements between two checkpoints
constexpr size_t kCheckpoints = 512;  ///< checkpoints of a part (its first ~4k statements)
constexpr size_t kSplitSearch = 4096; ///< lines tried after a target offset for a split point

/// A mapped text's pages leave memory behind a reader that passes it once, every
/// SplitOptions::dropEvery bytes (a page back: the statement being parsed has views into its
/// line); later reads (the compiler's, a message's line) fault them in again from the file. Its
/// parser keeps copies of the names the set's checks look up (Parser::ownNames), which would
/// read every page again.
class PassedPages {
public:
  PassedPages(std::string_view text, size_t from, size_t every, LineParser& lines)
      : text_(text), done_(from), every_(std::max(every, kBack)), mapped_(support::isMappedSource(text)) {
    if (mapped_) lines.ownNames();
  }
  void at(size_t offset) {
    if (!mapped_ || offset < done_ + every_) return;
    support::dropMappedPages(text_, done_, offset - kBack);
    done_ = offset - kBack;
  }

private:
  static constexpr size_t kBack = 4096;
  std::string_view text_;
  size_t done_, every_;
  bool mapped_;
};

/// The first line start from offset `from` on where `text` can be split (0: none near).
uint32_t splitPointFrom(std::string_view text, size_t from) {
  for (size_t tries = 0; tries < kSplitSearch; ++tries) {
    const size_t nl = text.find('\n', from);
    if (nl == std::string_view::npos || nl + 1 >= text.size()) return 0;
    const auto at = static_cast<uint32_t>(nl + 1);
    if (canSplitAt(text, at)) return at;
    from = nl + 1;
  }
  return 0;
}

/// Where the parts of `text` start, after the first (none: one thread checks it all).
std::vector<uint32_t> splitPoints(std::string_view text, const SplitOptions& o) {
  std::vector<uint32_t> out;
  if (o.at != 0) {
    if (canSplitAt(text, o.at)) out.push_back(o.at);
    return out;
  }
  const size_t parts = o.parts ? o.parts : 2;
  for (size_t k = 1; k < parts; ++k) {
    const uint32_t at = splitPointFrom(text, text.size() * k / parts);
    if (at != 0 && (out.empty() || at > out.back())) out.push_back(at);
  }
  return out;
}

/// The state before a statement of a part, as the thread that checked the part had it.
struct Checkpoint {
  size_t stmt = 0; ///< the statement's index in the part
  size_t diag = 0; ///< diagnostics of the part before it
  FileChecker::BlockState state;
};

/// A part of a split file after the first, as a thread parsed and checked it.
struct Part {
  uint32_t begin = 0, end = 0; ///< offsets: [begin, end)
  uint32_t firstLine = 1;
  File file;
  diag::DiagnosticList diags;
  std::vector<Checkpoint> checkpoints;
  FileChecker::BlockState last; ///< the state after its last statement
  std::exception_ptr error;
};

/// A file to hold a part of `f`'s lines.
File partOf(const File& f) {
  File part;
  part.id = f.id;
  part.path = f.path;
  part.kind = f.kind;
  return part;
}

void checkPart(Part& out, std::string_view text, const LexOptions& lex, const SemaOptions& opts,
               const FileChecker::BlockState& guess, size_t dropEvery) {
  try {
    File& g = out.file;
    LineParser lines(g, text, lex, out.diags, /*reserve=*/false);
    lines.setRange(out.begin, out.firstLine, out.end);
    LineChecker check(g, opts, out.diags);
    check.startWith(guess);
    out.checkpoints.reserve(kCheckpoints);
    auto mark = [&] {
      if (out.checkpoints.size() < kCheckpoints && g.stmts.size() % kCheckEvery == 0)
        out.checkpoints.push_back({g.stmts.size(), out.diags.size(), check.state()});
    };
    mark();
    PassedPages passed(text, out.begin, dropEvery, lines);
    while (lines.parseLine()) {
      check.line();
      mark();
      passed.at(lines.nextOffset());
    }
    out.last = check.state();
  } catch (...) {
    out.error = std::current_exception();
  }
}

/// Appends `part` to `f` and its diagnostics to `diags`, checked again from `state` (the true
/// state at its start) until a checkpoint agrees; returns the true state at its end.
FileChecker::BlockState joinPart(File& f, std::string_view text, const LexOptions& lex, const SemaOptions& opts,
                                 diag::DiagnosticList& diags, const FileChecker::BlockState& state, Part& part) {
  File again = partOf(f);
  diag::DiagnosticList againDiags;
  LineParser lines(again, text, lex, againDiags, /*reserve=*/false);
  lines.setRange(part.begin, part.firstLine, part.end);
  if (support::isMappedSource(text)) lines.ownNames(); // as the part's own reading did
  LineChecker check(again, opts, againDiags);
  check.startWith(state);
  const std::vector<Checkpoint>& points = part.checkpoints;
  size_t c = 0;
  for (;;) {
    const size_t n = again.stmts.size();
    while (c < points.size() && points[c].stmt < n)
      ++c;
    if (c < points.size() && points[c].stmt == n && check.state().sameAs(points[c].state)) {
      // The rest is as the part's thread checked it; the lines before, as checked again.
      appendPart(f, std::move(part.file), /*twoThreads=*/true);
      diags.append(std::move(againDiags));
      auto& tail = part.diags.items();
      for (size_t k = points[c].diag; k < tail.size(); ++k)
        diags.items().push_back(std::move(tail[k]));
      return part.last;
    }
    if (c == points.size() && !part.file.stmts.empty()) {
      part.file = File{}; // no checkpoint agreed: the part is checked again, whole
      part.diags = {};
    }
    if (!lines.parseLine()) break;
    check.line();
  }
  appendPart(f, std::move(again));
  diags.append(std::move(againDiags));
  return check.state();
}

} // namespace

FileFlow parseAndCheckFile(File& f, std::string_view text, const LexOptions& lex, const SemaOptions& opts,
                           diag::DiagnosticList& diags, unsigned threads, const SplitOptions& splitting) {
  std::vector<uint32_t> starts;
  if (threads >= 2 && text.size() >= splitting.minBytes && text.size() < UINT32_MAX)
    starts = splitPoints(text, splitting);
  const uint32_t split = starts.empty() ? 0 : starts.front(); // where the first part ends
  {
    LineParser lines(f, text, lex, diags);
    LineChecker check(f, opts, diags);
    std::vector<Part> parts(starts.size());
    std::atomic<size_t> nextPart{0};
    std::thread worker;
    struct Joiner {
      std::thread& t;
      ~Joiner() {
        if (t.joinable()) t.join();
      }
    } joiner{worker};
    FileChecker::BlockState guess;
    auto takeParts = [&] {
      for (size_t k = nextPart++; k < parts.size(); k = nextPart++)
        checkPart(parts[k], text, lex, opts, guess, splitting.dropEvery);
    };
    bool atSplit = false;
    PassedPages passed(text, 0, splitting.dropEvery, lines);
    while (lines.parseLine()) {
      check.line();
      const uint32_t at = lines.nextOffset();
      passed.at(at);
      if (split == 0) continue;
      // Started: the unit kind is known. Not past the split: a file whose first statement lies
      // beyond it is checked whole.
      if (!worker.joinable() && check.started() && at <= split &&
          (f.stmts.size() >= splitting.guessAfter || at == split)) {
        // Each part's statements go right after the room the parts before can take: one per
        // physical line at most (those joined by `$` leave a gap, closed by appendPart).
        size_t before = support::countByte(text.substr(0, split), '\n');
        for (size_t k = 0; k < parts.size(); ++k) {
          Part& p = parts[k];
          p.begin = starts[k];
          p.end = k + 1 < parts.size() ? starts[k + 1] : static_cast<uint32_t>(text.size());
          p.firstLine = static_cast<uint32_t>(before + 1);
          p.file = partOf(f);
          before += support::countByte(text.substr(p.begin, p.end - p.begin), '\n');
        }
        const size_t total = before + 1;
        if (f.stmts.capacity() < total) {
          f.stmts.reserve(total);
          support::adviseHugePages(f.stmts.data(), f.stmts.capacity() * sizeof(Stmt));
        }
        f.numbers.reserve(total); // at most one per statement: the same rooms
        for (size_t k = 0; k < parts.size(); ++k) {
          const size_t base = parts[k].firstLine - 1;
          const size_t room = (k + 1 < parts.size() ? parts[k + 1].firstLine - 1 : total) - base;
          parts[k].file.stmts = StmtArray::inside(f.stmts.data() + base, room);
          parts[k].file.numbers = InPlaceArray<LineNumber>::inside(f.numbers.data() + base, room);
        }
        guess = check.state();
        worker = std::thread(takeParts);
      }
      if (worker.joinable() && at == split) {
        atSplit = true;
        break;
      }
    }
    if (worker.joinable()) {
      // (A first part that read past the split, which a split point rules out, read the whole
      // file: the other parts are dropped.)
      if (atSplit) takeParts();
      worker.join();
      if (atSplit) {
        FileChecker::BlockState state = check.state();
        for (Part& p : parts) {
          if (p.error) std::rethrow_exception(p.error);
          state = joinPart(f, text, lex, opts, diags, state, p);
        }
        f.splitAt = split;
      }
    }
    check.finish(); // f.kind is set (LineChecker::start)
  }
  FileChecker c(f, opts, diags);
  return c.run(/*blocksChecked=*/true, /*twoThreads=*/split != 0);
}

} // namespace iso::frontend
