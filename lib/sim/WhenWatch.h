//! @file WhenWatch.h
//! @brief The root search of WHEN watching (SPEC §4.4): the first instant in an open interval
//!        at which a condition of time holds, to adjacent doubles. The condition is an oracle
//!        (the Simulator evaluates it on the axes' closed-form positions); the search itself
//!        knows only the sample points and bisection.
#pragma once

#include <cstddef>
#include <vector>

#include "sim/Motion.h"
#include "sim/RunMath.h"

namespace iso::sim {

/// Comparisons of a condition whose outcome class (-1, 0, +1) the search tracks.
constexpr size_t kMaxRecordedCmp = 64;

/// A WHEN condition as a function of time.
class WhenCondition {
public:
  virtual ~WhenCondition() = default;
  /// The condition at t. When `classes` is set, also the class (cmpClass) of each of its first
  /// kMaxRecordedCmp comparisons, in order, and their number in *n. May throw Fault.
  virtual bool holds(double t, int* classes, size_t* n) const = 0;
};

/// What a search found.
struct WhenHit {
  bool found = false; ///< the condition holds at `t` (or `error`)
  double t = 0;
  bool error = false; ///< evaluating the condition faulted at or after `t` (the last sample before)
  Fault fault{Status::Error, ""};
};

/// The first instant in (a, b) at which `cond` holds. Sample points: the phase boundaries of
/// every axis of `axes` moving after a, a grid of `h` from a, and the last double before b;
/// between two samples the condition turning true, or any comparison changing its class, is
/// located by bisection down to adjacent doubles.
WhenHit searchCondition(const WhenCondition& cond, double a, double b, const std::vector<AxisMotion>& axes, double h);

} // namespace iso::sim
