//! @file OverrideTests.cpp
//! @brief isosim --set KEY=VALUE and --m0-wait: what-if runs on a machine changed for one run,
//!        against hand-computed cycle times; the summary lists the changes; bad keys and values
//!        are usage errors naming the assignment.
#include <doctest/doctest.h>

#include <cmath>
#include <string>

#include "SimToolRun.h"
#include "TestUtil.h"

using namespace iso;
using test::contains;

namespace {
/// The cycle time a --summary run prints ("cycle_time_s: T").
double cycleOf(const test::ToolRun& r) {
  const size_t at = r.out.find("cycle_time_s: ");
  REQUIRE(at != std::string::npos);
  return std::stod(r.out.substr(at + 14));
}
driver::SimulateOptions summaryRun(const std::string& program) {
  driver::SimulateOptions o;
  o.program = program;
  o.summary = true;
  return o;
}
} // namespace

TEST_CASE("--set: an axis key by the axis name, with the time of a trapezoid by hand") {
  test::TempDir dir;
  // X 100 mm at F=50 mm/s with max_accel 100 mm/s^2: 100/50 + 50/100 = 2.5 s; M0 waits m0_wait_s
  auto o = summaryRun(dir.write("p.mpf", "G01 X100 F=50\nM0\nM30\n"));
  o.sets = {"axes.X.max_accel=100"};
  auto r = test::runSim(o);
  INFO(r.err);
  REQUIRE(r.rc == 0);
  CHECK(std::abs(cycleOf(r) - 2.5) <= 2.5e-9);
  CHECK(contains(r.out, "override: axes.X.max_accel=100\n"));
  o.sets = {"axes.x.max_accel=100"}; // the axis name in any case
  o.m0Wait = 3;
  r = test::runSim(o);
  CHECK(std::abs(cycleOf(r) - 5.5) <= 5.5e-9);
  CHECK(contains(r.out, "override: m0_wait_s=3\n"));
  // the last assignment of a key wins
  o.m0Wait.reset();
  o.sets = {"axes.X.max_accel=1", "axes.X.max_accel=100"};
  CHECK(std::abs(cycleOf(test::runSim(o)) - 2.5) <= 2.5e-9);
  // without --set the built-in machine's time, and no override line
  r = test::runSim(summaryRun(o.program));
  CHECK_FALSE(contains(r.out, "override:"));
  CHECK(cycleOf(r) < 2.5);
}

TEST_CASE("--set: a new M sequence, and a JSON summary that lists the overrides") {
  test::TempDir dir;
  auto o = summaryRun(dir.write("p.mpf", "M23\nM30\n"));
  o.sets = {"m_sequences.23.duration_s=1.25"};
  o.format = "json";
  auto r = test::runSim(o);
  INFO(r.err);
  REQUIRE(r.rc == 0);
  const auto j = nlohmann::json::parse(r.out);
  CHECK(j["cycle_time_s"] == 1.25);
  CHECK(j["overrides"] == nlohmann::json::array({"m_sequences.23.duration_s=1.25"}));
}

TEST_CASE("--set: keys that name nothing and values the machine file refuses are usage errors") {
  test::TempDir dir;
  auto o = summaryRun(dir.write("p.mpf", "G0 X1\nM30\n"));
  for (const auto& [set, why] :
       std::initializer_list<std::pair<const char*, const char*>>{{"axes.Q.max_accel=1", "no axis named 'Q'"},
                                                                  {"axes.X.max_accel=-5", "/axes/0/max_accel"},
                                                                  {"axes.X.max_accel=fast", "/axes/0/max_accel"},
                                                                  {"no_such_key=1", "unknown key"},
                                                                  {"block_time_s.x=1", "is not an object"},
                                                                  {"=3", "expected KEY=VALUE"},
                                                                  {"axes..max_accel=3", "empty part"}}) {
    o.sets = {set};
    const auto r = test::runSim(o);
    CAPTURE(set);
    CHECK(r.rc == 2);
    CHECK(contains(r.err, why));
    CHECK(r.out.empty());
  }
  o.sets.clear();
  o.m0Wait = -1;
  CHECK(test::runSim(o).rc == 2);
}

