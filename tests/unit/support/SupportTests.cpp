//! @file SupportTests.cpp
//! @brief support/: text escaping for terminals and JSON, atomic files, file identity.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include <sys/stat.h>

#include "TestUtil.h"
#include "support/File.h"
#include "support/Memory.h"
#include "support/Text.h"

using namespace iso;

namespace {
size_t temporariesIn(const std::string& dir) {
  size_t n = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    if (e.path().filename().string().find(".tmp-") != std::string::npos) ++n;
  return n;
}
} // namespace

TEST_CASE("support: UTF-8 validation") {
  CHECK(support::isValidUtf8("G01 X10 ; caff\xC3\xA8"));
  CHECK(support::isValidUtf8("\xF0\x9F\x98\x80"));
  CHECK_FALSE(support::isValidUtf8("caff\xE8"));         // Latin-1
  CHECK_FALSE(support::isValidUtf8("\xC0\xAF"));         // overlong
  CHECK_FALSE(support::isValidUtf8("\xED\xA0\x80"));     // surrogate
  CHECK_FALSE(support::isValidUtf8("\xE2\x80"));         // truncated
  CHECK_FALSE(support::isValidUtf8("\x80"));             // stray continuation
  CHECK_FALSE(support::isValidUtf8("\xF4\x90\x80\x80")); // above U+10FFFF
}

TEST_CASE("support: escapeForTerminal escapes control bytes, bad UTF-8, C1 and bidi controls") {
  CHECK(support::escapeForTerminal("\x1b[31mred") == "\\x1b[31mred");
  CHECK(support::escapeForTerminal(std::string("a\0b", 3)) == "a\\x00b");
  CHECK(support::escapeForTerminal("a\tb\x7f") == "a\tb\\x7f");
  CHECK(support::escapeForTerminal("caff\xE8") == "caff\\xe8");
  CHECK(support::escapeForTerminal("caff\xC3\xA8") == "caff\xC3\xA8"); // printable UTF-8 stays
  CHECK(support::escapeForTerminal("\xC2\x9B") == "\\xc2\\x9b");       // C1 CSI
  CHECK(support::escapeForTerminal("a\xE2\x80\xAE"
                                   "b") == "a\\xe2\\x80\\xaeb"); // RIGHT-TO-LEFT OVERRIDE
  CHECK(support::escapeForTerminal("\r\n") == "\\x0d\\x0a");
}

TEST_CASE("support: toValidUtf8 keeps valid text and spells out the rest") {
  CHECK(support::toValidUtf8("caff\xC3\xA8") == "caff\xC3\xA8");
  CHECK(support::toValidUtf8("caff\xE8.mpf") == "caff\\xe8.mpf");
  CHECK(support::toValidUtf8("\x1b") == "\x1b"); // valid UTF-8: JSON escapes it itself
  CHECK(support::isValidUtf8(support::toValidUtf8("\xFF\xFE\xC3")));
}

TEST_CASE("support: an AtomicFile replaces its target only at commit") {
  test::TempDir dir;
  const std::string target = dir.path() + "/out.csv";
  { std::ofstream(target) << "old"; }
  ::chmod(target.c_str(), 0640);
  {
    support::AtomicFile f(target);
    REQUIRE(f.open());
    f.stream() << "new content";
    CHECK(test::readFileBytes(target) == "old");
    CHECK(temporariesIn(dir.path()) == 1);
    REQUIRE(f.commit());
  }
  CHECK(test::readFileBytes(target) == "new content");
  CHECK(temporariesIn(dir.path()) == 0);
  struct stat st {};
  REQUIRE(::stat(target.c_str(), &st) == 0);
  CHECK((st.st_mode & 0777) == 0640); // the target's permissions are kept
}

TEST_CASE("support: an AtomicFile not committed leaves the target untouched and no temporary") {
  test::TempDir dir;
  const std::string target = dir.path() + "/out.svg";
  { std::ofstream(target) << "old"; }
  {
    support::AtomicFile f(target);
    REQUIRE(f.open());
    f.stream() << "half";
  }
  CHECK(test::readFileBytes(target) == "old");
  CHECK(temporariesIn(dir.path()) == 0);
  // removeRegisteredTemporaries (the signal handler's part) removes live temporaries
  support::AtomicFile g(target);
  REQUIRE(g.open());
  CHECK(temporariesIn(dir.path()) == 1);
  CHECK(support::removeRegisteredTemporaries() == 1);
  CHECK(temporariesIn(dir.path()) == 0);
}

