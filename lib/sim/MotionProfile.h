//! @file MotionProfile.h
//! @brief Exact closed-form trapezoidal motion profiles, path limits and junction speeds (SPEC §5.2).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "lang/Limits.h"
#include "support/FixedVec.h"

namespace iso::sim {

/// One value per axis, stored inline (no allocation per move).
using AxisValues = support::FixedVec<double, lang::kMaxImageAxes>;

/// A trapezoidal velocity profile over a distance d: accelerate at `accel` from v0 to vPeak,
/// cruise at vPeak, decelerate at `accel` to v1. Units: mm (or degrees), s, mm/s, mm/s².
/// Time 0 is the start of the move; distances are measured along the path from its start.
/// A plain value; build it with makeTrapezoid(). All member functions are pure.
struct Trapezoid {
  double distance = 0;   ///< d >= 0
  double accel = 0;      ///< A > 0 (0 only for the empty profile)
  double v0 = 0;         ///< entry speed
  double v1 = 0;         ///< exit speed (after clamping to what is reachable, see makeTrapezoid)
  double vPeak = 0;      ///< cruise speed = min(V, sqrt(A·d + (v0²+v1²)/2)), >= max(v0, v1)
  double tAccelEnd = 0;  ///< end of the acceleration phase = (vPeak − v0)/A
  double tCruiseEnd = 0; ///< end of the cruise phase
  double tEnd = 0;       ///< total duration
  double sAccelEnd = 0;  ///< distance travelled at tAccelEnd = (vPeak² − v0²)/(2A)
  double sCruiseEnd = 0; ///< distance travelled at tCruiseEnd = d − (vPeak² − v1²)/(2A)

  /// Total duration in seconds.
  double duration() const { return tEnd; }
  /// True when the profile reaches its velocity limit and cruises (tCruiseEnd > tAccelEnd).
  bool cruises() const { return tCruiseEnd > tAccelEnd; }
  /// Distance travelled at time t; 0 for t <= 0 and d for t >= duration().
  double position(double t) const;
  /// Speed at time t inside [0, duration()]; 0 outside it.
  double velocity(double t) const;
  /// The first time t at which position(t) == s. s is clamped to [0, d]: s <= 0 gives 0,
  /// s >= d gives duration() (0 for an empty profile). Solves each phase's quadratic exactly,
  /// in the cancellation-free form t = 2s / (v + sqrt(v² + 2As)).
  double timeAt(double s) const;
};

/// Rest-to-rest move (SPEC §5.2): if d >= V²/A then t = d/V + V/A, else t = 2·sqrt(d/A).
/// Preconditions: d >= 0, V > 0, A > 0 (d == 0 gives the empty profile whatever V and A are).
Trapezoid makeTrapezoid(double d, double vmax, double accel);

/// General move entering at speed v0 and leaving at v1 (G64 blending).
/// Preconditions: d >= 0, V > 0, A > 0, 0 <= v0, v1 <= V, |v1² − v0²| <= 2·A·d.
/// Defensive behaviour outside them (never NaN): negative inputs are taken as 0; V is raised to
/// max(v0, v1); an unreachable v1 is clamped to the speed actually reachable over d (the result's
/// v1 member holds the speed used).
Trapezoid makeTrapezoid(double d, double vmax, double accel, double v0, double v1);

/// What bounds a path speed.
enum class SpeedBound : uint8_t {
  Feed,         ///< the programmed feed F
  AxisVelocity, ///< the max velocity of one axis (see the `vAxis` member)
  Centripetal,  ///< arcs: sqrt(r · min(amax_p, amax_q))
  None,         ///< zero-length move: nothing moves
};

/// Limits of an interpolated straight move (SPEC §5.2).
struct LineLimits {
  double length = 0;                    ///< L = |delta| (mm, rotary axes in degrees count too)
  AxisValues dir;                       ///< unit direction u = delta / L (all 0 when L == 0)
  double vmax = 0;                      ///< V = min(F, min_i vmax_i/|u_i|); 0 when L == 0
  double accel = 0;                     ///< A = min_i amax_i/|u_i| over u_i != 0; 0 when L == 0
  SpeedBound vBound = SpeedBound::None; ///< Feed or AxisVelocity (None when L == 0)
  int vAxis = -1;                       ///< index of the axis that bounds V, -1 when the feed does
  int aAxis = -1;                       ///< index of the axis that bounds A, -1 when L == 0
};

/// Interpolated line over several axes. delta, axisVmax and axisAmax have one entry per axis
/// (same size; vmax/amax > 0). feed > 0 in mm/s (+infinity: no feed limit). On a tie the feed
/// wins over an axis, and a lower axis index over a higher one.
LineLimits lineLimits(const AxisValues& delta, const std::vector<double>& axisVmax, const std::vector<double>& axisAmax,
                      double feed);

/// The same on raw arrays, for the planner: `moving` has bit i set for each axis i with
/// delta[i] != 0 (all of them below kMaxImageAxes); fills `r` (its `dir` untouched) and writes
/// the unit direction of the moving axes into `dir`, whose other entries the caller has zeroed
/// (all are left as they were when L == 0).
void lineLimitsInto(const double* delta, uint32_t moving, const double* axisVmax, const double* axisAmax, double feed,
                    LineLimits& r, double* dir);

/// Limits of a circular move in the plane of axes p and q (SPEC §5.2).
struct ArcLimits {
  double length = 0;                    ///< d = r·|Δφ|
  double vmax = 0;                      ///< V = min(F, vmax_p, vmax_q, sqrt(r · min(amax_p, amax_q)))
  double accel = 0;                     ///< A = min(amax_p, amax_q)
  SpeedBound vBound = SpeedBound::Feed; ///< Feed, AxisVelocity or Centripetal
  int vAxis = -1;                       ///< 0 = p, 1 = q when vBound == AxisVelocity, else -1
  int aAxis = 0;                        ///< 0 = p, 1 = q: the axis whose amax is A (p on a tie)
};

/// Arc of radius r >= 0 sweeping |sweepRad| radians at feed F (> 0, +infinity: no limit).
/// Ties are resolved in the order feed, p, q, centripetal.
ArcLimits arcLimits(double radius, double sweepRad, double feed, double vmaxP, double vmaxQ, double amaxP,
                    double amaxQ);

/// Junction speed between two path segments (junction deviation, SPEC §5.2).
/// uIn: direction of travel at the end of the incoming segment, uOut: at the start of the
/// outgoing one (arcs: their tangents); same size as axisAmax. They are normalised here; a zero
/// vector gives 0. With s = sin(θ/2), θ the angle between −uIn and uOut:
/// v_j² = a_j·δ·s/(1−s), a_j = min_i amax_i/|ĵ_i| over ĵ_i != 0, ĵ = unit(uOut − uIn);
/// the result is min(v_j, vIn, vOut). Collinear (s = 1): min(vIn, vOut). Reversal: 0.
double junctionSpeed(std::span<const double> uIn, std::span<const double> uOut, const std::vector<double>& axisAmax,
                     double deviationMm, double vIn, double vOut);
inline double junctionSpeed(const AxisValues& uIn, const AxisValues& uOut, const std::vector<double>& axisAmax,
                            double deviationMm, double vIn, double vOut) {
  return junctionSpeed(std::span<const double>(uIn.data(), uIn.size()),
                       std::span<const double>(uOut.data(), uOut.size()), axisAmax, deviationMm, vIn, vOut);
}

} // namespace iso::sim
