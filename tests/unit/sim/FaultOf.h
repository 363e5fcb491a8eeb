//! @file FaultOf.h
//! @brief The message of the sim::Fault a call throws, for the unit tests of the pure rooms.
#pragma once

#include <string>

#include "sim/RunMath.h"

namespace iso::sim::test {

/// The message of the Fault `f()` throws ("" when it throws none).
template <class F> std::string faultOf(F&& f) {
  try {
    f();
  } catch (const Fault& e) {
    return e.what;
  }
  return "";
}

} // namespace iso::sim::test
