//! @file RunMath.h
//! @brief The pure run math of isosim: value arithmetic, comparisons with the §3.2 tolerance,
//!        integer indexes, and the program error (Fault) that ends a run.
//!
//! No machine, no time, no threads: each function maps values to a value or a Fault.
#pragma once

#include <cstdint>
#include <limits>
#include <string>

#include "image/Opcode.h"
#include "sim/Trace.h"

namespace iso::sim {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kIntTolerance = 1e-9;   ///< an index is an integer within this
constexpr double kCmpTolerance = 1e-12;  ///< relative equality of comparisons (§3.2)
constexpr double kLimitTolerance = 1e-9; ///< a target this close to a soft limit is on it (§4.3)

/// A program error that stops the run (thrown inside the interpreter, caught by the scheduler).
struct Fault {
  Status status;
  std::string what;
};

/// Throws Fault{Error, what}.
[[noreturn]] void fault(std::string what);
/// Throws Fault{Emergency, what}.
[[noreturn]] void emergency(std::string what);
/// An image the verifier should have refused: throws std::logic_error("isosim: " + what).
[[noreturn]] void internal(const std::string& what);

/// A number as the trace prints it (formatNumber).
std::string num(double v);
/// A value named in a runtime error: as the trace prints it when that text is the value
/// exactly, else to 15 significant digits (so an index of 3.000000002 is not shown as 3).
std::string valueText(double v);

/// a == b within the relative tolerance kCmpTolerance.
bool cmpEqual(double a, double b);
/// -1, 0 (equal within the tolerance), +1.
int cmpClass(double a, double b);
/// a op b for Add, Sub, Mul, Div; faults on division by zero, NaN and overflow.
double arith(image::Op op, double a, double b);
/// 1.0 or 0.0: a op b for the six comparison opcodes (equality within the tolerance).
double compare(image::Op op, double a, double b);
/// An index that must be an integer (within kIntTolerance) in [lo, hi]; `what` names it in the fault.
int64_t intIndex(double v, int64_t lo, int64_t hi, const char* what);

} // namespace iso::sim
