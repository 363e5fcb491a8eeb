//! @file EvaluateTests.cpp
//! @brief The debugger's expressions (breakpoint conditions, watches): ISO expressions read by
//!        the frontend, computed as the controller computes them; hit conditions.
#include <doctest/doctest.h>

#include <map>
#include <string>

#include "TestUtil.h"
#include "dap/Evaluate.h"
#include "dap/Session.h"
#include "sim/TraceWriter.h"

using namespace iso;

namespace {
bool mentions(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

/// A stopped run with a few values.
class FakeView : public sim::RunView {
public:
  std::map<int, double> rs;
  double t = 12.5;
  double time() const override { return t; }
  uint64_t blocks() const override { return 42; }
  uint64_t statements() const override { return 50; }
  std::vector<sim::DebugThread> threads() const override { return {}; }
  std::vector<sim::DebugFrame> stack(uint32_t) const override { return {}; }
  sim::DebugModal modal(uint32_t) const override { return {}; }
  std::vector<std::pair<uint32_t, double>> rParameters() const override { return {}; }
  std::vector<sim::DebugValue> z32Parameters() const override { return {}; }
  std::vector<sim::DebugAxis> axes() const override { return {}; }
  std::vector<sim::DebugValue> machineFunctions() const override { return {}; }
  std::vector<sim::DebugValue> io() const override { return {}; }
  std::optional<double> r(double i) const override {
    if (i < 1 || i > 2880 || i != static_cast<int>(i)) return std::nullopt;
    auto it = rs.find(static_cast<int>(i));
    return it == rs.end() ? 0.0 : it->second;
  }
  std::optional<double> par(double i) const override { return i == 3 ? std::optional<double>(7) : std::nullopt; }
  std::optional<double> pal(double) const override { return std::nullopt; }
  std::optional<double> userParameter(std::string_view name) const override {
    return name == "HA" ? std::optional<double>(2.5) : std::nullopt;
  }
  std::optional<double> axisVariable(lang::SysVar sv, char axis) const override {
    if (axis != 'X') return std::nullopt;
    return sv == lang::SysVar::AaIw ? 10.0 : 20.0;
  }
  std::optional<double> ioVariable(lang::SysVar, double index) const override {
    return index == 4 ? std::optional<double>(1) : std::nullopt;
  }
  sim::DebugFrame where(uint32_t) const override { return {}; }
};

std::string eval(const std::string& text, const sim::RunView& v, const machine::Machine& m = test::builtin(),
                 bool z32 = false) {
  auto e = dap::Expression::parse(text, m, z32);
  if (!e) return "parse: " + (e.error().where.empty() ? "" : e.error().where + ": ") + e.error().message;
  auto r = e->evaluate(v);
  if (!r) return "error: " + r.error().message;
  return sim::formatNumber(*r) + (e->isCondition() ? "?" : "");
}
} // namespace

TEST_CASE("debugger expressions: values and conditions as the controller computes them") {
  FakeView v;
  v.rs = {{1, 3}, {2, 4}, {5, 2}};
  CHECK(eval("R1", v) == "3");
  CHECK(eval("R1 + R2 * 2", v) == "14"); // strictly left to right: (3 + 4) * 2
  CHECK(eval("R[R5 - 1]", v) == "3");
  CHECK(eval("-R2 / 8", v) == "-0.5");
  CHECK(eval("R1 < R2", v) == "1?");
  CHECK(eval("(R1 > 5) OR (R2 == 4)", v) == "1?");
  CHECK(eval("NOT (R1 == 3)", v) == "0?");
  CHECK(eval("$aa_iw[X] + $aa_fw[X]", v) == "30");
  CHECK(eval("$aa_out[4]", v) == "1");
  CHECK(eval("time", v) == "12.5");
  CHECK(eval("  TIME ", v) == "12.5");
  CHECK(eval("blocks", v) == "42");
}

TEST_CASE("debugger expressions: errors name the column or the value that does not exist") {
  FakeView v;
  CHECK(mentions(eval("R1 +", v), "parse: column 5:"));
  CHECK(mentions(eval("R1 R2", v), "after the expression"));
  CHECK(mentions(eval("R1 < 2 AND R2 > 1", v), "parenthesised"));
  CHECK(eval("", v) == "parse: no expression");
  CHECK(mentions(eval(std::string(241, '1'), v), "longer than 240"));
  CHECK(mentions(eval("R1\nR2", v), "one line"));
  CHECK(eval("R1 / R2", v) == "error: division by zero");
  CHECK(mentions(eval("R[0]", v), "R[0] does not exist"));
  CHECK(mentions(eval("$aa_iw[Y]", v), "no axis Y"));
  CHECK(mentions(eval("$aa_out[9]", v), "does not exist"));
}

TEST_CASE("debugger expressions: z32 parameters") {
  FakeView v;
  machine::Machine m = test::builtin();
  m.dialect = machine::Dialect::Z32;
  m.parameters = {"HA"};
  CHECK(eval("PAR[3] + HA", v, m, true) == "9.5");
  CHECK(mentions(eval("PAR[4]", v, m, true), "PAR[4] does not exist"));
  CHECK(mentions(eval("PAR[3]", v), "parse:")); // not in dialect sidac
}

TEST_CASE("debugger hit conditions: N, ==N, >N, >=N, <N, <=N, %N") {
  using dap::HitCondition;
  auto holds = [](const char* text, uint64_t hits) { return HitCondition::parse(text)->holds(hits); };
  CHECK(holds("", 1));
  CHECK(holds("3", 3));
  CHECK_FALSE(holds("3", 4));
  CHECK(holds("== 2", 2));
  CHECK(holds(">2", 3));
  CHECK_FALSE(holds(">2", 2));
  CHECK(holds(">=2", 2));
  CHECK(holds("<2", 1));
  CHECK_FALSE(holds("<=2", 3));
  CHECK(holds("%3", 6));
  CHECK_FALSE(holds("%3", 7));
  CHECK_FALSE(HitCondition::parse("%0").has_value());
  CHECK_FALSE(HitCondition::parse("often").has_value());
  CHECK_FALSE(HitCondition::parse(">=-1").has_value());
  CHECK_FALSE(HitCondition::parse("99999999999999").has_value());
}
