//! @file ControlFlow.cpp
//! @brief Control flow: reachability (W404), the end of the unit (W405, E206, E207).
#include "frontend/checks/FileChecker.h"

namespace iso::frontend::checks {

// The members marked inline run for every statement and only this file calls them:
// inline keeps them inlined, as they were when the class was defined in one piece.

using diag::Msg;

/// The line ends the program or subprogram. In z32 a special M on the line ends it first
/// (the final M never runs, W415).
inline bool FileChecker::terminal(const Stmt& s) const {
  return (hasM(f_, s, lang::kMEnd) || hasM(f_, s, lang::kMReturn) ||
          (isZ32() && (hasM(f_, s, lang::kMEndZ32) || z32Return(s) || hasKg(s)))) &&
         !specialOn(s);
}

/// z32: the G26 item of the line (return from subprogram, like M17), or nullptr.
const Item* FileChecker::z32Return(const Stmt& s) const {
  if (s.kind != StmtKind::Block) return nullptr;
  const Item* it = f_.itemsOf(s);
  for (uint32_t k = 0; k < s.itemCount; ++k)
    if (it[k].kind == ItemKind::G && it[k].code == lang::kG26Return) return &it[k];
  return nullptr;
}

/// z32: the line ends with KG (continue in a subprogram without return).
bool FileChecker::hasKg(const Stmt& s) const {
  if (s.kind != StmtKind::Block) return false;
  const Item* it = f_.itemsOf(s);
  for (uint32_t k = 0; k < s.itemCount; ++k)
    if (it[k].kind == ItemKind::Kg) return true;
  return false;
}

void FileChecker::computeReachability() {
  flow_.reachable.assign(f_.stmts.size(), 0);
  std::vector<int32_t> work;
  auto push = [&](int32_t t) {
    if (t == n_) {
      flow_.endReachable = true;
      return;
    }
    if (t < 0 || t > n_) return;
    if (!flow_.reachable[static_cast<size_t>(t)]) {
      flow_.reachable[static_cast<size_t>(t)] = 1;
      work.push_back(t);
    }
  };
  push(0);
  if (n_ == 0) flow_.endReachable = true;
  while (!work.empty()) {
    int32_t i = work.back();
    work.pop_back();
    // A run of lines that only fall through to the next is walked here, not through the
    // work list (the same lines become reachable: a fall-through line pushes only i + 1,
    // which the list would pop next).
    while (fallsThroughOnly(st(i)) && i + 1 < n_ && !flow_.reachable[static_cast<size_t>(i + 1)]) {
      ++i;
      flow_.reachable[static_cast<size_t>(i)] = 1;
    }
    const Stmt& s = st(i);
    switch (s.kind) {
    case StmtKind::Go: { // a GO range returns to the next line; an unresolved GO falls through
      const GoJump& g = f_.goOf(s);
      if (g.target >= 0) push(g.target);
      if (g.target < 0 || g.range) push(i + 1);
      break;
    }
    case StmtKind::Jump:
      // An unresolved jump (E202/E204 already reported) falls through: no follow-on W404.
      push(f_.jumpOf(s).target >= 0 ? f_.jumpOf(s).target : i + 1);
      break;
    case StmtKind::If:
      push(i + 1);
      if (s.hasJump()) {
        if (f_.jumpOf(s).target >= 0) push(f_.jumpOf(s).target);
      } else if (s.inner >= 0) {
        const Stmt& in = f_.inner[static_cast<size_t>(s.inner)];
        if (in.kind == StmtKind::Jump && f_.jumpOf(in).target >= 0) push(f_.jumpOf(in).target);
      } else {
        int32_t m = flow_.match[static_cast<size_t>(i)];
        if (m >= 0)
          push(m + 1);
        else if (int32_t e = endifOf(i); e >= 0)
          push(e + 1);
      }
      break;
    case StmtKind::Else: {
      int32_t m = flow_.match[static_cast<size_t>(i)];
      push(m >= 0 ? m : i + 1);
      break;
    }
    case StmtKind::Case: {
      bool hasDefault = false;
      for (const CaseArm& arm : f_.armsOf(s)) {
        if (arm.isDefault && arm.jump.target >= 0) hasDefault = true;
        if (arm.jump.target >= 0) push(arm.jump.target);
      }
      if (!hasDefault) push(i + 1);
      break;
    }
    case StmtKind::Block:
      if (!terminal(s)) push(i + 1);
      break;
    case StmtKind::Invalid:
      push(i + 1);
      if (s.recoverAs == StmtKind::If) { // a bad block IF may still skip to its ELSE/ENDIF
        int32_t m = flow_.match[static_cast<size_t>(i)];
        if (m >= 0) push(m + 1);
      }
      break;
    default: push(i + 1); break;
    }
    // A '/' line is skipped when isosim runs with block skip on (SPEC §2): the next line is
    // reachable whatever the line does (`/M17` can leave the end reachable without M17, E206).
    if (s.skippable) push(i + 1);
  }
  reportUnreachable();
  checkUnitEnd();
}

/// The line's only successor is the next line (computeReachability's `default` and
/// non-terminal blocks).
inline bool FileChecker::fallsThroughOnly(const Stmt& s) const {
  switch (s.kind) {
  case StmtKind::Empty:
  case StmtKind::EndIf:
  case StmtKind::Call:
  case StmtKind::Proc:
  case StmtKind::Semi:
  case StmtKind::When:
  case StmtKind::Cancel: return true;
  case StmtKind::Block: return !terminal(s);
  default: return false;
  }
}

/// W404: runs of unreachable statements. ELSE and ENDIF only mark where a body ends: a
/// body that ends with M30 or a jump (IF c / GOTOF L / ENDIF) leaves them unreached, which
/// is no dead code, so a run never starts at them.
void FileChecker::reportUnreachable() {
  int32_t i = 0;
  while (i < n_) {
    if (flow_.reachable[static_cast<size_t>(i)] || st(i).kind == StmtKind::Empty || st(i).kind == StmtKind::Invalid ||
        st(i).kind == StmtKind::Else || st(i).kind == StmtKind::EndIf) {
      ++i;
      continue;
    }
    int32_t j = i;
    int32_t last = i;
    while (j < n_ && !flow_.reachable[static_cast<size_t>(j)]) {
      if (st(j).kind != StmtKind::Empty) last = j;
      ++j;
    }
    const Stmt& a = st(i);
    const Stmt& b = st(last);
    const Loc at{f_.id, a.line, a.hasN() ? f_.numberOf(a).loc.col : (a.hasLabel() ? f_.labelOf(a).loc.col : a.loc.col)};
    if (last == i)
      diags_.report(Msg::UnreachableLine, at, 1);
    else
      diags_.report(Msg::UnreachableLines, at, 1, a.line, b.lastLine);
    i = j;
  }
}

/// E207 M17 in a main program; E206 / W405: the end of the unit reachable without M17 / M30.
void FileChecker::checkUnitEnd() {
  bool anyM17 = false;
  for (int32_t k = 0; k < n_; ++k) {
    const Stmt& s = st(k);
    bool m17 = hasM(f_, s, lang::kMReturn) ||
               (s.inner >= 0 && hasM(f_, f_.inner[static_cast<size_t>(s.inner)], lang::kMReturn));
    if (const Item* g26 = isZ32() ? z32Return(s.inner >= 0 ? f_.inner[static_cast<size_t>(s.inner)] : s) : nullptr) {
      anyM17 = true;
      if (f_.kind != UnitKind::Sub)
        diags_.report(Msg::G26InMain, g26->loc, g26->len, lang::kMReturn, unitKindName(f_.kind), lang::kMEnd);
    }
    if (m17) {
      anyM17 = true;
      if (f_.kind != UnitKind::Sub) {
        const Item* it = f_.itemsOf(s.inner >= 0 ? f_.inner[static_cast<size_t>(s.inner)] : s);
        const Stmt& ss = s.inner >= 0 ? f_.inner[static_cast<size_t>(s.inner)] : s;
        Loc at = ss.loc;
        for (uint32_t q = 0; q < ss.itemCount; ++q)
          if (it[q].kind == ItemKind::M && it[q].code == lang::kMReturn) at = it[q].loc;
        diags_.report(Msg::M17InMain, at, 3, lang::kMReturn, unitKindName(f_.kind), lang::kMEnd);
      }
    }
  }
  uint32_t lastLine = n_ > 0 ? st(n_ - 1).lastLine : 1;
  if (n_ > 0 && st(n_ - 1).truncated) return; // the unchecked rest of the last line may end the unit
  if (f_.kind == UnitKind::Sub) {
    if (!anyM17)
      diags_.report(Msg::SubWithoutM17, L(lastLine), 1, lang::kMReturn, lang::kMReturn);
    else if (flow_.endReachable)
      diags_.report(Msg::SubEndWithoutM17, L(lastLine), 1, lang::kMReturn);
  } else if (flow_.endReachable) {
    diags_.report(Msg::MainWithoutEnd, L(lastLine), 1, unitKindName(f_.kind), lang::kMEnd);
  }
}

} // namespace iso::frontend::checks
