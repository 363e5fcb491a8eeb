//! @file TimeProfileTests.cpp
//! @brief `isosim --profile` (SimOptions::profile): every instant of the main program goes to one
//!        line and one category; the parts add up to the cycle time; closed-form splits; the
//!        limit that bounded each motion block; subprograms and M numbers.
#include <cmath>

#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include "SimTestUtil.h"
#include "frontend/ProgramSet.h"
#include "sim/TimeProfile.h"

using namespace iso;
using namespace iso::test;
using sim::TimeCat;

namespace {
constexpr double A = 2000; // built-in axes: 500 mm/s, 2000 mm/s²

struct Profiled {
  std::unique_ptr<SimRun> run;
  sim::TimeProfile prof;
};

/// Runs `run(options)` (simText or simFiles) with a profile.
template <class Run> Profiled profiled(Run run) {
  Profiled p;
  sim::SimOptions o;
  o.profile = &p.prof;
  p.run = run(o);
  REQUIRE(p.run->diagnostics.empty());
  return p;
}

Profiled profileText(const std::string& text, const machine::Machine& m = builtin()) {
  return profiled([&](const sim::SimOptions& o) { return simText(text, m, o); });
}

Profiled profileFiles(const std::vector<std::pair<std::string, std::string>>& files,
                      const machine::Machine& m = builtin()) {
  return profiled([&](const sim::SimOptions& o) { return simFiles(files, m, o); });
}

const sim::LineProfile* lineOf(const sim::TimeProfile& p, uint32_t line) {
  for (const auto& l : p.lines)
    if (l.line == line) return &l;
  return nullptr;
}

/// The parts of every line add up to the cycle time, and so do the totals.
void checkSums(const sim::TimeProfile& p, double cycle) {
  sim::ExactSum lines;
  for (const auto& l : p.lines) {
    sim::ExactSum parts;
    for (size_t c = 0; c < sim::kTimeCats; ++c) {
      CHECK(l.time.parts[c].value() >= 0);
      parts.add(l.time.parts[c].value());
    }
    CHECK(parts.value() == l.time.total());
    lines.add(l.time.total());
  }
  CHECK(p.cycleTimeS == cycle);
  CHECK(lines.value() == doctest::Approx(cycle).epsilon(1e-12));
  CHECK(p.total.total() == doctest::Approx(cycle).epsilon(1e-12));
}

} // namespace

TEST_CASE("time profile: motion, dwell, PLC and block time split exactly") {
  const machine::Machine m = machineFromJson(R"({"axes": [
      {"name": "X", "max_velocity": 500, "max_accel": 2000, "limit_minus": -1000, "limit_plus": 3000}],
      "block_time_s": 0.01, "m_sequences": {"3": {"duration_s": 0.25}}})");
  auto p = profileText("G01 X100 F100\nG04 F0.5\nM3\nM30\n", m);
  checkSums(p.prof, p.run->cycle());
  CHECK(p.run->cycle() == exact(0.04 + moveTime(100, 100, A) + 0.5 + 0.25));
  const auto* l1 = lineOf(p.prof, 1);
  REQUIRE(l1);
  CHECK(l1->count == 1);
  CHECK(l1->time.part(TimeCat::Block) == exact(0.01));
  CHECK(l1->time.part(TimeCat::Accel) == exact(0.05));
  CHECK(l1->time.part(TimeCat::Cruise) == exact(0.95));
  CHECK(l1->time.part(TimeCat::Decel) == exact(0.05));
  REQUIRE(l1->bounds.size() == 1);
  CHECK(l1->bounds[0] == "feed");
  CHECK(lineOf(p.prof, 2)->time.part(TimeCat::Dwell) == exact(0.5));
  CHECK(lineOf(p.prof, 3)->time.part(TimeCat::Plc) == exact(0.25));
  CHECK(lineOf(p.prof, 4)->time.total() == exact(0.01));
  REQUIRE(p.prof.ms.size() == 1);
  CHECK(p.prof.ms[0].m == 3);
  CHECK(p.prof.ms[0].count == 1);
  CHECK(p.prof.ms[0].time.part(TimeCat::Plc) == exact(0.25));
  CHECK(p.prof.ms[0].running.value() == exact(0.25));
}

