//! @file LintDriverTests.cpp
//! @brief The isolint driver: standard input with --stdin-filename, folders as program sets.
#include <doctest/doctest.h>

#include <filesystem>
#include <sstream>

#include "TestUtil.h"
#include "driver/Lint.h"

using namespace iso;

namespace {
struct LintRun {
  int rc = 0;
  std::string out, err;
};
LintRun lint(driver::LintOptions o, const std::string& stdinText = "") {
  std::ostringstream out, err;
  std::istringstream in(stdinText);
  driver::Io io{out, err};
  o.common.color = "never";
  LintRun r;
  r.rc = driver::runLint(o, io, &in);
  r.out = out.str();
  r.err = err.str();
  return r;
}
} // namespace

TEST_CASE("stdin: the buffer is linted as the named file, with its folder's programs") {
  test::TempDir dir;
  dir.write("lift.spf", "PROC Lift SAVE\nG00 Z10\nM17\n");
  dir.write("p.mpf", "this text on disk is not read\n");
  driver::LintOptions o;
  o.paths = {"-"};
  o.stdinFilename = dir.path() + "/p.mpf";
  auto r = lint(o, "G00 X10\nLift\nG01 X5\nM30\n");
  INFO(r.out, r.err);
  CHECK(r.rc == 0);
  CHECK(r.out.find("p.mpf:3:5: warning: feed move without a feed") != std::string::npos); // the buffer's line 3
  CHECK(r.out.find("E210") == std::string::npos);                                         // Lift found beside it
  CHECK(r.out.find("1 file checked") != std::string::npos);
  // the file need not exist on disk
  o.stdinFilename = dir.path() + "/new.mpf";
  r = lint(o, "Nowhere\nM30\n");
  CHECK(r.rc == 1);
  CHECK(r.out.find("new.mpf:1:1: error") != std::string::npos);
}

TEST_CASE("stdin: '-' alone is <stdin>, a program set of its own, and '-' is read once") {
  driver::LintOptions o;
  o.paths = {"-"};
  auto r = lint(o, "G00 X=\nM30\n");
  INFO(r.out, r.err);
  CHECK(r.rc == 1);
  CHECK(r.out.find("<stdin>:1:7: error:") != std::string::npos); // E100: no operand
  CHECK(lint(o, "M30\n").rc == 0);
  o.paths = {"-", "x.mpf"}; // without a file name it cannot join a folder's set
  r = lint(o, "M30\n");
  CHECK(r.rc == 2);
  CHECK(r.err.find("is a program set of its own") != std::string::npos);
  o.stdinFilename = "p.mpf";
  o.paths = {"-", "-"};
  r = lint(o, "M30\n");
  CHECK(r.rc == 2);
  CHECK(r.err.find("isolint: error: standard input is read as one file") != std::string::npos);
}

TEST_CASE("folders: every folder is its own program set, walked recursively") {
  test::TempDir dir;
  std::filesystem::create_directories(dir.path() + "/a/sub");
  std::filesystem::create_directories(dir.path() + "/b");
  std::filesystem::create_directories(dir.path() + "/.git");
  dir.write("a/main.mpf", "Lift\nM30\n");
  dir.write("a/lift.spf", "PROC Lift SAVE\nM17\n");
  dir.write("b/main.mpf", "Lift\nM30\n");
  dir.write("b/lift.spf", "PROC Lift SAVE\nM17\n");
  dir.write("a/sub/only.mpf", "Lift\nM30\n"); // its own set: Lift is not there
  dir.write(".git/x.mpf", "garbage (\n");
  driver::LintOptions o;
  o.paths = {dir.path()};
  auto r = lint(o);
  INFO(r.out, r.err);
  CHECK(r.out.find("E209") == std::string::npos);
  CHECK(r.out.find("only.mpf:1:1: error") != std::string::npos); // E210 in a/sub
  CHECK(r.out.find("x.mpf") == std::string::npos);
  CHECK(r.out.find("5 files checked: 1 error") != std::string::npos);
  // explicit files of two folders: no E209 across them
  o.paths = {dir.path() + "/a/main.mpf", dir.path() + "/b/main.mpf"};
  r = lint(o);
  CHECK(r.rc == 0);
  CHECK(r.out.find("2 files checked: 0 errors") != std::string::npos);
  std::vector<diag::InputError> errors;
  auto groups = driver::groupProgramSets({dir.path() + "/a", dir.path() + "/b/main.mpf", dir.path() + "/none"}, errors);
  REQUIRE(groups.size() == 3); // a, a/sub, b
  CHECK(groups[0] == std::vector<std::string>{dir.path() + "/a"});
  CHECK(groups[1] == std::vector<std::string>{dir.path() + "/a/sub"});
  CHECK(groups[2] == std::vector<std::string>{dir.path() + "/b/main.mpf"});
  REQUIRE(errors.size() == 1);
  CHECK(errors[0].message == "no such file or directory");
}
