//! @file DebugHookTests.cpp
//! @brief The debugger's hook (sim/Debug.h): called before each statement with its thread,
//!        line and depth, at the times it asks for and at a fault; it never changes the run
//!        (the same summary and events with and without it); it may end the run.
#include <doctest/doctest.h>

#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "SimTestUtil.h"
#include "SimToolRun.h"
#include "TestUtil.h"
#include "sim/Debug.h"

using namespace iso;

namespace {
struct Seen {
  uint32_t thread = 0;
  std::string file;
  uint32_t line = 0;
  size_t depth = 0;
  double t = 0;
};

/// Records every statement; asks for the times in `times`; ends the run at statement `endAt`.
class RecordingHook : public sim::DebugHook {
public:
  bool statement(const sim::RunView& v, uint32_t thread, uint32_t lineEntry, size_t depth) override {
    const sim::DebugFrame w = v.where(lineEntry);
    seen.push_back({thread, w.file, w.line, depth, v.time()});
    if (onStatement) onStatement(v, thread);
    return seen.size() != endAt;
  }
  double nextTimeStop() const override {
    return next < times.size() ? times[next] : std::numeric_limits<double>::infinity();
  }
  bool timeReached(const sim::RunView& v) override {
    ++next;
    reached.push_back(v.time());
    if (onTime) onTime(v);
    return true;
  }
  void fault(const sim::RunView& v, sim::Status st, const std::string& message, uint32_t thread) override {
    faults.push_back({st, message, thread, v.stack(thread ? thread : 1)});
  }
  struct FaultSeen {
    sim::Status status;
    std::string message;
    uint32_t thread;
    std::vector<sim::DebugFrame> stack;
  };
  std::vector<Seen> seen;
  std::vector<double> times;
  size_t next = 0;
  std::vector<double> reached;
  std::vector<FaultSeen> faults;
  size_t endAt = 0;
  std::function<void(const sim::RunView&, uint32_t)> onStatement;
  std::function<void(const sim::RunView&)> onTime;
};

void requireSameRun(const test::SimRun& a, const test::SimRun& b) {
  CHECK(a.summary().status == b.summary().status);
  CHECK(a.cycle() == b.cycle()); // exactly: the hook does not change the run
  CHECK(a.summary().blocks == b.summary().blocks);
  CHECK(a.message() == b.message());
  REQUIRE(a.rec.events.size() == b.rec.events.size());
  for (size_t i = 0; i < a.rec.events.size(); ++i) {
    CHECK(a.rec.events[i].t == b.rec.events[i].t);
    CHECK(a.rec.events[i].kind == b.rec.events[i].kind);
  }
  CHECK(a.rec.samples == b.rec.samples);
}

const std::vector<std::pair<std::string, std::string>> kDrilling = {
    {"main.mpf", "R1 = 0\n"
                 "G90 G60 F=100\n"
                 "WHEN $aa_iw[X] > 20 DO $aa_out[1] = 1\n"
                 "G01 X50\n"
                 "GIRO:\n"
                 "Foro\n"
                 "R1 = R1 + 1\n"
                 "IF R1 < 2 GOTOB GIRO\n"
                 "G64\n"
                 "G01 X60\n"
                 "G01 X70 Y10\n"
                 "M5\n"
                 "M30\n"},
    {"foro.spf", "PROC Foro SAVE\n"
                 "G01 Z-10 F=20\n"
                 "G01 Z0\n"
                 "M17\n"},
};
} // namespace

TEST_CASE("debug hook: the run with the hook is the run without it, every statement seen once") {
  auto plain = test::simFiles(kDrilling);
  REQUIRE(plain->diagnostics.empty());
  RecordingHook hook;
  sim::SimOptions o;
  o.debug = &hook;
  auto debugged = test::simFiles(kDrilling, test::builtin(), o);
  requireSameRun(*plain, *debugged);
  // the lines in order: the subprogram twice, at depth 1; the G64 lines once each
  std::vector<std::string> lines;
  for (const Seen& s : hook.seen)
    if (s.thread == 1) lines.push_back(s.file + ":" + std::to_string(s.line) + "@" + std::to_string(s.depth));
  const std::vector<std::string> want = {
      "main.mpf:1@0",  "main.mpf:2@0",  "main.mpf:3@0", "main.mpf:4@0", "main.mpf:6@0", "foro.spf:2@1",
      "foro.spf:3@1",  "foro.spf:4@1",  "main.mpf:7@0", "main.mpf:8@0", "main.mpf:6@0", "foro.spf:2@1",
      "foro.spf:3@1",  "foro.spf:4@1",  "main.mpf:7@0", "main.mpf:8@0", "main.mpf:9@0", "main.mpf:10@0",
      "main.mpf:11@0", "main.mpf:12@0", "main.mpf:13@0"};
  CHECK(lines == want);
  // the WHEN body ran as thread 2, once
  size_t body = 0;
  for (const Seen& s : hook.seen)
    if (s.thread == 2) ++body;
  CHECK(body == 1);
  // times never go back
  for (size_t i = 1; i < hook.seen.size(); ++i)
    CHECK(hook.seen[i].t >= hook.seen[i - 1].t);
}

