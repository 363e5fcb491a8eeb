//! @file MovePlanner.cpp
//! @brief The pure move planner of isosim (MovePlanner.h).
#include "sim/MovePlanner.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "lang/GCodes.h"
#include "sim/MotionProfile.h"
#include "sim/RunMath.h"

namespace iso::sim {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// A linear segment of axis 0, every member at its default (SegKind::Linear is the default).
constexpr PathBlock::Seg kBlankLinearSeg{0, AxisMotion{}};
static_assert(AxisMotion{}.kind == SegKind::Linear);

bool has(uint32_t mask, int a) { return ((mask >> a) & 1u) != 0; }

char letterOf(const MoveLimits& lim, int a) { return lim.m->axes[static_cast<size_t>(a)].letter; }

double feedOrFault(double feed) {
  if (std::isnan(feed)) fault("feed move without F: no F was ever set (F is modal, in mm/s)");
  if (!(feed > 0)) fault(fmt::format("feed move with F={} mm/s: F must be > 0", valueText(feed)));
  return feed;
}

/// Circular interpolation in the active plane (G02/G03).
void planArc(const MoveRequest& rq, const MoveLimits& lim, PathBlock& pb) {
  const MoveWords& w = rq.words;
  const machine::Machine& m = *lim.m;
  const int nAxes = static_cast<int>(m.axes.size());
  const lang::PlaneAxes pa = lang::planeAxes(rq.plane);
  const char pl = pa.p, ql = pa.q;
  const int ciWord = pa.pWord, cjWord = pa.qWord; // I J K index of the p and q offsets
  const int p = m.axisIndex(pl), q = m.axisIndex(ql);
  if (p < 0 || q < 0)
    fault(fmt::format("an arc in G{} needs axes {} and {}; the machine has no axis {}", rq.plane, pl, ql,
                      p < 0 ? pl : ql));
  for (int a = 0; a < nAxes; ++a) {
    if (!has(w.prog, a)) continue;
    if (a != p && a != q)
      fault(fmt::format("axis {} is not in the plane G{} ({}{}): an arc moves exactly the two plane axes",
                        letterOf(lim, a), rq.plane, pl, ql));
    if (w.nb[a]) fault("Posa on an arc: arc axes move blocking");
  }
  if (w.faMask) fault("Fa on an arc: an arc runs at the path feed F");
  for (int k = 0; k < 3; ++k)
    if (w.arcWord[k] && k != ciWord && k != cjWord)
      fault(fmt::format("centre word {} does not belong to plane G{}", "IJK"[k], rq.plane));
  const bool ijk = w.arcWord[ciWord] || w.arcWord[cjWord];
  if (!ijk && !w.arcWord[3]) fault(fmt::format("arc (G0{}) without centre (I/J/K) or radius (CR)", rq.motion));
  if (ijk && w.arcWord[3]) fault("arc with both centre (I/J/K) and radius (CR)");
  const double feed = feedOrFault(rq.feed) * lim.feedScale;
  ArcRequest ar;
  ar.p0 = rq.cur[p];
  ar.q0 = rq.cur[q];
  ar.p1 = has(w.prog, p) ? w.tgt[p] : ar.p0;
  ar.q1 = has(w.prog, q) ? w.tgt[q] : ar.q0;
  ar.ccw = rq.motion == lang::kMotionArcCcw;
  ar.byRadius = w.arcWord[3];
  ar.ci = w.arcVal[ciWord];
  ar.cj = w.arcVal[cjWord];
  ar.cr = w.arcVal[3];
  const support::Expected<ArcGeom> arc = makeArc(ar);
  if (!arc) fault(arc.error().message);
  const ArcGeom& g = *arc;
  double pMin, pMax, qMin, qMax;
  arcExtremes(g, pMin, pMax, qMin, qMax);
  pb.check = (1u << p) | (1u << q);
  pb.limits.push_back({p, pMin, pMax});
  pb.limits.push_back({q, qMin, qMax});
  const auto up = static_cast<size_t>(p), uq = static_cast<size_t>(q);
  const std::vector<double>& vmax = *lim.vmax;
  const std::vector<double>& amax = *lim.amax;
  const ArcLimits al = arcLimits(g.r0, g.sweep, feed, vmax[up], vmax[uq], amax[up], amax[uq]);
  pb.plan.length = al.length;
  pb.plan.vmax = al.vmax;
  pb.plan.accel = al.accel;
  pb.vBound = al.vBound;
  pb.vAxis = al.vAxis < 0 ? -1 : al.vAxis == 0 ? p : q;
  pb.aAxis = al.aAxis == 0 ? p : q;
  pb.plan.uStart.assign(static_cast<size_t>(nAxes), 0.0);
  pb.plan.uEnd.assign(static_cast<size_t>(nAxes), 0.0);
  const double len = g.length();
  const double n0 = std::hypot(g.dp(0), g.dq(0)), n1 = std::hypot(g.dp(len), g.dq(len));
  if (n0 > 0) {
    pb.plan.uStart[up] = g.dp(0) / n0;
    pb.plan.uStart[uq] = g.dq(0) / n0;
  }
  if (n1 > 0) {
    pb.plan.uEnd[up] = g.dp(len) / n1;
    pb.plan.uEnd[uq] = g.dq(len) / n1;
  }
  AxisMotion seg;
  seg.arc = g;
  seg.kind = SegKind::ArcP;
  seg.start = ar.p0;
  seg.target = ar.p1;
  pb.segs.push_back({p, seg});
  seg.kind = SegKind::ArcQ;
  seg.start = ar.q0;
  seg.target = ar.q1;
  pb.segs.push_back({q, seg});
}

/// An interpolated line (G01, <= 3 axes, no Fa).
void planLine(const MoveRequest& rq, const MoveLimits& lim, PathBlock& pb) {
  const MoveWords& w = rq.words;
  const auto nAxes = lim.m->axes.size();
  pb.check = w.prog;
  double delta[kMaxMoveAxes];
  uint32_t moving = 0; // the axes with a non-zero delta (programmed ones only)
  bool anyDelta = false;
  for (uint32_t bits = w.prog; bits != 0; bits &= bits - 1) { // the programmed axes, in order
    const int a = std::countr_zero(bits);
    pb.limits.push_back({a, w.tgt[a], w.tgt[a]});
    delta[a] = w.tgt[a] - rq.cur[a];
    if (delta[a] != 0) moving |= 1u << a;
    anyDelta = anyDelta || w.tgt[a] != rq.cur[a];
  }
  if (!anyDelta) return;
  const double feed = feedOrFault(rq.feed) * lim.feedScale;
  LineLimits ll;
  AxisValues& dir = pb.plan.uStart;
  dir.assign(nAxes, 0.0);
  lineLimitsInto(delta, moving, lim.vmax->data(), lim.amax->data(), feed, ll, dir.data());
  pb.plan.length = ll.length;
  pb.plan.vmax = ll.vmax;
  pb.plan.accel = ll.accel;
  pb.plan.uEnd = dir;
  pb.vBound = ll.vBound;
  pb.vAxis = ll.vAxis;
  pb.aAxis = ll.aAxis;
  for (uint32_t bits = moving; bits != 0; bits &= bits - 1) {
    const int a = std::countr_zero(bits);
    // filled in place: a segment built on the stack and then copied costs store-forwarding stalls
    pb.segs.push_back(kBlankLinearSeg);
    PathBlock::Seg& s = pb.segs.back();
    s.axis = a;
    s.seg.start = s.seg.base = rq.cur[a];
    s.seg.scale = dir[static_cast<size_t>(a)];
    s.seg.target = w.tgt[a];
  }
}

/// Axes moving each on its own (G00; G01 with Fa or more than 3 axes).
void planIndependent(const MoveRequest& rq, const MoveLimits& lim, MovePlan& out) {
  const MoveWords& w = rq.words;
  const int nAxes = static_cast<int>(lim.m->axes.size());
  const bool rapid = rq.motion == lang::kMotionRapid;
  double feed = kNaN;
  if (!rapid) {
    for (int a = 0; a < nAxes; ++a)
      if (has(w.prog, a) && !has(w.faMask, a) && w.tgt[a] != rq.cur[a]) feed = feedOrFault(rq.feed) * lim.feedScale;
    for (int a = 0; a < nAxes; ++a)
      if (has(w.faMask, a) && !(w.fa[a] > 0))
        fault(fmt::format("Fa[{}]={} mm/s: a feed must be > 0", letterOf(lim, a), valueText(w.fa[a])));
  }
  out.check = w.prog;
  for (int a = 0; a < nAxes; ++a) {
    const auto ua = static_cast<size_t>(a);
    if (!has(w.prog, a)) continue;
    const double d = w.tgt[a] - rq.cur[a];
    if (d == 0) continue;
    const double vmax = (*lim.vmax)[ua];
    double v = vmax * lim.rapidScale;
    if (!rapid) {
      const double programmed = has(w.faMask, a) ? w.fa[a] * lim.feedScale : feed;
      out.feedCapped = out.feedCapped || programmed > vmax;
      v = std::min(programmed, vmax);
    }
    AxisMotion seg;
    seg.prof = makeTrapezoid(std::fabs(d), v, (*lim.amax)[ua]);
    seg.tEnd = seg.prof.duration();
    seg.kind = SegKind::Linear;
    seg.start = seg.base = rq.cur[a];
    seg.scale = d > 0 ? 1.0 : -1.0;
    seg.target = w.tgt[a];
    out.segs.push_back({a, seg, !w.nb[a]});
  }
}

} // namespace

