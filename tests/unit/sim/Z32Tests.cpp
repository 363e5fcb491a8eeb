//! @file Z32Tests.cpp
//! @brief Dialect z32 in isosim (SPEC §4.6, seeds 001 and 004): the order inside a line,
//!        spindle/coolant/tool state and its events, special M, MA/MB/MC, M1, nesting, the
//!        summary figures. Times are hand-computed from the machine below (1e-9 relative).
#include <string>
#include <vector>

#include <doctest/doctest.h>
#include <fmt/format.h>

#include "SimTestUtil.h"
#include "lang/MFunctions.h"
#include "sim/Z32State.h"

using namespace iso;
using sim::EventKind;
using test::exact;
using test::machineFromJson;
using test::simFiles;
using test::simText;

namespace {

/// X: 100 mm/s, 1000 mm/s² (a move of d >= 10 mm takes d/100 + 0.1 s). M3 lasts 0.5 s, M6
/// 0.3 s, M23 0.25 s, every other M default_m_duration_s = 0.1 s; each MA/MB/MC 0.1 s;
/// M0 waits 2 s.
std::string machineJson(const std::string& extra = "") {
  return R"({"name": "z32test", "dialect": "z32",
    "axes": [{"name": "X", "max_velocity": 100, "max_accel": 1000, "limit_minus": -1000, "limit_plus": 1000}],
    "m_sequences": {"3": {"duration_s": 0.5}, "6": {"duration_s": 0.3}, "23": {"duration_s": 0.25}},
    "default_m_duration_s": 0.1, "aux_duration_s": 0.1, "m0_wait_s": 2)" +
         extra + "}";
}

machine::Machine z32Machine(const std::string& extra = "") { return machineFromJson(machineJson(extra)); }

/// The M numbers of the m_start events, in order.
std::vector<uint64_t> mOrder(const test::SimRun& r) {
  std::vector<uint64_t> out;
  for (const auto& e : r.events(EventKind::MStart))
    out.push_back(e.m);
  return out;
}

double mStart(const test::SimRun& r, uint64_t m) {
  for (const auto& e : r.events(EventKind::MStart))
    if (e.m == m) return e.t;
  return -1;
}

const std::vector<std::pair<std::string, std::string>> kPallet = {{"pallet.spf", "PROC PALLET SAVE\nG04 F2\nM17\n"},
                                                                  {"cambio.spf", "PROC CAMBIO SAVE\nG04 F1\nM17\n"}};

std::unique_ptr<test::SimRun> simSpecial(const std::string& main, const std::string& extra = "") {
  auto files = kPallet;
  files.push_back({"main.mpf", main});
  return simFiles(files, z32Machine(R"(, "special_m": {"40": "PALLET", "6": "CAMBIO"})" + extra));
}

} // namespace

TEST_CASE("z32: seed 004 'M3 M7 M8 M19 M2' runs M3, M7, M8, M19, M2 whatever the written order") {
  for (const char* line : {"M3 M7 M8 M19 M2", "M2 M19 M7 M8 M3"}) {
    CAPTURE(line);
    auto r = simText(std::string("S1000\n") + line + "\n", z32Machine());
    REQUIRE(r->diagnostics.empty());
    CHECK(r->status() == sim::Status::Ok);
    CHECK(mOrder(*r) == std::vector<uint64_t>{3, 7, 8, 19, 2});
    // M3 0.5 s, then M7 M8 M19 M2 0.1 s each; M2 ends the program like M30
    CHECK(r->cycle() == exact(0.9));
    CHECK(mStart(*r, 19) == exact(0.7));
    // the spindle turned from M3 (t = 0) to M19 (t = 0.7)
    CHECK(r->summary().spindleOnS == exact(0.7));
    auto sp = r->events(EventKind::Spindle);
    REQUIRE(sp.size() == 2);
    CHECK(sp[0].state == "cw");
    CHECK(sp[0].rpm == 1000);
    CHECK(sp[0].t == 0);
    CHECK(sp[1].state == "orient");
    CHECK(sp[1].rpm == 0);
    CHECK(sp[1].t == exact(0.7));
    auto co = r->events(EventKind::Coolant);
    REQUIRE(co.size() == 3);
    CHECK((co[0].c1 && !co[0].c2));
    CHECK((co[1].c1 && co[1].c2));
    CHECK((!co[2].c1 && !co[2].c2));      // M19 switches the coolants off
    CHECK(r->summary().warnings.empty()); // managed and final M are not "without a model"
  }
}

