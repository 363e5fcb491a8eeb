//! @file Motion.h
//! @brief Per-axis motion segments evaluated in closed form (SPEC §5.2), and the geometry of
//!        circular moves. An axis is always either at rest or on exactly one segment; its
//!        position at any time is computed from the segment, never integrated.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "sim/MotionProfile.h"
#include "support/Expected.h"

namespace iso::sim {

enum class SegKind : uint8_t {
  Linear, ///< position = base + scale · s(t − t0): independent axes (scale ±1) and lines (u_i)
  ArcP,   ///< position = cp + r(s)·cos(φ(s)): the first plane axis of an arc
  ArcQ,   ///< position = cq + r(s)·sin(φ(s)): the second plane axis of an arc
};

/// Geometry of one circular move in the plane (p, q), angles in radians from +p towards +q.
struct ArcGeom {
  double cp = 0, cq = 0; ///< centre
  double r0 = 0;         ///< radius at the start (the path length is r0·|sweep|)
  double r1 = 0;         ///< radius at the end (|r1 − r0| <= 0.01 mm; interpolated linearly)
  double phi0 = 0;       ///< start angle
  double sweep = 0;      ///< signed: > 0 counter-clockwise (G03), < 0 clockwise (G02)
  /// Point at arc length s (0..r0·|sweep|).
  double p(double s) const;
  double q(double s) const;
  double length() const;
  /// Derivatives dp/ds and dq/ds at arc length s (the unit tangent for a true circle).
  double dp(double s) const;
  double dq(double s) const;
};

/// The motion of one axis. Plain value; `moving(t)` is `t < tEnd`.
struct AxisMotion {
  double target = 0; ///< $aa_fw: the end of the current move, or the position at rest
  double t0 = 0;     ///< start of the current segment
  double tEnd = 0;   ///< end of the current segment (<= now: at rest at `target`)
  double start = 0;  ///< position at t0
  SegKind kind = SegKind::Linear;
  double base = 0, scale = 0; ///< Linear
  ArcGeom arc;                ///< ArcP / ArcQ
  Trapezoid prof;             ///< s(t − t0) along the segment's path

  bool moving(double t) const { return t < tEnd; }
  /// Exact position at time t (target from tEnd on).
  double positionAt(double t) const;
  /// Exact velocity at time t (mm/s, signed; 0 outside the segment).
  double velocityAt(double t) const;
  /// Puts the axis at rest at `pos` from time t on (emergency stop, start of a run).
  void stopAt(double t, double pos);
};

/// The phase boundaries of a segment in absolute time (acceleration end, cruise end), used to
/// split searches into pieces where every position is monotonic or smooth.
inline double phaseEnd1(const AxisMotion& a) { return a.t0 + a.prof.tAccelEnd; }
inline double phaseEnd2(const AxisMotion& a) { return a.t0 + a.prof.tCruiseEnd; }

/// Closed time intervals [first, second], in increasing order and disjoint.
using TimeIntervals = std::vector<std::pair<double, double>>;

/// The times from `from` on at which the axis's position lies in [lo, hi] (either bound may
/// be infinite), on its current segment and at rest at its target after it (the last
/// interval then ends at +inf). A line or an independent move is monotone along its path: its
/// bounds invert the trapezoid exactly (Trapezoid::timeAt). An arc is split where its angle
/// crosses a multiple of 90 degrees, so that each piece is monotone, and each bound is located
/// on a piece by bisection of the arc length to adjacent doubles.
TimeIntervals insideIntervals(const AxisMotion& a, double lo, double hi, double from);

/// The intersection of two interval lists.
TimeIntervals intersectIntervals(const TimeIntervals& a, const TimeIntervals& b);

/// Circle through a start point with a centre (I/J/K form) or radius (CR form), SPEC §4.3.
struct ArcRequest {
  double p0 = 0, q0 = 0; ///< start
  double p1 = 0, q1 = 0; ///< end
  bool ccw = false;      ///< G03
  bool byRadius = false; ///< CR given
  double ci = 0, cj = 0; ///< centre offsets from the start (I/J/K of the plane)
  double cr = 0;         ///< CR (negative: more than 180°)
};
/// Computes the arc, or the geometry error (end point off the circle by more than 0.01 mm, CR
/// too small for the chord, CR full circle, zero radius) as a message.
support::Expected<ArcGeom> makeArc(const ArcRequest& rq);

/// The extreme values of p and q along the arc (endpoints and the quadrant points swept).
void arcExtremes(const ArcGeom& g, double& pMin, double& pMax, double& qMin, double& qMax);

} // namespace iso::sim