TEST_CASE("time profile: the limit that bounded each motion block") {
  // X only at F=100: the feed; X at F=1000: X's 500 mm/s; 1 mm: too short to reach the feed;
  // 150 mm at 500 mm/s: 0.05 s cruising, 0.5 s ramping (acceleration); F=600 over 749 mm: velocity
  auto p = profileText("G01 X100 F100\nX1100 F1000\nX1101\nG00 X1251\nG01 X2000 F=600\nM30\n");
  CHECK(lineOf(p.prof, 1)->bounds == std::vector<std::string>{"feed"});
  CHECK(lineOf(p.prof, 2)->bounds == std::vector<std::string>{"velocity X"});
  CHECK(lineOf(p.prof, 3)->bounds == std::vector<std::string>{"short (accel X)"});
  CHECK(lineOf(p.prof, 4)->bounds == std::vector<std::string>{"accel X"});
  CHECK(lineOf(p.prof, 5)->bounds == std::vector<std::string>{"velocity X"});
  checkSums(p.prof, p.run->cycle());
  // a sharp corner taken fast in G64: the corner bounds both blocks
  auto c = profileText("G64 G01 X20 F400\nY20\nM30\n");
  CHECK(lineOf(c.prof, 1)->bounds == std::vector<std::string>{"corner"});
  CHECK(lineOf(c.prof, 2)->bounds == std::vector<std::string>{"corner"});
  checkSums(c.prof, c.run->cycle());
  // an arc bounded by its centripetal acceleration: r = 100, sqrt(100·2000) = 447 < F
  auto a = profileText("G02 X0 Y0 I100 J0 F480\nM30\n");
  CHECK(lineOf(a.prof, 1)->bounds == std::vector<std::string>{"centripetal"});
}

TEST_CASE("time profile: polling waits are inputs, WHEN joins are when, M0 is stop") {
  const machine::Machine m = machineFromJson(R"({"axes": [
      {"name": "X", "max_velocity": 500, "max_accel": 2000, "limit_minus": -1000, "limit_plus": 3000}],
      "inputs": {"3": [[0.0, 0], [0.1, 1]]}, "m0_wait_s": 0.2})");
  auto p = profileText("Wait: IF $aa_in[3] == 0 GOTOB Wait\nM0\n"
                       "WHEN $aa_iw[X] > 50 DO G04 F5\nG00 X100\nM30\n",
                       m);
  checkSums(p.prof, p.run->cycle());
  const auto* poll = lineOf(p.prof, 1);
  REQUIRE(poll);
  CHECK(poll->count == 50); // reads at t = 0.002, 0.004, ..., 0.1 (the input is 1 from 0.1 on)
  CHECK(poll->time.part(TimeCat::Inputs) == exact(0.1));
  CHECK(lineOf(p.prof, 2)->time.part(TimeCat::Stop) == exact(0.2));
  // the trigger arrives after 0.45 s; the body fired at X = 50 dwells 5 s
  const double tf = std::sqrt(50 / (A / 2));
  const auto* trig = lineOf(p.prof, 4);
  CHECK(trig->time.part(TimeCat::Accel) + trig->time.part(TimeCat::Cruise) + trig->time.part(TimeCat::Decel) ==
        exact(moveTime(100, 500, A)));
  CHECK(trig->time.part(TimeCat::When) == exact(tf + 5 - moveTime(100, 500, A)));
  CHECK(lineOf(p.prof, 3)->count == 2); // the WHEN line and its body (the same line)
}

TEST_CASE("time profile: subprograms are inclusive, counted per call - read-ahead lines take no time") {
  auto p = profileFiles({{"main.mpf", "G01 F100\nSUB1\nSUB1\nG64 X100\nR1=1\nX200\nM30\n"},
                         {"SUB1.spf", "PROC SUB1 SAVE\nG91 X10\nM17\n"}});
  checkSums(p.prof, p.run->cycle());
  REQUIRE(p.prof.procs.size() == 2);
  CHECK(p.prof.procs[0].name == "main");
  CHECK(p.prof.procs[0].calls == 1);
  CHECK(p.prof.procs[0].time.total() == exact(p.run->cycle()));
  CHECK(p.prof.procs[1].name == "SUB1");
  CHECK(p.prof.procs[1].calls == 2);
  CHECK(p.prof.procs[1].time.total() == exact(2 * moveTime(10, 100, A)));
  const auto* read = lineOf(p.prof, 5);
  REQUIRE(read);
  CHECK(read->count == 1);
  CHECK(read->time.total() == 0);
  // the chain X100 → X200 is one trapezoid of 180 mm
  CHECK(lineOf(p.prof, 4)->time.total() + lineOf(p.prof, 6)->time.total() == exact(moveTime(180, 100, A)));
}

