//! @file Evaluate.cpp
//! @brief The debugger's expressions, parsed by the frontend's lexer and parser and evaluated
//!        with the simulator's arithmetic (so `R1 == R2` has the run's tolerance).
#include "dap/Evaluate.h"

#include <deque>

#include <fmt/format.h>

#include "diag/Diagnostic.h"
#include "frontend/Ast.h"
#include "frontend/Lexer.h"
#include "frontend/Parser.h"
#include "sim/RunMath.h"
#include "sim/TraceWriter.h"
#include "support/CaseFold.h"
#include "support/Text.h"

namespace iso::dap {

namespace {
image::Op binOp(uint8_t op) {
  switch (static_cast<frontend::BinOp>(op)) {
  case frontend::BinOp::Add: return image::Op::Add;
  case frontend::BinOp::Sub: return image::Op::Sub;
  case frontend::BinOp::Mul: return image::Op::Mul;
  case frontend::BinOp::Div: return image::Op::Div;
  }
  return image::Op::Add;
}

image::Op cmpOp(uint8_t op) {
  switch (static_cast<frontend::CmpOp>(op)) {
  case frontend::CmpOp::Gt: return image::Op::CmpGt;
  case frontend::CmpOp::Lt: return image::Op::CmpLt;
  case frontend::CmpOp::Eq: return image::Op::CmpEq;
  case frontend::CmpOp::Ge: return image::Op::CmpGe;
  case frontend::CmpOp::Le: return image::Op::CmpLe;
  case frontend::CmpOp::Ne: return image::Op::CmpNe;
  }
  return image::Op::CmpEq;
}

struct EvalError {
  std::string message;
};
} // namespace

constexpr std::string_view kPrefix = "IF ";

struct Expression::Impl {
  /// The names that are not ISO: the simulated time and the blocks so far.
  enum class Special : uint8_t { None, Time, Blocks };
  static Special specialName(std::string_view text) {
    while (!text.empty() && (text.front() == ' ' || text.front() == '\t'))
      text.remove_prefix(1);
    while (!text.empty() && (text.back() == ' ' || text.back() == '\t'))
      text.remove_suffix(1);
    if (support::iequals(text, "time")) return Special::Time;
    if (support::iequals(text, "blocks")) return Special::Blocks;
    return Special::None;
  }

  std::string text;
  std::string line; ///< what the lexer reads: kPrefix, then the text
  frontend::File file;
  frontend::ExprId root = frontend::kNoExpr;
  Special special = Special::None;
  std::vector<std::string> userParams;

