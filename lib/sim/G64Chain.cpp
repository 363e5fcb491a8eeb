//! @file G64Chain.cpp
//! @brief The G64 chain's blocks, snapshot and plan (SPEC §5.2).
#include "sim/G64Chain.h"

#include <algorithm>
#include <utility>

#include "sim/MotionProfile.h"

namespace iso::sim {

void G64Chain::begin(const double* targets, int nAxes) {
  collecting_ = true;
  active_ = false;
  blocks_.clear();
  planned_.clear();
  cur_ = 0;
  readAhead_ = 0;
  std::fill(std::begin(pred_), std::end(pred_), 0.0);
  std::copy(targets, targets + nAxes, pred_);
}

void G64Chain::append(PathBlock pb, uint32_t stmt) {
  pb.stmt = stmt;
  for (const auto& s : pb.segs)
    pred_[s.axis] = s.seg.target;
  blocks_.push_back(std::move(pb));
}

void G64Chain::appendZeroLength(PathBlock pb, uint32_t stmt) {
  blocks_.back().zeroChecks.push_back({stmt, pb.check, std::move(pb.limits)});
}

bool G64Chain::full(int lookaheadBlocks) const {
  return blocks_.size() >= static_cast<size_t>(std::max(1, lookaheadBlocks));
}

void G64Chain::snapshot(const Thread& th, size_t rUndo, uint64_t steps, size_t profUndo) {
  snap_.pc = th.pc;
  snap_.stack = th.stack;
  snap_.frames = th.frames;
  snap_.modal = th.modal;
  snap_.stmt = th.stmt;
  snap_.rUndo = rUndo;
  snap_.steps = steps;
  snap_.after = blocks_.back().after.size();
  snap_.profUndo = profUndo;
}

const ChainSnapshot& G64Chain::restore(Thread& th) {
  th.pc = snap_.pc;
  th.stack = snap_.stack;
  th.frames = snap_.frames;
  th.modal = snap_.modal;
  th.stmt = snap_.stmt;
  blocks_.back().after.resize(snap_.after);
  return snap_;
}

void G64Chain::plan(const std::vector<double>& amax, double cornerDeviationMm) {
  collecting_ = false;
  if (blocks_.size() == 1) {
    planned_.assign(1, PlannedBlock{});
    const PlanBlock& p = blocks_[0].plan;
    planned_[0].profile = makeTrapezoid(p.length, p.vmax, p.accel);
  } else {
    std::vector<PlanBlock> plan;
    plan.reserve(blocks_.size());
    for (auto& b : blocks_)
      plan.push_back(std::move(b.plan)); // not needed after planning
    planned_ = planChain(plan, amax, cornerDeviationMm);
  }
  cur_ = 0;
  active_ = true;
}

bool G64Chain::advance() {
  ++cur_;
  if (cur_ < blocks_.size()) return true;
  active_ = false;
  blocks_.clear();
  return false;
}

} // namespace iso::sim
