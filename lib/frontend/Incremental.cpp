//! @file Incremental.cpp
//! @brief IncrementalFile: a recorded one-thread pass, and the lines an edit reaches checked
//!        again from the mark before it (Incremental.h tells the sequence).
#include "frontend/Incremental.h"

#include <bit>
#include <cstring>
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
class Fingerprints {
public:
  explicit Fingerprints(const File& f) : f_(f) {}

  uint64_t of(uint32_t i) {
    h_ = 0x9e3779b97f4a7c15ull;
    const Stmt& s = f_.stmts[i];
    stmt(s);
    if (s.inner >= 0) stmt(f_.inner[static_cast<size_t>(s.inner)]);
    if (s.hasN()) {
      const LineNumber& n = f_.numberOf(s);
      text(n.text);
      loc(n.loc);
      add(n.len);
      add(std::bit_cast<uint64_t>(n.value));
    }
    if (s.hasLabel()) {
      const StmtLabel& l = f_.labelOf(s);
      text(l.text);
      loc(l.loc);
    }
    sidePart(s);
    while (when_ < f_.whenAxes.size() && f_.whenAxes[when_].stmt < i)
      ++when_;
    if (when_ < f_.whenAxes.size() && f_.whenAxes[when_].stmt == i)
      text(std::string_view(f_.whenAxisLetters).substr(f_.whenAxes[when_].first, f_.whenAxes[when_].count));
    while (sup_ < f_.suppressions.size() && f_.suppressions[sup_].commentLine <= s.lastLine) {
      const Suppression& x = f_.suppressions[sup_++];
      add(x.line, x.lastLine, x.commentLine, x.col, x.length, static_cast<uint64_t>(x.code));
    }
    return h_;
  }

private:
  template <class... T> void add(T... v) {
    for (uint64_t x : {static_cast<uint64_t>(v)...}) {
      h_ ^= x + 0x9e3779b97f4a7c15ull + (h_ << 6) + (h_ >> 2);
      h_ *= 0xff51afd7ed558ccdull;
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
  void loc(const Loc& l) { add(l.line, l.col); }

  void stmt(const Stmt& s) {
    add(static_cast<uint64_t>(s.kind), static_cast<uint64_t>(s.recoverAs), static_cast<uint64_t>(s.part));
    add(s.skippable, s.procSave, s.isInner, s.partial, s.truncated, s.numbered, s.labelled);
    add(s.line, s.lastLine);
    loc(s.loc);
    add(s.itemCount, s.movedAxes, s.posaAxes, s.cond == kNoExpr, s.inner >= 0);
    const Item* it = f_.itemsOf(s);
    for (uint32_t k = 0; k < s.itemCount; ++k) {
      const Item& x = it[k];
      add(static_cast<uint64_t>(x.kind), static_cast<uint64_t>(x.mode), static_cast<uint64_t>(x.sysvar), x.nb,
          static_cast<uint8_t>(x.axis), static_cast<uint8_t>(x.zaddr[0]), static_cast<uint8_t>(x.zaddr[1]),
          static_cast<uint8_t>(x.zaddr[2]), static_cast<uint32_t>(x.len));
      loc(x.loc);
      if (x.kind == ItemKind::Kg)
        text(static_cast<size_t>(x.code) < f_.names.size() ? f_.names[static_cast<size_t>(x.code)].text : "");
      else
        add(static_cast<uint32_t>(x.code));
      if (x.kind == ItemKind::AxisControl) add(static_cast<uint32_t>(x.target));
    }
  }

  void jump(const Jump& j) {
    add(static_cast<uint64_t>(j.kind), j.len);
    text(j.label);
    loc(j.loc);
    loc(j.kwLoc);
  }

  void sidePart(const Stmt& s) {
    switch (s.part) {
    case StmtPart::None: return;
    case StmtPart::Jump: return jump(f_.jumpOf(s));
    case StmtPart::Name: {
      const StmtName& n = f_.nameOf(s);
      text(n.text);
      loc(n.loc);
      add(n.len, n.joined);
      return;
    }
    case StmtPart::Arms:
      for (const CaseArm& a : f_.armsOf(s)) {
        add(std::bit_cast<uint64_t>(a.value), a.isDefault);
        loc(a.valueLoc);
        jump(a.jump);
      }
      return;
    case StmtPart::Go: {
      const GoJump& g = f_.goOf(s);
      add(g.range, g.fromLen, g.toLen);
      text(g.from);
      text(g.to);
      loc(g.fromLoc);
      loc(g.toLoc);
      return;
    }
    }
  }

  const File& f_;
  uint64_t h_ = 0;
  size_t when_ = 0; ///< the WHEN axes of the statements before
  size_t sup_ = 0;  ///< the suppressions of the statements before
};

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
  size_t every = 64;
  LexOptions lex;
  SemaOptions opts;
  uint32_t id = 0;
  std::string path;
  UnitKind kind = UnitKind::Main;
  std::vector<uint64_t> prints;
  std::vector<Mark> marks;
  std::vector<diag::Diagnostic> lineDiags, fileDiags;
  bool valid = false;
  size_t rechecked = 0;

  /// The mark an update of this edit gives up at: kMaxMarksAhead past the edit's end.
  size_t limitMark(size_t at, size_t removed, size_t inserted) const {
    const auto after = std::upper_bound(marks.begin(), marks.end(), at + removed,
                                        [](size_t off, const Mark& k) { return off < k.offset; });
    return static_cast<size_t>(after - marks.begin()) + kMaxMarksAhead + inserted / 16;
  }
  bool fail() {
    valid = false;
    prints = {};
    std::vector<Mark>().swap(marks);
    lineDiags = {};
    fileDiags = {};
    return false;
  }
};

IncrementalFile::IncrementalFile(size_t markEvery) : impl_(std::make_unique<Impl>()) {
  impl_->every = markEvery ? markEvery : 1;
}
IncrementalFile::~IncrementalFile() = default;
IncrementalFile::IncrementalFile(IncrementalFile&&) noexcept = default;
IncrementalFile& IncrementalFile::operator=(IncrementalFile&&) noexcept = default;

bool IncrementalFile::valid() const { return impl_->valid; }
size_t IncrementalFile::lastRechecked() const { return impl_->rechecked; }

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
  Fingerprints prints(f);
  m.prints.reserve(f.stmts.size());
  for (uint32_t i = 0; i < f.stmts.size(); ++i)
    m.prints.push_back(prints.of(i));
  const size_t before = diags.size();
  FileChecker c(f, opts, diags);
  FileFlow flow = c.run(/*blocksChecked=*/true, /*twoThreads=*/false);
  m.fileDiags.assign(diags.items().begin() + static_cast<std::ptrdiff_t>(before), diags.items().end());
  m.kind = f.kind;
  // z32 GO targets are found in the raw text (GoTarget), which fingerprints do not cover.
  m.valid = marks && f.gos.empty() && !f.binary;
  if (!m.valid) m.fail();
  return flow;
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

bool IncrementalFile::update(std::string_view text, size_t size, size_t at, size_t removed, size_t inserted) {
  Impl& m = *impl_;
  if (!m.valid || size >= UINT32_MAX || text.size() > size) return m.fail();
  const auto delta = static_cast<int64_t>(inserted) - static_cast<int64_t>(removed);
  // the last mark at or before the edit (the lines before a mark end at it: it is a split point)
  auto it = std::upper_bound(m.marks.begin(), m.marks.end(), at,
                             [](size_t off, const Impl::Mark& k) { return off < k.offset; });
  if (it == m.marks.begin()) return m.fail();
  const size_t first = static_cast<size_t>(it - m.marks.begin()) - 1;
  const Impl::Mark& from = m.marks[first];
  if (!canSplitAt(text, from.offset)) return m.fail();
  const size_t editEnd = at + inserted; // in the new text

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
  Fingerprints prints(g);
  size_t next = first + 1; // the first old mark not passed
  const size_t limit = m.limitMark(at, removed, inserted);
  size_t stop = m.marks.size();
  uint32_t offset = from.offset;
  for (;;) {
    const size_t n = g.stmts.size();
    const size_t stmt = from.stmt + n;
    if (n > 0 && offset > editEnd) {
      while (next < m.marks.size() && m.marks[next].stmt < stmt)
        ++next;
      if (next < m.marks.size() && m.marks[next].stmt == stmt &&
          static_cast<int64_t>(m.marks[next].offset) + delta == offset && check.state().sameAs(*m.marks[next].state)) {
        stop = next;
        break;
      }
      if (next >= limit) return m.fail();
    }
    if (n > 0 && stmt % m.every == 0 && canSplitAt(text, offset))
      again.push_back({static_cast<uint32_t>(stmt), offset, g.stmts.back().lastLine + 1, from.diag + d.size(),
                       std::make_unique<FileChecker::BlockState>(check.state())});
    if (!lines.parseLine()) {
      if (text.size() < size || stmt != m.prints.size()) return m.fail(); // the statements end elsewhere
      break;
    }
    check.line();
    if (stmt >= m.prints.size() || prints.of(static_cast<uint32_t>(n)) != m.prints[stmt]) return m.fail();
    offset = lines.nextOffset();
  }
  check.finish();
  // The whole-file results stand: the per-line diagnostics of [from, stop) are replaced.
  const size_t oldEnd = stop < m.marks.size() ? m.marks[stop].diag : m.lineDiags.size();
  const size_t oldCount = oldEnd - from.diag;
  auto& lineDiags = m.lineDiags;
  lineDiags.erase(lineDiags.begin() + static_cast<std::ptrdiff_t>(from.diag),
                  lineDiags.begin() + static_cast<std::ptrdiff_t>(oldEnd));
  lineDiags.insert(lineDiags.begin() + static_cast<std::ptrdiff_t>(from.diag),
                   std::make_move_iterator(d.items().begin()), std::make_move_iterator(d.items().end()));
  const auto shift = static_cast<int64_t>(d.size()) - static_cast<int64_t>(oldCount);
  for (size_t k = stop; k < m.marks.size(); ++k) {
    m.marks[k].offset = static_cast<uint32_t>(static_cast<int64_t>(m.marks[k].offset) + delta);
    m.marks[k].diag = static_cast<size_t>(static_cast<int64_t>(m.marks[k].diag) + shift);
  }
  // the marks checked again replace those between (the same statements, so the same count
  // unless a mark's line start stopped being a split point, or became one)
  m.marks.erase(m.marks.begin() + static_cast<std::ptrdiff_t>(first + 1),
                m.marks.begin() + static_cast<std::ptrdiff_t>(stop));
  m.marks.insert(m.marks.begin() + static_cast<std::ptrdiff_t>(first + 1), std::make_move_iterator(again.begin()),
                 std::make_move_iterator(again.end()));
  m.rechecked = g.stmts.size();
  return true;
}

} // namespace iso::frontend
