//! @file Motion.cpp
//! @brief Closed-form axis positions and arc geometry.
#include "sim/Motion.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "lang/Limits.h"
#include "sim/TraceWriter.h"

namespace iso::sim {

namespace {
const double kPi = std::acos(-1.0);
using lang::kArcTolerance;
constexpr double kSamePoint = 1e-9; // mm: end == start for a full circle
/// Arc radii above this (1000 km) are a runtime error: the arc arithmetic would lose every
/// digit of a position, or overflow (a CR of 1e200 squares to infinity).
constexpr double kMaxArcRadius = 1e9; // mm

/// A radius in a message: as the trace prints it, or "1e+256" for one too long to read.
std::string radiusText(double r) { return std::fabs(r) < 1e15 ? formatNumber(r) : fmt::format("{:g}", r); }

/// The sweep from phi0 to phi1 (radians) in the direction of the arc: (0, 2π] counter-clockwise,
/// [-2π, 0) clockwise. One reduction, whatever the size of the difference (never a loop).
double wrapSweep(double diff, bool ccw) {
  const double turn = 2 * kPi;
  double s = std::fmod(diff, turn); // (-2π, 2π), NaN stays NaN
  if (ccw && s <= 0) s += turn;
  if (!ccw && s >= 0) s -= turn;
  return s;
}
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

namespace {
/// The arc lengths in [sa, sb] at which a monotone f enters and leaves [lo, hi] (empty: none).
/// Bisection to adjacent doubles on each bound.
template <class F>
bool monotoneInside(F&& f, double sa, double sb, double lo, double hi, double& enter, double& leave) {
  const double fa = f(sa), fb = f(sb);
  const bool rising = fb >= fa;
  const auto inside = [&](double x) { return x >= lo && x <= hi; };
  // the first s where the bound on the entering side holds, the last where the other holds
  const auto firstWhere = [&](auto&& pred) { // pred false..true along [sa, sb]
    if (pred(f(sa))) return sa;
    double a = sa, b = sb;
    for (int i = 0; i < 200; ++i) {
      const double mid = a + (b - a) / 2;
      if (!(mid > a && mid < b)) break;
      (pred(f(mid)) ? b : a) = mid;
    }
    return b;
  };
  const auto lastWhere = [&](auto&& pred) { // pred true..false along [sa, sb]
    if (pred(f(sb))) return sb;
    double a = sa, b = sb;
    for (int i = 0; i < 200; ++i) {
      const double mid = a + (b - a) / 2;
      if (!(mid > a && mid < b)) break;
      (pred(f(mid)) ? a : b) = mid;
    }
    return a;
  };
  if (rising) {
    if (fb < lo || fa > hi) return false;
    enter = firstWhere([&](double x) { return x >= lo; });
    leave = lastWhere([&](double x) { return x <= hi; });
  } else {
    if (fa < lo || fb > hi) return false;
    enter = firstWhere([&](double x) { return x <= hi; });
    leave = lastWhere([&](double x) { return x >= lo; });
  }
  return enter <= leave && (inside(f(enter)) || inside(f(leave)));
}

void addInterval(TimeIntervals& out, double a, double b) {
  if (!(a <= b)) return;
  if (!out.empty() && a <= out.back().second) {
    out.back().second = std::max(out.back().second, b);
    return;
  }
  out.emplace_back(a, b);
}
} // namespace

TimeIntervals insideIntervals(const AxisMotion& a, double lo, double hi, double from) {
  TimeIntervals out;
  const auto in = [&](double x) { return x >= lo && x <= hi; };
  const double inf = std::numeric_limits<double>::infinity();
  if (!(from < a.tEnd)) { // at rest
    if (in(a.target)) out.emplace_back(from, inf);
    return out;
  }
  const double d = a.prof.distance;
  const auto timeOf = [&](double s) { return a.t0 + a.prof.timeAt(s); };
  // the s-intervals inside, in increasing s
  std::vector<std::pair<double, double>> sIn;
  if (a.kind == SegKind::Linear) {
    if (a.scale == 0) {
      if (in(a.base)) sIn.emplace_back(0.0, d);
    } else {
      double s1 = (lo - a.base) / a.scale, s2 = (hi - a.base) / a.scale;
      if (s1 > s2) std::swap(s1, s2);
      s1 = std::max(s1, 0.0);
      s2 = std::min(s2, d);
      if (s1 <= s2) sIn.emplace_back(s1, s2);
    }
  } else {
    const ArcGeom& g = a.arc;
    const double len = g.length();
    const bool isP = a.kind == SegKind::ArcP;
    const auto f = [&](double s) { return isP ? g.p(s) : g.q(s); };
    // piece ends: where phi0 + sweep·s/len crosses a multiple of pi/2
    std::vector<double> cuts{0.0};
    const double quarter = kPi / 2;
    const double phi1 = g.phi0 + g.sweep;
    const double kLo = std::ceil(std::min(g.phi0, phi1) / quarter), kHi = std::floor(std::max(g.phi0, phi1) / quarter);
    for (double k = kLo; k <= kHi && len > 0; ++k)
      cuts.push_back(std::clamp((k * quarter - g.phi0) / g.sweep * len, 0.0, len));
    cuts.push_back(len);
    std::sort(cuts.begin(), cuts.end());
    for (size_t i = 0; i + 1 < cuts.size(); ++i) {
      double enter = 0, leave = 0;
      if (monotoneInside(f, cuts[i], cuts[i + 1], lo, hi, enter, leave)) addInterval(sIn, enter, leave);
    }
  }
  for (const auto& [s1, s2] : sIn) {
    const double t1 = std::max(timeOf(s1), a.t0);
    const double t2 = s2 >= d ? a.tEnd : timeOf(s2);
    addInterval(out, std::max(t1, from), t2);
  }
  if (in(a.target)) addInterval(out, std::max(a.tEnd, from), inf);
  return out;
}

TimeIntervals intersectIntervals(const TimeIntervals& a, const TimeIntervals& b) {
  TimeIntervals out;
  size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    const double lo = std::max(a[i].first, b[j].first);
    const double hi = std::min(a[i].second, b[j].second);
    if (lo <= hi) addInterval(out, lo, hi);
    (a[i].second < b[j].second ? i : j)++;
  }
  return out;
}

support::Expected<ArcGeom> makeArc(const ArcRequest& rq) {
  ArcGeom out;
  const double chord = std::hypot(rq.p1 - rq.p0, rq.q1 - rq.q0);
  double cp = 0, cq = 0;
  if (rq.byRadius) {
    const double r = std::fabs(rq.cr);
    if (chord <= kSamePoint) {
      return support::Error{"", "CR with end point = start point: a full circle needs I/J/K"};
    }
    if (!(r > 0)) {
      return support::Error{"", "CR=0 is not a radius"};
    }
    if (!(r <= kMaxArcRadius)) {
      return support::Error{"", "CR=" + radiusText(rq.cr) + " mm is out of range: an arc radius is at most " +
                                    formatNumber(kMaxArcRadius) + " mm"};
    }
    const double half = chord / 2;
    if (half > r + kArcTolerance / 2) {
      return support::Error{"", "radius " + formatNumber(r) + " mm is too small for the chord " + formatNumber(chord) +
                                    " mm between start and end"};
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
  if (!std::isfinite(cp) || !std::isfinite(cq) || !(r0 <= kMaxArcRadius) || !(r1 <= kMaxArcRadius)) {
    return support::Error{
        "", "arc radius out of range: at most " + formatNumber(kMaxArcRadius) + " mm (the centre is " +
                (std::isfinite(r0) && std::isfinite(r1) ? radiusText(std::max(r0, r1)) + " mm away)" : "not finite)")};
  }
  if (!(r0 > kSamePoint)) {
    return support::Error{"", "arc centre equals its start point (radius 0)"};
  }
  if (!rq.byRadius && std::fabs(r1 - r0) > kArcTolerance) {
    return support::Error{"", "end point is " + formatNumber(std::fabs(r1 - r0)) + " mm off the circle (radius " +
                                  formatNumber(r0) + " mm at the start, " + formatNumber(r1) +
                                  " mm at the end; tolerance 0.01 mm)"};
  }
  const double phi0 = std::atan2(rq.q0 - cq, rq.p0 - cp);
  double sweep = 0;
  if (!rq.byRadius && chord <= kSamePoint)
    sweep = rq.ccw ? 2 * kPi : -2 * kPi;
  else
    sweep = wrapSweep(std::atan2(rq.q1 - cq, rq.p1 - cp) - phi0, rq.ccw);
  if (!std::isfinite(phi0) || !std::isfinite(sweep) || !std::isfinite(r0 * std::fabs(sweep))) {
    return support::Error{"", "arc geometry out of range (angle or length not finite)"};
  }
  out.cp = cp;
  out.cq = cq;
  out.r0 = r0;
  out.r1 = rq.byRadius ? r0 : r1;
  out.phi0 = phi0;
  out.sweep = sweep;
  return out;
}

void arcExtremes(const ArcGeom& g, double& pMin, double& pMax, double& qMin, double& qMax) {
  const double len = g.length();
  const double ps = g.p(0), qs = g.q(0), pe = g.p(len), qe = g.q(len);
  pMin = std::min(ps, pe);
  pMax = std::max(ps, pe);
  qMin = std::min(qs, qe);
  qMax = std::max(qs, qe);
  const double lo = std::min(g.phi0, g.phi0 + g.sweep), hi = std::max(g.phi0, g.phi0 + g.sweep);
  if (!std::isfinite(lo) || !std::isfinite(hi)) return; // makeArc refuses such arcs
  static const double cosq[4] = {1, 0, -1, 0};
  static const double sinq[4] = {0, 1, 0, -1};
  auto extend = [&](double p, double q) {
    pMin = std::min(pMin, p);
    pMax = std::max(pMax, p);
    qMin = std::min(qMin, q);
    qMax = std::max(qMax, q);
  };
  const double rBig = std::max(g.r0, g.r1);
  if (hi - lo > 2 * kPi) { // more than a full circle: every quadrant point is swept
    for (size_t qd = 0; qd < 4; ++qd)
      extend(g.cp + rBig * cosq[qd], g.cq + rBig * sinq[qd]);
    return;
  }
  // The quadrant points k·π/2 in [lo, hi]: at most four, counted in doubles (k never becomes an
  // integer type, so no angle can overflow a cast).
  const double quarter = kPi / 2;
  const double k0 = std::ceil(lo / quarter);
  for (int j = 0; j < 5; ++j) {
    const double k = k0 + j;
    const double theta = k * quarter;
    if (theta > hi) break;
    const double frac = g.sweep != 0 ? std::clamp((theta - g.phi0) / g.sweep, 0.0, 1.0) : 0.0;
    const double r = g.r0 + (g.r1 - g.r0) * frac;
    const double m = std::fmod(k, 4.0);
    const auto qd = static_cast<size_t>(m < 0 ? m + 4 : m);
    extend(g.cp + r * cosq[qd], g.cq + r * sinq[qd]);
  }
}

} // namespace iso::sim
