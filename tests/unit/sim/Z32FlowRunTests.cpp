//! @file Z32FlowRunTests.cpp
//! @brief Dialect z32 program flow from source to run: GO jumps and ranges, GOP, KG, G26,
//!        G28/G29, origins, the order of a line that combines many steps. Times are computed
//!        by hand from the machine below (SPEC §5.2 trapezoids; 1e-9 relative).
#include <cmath>
#include <string>
#include <vector>

#include <doctest/doctest.h>

#include "SimTestUtil.h"

using namespace iso;
using sim::EventKind;
using test::exact;
using test::machineFromJson;
using test::simFiles;
using test::simText;

namespace {

/// X and Y: 100 mm/s, 1000 mm/s². A move of d >= v²/a = 10 mm takes d/100 + 0.1 s; a shorter
/// one 2·sqrt(d/1000). M6 lasts 0.3 s, every other M 0 s. Origin 1 shifts X by 100 mm.
machine::Machine flowMachine(const std::string& extra = "") {
  return machineFromJson(R"({"name": "z32flow", "dialect": "z32",
    "axes": [{"name": "X", "max_velocity": 100, "max_accel": 1000, "limit_minus": -1000, "limit_plus": 1000},
             {"name": "Y", "max_velocity": 100, "max_accel": 1000, "limit_minus": -1000, "limit_plus": 1000}],
    "m_sequences": {"6": {"duration_s": 0.3}},
    "origins": {"1": {"X": 100}})" +
                         extra + "}");
}

/// A trapezoid (or triangle) move of d mm at 100 mm/s and 1000 mm/s².
double moveTime(double d) { return d >= 10 ? d / 100 + 0.1 : 2 * std::sqrt(d / 1000); }

bool hasError(const test::SimRun& r) { return r.diagnostics.find("error") != std::string::npos; }

} // namespace

TEST_CASE("z32 flow: GO jumps forward over lines and backward to an earlier line") {
  SUBCASE("forward") {
    auto r = simText("G00 X10\nGON30\nN20 X100\nN30 X30\nM30\n", flowMachine());
    REQUIRE_FALSE(hasError(*r));
    CHECK(r->status() == sim::Status::Ok);
    CHECK(r->cycle() == exact(moveTime(10) + moveTime(20)));
    CHECK(r->pos('X') == exact(30));
    CHECK(std::isnan(r->lineTime(3))); // N20 never runs
    CHECK(r->summary().blocks == 4);
  }
  SUBCASE("backward") {
    auto r = simText("GON30\nN20 X20\nM30\nN30 X30\nGON20\n", flowMachine());
    REQUIRE_FALSE(hasError(*r));
    CHECK(r->status() == sim::Status::Ok);
    CHECK(r->cycle() == exact(moveTime(30) + moveTime(10)));
    CHECK(r->pos('X') == exact(20));
  }
}

TEST_CASE("z32 flow: a GO range runs its lines, then returns to the line after the GO") {
  // N10 and N20 run twice: from the range of line 1 and from the range of line 3
  auto r = simText("GON10-N20\nG90\nGON10-N20\nM30\nN10 G91 X10\nN20 X10\n", flowMachine());
  REQUIRE_FALSE(hasError(*r));
  CHECK(r->status() == sim::Status::Ok);
  CHECK(r->cycle() == exact(4 * moveTime(10)));
  CHECK(r->pos('X') == exact(40));
  CHECK(r->lineTime(5, 1) == exact(2 * moveTime(10)));
}

TEST_CASE("z32 flow: ten nested GO ranges run, an eleventh level is a runtime error") {
  // line k (k = 1..10) runs the range of line k+1 only; line 11 moves
  std::string ok;
  for (int k = 1; k <= 10; ++k)
    ok += "N" + std::to_string(k) + " GON" + std::to_string(k + 1) + "-N" + std::to_string(k + 1) + "\n";
  ok += "N11 X10\n";
  // the main program starts at line 1: its GO is level 1, line 10's is level 10
  auto r = simText("GON1-N1\nM30\n" + ok, flowMachine());
  CHECK(r->diagnostics.find("E211") != std::string::npos); // 11 levels statically
  auto r10 = simText("GON2-N2\nM30\n" + ok, flowMachine());
  REQUIRE_FALSE(hasError(*r10));
  CHECK(r10->status() == sim::Status::Ok);
  CHECK(r10->pos('X') == exact(10));
  CHECK(r10->cycle() == exact(moveTime(10)));
  // a range that runs itself: levels grow at run time until the eleventh
  auto rec = simText("N1 GON2-N3\nM30\nN2 G91 X1\nN3 GON2-N3\n", flowMachine());
  REQUIRE_FALSE(hasError(*rec));
  CHECK(rec->status() == sim::Status::Error);
  CHECK(rec->message().find("too many subroutines") != std::string::npos);
  CHECK(rec->pos('X') == exact(10)); // N2 ran on levels 1..10
}

