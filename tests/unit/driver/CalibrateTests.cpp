//! @file CalibrateTests.cpp
//! @brief isosim --calibrate: the calibration file (its errors with file:line:column), the
//!        bounded least-squares solver on analytic models (log and linear parameters, a bound
//!        that holds, keys no residual depends on, keys that act only together), and the
//!        number keys a calibration may fit.
#include <doctest/doctest.h>

#include <cmath>

#include "TestUtil.h"
#include "driver/Calibrate.h"
#include "driver/MachineOverrides.h"

using namespace iso;

namespace {
std::string calibError(const std::string& text) {
  auto c = driver::parseCalibration(text, "m.csv");
  if (c) return "";
  return c.error().where + ": " + c.error().message;
}

/// A model of residuals f(point) - y, evaluated point by point.
driver::FitModel pointModel(std::function<std::vector<double>(const std::vector<double>&)> f) {
  return [f](const std::vector<std::vector<double>>& points) {
    std::vector<std::optional<std::vector<double>>> out;
    for (const auto& p : points)
      out.emplace_back(f(p));
    return out;
  };
}
} // namespace

TEST_CASE("calibrate: the file's rows, comments, quotes and paths beside the file") {
  auto c = driver::parseCalibration("# measured on 3 June\n\nprogram,cycle_time_s\r\n"
                                    "a.mpf,12.5\r\n"
                                    "  \"sub/b, c.mpf\" , 3\n"
                                    "   # again\n"
                                    "a.mpf,12.7\n",
                                    "dir/m.csv");
  REQUIRE(c);
  REQUIRE(c->rows.size() == 3);
  CHECK(c->rows[0].program == "dir/a.mpf");
  CHECK(c->rows[0].cycleTimeS == 12.5);
  CHECK(c->rows[0].where == "dir/m.csv:4:1");
  CHECK(c->rows[1].program == "dir/sub/b, c.mpf");
  CHECK(c->rows[1].where == "dir/m.csv:5:3");
  CHECK(c->programs == std::vector<std::string>{"dir/a.mpf", "dir/sub/b, c.mpf"});
  CHECK(c->programOf == std::vector<size_t>{0, 1, 0});
}

TEST_CASE("calibrate: a byte order mark before the header is skipped") {
  auto c = driver::parseCalibration("\xEF\xBB\xBFprogram,cycle_time_s\na.mpf,1.5\n", "m.csv");
  REQUIRE(c);
  CHECK(c->rows.size() == 1);
}

TEST_CASE("calibrate: a bad file is an error at its line and column") {
  CHECK(calibError("") == "m.csv: the file is empty: expected the header 'program,cycle_time_s'");
  CHECK(calibError("program,time\n") == "m.csv:1:1: the first line must be the header 'program,cycle_time_s'");
  CHECK(calibError("program,cycle_time_s\n") ==
        "m.csv: no measurement after the header: expected rows PROGRAM,SECONDS");
  CHECK(calibError("program,cycle_time_s\na.mpf,1.5s\n") ==
        "m.csv:2:7: the cycle time '1.5s' is not a number (seconds)");
  CHECK(calibError("program,cycle_time_s\na.mpf,-2\n") == "m.csv:2:7: the cycle time must be above 0 s, not -2");
  CHECK(calibError("program,cycle_time_s\na.mpf,0\n") == "m.csv:2:7: the cycle time must be above 0 s, not 0");
  CHECK(calibError("program,cycle_time_s\na.mpf,nan\n") == "m.csv:2:7: the cycle time 'nan' is not a number (seconds)");
  CHECK(calibError("program,cycle_time_s\na.mpf,1,2\n") ==
        "m.csv:2:9: expected 2 fields (program,cycle_time_s), found 3");
  CHECK(calibError("program,cycle_time_s\na.mpf\n") == "m.csv:2:1: expected 2 fields (program,cycle_time_s), found 1");
  CHECK(calibError("program,cycle_time_s\n,1\n") == "m.csv:2:1: the program is empty");
  CHECK(calibError("program,cycle_time_s\n\"a.mpf,1\n") ==
        "m.csv:2:1: a quoted field must end with '\"' before the next ',' or the end of the line");
  CHECK(calibError("program,cycle_time_s\n\"a\"b.mpf,1\n") ==
        "m.csv:2:4: a quoted field must end with '\"' before the next ',' or the end of the line");
}

