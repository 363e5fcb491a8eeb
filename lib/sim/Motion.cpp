//! @file Motion.cpp
//! @brief Closed-form axis positions and arc geometry.
#include "sim/Motion.h"

#include <algorithm>
#include <cmath>

#include "lang/Limits.h"
#include "sim/TraceWriter.h"

namespace iso::sim {

namespace {
const double kPi = std::acos(-1.0);
using lang::kArcTolerance;
constexpr double kSamePoint = 1e-9; // mm: end == start for a full circle
} // namespace

double ArcGeom::length() const { return r0 * std::fabs(sweep); }

namespace {
/// Radius and angle of an arc at arc length s (the radius runs linearly from r0 to r1).
struct ArcPoint {
  double r, phi;
};
ArcPoint arcPoint(const ArcGeom& g, double s) {
  const double len = g.length();
  const double frac = len > 0 ? std::clamp(s / len, 0.0, 1.0) : 0.0;
  return {g.r0 + (g.r1 - g.r0) * frac, g.phi0 + g.sweep * frac};
}
} // namespace

double ArcGeom::p(double s) const {
  const ArcPoint a = arcPoint(*this, s);
  return cp + a.r * std::cos(a.phi);
}

double ArcGeom::q(double s) const {
  const ArcPoint a = arcPoint(*this, s);
  return cq + a.r * std::sin(a.phi);
}

// d/ds of (r cos phi, r sin phi) with dr/ds = (r1 - r0)/len and dphi/ds = sweep/len.
double ArcGeom::dp(double s) const {
  const double len = length();
  if (!(len > 0)) return 0;
  const ArcPoint a = arcPoint(*this, s);
  return ((r1 - r0) * std::cos(a.phi) - a.r * std::sin(a.phi) * sweep) / len;
}

double ArcGeom::dq(double s) const {
  const double len = length();
  if (!(len > 0)) return 0;
  const ArcPoint a = arcPoint(*this, s);
  return ((r1 - r0) * std::sin(a.phi) + a.r * std::cos(a.phi) * sweep) / len;
}

double AxisMotion::velocityAt(double t) const {
  if (!(t < tEnd) || t < t0) return 0;
  const double v = prof.velocity(t - t0);
  switch (kind) {
  case SegKind::Linear: return scale * v;
  case SegKind::ArcP: return arc.dp(prof.position(t - t0)) * v;
  case SegKind::ArcQ: return arc.dq(prof.position(t - t0)) * v;
  }
  return 0;
}

double AxisMotion::positionAt(double t) const {
  if (!(t < tEnd)) return target;
  if (!(t > t0)) return start;
  const double s = prof.position(t - t0);
  switch (kind) {
  case SegKind::Linear: return base + scale * s;
  case SegKind::ArcP: return arc.p(s);
  case SegKind::ArcQ: return arc.q(s);
  }
  return target;
}

void AxisMotion::stopAt(double t, double pos) {
  target = pos;
  start = pos;
  t0 = t;
  tEnd = t;
  kind = SegKind::Linear;
  base = pos;
  scale = 0;
  prof = Trapezoid{};
}

bool makeArc(const ArcRequest& rq, ArcGeom& out, std::string& why) {
  out = ArcGeom{};
  const double chord = std::hypot(rq.p1 - rq.p0, rq.q1 - rq.q0);
  double cp = 0, cq = 0;
  if (rq.byRadius) {
    const double r = std::fabs(rq.cr);
    if (chord <= kSamePoint) {
      why = "CR with end point = start point: a full circle needs I/J/K";
      return false;
    }
    if (!(r > 0)) {
      why = "CR=0 is not a radius";
      return false;
    }
    const double half = chord / 2;
    if (half > r + kArcTolerance / 2) {
      why = "radius " + formatNumber(r) + " mm is too small for the chord " + formatNumber(chord) +
            " mm between start and end";
      return false;
    }
    const double h = std::sqrt(std::max(0.0, r * r - half * half));
    const double dp = (rq.p1 - rq.p0) / chord, dq = (rq.q1 - rq.q0) / chord;
    // Left normal of the chord: the centre of a counter-clockwise arc of at most 180° lies there.
    double side = rq.ccw ? 1.0 : -1.0;
    if (rq.cr < 0) side = -side;
    cp = (rq.p0 + rq.p1) / 2 - side * h * dq;
    cq = (rq.q0 + rq.q1) / 2 + side * h * dp;
  } else {
    cp = rq.p0 + rq.ci;
    cq = rq.q0 + rq.cj;
  }
  const double r0 = std::hypot(rq.p0 - cp, rq.q0 - cq);
  const double r1 = std::hypot(rq.p1 - cp, rq.q1 - cq);
  if (!(r0 > kSamePoint)) {
    why = "arc centre equals its start point (radius 0)";
    return false;
  }
  if (!rq.byRadius && std::fabs(r1 - r0) > kArcTolerance) {
    why = "end point is " + formatNumber(std::fabs(r1 - r0)) + " mm off the circle (radius " + formatNumber(r0) +
          " mm at the start, " + formatNumber(r1) + " mm at the end; tolerance 0.01 mm)";
    return false;
  }
  const double phi0 = std::atan2(rq.q0 - cq, rq.p0 - cp);
  double sweep = 0;
  if (!rq.byRadius && chord <= kSamePoint) {
    sweep = rq.ccw ? 2 * kPi : -2 * kPi;
  } else {
    const double phi1 = std::atan2(rq.q1 - cq, rq.p1 - cp);
    sweep = phi1 - phi0;
    if (rq.ccw) {
      while (sweep <= 0)
        sweep += 2 * kPi;
      while (sweep > 2 * kPi)
        sweep -= 2 * kPi;
    } else {
      while (sweep >= 0)
        sweep -= 2 * kPi;
      while (sweep < -2 * kPi)
        sweep += 2 * kPi;
    }
  }
  out.cp = cp;
  out.cq = cq;
  out.r0 = r0;
  out.r1 = rq.byRadius ? r0 : r1;
  out.phi0 = phi0;
  out.sweep = sweep;
  return true;
}

void arcExtremes(const ArcGeom& g, double& pMin, double& pMax, double& qMin, double& qMax) {
  const double len = g.length();
  const double ps = g.p(0), qs = g.q(0), pe = g.p(len), qe = g.q(len);
  pMin = std::min(ps, pe);
  pMax = std::max(ps, pe);
  qMin = std::min(qs, qe);
  qMax = std::max(qs, qe);
  const double lo = std::min(g.phi0, g.phi0 + g.sweep), hi = std::max(g.phi0, g.phi0 + g.sweep);
  const double quarter = kPi / 2;
  const auto k0 = static_cast<long long>(std::ceil(lo / quarter));
  const auto k1 = static_cast<long long>(std::floor(hi / quarter));
  static const double cosq[4] = {1, 0, -1, 0};
  static const double sinq[4] = {0, 1, 0, -1};
  for (long long k = k0; k <= k1; ++k) {
    const double theta = static_cast<double>(k) * quarter;
    const double frac = g.sweep != 0 ? std::clamp((theta - g.phi0) / g.sweep, 0.0, 1.0) : 0.0;
    const double r = g.r0 + (g.r1 - g.r0) * frac;
    const auto qd = static_cast<size_t>(((k % 4) + 4) % 4);
    const double p = g.cp + r * cosq[qd], q = g.cq + r * sinq[qd];
    pMin = std::min(pMin, p);
    pMax = std::max(pMax, p);
    qMin = std::min(qMin, q);
    qMax = std::max(qMax, q);
  }
}

} // namespace iso::sim
