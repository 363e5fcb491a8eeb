//! @file NameTests.cpp
//! @brief Names from images reach text escaped (image::printableName): the disassembler, the
//!        simulator's messages and its JSON trace.
#include <sstream>
#include <string>

#include <doctest/doctest.h>

#include "ImageTestUtil.h"
#include "TestUtil.h"
#include "image/Disassembler.h"
#include "sim/Run.h"
#include "sim/SimTestUtil.h"
#include "sim/TraceWriter.h"

using namespace iso;
using namespace iso::test;
using image::printableName;

namespace {

/// No control byte but newline, and every byte >= 0x80 part of valid UTF-8 (printableName
/// leaves valid UTF-8 unchanged, so this is its own fixed point).
bool isCleanText(const std::string& s) {
  for (char c : s)
    if (c == '\x1B' || c == '\x7F' || (static_cast<unsigned char>(c) < 0x20 && c != '\n' && c != '\t')) return false;
  std::string noNl = s;
  for (char& c : noNl)
    if (c == '\n' || c == '\t') c = ' ';
  return printableName(noNl) == noNl;
}

/// main program "ev\x1B[2Jil\xFF" from file "a\x1B]0;x\x07\xC3.mpf": R1 = 1 / 0.
image::Image hostileImage() {
  Builder b;
  b.img.constants = {2.5};
  Asm a;
  a.stmt().push(1).push(0).op(image::Op::Div).storeR(1).stmt().op(image::Op::End);
  b.proc(image::UnitKind::Main, std::string("ev\x1B[2Jil\xFF"), std::string("a\x1B]0;x\x07\xC3.mpf"), a);
  return b.img;
}

} // namespace

TEST_CASE("image: printableName escapes control bytes and invalid UTF-8, keeps valid UTF-8") {
  CHECK(printableName("m.mpf") == "m.mpf");
  CHECK(printableName("pi\xC3\xA8"
                      "ce_\xE2\x82\xAC.mpf") == "pi\xC3\xA8"
                                                "ce_\xE2\x82\xAC.mpf"); // è, €
  CHECK(printableName("\xF0\x9F\x94\xA7") == "\xF0\x9F\x94\xA7");       // 4 bytes
  CHECK(printableName("a\x1B[31mb") == "a\\x1B[31mb");
  CHECK(printableName(std::string("n\0l\x7F", 4)) == "n\\x00l\\x7F");
  CHECK(printableName("x\xFFy") == "x\\xFFy");
  CHECK(printableName("\xC3") == "\\xC3");                   // truncated sequence
  CHECK(printableName("\xC0\xAF") == "\\xC0\\xAF");          // overlong
  CHECK(printableName("\xED\xA0\x80") == "\\xED\\xA0\\x80"); // surrogate
  CHECK(printableName("\xC3\xA8\xFF") == "\xC3\xA8\\xFF");   // valid sequence kept next to a bad byte
  CHECK(printableName("a\"b\\c") == "a\"b\\c");
  CHECK(printableName("a\"b\\c", true) == "a\\\"b\\\\c");
}

TEST_CASE("image: the disassembler prints names from the image escaped") {
  const image::Image img = hostileImage();
  REQUIRE(check(img).verified);
  const std::string text = image::disassemble(img);
  CHECK(isCleanText(text));
  CHECK(text.find("a\\x1B]0;x\\x07\\xC3.mpf:1") != std::string::npos);
  CHECK(text.find("ev\\x1B[2Jil\\xFF") != std::string::npos);
}

TEST_CASE("sim: names from the image are escaped in messages and in the JSON trace") {
  const image::Image img = hostileImage();
  std::ostringstream json;
  sim::SimResult res;
  {
    sim::JsonTraceWriter w(json);
    res = test::runImage(img, builtin(), {}, &w);
  }
  REQUIRE(res.summary.status == sim::Status::Error);
  CHECK(res.summary.message.rfind("a\\x1B]0;x\\x07\\xC3.mpf:1: runtime error at t=0 s: division by zero", 0) == 0);
  CHECK(isCleanText(json.str()));
  CHECK(json.str().find("a\\\\x1B]0;x\\\\x07\\\\xC3.mpf") != std::string::npos); // the JSON form of "\x1B"
  sim::SimOptions o;
  o.entry = "nothing";
  auto unknown = test::runImage(img, builtin(), o, nullptr);
  CHECK(unknown.setupMessage.find("\"ev\\x1B[2Jil\\xFF\"") != std::string::npos);
  // valid UTF-8 names stay as they are
  Builder b;
  Asm a;
  a.stmt().push(1).push(0).op(image::Op::Div).storeR(1).stmt().op(image::Op::End);
  b.proc(image::UnitKind::Main,
         "pi\xC3\xA8"
         "ce",
         "pi\xC3\xA8"
         "ce.mpf",
         a);
  auto utf8 = test::runImage(b.img, builtin(), {}, nullptr);
  CHECK(utf8.summary.message.rfind("pi\xC3\xA8"
                                   "ce.mpf:1:",
                                   0) == 0);
}
