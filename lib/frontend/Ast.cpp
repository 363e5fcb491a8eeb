//! @file Ast.cpp
//! @brief Names for AST enums.
#include "frontend/Ast.h"

#include <cstdlib>
#include <cstring>
#include <functional>
#include <stdexcept>
#include <thread>
#include <type_traits>

#include "lang/Keywords.h"
#include "support/Memory.h"

namespace iso::frontend {

const char* unitKindName(UnitKind k) {
  switch (k) {
  case UnitKind::Main: return "main program";
  case UnitKind::Semi: return "semi-automatic program";
  case UnitKind::Sub: return "subprogram";
  }
  return "program";
}

const char* sysVarName(SysVar v) {
  // the spellings are string literals of lang/SysVars.def: NUL-terminated
  return lang::isSysVarId(static_cast<uint8_t>(v)) ? lang::sysVarInfo(v).name.data() : "$?";
}

const char* cmpOpText(CmpOp op) {
  switch (op) {
  case CmpOp::Gt: return ">";
  case CmpOp::Lt: return "<";
  case CmpOp::Eq: return "==";
  case CmpOp::Ge: return ">=";
  case CmpOp::Le: return "<=";
  case CmpOp::Ne: return "<>";
  }
  return "?";
}

std::string_view File::whenAxesOf(uint32_t stmt) const {
  const uint32_t i = byStmtIndex(whenAxes, stmt);
  if (i == kNoIndex) return {};
  return std::string_view(whenAxisLetters).substr(whenAxes[i].first, whenAxes[i].count);
}

const char* jumpKindName(JumpKind k) {
  switch (k) {
  // the spellings are string literals of lang/Keywords.def: NUL-terminated
  case JumpKind::Gotof: return lang::keywordInfo(lang::Keyword::Gotof).spelling.data();
  case JumpKind::Gotob: return lang::keywordInfo(lang::Keyword::Gotob).spelling.data();
  case JumpKind::Goto: break;
  }
  return lang::keywordInfo(lang::Keyword::Goto).spelling.data();
}

} // namespace iso::frontend

