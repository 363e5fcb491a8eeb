//! @file Jumps.cpp
//! @brief Jump targets (E202, E204, E205, W408, W413, CASE duplicates) and jumps, z32 GO
//!        jumps too, into IF or WHEN bodies (W412).
#include "frontend/checks/FileChecker.h"

#include <algorithm>
#include <unordered_map>

namespace iso::frontend::checks {

using diag::Msg;

void FileChecker::resolveJump(Jump& j, int32_t from, bool isCase) {
  int32_t t = findLabel(j.label);
  if (t < 0) {
    diags_.report(Msg::LabelUnknown, j.loc, j.len, j.label);
    return;
  }
  const Stmt& target = f_.stmts[static_cast<size_t>(t)];
  if (isCase) {
    if (j.kind != JumpKind::Gotof || t <= from) {
      auto& d = j.kind != JumpKind::Gotof ? diags_.report(Msg::CaseNotGotof, j.kwLoc, 5, jumpKindName(j.kind))
                                          : diags_.report(Msg::CaseLabelBefore, j.loc, j.len, j.label);
      d.note(Msg::CaseLabelNote, f_.labelOf(target).loc);
      if (j.kind == JumpKind::Gotof) return;
    }
    j.target = t;
    return;
  }
  switch (j.kind) {
  case JumpKind::Gotof:
    if (t <= from) {
      auto& d = t == from ? diags_.report(Msg::GotofSameLine, j.kwLoc, 5, j.label)
                          : diags_.report(Msg::GotofBackward, j.kwLoc, 5, j.label);
      d.note(Msg::JumpDirectionLabelNote, f_.labelOf(target).loc);
      return;
    }
    break;
  case JumpKind::Gotob:
    if (t > from) {
      auto& d = diags_.report(Msg::GotobForward, j.kwLoc, 5, j.label);
      d.note(Msg::JumpDirectionLabelNote, f_.labelOf(target).loc);
      return;
    }
    break;
  case JumpKind::Goto:
    diags_.report(Msg::GotoDirection, j.kwLoc, 4, jumpKindName(t > from ? JumpKind::Gotof : JumpKind::Gotob), j.label);
    break;
  }
  j.target = t;
}

/// The jumps of statement `i` (its own, its THEN's, its CASE arms').
void FileChecker::resolveJumpsOf(int32_t i, Stmt& s) {
  if ((s.kind == StmtKind::Jump || s.kind == StmtKind::If) && s.hasJump()) resolveJump(f_.jumpOf(s), i, false);
  if (s.inner >= 0) {
    Stmt& in = f_.inner[static_cast<size_t>(s.inner)];
    if (in.kind == StmtKind::Jump) resolveJump(f_.jumpOf(in), i, false);
  }
  if (s.kind == StmtKind::Case) {
    std::unordered_map<double, const CaseArm*> seen; // value (0 for -0) -> first arm
    for (CaseArm& arm : f_.armsOf(s)) {
      resolveJump(arm.jump, i, true);
      if (arm.isDefault) continue;
      auto [prev, inserted] = seen.emplace(arm.value == 0 ? 0.0 : arm.value, &arm);
      if (!inserted) {
        auto& d = diags_.report(Msg::CaseDuplicate, arm.valueLoc, 1, arm.value);
        d.note(Msg::CaseDuplicateNote, prev->second->valueLoc);
      }
    }
  }
}

void FileChecker::checkJumpsIntoBlocks() {
  // Innermost IF body (then or else range) of every label and the WHEN body of a statement:
  // one linear pass, then each jump is checked in O(log n) (jump targets are labels).
  // Nothing here is per statement: a CAM program of millions of lines has few labels.
  struct Range {
    int32_t lo, hi;
  };
  std::vector<Range> ranges;
  std::vector<int32_t> innerOfLabel(f_.labels.size(), -1);
  std::vector<int32_t> open;
  std::vector<int32_t> matchedEnds;
  matchedEnds.reserve(endifOf_.size());
  for (const auto& [ifIdx, endIdx] : endifOf_)
    matchedEnds.push_back(endIdx);
  std::sort(matchedEnds.begin(), matchedEnds.end());
  // matchedEnds, endifOf_ and File::labels are in statement order: read as `i` goes
  size_t nextEnd = 0, nextIf = 0, nextLabel = 0;
  auto isMatchedEnd = [&](int32_t i) {
    while (nextEnd < matchedEnds.size() && matchedEnds[nextEnd] < i)
      ++nextEnd;
    return nextEnd < matchedEnds.size() && matchedEnds[nextEnd] == i;
  };
  auto hasEndif = [&](int32_t i) {
    while (nextIf < endifOf_.size() && endifOf_[nextIf].first < i)
      ++nextIf;
    return nextIf < endifOf_.size() && endifOf_[nextIf].first == i;
  };
  auto labelIndex = [&](int32_t i) {
    while (nextLabel < f_.labels.size() && f_.labels[nextLabel].stmt < static_cast<uint32_t>(i))
      ++nextLabel;
    return nextLabel;
  };
  // z32 GO targets are statements, not labels: theirs are recorded on the same pass
  std::vector<int32_t> goTargets;
  for (const GoJump& g : f_.gos)
    if (g.target >= 0) goTargets.push_back(g.target);
  std::sort(goTargets.begin(), goTargets.end());
  goTargets.erase(std::unique(goTargets.begin(), goTargets.end()), goTargets.end());
  std::vector<int32_t> innerOfGo(goTargets.size(), -1);
  size_t nextGo = 0;
  for (int32_t i = 0; i < n_; ++i) {
    const Stmt& s = st(i);
    bool closes = (s.kind == StmtKind::Else && flow_.match[static_cast<size_t>(i)] >= 0) ||
                  (s.kind == StmtKind::EndIf && isMatchedEnd(i));
    if (closes) {
      if (!open.empty()) {
        ranges[static_cast<size_t>(open.back())].hi = i - 1;
        open.pop_back();
      }
    }
    if (s.hasLabel()) innerOfLabel[labelIndex(i)] = open.empty() ? -1 : open.back();
    while (nextGo < goTargets.size() && goTargets[nextGo] < i)
      ++nextGo;
    if (nextGo < goTargets.size() && goTargets[nextGo] == i) innerOfGo[nextGo] = open.empty() ? -1 : open.back();
    bool opens = (s.kind == StmtKind::If && s.inner < 0 && !s.hasJump() && hasEndif(i)) ||
                 (s.kind == StmtKind::Else && flow_.match[static_cast<size_t>(i)] >= 0);
    if (opens) {
      ranges.push_back({i + 1, n_ - 1});
      open.push_back(static_cast<int32_t>(ranges.size() - 1));
    }
  }
  // WHEN bodies are disjoint and found in file order (checkWhens)
  auto whenOf = [&](int32_t k) -> int32_t {
    auto it = std::upper_bound(whenBodies_.begin(), whenBodies_.end(), k,
                               [](int32_t v, const std::pair<int32_t, int32_t>& b) { return v < b.first; });
    if (it == whenBodies_.begin()) return -1;
    --it;
    return k <= it->second ? static_cast<int32_t>(it - whenBodies_.begin()) : -1;
  };
  auto outside = [&](int32_t r, int32_t from) {
    return r >= 0 && !(from >= ranges[static_cast<size_t>(r)].lo && from <= ranges[static_cast<size_t>(r)].hi);
  };
  auto check = [&](const Jump& j, int32_t from) {
    if (j.target < 0) return;
    int32_t wt = whenOf(j.target);
    if (wt >= 0 && whenOf(from) != wt) diags_.report(Msg::JumpIntoWhen, j.loc, j.len);
    const Stmt& target = st(j.target);
    int32_t r = target.hasLabel() ? innerOfLabel[f_.labelIndexOf(static_cast<uint32_t>(j.target))] : -1;
    if (outside(r, from)) {
      auto& d = diags_.report(Msg::JumpIntoBlock, j.loc, j.len, j.label);
      d.note(Msg::JumpIntoBlockNote, f_.labelOf(target).loc);
    }
  };
  // a GO range runs its body and returns: only its start is a jump into a body
  auto checkGo = [&](const GoJump& g, int32_t from) {
    if (g.target < 0) return;
    int32_t wt = whenOf(g.target);
    if (wt >= 0 && whenOf(from) != wt) diags_.report(Msg::JumpIntoWhen, g.fromLoc, g.fromLen);
    auto at = std::lower_bound(goTargets.begin(), goTargets.end(), g.target);
    if (outside(innerOfGo[static_cast<size_t>(at - goTargets.begin())], from)) {
      auto& d = diags_.report(Msg::JumpIntoBlockGo, g.fromLoc, g.fromLen, g.from);
      d.note(Msg::JumpIntoBlockGoNote, L(st(g.target).line));
    }
  };
  for (int32_t i = 0; i < n_; ++i) {
    const Stmt& s = st(i);
    if (s.hasJump()) check(f_.jumpOf(s), i);
    if (s.kind == StmtKind::Go) checkGo(f_.goOf(s), i);
    if (s.inner >= 0 && f_.inner[static_cast<size_t>(s.inner)].kind == StmtKind::Jump)
      check(f_.jumpOf(f_.inner[static_cast<size_t>(s.inner)]), i);
    if (s.kind == StmtKind::Case)
      for (const CaseArm& arm : f_.armsOf(s))
        check(arm.jump, i);
  }
}

} // namespace iso::frontend::checks
