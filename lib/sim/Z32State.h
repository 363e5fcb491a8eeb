//! @file Z32State.h
//! @brief The machine functions of dialect z32 (SPEC §4.6): spindle, coolants and tool, as a
//!        pure state machine. The simulator feeds it S and T words and managed M functions at
//!        the instant they run and reports what changed as events.
#pragma once

#include <cstdint>
#include <optional>

#include "lang/MFunctions.h"

namespace iso::sim {

enum class SpindleDir : uint8_t { Stop, Cw, Ccw, Orient };
/// "stop", "cw", "ccw", "orient" (JSON trace events).
const char* spindleDirName(SpindleDir d);

class Z32State {
public:
  /// What an operation changed (each change is one trace event).
  struct Change {
    bool spindle = false;
    bool coolant = false;
    bool tool = false;
    bool speedUnset = false; ///< M3/M4 with no S ever: the spindle turns at 0 rpm
    bool toolUnset = false;  ///< M6 with no T ever: the tool did not change
  };

  /// S: the programmed speed (rpm, >= 0); a turning spindle takes it at once.
  Change setSpeed(double rpm, double now);
  /// T: the programmed tool (mounted by the next M6).
  void setProgrammedTool(int64_t tool) { programmed_ = tool; }
  /// The effect of a managed or final M (roles Plain, End and Return change nothing).
  /// M1 acts only when `optionalStop`.
  Change apply(lang::MRole role, double now, bool optionalStop);
  /// The tool change of M6 alone (a special M6 applies it when its subprogram returns).
  Change changeTool(double now);
  /// TA: the actual tool, mounted at once (no tool change: spindle and coolants stay).
  void mountTool(int64_t tool) { mounted_ = tool; }
  /// Closes the spindle-on time at the end of the run.
  void finish(double now) { setTurning(false, now); }

  SpindleDir dir() const { return dir_; }
  double rpm() const { return turning() ? speed_ : 0; }
  bool coolant1() const { return c1_; }
  bool coolant2() const { return c2_; }
  std::optional<int64_t> tool() const { return mounted_; }
  uint64_t toolChanges() const { return toolChanges_; }
  double spindleOnS() const { return onTotal_; }

private:
  bool turning() const { return dir_ == SpindleDir::Cw || dir_ == SpindleDir::Ccw; }
  void setDir(SpindleDir d, double now, Change& c);
  void coolantsOff(Change& c);
  void setTurning(bool on, double now);

  SpindleDir dir_ = SpindleDir::Stop;
  bool speedSet_ = false;
  double speed_ = 0;
  bool c1_ = false, c2_ = false;
  std::optional<int64_t> programmed_, mounted_;
  uint64_t toolChanges_ = 0;
  double onSince_ = -1; ///< >= 0 while the spindle turns at rpm > 0
  double onTotal_ = 0;
};

} // namespace iso::sim