TEST_CASE("z32: seed 004 'G00 X100 M5' moves, then stops the spindle (sidac: the M first)") {
  auto r = simText("S200 M3\nG00 X100 M5\nM30\n", z32Machine());
  REQUIRE(r->diagnostics.empty());
  // M3 0.5 s; X 100 mm: 100/100 + 100/1000 = 1.1 s; M5 0.1 s
  CHECK(r->moveStart('X') == exact(0.5));
  CHECK(mStart(*r, 5) == exact(1.6));
  CHECK(r->cycle() == exact(1.7));
  CHECK(r->summary().spindleOnS == exact(1.6)); // from M3 (t = 0) to M5

  machine::Machine sidac = z32Machine();
  sidac.dialect = machine::Dialect::Sidac;
  auto s = simText("G00 X100 M23\nM30\n", sidac);
  REQUIRE(s->diagnostics.empty());
  CHECK(s->moveStart('X') == exact(0.25)); // sidac: M23 (0.25 s) first
  CHECK(!s->summary().z32);
}

TEST_CASE("z32: the line order puts M6 after motion and dwell, M19 before M5, final M last") {
  // written backwards: M30 M6 M5 M19 G04 F1 ... X is on its own line (G04 cannot share one)
  auto r = simText("T4 S100\nM3\nM30 M6 M5 M19 MA5 M23\n", z32Machine());
  REQUIRE(r->diagnostics.empty());
  CHECK(mOrder(*r) == std::vector<uint64_t>{3, 23, 19, 5, 6});
  // M3 0.5; MA (0.1) and M23 (0.25) in written order: MA at 0.5, M23 at 0.6; M19 at 0.85,
  // M5 at 0.95, M6 at 1.05 (0.3 s)
  auto aux = r->events(EventKind::Aux);
  REQUIRE(aux.size() == 1);
  CHECK(aux[0].t == exact(0.5));
  CHECK(mStart(*r, 23) == exact(0.6));
  CHECK(mStart(*r, 6) == exact(1.05));
  CHECK(r->cycle() == exact(1.35));
  CHECK(r->summary().toolChanges == 1);
  REQUIRE(r->summary().tool.has_value());
  CHECK(*r->summary().tool == 4);
}

TEST_CASE("z32: MA MB MC are sent as seed 004 says, each taking aux_duration_s") {
  struct Case {
    const char* word;
    double programmed;
    int sent;
  } cases[] = {{"MA", -100, 8100}, {"MA", 8100, 8100},  {"MA", -1, 8001},    {"MB", -1040, 9040}, {"MA", -0.0, 0},
               {"MA", -0.4, 0},    {"MA", 12345, 9999}, {"MA", -5000, 9999}, {"MC", 99.99, 99},   {"MB", 9999.9, 9999}};
  std::string src;
  for (const Case& c : cases)
    src += fmt::format("{}{}\n", c.word, c.programmed);
  src += "R1=-3.7\nMC=R1*10\nM30\n";
  auto r = simText(src, z32Machine());
  REQUIRE(r->diagnostics.empty());
  auto aux = r->events(EventKind::Aux);
  REQUIRE(aux.size() == std::size(cases) + 1);
  for (size_t i = 0; i < std::size(cases); ++i) {
    CAPTURE(i);
    CHECK(aux[i].state == cases[i].word);
    CHECK(aux[i].sent == cases[i].sent);
    CHECK(aux[i].t == exact(0.1 * static_cast<double>(i)));
    CHECK(lang::auxSent(cases[i].programmed) == cases[i].sent);
  }
  CHECK(aux.back().programmed == exact(-37));
  CHECK(aux.back().sent == 8037);
  CHECK(r->cycle() == exact(0.1 * static_cast<double>(aux.size())));
}