  double value(const sim::RunView& v, frontend::ExprId id) const {
    const frontend::Expr& e = file.exprs[static_cast<size_t>(id)];
    auto need = [](std::optional<double> x, const std::string& what) {
      if (!x) throw EvalError{what};
      return *x;
    };
    using K = frontend::ExprKind;
    switch (e.kind) {
    case K::Number: return e.value;
    case K::RParam: return need(v.r(e.rIndex), fmt::format("R{} does not exist", e.rIndex));
    case K::RIndirect: {
      const double i = value(v, e.a);
      return need(v.r(i), fmt::format("R[{}] does not exist (R1 to R{})", sim::formatNumber(i), lang::kMaxRIndex));
    }
    case K::SysAxis: {
      const std::string_view name = lang::sysVarInfo(e.sysvar).name;
      return need(v.axisVariable(e.sysvar, e.axis),
                  fmt::format("{}[{}]: the machine has no axis {}", name, e.axis, e.axis));
    }
    case K::SysIndex: {
      const double i = value(v, e.a);
      const std::string_view name = lang::sysVarInfo(e.sysvar).name;
      return need(v.ioVariable(e.sysvar, i),
                  fmt::format("{}[{}] does not exist on this machine", name, sim::formatNumber(i)));
    }
    case K::Neg: return -value(v, e.a);
    case K::Binary: {
      const double a = value(v, e.a);
      const double b = value(v, e.b);
      if (static_cast<frontend::BinOp>(e.op) == frontend::BinOp::Div && b == 0) throw EvalError{"division by zero"};
      return sim::arith(binOp(e.op), a, b);
    }
    case K::Compare: return sim::compare(cmpOp(e.op), value(v, e.a), value(v, e.b));
    case K::Logic: {
      const bool a = value(v, e.a) != 0;
      const bool b = value(v, e.b) != 0;
      return static_cast<frontend::LogicOp>(e.op) == frontend::LogicOp::And ? (a && b ? 1.0 : 0.0)
                                                                            : (a || b ? 1.0 : 0.0);
    }
    case K::Not: return value(v, e.a) != 0 ? 0.0 : 1.0;
    case K::Par: {
      const double i = value(v, e.a);
      return need(v.par(i),
                  fmt::format("PAR[{}] does not exist (PAR[0] to PAR[999], dialect z32)", sim::formatNumber(i)));
    }
    case K::Pal: {
      const double i = value(v, e.a);
      return need(v.pal(i),
                  fmt::format("PAL[{}] does not exist (PAL[0] to PAL[255], dialect z32)", sim::formatNumber(i)));
    }
    case K::UserParam: {
      const auto i = static_cast<size_t>(e.rIndex);
      const std::string name = i < userParams.size() ? userParams[i] : std::string("?");
      return need(v.userParameter(name), fmt::format("no user parameter {}", name));
    }
    case K::Error: break;
    }
    throw EvalError{"the expression has an error"};
  }
};

Expression::Expression(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Expression::~Expression() = default;
Expression::Expression(Expression&&) noexcept = default;
Expression& Expression::operator=(Expression&&) noexcept = default;

support::Expected<Expression> Expression::parse(const std::string& text, const machine::Machine& m, bool z32) {
  if (text.size() > kMaxExpressionBytes)
    return support::Error{"", fmt::format("the expression is longer than {} characters", kMaxExpressionBytes)};
  if (!support::isValidUtf8(text) || text.find_first_of("\r\n") != std::string::npos)
    return support::Error{"", "the expression must be one line of text"};
  auto impl = std::make_unique<Impl>();
  impl->text = text;
  impl->special = Impl::specialName(text);
  if (impl->special != Impl::Special::None) return Expression(std::move(impl));
  frontend::LexOptions lo;
  lo.dialect = z32 ? machine::Dialect::Z32 : machine::Dialect::Sidac;
  lo.axisLetters.clear();
  for (const machine::Axis& a : m.axes)
    lo.axisLetters.push_back(a.letter);
  if (z32) lo.userParams = m.parameters;
  impl->userParams = lo.userParams;
  diag::DiagnosticList diags;
  std::vector<frontend::Suppression> suppressions;
  std::deque<std::string> owned;
  // Lexed as the condition of an IF: a line that starts with `(` or a name would read as
  // something else (a comment, a label).
  impl->line = std::string(kPrefix) + impl->text;
  frontend::Lexer lexer(impl->line, 0, lo, diags, suppressions, owned);
  frontend::LogicalLine line;
  if (!lexer.next(line) || line.tokens.size() <= 2) return support::Error{"", "no expression"};
  frontend::Parser parser(impl->file, lo, diags);
  if (diags.items().empty()) impl->root = parser.parseExpressionAt(line, 1);
  if (impl->root == frontend::kNoExpr || !diags.items().empty()) {
    if (diags.items().empty()) return support::Error{"", "not an expression"};
    const diag::Diagnostic& d = diags.items().front();
    const uint32_t col = d.loc.col > kPrefix.size() ? d.loc.col - static_cast<uint32_t>(kPrefix.size()) : 1;
    return support::Error{fmt::format("column {}", col), d.message};
  }
  return Expression(std::move(impl));
}

support::Expected<double> Expression::evaluate(const sim::RunView& view) const {
  switch (impl_->special) {
  case Impl::Special::Time: return view.time();
  case Impl::Special::Blocks: return static_cast<double>(view.blocks());
  case Impl::Special::None: break;
  }
  try {
    return impl_->value(view, impl_->root);
  } catch (const EvalError& e) {
    return support::Error{"", e.message};
  } catch (const sim::Fault& f) {
    return support::Error{"", f.what};
  }
}

bool Expression::isCondition() const {
  if (impl_->special != Impl::Special::None) return false;
  return impl_->file.exprs[static_cast<size_t>(impl_->root)].isBool;
}

} // namespace iso::dap
