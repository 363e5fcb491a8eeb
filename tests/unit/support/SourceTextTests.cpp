//! @file SourceTextTests.cpp
//! @brief support::SourceText and readSource: large regular files are mapped, the rest read;
//!        either way the bytes, and the NUL after them, are the file's.
#include <string>
#include <utility>

#include <doctest/doctest.h>

#include "TestUtil.h"
#include "support/File.h"
#include "support/SourceText.h"

#include <unistd.h>

using iso::support::readSource;
using iso::support::SourceText;

namespace {
/// `n` bytes of program text, lines of varying length.
std::string programBytes(size_t n) {
  std::string s;
  for (size_t i = 0; s.size() < n; ++i)
    s += "N" + std::to_string(i) + " G1 X" + std::to_string(i % 977) + ".5 F100\n";
  s.resize(n);
  return s;
}
} // namespace

TEST_CASE("source text: a large file is mapped, with the bytes readFile gives and a NUL after them") {
  iso::test::TempDir dir;
  const std::string text = programBytes(iso::support::kMapSourcesFrom + 12345);
  const std::string path = dir.write("big.mpf", text);
  auto read = readSource(path);
  REQUIRE(read);
  CHECK(read->isMapped());
  CHECK(read->size() == text.size());
  CHECK(*read == text);
  CHECK(read->data()[read->size()] == '\0');
  // a handler finds the file by any of its bytes, and only while it is mapped
  CHECK(std::string(iso::support::mappedSourceAt(read->data() + 17)) == path);
  CHECK(std::string(iso::support::mappedSourceAt(read->data() + read->size() - 1)) == path);
  CHECK(iso::support::mappedSourceAt(read->data() + read->size() + 4096 * 1024) == nullptr);
  const char* at = read->data();
  {
    SourceText moved = std::move(*read);
    CHECK(moved.isMapped());
    CHECK(moved.data() == at); // a move keeps the mapping: string views into it stay valid
    CHECK_FALSE(read->isMapped());
    CHECK(read->empty());
    SourceText copy = moved; // a copy holds its bytes
    CHECK_FALSE(copy.isMapped());
    CHECK(copy == text);
  }
  CHECK(iso::support::mappedSourceAt(at) == nullptr); // unmapped with its last owner
}

TEST_CASE("source text: a mapped file whose pages were dropped still reads as the file") {
  iso::test::TempDir dir;
  const std::string text = programBytes(iso::support::kMapSourcesFrom * 3 + 777);
  auto read = readSource(dir.write("big.mpf", text));
  REQUIRE(read);
  REQUIRE(read->isMapped());
  CHECK(*read == text); // every page touched
  read->dropPages();
  CHECK(read->isMapped());
  CHECK(*read == text); // read again from the file
  CHECK(read->data()[read->size()] == '\0');
  SourceText held(text);
  held.dropPages(); // held in memory: nothing happens
  CHECK(held == text);
}

TEST_CASE("source text: dropMappedPages drops the pages of a mapped source known by its view, nothing else") {
  iso::test::TempDir dir;
  const std::string text = programBytes(iso::support::kMapSourcesFrom * 2 + 99);
  auto read = readSource(dir.write("big.mpf", text));
  REQUIRE(read);
  REQUIRE(read->isMapped());
  CHECK(iso::support::isMappedSource(read->view()));
  CHECK_FALSE(iso::support::isMappedSource(read->view().substr(1)));               // not its whole view
  CHECK_FALSE(iso::support::isMappedSource(read->view().substr(0, 4096)));         // nor a part of it
  iso::support::dropMappedPages(read->view(), 100, read->size() - 100);            // (every whole page inside)
  iso::support::dropMappedPages(read->view(), read->size() - 5, read->size() + 9); // past its end: nothing
  CHECK(*read == text);                                                            // read again from the file
  std::string held = text;
  CHECK_FALSE(iso::support::isMappedSource(held));
  iso::support::dropMappedPages(held, 0, held.size()); // in memory: its bytes stay
  CHECK(held == text);
}

TEST_CASE("source text: small files, and files that fill their last page, are read") {
  iso::test::TempDir dir;
  const std::string small = programBytes(4000);
  auto s = readSource(dir.write("small.mpf", small));
  REQUIRE(s);
  CHECK_FALSE(s->isMapped());
  CHECK(*s == small);
  // a whole number of pages leaves no room for the NUL after the last byte
  const auto page = static_cast<size_t>(::sysconf(_SC_PAGESIZE));
  const std::string whole = programBytes(((iso::support::kMapSourcesFrom / page) + 3) * page);
  auto w = readSource(dir.write("pages.mpf", whole));
  REQUIRE(w);
  CHECK_FALSE(w->isMapped());
  CHECK(*w == whole);
  // a lower threshold maps the small file too
  auto m = readSource(dir.path() + "/small.mpf", 1);
  REQUIRE(m);
  CHECK(m->isMapped());
  CHECK(*m == small);
  CHECK(m->data()[m->size()] == '\0');
}

TEST_CASE("source text: what cannot be read is the error readFile gives") {
  iso::test::TempDir dir;
  auto missing = readSource(dir.path() + "/none.mpf");
  REQUIRE_FALSE(missing);
  CHECK(missing.error().message == iso::support::readFile(dir.path() + "/none.mpf").error().message);
  auto folder = readSource(dir.path());
  REQUIRE_FALSE(folder);
  CHECK(folder.error().message == "is a directory");
  auto empty = readSource(dir.write("empty.mpf", ""), 0);
  REQUIRE(empty);
  CHECK(empty->empty());
}
