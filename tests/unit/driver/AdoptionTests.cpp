//! @file AdoptionTests.cpp
//! @brief isolint on legacy programs: --baseline FILE (written when absent, then only new
//!        findings are reported), --select (only these rules) and --statistics (a count per code).
#include <doctest/doctest.h>

#include <filesystem>
#include <sstream>

#include <nlohmann/json.hpp>

#include "TestUtil.h"
#include "driver/Lint.h"

using namespace iso;

namespace {
struct Outcome {
  int rc = 0;
  std::string out, err;
};
Outcome lintWith(driver::LintOptions o) {
  std::ostringstream out, err;
  driver::Io io{out, err};
  o.common.color = "never";
  Outcome r;
  r.rc = driver::runLint(o, io, nullptr);
  r.out = out.str();
  r.err = err.str();
  return r;
}
/// A main program with two W402 and a subprogram with an E208 and a W402.
void legacyFolder(const test::TempDir& dir) {
  dir.write("a.mpf", "G1 X10\nG0 X0 Y0\nG1 Y5\nM30\n");
  dir.write("s.spf", "PROC Sub\nG1 X1\nM17\n");
}
} // namespace

TEST_CASE("--baseline: a missing file is written with the findings, and the run reports as usual") {
  test::TempDir dir;
  legacyFolder(dir);
  driver::LintOptions o;
  o.paths = {dir.path()};
  o.baseline = dir.path() + "/known.json";
  const auto first = lintWith(o);
  INFO(first.out, first.err);
  CHECK(first.rc == 1); // the E208 is reported this time
  CHECK(first.out.find("1 error, 3 warnings") != std::string::npos);
  CHECK(first.err.find("wrote the baseline") != std::string::npos);
  const auto doc = nlohmann::json::parse(test::readFileBytes(o.baseline));
  CHECK(doc["isolint_baseline"] == 1);
  REQUIRE(doc["findings"].size() == 4);
  CHECK(doc["findings"][2]["code"] == "E208");
  CHECK(doc["findings"][2]["line"] == 1);

  // the second run leaves out what the baseline lists
  const auto second = lintWith(o);
  INFO(second.out, second.err);
  CHECK(second.rc == 0);
  CHECK(second.out.find("0 errors, 0 warnings") != std::string::npos);
  CHECK(second.err.find("4 known findings") != std::string::npos);

  // a new finding is reported; the known ones stay left out although their lines moved
  dir.write("a.mpf", "G0 Z50\nG1 X10\nG0 X0 Y0\nG1 Y5\nG1 Z4\nM30\n");
  const auto third = lintWith(o);
  INFO(third.out);
  CHECK(third.out.find("a.mpf:5:4: warning") != std::string::npos);
  CHECK(third.out.find("0 errors, 1 warning,") != std::string::npos);
  CHECK(third.out.find(":2:4:") == std::string::npos);
}

TEST_CASE("--baseline: a file that is not a baseline is refused before anything is checked") {
  test::TempDir dir;
  legacyFolder(dir);
  driver::LintOptions o;
  o.paths = {dir.path()};
  o.baseline = dir.write("known.json", "{\"findings\": []}");
  auto r = lintWith(o);
  CHECK(r.rc == 2);
  CHECK(r.err.find("not an isolint baseline") != std::string::npos);
  CHECK(r.out.empty());
  o.baseline = dir.write("garbage.json", "G1 X1\n");
  r = lintWith(o);
  CHECK(r.rc == 2);
  CHECK(r.err.find("garbage.json:byte") != std::string::npos);
  o.baseline = dir.write("other.json", "{\"isolint_baseline\": 7, \"findings\": []}");
  r = lintWith(o);
  CHECK(r.rc == 2);
  CHECK(r.err.find("version 7") != std::string::npos);
  CHECK(test::readFileBytes(o.baseline) == "{\"isolint_baseline\": 7, \"findings\": []}"); // never rewritten
  o.baseline = dir.path() + "/new.json";
  o.fix = true;
  r = lintWith(o);
  CHECK(r.rc == 2);
  CHECK(!std::filesystem::exists(o.baseline));
}

TEST_CASE("--select: only the rules named are shown, and the exit status follows them") {
  test::TempDir dir;
  legacyFolder(dir);
  driver::LintOptions o;
  o.paths = {dir.path()};
  o.select = {"feed-unset"};
  auto r = lintWith(o);
  CHECK(r.rc == 0);
  CHECK(r.out.find("0 errors, 3 warnings") != std::string::npos);
  CHECK(r.out.find("E208") == std::string::npos);
  o.select = {"E208,W402"};
  r = lintWith(o);
  CHECK(r.rc == 1);
  CHECK(r.out.find("1 error, 3 warnings") != std::string::npos);
  o.select = {"E208"};
  o.disable = {"E208"}; // --disable wins over --select
  r = lintWith(o);
  CHECK(r.out.find("0 errors, 0 warnings") != std::string::npos);
  o.select = {"W999"};
  r = lintWith(o);
  CHECK(r.rc == 2);
  CHECK(r.err.find("unknown diagnostic 'W999'") != std::string::npos);
}

TEST_CASE("--statistics: one row per code, most frequent first, then the count line, or JSON") {
  test::TempDir dir;
  legacyFolder(dir);
  driver::LintOptions o;
  o.paths = {dir.path()};
  o.statistics = true;
  auto r = lintWith(o);
  CHECK(r.rc == 1);
  CHECK(r.out ==
        "      3  W402  feed-unset\n      1  E208  proc-header\n2 files checked: 1 error, 3 warnings, 0 infos\n");
  o.format = "json";
  r = lintWith(o);
  const auto doc = nlohmann::json::parse(r.out);
  REQUIRE(doc["statistics"].size() == 2);
  CHECK(doc["statistics"][0]["code"] == "W402");
  CHECK(doc["statistics"][0]["count"] == 3);
  CHECK(doc["statistics"][1]["severity"] == "error");
  CHECK(doc["errors"] == 1);
  CHECK(doc["files"] == 2);
  o.format = "sarif";
  r = lintWith(o);
  CHECK(r.rc == 2);
  // clean files: no rows, the count line
  test::TempDir clean;
  clean.write("p.mpf", "G0 X1\nM30\n");
  driver::LintOptions c;
  c.paths = {clean.path()};
  c.statistics = true;
  r = lintWith(c);
  CHECK(r.rc == 0);
  CHECK(r.out == "1 file checked: 0 errors, 0 warnings, 0 infos\n");
}