TEST_CASE("z32: MA values are evaluated in written order, sent at step 4") {
  // R1=2 is visible to MA=R1*3 on its right; MB=R1 on its left sees the old R1
  auto r = simText("R1=5\nMB=R1 R1=2 MA=R1*3 G0 X10\nM30\n", z32Machine());
  REQUIRE(r->diagnostics.empty());
  auto aux = r->events(EventKind::Aux);
  REQUIRE(aux.size() == 2);
  CHECK(aux[0].state == "MB");
  CHECK(aux[0].programmed == 5);
  CHECK(aux[1].state == "MA");
  CHECK(aux[1].programmed == 6);
  CHECK(r->moveStart('X') == exact(0.2)); // the move waits for both (step 5)
  CHECK(r->pos('X') == 10);
}

TEST_CASE("z32: a special M abandons the rest of its line and resumes at the next line") {
  auto r = simSpecial("G0 X10\nM40 X50 M8 MA1\nG0 X20\nM30\n");
  REQUIRE(r->diagnostics.empty());
  // X 10 mm: 0.2 s; PALLET dwells 2 s; X 10 -> 20: 0.2 s
  CHECK(r->count(EventKind::Coolant) == 0);
  CHECK(r->count(EventKind::Aux) == 0);
  CHECK(r->moveStart('X', 1) == exact(2.2));
  CHECK(r->cycle() == exact(2.4));
  CHECK(r->pos('X') == 20);
  CHECK(r->count(EventKind::MStart) == 0); // a special M is a call, not a PLC sequence
}

TEST_CASE("z32: a special M6 runs after the motion and mounts the tool when its subprogram returns") {
  auto r = simSpecial("S300 M3\nT7 X20 M6 M30\nM30\n");
  REQUIRE(r->diagnostics.empty());
  // M3 0.5; X 20 mm: 0.3 s; CAMBIO dwells 1 s; the M30 of line 2 never runs (line 3 ends)
  auto tool = r->events(EventKind::Tool);
  REQUIRE(tool.size() == 1);
  CHECK(tool[0].t == exact(1.8));
  CHECK(tool[0].tool == 7);
  CHECK(r->lineTime(3) == exact(1.8));
  CHECK(r->cycle() == exact(1.8));
  CHECK(r->summary().spindleOnS == exact(1.8)); // stopped by the tool change, at the return
  CHECK(r->summary().toolChanges == 1);
}

TEST_CASE("z32: a plain M6 with T, and M6 or M3 without T or S, warn and report") {
  auto r = simText("T3\nS500 M3\nM6\nM30\n", z32Machine());
  REQUIRE(r->diagnostics.empty());
  CHECK(r->cycle() == exact(0.8));
  CHECK(r->summary().spindleOnS == exact(0.5));
  CHECK(*r->summary().tool == 3);

  auto u = simText("M3\nM6\nM30\n", z32Machine());
  REQUIRE(u->diagnostics.empty());
  CHECK(u->summary().spindleOnS == 0); // 0 rpm does not turn
  CHECK(!u->summary().tool.has_value());
  CHECK(u->summary().toolChanges == 0);
  REQUIRE(u->summary().warnings.size() == 2);
  CHECK(u->summary().warnings[0].find("no S programmed") != std::string::npos);
  CHECK(u->summary().warnings[1].find("M6 with no T programmed") != std::string::npos);
}

