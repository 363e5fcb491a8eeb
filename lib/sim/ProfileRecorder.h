//! @file ProfileRecorder.h
//! @brief The --profile journal of isosim: where the main program's time went, by statement,
//!        procedure, M number and category (SPEC §6, TimeProfile.h). Counts made while a G64
//!        chain reads ahead are journaled, so that a rollback can take them back (mark/rollback).
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "image/Image.h"
#include "sim/InstructionStream.h"
#include "sim/Motion.h"
#include "sim/MotionProfile.h"
#include "sim/TimeProfile.h"

namespace iso::sim {

/// The reason a motion took its time, for a profile row: "feed", "velocity X", "accel Y",
/// "short (accel X)", "centripetal", "corner" (a G64 junction that bounds the block).
std::string boundLabel(const Trapezoid& prof, SpeedBound vb, char vAxis, char aAxis, bool corner);

class ProfileRecorder {
public:
  /// Empties the record for a program of `codeSize` instructions and `nProcs` procedures.
  void start(size_t codeSize, size_t nProcs);

  /// Statement `stmt` runs (journaled: it is read ahead, a rollback may take it back).
  void count(uint32_t stmt, bool journaled);
  /// Procedure `proc` is called (journaled as for count).
  void call(uint32_t proc, bool journaled);
  /// Statement `stmt` (kNoIndex: none) was bound by `label` (each label once).
  void bound(uint32_t stmt, std::string label);
  /// An M sequence of `m` started and runs `duration` s.
  void mStarted(uint64_t m, double duration);

  /// The main program waits from t0 on for `cat` (for statement `stmt`; `m`: the M sequence
  /// waited for, or -1), after the phases of `mot` when it is a motion wait. Closes the open
  /// activity first (at t0). Returns the activity's procedures, for the caller to fill.
  std::vector<uint32_t>& begin(uint32_t stmt, TimeCat cat, int64_t m, double t0, const AxisMotion* mot);
  /// Is an activity open?
  bool open() const { return act_.open; }
  /// Closes the open activity at t1: its time goes to its statement, M, procedures and the total.
  void end(double t1);
  /// The open activity's procedures.
  void setProcs(const std::vector<uint32_t>& procs) { act_.procs = procs; }

  /// The journal's position: rollback(mark()) takes back what was journaled after it.
  size_t mark() const { return undo_.size(); }
  void rollback(size_t mark);
  /// Keeps what was journaled (the read-ahead is taken).
  void commit() { undo_.clear(); }

  /// The profile of a run that ended at `cycleTime`; `first` is the procedure that ran first.
  void build(TimeProfile& out, const image::Image& img, const InstructionStream& prog,
             const std::vector<std::string>& names, uint32_t first, double cycleTime) const;

private:
  struct LineAcc {
    uint32_t stmt = 0;
    uint64_t count = 0;
    TimeSplit time;
    std::vector<std::string> bounds;
  };
  /// What the main program is waiting for, from t0 on: the motion of `mot` (split into its
  /// phases, up to mEnd), then `cat`.
  struct Activity {
    bool open = false;
    uint32_t stmt = kNoIndex;
    TimeCat cat = TimeCat::Plc;
    int64_t m = -1;
    double t0 = 0, p1 = 0, p2 = 0, mEnd = 0;
    std::vector<uint32_t> procs; ///< procedures on the call stack, each once
  };
  static constexpr uint32_t kCallUndo = 0x80000000u;
  LineAcc& lineAcc(uint32_t stmt);

  size_t codeSize_ = 0;
  std::vector<int32_t> pcToAcc_;
  std::vector<LineAcc> lineAcc_;
  std::vector<uint64_t> procCalls_;
  std::vector<TimeSplit> procTime_;
  std::map<uint64_t, MProfile> mProf_;
  TimeSplit total_;
  Activity act_;
  std::vector<uint32_t> undo_; ///< counts journaled (kCallUndo | proc, or a stmt)
};

} // namespace iso::sim
