//! @file SimToolRun.h
//! @brief isosim in process, as its main calls it: runSimulate with captured standard output
//!        and error, for the driver tests of isosim.
#pragma once

#include <sstream>
#include <string>

#include "driver/Simulate.h"

namespace iso::test {

/// What one isosim run printed and returned.
struct ToolRun {
  int rc = -1;
  std::string out, err;
};

inline ToolRun runSim(const driver::SimulateOptions& o) {
  std::ostringstream out, err;
  driver::Io io{out, err, false, false};
  ToolRun r;
  r.rc = driver::runSimulate(o, io);
  r.out = out.str();
  r.err = err.str();
  return r;
}

inline bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

} // namespace iso::test
