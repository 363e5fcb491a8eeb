//! @file When.cpp
//! @brief WHEN chains (E212, E213): bodies, chain length, triggers and their axes.
#include "frontend/checks/FileChecker.h"

#include "lang/Limits.h"

namespace iso::frontend::checks {

using diag::Msg;

FileChecker::BodyCheck FileChecker::bodyForbidden(const File& f, const Stmt& s) const {
  if (s.hasLabel()) return {Forbidden::Label};
  switch (s.kind) {
  case StmtKind::Jump:
  case StmtKind::Go: return {Forbidden::Jump}; // z32: GO jumps and ranges too
  case StmtKind::Case: return {Forbidden::Case};
  case StmtKind::Call: return {Forbidden::Call};
  case StmtKind::When: return {Forbidden::When};
  case StmtKind::If: return {s.hasJump() ? Forbidden::Jump : Forbidden::None};
  case StmtKind::Block:
    if (hasM(f, s, lang::kMReturn)) return {Forbidden::EndM, lang::kMReturn};
    if (hasM(f, s, lang::kMEnd)) return {Forbidden::EndM, lang::kMEnd};
    if (isZ32() && hasM(f, s, lang::kMEndZ32)) return {Forbidden::EndM, lang::kMEndZ32}; // z32: M2 ends like M30
    if (specialOn(s)) return {Forbidden::SpecialM};
    if (isZ32() && hasKg(s)) return {Forbidden::Kg};
    if (isZ32() && z32Return(s)) return {Forbidden::Return};
    return {};
  default: return {};
  }
}

void FileChecker::reportForbidden(const Loc& at, BodyCheck c) {
  switch (c.what) {
  case Forbidden::None: break;
  case Forbidden::Label: diags_.report(Msg::WhenBodyLabel, at, 1); break;
  case Forbidden::Jump: diags_.report(Msg::WhenBodyJump, at, 1); break;
  case Forbidden::Case: diags_.report(Msg::WhenBodyCase, at, 1); break;
  case Forbidden::Call: diags_.report(Msg::WhenBodyCall, at, 1); break;
  case Forbidden::When: diags_.report(Msg::WhenBodyWhen, at, 1); break;
  case Forbidden::EndM: diags_.report(Msg::WhenBodyEndM, at, 1, c.m); break;
  case Forbidden::SpecialM: diags_.report(Msg::WhenBodySpecialM, at, 1); break;
  case Forbidden::Kg: diags_.report(Msg::WhenBodyKg, at, 1); break;
  case Forbidden::Return: diags_.report(Msg::WhenBodyReturn, at, 1); break;
  }
}

void FileChecker::checkTriggerAxis(int32_t whenIdx, const Stmt& trigger) {
  const Stmt& when = st(whenIdx);
  const std::string_view axes = f_.whenAxesOf(static_cast<uint32_t>(whenIdx));
  if (axes.empty()) {
    diags_.report(Msg::WhenReadsNoAxis, when.loc, 4, sysVarName(SysVar::AaIw));
    return;
  }
  for (char a : axes) {
    const uint32_t bit = a >= 'A' && a <= 'Z' ? uint32_t{1} << (a - 'A') : 0;
    const bool moved = (trigger.movedAxes & bit) != 0, posa = (trigger.posaAxes & bit) != 0;
    if (!moved) {
      auto& d = posa ? diags_.report(Msg::TriggerPosa, when.loc, 4, a, a, a)
                     : diags_.report(Msg::TriggerNoMove, when.loc, 4, a, sysVarName(SysVar::AaIw));
      d.note(Msg::TriggerNote, trigger.loc);
    }
  }
}

void FileChecker::checkWhens() {
  int32_t i = 0;
  while (i < n_) {
    const Stmt& s = st(i);
    if (isKind(s, StmtKind::Cancel)) {
      diags_.report(Msg::CancelWithoutWhen, s.loc, 6);
      ++i;
      continue;
    }
    if (s.kind == StmtKind::Invalid && s.recoverAs == StmtKind::When) {
      // A long-form WHEN whose line failed to parse: skip its body and CANCEL.
      int32_t k = i + 1;
      while (k < n_ && !isKind(st(k), StmtKind::Cancel) && !isKind(st(k), StmtKind::When))
        ++k;
      i = k < n_ && isKind(st(k), StmtKind::Cancel) ? k + 1 : i + 1;
      continue;
    }
    if (s.kind != StmtKind::When) {
      ++i;
      continue;
    }
    // A chain: WHEN [body CANCEL] { WHEN ... } trigger
    std::vector<int32_t> chain;
    std::vector<const Stmt*> bodies; // the single path instruction of each inner body, or null
    int32_t j = i;
    bool broken = false;
    while (j < n_ && st(j).kind == StmtKind::When) {
      const Stmt& w = st(j);
      if (!chain.empty() && w.hasLabel()) diags_.report(Msg::WhenChainLabel, f_.labelOf(w).loc, 1);
      chain.push_back(j);
      const Stmt* single = nullptr;
      int bodyCount = 0;
      int32_t next;
      if (w.inner >= 0) {
        const Stmt& in = f_.inner[static_cast<size_t>(w.inner)];
        reportForbidden(in.loc, bodyForbidden(f_, in));
        single = &in;
        bodyCount = 1;
        next = j + 1;
      } else {
        int32_t k = j + 1;
        while (k < n_ && !isKind(st(k), StmtKind::Cancel) && st(k).kind != StmtKind::When)
          ++k;
        if (k < n_ && st(k).kind == StmtKind::When) {
          diags_.report(Msg::WhenInWhenBody, st(k).loc, 4);
          broken = true;
          j = j + 1;
          break;
        }
        if (k >= n_) {
          // Body checks would only repeat this error: the body's end is unknown.
          diags_.report(Msg::WhenWithoutCancel, w.loc, 4);
          broken = true;
          j = j + 1;
          break;
        }
        for (int32_t b = j + 1; b < k; ++b) {
          const Stmt& bs = st(b);
          if (bs.kind == StmtKind::Empty && !bs.hasLabel()) continue;
          const BodyCheck c = bodyForbidden(f_, bs);
          reportForbidden(c.what == Forbidden::Label ? f_.labelOf(bs).loc : bs.loc, c);
          ++bodyCount;
          single = &bs;
        }
        flow_.match[static_cast<size_t>(j)] = k;
        next = k + 1;
      }
      bodies.push_back(bodyCount == 1 ? single : nullptr);
      (void)bodyCount;
      // skip blank and comment lines
      while (next < n_ && st(next).kind == StmtKind::Empty && !st(next).hasLabel())
        ++next;
      j = next;
    }
    if (broken) {
      i = j;
      continue;
    }
    i = checkWhenChain(chain, bodies, j);
  }
}

/// A parsed WHEN chain (`chain`: its WHEN lines, `bodies`: each inner body's one statement)
/// before the statement `j`: the chain length, the inner bodies, the trigger. Returns where
/// the next WHEN may start.
int32_t FileChecker::checkWhenChain(const std::vector<int32_t>& chain, std::vector<const Stmt*>& bodies, int32_t j) {
  if (chain.size() > static_cast<size_t>(lang::kMaxWhenChain)) {
    auto& d =
        diags_.report(Msg::WhenChainTooLong, st(chain[lang::kMaxWhenChain]).loc, 4, lang::kMaxWhenChain, chain.size());
    d.note(Msg::WhenChainStartNote, st(chain[0]).loc);
  }
  // inner bodies (every WHEN but the first written) must be exactly one path instruction
  for (size_t c = 1; c < chain.size(); ++c) {
    const Stmt* b = bodies[c];
    if (!b || !b->hasMotion()) {
      diags_.report(Msg::WhenChainBody, st(chain[c]).loc, 4);
      bodies[c] = nullptr;
    }
  }
  // the trigger
  if (j >= n_ || st(j).kind != StmtKind::Block || !st(j).hasMotion()) {
    const Stmt& last = st(chain.back());
    diags_.report(Msg::WhenWithoutTrigger, j < n_ ? st(j).loc : last.loc, 4);
    return j;
  }
  const Stmt& trigger = st(j);
  if (trigger.hasLabel()) diags_.report(Msg::WhenTriggerLabel, f_.labelOf(trigger).loc, 1);
  checkTriggerAxis(chain.back(), trigger);
  for (size_t c = 0; c + 1 < chain.size(); ++c)
    if (bodies[c + 1]) checkTriggerAxis(chain[c], *bodies[c + 1]);
  for (int32_t c : chain) {
    int32_t cancel = flow_.match[static_cast<size_t>(c)];
    if (cancel > c) whenBodies_.push_back({c + 1, cancel - 1});
  }
  return j + 1;
}

} // namespace iso::frontend::checks
