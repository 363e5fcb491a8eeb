//! @file Z32FlowTests.cpp
//! @brief Dialect z32's program flow and the rest of the line in isosim (SPEC §4.7), on
//!        images built by hand: GO ranges (nesting levels, the return), KG, axes under
//!        control, origins, PAR/PAL/user parameters, not-modelled G codes, TA/TB and the block
//!        counter inside a special M's subprogram. Cycle times are computed by hand (SPEC §5.2:
//!        the built-in axes have V = 500 mm/s, A = 2000 mm/s^2; a G00 move of d mm lasts
//!        d/V + V/A when d >= V^2/A = 125 mm, else 2 sqrt(d/A)).
#include <algorithm>
#include <string>

#include <doctest/doctest.h>

#include "SimTestUtil.h"
#include "image/ImageTestUtil.h"

using namespace iso;
using namespace iso::test;
using image::Op;
using sim::EventKind;
using sim::Status;

namespace {

constexpr uint8_t kX = 0x00, kY = 0x01, kZ = 0x02; // Pos[X], Pos[Y], Pos[Z] (image axes X Y Z)

/// A G00 move of d mm on a built-in axis.
double g0(double d) { return moveTime(d, 500, 2000); }

/// A z32 image: main program "m" (m.mpf, a line per stmt) and the subprograms given, which
/// are procedures 1, 2, ... (s1.spf, s2.spf, ...). The user parameter name "HA" is string 0.
image::Image z32Image(const Asm& main, const std::vector<Asm>& subs = {}) {
  Builder b;
  b.img.flags = image::Image::kFlagZ32;
  b.str("HA");
  b.proc(image::UnitKind::Main, "m", "m.mpf", main);
  for (size_t i = 0; i < subs.size(); ++i)
    b.proc(image::UnitKind::Sub, "S" + std::to_string(i + 1), "s" + std::to_string(i + 1) + ".spf", subs[i]);
  return b.img;
}

machine::Machine z32Machine() {
  return machineWith([](machine::Machine& m) {
    m.dialect = machine::Dialect::Z32;
    m.origins[1] = {{'X', 100.0}, {'Y', -20.0}};
    m.palPreset[3] = 1.5;
  });
}

std::unique_ptr<SimRun> run(const image::Image& img, const machine::Machine& m = z32Machine()) {
  auto r = std::make_unique<SimRun>();
  REQUIRE_NOTHROW(r->result = test::runImage(img, m, {}, &r->rec));
  return r;
}

Asm& moveTo(Asm& a, uint8_t axis, int64_t v) { return a.push(v).move({axis}); }

bool has(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

} // namespace

TEST_CASE("sim z32: a GO range runs its lines, returns after the end line and keeps the modal state") {
  Asm a;
  a.stmt().op(Op::G0);                              // 1
  a.stmt().op(Op::GoRange).ref("from").ref("to");   // 2: GON4-N5
  a.stmt().jump(Op::Jump, "after");                 // 3
  moveTo(a.label("from").stmt(), kX, 10);           // 4
  moveTo(a.label("to").stmt().op(Op::G91), kX, 20); // 5: the end line (G91: kept after the return)
  moveTo(a.stmt(), kX, 100);                        // 6: never runs
  moveTo(a.label("after").stmt(), kY, 5);           // 7: Y5 incremental
  a.stmt().op(Op::End);                             // 8
  auto r = run(z32Image(a));
  REQUIRE_MESSAGE(r->status() == Status::Ok, r->message());
  CHECK(r->pos('X') == 30);
  CHECK(r->pos('Y') == 5);
  CHECK(r->cycle() == exact(g0(10) + g0(20) + g0(5)));
  CHECK(r->lineTime(3) == exact(g0(10) + g0(20))); // after the range
  CHECK(std::isnan(r->lineTime(6)));
  CHECK(r->summary().blocks == 7); // lines 1 2 4 5 3 7 8
}

TEST_CASE("sim z32: GO ranges nest 10 levels, and an eleventh is too many subroutines") {
  const auto nested = [](int depth) {
    Asm a;
    for (int k = 0; k < depth; ++k) {
      const std::string next = "A" + std::to_string(k + 1);
      if (k > 0) a.label("A" + std::to_string(k));
      a.stmt().op(Op::GoRange).ref(next).ref(next).jump(Op::Jump, "end");
    }
    moveTo(a.label("A" + std::to_string(depth)).stmt(), kX, 1);
    a.label("end").stmt().op(Op::End);
    return z32Image(a);
  };
  auto ok = run(nested(10));
  REQUIRE_MESSAGE(ok->status() == Status::Ok, ok->message());
  CHECK(ok->cycle() == exact(g0(1)));
  CHECK(ok->summary().blocks == 12); // the 11 lines, then the end line once
  auto over = run(nested(11));
  CHECK(over->status() == Status::Error);
  CHECK(has(over->message(), "too many subroutines: call nesting deeper than 10 levels (a GO range)"));
  CHECK(has(over->message(), "m.mpf:11"));
}

TEST_CASE("sim z32: a ret inside a GO range leaves the range with its subprogram") {
  Asm m;
  m.stmt().call(1);
  moveTo(m.stmt(), kZ, 3);
  m.stmt().op(Op::End);
  Asm s;
  s.stmt().op(Op::GoRange).ref("a").ref("b");
  moveTo(s.stmt(), kY, 1); // never runs: the ret in the range returns from S1
  s.stmt().op(Op::Ret);
  moveTo(s.label("a").stmt(), kX, 10);
  s.stmt().op(Op::Ret);
  moveTo(s.label("b").stmt(), kX, 99);
  s.stmt().op(Op::Ret);
  auto r = run(z32Image(m, {s}));
  REQUIRE_MESSAGE(r->status() == Status::Ok, r->message());
  CHECK(r->pos('X') == 10);
  CHECK(r->pos('Y') == 0);
  CHECK(r->pos('Z') == 3);
  CHECK(r->cycle() == exact(g0(10) + g0(3)));
}

TEST_CASE("sim z32: KG replaces the running program without return") {
  SUBCASE("from the main program: the subprogram's return ends the program like M30") {
    Asm m;
    m.stmt().op(Op::Kg).uleb(1);
    Asm s;
    moveTo(s.stmt(), kX, 10);
    s.stmt().op(Op::Ret);
    auto r = run(z32Image(m, {s}));
    REQUIRE_MESSAGE(r->status() == Status::Ok, r->message());
    CHECK(r->pos('X') == 10);
    CHECK(r->cycle() == exact(g0(10)));
    CHECK(r->summary().warnings.empty()); // no "ended without M30"
    CHECK(r->count(EventKind::End) == 1);
  }
  SUBCASE("from a subprogram: the new one returns to the caller, whose SAVE state comes back") {
    Asm m;
    moveTo(m.stmt(), kY, 2);
    m.stmt().call(1);
    moveTo(m.stmt(), kY, 5); // G90 again: Y5 absolute
    m.stmt().op(Op::End);
    Asm s1;
    s1.stmt().op(Op::G91);
    s1.stmt().op(Op::Kg).uleb(2);
    moveTo(s1.stmt(), kX, 99); // never runs
    s1.stmt().op(Op::Ret);
    Asm s2;
    moveTo(s2.stmt(), kX, 10); // G91 of S1 still holds: X10 incremental from 0
    moveTo(s2.stmt(), kX, 10); // X20
    s2.stmt().op(Op::Ret);
    auto r = run(z32Image(m, {s1, s2}));
    REQUIRE_MESSAGE(r->status() == Status::Ok, r->message());
    CHECK(r->pos('X') == 20);
    CHECK(r->pos('Y') == 5);
    CHECK(r->cycle() == exact(g0(2) + g0(10) + g0(10) + g0(3)));
  }
}

TEST_CASE("sim z32: G29 releases axes (a move of one is a runtime error), G28 takes them back") {
  SUBCASE("a released axis") {
    Asm a;
    a.stmt().op(Op::AxisCtl).uleb(image::axisCtlOperand(0b001, false)); // 1: G29X
    moveTo(a.stmt(), kY, 10);                                           // 2
    moveTo(a.stmt(), kX, 10);                                           // 3
    a.stmt().op(Op::End);
    auto r = run(z32Image(a));
    CHECK(r->status() == Status::Error);
    CHECK(has(r->message(), "m.mpf:3"));
    CHECK(has(r->message(), "axis X is not under control: released by G29 at m.mpf:1"));
    CHECK(r->pos('X') == 0);
    CHECK(r->pos('Y') == 10);
    const auto ev = r->events(EventKind::AxisControl);
    REQUIRE(ev.size() == 1);
    CHECK(ev[0].axis == 'X');
    CHECK_FALSE(ev[0].on);
  }
  SUBCASE("G28 without letters: every axis") {
    Asm a;
    a.stmt().op(Op::AxisCtl).uleb(image::axisCtlOperand(0b011, false)); // G29XY
    a.stmt().op(Op::AxisCtl).uleb(image::axisCtlOperand(0, true));      // G28
    moveTo(a.stmt(), kX, 10);
    a.stmt().op(Op::End);
    auto r = run(z32Image(a));
    REQUIRE_MESSAGE(r->status() == Status::Ok, r->message());
    CHECK(r->cycle() == exact(g0(10)));
    const auto ev = r->events(EventKind::AxisControl);
    REQUIRE(ev.size() == 2 + 9);
    CHECK(ev[1].axis == 'Y');
    CHECK(ev[2].on);
    CHECK(ev[10].axis == 'W');
  }
}

TEST_CASE("sim z32: an origin offsets absolute targets, not steps, and $aa_iw reads program coordinates") {
  Asm a;
  a.stmt().op(Op::Origin).uleb(1);                                   // 1: O1 (X+100, Y-20)
  moveTo(a.stmt(), kX, 10);                                          // 2: machine X110
  moveTo(a.stmt().op(Op::G91), kX, 5);                               // 3: X115
  moveTo(a.stmt().op(Op::G90), kY, 0);                               // 4: machine Y-20
  a.stmt().op(Op::LoadAxVar).byte(3).byte(0).move({kZ});             // 5: Z = $aa_iw[X] = 15 (Z: offset 0)
  a.stmt().op(Op::LoadAxVar).byte(4).byte(1).op(Op::StoreR).uleb(1); // 6: R1 = $aa_fw[Y] = 0
  a.stmt().loadR(1).push(7).op(Op::Add).op(Op::StoreR).uleb(1);      // 7: R1 = 7
  SUBCASE("O1 stays") {
    a.stmt().op(Op::End);
    auto r = run(z32Image(a));
    REQUIRE_MESSAGE(r->status() == Status::Ok, r->message());
    CHECK(r->pos('X') == 115);
    CHECK(r->pos('Y') == -20);
    CHECK(r->pos('Z') == 15);
    CHECK(r->summary().origin == 1);
    CHECK(r->cycle() == exact(g0(110) + g0(5) + g0(20) + g0(15)));
    const auto moves = r->events(EventKind::MoveStart);
    REQUIRE(moves.size() == 4);
    CHECK(moves[0].target == 110); // events in machine coordinates
  }
  SUBCASE("O0 selects none") {
    a.stmt().op(Op::Origin).uleb(0);
    a.stmt().loadR(1).move({kY}); // Y = R1 = 7: $aa_fw[Y] read 0
    a.stmt().op(Op::End);
    auto r = run(z32Image(a));
    REQUIRE_MESSAGE(r->status() == Status::Ok, r->message());
    CHECK(r->pos('Y') == 7);
    CHECK(r->summary().origin == 0);
    CHECK(r->cycle() == exact(g0(110) + g0(5) + g0(20) + g0(15) + g0(27)));
  }
  SUBCASE("an origin the machine lacks") {
    a.stmt().op(Op::Origin).uleb(5);
    a.stmt().op(Op::End);
    auto r = run(z32Image(a));
    CHECK(r->status() == Status::Error);
    CHECK(has(r->message(), "origin O5 is not in the origins of machine"));
  }
}

TEST_CASE("sim z32: PAL writes are events and real-time, reads give the last write or pal_preset, and PAR and user "
          "parameters") {
  Asm a;
  a.stmt().push(3).op(Op::LoadPal).op(Op::StoreR).uleb(1); // 1: R1 = PAL[3] = 1.5 (preset)
  a.stmt().push(3).push(7).op(Op::StorePal).op(Op::Sync);  // 2: PAL[3] = 7 (waits for the ipo tick)
  a.stmt().push(3).op(Op::LoadPal).move({kX});             // 3: X = PAL[3] = 7
  a.stmt().loadR(1).move({kY});                            // 4: Y1.5
  a.stmt().push(999).push(4).op(Op::StorePar);             // 5: PAR[999] = 4
  a.stmt().push(2).op(Op::StoreUser).uleb(0);              // 6: HA = 2
  a.stmt().push(999).op(Op::LoadPar).op(Op::LoadUser).uleb(0).op(Op::Add).move({kZ}); // 7: Z = 6
  SUBCASE("in range") {
    a.stmt().op(Op::End);
    auto r = run(z32Image(a));
    REQUIRE_MESSAGE(r->status() == Status::Ok, r->message());
    CHECK(r->pos('X') == 7);
    CHECK(r->pos('Y') == 1.5);
    CHECK(r->pos('Z') == 6);
    CHECK(r->cycle() == exact(0.002 + g0(7) + g0(1.5) + g0(6)));
    const auto pal = r->events(EventKind::Pal);
    REQUIRE(pal.size() == 1);
    CHECK(pal[0].index == 3);
    CHECK(pal[0].number == 7);
    CHECK(pal[0].t == 0);
  }
  SUBCASE("PAL index out of range") {
    a.stmt().push(256).op(Op::LoadPal).op(Op::StoreR).uleb(1);
    a.stmt().op(Op::End);
    auto r = run(z32Image(a));
    CHECK(r->status() == Status::Error);
    CHECK(has(r->message(), "PAL"));
  }
  SUBCASE("PAR index out of range") {
    a.stmt().push(1000).push(1).op(Op::StorePar);
    a.stmt().op(Op::End);
    auto r = run(z32Image(a));
    CHECK(r->status() == Status::Error);
    CHECK(has(r->message(), "PAR"));
  }
}

TEST_CASE("sim z32: the statements of a special M's subprogram do not count in blocks") {
  const auto image = [](bool special) {
    Asm m;
    m.stmt();
    if (special) m.op(Op::MSpecial).uleb(40);
    m.call(1);
    moveTo(m.stmt(), kX, 10);
    m.stmt().op(Op::End);
    Asm s;
    moveTo(s.stmt(), kY, 5);
    s.stmt().call(2); // and what it calls
    s.stmt().op(Op::Ret);
    Asm s2;
    s2.stmt().op(Op::Ret);
    return z32Image(m, {s, s2});
  };
  auto plain = run(image(false));
  auto special = run(image(true));
  REQUIRE(special->status() == Status::Ok);
  CHECK(plain->summary().blocks == 7);
  CHECK(special->summary().blocks == 3);
  CHECK(special->count(EventKind::Line) == 7); // their line events are still written
  CHECK(special->cycle() == exact(g0(5) + g0(10)));
}

TEST_CASE("sim z32: a not-modelled G code takes no time and is listed once, TA mounts, TB reports") {
  Asm a;
  a.stmt().op(Op::Nm).uleb(84).op(Op::Nm).uleb(110);
  a.stmt().op(Op::Nm).uleb(84).push(5).op(Op::ZWord).byte(static_cast<uint8_t>(image::ZAddr::TA));
  a.stmt().push(7).op(Op::ZWord).byte(static_cast<uint8_t>(image::ZAddr::TB));
  a.stmt().op(Op::End);
  auto r = run(z32Image(a));
  REQUIRE_MESSAGE(r->status() == Status::Ok, r->message());
  CHECK(r->cycle() == 0);
  std::vector<std::string> warnings = r->summary().warnings;
  std::sort(warnings.begin(), warnings.end());
  CHECK(warnings == std::vector<std::string>{"G110 not modelled: 0 s", "G84 not modelled: 0 s"});
  REQUIRE(r->summary().tool.has_value());
  CHECK(*r->summary().tool == 5);
  CHECK(r->summary().toolChanges == 0);
  const auto tools = r->events(EventKind::Tool);
  REQUIRE(tools.size() == 2);
  CHECK(tools[0].state == "TA");
  CHECK(tools[0].tool == 5);
  CHECK(tools[1].state == "TB");
  CHECK(tools[1].tool == 7);
}
