//! @file WhenWatch.cpp
//! @brief The root search of WHEN watching (WhenWatch.h).
#include "sim/WhenWatch.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "sim/RunMath.h"

namespace iso::sim {

namespace {

/// The sample points of (a, b): the grid a + k·h (not stored: a long move has millions of
/// points) merged on the fly with the phase boundaries and the last double before b.
class SamplePoints {
public:
  SamplePoints(double a, double b, const std::vector<AxisMotion>& axes, double h) : a_(a), h_(h) {
    for (const AxisMotion& ax : axes) {
      if (!(ax.tEnd > a)) continue;
      for (double t : {phaseEnd1(ax), phaseEnd2(ax), ax.tEnd})
        if (t > a && t < b) pts_.push_back(t);
    }
    const double ceilSteps = std::ceil((b - a) / h);
    steps_ = ceilSteps < 1e7 ? ceilSteps : 1; // grid points a + k·h, 0 < k < steps
    const double last = std::nextafter(b, a);
    if (last > a) pts_.push_back(last);
    std::sort(pts_.begin(), pts_.end());
    pts_.erase(std::unique(pts_.begin(), pts_.end()), pts_.end());
  }

  bool next(double& t) {
    const double g = gridK_ < steps_ ? a_ + gridK_ * h_ : kInf;
    const double p = pi_ < pts_.size() ? pts_[pi_] : kInf;
    if (g == kInf && p == kInf) return false;
    if (g <= p) {
      t = g;
      gridK_ += 1;
    } else {
      t = p;
      ++pi_;
    }
    return true;
  }

private:
  double a_, h_;
  double steps_ = 1;
  double gridK_ = 1;
  size_t pi_ = 0;
  std::vector<double> pts_;
};

/// The first instant in (lo, hi] where the condition holds, given it is false at lo and true at hi.
double bisectTrue(const WhenCondition& cond, double lo, double hi) {
  for (;;) {
    const double mid = lo + (hi - lo) / 2;
    if (!(mid > lo && mid < hi)) break;
    if (cond.holds(mid, nullptr, nullptr))
      hi = mid;
    else
      lo = mid;
  }
  return hi;
}

/// Where comparison k leaves its class `from` (at lo) in (lo, hi], to adjacent doubles.
double bisectClass(const WhenCondition& cond, double lo, double hi, size_t k, int from) {
  int clm[kMaxRecordedCmp];
  size_t nm = 0;
  for (;;) {
    const double mid = lo + (hi - lo) / 2;
    if (!(mid > lo && mid < hi)) break;
    cond.holds(mid, clm, &nm);
    if (k < nm && clm[k] == from)
      lo = mid;
    else
      hi = mid;
  }
  return hi;
}

} // namespace

WhenHit searchCondition(const WhenCondition& cond, double a, double b, const std::vector<AxisMotion>& axes, double h) {
  WhenHit out;
  SamplePoints points(a, b, axes, h);
  int cl0[kMaxRecordedCmp], cl1[kMaxRecordedCmp];
  size_t n0 = 0, n1 = 0;
  double t0 = a;
  try {
    cond.holds(t0, cl0, &n0);
    for (double t1 = 0; points.next(t1);) {
      if (!(t1 > t0)) continue;
      if (cond.holds(t1, cl1, &n1)) {
        out.found = true;
        out.t = bisectTrue(cond, t0, t1);
        return out;
      }
      // The condition is false at both ends; a comparison that changed in between may have
      // made it true for a moment (an equality, or several comparisons crossing).
      double bestT = kInf;
      const size_t nc = std::min(n0, n1);
      for (size_t k = 0; k < nc; ++k) {
        if (cl0[k] == cl1[k]) continue;
        const double hi = bisectClass(cond, t0, t1, k, cl0[k]);
        if (hi < bestT && cond.holds(hi, nullptr, nullptr)) bestT = hi;
      }
      if (bestT < kInf) {
        out.found = true;
        out.t = bestT;
        return out;
      }
      t0 = t1;
      std::copy(cl1, cl1 + n1, cl0);
      n0 = n1;
    }
  } catch (const Fault& f) {
    out.found = true;
    out.error = true;
    out.fault = f;
    out.t = t0;
  }
  return out;
}

} // namespace iso::sim
