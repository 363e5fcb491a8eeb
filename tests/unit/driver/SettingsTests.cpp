//! @file SettingsTests.cpp
//! @brief isotools.toml: discovery, keys, errors, rules per path, exclusions; used by isolint.
#include <doctest/doctest.h>

#include <filesystem>
#include <sstream>
#include <tuple>
#include <utility>

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

namespace {
std::string dottedKey(size_t parts) {
  std::string key = "a";
  for (size_t i = 1; i < parts; ++i)
    key += ".a";
  return key;
}

/// isolint over `input` with the settings it finds (or --config `config`): exit code, stderr.
std::pair<int, std::string> lintWith(const std::string& input, const std::string& config = "") {
  std::ostringstream out, err;
  driver::Io io{out, err};
  driver::LintOptions o;
  o.common.color = "never";
  o.common.config = config;
  o.paths = {input};
  const int rc = driver::runLint(o, io);
  return {rc, err.str()};
}
} // namespace

TEST_CASE("settings: nesting deeper than 64 levels is an error before the TOML parser sees it") {
  test::TempDir dir;
  driver::Settings s;
  std::string error;
  // 50,001 parts (100 KB): the TOML parser's recursion would overflow the stack
  CHECK_FALSE(driver::loadSettings(dir.write("a.toml", "x = 1\n" + dottedKey(50001) + " = 1\n"), s, error));
  CHECK(error == dir.path() + "/a.toml:2:128: error: tables, arrays or dotted keys nested deeper than 64 levels");
  CHECK_FALSE(driver::loadSettings(dir.write("b.toml", "exclude = " + std::string(100000, '[') + "\n"), s, error));
  CHECK(error.find("b.toml:1:74: error: tables, arrays or dotted keys nested deeper than 64 levels") !=
        std::string::npos);
  std::string inl = "x = ";
  for (int i = 0; i < 20000; ++i)
    inl += "{a = ";
  CHECK_FALSE(driver::loadSettings(dir.write("c.toml", inl + "\n"), s, error));
  CHECK(error.find("nested deeper than 64 levels") != std::string::npos);
  CHECK_FALSE(driver::loadSettings(dir.write("d.toml", "[" + dottedKey(20000) + "]\n"), s, error));
  CHECK(error.find("d.toml:1:") != std::string::npos);
  CHECK(error.find("nested deeper than 64 levels") != std::string::npos);
  // within the limit the file is read as usual (and its unknown key reported)
  CHECK_FALSE(driver::loadSettings(dir.write("e.toml", dottedKey(60) + " = 1\n"), s, error));
  CHECK(error.find("unknown key 'a'") != std::string::npos);
}

TEST_CASE("settings: a deep isotools.toml found above the inputs is exit 2, not a crash") {
  test::TempDir dir;
  std::filesystem::create_directories(dir.path() + "/progs");
  dir.write("isotools.toml", dottedKey(50001) + " = 1\n");
  const std::string p = dir.write("progs/p.mpf", "M30\n");
  const auto [rc, err] = lintWith(p);
  CHECK(rc == 2);
  CHECK(err.find("isotools.toml:1:128: error: tables, arrays or dotted keys nested deeper than 64 levels") !=
        std::string::npos);
}

TEST_CASE("settings: a file that cannot be opened, is too large or is not text") {
  test::TempDir dir;
  const std::string p = dir.write("p.mpf", "M30\n");
  auto [rc, err] = lintWith(p, dir.path() + "/nope.toml");
  CHECK(rc == 2);
  CHECK(err == dir.path() + "/nope.toml: error: cannot open the settings file: no such file or directory\n");
  std::tie(rc, err) = lintWith(p, "/dev/zero"); // read only up to the cap
  CHECK(rc == 2);
  CHECK(err == "/dev/zero: error: the settings file is larger than 16 MiB\n");
  driver::Settings s;
  std::string error;
  CHECK_FALSE(driver::loadSettings(dir.write("big.toml", std::string(driver::kMaxSettingsBytes + 1, '#')), s, error));
  CHECK(error.find("larger than 16 MiB") != std::string::npos);
  CHECK(driver::loadSettings(dir.write("cap.toml", std::string(driver::kMaxSettingsBytes, '#')), s, error));
  CHECK_FALSE(driver::loadSettings(dir.write("nul.toml", std::string("dialect = \"z32\"\n# a\0b\n", 22)), s, error));
  CHECK(error == dir.path() + "/nul.toml: error: not a text file: a NUL byte at offset 19");
  CHECK_FALSE(driver::loadSettings(dir.write("bin.toml", "# caf\xe9\n"), s, error));
  CHECK(error == dir.path() + "/bin.toml: error: not a text file: byte 0xe9 at offset 5 is not UTF-8");
  CHECK(driver::loadSettings(dir.write("utf8.toml", "# caf\xc3\xa9\ndialect = \"z32\"\n"), s, error));
}

TEST_CASE("settings: unknown keys and rule names say what was meant") {
  test::TempDir dir;
  driver::Settings s;
  std::string error;
  CHECK_FALSE(driver::loadSettings(dir.write("a.toml", "machnie = \"m.json\"\n"), s, error));
  CHECK(error.find("a.toml:1: error: unknown key 'machnie'; did you mean 'machine'? (known:") != std::string::npos);
  CHECK_FALSE(driver::loadSettings(dir.write("b.toml", "colour = 1\n"), s, error));
  CHECK(error.find("did you mean") == std::string::npos);
  CHECK_FALSE(driver::loadSettings(dir.write("c.toml", "disable = [\"unreachabel\"]\n"), s, error));
  CHECK(error.find("'disable': unknown diagnostic 'unreachabel'; did you mean 'unreachable'?") != std::string::npos);
  CHECK_FALSE(driver::loadSettings(dir.write("d.toml", "enable = [\"W40\"]\n"), s, error));
  CHECK(error.find("unknown diagnostic 'W40' (") != std::string::npos); // W401 or W402: no guess
  CHECK_FALSE(driver::loadSettings(dir.write("e.toml", "[[overrides]]\npaths = [\"x\"]\ndisabel = []\n"), s, error));
  CHECK(error.find("unknown key 'overrides.disabel'; did you mean 'disable'?") != std::string::npos);
  CHECK(driver::suggestCode("feed-unst") == "feed-unset");
  CHECK(driver::suggestCode("unreachble") == "unreachable");
  CHECK(driver::suggestCode("no-such-rule-at-all").empty());
}
