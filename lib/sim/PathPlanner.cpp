//! @file PathPlanner.cpp
//! @brief Junction speeds and the two-pass speed planning of a G64 chain.
#include "sim/PathPlanner.h"

#include <algorithm>
#include <cmath>

namespace iso::sim {

std::vector<PlannedBlock> planChain(const std::vector<PlanBlock>& blocks, const std::vector<double>& axisAmax,
                                    double deviationMm) {
  const size_t n = blocks.size();
  std::vector<PlannedBlock> out(n);
  if (n == 0) return out;
  // Junction limit at the start of each block (block 0 starts at rest).
  std::vector<double> vj(n, 0.0);
  std::vector<JunctionBound> jb(n, JunctionBound::Rest);
  for (size_t k = 1; k < n; ++k) {
    const PlanBlock& a = blocks[k - 1];
    const PlanBlock& b = blocks[k];
    double cap = std::min(a.vmax, b.vmax);
    double v = junctionSpeed(a.uEnd, b.uStart, axisAmax, deviationMm, a.vmax, b.vmax);
    vj[k] = v;
    jb[k] = v < cap ? JunctionBound::Corner : JunctionBound::Velocity;
  }
  // Backward pass: the highest entry speed from which each block can still brake to the
  // (already limited) entry speed of the next block, ending the chain at rest.
  std::vector<double> entry(n), exitv(n);
  std::vector<JunctionBound> entryB(n), exitB(n);
  double next = 0.0;
  JunctionBound nextB = JunctionBound::Rest;
  for (size_t k = n; k-- > 0;) {
    const PlanBlock& b = blocks[k];
    exitv[k] = next;
    exitB[k] = nextB;
    double brake = std::sqrt(next * next + 2.0 * b.accel * b.length);
    if (k == 0) {
      entry[k] = 0.0;
      entryB[k] = JunctionBound::Rest;
    } else if (brake < vj[k]) {
      entry[k] = brake;
      entryB[k] = JunctionBound::Accel;
    } else {
      entry[k] = vj[k];
      entryB[k] = jb[k];
    }
    next = entry[k];
    nextB = entryB[k];
  }
  // Forward pass: what each block can reach from its entry speed.
  for (size_t k = 0; k < n; ++k) {
    const PlanBlock& b = blocks[k];
    double reach = std::sqrt(entry[k] * entry[k] + 2.0 * b.accel * b.length);
    if (reach < exitv[k]) {
      exitv[k] = reach;
      exitB[k] = JunctionBound::Accel;
      if (k + 1 < n) {
        entry[k + 1] = reach;
        entryB[k + 1] = JunctionBound::Accel;
      }
    }
    out[k].vEntry = entry[k];
    out[k].vExit = exitv[k];
    out[k].vJunction = vj[k];
    out[k].entryBound = entryB[k];
    out[k].exitBound = exitB[k];
    out[k].profile = makeTrapezoid(b.length, b.vmax, b.accel, entry[k], exitv[k]);
  }
  return out;
}

} // namespace iso::sim
