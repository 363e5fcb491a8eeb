//! @file G64Chain.h
//! @brief The G64 chain of isosim (SPEC §5.2): the blocks read ahead, the thread snapshot a
//!        read-ahead rolls back to, the plan of the whole chain, and running it block by block.
//!        No time and no machine: the Simulator reads ahead, starts each block and runs the
//!        junctions; this room keeps what a chain is.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "lang/Limits.h"
#include "sim/MovePlanner.h"
#include "sim/PathPlanner.h"
#include "sim/Thread.h"

namespace iso::sim {

/// The thread state to return to when reading ahead meets a line that ends the chain, with the
/// marks of the journals (R, --profile) and the step count taken at the same point.
struct ChainSnapshot {
  uint32_t pc = 0;
  std::vector<double> stack;
  std::vector<Frame> frames;
  Modal modal;
  uint32_t stmt = kNoIndex;
  size_t rUndo = 0;    ///< MachineState::markR()
  uint64_t steps = 0;  ///< statements executed
  size_t after = 0;    ///< statements read ahead after the last block
  size_t profUndo = 0; ///< ProfileRecorder::mark()
};

class G64Chain {
public:
  bool collecting() const { return collecting_; } ///< reading ahead (no time passes)
  bool active() const { return active_; }         ///< running its blocks

  /// Starts reading ahead from the axes' current targets.
  void begin(const double* targets, int nAxes);
  /// A block read ahead (length > 0) joins the chain.
  void append(PathBlock pb, uint32_t stmt);
  /// A zero-length block read ahead: only its checks remain, run when the path reaches the
  /// end of the last block.
  void appendZeroLength(PathBlock pb, uint32_t stmt);
  /// A statement read ahead: its line event comes when the path reaches the last block's end.
  void noteStatement(uint32_t stmt) { blocks_.back().after.push_back(stmt); }
  /// Counts one statement read ahead; false when the chain has read `cap` statements.
  bool countReadAhead(uint64_t cap) { return ++readAhead_ <= cap; }
  /// True when `lookaheadBlocks` blocks have been read (at least one).
  bool full(int lookaheadBlocks) const;
  /// Where axis `ax` is after the blocks read so far.
  double predicted(int ax) const { return pred_[ax]; }

  /// Remembers the thread and the journal marks at this point of the read-ahead.
  void snapshot(const Thread& th, size_t rUndo, uint64_t steps, size_t profUndo);
  /// Puts the thread back where the last snapshot was taken and drops the statements read
  /// after it; the caller rolls its journals back to the marks returned.
  const ChainSnapshot& restore(Thread& th);

  /// Ends reading ahead and plans the chain: one block alone runs from rest to rest (as in
  /// G60), more run the junction speeds of planChain.
  void plan(const std::vector<double>& amax, double cornerDeviationMm);
  PathBlock& current() { return blocks_[cur_]; }
  const PlannedBlock& currentPlan() const { return planned_[cur_]; }
  /// Moves on to the next block; false (and the chain ends) after the last.
  bool advance();

private:
  bool collecting_ = false;
  bool active_ = false;
  std::vector<PathBlock> blocks_;
  std::vector<PlannedBlock> planned_; ///< speeds and trapezoid of each block
  size_t cur_ = 0;
  uint64_t readAhead_ = 0;                ///< statements read ahead so far
  double pred_[lang::kMaxImageAxes] = {}; ///< axis targets after the blocks read so far
  ChainSnapshot snap_;
};

} // namespace iso::sim
