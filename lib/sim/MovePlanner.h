//! @file MovePlanner.h
//! @brief The pure move planner of isosim (SPEC §5): a Move instruction's operands, the modal
//!        state and the machine's limits in; an interpolated path block (line or arc) or
//!        independent axis segments out. No time, no threads: the Simulator starts the result.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "image/Image.h"
#include "lang/Limits.h"
#include "machine/Machine.h"
#include "sim/InstructionStream.h"
#include "sim/Motion.h"
#include "sim/PathPlanner.h"
#include "support/FixedVec.h"

namespace iso::sim {

constexpr int kMaxMoveAxes = lang::kMaxImageAxes;

/// One interpolated block (line or arc), ready to start alone or as one block of a G64 chain.
struct PathBlock {
  PlanBlock plan; ///< length, V, A, tangents
  SpeedBound vBound = SpeedBound::None;
  int vAxis = -1, aAxis = -1; ///< machine axes bounding V (-1: the feed) and A
  struct Seg {
    int axis;
    AxisMotion seg; ///< geometry; t0, tEnd and prof are set when the block starts
  };
  support::FixedVec<Seg, kMaxMoveAxes> segs;
  uint32_t check = 0; ///< programmed axes: must not be moving when the block starts
  struct Limit {
    int axis;
    double lo, hi;
  };
  using LimitList = support::FixedVec<Limit, kMaxMoveAxes>;
  LimitList limits;            ///< soft-limit checks when the block starts
  uint32_t stmt = kNoIndex;    ///< the block's statement
  std::vector<uint32_t> after; ///< statements read ahead after it: their line events come at its end
  std::vector<uint32_t> procs; ///< --profile: the procedures on the call stack when it was read
  /// Zero-length blocks read ahead after it: their checks run when the path reaches its end.
  struct Check {
    uint32_t stmt;
    uint32_t mask;
    LimitList limits;
  };
  std::vector<Check> zeroChecks;
};

/// The decoded words of one Move instruction, by machine axis.
struct MoveWords {
  uint32_t prog = 0;   ///< programmed axes
  uint32_t faMask = 0; ///< axes with an Fa word
  int progCount = 0;
  bool anyNb = false;            ///< some axis is POSA (does not block)
  double tgt[kMaxMoveAxes] = {}; ///< absolute targets of the programmed axes
  double fa[kMaxMoveAxes] = {};
  bool nb[kMaxMoveAxes] = {};
  bool arcWord[4] = {false, false, false, false}; ///< I J K CR given
  double arcVal[4] = {0, 0, 0, 0};
};

/// Decodes the `n` operands `vals` of a Move whose descriptors are `moves[first..]`.
/// `cur[a]`: machine axis a's programmed position before the block (for G91).
/// `offset[a]` (z32, may be null): the selected origin's offset, added to an absolute target.
/// Faults on a value that is not finite, an axis or Fa given twice, an overflowing target.
MoveWords decodeMove(const std::vector<uint8_t>& moves, uint32_t first, uint32_t n, const double* vals,
                     const std::vector<int>& axisMap, const machine::Machine& m, bool incremental, const double* cur,
                     const double* offset = nullptr);

/// A move to plan: its words, the modal state, and where the axes are.
struct MoveRequest {
  MoveWords words;
  uint8_t motion = 0;          ///< 0..3 (G00..G03)
  uint8_t plane = 17;          ///< 17, 18, 19
  double feed = 0;             ///< F, mm/s; NaN = never set
  const double* cur = nullptr; ///< programmed position of each machine axis before the block
};

/// The machine's limits, by machine axis.
struct MoveLimits {
  const machine::Machine* m = nullptr;
  const std::vector<double>* vmax = nullptr;
  const std::vector<double>* amax = nullptr;
  double feedScale = 1.0;  ///< the feed override: times the programmed F and Fa
  double rapidScale = 1.0; ///< the rapid override: times max_velocity for G00
};

/// What a move does.
struct MovePlan {
  bool path = false; ///< an interpolated block (`block`), else independent axes (`segs`)
  PathBlock block;   ///< path: zero length when no axis moves
  /// Independent axes: each segment's prof and tEnd are from t0 = 0 (the Simulator shifts them).
  struct AxisSeg {
    int axis;
    AxisMotion seg;
    bool blocking;
  };
  support::FixedVec<AxisSeg, kMaxMoveAxes> segs;
  uint32_t check = 0;     ///< independent: programmed axes (not moving, within the soft limits)
  bool faIgnored = false; ///< Fa on a G00 line (a warning)
  /// A feed move whose programmed F (or Fa), times the feed override, is above an axis'
  /// max_velocity: the axis limit sets the speed (a summary warning lists these lines).
  bool feedCapped = false;
};

/// Plans a move (SPEC §5.1–§5.3). Faults on words the motion does not allow, a missing or
/// non-positive feed, and an arc that does not close.
MovePlan planMove(const MoveRequest& rq, const MoveLimits& lim);

} // namespace iso::sim
