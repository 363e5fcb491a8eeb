//! @file JsonDepthTests.cpp
//! @brief support/JsonDepth: the nesting of JSON text, strings and escapes skipped.
#include <doctest/doctest.h>

#include <string>

#include "support/JsonDepth.h"

using iso::support::jsonNestingWithin;

namespace {
std::string nested(unsigned depth, char open = '[', char close = ']') {
  return std::string(depth, open) + std::string(depth, close);
}
} // namespace

TEST_CASE("json depth: scalars and empty text are depth 0") {
  CHECK(jsonNestingWithin("", 0));
  CHECK(jsonNestingWithin("42", 0));
  CHECK(jsonNestingWithin("\"[[[\"", 0));
  CHECK_FALSE(jsonNestingWithin("[]", 0));
  CHECK(jsonNestingWithin("[]", 1));
}

TEST_CASE("json depth: the limit itself is within, one more is not") {
  CHECK(jsonNestingWithin(nested(64)));
  CHECK_FALSE(jsonNestingWithin(nested(65)));
  CHECK(jsonNestingWithin(nested(3, '{', '}'), 3));
  CHECK_FALSE(jsonNestingWithin(nested(4, '{', '}'), 3));
  // arrays and objects count alike
  CHECK(jsonNestingWithin(R"({"a": [{"b": [1]}]})", 4));
  CHECK_FALSE(jsonNestingWithin(R"({"a": [{"b": [1]}]})", 3));
}

TEST_CASE("json depth: siblings do not add up") {
  std::string many;
  for (int i = 0; i < 1000; ++i)
    many += "[[]],";
  CHECK(jsonNestingWithin("[" + many + "1]", 3));
  CHECK_FALSE(jsonNestingWithin("[" + many + "1]", 2));
}

TEST_CASE("json depth: brackets inside strings do not count, escapes are skipped") {
  CHECK(jsonNestingWithin(R"(["[[[[{{{{", "]]]]"])", 1));
  // an escaped quote does not end the string; an escaped backslash does not escape the quote
  CHECK(jsonNestingWithin(R"(["a\"[[[[", 1])", 1));
  CHECK_FALSE(jsonNestingWithin(R"(["a\\", [[1]]])", 2));
  CHECK(jsonNestingWithin(R"(["a\\", [[1]]])", 3));
  CHECK(jsonNestingWithin(R"({"k\u005b": "\\\"[["})", 1));
}

TEST_CASE("json depth: malformed text is scanned without failing") {
  // stray closers do not go below 0 (and do not earn extra depth later)
  CHECK_FALSE(jsonNestingWithin("]]]]" + nested(5), 4));
  CHECK(jsonNestingWithin("]]]]" + nested(4), 4));
  // unterminated string: the rest is string
  CHECK(jsonNestingWithin("[\"" + nested(100), 1));
  // a trailing backslash
  CHECK(jsonNestingWithin("[\"\\", 1));
  // unclosed arrays count as they open
  CHECK_FALSE(jsonNestingWithin(std::string(300000, '['), 64));
  CHECK(jsonNestingWithin(std::string(64, '['), 64));
}
