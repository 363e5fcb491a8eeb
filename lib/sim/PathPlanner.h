//! @file PathPlanner.h
//! @brief G64 continuous path (SPEC §5.2): junction speeds between consecutive interpolated
//!        blocks and a backward + forward pass so that every block runs its own trapezoid
//!        between an entry and an exit speed, starting and ending the chain at rest.
#pragma once

#include <cstdint>
#include <vector>

#include "sim/MotionProfile.h"

namespace iso::sim {

/// One interpolated block of a chain (a line or an arc), in machine-axis space.
struct PlanBlock {
  double length = 0; ///< path length d > 0 (zero-length blocks are not chained)
  double vmax = 0;   ///< V of the block (feed, axis velocities, centripetal limit)
  double accel = 0;  ///< A of the block
  AxisValues uStart; ///< unit tangent at the start (one component per machine axis)
  AxisValues uEnd;   ///< unit tangent at the end (== uStart for a line)
};

/// Why a block's entry or exit speed is what it is.
enum class JunctionBound : uint8_t {
  Rest,     ///< the chain starts or ends here (speed 0)
  Corner,   ///< the junction-deviation limit of the corner
  Velocity, ///< min(V_in, V_out): the corner does not limit
  Accel,    ///< reachable speed: the neighbour block is too short to brake or accelerate more
};

struct PlannedBlock {
  double vEntry = 0;
  double vExit = 0;
  double vJunction = 0; ///< the corner limit at the block's start (0 for the first)
  JunctionBound entryBound = JunctionBound::Rest;
  JunctionBound exitBound = JunctionBound::Rest;
  Trapezoid profile; ///< makeTrapezoid(length, vmax, accel, vEntry, vExit)
};

/// Plans one chain from rest to rest. `axisAmax` has one entry per machine axis;
/// `deviationMm` is corner_deviation_mm.
std::vector<PlannedBlock> planChain(const std::vector<PlanBlock>& blocks, const std::vector<double>& axisAmax,
                                    double deviationMm);

} // namespace iso::sim
