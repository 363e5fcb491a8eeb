//! @file SettingsTests.cpp
//! @brief isotools.toml: discovery, keys, errors, rules per path, exclusions; used by isolint.
#include <doctest/doctest.h>

#include <filesystem>
#include <sstream>

#include "TestUtil.h"
#include "driver/Lint.h"
#include "driver/Settings.h"

using namespace iso;
using driver::globMatch;

TEST_CASE("settings: glob patterns") {
  CHECK(globMatch("*.mpf", "a.mpf"));
  CHECK_FALSE(globMatch("*.mpf", "sub/a.mpf")); // * stays in one folder name
  CHECK(globMatch("**/*.mpf", "sub/deep/a.mpf"));
  CHECK(globMatch("**/*.mpf", "a.mpf"));
  CHECK(globMatch("legacy/**", "legacy/x/y.spf"));
  CHECK_FALSE(globMatch("legacy/**", "new/legacy.spf"));
  CHECK(globMatch("p?.mpf", "p1.mpf"));
  CHECK_FALSE(globMatch("p?.mpf", "p/.mpf"));
  CHECK(globMatch("a*b*c", "axxbyyc"));
  CHECK_FALSE(globMatch("a*b*c", "axxbyy"));
}

TEST_CASE("settings: keys are read, relative machine paths start at the file") {
  test::TempDir dir;
  std::string f = dir.write("isotools.toml", "machine = \"m/mill.json\"\ndialect = \"z32\"\nmax-diagnostics = 7\n"
                                             "disable = [\"W402\", \"unreachable\"]\nenable = [\"W402\"]\n"
                                             "exclude = [\"old/**\"]\n[[overrides]]\npaths = [\"legacy/**\"]\n"
                                             "disable = [\"E301\"]\n");
  driver::Settings s;
  std::string error;
  REQUIRE_MESSAGE(driver::loadSettings(f, s, error), error);
  CHECK(s.machine == (std::filesystem::path(s.dir) / "m/mill.json").string());
  CHECK(s.dialect == "z32");
  CHECK(s.maxDiagnostics == 7);
  CHECK(s.disabledFor(dir.path() + "/p.mpf", diag::Code::Unreachable));
  CHECK_FALSE(s.disabledFor(dir.path() + "/p.mpf", diag::Code::FeedUnset)); // enabled again
  CHECK(s.disabledFor(dir.path() + "/legacy/a/p.mpf", diag::Code::RIndex));
  CHECK_FALSE(s.disabledFor(dir.path() + "/p.mpf", diag::Code::RIndex));
  CHECK(s.excludes(dir.path() + "/old/x.mpf"));
  CHECK_FALSE(s.excludes(dir.path() + "/x.mpf"));
  std::filesystem::create_directories(dir.path() + "/a/b");
  CHECK(driver::findSettings(dir.path() + "/a/b") == f);
  CHECK(driver::findSettings(dir.path() + "/a/b/p.mpf") == f);
}

TEST_CASE("settings: errors name the file, the line and the key") {
  test::TempDir dir;
  driver::Settings s;
  std::string error;
  CHECK_FALSE(driver::loadSettings(dir.write("a.toml", "dialect = \"sidac\"\nmachnie = \"m.json\"\n"), s, error));
  CHECK(error.find("a.toml:2: error: unknown key 'machnie'") != std::string::npos);
  CHECK_FALSE(driver::loadSettings(dir.write("b.toml", "disable = \"W402\"\n"), s, error));
  CHECK(error.find("b.toml:1: error: 'disable' must be an array of strings") != std::string::npos);
  CHECK_FALSE(driver::loadSettings(dir.write("c.toml", "disable = [\"W999\"]\n"), s, error));
  CHECK(error.find("unknown diagnostic 'W999'") != std::string::npos);
  CHECK_FALSE(driver::loadSettings(dir.write("d.toml", "[[overrides]]\npaths = [\"x\"]\nfoo = 1\n"), s, error));
  CHECK(error.find("unknown key 'overrides.foo'") != std::string::npos);
  CHECK_FALSE(driver::loadSettings(dir.write("e.toml", "dialect = \"fanuc\"\n"), s, error));
  CHECK(error.find("'dialect' must be") != std::string::npos);
  CHECK_FALSE(driver::loadSettings(dir.write("f.toml", "max-diagnostics = -1\n"), s, error));
  CHECK_FALSE(driver::loadSettings(dir.write("g.toml", "this is = not toml [\n"), s, error));
  CHECK(error.find("g.toml:1:") != std::string::npos);
}

TEST_CASE("settings: isolint finds isotools.toml above its inputs and applies it") {
  test::TempDir dir;
  std::filesystem::create_directories(dir.path() + "/progs/old");
  dir.write("isotools.toml", "disable = [\"W402\"]\nexclude = [\"progs/old/**\"]\nmax-diagnostics = 1\n");
  dir.write("progs/p.mpf", "G01 X1\nG01 X2\nG00 G01 X3\nG00 G01 X4\nM30\n");
  dir.write("progs/old/q.mpf", "R0 = 1\nM30\n");
  std::ostringstream out, err;
  driver::Io io{out, err};
  driver::LintOptions o;
  o.common.color = "never";
  o.paths = {dir.path() + "/progs"};
  int rc = driver::runLint(o, io);
  INFO(out.str(), err.str());
  CHECK(rc == 0);
  CHECK(out.str().find("W402") == std::string::npos);                 // disabled by the settings
  CHECK(out.str().find("q.mpf") == std::string::npos);                // excluded
  CHECK(out.str().find("1 more diagnostic in") != std::string::npos); // max-diagnostics = 1 (two W401)
  CHECK(out.str().find("1 file checked: 0 errors, 2 warnings") != std::string::npos);
  // --config names another file; an invalid one is exit 2
  o.common.config = dir.write("bad.toml", "colour = \"red\"\n");
  std::ostringstream out2, err2;
  driver::Io io2{out2, err2};
  CHECK(driver::runLint(o, io2) == 2);
  CHECK(err2.str().find("bad.toml:1: error: unknown key 'colour'") != std::string::npos);
}

#include "driver/Compile.h"

TEST_CASE("settings: isocc takes the machine and the disabled warnings from isotools.toml") {
  test::TempDir dir;
  dir.write("isotools.toml", "machine = \"m.json\"\ndisable = [\"W402\", \"E301\"]\n");
  dir.write("m.json", "{\"axes\": [{\"name\": \"X\", \"max_velocity\": 100, \"max_accel\": 1000, "
                      "\"limit_minus\": -10, \"limit_plus\": 10}]}\n");
  dir.write("p.mpf", "G01 X5\nM30\n");
  driver::CompileOptions o;
  o.common.color = "never";
  o.paths = {dir.path() + "/p.mpf"};
  o.output = dir.path() + "/p.isob";
  std::ostringstream out, err;
  driver::Io io{out, err};
  CHECK(driver::runCompile(o, io) == 0);
  CHECK(err.str().find("W402") == std::string::npos); // disabled by the settings
  // the machine of the settings: axis Y does not exist there
  dir.write("p.mpf", "G01 Y5 F10\nR0 = 1\nM30\n");
  std::ostringstream out2, err2;
  driver::Io io2{out2, err2};
  CHECK(driver::runCompile(o, io2) == 1);
  CHECK(err2.str().find("E302") != std::string::npos);
  CHECK(err2.str().find("E301") != std::string::npos); // an error cannot be disabled for compiling
}
