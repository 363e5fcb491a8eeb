//! @file RunMath.cpp
//! @brief The pure run math of isosim (RunMath.h).
#include "sim/RunMath.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <stdexcept>

#include <fmt/format.h>

#include "sim/TraceWriter.h"

namespace iso::sim {

using image::Op;

void fault(std::string what) { throw Fault{Status::Error, std::move(what)}; }
void emergency(std::string what) { throw Fault{Status::Emergency, std::move(what)}; }
void internal(const std::string& what) { throw std::logic_error("isosim: " + what); }

std::string num(double v) { return formatNumber(v); }

std::string valueText(double v) {
  std::string s = formatNumber(v);
  if (std::isfinite(v) && readNumber(s) != v) s = fmt::format("{:.15g}", v);
  return s;
}

bool cmpEqual(double a, double b) { return std::fabs(a - b) <= kCmpTolerance * std::max(std::fabs(a), std::fabs(b)); }

int cmpClass(double a, double b) {
  if (cmpEqual(a, b)) return 0;
  return a < b ? -1 : 1;
}

double arith(Op op, double a, double b) {
  double r = 0;
  switch (op) {
  case Op::Add: r = a + b; break;
  case Op::Sub: r = a - b; break;
  case Op::Mul: r = a * b; break;
  case Op::Div:
    if (b == 0) fault(fmt::format("division by zero ({} / 0)", valueText(a)));
    r = a / b;
    break;
  default: internal("arith: not an arithmetic opcode");
  }
  if (!std::isfinite(r)) {
    static const char* sym[] = {"+", "-", "*", "/"};
    const char* s = sym[static_cast<int>(op) - static_cast<int>(Op::Add)];
    if (std::isnan(r)) fault(fmt::format("arithmetic gives no number (NaN): {} {} {}", valueText(a), s, valueText(b)));
    fault(fmt::format("arithmetic overflow: {} {} {}", valueText(a), s, valueText(b)));
  }
  return r;
}

double compare(Op op, double a, double b) {
  const int c = cmpClass(a, b);
  bool r = false;
  switch (op) {
  case Op::CmpGt: r = c > 0; break;
  case Op::CmpLt: r = c < 0; break;
  case Op::CmpEq: r = c == 0; break;
  case Op::CmpGe: r = c >= 0; break;
  case Op::CmpLe: r = c <= 0; break;
  case Op::CmpNe: r = c != 0; break;
  default: internal("compare: not a comparison opcode");
  }
  return r ? 1.0 : 0.0;
}

int64_t intIndex(double v, int64_t lo, int64_t hi, const char* what) {
  const double r = std::nearbyint(v);
  if (!std::isfinite(v) || std::fabs(v - r) > kIntTolerance)
    fault(fmt::format("{} index {} is not an integer", what, valueText(v)));
  if (r < static_cast<double>(lo) || r > static_cast<double>(hi))
    fault(fmt::format("{} index {} is outside {}..{}", what, num(r), lo, hi));
  return static_cast<int64_t>(r);
}

} // namespace iso::sim