TEST_CASE("--feed-override and --rapid-override: hand-computed times and the summary lines") {
  test::TempDir dir;
  // X 100 at F=50 -> 25 mm/s: 100/25 + 25/2000 = 4.0125; back at G00 250 mm/s: 100/250 + 250/2000 = 0.525
  auto o = summaryRun(dir.write("p.mpf", "G01 X100 F=50\nG00 X0\nM30\n"));
  o.feedOverride = "50";
  auto r = test::runSim(o);
  INFO(r.err);
  REQUIRE(r.rc == 0);
  // the rapid unchanged: 100 mm < 500²/2000, 2·sqrt(100/2000)
  CHECK(std::abs(cycleOf(r) - (4.0125 + 2 * std::sqrt(0.05))) <= 1e-6);
  CHECK(contains(r.out, "override: feed_override=50\n"));
  CHECK_FALSE(contains(r.out, "rapid_override"));
  o.rapidOverride = "50%"; // a trailing % is allowed; the summary shows the number
  r = test::runSim(o);
  REQUIRE(r.rc == 0);
  CHECK(std::abs(cycleOf(r) - 4.5375) <= 4.5375e-9);
  CHECK(contains(r.out, "override: feed_override=50\noverride: rapid_override=50\n"));
  o.format = "json";
  o.feedOverride.clear();
  r = test::runSim(o);
  REQUIRE(r.rc == 0);
  const auto j = nlohmann::json::parse(r.out);
  CHECK(j["overrides"] == nlohmann::json::array({"rapid_override=50"}));
  CHECK(std::abs(j["cycle_time_s"].get<double>() - 2.55) <= 2.55e-9); // 2.025 + 0.525
  // 100%: the same run as without the option, and no override line
  o = summaryRun(o.program);
  o.feedOverride = "100";
  o.rapidOverride = "100";
  r = test::runSim(o);
  CHECK_FALSE(contains(r.out, "override:"));
  CHECK(r.out == test::runSim(summaryRun(o.program)).out);
}

TEST_CASE("--optional-stop: M1 waits the M0 wait time when on, nothing when off or by default") {
  test::TempDir dir;
  auto o = summaryRun(dir.write("p.mpf", "G04 F0.5\nM1\nM30\n"));
  o.common.dialect = "z32";
  o.m0Wait = 2;
  auto r = test::runSim(o); // the machine's optional_stop: false
  INFO(r.err);
  REQUIRE(r.rc == 0);
  CHECK(std::abs(cycleOf(r) - 0.5) <= 0.5e-9);
  CHECK_FALSE(contains(r.out, "optional_stop"));
  o.optionalStop = "on";
  r = test::runSim(o);
  REQUIRE(r.rc == 0);
  CHECK(std::abs(cycleOf(r) - 2.5) <= 2.5e-9);
  CHECK(contains(r.out, "override: m0_wait_s=2\noverride: optional_stop=true\n"));
  o.optionalStop = "OFF";
  r = test::runSim(o);
  CHECK(std::abs(cycleOf(r) - 0.5) <= 0.5e-9);
  CHECK(contains(r.out, "override: optional_stop=false\n"));
  // off on a machine whose optional_stop is true
  o.sets = {"optional_stop=true"};
  r = test::runSim(o);
  CHECK(std::abs(cycleOf(r) - 0.5) <= 0.5e-9);
}

TEST_CASE("--feed-override, --rapid-override, --optional-stop: bad values are usage errors") {
  test::TempDir dir;
  const std::string program = dir.write("p.mpf", "G01 X1 F=10\nM30\n");
  const std::string huge = "1" + std::string(400, '0'); // past the range of a double
  for (const char* bad : {"0", "-5", "abc", "1001", "0.5", "50%%", "1e2", ".", "%", "1000.5", huge.c_str()}) {
    auto o = summaryRun(program);
    o.feedOverride = bad;
    const auto r = test::runSim(o);
    CAPTURE(bad);
    CHECK(r.rc == 2);
    CHECK(contains(r.err, "--feed-override"));
    CHECK(contains(r.err, "from 1 to 1000"));
    CHECK(r.out.empty());
  }
  for (const char* bad : {"0", "101", "x", "-1"}) {
    auto o = summaryRun(program);
    o.rapidOverride = bad;
    const auto r = test::runSim(o);
    CAPTURE(bad);
    CHECK(r.rc == 2);
    CHECK(contains(r.err, "--rapid-override"));
    CHECK(contains(r.err, "from 1 to 100"));
  }
  for (const char* bad : {"yes", "1", "true", "o"}) {
    auto o = summaryRun(program);
    o.optionalStop = bad;
    const auto r = test::runSim(o);
    CAPTURE(bad);
    CHECK(r.rc == 2);
    CHECK(contains(r.err, "--optional-stop"));
    CHECK(contains(r.err, "on or off"));
  }
  // the ends of the ranges are accepted
  auto o = summaryRun(program);
  o.feedOverride = "1000";
  o.rapidOverride = "1";
  CHECK(test::runSim(o).rc == 0);
  o.feedOverride = "1";
  o.rapidOverride = "100%";
  CHECK(test::runSim(o).rc == 0);
}