MoveWords decodeMove(const std::vector<uint8_t>& moves, uint32_t first, uint32_t n, const double* vals,
                     const std::vector<int>& axisMap, const machine::Machine& m, bool incremental, const double* cur,
                     const double* offset) {
  MoveWords w;
  for (uint32_t k = 0; k < n; ++k) {
    const uint8_t d = moves[first + k];
    const auto kind = static_cast<image::MoveKind>(d >> 4);
    const double v = vals[k];
    if (!std::isfinite(v)) fault("a move value is not a finite number");
    if (kind == image::MoveKind::Target || kind == image::MoveKind::TargetNb || kind == image::MoveKind::Fa) {
      const int ax = axisMap[d & 0x0F];
      const uint32_t bit = 1u << ax;
      const char letter = m.axes[static_cast<size_t>(ax)].letter;
      if (kind == image::MoveKind::Fa) {
        if (w.faMask & bit) fault(fmt::format("Fa[{}] given twice in one block", letter));
        w.faMask |= bit;
        w.fa[ax] = v;
        continue;
      }
      if (w.prog & bit) fault(fmt::format("axis {} is programmed twice in one block", letter));
      w.prog |= bit;
      ++w.progCount;
      const double t = incremental ? cur[ax] + v : offset ? v + offset[ax] : v;
      if (!std::isfinite(t)) fault(fmt::format("axis {}: the incremental target overflows", letter));
      w.tgt[ax] = t;
      w.nb[ax] = kind == image::MoveKind::TargetNb;
      w.anyNb = w.anyNb || w.nb[ax];
    } else {
      const int i = static_cast<int>(kind) - static_cast<int>(image::MoveKind::I);
      w.arcWord[i] = true;
      w.arcVal[i] = v;
    }
  }
  return w;
}

