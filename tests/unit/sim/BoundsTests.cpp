//! @file BoundsTests.cpp
//! @brief Bounded work on any verified image (SPEC §6.3): every instruction counts against a
//!        budget tied to --max-steps, loops without a statement are runtime errors, WHEN
//!        conditions as deep as the verifier allows, G64 read-ahead bounded in statements.
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

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

/// A verified image "m" (m.mpf, one line per stmt) with the given main code.
image::Image verifiedMain(const Asm& code) {
  Builder b;
  b.img.constants = {2.5};
  b.proc(image::UnitKind::Main, "m", "m.mpf", code);
  Checked c = check(b.img);
  INFO(c.err.message);
  REQUIRE(c.verified);
  return b.img;
}

/// Runs an image on the built-in machine; the run must end with a runtime error (never an
/// internal error) whose message holds `part`.
std::unique_ptr<SimRun> runImage(const image::Image& img, sim::SimOptions opts = {}) {
  auto run = std::make_unique<SimRun>();
  REQUIRE_NOTHROW(run->result = test::runImage(img, builtin(), opts, &run->rec));
  return run;
}

void expectError(const SimRun& r, const std::string& part) {
  INFO("message: " << r.message());
  CHECK(r.status() == Status::Error);
  CHECK(contains(r.message(), "runtime error at t="));
  CHECK(contains(r.message(), part));
  CHECK(r.count(EventKind::Error) == 1);
}

/// Line 1: G1 F`feed`; line 2: WHEN `cond` DO `body` (body statement on line 3); line 4: X10;
/// line 5: M30.
image::Image whenImage(const Asm& cond, const Asm& body, int64_t feed = 100) {
  Asm a;
  a.stmt()
      .op(Op::G1)
      .push(feed)
      .op(Op::SetF)
      .stmt()
      .op(Op::When)
      .ref("cond")
      .ref("body")
      .jump(Op::Jump, "after")
      .label("cond");
  a.b.insert(a.b.end(), cond.b.begin(), cond.b.end());
  a.label("body");
  const uint32_t bodyAt = a.here();
  a.b.insert(a.b.end(), body.b.begin(), body.b.end());
  for (const auto& [at, l] : body.refs)
    a.refs.emplace_back(at + bodyAt, l);
  for (const auto& [l, at] : body.labels)
    a.labels[l] = at + bodyAt;
  a.label("after").stmt().push(10).move({0x00}).stmt().op(Op::End);
  return verifiedMain(a);
}

} // namespace

TEST_CASE("sim: a loop without a statement between statements counts against the step budget") {
  // One statement, then 8000 instructions without one, then back: --max-steps alone lets it
  // run 1000 x 8000 instructions; the instruction budget stops it after a few statements.
  Asm a;
  a.label("top")
      .stmt()
      .push(0)
      .storeR(2)
      .label("inner")
      .loadR(2)
      .push(1)
      .op(Op::Add)
      .storeR(2)
      .loadR(2)
      .push(1000)
      .op(Op::CmpLt)
      .jump(Op::JumpTrue, "inner")
      .jump(Op::Jump, "top");
  sim::SimOptions o;
  o.maxSteps = 1000;
  auto r = runImage(verifiedMain(a), o);
  expectError(*r, "instructions (16 per statement of --max-steps); a runaway program?");
  CHECK(contains(r->message(), "m.mpf:1:"));
  CHECK(r->summary().blocks < 10);
}

