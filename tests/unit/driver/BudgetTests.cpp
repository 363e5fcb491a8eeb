//! @file BudgetTests.cpp
//! @brief isosim --compare --budget: the spellings it takes, the growth it allows, and the
//!        verdict at the printed resolution (a growth of exactly the budget passes).
#include <doctest/doctest.h>

#include "driver/Compare.h"

using namespace iso;

TEST_CASE("budget: shares and seconds, with or without a blank, and what is refused") {
  auto p = driver::parseBudget("2%");
  REQUIRE(p);
  CHECK(p->percent);
  CHECK(p->value == 2);
  CHECK(p->allowedS(50) == doctest::Approx(1.0).epsilon(1e-12));
  p = driver::parseBudget("1.5 s");
  REQUIRE(p);
  CHECK_FALSE(p->percent);
  CHECK(p->allowedS(1000) == 1.5);
  CHECK(driver::parseBudget("0%"));
  CHECK(driver::parseBudget(".5%"));
  for (const char* bad : {"", "2", "%", "s", "-2%", "+2%", "2.5.1s", "1e3s", "2 %%", "inf s", "2ms", ".s"})
    CHECK_MESSAGE(!driver::parseBudget(bad), bad);
}

TEST_CASE("budget: exceeded only past the allowed growth, compared at 1 microsecond") {
  driver::CompareSide oldSide, newSide;
  oldSide.summary.cycleTimeS = 50;
  newSide.summary.cycleTimeS = 51; // +1 s = 2% of 50 s exactly
  auto c = driver::compareProfiles(oldSide, newSide);
  driver::applyBudget(c, *driver::parseBudget("2%"));
  CHECK(c.allowedS == doctest::Approx(1.0));
  CHECK_FALSE(c.overBudget);
  CHECK(driver::renderComparisonText(c).find("budget  +1 s (2% of the old cycle time): within\n") != std::string::npos);
  newSide.summary.cycleTimeS = 51.000002;
  c = driver::compareProfiles(oldSide, newSide);
  driver::applyBudget(c, *driver::parseBudget("2%"));
  CHECK(c.overBudget);
  CHECK(driver::renderComparisonText(c).find("exceeded by 0.000002 s") != std::string::npos);
  CHECK(driver::renderComparisonGithub(c, "").rfind("::error title=cycle time over budget::", 0) == 0);
  // a program that got faster is within any budget, also 0 s
  newSide.summary.cycleTimeS = 40;
  c = driver::compareProfiles(oldSide, newSide);
  driver::applyBudget(c, *driver::parseBudget("0s"));
  CHECK_FALSE(c.overBudget);
  CHECK(driver::renderComparisonGithub(c, "").rfind("::notice title=cycle time::", 0) == 0);
}
