//! @file Splice.cpp
//! @brief A checked file's statements replaced in place by those parsed again from the same
//!        lines of an edited text (the language server's incremental check), and the texts a
//!        file's records view copied into storage of its own.
#include <algorithm>
#include <cstring>
#include <type_traits>

#include "frontend/Ast.h"

namespace iso::frontend {

namespace {

template <class V> void setLength(V& v, size_t n) { v.resize(n); }
template <class T> void setLength(InPlaceArray<T>& v, size_t n) {
  v.reserve(n);
  v.setSize(n);
}

/// v[lo, hi) becomes `ins`, each record through `fresh`; the records after follow them, each
/// through `after` when anything moved.
template <class V, class W, class Fresh, class After>
void spliceTable(V& v, size_t lo, size_t hi, const W& ins, Fresh fresh, After after, bool moved) {
  using T = std::remove_reference_t<decltype(v[0])>;
  static_assert(std::is_trivially_copyable_v<T>, "records are moved as bytes");
  const size_t old = v.size(), n = ins.size(), tail = old - hi, size = lo + n + tail;
  if (size > old) setLength(v, size);
  T* d = v.data();
  if (lo + n != hi && tail > 0) std::memmove(static_cast<void*>(d + lo + n), d + hi, tail * sizeof(T));
  if (size < old) setLength(v, size);
  for (size_t k = 0; k < n; ++k)
    d[lo + k] = fresh(ins[k]);
  if (moved)
    for (size_t k = lo + n; k < size; ++k)
      d[k] = after(d[k]);
}

/// The first record of each side table that belongs to a statement at or after `at` (the
/// tables are written in statement order; a table no such statement uses: its size).
struct Cuts {
  size_t inner, items, jumps, names, ranges, arms, gos, numbers, labels, whens, letters, sups;
};

Cuts cutsAt(const File& f, uint32_t at) {
  Cuts c{};
  // A statement's records lie on its lines, after the records of the statements before: the
  // first record of a table at or after the line statement `at` starts on is its first.
  const uint32_t line = at < f.stmts.size() ? f.stmts[at].line : UINT32_MAX;
  auto byLine = [line](const auto& v, auto lineOf) {
    return static_cast<size_t>(
        std::partition_point(v.begin(), v.end(), [&](const auto& x) { return lineOf(x) < line; }) - v.begin());
  };
  c.inner = byLine(f.inner, [](const Stmt& s) { return s.line; });
  c.items = byLine(f.items, [](const Item& x) { return x.loc.line; });
  c.jumps = byLine(f.jumps, [](const Jump& j) { return j.kwLoc.line; });
  c.names = byLine(f.names, [](const StmtName& n) { return n.loc.line; });
  c.gos = byLine(f.gos, [](const GoJump& g) { return g.fromLoc.line; });
  // a CASE's arms: by the first statement from `at` that has some
  c.ranges = f.armRanges.size();
  if (!f.armRanges.empty())
    for (size_t i = at; i < f.stmts.size(); ++i)
      if (f.stmts[i].part == StmtPart::Arms) {
        c.ranges = f.stmts[i].partIdx;
        break;
      }
  c.arms = c.ranges < f.armRanges.size() ? f.armRanges[c.ranges].first : f.arms.size();
  auto byStmt = [at](const auto& v) {
    return static_cast<size_t>(
        std::lower_bound(v.begin(), v.end(), at, [](const auto& x, uint32_t i) { return x.stmt < i; }) - v.begin());
  };
  c.numbers = byStmt(f.numbers);
  c.labels = byStmt(f.labels);
  c.whens = byStmt(f.whenAxes);
  c.letters = c.whens < f.whenAxes.size() ? f.whenAxes[c.whens].first : f.whenAxisLetters.size();
  // a suppression belongs to the statement whose lines reach its comment first
  const uint32_t before = at == 0 ? 0 : f.stmts[at - 1].lastLine;
  c.sups =
      static_cast<size_t>(std::partition_point(f.suppressions.begin(), f.suppressions.end(),
                                               [before](const Suppression& s) { return s.commentLine <= before; }) -
                          f.suppressions.begin());
  return c;
}

/// What the whole-file passes resolved stands for the old statements: they resolve it again.
void clearResolved(File& f) {
  for (Jump& j : f.jumps)
    j.target = -1;
  for (CaseArm& a : f.arms)
    a.jump.target = -1;
  f.splitAt = 0;
}

template <class T> T plus(T v, int64_t d) { return static_cast<T>(static_cast<int64_t>(v) + d); }

/// Lines after the statements replaced move by `d` (0: no line).
struct LineShift {
  int32_t d;
  uint32_t line(uint32_t l) const { return l == 0 ? 0 : plus(l, d); }
  Loc loc(Loc l) const {
    l.line = line(l.line);
    return l;
  }
};

/// spliceStatements' tables in statement order: N numbers, labels, WHEN axes, suppressions.
void spliceByStatement(File& f, const Cuts& lo, const Cuts& hi, File& part, uint32_t from, int64_t dStmts,
                       LineShift shift, bool anyMoved) {
  const int64_t dLetters =
      static_cast<int64_t>(part.whenAxisLetters.size()) - static_cast<int64_t>(hi.letters - lo.letters);
  auto freshByStmt = [from](auto x) {
    x.stmt += from;
    return x;
  };
  auto afterByStmt = [&](auto x) {
    x.stmt = plus(x.stmt, dStmts);
    x.loc = shift.loc(x.loc);
    return x;
  };
  spliceTable(f.numbers, lo.numbers, hi.numbers, part.numbers, freshByStmt, afterByStmt, anyMoved);
  spliceTable(f.labels, lo.labels, hi.labels, part.labels, freshByStmt, afterByStmt, anyMoved);
  spliceTable(
      f.whenAxes, lo.whens, hi.whens, part.whenAxes,
      [&](WhenAxes w) {
        w.stmt += from;
        w.first = plus(w.first, static_cast<int64_t>(lo.letters));
        return w;
      },
      [&](WhenAxes w) {
        w.stmt = plus(w.stmt, dStmts);
        w.first = plus(w.first, dLetters);
        return w;
      },
      anyMoved);
  f.whenAxisLetters.replace(lo.letters, hi.letters - lo.letters, part.whenAxisLetters);
  spliceTable(
      f.suppressions, lo.sups, hi.sups, part.suppressions, [](const Suppression& x) { return x; },
      [&](Suppression s) {
        s.line = shift.line(s.line);
        s.lastLine = shift.line(s.lastLine);
        s.commentLine = shift.line(s.commentLine);
        return s;
      },
      anyMoved);
}

} // namespace

bool spliceStatements(File& f, uint32_t from, uint32_t to, File&& part, int32_t lineShift) {
  if (!f.exprs.empty() || !part.exprs.empty() || !f.gos.empty() || !part.gos.empty() || from > to ||
      to > f.stmts.size())
    return false;
  const Cuts lo = cutsAt(f, from), hi = cutsAt(f, to);
  auto delta = [](size_t n, size_t a, size_t b) { return static_cast<int64_t>(n) - static_cast<int64_t>(b - a); };
  const int64_t dStmts = delta(part.stmts.size(), from, to), dInner = delta(part.inner.size(), lo.inner, hi.inner),
                dItems = delta(part.items.size(), lo.items, hi.items),
                dJumps = delta(part.jumps.size(), lo.jumps, hi.jumps),
                dNames = delta(part.names.size(), lo.names, hi.names),
                dRanges = delta(part.armRanges.size(), lo.ranges, hi.ranges),
                dArms = delta(part.arms.size(), lo.arms, hi.arms),
                dLetters = delta(part.whenAxisLetters.size(), lo.letters, hi.letters);
  // the records after move only when an index or a line does
  const bool anyMoved = dStmts != 0 || dInner != 0 || dItems != 0 || dJumps != 0 || dNames != 0 || dRanges != 0 ||
                        dArms != 0 || dLetters != 0 || lineShift != 0;
  const LineShift shift{lineShift};
  auto line = [&](uint32_t l) { return shift.line(l); };
  auto loc = [&](Loc l) { return shift.loc(l); };
  // A statement's indices, moved by the first records of the part (`fresh`) or by the change in
  // size of each table (the statements after).
  auto moved = [](Stmt s, int64_t items, int64_t inner, int64_t jumps, int64_t names, int64_t ranges) {
    s.firstItem = s.itemCount > 0 ? plus(s.firstItem, items) : 0;
    if (s.inner >= 0) s.inner = plus(s.inner, inner);
    switch (s.part) {
    case StmtPart::None:
    case StmtPart::Go: break;
    case StmtPart::Jump: s.partIdx = plus(s.partIdx, jumps); break;
    case StmtPart::Name: s.partIdx = plus(s.partIdx, names); break;
    case StmtPart::Arms: s.partIdx = plus(s.partIdx, ranges); break;
    }
    return s;
  };
  auto freshStmt = [&](const Stmt& s) {
    return moved(s, static_cast<int64_t>(lo.items), static_cast<int64_t>(lo.inner), static_cast<int64_t>(lo.jumps),
                 static_cast<int64_t>(lo.names), static_cast<int64_t>(lo.ranges));
  };
  auto afterStmt = [&](const Stmt& s) {
    Stmt t = moved(s, dItems, dInner, dJumps, dNames, dRanges);
    t.line = line(t.line);
    t.lastLine = line(t.lastLine);
    t.loc = loc(t.loc);
    return t;
  };
  spliceTable(f.stmts, from, to, part.stmts, freshStmt, afterStmt, anyMoved);
  spliceTable(f.inner, lo.inner, hi.inner, part.inner, freshStmt, afterStmt, anyMoved);
  spliceTable(
      f.items, lo.items, hi.items, part.items,
      [&](Item x) {
        if (x.kind == ItemKind::Kg) x.code = plus(x.code, static_cast<int64_t>(lo.names));
        return x;
      },
      [&](Item x) {
        if (x.kind == ItemKind::Kg) x.code = plus(x.code, dNames);
        x.loc = loc(x.loc);
        return x;
      },
      anyMoved);
  auto afterJump = [&](Jump j) {
    j.loc = loc(j.loc);
    j.kwLoc = loc(j.kwLoc);
    return j;
  };
  auto same = [](const auto& x) { return x; };
  spliceTable(f.jumps, lo.jumps, hi.jumps, part.jumps, same, afterJump, anyMoved);
  spliceTable(
      f.names, lo.names, hi.names, part.names, same,
      [&](StmtName n) {
        n.loc = loc(n.loc);
        return n;
      },
      anyMoved);
  spliceTable(
      f.armRanges, lo.ranges, hi.ranges, part.armRanges,
      [&](ArmRange r) {
        r.first = plus(r.first, static_cast<int64_t>(lo.arms));
        return r;
      },
      [&](ArmRange r) {
        r.first = plus(r.first, dArms);
        return r;
      },
      anyMoved);
  spliceTable(
      f.arms, lo.arms, hi.arms, part.arms, same,
      [&](CaseArm a) {
        a.valueLoc = loc(a.valueLoc);
        a.jump = afterJump(a.jump);
        return a;
      },
      anyMoved);
  spliceByStatement(f, lo, hi, part, from, dStmts, shift, anyMoved);
  clearResolved(f);
  if (!part.ownedText.empty()) f.ownedParts.push_front(std::move(part.ownedText));
  f.ownedParts.splice_after(f.ownedParts.before_begin(), part.ownedParts);
  part = File{};
  return true;
}

void ownTexts(File& f) {
  size_t total = f.procName.size();
  auto count = [&](std::string_view t) { total += t.size(); };
  for (const auto& n : f.numbers)
    count(n.text);
  for (const auto& l : f.labels)
    count(l.text);
  for (const auto& j : f.jumps)
    count(j.label);
  for (const auto& n : f.names)
    count(n.text);
  for (const auto& a : f.arms)
    count(a.jump.label);
  for (const auto& g : f.gos) {
    count(g.from);
    count(g.to);
  }
  std::string& arena = f.ownedText.emplace_back();
  arena.reserve(total);
  auto own = [&](std::string_view& t) {
    const size_t at = arena.size();
    arena.append(t);
    t = std::string_view(arena.data() + at, t.size());
  };
  own(f.procName);
  for (auto& n : f.numbers)
    own(n.text);
  for (auto& l : f.labels)
    own(l.text);
  for (auto& j : f.jumps)
    own(j.label);
  for (auto& n : f.names)
    own(n.text);
  for (auto& a : f.arms)
    own(a.jump.label);
  for (auto& g : f.gos) {
    own(g.from);
    own(g.to);
  }
  f.source = {};
}

} // namespace iso::frontend
