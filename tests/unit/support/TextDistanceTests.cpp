//! @file TextDistanceTests.cpp
//! @brief The edit distance and the "did you mean" choice of support/Text, and the nesting
//!        pre-scan of TOML text (support/TomlDepth).
#include <doctest/doctest.h>

#include <string>

#include "support/Text.h"
#include "support/TomlDepth.h"

using iso::support::closestMatch;
using iso::support::editDistance;
using iso::support::tomlNestingBeyond;

TEST_CASE("text: edit distance counts insertions, deletions, substitutions and swaps") {
  CHECK(editDistance("", "") == 0);
  CHECK(editDistance("abc", "") == 3);
  CHECK(editDistance("machine", "machine") == 0);
  CHECK(editDistance("machnie", "machine") == 1); // two neighbours swapped
  CHECK(editDistance("max-tme", "max-time") == 1);
  CHECK(editDistance("kitten", "sitting") == 3);
  CHECK(editDistance("W402", "w402") == 0);   // ASCII case is ignored
  CHECK(editDistance("abcdef", "x", 2) == 3); // beyond the limit: limit + 1
  CHECK(editDistance(std::string(100000, 'a'), "a", 2) == 3);
}

TEST_CASE("text: closestMatch suggests only a near and unambiguous candidate") {
  const std::vector<std::string_view> options = {"--max-time", "--max-steps", "--summary", "--format", "-o"};
  CHECK(closestMatch("--max-tme", options) == "--max-time");
  CHECK(closestMatch("--sumary", options) == "--summary");
  CHECK(closestMatch("--formt", options) == "--format");
  CHECK(closestMatch("--colour", options).empty()); // nothing near
  CHECK(closestMatch("-x", options) == "-o");       // one edit in a short word
  CHECK(closestMatch("-xy", options).empty());      // two edits in a word of 3
  const std::vector<std::string_view> codes = {"W401", "W402", "unreachable"};
  CHECK(closestMatch("W40", codes).empty()); // as near to W401 as to W402: no guess
  CHECK(closestMatch("unreachabel", codes) == "unreachable");
  CHECK(closestMatch("W999", codes).empty());
}

namespace {
std::string dotted(size_t parts) {
  std::string key = "a";
  for (size_t i = 1; i < parts; ++i)
    key += ".a";
  return key;
}
} // namespace

TEST_CASE("toml depth: dotted keys, headers, arrays and inline tables count as JSON would") {
  constexpr size_t none = std::string_view::npos;
  CHECK(tomlNestingBeyond("a = 1\nb.c = [1, [2]]\n[t]\nx = {y = 1}\n") == none);
  // a key of 64 parts is 64 levels (the document and 63 tables), one of 65 is too deep
  CHECK(tomlNestingBeyond(dotted(64) + " = 1\n") == none);
  const std::string deep = dotted(65) + " = 1\n";
  CHECK(tomlNestingBeyond(deep) == deep.rfind('.'));
  CHECK(tomlNestingBeyond(dotted(50001) + " = 1\n") == 127); // stops at the 64th dot
  CHECK(tomlNestingBeyond("[" + dotted(63) + "]\nx = 1\n") == none);
  CHECK(tomlNestingBeyond("[" + dotted(64) + "]\n") != none);
  CHECK(tomlNestingBeyond("[[" + dotted(63) + "]]\n") != none); // the array of tables is one more
  CHECK(tomlNestingBeyond("x = " + std::string(63, '[') + std::string(63, ']') + "\n") == none);
  CHECK(tomlNestingBeyond("x = " + std::string(64, '[') + "\n") == 4 + 63);
  std::string inl = "x = ";
  for (int i = 0; i < 70; ++i)
    inl += "{a = ";
  CHECK(tomlNestingBeyond(inl) != none);
  // levels add up: a header, a dotted key, an array and an inline table with a dotted key
  CHECK(tomlNestingBeyond("[" + dotted(30) + "]\n" + dotted(30) + " = [{b.c = 1}]\n") == none);
  CHECK(tomlNestingBeyond("[" + dotted(30) + "]\n" + dotted(31) + " = [{b.c.d = 1}]\n") != none);
  // an inline table's key ends at its comma: sibling keys do not add up
  std::string wide = "x = {";
  for (int i = 0; i < 100; ++i)
    wide += "k" + std::to_string(i) + ".a.b = 1, ";
  CHECK(tomlNestingBeyond(wide + "z = 1}\n") == none);
  // comments and strings do not count, nor do closers with nothing open
  CHECK(tomlNestingBeyond("# " + std::string(100, '[') + "\nx = \"" + std::string(100, '{') + "\"\n") == none);
  CHECK(tomlNestingBeyond("x = '''\n" + std::string(100, '[') + "'''\n]]]}}}\ny = 1\n") == none);
  CHECK(tomlNestingBeyond("\"" + dotted(100) + "\" = 1\n") == none); // one quoted key part
  CHECK(tomlNestingBeyond("x = \"unterminated " + std::string(100, '[')) == none);
}