TEST_CASE("debug hook: the view at a statement shows the R parameters written, the stack and the axes") {
  RecordingHook hook;
  bool checked = false;
  hook.onStatement = [&](const sim::RunView& v, uint32_t thread) {
    const std::vector<sim::DebugFrame> st = v.stack(thread);
    if (checked || st.empty() || st.front().file != "foro.spf" || st.front().line != 3) return;
    checked = true;
    REQUIRE(st.size() == 2);
    CHECK(st[0].proc == "Foro");
    CHECK(st[0].kind == sim::DebugFrameKind::Call);
    CHECK(st[1].file == "main.mpf");
    CHECK(st[1].line == 6); // the call line
    CHECK(st[1].kind == sim::DebugFrameKind::Main);
    const auto r = v.rParameters();
    REQUIRE(r.size() == 1);
    CHECK(r[0].first == 1);
    CHECK(r[0].second == 0);
    CHECK(v.r(1) == 0.0);
    CHECK_FALSE(v.r(0).has_value());
    CHECK_FALSE(v.r(2881).has_value());
    CHECK_FALSE(v.r(1.5).has_value());
    CHECK(v.axisVariable(lang::SysVar::AaIw, 'X') == 50.0);
    CHECK(v.axisVariable(lang::SysVar::AaIw, 'Z') == -10.0);
    CHECK_FALSE(v.axisVariable(lang::SysVar::AaIw, 'Q').has_value());
    CHECK(v.ioVariable(lang::SysVar::AaOut, 1) == 1.0); // the WHEN fired at X 20
    CHECK_FALSE(v.ioVariable(lang::SysVar::AaOut, 100000).has_value());
    const sim::DebugModal m = v.modal(thread);
    CHECK(m.motion == 1);
    CHECK(m.feed == 20);
    bool sawOut = false;
    for (const sim::DebugValue& io : v.io())
      sawOut = sawOut || io.name == "$aa_out[1]";
    CHECK(sawOut);
  };
  sim::SimOptions o;
  o.debug = &hook;
  auto run = test::simFiles(kDrilling, test::builtin(), o);
  REQUIRE(run->diagnostics.empty());
  CHECK(checked);
}

TEST_CASE("debug hook: a time stop sees the axes where the closed form puts them, and changes nothing") {
  // X 100 mm at F=50 mm/s, max_accel 2000: accelerating for 0.025 s (0.625 mm), then cruising
  const std::string text = "G90 G60\nG01 X100 F=50\nM30\n";
  auto plain = test::simText(text);
  REQUIRE(plain->diagnostics.empty());
  const double t0 = plain->moveStart('X');
  RecordingHook hook;
  hook.times = {t0 + 0.75, t0 + 1.5};
  std::vector<double> xs, vs;
  hook.onTime = [&](const sim::RunView& v) {
    for (const sim::DebugAxis& a : v.axes())
      if (a.letter == 'X') {
        xs.push_back(a.position);
        vs.push_back(a.velocity);
        CHECK(a.moving);
        CHECK(a.target == 100);
      }
  };
  sim::SimOptions o;
  o.debug = &hook;
  auto debugged = test::simText(text, test::builtin(), o);
  requireSameRun(*plain, *debugged);
  REQUIRE(hook.reached.size() == 2);
  CHECK(hook.reached[0] == t0 + 0.75);
  REQUIRE(xs.size() == 2);
  CHECK(std::abs(xs[0] - (0.625 + 50 * (0.75 - 0.025))) <= 1e-9 * 100);
  CHECK(std::abs(xs[1] - (0.625 + 50 * (1.5 - 0.025))) <= 1e-9 * 100);
  CHECK(std::abs(vs[0] - 50) <= 1e-9 * 50);
}

TEST_CASE("debug hook: a fault is reported with the state where it happens") {
  RecordingHook hook;
  sim::SimOptions o;
  o.debug = &hook;
  auto run = test::simText("G90 G60\nG00 X=100\nG00 X=5000\nM30\n", test::builtin(), o);
  REQUIRE(run->status() == sim::Status::Emergency);
  REQUIRE(hook.faults.size() == 1);
  CHECK(hook.faults[0].status == sim::Status::Emergency);
  CHECK(hook.faults[0].message == run->message());
  CHECK(hook.faults[0].thread == 1);
  REQUIRE(!hook.faults[0].stack.empty());
  CHECK(hook.faults[0].stack[0].line == 3);
}

TEST_CASE("debug hook: the hook ends the run, and the summary says so") {
  RecordingHook hook;
  hook.endAt = 2;
  sim::SimOptions o;
  o.debug = &hook;
  auto run = test::simText("R1 = 1\nR2 = 2\nR3 = 3\nM30\n", test::builtin(), o);
  CHECK(run->status() == sim::Status::Error);
  CHECK(test::contains(run->message(), std::string(sim::kDebuggerEndedRun)));
  CHECK(test::contains(run->message(), "t.mpf:2"));
  CHECK(hook.faults.empty()); // not a fault of the program
  CHECK(hook.seen.size() == 2);
}