TEST_CASE("z32: S while the spindle turns changes its speed at once") {
  auto r = simText("S100 M3\nS250\nM5\nM30\n", z32Machine());
  REQUIRE(r->diagnostics.empty());
  auto sp = r->events(EventKind::Spindle);
  REQUIRE(sp.size() == 3);
  CHECK(sp[1].rpm == 250);
  CHECK(sp[1].t == exact(0.5));
  CHECK(sp[2].state == "stop");
}

TEST_CASE("z32: M1 stops only with optional_stop - M0 stops the spindle and waits m0_wait_s") {
  auto off = simText("S100 M3\nM1\nM30\n", z32Machine());
  REQUIRE(off->diagnostics.empty());
  CHECK(off->cycle() == exact(0.6));
  CHECK(off->summary().spindleOnS == exact(0.6));
  CHECK(off->count(EventKind::Stop) == 0);

  auto on = simText("S100 M3\nM1\nM30\n", z32Machine(R"(, "optional_stop": true)"));
  REQUIRE(on->diagnostics.empty());
  CHECK(on->cycle() == exact(2.6)); // M1 sequence 0.1 s, then the 2 s stop
  CHECK(on->summary().spindleOnS == exact(0.5));
  CHECK(on->count(EventKind::Stop) == 1);

  auto m0 = simText("S100 M3 M8\nM0\nM30\n", z32Machine());
  REQUIRE(m0->diagnostics.empty());
  CHECK(m0->cycle() == exact(2.7)); // M3 0.5, M8 0.1, M0 0.1 + 2 s
  CHECK(m0->summary().spindleOnS == exact(0.6));
  auto co = m0->events(EventKind::Coolant);
  REQUIRE(co.size() == 2);
  CHECK(!co[1].c2);
}

TEST_CASE("z32: nesting over 10 levels, special M counted, is 'too many subroutines'") {
  // PALLET calls itself through M40: the 11th nested call fails
  auto files = std::vector<std::pair<std::string, std::string>>{
      {"main.mpf", "M40\nM30\n"}, {"pallet.spf", "PROC PALLET SAVE\nR1=R1+1\nM40\nM17\n"}};
  auto r = simFiles(files, z32Machine(R"(, "special_m": {"40": "PALLET"})"));
  REQUIRE(r->diagnostics.empty());
  CHECK(r->status() == sim::Status::Error);
  CHECK(r->message().find("too many subroutines") != std::string::npos);
  CHECK(r->message().find("deeper than 10 levels") != std::string::npos);
}

TEST_CASE("z32: isosim warns when its machine maps an M that the image runs as a sequence") {
  machine::Machine plain = z32Machine();
  auto set = test::loadText("M40\nM30\n", "t.mpf", plain, plain.dialect);
  image::Image img = test::compileSet(*set, plain, nullptr);
  REQUIRE(img.z32());
  machine::Machine special = z32Machine(R"(, "special_m": {"40": "PALLET"})");
  auto res = test::runImage(img, special, {}, nullptr);
  bool warned = false;
  for (const auto& w : res.summary.warnings)
    warned = warned || w.find("M40 is a special M of machine 'z32test' (it calls PALLET)") == 0;
  CHECK(warned);
}

TEST_CASE("z32: seed 001 continuation 'N12G0X0$ AB12 / Y0Z0$ / M6' is one line: M6 after the motion") {
  machine::Machine m = z32Machine();
  m.axes.push_back(m.axes[0]);
  m.axes.back().letter = 'Y';
  m.axes.push_back(m.axes[0]);
  m.axes.back().letter = 'Z';
  auto r = simText("T1\nG0 X5 Y5 Z5\nN12G0X0$ AB12\nY0Z0$\nM6\nN13 M30\n", m);
  REQUIRE(r->diagnostics.empty());
  // line 2: each axis 5 mm, 2*sqrt(5/1000) s; line 3: back to 0 the same; then M6 (0.3 s)
  const double t5 = 2 * std::sqrt(5.0 / 1000);
  CHECK(mStart(*r, 6) == exact(2 * t5));
  CHECK(r->lineTime(6) == exact(2 * t5 + 0.3));
  CHECK(r->summary().blocks == 4);
}