TEST_CASE("z32 flow: GOP calls a subprogram, G26 returns from it") {
  auto r = simFiles({{"main.mpf", "GOPLIFT\nX30\nM30\n"}, {"lift.spf", "PROC LIFT SAVE\nX10 G26\n"}}, flowMachine());
  REQUIRE_FALSE(hasError(*r));
  CHECK(r->status() == sim::Status::Ok);
  CHECK(r->cycle() == exact(moveTime(10) + moveTime(20)));
  CHECK(r->pos('X') == exact(30));
}

TEST_CASE("z32 flow: KG continues in a subprogram without return") {
  SUBCASE("from the main program: its return ends the program") {
    auto r =
        simFiles({{"main.mpf", "X10 KGSUB\nX500\nM30\n"}, {"sub.spf", "PROC SUB SAVE\nX30\nM17\n"}}, flowMachine());
    REQUIRE_FALSE(hasError(*r));
    CHECK(r->status() == sim::Status::Ok);
    CHECK(r->cycle() == exact(moveTime(10) + moveTime(20)));
    CHECK(r->pos('X') == exact(30)); // X500 never runs
  }
  SUBCASE("from a subprogram: the new one returns to the caller, restoring the caller's SAVE state") {
    auto r = simFiles({{"main.mpf", "G00 X10\nSUBA\nX0\nM30\n"},
                       {"suba.spf", "PROC SUBA SAVE\nG91\nKGSUBB\nM17\n"},
                       {"subb.spf", "PROC SUBB SAVE\nX5\nM17\n"}},
                      flowMachine());
    REQUIRE_FALSE(hasError(*r));
    CHECK(r->status() == sim::Status::Ok);
    // X10, then G91 X5 in SUBB (X15), then back in the main program in G90: X0
    CHECK(r->cycle() == exact(moveTime(10) + moveTime(5) + moveTime(15)));
    CHECK(r->pos('X') == exact(0));
  }
}

TEST_CASE("z32 flow: a move of an axis released by G29 is a runtime error, G28 takes it back") {
  auto bad = simText("G29X\nG00 X10\nM30\n", flowMachine());
  REQUIRE_FALSE(hasError(*bad));
  CHECK(bad->status() == sim::Status::Error);
  CHECK(bad->message().find("X") != std::string::npos);
  CHECK(bad->message().find(":1") != std::string::npos); // names the G29 line
  auto ok = simText("G29X\nG00 Y10\nG28X\nX10\nM30\n", flowMachine());
  REQUIRE_FALSE(hasError(*ok));
  CHECK(ok->status() == sim::Status::Ok);
  CHECK(ok->cycle() == exact(2 * moveTime(10)));
}

TEST_CASE("z32 flow: an origin shifts absolute targets, not incremental ones, and $aa_iw reads program coordinates") {
  // machine X: 110 (1.2 s), then the real-time read waits for the next 2 ms boundary after
  // 1.2 s, then G91 X10 (machine 120), O0 and G90 X=R1: R1 = 10 (program coordinates), so X
  // goes from 120 to 10
  auto r = simText("O1\nG00 G90 X10\nR1=$aa_iw[X]\nG91 X10\nO0\nG90 X=R1\nM30\n", flowMachine());
  REQUIRE_FALSE(hasError(*r));
  CHECK(r->status() == sim::Status::Ok);
  CHECK(r->pos('X') == exact(10));
  CHECK(r->cycle() == exact(moveTime(110) + 0.002 + moveTime(10) + moveTime(110)));
  CHECK(r->summary().finalPosition.size() == 2);
}

TEST_CASE("z32 flow: the order of a line that combines many steps") {
  // written backwards; it runs: G84 (step 0), T2 (4), O1 (4b), the move (5), G29Y (6b), M6 (9),
  // KG (11): the move goes to machine X 110 in program coordinates of origin 1
  auto r = simFiles({{"main.mpf", "KGEND M6 G29Y X10 O1 T2 G84\nM30\n"}, {"end.spf", "PROC END SAVE\nY5\nM17\n"}},
                    flowMachine());
  REQUIRE_FALSE(hasError(*r));
  CHECK(r->status() == sim::Status::Error); // Y was released on the line before the KG
  CHECK(r->pos('X') == exact(110));
  CHECK(r->summary().tool == 2); // M6 mounted T2 before KG
  auto mStarts = r->events(EventKind::MStart);
  REQUIRE(mStarts.size() == 1);
  CHECK(mStarts[0].t == exact(moveTime(110))); // M6 after the move
}
