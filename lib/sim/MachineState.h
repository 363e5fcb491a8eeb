//! @file MachineState.h
//! @brief The machine state of isosim beside the axes (SPEC §4): the R parameters (with the
//!        journal a G64 read-ahead rolls back), inputs, outputs and markers, the machine's
//!        input schedule and the running PLC sequences. No time of its own and no events: the
//!        Simulator asks, and reports what changed.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "lang/Limits.h"
#include "machine/Machine.h"

namespace iso::sim {

/// A step of the machine's input schedule.
struct InputStep {
  double t = 0;
  int index = 0;
  int value = 0;
};

/// An M sequence running on the PLC.
struct RunningSeq {
  uint64_t m = 0;
  double end = 0;
  uint64_t order = 0;
  const machine::MSequence* model = nullptr;
};

/// A write to an output or a marker, as its event reports it.
struct IoWrite {
  bool output = false; ///< else a marker
  int index = 0;
  uint8_t value = 0;
};

class MachineState {
public:
  /// Resets everything for a run on `m` (R presets, I/O sizes, the input schedule). With
  /// `userSlots`, dialect z32's PAR[0..999], PAL[0..255] (from pal_preset) and that many user
  /// parameters (by the string index of their name) are set up too.
  void start(const machine::Machine& m, size_t userSlots = 0);

  // ---- R parameters (1..lang::kMaxRIndex)
  double r(size_t i) const { return r_[i]; }
  /// Stores R[i]; `journaled` (reading ahead): the old value can be restored by rollbackR.
  void setR(size_t i, double v, bool journaled) {
    if (journaled) saveR(i);
    r_[i] = v;
    written_[i] = 1;
  }
  /// R[i] (or a PAR, a user parameter) was written in this run, or preset by the machine.
  bool written(size_t i) const { return written_[i] != 0; }
  /// A new statement is read ahead: the journal's position, to roll back to.
  size_t markR() {
    ++undoEpoch_;
    return rUndo_.size();
  }
  void rollbackR(size_t mark);
  /// Keeps the R writes read ahead.
  void commitR() { rUndo_.clear(); }

  // ---- dialect z32: PAR and user parameters live beside R (journaled the same way), PAL
  // is real-time (never read ahead). Indices are checked by the caller.
  static constexpr size_t kParBase = lang::kMaxRIndex + 1;
  static constexpr size_t kUserBase = kParBase + 1000;
  double par(size_t i) const { return r_[kParBase + i]; }
  void setPar(size_t i, double v, bool journaled) { setR(kParBase + i, v, journaled); }
  double user(uint32_t name) const { return r_[kUserBase + name]; }
  void setUser(uint32_t name, double v, bool journaled) { setR(kUserBase + name, v, journaled); }
  double pal(size_t i) const { return pal_[i]; }
  void setPal(size_t i, double v) { pal_[i] = v; }

  // ---- I/O (SPEC §4.5)
  /// $aa_in, $aa_out or $aa_marker at `index`; faults on a bad index.
  double ioRead(uint8_t sv, double index) const;
  /// $aa_out or $aa_marker at `index` = value (0 or 1); faults otherwise.
  IoWrite ioWrite(uint8_t sv, double index, double value);
  /// Sets input `index` (out of range: ignored); true when it changed.
  bool setInput(int index, int value);

  // ---- the input schedule
  /// The time of the next scheduled input step (infinity: none).
  double nextInputTime() const;
  /// Takes the next input step due at or before t.
  bool takeInputStep(double t, InputStep& out);

  // ---- PLC sequences
  const std::vector<RunningSeq>& seqs() const { return seqs_; }
  void startSeq(uint64_t m, double end, const machine::MSequence* model) {
    seqs_.push_back({m, end, seqOrder_++, model});
  }
  /// Takes the sequence ending first at or before t (ties: the one started first).
  bool takeEndedSeq(double t, RunningSeq& out);
  void stopSeqs() { seqs_.clear(); }

private:
  void saveR(size_t i);

  std::vector<double> r_;        ///< R, then (z32) PAR and the user parameters
  std::vector<uint8_t> written_; ///< by r_ index: written or preset (the debugger's view)
  std::vector<double> pal_;
  std::vector<std::pair<uint32_t, double>> rUndo_; ///< R writes made while reading ahead
  /// The statement (snapshot) epoch in which each R was last saved in rUndo_: one entry per R
  /// and statement read ahead, however often the statement stores it.
  std::vector<uint64_t> rSaved_;
  uint64_t undoEpoch_ = 0;
  std::vector<uint8_t> inputs_, outputs_, markers_;
  std::vector<InputStep> inputSteps_;
  size_t nextInput_ = 0;
  std::vector<RunningSeq> seqs_;
  uint64_t seqOrder_ = 0;
};

} // namespace iso::sim
