//! @file Evaluate.h
//! @brief The debugger's expressions: an ISO expression (SPEC §3: R parameters, system
//!        variables, z32 PAR/PAL and user parameters, arithmetic, comparisons, logic) parsed by
//!        the frontend and evaluated against a stopped run. `time` and `blocks` name the
//!        simulated time and the blocks so far.
#pragma once

#include <memory>
#include <string>

#include "machine/Machine.h"
#include "sim/Debug.h"
#include "support/Expected.h"

namespace iso::dap {

/// The longest expression accepted (a program line's limit).
inline constexpr size_t kMaxExpressionBytes = 240;

/// An expression parsed once, evaluated at each stop (a breakpoint condition).
class Expression {
public:
  ~Expression();
  Expression(Expression&&) noexcept;
  Expression& operator=(Expression&&) noexcept;

  /// Parses `text` for a program of `m`'s axes and parameters (`z32`: the z32 dialect); the
  /// error says what is wrong and at which column.
  static support::Expected<Expression> parse(const std::string& text, const machine::Machine& m, bool z32);

  /// The value against `view`; an error for a division by zero or an index that does not
  /// exist. A comparison or a logic operation gives 1 or 0.
  support::Expected<double> evaluate(const sim::RunView& view) const;
  /// The expression is a condition (a comparison, logic, NOT), not a value.
  bool isCondition() const;

private:
  struct Impl;
  explicit Expression(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

} // namespace iso::dap
