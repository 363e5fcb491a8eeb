//! @file Incremental.cpp
//! @brief IncrementalFile: a recorded one-thread pass, and the lines an edit reaches checked
//!        again from the mark before it (Incremental.h tells the sequence).
#include "frontend/Incremental.h"

#include <algorithm>
#include <bit>
#include <cstring>
#include <optional>
#include <string>

#include "frontend/LineChecker.h"
#include "frontend/Parser.h"

namespace iso::frontend {

using checks::FileChecker;
using detail::canSplitAt;
using detail::LineChecker;

namespace {

/// A statement's fingerprint: every field the whole-file passes and the set-level checks read
/// (not the indices into side tables, which differ between a file and a part of it, and not
/// what the passes resolve). Taken in statement order, as the side tables are.
/// A 64-bit hash of the values added, in order.
struct Hash {
  uint64_t value = 0x9e3779b97f4a7c15ull;
  template <class... T> void add(T... v) {
    for (uint64_t x : {static_cast<uint64_t>(v)...}) {
      value ^= x + 0x9e3779b97f4a7c15ull + (value << 6) + (value >> 2);
      value *= 0xff51afd7ed558ccdull;
    }
  }
  void text(std::string_view t) {
    add(t.size());
    uint64_t w = 0;
    for (size_t k = 0; k < t.size(); k += 8) {
      w = 0;
      std::memcpy(&w, t.data() + k, std::min<size_t>(8, t.size() - k));
      add(w);
    }
  }
};

class Fingerprints {
public:
  explicit Fingerprints(const File& f) : f_(f) {}

  /// The next of() is for statement `i` (or later): the side tables read in order start there.
  void seek(uint32_t i) {
    when_ = static_cast<size_t>(std::lower_bound(f_.whenAxes.begin(), f_.whenAxes.end(), i,
                                                 [](const WhenAxes& w, uint32_t k) { return w.stmt < k; }) -
                                f_.whenAxes.begin());
    const uint32_t before = i == 0 ? 0 : f_.stmts[i - 1].lastLine;
    sup_ =
        static_cast<size_t>(std::partition_point(f_.suppressions.begin(), f_.suppressions.end(),
                                                 [before](const Suppression& x) { return x.commentLine <= before; }) -
                            f_.suppressions.begin());
  }

  uint64_t of(uint32_t i) {
    h_ = Hash{};
    const Stmt& s = f_.stmts[i];
    stmt(s);
    if (s.inner >= 0) stmt(f_.inner[static_cast<size_t>(s.inner)]);
    if (s.hasN()) {
      const LineNumber& n = f_.numberOf(s);
      h_.text(n.text);
      loc(n.loc);
      h_.add(n.len);
      h_.add(std::bit_cast<uint64_t>(n.value));
    }
    if (s.hasLabel()) {
      const StmtLabel& l = f_.labelOf(s);
      h_.text(l.text);
      loc(l.loc);
    }
    sidePart(s);
    while (when_ < f_.whenAxes.size() && f_.whenAxes[when_].stmt < i)
      ++when_;
    if (when_ < f_.whenAxes.size() && f_.whenAxes[when_].stmt == i)
      h_.text(std::string_view(f_.whenAxisLetters).substr(f_.whenAxes[when_].first, f_.whenAxes[when_].count));
    while (sup_ < f_.suppressions.size() && f_.suppressions[sup_].commentLine <= s.lastLine) {
      const Suppression& x = f_.suppressions[sup_++];
      h_.add(x.line, x.lastLine, x.commentLine, x.col, x.length, static_cast<uint64_t>(x.code));
    }
    return h_.value;
  }

private:
  void loc(const Loc& l) { h_.add(l.line, l.col); }