namespace iso::frontend {
// The records a CAM program of millions of lines holds one or several of per line.
static_assert(sizeof(Stmt) <= 52 && sizeof(Expr) <= 40 && sizeof(Item) <= 36);

namespace {

/// Appends `from`'s records to `to`, each through `adjust`, a chunk at a time; each chunk's pages
/// are given back once copied. `from` is left empty.
template <class Array, class Adjust> void appendReleasing(Array& to, Array& from, Adjust adjust) {
  using T = std::remove_reference_t<decltype(from[0])>;
  constexpr size_t kChunkBytes = size_t{1} << 20;
  constexpr size_t kChunk = kChunkBytes / sizeof(T) + 1;
  // parts come one after another: room grows geometrically, not to each exact size
  if (to.capacity() < to.size() + from.size()) to.reserve(std::max(to.size() + from.size(), 2 * to.capacity()));
  for (size_t k = 0; k < from.size(); k += kChunk) {
    const size_t end = std::min(from.size(), k + kChunk);
    for (size_t j = k; j < end; ++j)
      to.push_back(adjust(from[j]));
    // the pages wholly behind `end`, from the start (releasePages keeps the partial ones), if
    // they are `from`'s own
    bool own = true;
    if constexpr (requires { from.ownsStorage(); }) own = from.ownsStorage();
    if (own) support::releasePages(from.data(), end * sizeof(T));
  }
  from = Array{};
}

/// `from`'s records already lie in `to`'s storage, at or after its end (InPlaceArray::inside).
template <class T> bool liesBeyond(const InPlaceArray<T>& to, const InPlaceArray<T>& from) {
  const std::less<const T*> before;
  return !from.ownsStorage() && !before(from.data(), to.data() + to.size()) &&
         !before(to.data() + to.capacity(), from.data() + from.size());
}

/// appendReleasing for an array whose records may lie in `to`'s storage already: then they are
/// moved down to its end in place (to <= from: each is read before anything is written over it).
template <class T, class Adjust> void appendInPlace(InPlaceArray<T>& to, InPlaceArray<T>& from, Adjust adjust) {
  if (!liesBeyond(to, from)) {
    appendReleasing(to, from, adjust);
    return;
  }
  T* at = to.data() + to.size();
  T* src = from.data();
  const size_t n = from.size();
  for (size_t k = 0; k < n; ++k)
    at[k] = adjust(src[k]);
  to.setSize(to.size() + n);
  from = InPlaceArray<T>{};
  // The records' old place, where the new one does not cover it, is given back.
  T* vacated = std::max(at + n, src);
  support::releasePages(vacated, static_cast<size_t>(src + n - vacated) * sizeof(T));
}

} // namespace

void appendPart(File& f, File&& part, bool twoThreads) {
  const auto stmts0 = static_cast<uint32_t>(f.stmts.size());
  const auto inner0 = static_cast<int32_t>(f.inner.size());
  const auto items0 = static_cast<uint32_t>(f.items.size());
  const auto exprs0 = static_cast<ExprId>(f.exprs.size());
  const auto arms0 = static_cast<uint32_t>(f.arms.size());
  const auto jumps0 = static_cast<uint32_t>(f.jumps.size());
  const auto names0 = static_cast<uint32_t>(f.names.size());
  const auto gos0 = static_cast<uint32_t>(f.gos.size());
  const auto ranges0 = static_cast<uint32_t>(f.armRanges.size());
  const auto letters0 = static_cast<uint32_t>(f.whenAxisLetters.size());
  auto expr = [exprs0](ExprId e) { return e == kNoExpr ? e : e + exprs0; };
  auto stmt = [&](Stmt s) {
    s.firstItem += items0;
    s.cond = expr(s.cond);
    if (s.inner >= 0) s.inner += inner0;
    switch (s.part) {
    case StmtPart::None: break;
    case StmtPart::Jump: s.partIdx += jumps0; break;
    case StmtPart::Name: s.partIdx += names0; break;
    case StmtPart::Arms: s.partIdx += ranges0; break;
    case StmtPart::Go: s.partIdx += gos0; break;
    }
    return s;
  };
  // Two halves of the work that touch different arrays: the statements' second half and the
  // side tables read by statement index on a second thread (`twoThreads`), the rest here.
  const size_t count = part.stmts.size();
  const bool inPlace = liesBeyond(f.stmts, part.stmts);
  // In place: the part's statements are in f's storage already, at or after f's end, and are
  // moved down (to <= from: each is read before anything is written over it). In two halves
  // only when nothing moves (no `$` joins left a gap).
  Stmt* to = f.stmts.end();
  const Stmt* from = part.stmts.data();
  const size_t half = inPlace && to == from && twoThreads ? count / 2 : count;
  auto renumber = [&](size_t lo, size_t hi) {
    for (size_t k = lo; k < hi; ++k)
      to[k] = stmt(from[k]);
  };
  auto byStatement = [&] {
    renumber(half, inPlace ? count : half);
    appendInPlace(f.numbers, part.numbers, [&](LineNumber n) {
      n.stmt += stmts0;
      return n;
    });
    appendReleasing(f.labels, part.labels, [&](StmtLabel l) {
      l.stmt += stmts0;
      return l;
    });
    appendReleasing(f.whenAxes, part.whenAxes, [&](WhenAxes w) {
      w.stmt += stmts0;
      w.first += letters0;
      return w;
    });
  };
  auto rest = [&] {
    if (inPlace)
      renumber(0, half);
    else
      appendReleasing(f.stmts, part.stmts, stmt);
    appendReleasing(f.inner, part.inner, stmt);
    appendReleasing(f.items, part.items, [&](Item x) {
      if (x.kind != ItemKind::AxisControl) x.target = expr(x.target); // AxisControl: an axis mask
      x.value = expr(x.value);
      if (x.kind == ItemKind::Kg) x.code += static_cast<int32_t>(names0);
      return x;
    });
    appendReleasing(f.exprs, part.exprs, [&](Expr x) {
      x.a = expr(x.a);
      x.b = expr(x.b);
      return x;
    });
    appendReleasing(f.arms, part.arms, [](const CaseArm& a) { return a; });
    appendReleasing(f.armRanges, part.armRanges, [&](ArmRange r) {
      r.first += arms0;
      return r;
    });
    appendReleasing(f.jumps, part.jumps, [](const Jump& j) { return j; });
    appendReleasing(f.names, part.names, [](const StmtName& n) { return n; });
    appendReleasing(f.gos, part.gos, [](const GoJump& g) { return g; });
    appendReleasing(f.suppressions, part.suppressions, [](const Suppression& s) { return s; });
    f.whenAxisLetters += part.whenAxisLetters;
    f.usedAxes |= part.usedAxes;
  };
  if (twoThreads) {
    std::thread second(byStatement);
    struct Join {
      std::thread& t;
      ~Join() { t.join(); }
    } join{second};
    rest();
  } else {
    byStatement();
    rest();
  }
  if (inPlace) {
    f.stmts.setSize(f.stmts.size() + count);
    part.stmts = StmtArray{};
  }
  if (!part.ownedText.empty()) f.ownedParts.push_front(std::move(part.ownedText));
  f.ownedParts.splice_after(f.ownedParts.before_begin(), part.ownedParts);
}

} // namespace iso::frontend
