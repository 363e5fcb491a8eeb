//! @file ProfileRecorderTests.cpp
//! @brief The --profile journal: counts, mark/rollback of read-ahead, time split by phase.
#include <doctest/doctest.h>

#include "sim/ProfileRecorder.h"

using namespace iso::sim;

namespace {

/// One procedure "MAIN" in main.iso, two statements on lines 3 and 4.
struct Fixture {
  iso::image::Image img;
  InstructionStream prog{code(), {0}};
  std::vector<std::string> names;
  static std::vector<Ins> code() {
    Ins s;
    s.op = iso::image::Op::Stmt;
    s.c = 0;
    std::vector<Ins> out{s};
    s.c = 1;
    out.push_back(s);
    return out;
  }
  Fixture() {
    img.strings = {"MAIN", "main.iso"};
    names = img.strings;
    iso::image::Proc p;
    p.name = 0;
    p.file = 1;
    img.procs.push_back(p);
    iso::image::LineEntry l;
    l.file = 1;
    l.line = 3;
    img.lines.push_back(l);
    l.line = 4;
    img.lines.push_back(l);
  }
};

} // namespace

TEST_CASE("profile recorder: a rollback takes back what was journaled after the mark") {
  Fixture f;
  ProfileRecorder rec;
  rec.start(f.prog.size(), f.img.procs.size());
  rec.count(0, false);
  const size_t mark = rec.mark();
  rec.count(1, true);
  rec.count(0, true);
  rec.rollback(mark);
  rec.count(1, true);
  rec.commit();
  rec.rollback(0); // nothing left to take back
  TimeProfile out;
  rec.build(out, f.img, f.prog, f.names, 0, 0);
  REQUIRE(out.lines.size() == 2);
  CHECK(out.lines[0].line == 3);
  CHECK(out.lines[0].count == 1);
  CHECK(out.lines[1].line == 4);
  CHECK(out.lines[1].count == 1);
  REQUIRE(out.procs.size() == 1);
  CHECK(out.procs[0].name == "MAIN");
}

TEST_CASE("profile recorder: a motion wait splits into accel, cruise, decel, then its category") {
  Fixture f;
  ProfileRecorder rec;
  rec.start(f.prog.size(), f.img.procs.size());
  AxisMotion mot;
  mot.prof = makeTrapezoid(100, 100, 2000); // 0.05 s accel, 0.95 s cruise, 0.05 s decel
  mot.tEnd = mot.prof.duration();
  rec.begin(0, TimeCat::Plc, -1, 0, &mot).push_back(0);
  rec.bound(0, "feed");
  rec.bound(0, "feed");
  rec.end(2);
  CHECK_FALSE(rec.open());
  TimeProfile out;
  rec.build(out, f.img, f.prog, f.names, 0, 2);
  CHECK(out.cycleTimeS == 2);
  CHECK(out.total.part(TimeCat::Accel) == doctest::Approx(0.05));
  CHECK(out.total.part(TimeCat::Cruise) == doctest::Approx(0.95));
  CHECK(out.total.part(TimeCat::Decel) == doctest::Approx(0.05));
  CHECK(out.total.part(TimeCat::Plc) == doctest::Approx(0.95));
  REQUIRE(out.lines.size() == 1);
  CHECK(out.lines[0].bounds == std::vector<std::string>{"feed"});
  CHECK(out.procs[0].time.part(TimeCat::Cruise) == doctest::Approx(0.95));
}

TEST_CASE("profile recorder: bound labels") {
  const Trapezoid cruising = makeTrapezoid(100, 100, 2000);
  CHECK(boundLabel(cruising, SpeedBound::Feed, 'X', 'X', false) == "feed");
  CHECK(boundLabel(cruising, SpeedBound::AxisVelocity, 'Y', 'X', false) == "velocity Y");
  CHECK(boundLabel(makeTrapezoid(1, 500, 2000), SpeedBound::Feed, 'X', 'Z', false) == "short (accel Z)");
  CHECK(boundLabel(makeTrapezoid(1, 500, 2000), SpeedBound::Feed, 'X', 'Z', true) == "corner");
}