TEST_CASE("calibrate: the solver fits an exponential decay on log-scale parameters") {
  // y = a exp(-t / tau) at t = 0..5, a = 3, tau = 2; from a = 1, tau = 10
  const std::vector<double> ts{0, 1, 2, 3, 4, 5};
  auto model = pointModel([&](const std::vector<double>& p) {
    std::vector<double> r;
    for (double t : ts)
      r.push_back(p[0] * std::exp(-t / p[1]) - 3 * std::exp(-t / 2));
    return r;
  });
  const auto fit = driver::fitLeastSquares({{1, true, 0, {}}, {10, true, 0, {}}}, model);
  REQUIRE(fit.values.size() == 2);
  CHECK(fit.converged);
  CHECK(fit.determined == std::vector<bool>{true, true});
  CHECK(fit.values[0] == doctest::Approx(3).epsilon(1e-9));
  CHECK(fit.values[1] == doctest::Approx(2).epsilon(1e-9));
  CHECK(fit.iterations < driver::kMaxFitIterations);
}

TEST_CASE("calibrate: a linear model is solved, and a bound holds where the optimum lies beyond it") {
  // r = (b - 0.5, c + 1): b goes to 0.5; c's optimum -1 is below its bound 0, so c stays at 0
  auto model = pointModel([](const std::vector<double>& p) { return std::vector<double>{p[0] - 0.5, p[1] + 1}; });
  const auto fit = driver::fitLeastSquares({{0, false, 0, {}}, {0.25, false, 0, {}}}, model);
  CHECK(fit.converged);
  CHECK(fit.values[0] == doctest::Approx(0.5).epsilon(1e-12));
  CHECK(fit.values[1] == 0);
  // an upper bound: b <= 0.3
  const auto capped = driver::fitLeastSquares({{0, false, 0, 0.3}, {0, false, 0, {}}}, model);
  CHECK(capped.values[0] == doctest::Approx(0.3).epsilon(1e-12));
}

TEST_CASE("calibrate: a parameter no residual depends on, and two that act only together, stay at their start") {
  // r = (x0 + x1 - 2, 2 x0 + 2 x1 - 4, x3 - 7): x2 moves nothing, x0 and x1 only as x0 + x1
  auto model = pointModel([](const std::vector<double>& p) {
    return std::vector<double>{p[0] + p[1] - 2, 2 * p[0] + 2 * p[1] - 4, p[3] - 7};
  });
  const auto fit =
      driver::fitLeastSquares({{0, false, 0, {}}, {0, false, 0, {}}, {5, true, 0, {}}, {1, false, 0, {}}}, model);
  CHECK(fit.determined == std::vector<bool>{false, false, false, true});
  CHECK(fit.alone == std::vector<bool>{false, false, true, false});
  CHECK(fit.values[0] == 0);
  CHECK(fit.values[1] == 0);
  CHECK(fit.values[2] == 5);
  CHECK(fit.values[3] == doctest::Approx(7).epsilon(1e-12));
}

TEST_CASE("calibrate: a model that fails at the start is a failed fit") {
  driver::FitModel model = [](const std::vector<std::vector<double>>& points) {
    return std::vector<std::optional<std::vector<double>>>(points.size());
  };
  CHECK(driver::fitLeastSquares({{1, true, 0, {}}}, model).failed);
}

TEST_CASE("calibrate: the number keys a calibration fits, with their values and bounds") {
  const machine::Machine m = machine::builtinMachine();
  auto accel = driver::machineNumberKey(m, "axes.x.max_accel"); // an axis in any case, as --set names it
  REQUIRE(accel);
  CHECK(accel->value == 2000);
  CHECK(accel->positive);
  auto block = driver::machineNumberKey(m, "block_time_s");
  REQUIRE(block);
  CHECK(block->value == 0);
  CHECK(!block->positive);
  CHECK(block->lower == 0);
  auto changed = driver::overriddenMachine(m, {"default_m_duration_s=0.3", "m_sequences.8.duration_s=2"});
  REQUIRE(changed);
  auto m23 = driver::machineNumberKey(*changed, "m_sequences.23.duration_s"); // no entry: the default
  REQUIRE(m23);
  CHECK(m23->value == 0.3);
  CHECK(driver::machineNumberKey(*changed, "m_sequences.8.duration_s")->value == 2);
  CHECK(driver::machineNumberKey(m, "aux_duration_s")->value == 0); // not printed for a sidac machine: its default
  CHECK(driver::machineNumberKey(m, "axes.Q.max_accel").error().message == "no axis named 'Q' in axes");
  for (const char* bad : {"name", "lookahead_blocks", "axes.X.limit_plus", "axes.X", "m_sequences.23.set_inputs",
                          "zones.0.min", "block_time_s.x"})
    CHECK_MESSAGE(!driver::machineNumberKey(m, bad), bad);
}