TEST_CASE("sim: loops that never reach a statement are runtime errors, not internal errors") {
  const std::string part = "10000000 instructions without a statement";
  SUBCASE("a jump to itself") {
    auto r = runImage(verifiedMain(Asm().stmt().label("l").jump(Op::Jump, "l")));
    expectError(*r, part);
    CHECK(contains(r->message(), "m.mpf:1:"));
  }
  SUBCASE("a CASE whose default is itself") {
    Asm a;
    a.stmt().label("l").push(7).op(Op::Case).uleb(1).uleb(0).ref("out").ref("l").label("out").stmt().op(Op::End);
    expectError(*runImage(verifiedMain(a)), part);
  }
  SUBCASE("stmt.skip to itself with --block-skip") {
    sim::SimOptions o;
    o.blockSkip = true;
    auto r = runImage(verifiedMain(Asm().label("l").op(Op::StmtSkip).ref("l").op(Op::End)), o);
    expectError(*r, part);
    CHECK(contains(r->message(), "m.mpf"));
  }
  SUBCASE("a WHEN body that spins") {
    auto img = whenImage(Asm().push(1).op(Op::CondEnd), Asm().stmt().label("spin").jump(Op::Jump, "spin"));
    auto r = runImage(img);
    expectError(*r, part);
    CHECK(contains(r->message(), "m.mpf:3:"));
  }
}

TEST_CASE("sim: a WHEN condition as deep as the verifier allows is evaluated") {
  Asm cond;
  for (int i = 0; i < 200; ++i)
    cond.push(1);
  for (int i = 0; i < 199; ++i)
    cond.op(Op::And);
  cond.op(Op::CondEnd);
  auto r = runImage(whenImage(cond, Asm().stmt().push(1).push(1).op(Op::StoreIo).byte(7).op(Op::BodyEnd)));
  INFO(r->message());
  CHECK(r->status() == Status::Ok);
  CHECK(r->whenTime("fired") == 0);
}

TEST_CASE("sim: watching a WHEN condition counts against the instruction budget") {
  // $aa_iw[X] > 1000 over a 10 s move: thousands of evaluations of 4 instructions.
  Asm cond;
  cond.op(Op::LoadAxVar).byte(3).byte(0).push(1000).op(Op::CmpGt).op(Op::CondEnd);
  auto img = whenImage(cond, Asm().stmt().op(Op::BodyEnd), 1);
  sim::SimOptions o;
  o.maxSteps = 50;
  auto r = runImage(img, o);
  expectError(*r, "per statement of --max-steps");
  CHECK(contains(r->message(), "m.mpf:2:"));
  // with the default bounds the same watch is cheap
  CHECK(runImage(img)->status() == Status::Ok);
}

TEST_CASE("sim: G64 reads ahead a bounded number of statements, moving or not") {
  // A G64 block followed by an endless loop of R assignments: reading ahead stops after
  // 16 x lookahead_blocks statements; the rest run after the path has stopped, with their
  // block time.
  auto m = machineWith([](machine::Machine& mm) {
    mm.blockTimeS = 0.001;
    mm.lookaheadBlocks = 4;
  });
  sim::SimOptions o;
  o.maxSteps = 1000;
  auto r = simText("G64 G01 F100\nX10\nL: R1 = R1 + 1\nGOTOB L\nM30\n", m, o);
  REQUIRE(r->diagnostics.empty());
  CHECK(r->status() == Status::Error);
  CHECK(contains(r->message(), "--max-steps"));
  // 2 statements before the chain, 64 read ahead (not counted in blocks: SPEC §5.3), 933 at 1 ms
  // each after the move; the statement number 1000 stops the run (SPEC §6.3)
  CHECK(r->summary().blocks == 2 + 933);
  CHECK(r->summary().linesExecuted == 2 + 64 + 933); // the read-ahead ones too
  const double moveEnd = 0.002 + moveTime(10, 100, 2000);
  CHECK(r->moveEnd('X') == exact(moveEnd));
  CHECK(r->cycle() == doctest::Approx(moveEnd + 933 * 0.001).epsilon(1e-9));
  CHECK(r->lineTime(3, 31) == exact(moveEnd)); // read ahead: at the junction instant
  CHECK(r->lineTime(3, 32) == exact(moveEnd)); // the first one run after the stop
  CHECK(r->lineTime(3, 33) > moveEnd);
}
