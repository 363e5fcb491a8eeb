//! @file MoveStart.cpp
//! @brief Starting moves (path blocks, independent segments) and running G64 chains (SPEC §5).
#include "sim/Simulator.h"

#include <algorithm>
#include <bit>
#include <cassert>
#include <cmath>

#include <fmt/format.h>

#include "lang/GCodes.h"

namespace iso::sim {

// ============================================================================================
// motion

bool Simulator::doMove(size_t id, const Ins& in) {
  Thread& th = threads_[id];
  const uint32_t n = in.b;
  assert(th.stack.size() >= n); // verified
  const Modal& md = th.modal;
  double cur[kMaxAxes];
  for (int a = 0; a < nAxes_; ++a)
    cur[a] = curTarget(a);
  MoveRequest rq{.words = decodeMove(img_.code, in.a, n, th.stack.data() + (th.stack.size() - n), axisMap_, m_,
                                     md.incremental, cur, z32_ ? originOffset_.data() : nullptr),
                 .motion = md.motion,
                 .plane = md.plane,
                 .feed = md.feed,
                 .cur = cur};
  // A G64 chain holds interpolated feed blocks of the main program whose axes all block
  // (SPEC §5.2); anything else met while reading ahead ends the chain before its line.
  const MoveWords& w = rq.words;
  if (z32_) checkUnderControl(w.prog);
  if (searching_) return searchMove(id, w, n);
  const bool chainable = id == 0 && !th.body && md.continuous && th.pending.empty() && w.faMask == 0 && !w.anyNb &&
                         (lang::isArc(md.motion) || (md.motion == lang::kMotionLinear && w.progCount <= 3));
  if (chain_.collecting() && !chainable) {
    rollbackChain(id);
    return true;
  }
  th.stack.resize(th.stack.size() - n);
  MovePlan plan = planMove(rq, MoveLimits{&m_, &vmax_, &amax_, opts_.feedScale, opts_.rapidScale});
  if (plan.faIgnored) warnOnce("Fa on a G00 line is ignored");
  if (plan.feedCapped) feedCapped_.insert(th.stmt);
  MoveEnd end{now_, now_, -1};
  if (plan.path) {
    if (chain_.collecting()) return readAheadBlock(id, std::move(plan.block));
    checkBlock(plan.block);
    if (plan.block.plan.length > 0) {
      if (chainable) return beginChain(id, std::move(plan.block));
      startPathBlock(th, plan.block, w, end);
    }
  } else {
    startIndependent(th, plan, w, end);
  }
  if (!th.pending.empty()) {
    // The trigger's window is its blocking motion (a trigger with none: the whole block).
    arm(id, end.tBlock > now_ ? end.tBlock : end.tAll);
  }
  Thread& t2 = threads_[id];
  ++t2.pc;
  const AxisMotion* last = end.lastAxis >= 0 ? &axes_[static_cast<size_t>(end.lastAxis)] : nullptr;
  if (waitUntil(t2, end.tBlock, TimeCat::Accel, -1, last)) return true;
  return mustJoin(id);
}

void Simulator::startSegment(int ax, const AxisMotion& geom, const Trapezoid& prof, double tEnd, bool blocking,
                             const Modal& md, MoveEnd& end) {
  startAxis(ax, geom, prof, tEnd, md.motion, md.plane);
  end.tAll = std::max(end.tAll, tEnd);
  if (blocking && tEnd >= end.tBlock) {
    end.tBlock = tEnd;
    end.lastAxis = ax;
  }
}

void Simulator::startIndependent(const Thread& th, const MovePlan& plan, const MoveWords& w, MoveEnd& end) {
  moveStmt_ = th.stmt;
  for (int a = 0; a < nAxes_; ++a)
    if ((plan.check >> a) & 1u) checkNotMoving(a);
  for (int a = 0; a < nAxes_; ++a)
    if ((plan.check >> a) & 1u) checkLimit(a, w.tgt[a], w.tgt[a]);
  for (const auto& s : plan.segs)
    startSegment(s.axis, s.seg, s.seg.prof, now_ + s.seg.prof.duration(), s.blocking, th.modal, end);
  if (prof_ && end.lastAxis >= 0) {
    const AxisMotion& la = axes_[static_cast<size_t>(end.lastAxis)];
    const char letter = m_.axes[static_cast<size_t>(end.lastAxis)].letter;
    const double scale = th.modal.motion == lang::kMotionRapid ? opts_.rapidScale : 1.0;
    const bool atVmax = la.prof.vPeak >= vmax_[static_cast<size_t>(end.lastAxis)] * scale;
    rec_.bound(th.stmt,
               boundLabel(la.prof, atVmax ? SpeedBound::AxisVelocity : SpeedBound::Feed, letter, letter, false));
  }
}

void Simulator::startPathBlock(const Thread& th, const PathBlock& pb, const MoveWords& w, MoveEnd& end) {
  moveStmt_ = th.stmt;
  const Trapezoid prof = makeTrapezoid(pb.plan.length, pb.plan.vmax, pb.plan.accel);
  if (prof_) rec_.bound(th.stmt, pathBoundLabel(pb, prof, false));
  const double tEnd = now_ + prof.duration();
  for (const auto& s : pb.segs)
    startSegment(s.axis, s.seg, prof, tEnd, !w.nb[s.axis], th.modal, end);
}

bool Simulator::readAheadBlock(size_t id, PathBlock pb) {
  // read ahead: the block joins the chain; its checks run when the path reaches it
  Thread& th = threads_[id];
  ++th.pc;
  if (pb.plan.length > 0)
    appendChainBlock(th, std::move(pb));
  else
    chain_.appendZeroLength(std::move(pb), th.stmt);
  snapshotChain(th);
  if (chain_.full(m_.lookaheadBlocks)) {
    finalizeChain(id);
    return true;
  }
  return false;
}

bool Simulator::beginChain(size_t id, PathBlock pb) {
  // the first block of a G64 chain: read ahead before anything moves
  Thread& th = threads_[id];
  ++th.pc;
  double targets[kMaxAxes];
  for (int a = 0; a < nAxes_; ++a)
    targets[a] = axes_[static_cast<size_t>(a)].target;
  chain_.begin(targets, nAxes_);
  appendChainBlock(th, std::move(pb));
  snapshotChain(th);
  if (m_.lookaheadBlocks <= 1) {
    finalizeChain(id);
    return true;
  }
  return false;
}

double Simulator::curTarget(int ax) const {
  return chain_.collecting() ? chain_.predicted(ax) : axes_[static_cast<size_t>(ax)].target;
}

void Simulator::checkNotMoving(int ax) const {
  const AxisMotion& a = axes_[static_cast<size_t>(ax)];
  if (a.moving(now_))
    emergency(fmt::format("axis {} programmed while moving (it moves to {} until t={} s)",
                          m_.axes[static_cast<size_t>(ax)].letter, num(a.target), num(a.tEnd)));
}

void Simulator::checkLimit(int ax, double lo, double hi) const {
  const machine::Axis& A = m_.axes[static_cast<size_t>(ax)];
  const bool below = lo < A.limitMinus - kLimitTolerance;
  if (below || hi > A.limitPlus + kLimitTolerance) {
    // shortest round-trip form: a target just past the limit must not print as the limit
    emergency(fmt::format("soft limit: axis {} would reach {}, outside [{}, {}]", A.letter, below ? lo : hi,
                          A.limitMinus, A.limitPlus));
  }
}

void Simulator::checkAxes(uint32_t mask, const PathBlock::LimitList& limits) const {
  for (uint32_t bits = mask; bits != 0; bits &= bits - 1)
    checkNotMoving(std::countr_zero(bits));
  for (const auto& l : limits)
    checkLimit(l.axis, l.lo, l.hi);
}

void Simulator::startAxis(int ax, const AxisMotion& geom, const Trapezoid& prof, double tEnd, uint8_t motion,
                          uint8_t plane) {
  // written in place (the segment is not completed in a copy first: fewer bytes moved, and no
  // wide reads of fields just written)
  AxisMotion& seg = axes_[static_cast<size_t>(ax)];
  zoneDirty_ |= 1u << ax;
  axisStmt_[static_cast<size_t>(ax)] = moveStmt_;
  seg = geom;
  seg.t0 = now_;
  seg.prof = prof;
  seg.tEnd = tEnd;
  if (events_) {
    Event e;
    e.kind = EventKind::MoveStart;
    e.axis = m_.axes[static_cast<size_t>(ax)].letter;
    e.target = seg.target;
    e.motion = motion;
    e.plane = plane;
    emit(e);
    moveEnds_.push_back({seg.tEnd, moveOrder_++, ax, seg.target});
  }
}

// ============================================================================================
// G64 chains (SPEC §5.2): read ahead, plan, then run block by block

void Simulator::appendChainBlock(const Thread& th, PathBlock pb) {
  if (prof_) stackProcs(th, pb.procs);
  chain_.append(std::move(pb), th.stmt);
}

void Simulator::snapshotChain(const Thread& th) { chain_.snapshot(th, ms_.markR(), steps_, rec_.mark()); }

void Simulator::rollbackChain(size_t id) {
  ++debugRollbacks_;
  const ChainSnapshot& s = chain_.restore(threads_[id]);
  ms_.rollbackR(s.rUndo);
  lines_ -= steps_ - s.steps; // the statements read ahead since the snapshot run again
  steps_ = s.steps;
  rec_.rollback(s.profUndo);
  finalizeChain(id);
}

void Simulator::finalizeChain(size_t id) {
  ms_.commitR();
  rec_.commit();
  chain_.plan(amax_, m_.cornerDeviationMm);
  startChainBlock(id);
}

void Simulator::startChainBlock(size_t id) {
  Thread& th = threads_[id];
  PathBlock& b = chain_.current();
  const PlannedBlock& planned = chain_.currentPlan();
  const Trapezoid& prof = planned.profile;
  const double tEnd = now_ + prof.duration();
  th.stmt = b.stmt;
  moveStmt_ = b.stmt;
  for (const auto& s : b.segs)
    startAxis(s.axis, s.seg, prof, tEnd, 1, th.modal.plane); // chains hold feed moves only (lines or arcs)
  if (prof_) {
    const bool corner = planned.entryBound == JunctionBound::Corner || planned.exitBound == JunctionBound::Corner;
    rec_.bound(b.stmt, pathBoundLabel(b, prof, corner));
  }
  // (a block too short to take time at this instant is over at once: the thread stays runnable
  // and its next run is the junction)
  if (waitUntil(th, tEnd, TimeCat::Accel, -1, &axes_[static_cast<size_t>(b.segs.front().axis)]) && prof_)
    rec_.setProcs(b.procs); // the call stack when the block was read, not after reading ahead
}

bool Simulator::chainJunction(size_t id) {
  // The path has reached the end of the current block: the statements read ahead after it run
  // now (their line events carry this instant), then the next block starts (its checks first).
  {
    const PathBlock& b = chain_.current();
    if (events_)
      for (uint32_t pc : b.after)
        emitLine(pc);
    for (const auto& z : b.zeroChecks) {
      threads_[id].stmt = z.stmt;
      checkAxes(z.mask, z.limits);
    }
  }
  if (!chain_.advance()) return false;
  threads_[id].stmt = chain_.current().stmt;
  checkBlock(chain_.current());
  startChainBlock(id);
  return true;
}

// ============================================================================================
// crash zones: the first instant the commanded path is inside a zone on every axis it bounds

void Simulator::updateZones() {
  if (searching_ || stopped_ || zoneDirty_ == 0) return;
  for (size_t z = 0; z < m_.zones.size(); ++z)
    if (zoneMask_[z] & zoneDirty_) planZone(z);
  zoneDirty_ = 0;
}

void Simulator::planZone(size_t z) {
  TimeIntervals in{{now_, kInf}};
  for (const machine::ZoneAxis& za : m_.zones[z].axes) {
    const int ax = m_.axisIndex(za.letter);
    if (ax < 0) continue;
    in = intersectIntervals(in, insideIntervals(axes_[static_cast<size_t>(ax)], za.min, za.max, now_));
    if (in.empty()) break;
  }
  if (in.empty() || in.front().first > now_) {
    zoneIn_[z] = 0; // outside now: the next entry is the start of the next stay
    zoneDue_[z] = in.empty() ? kInf : in.front().first;
  } else {
    // inside now: an entry now, unless this stay was already reported
    zoneDue_[z] = !zoneIn_[z] ? now_ : in.size() > 1 ? in[1].first : kInf;
  }
}

void Simulator::enterZonesAt(double t) {
  for (size_t z = 0; z < m_.zones.size(); ++z) {
    if (!(zoneDue_[z] <= t)) continue;
    const machine::Zone& zone = m_.zones[z];
    // the statement of the latest segment of the zone's axes (none moved yet: the main program)
    uint32_t ctx = kNoIndex;
    double latest = -kInf;
    std::string where;
    double pos[kMaxAxes] = {};
    for (size_t i = 0; i < zone.axes.size(); ++i) {
      const int ax = m_.axisIndex(zone.axes[i].letter);
      const AxisMotion& a = axes_[static_cast<size_t>(ax)];
      pos[i] = a.positionAt(now_);
      where += fmt::format("{}{}={}", i ? " " : "", zone.axes[i].letter, num(pos[i]));
      if (axisStmt_[static_cast<size_t>(ax)] != kNoIndex && a.t0 > latest) {
        latest = a.t0;
        ctx = axisStmt_[static_cast<size_t>(ax)];
      }
    }
    if (ctx == kNoIndex) ctx = mainContext();
    std::string_view file;
    uint32_t line = 0;
    fileLineOf(ctx, file, line);
    if (events_) {
      Event e;
      e.kind = EventKind::Zone;
      e.file = file;
      e.line = line;
      e.zone = &zone;
      e.zonePosition = pos;
      emit(e);
    }
    if (zone.forbidden) {
      stopWith(Status::Emergency, fmt::format("{} enters the forbidden zone '{}'", where, zone.name), ctx);
      return;
    }
    zoneIn_[z] = 1;
    if (!zoneWarned_[z]) {
      zoneWarned_[z] = 1;
      warnings_.push_back(
          fmt::format("the tool entered zone '{}' at {} (t={} s) at {}", zone.name, locationOf(ctx), num(now_), where));
    }
    planZone(z);
  }
}

} // namespace iso::sim