TEST_CASE("support: AtomicFile errors: a missing folder, a folder as target") {
  test::TempDir dir;
  support::AtomicFile f(dir.path() + "/no/such/out.csv");
  const support::Status missing = f.open();
  CHECK_FALSE(missing);
  CHECK(missing.why().find("no such file or directory") != std::string::npos);
  support::AtomicFile g(dir.path());
  const support::Status folder = g.open();
  CHECK_FALSE(folder);
  CHECK(folder.why() == "is a directory");
}

TEST_CASE("support: adviseHugePages is a hint: any range, and the bytes stay as written") {
  std::vector<unsigned char> big(9u << 20);
  for (size_t i = 0; i < big.size(); ++i)
    big[i] = static_cast<unsigned char>(i * 7);
  support::adviseHugePages(big.data() + 1, big.size() - 1); // unaligned: the aligned part
  support::adviseHugePages(big.data(), 100);                // too small: nothing
  support::adviseHugePages(big.data(), 0);
  bool same = true;
  for (size_t i = 0; i < big.size(); ++i)
    same = same && big[i] == static_cast<unsigned char>(i * 7);
  CHECK(same);
}

TEST_CASE("support: readFilePrefix reads whole files and prefixes exactly, and says which") {
  test::TempDir dir;
  const std::string p = dir.path() + "/big.mpf";
  std::string data;
  for (int i = 0; data.size() < 300000; ++i)
    data += "N" + std::to_string(i) + " G1 X" + std::to_string(i % 997) + "\n";
  { std::ofstream(p, std::ios::binary) << data; }
  bool whole = false;
  auto all = support::readFilePrefix(p, SIZE_MAX, whole);
  REQUIRE(all);
  CHECK(*all == data);
  CHECK(whole);
  auto head = support::readFilePrefix(p, 1000, whole);
  REQUIRE(head);
  CHECK(*head == data.substr(0, 1000));
  CHECK_FALSE(whole);
  auto exact = support::readFilePrefix(p, data.size(), whole); // as long as the file: its end not seen
  REQUIRE(exact);
  CHECK(*exact == data);
  CHECK_FALSE(whole);
  auto more = support::readFilePrefix(p, data.size() + 1, whole);
  REQUIRE(more);
  CHECK(*more == data);
  CHECK(whole);
  const std::string empty = dir.path() + "/empty.mpf";
  { std::ofstream(empty, std::ios::binary); }
  auto none = support::readFilePrefix(empty, 100, whole);
  REQUIRE(none);
  CHECK(none->empty());
  CHECK(whole);
}

TEST_CASE("support: readFile and fileId") {
  test::TempDir dir;
  const std::string p = dir.path() + "/a.mpf";
  { std::ofstream(p, std::ios::binary) << std::string("G0\0X1\n", 6); }
  const auto text = support::readFile(p);
  REQUIRE(text);
  CHECK(*text == std::string("G0\0X1\n", 6));
  const auto missing = support::readFile(dir.path() + "/b.mpf");
  REQUIRE_FALSE(missing);
  CHECK(missing.error().where == dir.path() + "/b.mpf");
  CHECK(missing.error().message == "no such file or directory");
  const auto folder = support::readFile(dir.path());
  REQUIRE_FALSE(folder);
  CHECK(folder.error().message == "is a directory");
  auto a = support::fileId(p);
  auto b = support::fileId(dir.path() + "/./a.mpf");
  REQUIRE(a);
  CHECK(a == b);
  std::filesystem::create_symlink(p, dir.path() + "/link.csv");
  CHECK(support::fileId(dir.path() + "/link.csv") == a);
  CHECK_FALSE(support::fileId(dir.path() + "/none"));
}

TEST_CASE("support: an AtomicFile onto a device writes in place and never replaces it") {
  support::AtomicFile f("/dev/null");
  REQUIRE(f.open());
  f.stream() << "discarded";
  REQUIRE(f.commit());
  struct stat st {};
  REQUIRE(::stat("/dev/null", &st) == 0);
  CHECK(S_ISCHR(st.st_mode));
}

TEST_CASE("support: a Status is success by default and carries the reason of a failure") {
  const support::Status done;
  CHECK(done.ok());
  CHECK(done.why().empty());
  const support::Status failed = support::Status::failure("write error");
  CHECK_FALSE(failed);
  CHECK(failed.why() == "write error");
  CHECK(failed.error().where.empty());
  const support::Status placed(support::Error{"out.csv", ""}); // a failure even without a message
  CHECK_FALSE(placed.ok());
  CHECK(placed.error().where == "out.csv");
}