  void stmt(const Stmt& s) {
    h_.add(static_cast<uint64_t>(s.kind), static_cast<uint64_t>(s.recoverAs), static_cast<uint64_t>(s.part));
    h_.add(s.skippable, s.procSave, s.isInner, s.partial, s.truncated, s.numbered, s.labelled);
    h_.add(s.line, s.lastLine);
    loc(s.loc);
    h_.add(s.itemCount, s.movedAxes, s.posaAxes, s.cond == kNoExpr, s.inner >= 0);
    const Item* it = f_.itemsOf(s);
    for (uint32_t k = 0; k < s.itemCount; ++k) {
      const Item& x = it[k];
      h_.add(static_cast<uint64_t>(x.kind), static_cast<uint64_t>(x.mode), static_cast<uint64_t>(x.sysvar), x.nb,
             static_cast<uint8_t>(x.axis), static_cast<uint8_t>(x.zaddr[0]), static_cast<uint8_t>(x.zaddr[1]),
             static_cast<uint8_t>(x.zaddr[2]), static_cast<uint32_t>(x.len));
      loc(x.loc);
      if (x.kind == ItemKind::Kg)
        h_.text(static_cast<size_t>(x.code) < f_.names.size() ? f_.names[static_cast<size_t>(x.code)].text : "");
      else
        h_.add(static_cast<uint32_t>(x.code));
      if (x.kind == ItemKind::AxisControl) h_.add(static_cast<uint32_t>(x.target));
    }
  }

  void jump(const Jump& j) {
    h_.add(static_cast<uint64_t>(j.kind), j.len);
    h_.text(j.label);
    loc(j.loc);
    loc(j.kwLoc);
  }

  void sidePart(const Stmt& s) {
    switch (s.part) {
    case StmtPart::None: return;
    case StmtPart::Jump: return jump(f_.jumpOf(s));
    case StmtPart::Name: {
      const StmtName& n = f_.nameOf(s);
      h_.text(n.text);
      loc(n.loc);
      h_.add(n.len, n.joined);
      return;
    }
    case StmtPart::Arms:
      for (const CaseArm& a : f_.armsOf(s)) {
        h_.add(std::bit_cast<uint64_t>(a.value), a.isDefault);
        loc(a.valueLoc);
        jump(a.jump);
      }
      return;
    case StmtPart::Go: {
      const GoJump& g = f_.goOf(s);
      h_.add(g.range, g.fromLen, g.toLen);
      h_.text(g.from);
      h_.text(g.to);
      loc(g.fromLoc);
      loc(g.toLoc);
      return;
    }
    }
  }

  const File& f_;
  Hash h_;
  size_t when_ = 0; ///< the WHEN axes of the statements before
  size_t sup_ = 0;  ///< the suppressions of the statements before
};

/// What the set-level checks read of a file (SetChecks.cpp), but not where: its kind and
/// names, and each call (a call line, a special M, a KG) in order; `calls` gets their places.
uint64_t setPrint(const File& f, const SemaOptions& opts, std::vector<Loc>& calls) {
  Hash h;
  h.add(static_cast<uint64_t>(f.kind));
  h.text(f.procName);
  h.text(f.semiName);
  calls.clear();
  forEachCall(
      f, opts.specialMap(),
      [&](const Stmt& s) {
        const StmtName& n = f.nameOf(s);
        h.add(1, n.len, n.joined, s.isInner);
        h.text(n.text);
        calls.push_back(n.loc);
      },
      [&](const Item& x, const std::string& name) {
        h.add(2, static_cast<uint32_t>(x.code), x.len);
        h.text(name);
        calls.push_back(x.loc);
      },
      [&](const Item& x, std::string_view name) {
        h.add(3, x.len);
        h.text(name);
        calls.push_back(x.loc);
      });
  return h.value;
}

/// How far an update checks again before it gives up: the file is then checked in full.
constexpr size_t kMaxMarksAhead = 64;

} // namespace

struct IncrementalFile::Impl {
  struct Mark {
    uint32_t stmt = 0;   ///< the statement that starts here
    uint32_t offset = 0; ///< its first byte
    uint32_t line = 1;   ///< its first line
    size_t diag = 0;     ///< per-line diagnostics of the statements before
    /// (apart, so that shifting the marks after an edit reads only these 32-byte records)
    std::unique_ptr<FileChecker::BlockState> state;
  };
  /// How the last update moved places: the lines [first, last] of the old text were edited;
  /// the lines after moved by `shift`; the calls on the edited lines are found in `oldCalls`
  /// (every call of the file, in order) and moved to the place of the same call in `newCalls`.
  struct Moves {
    uint32_t first = 0, last = 0;
    int64_t shift = 0;
    std::vector<Loc> oldCalls, newCalls;
  };
  size_t every = 64;
  LexOptions lex;
  SemaOptions opts;
  uint32_t id = 0;
  std::string path;
  UnitKind kind = UnitKind::Main;
  File file; ///< the compact file, once adopted
  bool adopted = false;
  uint64_t setHash = 0;   ///< setPrint of the file
  std::vector<Loc> calls; ///< its calls' places
  std::vector<Mark> marks;
  std::vector<diag::Diagnostic> lineDiags, fileDiags;
  Moves moves;
  bool valid = false, wholeFile = false;
  size_t rechecked = 0;