TEST_CASE("z32: the machine-state room alone (Z32State)") {
  sim::Z32State z;
  CHECK(z.apply(lang::MRole::SpindleCw, 0, false).speedUnset);
  CHECK(z.rpm() == 0);
  z.setSpeed(100, 1);
  CHECK(z.rpm() == 100);
  CHECK(z.apply(lang::MRole::SpindleStop, 3, false).spindle);
  CHECK(z.spindleOnS() == 2);
  CHECK(!z.apply(lang::MRole::OptionalStop, 4, false).spindle);
  CHECK(z.changeTool(5).toolUnset);
  z.setProgrammedTool(9);
  CHECK(z.changeTool(6).tool);
  CHECK(z.tool() == 9);
}

TEST_CASE("lang: the M function table agrees with SPEC §4.5 and §4.6") {
  using lang::Dialect;
  using lang::MRole;
  for (int n = 0; n <= 100; ++n) {
    CAPTURE(n);
    const MRole s = lang::mRole(n, Dialect::Sidac);
    const MRole z = lang::mRole(n, Dialect::Z32);
    // sidac knows only M0 M17 M30
    CHECK((s != MRole::Plain) == (n == 0 || n == 17 || n == 30));
    // z32: final M are M0 M1 M2 M17 M30, managed M3 M4 M5 M6 M7 M8 M9 M19, nothing is both
    CHECK(lang::isFinal(z) == (n == 0 || n == 1 || n == 2 || n == 17 || n == 30));
    CHECK(lang::isManaged(z) == ((n >= 3 && n <= 9) || n == 19));
    CHECK(!(lang::isFinal(z) && lang::isManaged(z)));
    // only M6 of the control's M may be special
    CHECK(lang::mayBeSpecial(n) == (z == MRole::Plain || n == 6));
    const auto step = lang::z32Step(n, lang::mayBeSpecial(n));
    if (lang::isFinal(z)) CHECK(step == lang::Z32Step::Final);
  }
  CHECK(lang::z32Step(6, true) == lang::Z32Step::Tool);
  CHECK(lang::z32Step(40, true) == lang::Z32Step::Special);
  CHECK(lang::z32Step(40, false) == lang::Z32Step::Other);
  CHECK(lang::maxNesting(Dialect::Z32) == 10);
  CHECK(lang::maxNesting(Dialect::Sidac) == 30);
}

TEST_CASE("z32: seed 001 order with a dwell: other M, then G04, then M19, M5, then the final M") {
  // written: M5 M19 G04 F1 M8 M2 -> M8 (step 4), dwell (6), M19 (7), M5 (8), M2 (10)
  auto r = simText("S100 M3\nM5 M19 G04 F1 M8 M2\n", z32Machine());
  REQUIRE(r->diagnostics.empty());
  CHECK(mOrder(*r) == std::vector<uint64_t>{3, 8, 19, 5, 2});
  auto dw = r->events(EventKind::Dwell);
  REQUIRE(dw.size() == 1);
  CHECK(dw[0].t == exact(0.6)); // after M3 (0.5) and M8 (0.1)
  CHECK(mStart(*r, 19) == exact(1.6));
  CHECK(mStart(*r, 5) == exact(1.7));
  CHECK(r->cycle() == exact(1.9));
  // a special M at step 3 abandons the dwell too
  auto s = simSpecial("G04 F5 M40\nM30\n");
  REQUIRE(s->diagnostics.empty());
  CHECK(s->count(EventKind::Dwell) == 1); // PALLET's own G04 F2 only
  CHECK(s->cycle() == exact(2));
}
