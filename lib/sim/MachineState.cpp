//! @file MachineState.cpp
//! @brief The machine state of isosim beside the axes (MachineState.h).
#include "sim/MachineState.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "image/Opcode.h"
#include "lang/Limits.h"
#include "sim/RunMath.h"

namespace iso::sim {

using image::SysVarId;

void MachineState::start(const machine::Machine& m, size_t userSlots) {
  const size_t slots = userSlots > 0 ? kUserBase + userSlots : size_t{lang::kMaxRIndex} + 1;
  r_.assign(slots, 0.0);
  rSaved_.assign(slots, 0);
  written_.assign(slots, 0);
  for (const auto& [idx, v] : m.rPreset)
    if (idx >= 1 && static_cast<uint64_t>(idx) <= lang::kMaxRIndex) {
      r_[static_cast<size_t>(idx)] = v;
      written_[static_cast<size_t>(idx)] = 1;
    }
  pal_.assign(userSlots > 0 ? image::kPalCount : 0, 0.0);
  for (const auto& [idx, v] : m.palPreset)
    if (idx >= 0 && static_cast<size_t>(idx) < pal_.size()) pal_[static_cast<size_t>(idx)] = v;
  inputs_.assign(static_cast<size_t>(std::max(0, m.numInputs)), 0);
  outputs_.assign(static_cast<size_t>(std::max(0, m.numOutputs)), 0);
  markers_.assign(lang::kMaxMarker + 1, 0);
  for (const auto& [idx, steps] : m.inputs)
    for (const auto& [t, v] : steps)
      inputSteps_.push_back({t, idx, v});
  std::stable_sort(inputSteps_.begin(), inputSteps_.end(), [](const InputStep& a, const InputStep& b) {
    return a.t < b.t || (a.t == b.t && a.index < b.index);
  });
}

void MachineState::saveR(size_t i) {
  if (rSaved_[i] == undoEpoch_) return;
  rSaved_[i] = undoEpoch_;
  rUndo_.emplace_back(static_cast<uint32_t>(i), r_[i]);
}

void MachineState::rollbackR(size_t mark) {
  while (rUndo_.size() > mark) {
    r_[rUndo_.back().first] = rUndo_.back().second;
    rUndo_.pop_back();
  }
}

double MachineState::ioRead(uint8_t sv, double index) const {
  const char* name = image::sysVarIdName(sv);
  switch (static_cast<SysVarId>(sv)) {
  case SysVarId::AaIn: {
    if (inputs_.empty()) fault(fmt::format("{}: the machine has no inputs (num_inputs 0)", name));
    auto i = intIndex(index, 0, static_cast<int64_t>(inputs_.size()) - 1, name);
    return inputs_[static_cast<size_t>(i)];
  }
  case SysVarId::AaOut: {
    if (outputs_.empty()) fault(fmt::format("{}: the machine has no outputs (num_outputs 0)", name));
    auto i = intIndex(index, 0, static_cast<int64_t>(outputs_.size()) - 1, name);
    return outputs_[static_cast<size_t>(i)];
  }
  case SysVarId::AaMarker: {
    auto i = intIndex(index, 0, lang::kMaxMarker, name);
    return markers_[static_cast<size_t>(i)];
  }
  default: internal("I/O variable id");
  }
}

IoWrite MachineState::ioWrite(uint8_t sv, double index, double value) {
  const bool out = static_cast<SysVarId>(sv) == SysVarId::AaOut;
  const char* name = image::sysVarIdName(sv); // $aa_out or $aa_marker
  if (out && outputs_.empty()) fault("$aa_out: the machine has no outputs (num_outputs 0)");
  auto i = intIndex(index, 0, out ? static_cast<int64_t>(outputs_.size()) - 1 : lang::kMaxMarker, name);
  const double r = std::nearbyint(value);
  if (!(std::fabs(value - r) <= kIntTolerance) || (r != 0 && r != 1))
    fault(fmt::format("{}[{}] = {}: only 0 or 1 can be written", name, i, valueText(value)));
  const auto v = static_cast<uint8_t>(r != 0);
  (out ? outputs_ : markers_)[static_cast<size_t>(i)] = v;
  return IoWrite{out, static_cast<int>(i), v};
}

bool MachineState::setInput(int index, int value) {
  if (index < 0 || static_cast<size_t>(index) >= inputs_.size()) return false;
  auto& slot = inputs_[static_cast<size_t>(index)];
  const auto v = static_cast<uint8_t>(value != 0);
  if (slot == v) return false;
  slot = v;
  return true;
}

double MachineState::nextInputTime() const {
  return nextInput_ < inputSteps_.size() ? inputSteps_[nextInput_].t : std::numeric_limits<double>::infinity();
}

bool MachineState::takeInputStep(double t, InputStep& out) {
  if (!(nextInput_ < inputSteps_.size() && inputSteps_[nextInput_].t <= t)) return false;
  out = inputSteps_[nextInput_++];
  return true;
}

bool MachineState::takeEndedSeq(double t, RunningSeq& out) {
  size_t best = seqs_.size();
  for (size_t i = 0; i < seqs_.size(); ++i)
    if (seqs_[i].end <= t && (best == seqs_.size() || seqs_[i].end < seqs_[best].end ||
                              (seqs_[i].end == seqs_[best].end && seqs_[i].order < seqs_[best].order)))
      best = i;
  if (best == seqs_.size()) return false;
  out = seqs_[best];
  seqs_.erase(seqs_.begin() + static_cast<std::ptrdiff_t>(best));
  return true;
}

} // namespace iso::sim
