//! @file WhenArm.cpp
//! @brief WHEN anticipations: arming, checking, firing and dropping (SPEC §6).
#include "sim/Simulator.h"

#include <algorithm>
#include <cassert>
#include <cmath>

#include <fmt/format.h>

namespace iso::sim {

// ============================================================================================
// WHEN anticipations

void Simulator::arm(size_t id, double windowEnd) {
  Thread& th = threads_[id];
  Armed a;
  a.when = th.pending.back();
  a.chain.assign(th.pending.begin(), th.pending.end() - 1);
  th.pending.clear();
  a.windowEnd = windowEnd;
  a.modal = th.modal;
  if (th.body) {
    a.group = th.group;
  } else {
    a.group = newGroup();
    th.join = a.group;
  }
  ++groups_[static_cast<size_t>(a.group)].armed;
  a.readsIw = prog_.readsIw(prog_[a.when].a);
  if (events_) emitWhen(a.when, "armed");
  armed_.push_back(std::move(a));
}

void Simulator::emitWhen(uint32_t when, const char* action, uint32_t thread) {
  Event e;
  e.kind = EventKind::When;
  e.action = action;
  e.thread = thread;
  fileLineOf(when, e.file, e.line);
  emit(e);
}

bool Simulator::evalCond(uint32_t pc, double t, int* classes, size_t* nClasses) const {
  // The verifier bounds every stack, conditions included, by the same constant.
  double st[image::kMaxStackDepth];
  size_t sp = 0;
  size_t nc = 0;
  auto push = [&](double v) {
    assert(sp < image::kMaxStackDepth);
    st[sp++] = v;
  };
  auto pop = [&]() -> double {
    assert(sp > 0);
    return st[--sp];
  };
  auto onCmp = [&](double a, double b) {
    if (classes && nc < kMaxRecordedCmp) classes[nc] = cmpClass(a, b);
    ++nc;
  };
  for (;; ++pc) {
    const Ins in = prog_[pc];
    countWork(1);
    if (valueOp(in, push, pop, onCmp)) continue;
    switch (in.op) {
    case Op::LoadAxVar: push(axVar(in.a8, in.b8, t)); break;
    case Op::CondEnd:
      if (nClasses) *nClasses = std::min(nc, kMaxRecordedCmp);
      return pop() != 0;
    default: internal("a WHEN condition holds an instruction that is not an expression (malformed image)");
    }
  }
}

bool Simulator::checkWhensAt() {
  bool changed = false;
  for (size_t i = 0; i < armed_.size();) {
    const uint32_t cond = prog_[armed_[i].when].a;
    if (evalCond(cond, now_, nullptr, nullptr)) {
      fire(i);
      changed = true;
      continue;
    }
    if (armed_[i].windowEnd <= now_) {
      drop(i);
      changed = true;
      continue;
    }
    ++i;
  }
  return changed;
}

void Simulator::fire(size_t i) {
  Armed a = std::move(armed_[i]);
  armed_.erase(armed_.begin() + static_cast<std::ptrdiff_t>(i));
  Group& g = groups_[static_cast<size_t>(a.group)];
  --g.armed;
  ++g.live;
  ++bodySerial_;
  if (events_) emitWhen(a.when, "fired", bodySerial_);
  size_t id = spawn();
  Thread& th = threads_[id];
  th.serial = bodySerial_;
  th.when = a.when;
  th.pc = prog_[a.when].b;
  th.modal = a.modal;
  th.group = a.group;
  th.body = true;
  th.pending = std::move(a.chain);
  th.stmt = a.when;
  th.state = TState::Runnable;
}

void Simulator::drop(size_t i) {
  Armed a = std::move(armed_[i]);
  armed_.erase(armed_.begin() + static_cast<std::ptrdiff_t>(i));
  --groups_[static_cast<size_t>(a.group)].armed;
  if (events_) emitWhen(a.when, "dropped");
  groupCheck(a.group);
}

Simulator::Found Simulator::searchWhens(double a, double b) {
  Found best;
  for (size_t i = 0; i < armed_.size(); ++i) {
    if (!armed_[i].readsIw) continue; // nothing it reads changes between events
    const double end = std::min(b, armed_[i].windowEnd);
    if (!(end > a)) continue;
    Found f = searchOne(i, a, best.found ? std::min(end, std::nextafter(best.t, kInf)) : end);
    if (f.found && (!best.found || f.t < best.t)) best = std::move(f);
  }
  return best;
}

Simulator::Found Simulator::searchOne(size_t i, double a, double b) {
  // Watches the condition over the open interval (a, b), where only axis positions change.
  struct Condition final : WhenCondition {
    Condition(const Simulator& sim, uint32_t pc) : sim_(sim), pc_(pc) {}
    bool holds(double t, int* classes, size_t* n) const override { return sim_.evalCond(pc_, t, classes, n); }
    const Simulator& sim_;
    uint32_t pc_;
  };
  const WhenHit hit = searchCondition(Condition(*this, prog_[armed_[i].when].a), a, b, axes_, m_.ipoCycleS);
  Found out;
  out.index = i;
  out.found = hit.found;
  out.t = hit.t;
  out.error = hit.error;
  out.fault = hit.fault;
  return out;
}

} // namespace iso::sim
