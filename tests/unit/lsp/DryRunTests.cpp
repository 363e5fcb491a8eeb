//! @file DryRunTests.cpp
//! @brief The language server's dry runs: the cycle time and blocks of isosim, the title of a
//!        runtime error or emergency, a program that cannot run, a run the editor interrupts and
//!        one over its budget; the readable times of the lens.
#include <doctest/doctest.h>

#include <string>

#include "TestUtil.h"
#include "lsp/DryRun.h"

using namespace iso;

TEST_CASE("dry run: times read as seconds, then minutes, then hours") {
  CHECK(lsp::readableSeconds(0) == "0.000 s");
  CHECK(lsp::readableSeconds(39.2764) == "39.276 s");
  CHECK(lsp::readableSeconds(62.34) == "1:02.3");
  CHECK(lsp::readableSeconds(3723.44) == "1:02:03.4");
  CHECK(lsp::readableSeconds(59.99) == "59.990 s");
}

TEST_CASE("dry run: the cycle time, the blocks and the profile of a program") {
  test::TempDir dir;
  // X 100 mm at F=50, max_accel 2000: 100/50 + 50/2000 = 2.025 s; then a dwell of 1.5 s
  const std::string prog = dir.write("main.mpf", "G90 G60\nG01 X100 F=50\nG04 F1.5\nM30\n");
  lsp::DryRun r = lsp::dryRun(prog, nullptr, {}, nullptr);
  REQUIRE(r.state == lsp::DryRun::State::Ok);
  CHECK(std::abs(r.summary.cycleTimeS - 3.525) <= 3.525e-9);
  CHECK(r.title == "cycle 3.525 s · 4 blocks");
  double line2 = 0;
  for (const sim::LineProfile& lp : r.profile.lines)
    if (lp.line == 2) line2 = lp.time.total();
  CHECK(std::abs(line2 - 2.025) <= 2.025e-9);
}

TEST_CASE("dry run: an emergency, a program with errors, an interrupted run, a run over its budget") {
  test::TempDir dir;
  lsp::DryRun e = lsp::dryRun(dir.write("crash.mpf", "G90 G60\nG00 X=5000\nM30\n"), nullptr, {}, nullptr);
  CHECK(e.state == lsp::DryRun::State::Emergency);
  CHECK(e.title.find("crash.mpf:2") != std::string::npos);
  lsp::DryRun f = lsp::dryRun(dir.write("bad.mpf", "G00 X=\nM30\n"), nullptr, {}, nullptr);
  CHECK(f.state == lsp::DryRun::State::Failed);
  CHECK(f.title.rfind("no dry run: ", 0) == 0);
  const std::string loop = dir.write("loop.mpf", "R1 = 0\nGIRO:\nR1 = R1 + 1\nIF R1 < 90000000 GOTOB GIRO\nM30\n");
  lsp::DryRun c = lsp::dryRun(loop, nullptr, {}, [] { return true; });
  CHECK(c.state == lsp::DryRun::State::Cancelled);
  lsp::DryRunOptions quick;
  quick.budgetSeconds = 0.05;
  lsp::DryRun b = lsp::dryRun(loop, nullptr, quick, [] { return false; });
  CHECK(b.state == lsp::DryRun::State::OverBudget);
  CHECK(b.title.find("stopped after 0.05 s") != std::string::npos);
}