  /// The mark an update of this edit gives up at: kMaxMarksAhead past the edit's end.
  size_t limitMark(size_t at, size_t removed, size_t inserted) const {
    const auto after = std::upper_bound(marks.begin(), marks.end(), at + removed,
                                        [](size_t off, const Mark& k) { return off < k.offset; });
    return static_cast<size_t>(after - marks.begin()) + kMaxMarksAhead + inserted / 16;
  }
  bool fail() {
    valid = false;
    adopted = false;
    file = File{};
    std::vector<Mark>().swap(marks);
    lineDiags = {};
    calls = {};
    fileDiags = {};
    moves = {};
    return false;
  }
  /// `l` of the old text in the new one (Moves); nothing for a place in the lines checked
  /// again that is not a call.
  std::optional<Loc> moved(Loc l) const {
    if (l.file != id || l.line < moves.first) return l;
    if (l.line > moves.last) return Loc{l.file, static_cast<uint32_t>(l.line + moves.shift), l.col};
    const auto it = std::lower_bound(moves.oldCalls.begin(), moves.oldCalls.end(), l, [](const Loc& a, const Loc& b) {
      return a.line != b.line ? a.line < b.line : a.col < b.col;
    });
    if (it == moves.oldCalls.end() || it->line != l.line || it->col != l.col) return std::nullopt;
    return moves.newCalls[static_cast<size_t>(it - moves.oldCalls.begin())];
  }
  bool stateAgrees(const FileChecker::BlockState& now, const FileChecker::BlockState& old, uint32_t editFirst,
                   uint32_t editLast, int64_t shift) const;
  bool spliceAndRun(File&& part, size_t first, size_t stop, int64_t shift);
};

IncrementalFile::IncrementalFile(size_t markEvery) : impl_(std::make_unique<Impl>()) {
  impl_->every = markEvery ? markEvery : 1;
}
IncrementalFile::~IncrementalFile() = default;
IncrementalFile::IncrementalFile(IncrementalFile&&) noexcept = default;
IncrementalFile& IncrementalFile::operator=(IncrementalFile&&) noexcept = default;

bool IncrementalFile::valid() const { return impl_->valid; }
size_t IncrementalFile::lastRechecked() const { return impl_->rechecked; }
bool IncrementalFile::lastRanWholeFile() const { return impl_->wholeFile; }
const File& IncrementalFile::file() const { return impl_->file; }

std::vector<diag::Diagnostic> IncrementalFile::diagnostics() const {
  std::vector<diag::Diagnostic> out = impl_->lineDiags;
  out.insert(out.end(), impl_->fileDiags.begin(), impl_->fileDiags.end());
  return out;
}

FileFlow IncrementalFile::check(File& f, std::string_view text, const LexOptions& lex, const SemaOptions& opts,
                                diag::DiagnosticList& diags) {
  Impl& m = *impl_;
  m.fail();
  m.lex = lex;
  m.lex.cancel = nullptr; // an update is not given up (the caller's function may be gone)
  m.opts = opts;
  m.id = f.id;
  m.path = f.path;
  const size_t base = diags.size();
  const bool marks = text.size() < UINT32_MAX;
  {
    LineParser lines(f, text, lex, diags);
    LineChecker check(f, opts, diags);
    uint32_t offset = 0, line = 1;
    for (;;) {
      // a mark every `every` statements, and one as soon as the unit kind is known
      if (marks && check.started() && (f.stmts.size() % m.every == 0 || m.marks.empty()) && offset > 0 &&
          canSplitAt(text, offset))
        m.marks.push_back({static_cast<uint32_t>(f.stmts.size()), offset, line, diags.size() - base,
                           std::make_unique<FileChecker::BlockState>(check.state())});
      if (!lines.parseLine()) break;
      check.line();
      offset = lines.nextOffset();
      line = f.stmts.back().lastLine + 1;
    }
    check.finish();
  }
  m.lineDiags.assign(diags.items().begin() + static_cast<std::ptrdiff_t>(base), diags.items().end());
  const size_t before = diags.size();
  FileChecker c(f, opts, diags);
  FileFlow flow = c.run(/*blocksChecked=*/true, /*twoThreads=*/false);
  m.fileDiags.assign(diags.items().begin() + static_cast<std::ptrdiff_t>(before), diags.items().end());
  m.kind = f.kind;
  // z32 GO targets are found in the raw text (GoTarget), which fingerprints do not cover.
  m.valid = marks && f.gos.empty() && !f.binary && f.exprs.empty();
  if (!m.valid) m.fail();
  return flow;
}

void IncrementalFile::adopt(File&& f) {
  Impl& m = *impl_;
  if (!m.valid || f.id != m.id) {
    m.fail();
    return;
  }
  m.file = std::move(f);
  ownTexts(m.file);
  // the room reserved for parsing (an item and an expression per few bytes) is given back
  File& k = m.file;
  k.stmts = StmtArray(k.stmts);
  k.numbers = InPlaceArray<LineNumber>(k.numbers);
  k.items.shrink_to_fit();
  k.exprs.shrink_to_fit();
  k.inner.shrink_to_fit();
  k.jumps.shrink_to_fit();
  k.labels.shrink_to_fit();
  m.setHash = setPrint(m.file, m.opts, m.calls);
  m.adopted = true;
}

bool IncrementalFile::update(std::string_view text, size_t at, size_t removed, size_t inserted) {
  return update(text, text.size(), at, removed, inserted);
}

size_t IncrementalFile::reach(size_t size, size_t at, size_t removed, size_t inserted) const {
  const Impl& m = *impl_;
  const size_t limit = m.limitMark(at, removed, inserted) + 1; // the statement after the last mark tried
  if (!m.valid || limit >= m.marks.size()) return size;
  const auto delta = static_cast<int64_t>(inserted) - static_cast<int64_t>(removed);
  return std::min(size, static_cast<size_t>(static_cast<int64_t>(m.marks[limit].offset) + delta));
}

/// The state checked again agrees with the one a mark recorded, whose place (W422's F word) is
/// in the old text: lines after the edit's (`editLast`, old) moved by `shift`.
bool IncrementalFile::Impl::stateAgrees(const FileChecker::BlockState& now, const FileChecker::BlockState& old,
                                        uint32_t editFirst, uint32_t editLast, int64_t shift) const {
  if (shift == 0) return now.sameAs(old);
  FileChecker::BlockState moved = old;
  Loc& at = moved.modal.highFeedLoc;
  if (at.line > editLast)
    at.line = static_cast<uint32_t>(at.line + shift);
  else if (at.line >= editFirst)
    return false; // on a line the edit changed
  return now.sameAs(moved);
}

bool IncrementalFile::update(std::string_view text, size_t size, size_t at, size_t removed, size_t inserted) {
  Impl& m = *impl_;
  if (!m.valid || !m.adopted || size >= UINT32_MAX || text.size() > size) return m.fail();
  const auto delta = static_cast<int64_t>(inserted) - static_cast<int64_t>(removed);
  // the last mark at or before the edit (the lines before a mark end at it: it is a split point)
  auto it = std::upper_bound(m.marks.begin(), m.marks.end(), at,
                             [](size_t off, const Impl::Mark& k) { return off < k.offset; });
  if (it == m.marks.begin()) return m.fail();
  const size_t first = static_cast<size_t>(it - m.marks.begin()) - 1;
  const Impl::Mark& from = m.marks[first];
  if (!canSplitAt(text, from.offset)) return m.fail();
  const size_t editEnd = at + inserted; // in the new text
  // the edit's first line, and its last in the new text
  auto lfs = [&](size_t a, size_t b) {
    a = std::min(a, text.size());
    return static_cast<uint32_t>(
        std::count(text.begin() + static_cast<std::ptrdiff_t>(a),
                   text.begin() + static_cast<std::ptrdiff_t>(std::max(a, std::min(b, text.size()))), '\n'));
  };
  const uint32_t editFirst = from.line + lfs(from.offset, at), editLast = editFirst + lfs(at, editEnd);

  File g;
  g.id = m.id;
  g.path = m.path;
  g.kind = m.kind;
  diag::DiagnosticList d;
  std::vector<Impl::Mark> again; // the marks between, as checked again
  LineParser lines(g, text, m.lex, d, /*reserve=*/false);
  lines.setRange(from.offset, from.line, static_cast<uint32_t>(text.size()));
  LineChecker check(g, m.opts, d);
  check.startWith(*from.state);
  Fingerprints prints(g), old(m.file);
  old.seek(from.stmt);
  bool same = true;        // the statements checked so far are the old ones, on the same lines
  size_t next = first + 1; // the first old mark not passed
  const size_t limit = m.limitMark(at, removed, inserted);
  size_t stop = m.marks.size();
  uint32_t offset = from.offset, line = from.line;
  for (;;) {
    const size_t n = g.stmts.size();
    const size_t stmt = from.stmt + n;
    if (n > 0 && offset > editEnd) {
      while (next < m.marks.size() && static_cast<int64_t>(m.marks[next].offset) + delta < offset)
        ++next;
      if (next < m.marks.size() && static_cast<int64_t>(m.marks[next].offset) + delta == offset &&
          m.stateAgrees(check.state(), *m.marks[next].state, editFirst,
                        static_cast<uint32_t>(editLast - (static_cast<int64_t>(line) - m.marks[next].line)),
                        static_cast<int64_t>(line) - m.marks[next].line)) {
        stop = next;
        break;
      }
      if (next >= limit) return m.fail();
    }
    if (n > 0 && stmt % m.every == 0 && canSplitAt(text, offset))
      again.push_back({static_cast<uint32_t>(stmt), offset, line, from.diag + d.size(),
                       std::make_unique<FileChecker::BlockState>(check.state())});
    if (!lines.parseLine()) {
      if (text.size() < size) return m.fail(); // the bytes given end before the text
      break;
    }
    check.line();
    if (same)
      same = stmt < m.file.stmts.size() && prints.of(static_cast<uint32_t>(n)) == old.of(static_cast<uint32_t>(stmt));
    offset = lines.nextOffset();
    line = g.stmts.back().lastLine + 1;
  }
  check.finish();
  const uint32_t oldStop = stop < m.marks.size() ? m.marks[stop].stmt : static_cast<uint32_t>(m.file.stmts.size());
  // the lines after the edit moved by: (at the end, the last lines of the two texts tell)
  const int64_t shift = stop < m.marks.size() ? static_cast<int64_t>(line) - m.marks[stop].line
                        : m.file.stmts.empty() || g.stmts.empty()
                            ? 0
                            : static_cast<int64_t>(g.stmts.back().lastLine) - m.file.stmts.back().lastLine;
  const auto editLastOld = static_cast<uint32_t>(editLast - shift);
  const size_t newCount = g.stmts.size();
  m.wholeFile = !same || newCount != oldStop - from.stmt || shift != 0;
  m.moves = {editFirst, editLastOld, shift, {}, {}};
  if (m.wholeFile && !m.spliceAndRun(std::move(g), first, stop, shift)) return m.fail();
  // The per-line diagnostics of [from, stop) are replaced; those after move with their lines.
  const size_t oldDiagEnd = stop < m.marks.size() ? m.marks[stop].diag : m.lineDiags.size();
  const size_t oldCount = oldDiagEnd - from.diag;
  auto& lineDiags = m.lineDiags;
  if (shift != 0)
    for (size_t k = oldDiagEnd; k < lineDiags.size(); ++k)
      if (!remap(lineDiags[k])) return m.fail();
  lineDiags.erase(lineDiags.begin() + static_cast<std::ptrdiff_t>(from.diag),
                  lineDiags.begin() + static_cast<std::ptrdiff_t>(oldDiagEnd));
  lineDiags.insert(lineDiags.begin() + static_cast<std::ptrdiff_t>(from.diag),
                   std::make_move_iterator(d.items().begin()), std::make_move_iterator(d.items().end()));
  const auto diagShift = static_cast<int64_t>(d.size()) - static_cast<int64_t>(oldCount);
  const auto stmtShift = static_cast<int64_t>(newCount) - static_cast<int64_t>(oldStop - from.stmt);
  for (size_t k = stop; k < m.marks.size(); ++k) {
    Impl::Mark& mk = m.marks[k];
    mk.offset = static_cast<uint32_t>(static_cast<int64_t>(mk.offset) + delta);
    mk.diag = static_cast<size_t>(static_cast<int64_t>(mk.diag) + diagShift);
    mk.stmt = static_cast<uint32_t>(static_cast<int64_t>(mk.stmt) + stmtShift);
    mk.line = static_cast<uint32_t>(static_cast<int64_t>(mk.line) + shift);
    if (Loc& hf = mk.state->modal.highFeedLoc; shift != 0 && hf.line > editLastOld)
      hf.line = static_cast<uint32_t>(static_cast<int64_t>(hf.line) + shift);
  }
  // the marks checked again replace those between (the same statements, so the same count
  // unless a mark's line start stopped being a split point, or became one)
  m.marks.erase(m.marks.begin() + static_cast<std::ptrdiff_t>(first + 1),
                m.marks.begin() + static_cast<std::ptrdiff_t>(stop));
  m.marks.insert(m.marks.begin() + static_cast<std::ptrdiff_t>(first + 1), std::make_move_iterator(again.begin()),
                 std::make_move_iterator(again.end()));
  m.rechecked = newCount;
  return true;
}

/// The statements checked again (`part`, from mark `first` to mark `stop`) replace the old
/// ones in the kept file, and the whole-file passes run again over its records. False when
/// what the set-level checks read of the file changed.
bool IncrementalFile::Impl::spliceAndRun(File&& part, size_t first, size_t stop, int64_t shift) {
  const uint32_t from = marks[first].stmt;
  const uint32_t to = stop < marks.size() ? marks[stop].stmt : static_cast<uint32_t>(file.stmts.size());
  moves.oldCalls = calls;
  ownTexts(part);
  if (!spliceStatements(file, from, to, std::move(part), static_cast<int32_t>(shift))) return false;
  if (setPrint(file, opts, moves.newCalls) != setHash) return false;
  calls = moves.newCalls;
  diag::DiagnosticList d;
  FileChecker c(file, opts, d);
  c.run(/*blocksChecked=*/true, /*twoThreads=*/file.stmts.size() >= (size_t{1} << 16));
  fileDiags = std::move(d.items());
  return true;
}

bool IncrementalFile::remap(diag::Diagnostic& d) const {
  const Impl& m = *impl_;
  if (!m.wholeFile) return true; // nothing moved
  // a place and what is measured from it (an end, on its line or after) move together
  auto move = [&](Loc& at, uint32_t* endLine, uint32_t* endCol) {
    const Loc was = at;
    const auto to = m.moved(at);
    if (!to) return false;
    at = *to;
    if (endLine && *endLine != 0) {
      if (endCol && *endLine == was.line) *endCol = static_cast<uint32_t>(*endCol + (int64_t{to->col} - was.col));
      *endLine = static_cast<uint32_t>(*endLine + (int64_t{to->line} - was.line));
    }
    return true;
  };
  if (!move(d.loc, &d.endLine, &d.endCol)) return false;
  for (auto& n : d.notes)
    if (!move(n.loc, nullptr, nullptr)) return false;
  for (auto& f : d.fixes)
    for (auto& e : f.edits)
      if (!move(e.start, &e.endLine, &e.endCol)) return false;
  return true;
}

} // namespace iso::frontend