TEST_CASE("time profile: a main program that ends after a call, without M30, owns the wait at its end") {
  // M40 (3 s, not blocking) is still running when the main program runs off its end after SUB1:
  // the wait belongs to the main program too, and the warning names the main program's end.
  auto m = machineWith([](machine::Machine& mm) { mm.mSequences[40] = {3.0, {}}; });
  auto p = profileFiles({{"main.mpf", "M=NB(40)\nSUB1\n"}, {"sub1.spf", "PROC SUB1 SAVE\nM17\n"}}, m);
  checkSums(p.prof, p.run->cycle());
  CHECK(p.run->cycle() == doctest::Approx(3.0 + 3 * m.blockTimeS).epsilon(1e-9));
  REQUIRE(p.prof.procs.size() == 2);
  CHECK(p.prof.procs[0].name == "main");
  CHECK(p.prof.procs[0].time.total() == exact(p.run->cycle()));
  bool named = false;
  for (const auto& w : p.run->summary().warnings)
    named = named || w == "the main program ended without M30 (main.mpf)";
  CHECK(named);
}

TEST_CASE("time profile: a G64 chain read through calls charges each block to its own call stack") {
  auto p = profileFiles({{"main.mpf", "G64 G01 F100\nOUTER\nM30\n"},
                         {"OUTER.spf", "PROC OUTER SAVE\nINNER\nX0\nM17\n"},
                         {"INNER.spf", "PROC INNER SAVE\nX10\nM17\n"}});
  checkSums(p.prof, p.run->cycle());
  REQUIRE(p.prof.procs.size() == 3);
  CHECK(p.prof.procs[0].time.total() == exact(p.run->cycle()));
  CHECK(p.prof.procs[1].name == "INNER");
  CHECK(p.prof.procs[2].name == "OUTER");
  CHECK(p.prof.procs[2].time.total() == exact(p.run->cycle()));
  CHECK(p.prof.procs[1].time.total() == exact(moveTime(10, 100, A)));
}

TEST_CASE("time profile: a G64 line rolled back when reading ahead is counted once") {
  auto p = profileText("R1=0\nG64 G01 X10 F100\nR1=R1+1 G04 F0.5\nX20\nM30\n");
  checkSums(p.prof, p.run->cycle());
  CHECK(lineOf(p.prof, 3)->count == 1);
  CHECK(lineOf(p.prof, 3)->time.part(TimeCat::Dwell) == exact(0.5));
}

TEST_CASE("time profile: a run that stops on an error still adds up to its stop time") {
  auto p = profileText("G01 X100 F100\nR1=1/0\nM30\n");
  CHECK(p.run->status() == sim::Status::Error);
  checkSums(p.prof, p.run->cycle());
  auto e = profileText("G00 X100\nG00 X5000\nM30\n");
  CHECK(e.run->status() == sim::Status::Emergency);
  checkSums(e.prof, e.run->cycle());
}

TEST_CASE("time profile: every sample adds up to its cycle time - text and JSON renderings") {
  const std::string dir = std::string(ISO_SOURCE_DIR) + "/samples/";
  for (const char* prog :
       {"pallet_loader/pallettizzatore.mpf", "drilling_when/foratura_piastra.mpf", "wait_input/stazione_saldatura.mpf",
        "recipe_case/dosatrice.mpf", "five_axis/marcatura_5assi.mpf", "semi_auto/fresatura_cornice.mpf",
        "contour_g64/taglio_piastra.mpf"}) {
    INFO(prog);
    machine::Machine m = machine::builtinMachine();
    frontend::LoadOptions lo;
    lo.machine = &m;
    lo.dialect = m.dialect;
    frontend::ProgramSet set;
    frontend::SetError err;
    REQUIRE(frontend::loadProgramSet({dir + prog}, lo, set, err));
    std::string diags;
    image::Image img = compileSet(set, m, &diags);
    REQUIRE(diags.empty());
    sim::TimeProfile prof;
    sim::SimOptions o;
    o.profile = &prof;
    sim::SimResult r = test::runImage(img, m, o, nullptr);
    REQUIRE(r.setupError == sim::SetupError::None);
    checkSums(prof, r.summary.cycleTimeS);
    const std::string text = sim::renderProfileText(prof);
    CHECK(text.find("profile: cycle time") == 0);
    CHECK(text.find("total") != std::string::npos);
    auto j = nlohmann::json::parse(sim::renderProfileJson(prof));
    CHECK(j["cycle_time_s"].get<double>() == r.summary.cycleTimeS);
    double sum = 0;
    for (const auto& l : j["lines"])
      sum += l["total_s"].get<double>();
    CHECK(sum == doctest::Approx(r.summary.cycleTimeS).epsilon(1e-12));
    CHECK(j["programs"][0]["total_s"].get<double>() == doctest::Approx(r.summary.cycleTimeS).epsilon(1e-12));
  }
}