MovePlan planMove(const MoveRequest& rq, const MoveLimits& lim) {
  const MoveWords& w = rq.words;
  const int nAxes = static_cast<int>(lim.m->axes.size());
  if (w.faMask & ~w.prog) {
    for (int a = 0; a < nAxes; ++a)
      if (has(w.faMask, a) && !has(w.prog, a))
        fault(fmt::format("Fa[{}] but axis {} does not move in this block", letterOf(lim, a), letterOf(lim, a)));
  }
  MovePlan out;
  if (lang::isArc(rq.motion)) {
    out.path = true;
    planArc(rq, lim, out.block);
    out.feedCapped = out.block.vBound == SpeedBound::AxisVelocity;
    return out;
  }
  const bool rapid = rq.motion == lang::kMotionRapid;
  const bool interp = !rapid && w.progCount <= 3 && w.faMask == 0;
  if (w.arcWord[0] || w.arcWord[1] || w.arcWord[2] || w.arcWord[3])
    fault("arc centre or radius (I/J/K/CR) on a line without G02/G03");
  out.faIgnored = rapid && w.faMask != 0;
  if (interp) {
    out.path = true;
    planLine(rq, lim, out.block);
    out.feedCapped = out.block.vBound == SpeedBound::AxisVelocity;
  } else {
    planIndependent(rq, lim, out);
  }
  return out;
}

} // namespace iso::sim
