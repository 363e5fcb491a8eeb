//! @file MotionProfile.cpp
//! @brief Closed-form trapezoid kinematics, interpolated line/arc limits and junction speed.
#include "sim/MotionProfile.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <span>

#include "sim/RunMath.h"

namespace iso::sim {

namespace {

/// Non-negative, NaN-free view of an input that should be >= 0.
double nonNegative(double x) { return x > 0 ? x : 0.0; }

/// The time to cover s >= 0 from speed v at acceleration a > 0: the positive root of
/// a/2·t² + v·t − s = 0, written as 2s / (v + sqrt(v² + 2as)) so that a small s or a large v
/// does not cancel (the textbook (−v + sqrt(...))/a loses every digit when v² >> 2as).
double timeToCover(double s, double v, double a) {
  if (!(s > 0)) {
    return 0.0;
  }
  const double disc = std::max(0.0, v * v + 2.0 * a * s);
  const double den = v + std::sqrt(disc);
  return den > 0 ? 2.0 * s / den : 0.0;
}

double norm(const double* first, const double* last) {
  double scale = 0;
  for (const double* x = first; x != last; ++x)
    scale = std::max(scale, std::fabs(*x));
  if (!(scale > 0) || !std::isfinite(scale)) {
    return scale > 0 ? scale : 0.0;
  }
  // Scaled sum of squares: no overflow or underflow for extreme deltas. Zero components add
  // nothing (the sum is the same without them).
  double sum = 0;
  for (const double* x = first; x != last; ++x) {
    if (*x == 0) continue;
    const double y = *x / scale;
    sum += y * y;
  }
  return scale * std::sqrt(sum);
}

} // namespace

double Trapezoid::position(double t) const {
  if (!(t > 0)) {
    return 0.0;
  }
  if (t >= tEnd) {
    return distance;
  }
  double s = 0;
  if (t < tAccelEnd) {
    s = v0 * t + 0.5 * accel * t * t;
  } else if (t < tCruiseEnd) {
    s = sAccelEnd + vPeak * (t - tAccelEnd);
  } else {
    // Measured back from the end so that position(tEnd) is exactly d.
    const double sigma = tEnd - t;
    s = distance - (v1 * sigma + 0.5 * accel * sigma * sigma);
  }
  return std::clamp(s, 0.0, distance);
}

double Trapezoid::velocity(double t) const {
  if (t < 0 || t > tEnd) {
    return 0.0;
  }
  if (t < tAccelEnd) {
    return v0 + accel * t;
  }
  if (t <= tCruiseEnd) {
    return vPeak;
  }
  return v1 + accel * (tEnd - t);
}

double Trapezoid::timeAt(double s) const {
  if (!(s > 0)) {
    return 0.0;
  }
  if (s >= distance) {
    return tEnd;
  }
  if (s <= sAccelEnd) {
    return std::min(timeToCover(s, v0, accel), tAccelEnd);
  }
  if (s <= sCruiseEnd) {
    return std::min(tAccelEnd + (s - sAccelEnd) / vPeak, tCruiseEnd);
  }
  // Deceleration: solve backwards from the end, where the speed is v1.
  const double sigma = timeToCover(distance - s, v1, accel);
  return std::clamp(tEnd - sigma, tCruiseEnd, tEnd);
}

Trapezoid makeTrapezoid(double d, double vmax, double accel) { return makeTrapezoid(d, vmax, accel, 0.0, 0.0); }

Trapezoid makeTrapezoid(double d, double vmax, double accel, double v0, double v1) {
  Trapezoid p;
  d = nonNegative(d);
  v0 = nonNegative(v0);
  v1 = nonNegative(v1);
  p.accel = nonNegative(accel);
  p.v0 = v0;
  if (!(d > 0) || !(p.accel > 0)) {
    // Nothing to travel (or no way to travel it): the speed cannot change.
    p.distance = d;
    p.v1 = v0;
    p.vPeak = v0;
    return p;
  }
  p.distance = d;
  const double a = p.accel;
  const double v = std::max({nonNegative(vmax), v0, v1});

  // Clamp an unreachable exit speed to the one reachable over d.
  const double reach = 2.0 * a * d;
  if (v1 * v1 > v0 * v0 + reach) {
    v1 = std::sqrt(v0 * v0 + reach);
  } else if (v1 * v1 < v0 * v0 - reach) {
    v1 = std::sqrt(v0 * v0 - reach);
  }
  p.v1 = v1;

  const double peakSq = a * d + 0.5 * (v0 * v0 + v1 * v1);
  if (peakSq >= v * v) {
    // Reaches V: accelerate, cruise, decelerate.
    p.vPeak = v;
    const double sAccel = (v - v0) * (v + v0) / (2.0 * a);
    const double sDecel = (v - v1) * (v + v1) / (2.0 * a);
    const double cruise = std::max(0.0, d - sAccel - sDecel);
    p.tAccelEnd = (v - v0) / a;
    p.tCruiseEnd = p.tAccelEnd + (v > 0 ? cruise / v : 0.0);
    p.tEnd = p.tCruiseEnd + (v - v1) / a;
    p.sAccelEnd = std::min(sAccel, d);
    p.sCruiseEnd = std::clamp(d - sDecel, p.sAccelEnd, d);
  } else {
    // Triangle: the peak is where the acceleration and deceleration parabolas meet.
    const double peak = std::max({std::sqrt(peakSq), v0, v1});
    p.vPeak = peak;
    p.tAccelEnd = (peak - v0) / a;
    p.tCruiseEnd = p.tAccelEnd;
    p.tEnd = p.tAccelEnd + (peak - v1) / a;
    p.sAccelEnd = std::min((peak - v0) * (peak + v0) / (2.0 * a), d);
    p.sCruiseEnd = p.sAccelEnd;
  }
  return p;
}

LineLimits lineLimits(const AxisValues& delta, const std::vector<double>& axisVmax, const std::vector<double>& axisAmax,
                      double feed) {
  LineLimits r;
  const size_t n = std::min({delta.size(), axisVmax.size(), axisAmax.size()});
  r.dir.assign(delta.size(), 0.0);
  uint32_t moving = 0;
  for (size_t i = 0; i < n; ++i)
    if (delta[i] != 0) moving |= 1u << i;
  lineLimitsInto(delta.data(), moving, axisVmax.data(), axisAmax.data(), feed, r, r.dir.data());
  return r;
}

void lineLimitsInto(const double* delta, uint32_t moving, const double* axisVmax, const double* axisAmax, double feed,
                    LineLimits& r, double* dir) {
  // Only the moving axes count (a zero component adds nothing to the norm and bounds nothing),
  // so the work is per moving axis, in axis order: the same arithmetic as over all of them.
  if (moving != 0 && (moving & (moving - 1)) == 0) {
    // One moving axis: the arithmetic below gives exactly L = |d|, u = d/|d| = ±1 (so the sum
    // of squares is 1 and each limit divided by |u| is the limit itself), without a division.
    const int i = std::countr_zero(moving);
    const double len = std::fabs(delta[i]);
    if (!(len > 0) || !std::isfinite(len)) {
      r.length = 0;
      return;
    }
    r.length = len;
    dir[i] = delta[i] > 0 ? 1.0 : -1.0;
    r.vmax = feed;
    r.vBound = SpeedBound::Feed;
    if (axisVmax[i] < r.vmax) {
      r.vmax = axisVmax[i];
      r.vBound = SpeedBound::AxisVelocity;
      r.vAxis = i;
    }
    r.accel = kInf;
    if (axisAmax[i] < r.accel) {
      r.accel = axisAmax[i];
      r.aAxis = i;
    }
    return;
  }
  // norm() of the moving components, inline: their largest magnitude, then the scaled sum of
  // squares (no overflow or underflow for extreme deltas).
  double scale = 0;
  for (uint32_t bits = moving; bits != 0; bits &= bits - 1)
    scale = std::max(scale, std::fabs(delta[std::countr_zero(bits)]));
  if (!(scale > 0) || !std::isfinite(scale)) {
    r.length = 0;
    return;
  }
  double sum = 0;
  for (uint32_t bits = moving; bits != 0; bits &= bits - 1) {
    const double y = delta[std::countr_zero(bits)] / scale;
    sum += y * y;
  }
  r.length = scale * std::sqrt(sum);
  if (!(r.length > 0) || !std::isfinite(r.length)) {
    r.length = 0;
    return;
  }
  r.vmax = feed;
  r.vBound = SpeedBound::Feed;
  r.accel = kInf;
  for (uint32_t bits = moving; bits != 0; bits &= bits - 1) {
    const int i = std::countr_zero(bits);
    dir[i] = delta[i] / r.length;
    const double u = std::fabs(dir[i]);
    if (u == 0) continue;
    const double vLim = axisVmax[i] / u;
    if (vLim < r.vmax) {
      r.vmax = vLim;
      r.vBound = SpeedBound::AxisVelocity;
      r.vAxis = i;
    }
    const double aLim = axisAmax[i] / u;
    if (aLim < r.accel) {
      r.accel = aLim;
      r.aAxis = i;
    }
  }
}

ArcLimits arcLimits(double radius, double sweepRad, double feed, double vmaxP, double vmaxQ, double amaxP,
                    double amaxQ) {
  ArcLimits r;
  radius = nonNegative(radius);
  r.length = radius * std::fabs(sweepRad);
  r.accel = std::min(amaxP, amaxQ);
  r.aAxis = amaxQ < amaxP ? 1 : 0;
  r.vmax = feed;
  r.vBound = SpeedBound::Feed;
  if (vmaxP < r.vmax) {
    r.vmax = vmaxP;
    r.vBound = SpeedBound::AxisVelocity;
    r.vAxis = 0;
  }
  if (vmaxQ < r.vmax) {
    r.vmax = vmaxQ;
    r.vBound = SpeedBound::AxisVelocity;
    r.vAxis = 1;
  }
  // The centripetal acceleration v²/r may not exceed what the weaker axis can do.
  const double centripetal = std::sqrt(radius * nonNegative(r.accel));
  if (centripetal < r.vmax) {
    r.vmax = centripetal;
    r.vBound = SpeedBound::Centripetal;
    r.vAxis = -1;
  }
  return r;
}

double junctionSpeed(std::span<const double> uIn, std::span<const double> uOut, const std::vector<double>& axisAmax,
                     double deviationMm, double vIn, double vOut) {
  const size_t n = std::min({uIn.size(), uOut.size(), axisAmax.size()});
  const double vCap = std::min(vIn, vOut);
  const double* in = uIn.data();
  const double* out = uOut.data();
  const double inNorm = norm(in, in + n);
  const double outNorm = norm(out, out + n);
  if (!(inNorm > 0) || !(outNorm > 0)) {
    return 0.0;
  }
  AxisValues diff;
  diff.assign(n, 0.0);
  double sumSq = 0;
  double diffSq = 0;
  for (size_t i = 0; i < n; ++i) {
    const double a = in[i] / inNorm;
    const double b = out[i] / outNorm;
    sumSq += (a + b) * (a + b);
    diff[i] = b - a;
    diffSq += diff[i] * diff[i];
  }
  // s = sin(θ/2) = |uIn + uOut|/2 and c = cos(θ/2) = |uOut − uIn|/2 (θ between −uIn and uOut):
  // taking both from their own vectors avoids 1 ± dot cancellation near 0° and 180°.
  const double s = std::min(1.0, 0.5 * std::sqrt(sumSq));
  const double c = 0.5 * std::sqrt(diffSq);
  if (c == 0) {
    return vCap;
  }
  if (s == 0) {
    return 0.0;
  }
  const double diffNorm = 2.0 * c;
  double aj = kInf;
  for (size_t i = 0; i < n; ++i) {
    const double j = std::fabs(diff[i]) / diffNorm;
    if (j != 0) {
      aj = std::min(aj, axisAmax[i] / j);
    }
  }
  // s/(1−s) = s(1+s)/(1−s²) = s(1+s)/c²: no cancellation when s is close to 1.
  const double vjSq = aj * nonNegative(deviationMm) * s * (1.0 + s) / (c * c);
  return std::min(std::sqrt(vjSq), vCap);
}

} // namespace iso::sim
