//! @file Z32State.cpp
//! @brief Spindle, coolants and tool of dialect z32 (SPEC §4.6).
#include "sim/Z32State.h"

namespace iso::sim {

const char* spindleDirName(SpindleDir d) {
  switch (d) {
  case SpindleDir::Stop: return "stop";
  case SpindleDir::Cw: return "cw";
  case SpindleDir::Ccw: return "ccw";
  case SpindleDir::Orient: return "orient";
  }
  return "?";
}

void Z32State::setTurning(bool on, double now) {
  if (on && onSince_ < 0) onSince_ = now;
  if (!on && onSince_ >= 0) {
    onTotal_ += now - onSince_;
    onSince_ = -1;
  }
}

void Z32State::setDir(SpindleDir d, double now, Change& c) {
  if (d != dir_) c.spindle = true;
  dir_ = d;
  setTurning(turning() && speed_ > 0, now);
}

void Z32State::coolantsOff(Change& c) {
  if (c1_ || c2_) c.coolant = true;
  c1_ = c2_ = false;
}

Z32State::Change Z32State::setSpeed(double rpm, double now) {
  Change c;
  if (turning() && rpm != speed_) c.spindle = true;
  speedSet_ = true;
  speed_ = rpm;
  setTurning(turning() && speed_ > 0, now);
  return c;
}

Z32State::Change Z32State::changeTool(double now) {
  Change c;
  setDir(SpindleDir::Stop, now, c);
  coolantsOff(c);
  if (!programmed_) {
    c.toolUnset = true;
    return c;
  }
  mounted_ = programmed_;
  ++toolChanges_;
  c.tool = true;
  return c;
}

Z32State::Change Z32State::apply(lang::MRole role, double now, bool optionalStop) {
  Change c;
  switch (role) {
  case lang::MRole::SpindleCw:
  case lang::MRole::SpindleCcw:
    c.speedUnset = !speedSet_;
    setDir(role == lang::MRole::SpindleCw ? SpindleDir::Cw : SpindleDir::Ccw, now, c);
    break;
  case lang::MRole::SpindleStop:
    setDir(SpindleDir::Stop, now, c);
    coolantsOff(c);
    break;
  case lang::MRole::SpindleOrient:
    setDir(SpindleDir::Orient, now, c);
    coolantsOff(c);
    break;
  case lang::MRole::ToolChange: return changeTool(now);
  case lang::MRole::Coolant1:
    c.coolant = !c1_;
    c1_ = true;
    break;
  case lang::MRole::Coolant2:
    c.coolant = !c2_;
    c2_ = true;
    break;
  case lang::MRole::CoolantOff: coolantsOff(c); break;
  case lang::MRole::OptionalStop:
    if (!optionalStop) break;
    [[fallthrough]];
  case lang::MRole::Stop:
    setDir(SpindleDir::Stop, now, c);
    coolantsOff(c);
    break;
  case lang::MRole::Plain:
  case lang::MRole::End:
  case lang::MRole::Return: break;
  }
  return c;
}

} // namespace iso::sim
