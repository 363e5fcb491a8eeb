//! @file Search.cpp
//! @brief Block search (isosim --search, SPEC §4.8): the lines of the entry program before the
//!        found line run in search mode, then the run goes on normally from that line.
//!
//! Search mode runs every statement as written, in zero time and without events:
//!   - each programmed axis takes its target at once (no profile; a target outside the soft
//!     limits is still an emergency, the path is not checked; a feed move needs no F);
//!   - R, PAR, PAL and user parameters, modal G and F, origins, S, T, TA and TB, outputs and
//!     markers are computed as written; G04 and real-time reads do not wait (time stays 0);
//!   - M functions, MA, MB and MC are not sent: no duration, no set_inputs, no m events; in
//!     dialect z32 the spindle, coolant and tool functions (M3 M4 M5 M6 M7 M8 M9 M19) still
//!     change the state they report, so the spindle, the coolants and the mounted tool at the
//!     found line are the ones the skipped lines programmed; M0 and M1 neither stop nor stop
//!     the spindle;
//!   - calls, GOP, GO ranges and special M run their statements in search mode (one block);
//!   - WHENs are not armed (their bodies never run);
//!   - the end of the program (M30, M2, the end of the main program) before the found line is
//!     a runtime error: the search did not reach its line.
//! At the found line the state the search collected is output at t = 0: one output/marker
//! event per index written while searching (its last value), then, in z32, the spindle (when
//! it turns or is oriented), the coolants (when one is on) and the mounted tool (when there
//! is one: it counts as one tool change). Time, `blocks`, events and the trace start there.
#include "sim/Simulator.h"

#include <cmath>

#include <fmt/format.h>

namespace iso::sim {

bool Simulator::searchOp(Thread& th, const Ins& in) {
  switch (in.op) {
  case Op::Sync: // real-time reads see time 0
  case Op::M0:
  case Op::M1:
  case Op::When: ++th.pc; return true;
  case Op::Dwell: {
    const double d = pop(th);
    if (!(d >= 0) || !std::isfinite(d)) fault(fmt::format("G04 dwell time {} s is not a duration >= 0", valueText(d)));
    ++th.pc;
    return true;
  }
  case Op::M:
  case Op::MNb: searchM(th, in); return true;
  case Op::Aux: takeAux(th, in); return true; // not sent
  case Op::End:
  case Op::EndImplicit: fault(searchNotReached());
  default: return false;
  }
}

bool Simulator::searchFound(const Ins& in) const {
  return in.c != kNoIndex && img_.lines[in.c].offset == opts_.search->offset;
}

std::string Simulator::searchNotReached() const {
  const SearchInfo& w = opts_.search->where;
  return fmt::format("the program ended before the searched line {}:{} (--search {})", w.file, w.line, w.text);
}

bool Simulator::searchMove(size_t id, const MoveWords& w, uint32_t n) {
  Thread& th = threads_[id];
  th.stack.resize(th.stack.size() - n);
  for (int a = 0; a < nAxes_; ++a)
    if ((w.prog >> a) & 1u) checkLimit(a, w.tgt[a], w.tgt[a]);
  for (int a = 0; a < nAxes_; ++a)
    if ((w.prog >> a) & 1u) axes_[static_cast<size_t>(a)].stopAt(now_, w.tgt[a]);
  th.pending.clear();
  ++th.pc;
  return false;
}

void Simulator::searchM(Thread& th, const Ins& in) {
  ++th.pc;
  if (!z32_) return;
  const auto mnum = static_cast<uint64_t>(in.value());
  const lang::MRole role =
      lang::mRole(static_cast<int64_t>(std::min<uint64_t>(mnum, lang::kMaxMNumber + 1)), lang::Dialect::Z32);
  switch (role) {
  case lang::MRole::Plain:
  case lang::MRole::Stop:
  case lang::MRole::OptionalStop:
  case lang::MRole::End:
  case lang::MRole::Return: return;
  default: z32Report(zs_.apply(role, now_, m_.optionalStop), th.stmt);
  }
}

void Simulator::endSearch(bool found) {
  searching_ = false;
  events_ = searchEvents_;
  // the tool changes of the search do not count; the tool mounted at the found line does
  const uint64_t changes = zs_.toolChanges();
  searchToolChanges_ = found && zs_.tool() && changes > 0 ? changes - 1 : changes;
  if (!found || !events_) return;
  for (const auto& [key, value] : searchIo_)
    emit({.kind = key.first ? EventKind::Marker : EventKind::Output, .index = key.second, .value = value});
  if (!z32_) return;
  Z32State::Change c;
  c.spindle = zs_.dir() != SpindleDir::Stop;
  c.coolant = zs_.coolant1() || zs_.coolant2();
  c.tool = zs_.tool().has_value();
  z32Report(c, threads_[0].stmt);
}

} // namespace iso::sim
