// support/Text's escapeMarkup (HTML report, SVG plot) and support/CaseFold.
#include <doctest/doctest.h>

#include <string>

#include "support/CaseFold.h"
#include "support/Text.h"

using iso::support::escapeMarkup;

TEST_CASE("escapeMarkup turns the five specials into entities") {
  CHECK(escapeMarkup("a<b>&\"c'") == "a&lt;b&gt;&amp;&quot;c&#39;");
  CHECK(escapeMarkup("plain text, 1.5 s") == "plain text, 1.5 s");
  CHECK(escapeMarkup("") == "");
}

TEST_CASE("escapeMarkup keeps valid UTF-8, TAB and LF and replaces what would break a document") {
  CHECK(escapeMarkup("caf\xc3\xa9\t\n") == "caf\xc3\xa9\t\n");
  CHECK(escapeMarkup(std::string("a\x01\x1b\x7f"
                                 "b",
                                 5)) == "a???b");
  CHECK(escapeMarkup(std::string("\0z", 2)) == "?z");
  // a stray continuation byte, an overlong form, a surrogate, a truncated sequence: one '?' a byte
  CHECK(escapeMarkup("\x80") == "?");
  CHECK(escapeMarkup("\xc0\x80") == "??");
  CHECK(escapeMarkup("\xed\xa0\x80") == "???");
  CHECK(escapeMarkup("x\xe2\x82") == "x??");
  CHECK(escapeMarkup("\xf0\x9f\x98\x80") == "\xf0\x9f\x98\x80");
}

TEST_CASE("CaseFold compares ASCII letters without case and nothing else") {
  using namespace iso::support;
  static_assert(iequals("G01", "g01"));
  static_assert(!iequals("G01", "G1"));
  static_assert(istartsWith("Content-Length: 5", "content-length"));
  static_assert(!istartsWith("Con", "content"));
  static_assert(iendsWith("trace.JSON", ".json"));
  static_assert(!iendsWith("json", ".json"));
  CHECK(!iequals("\xc3\xa9", "\xc3\x89")); // é and É: not ASCII, compared as bytes
  CHECK(upperCopy("pallet_1.spf") == "PALLET_1.SPF");
  CHECK(lowerCopy("XY-Plane") == "xy-plane");
  CHECK(upperAscii('{') == '{');
  CHECK(lowerAscii('@') == '@');
}
