//! @file VerifierTests.cpp
//! @brief Every verifier rule, with an image that passes the reader (and its CRC) but breaks
//!        exactly that rule.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include <fmt/format.h>

#include <doctest/doctest.h>

#include "BadImages.h"
#include "image/Disassembler.h"

using namespace iso;
using namespace iso::test;

TEST_CASE("image: every verifier rule rejects its bad image") {
  for (const BadImage& b : badImages()) {
    std::string name = b.name;
    CAPTURE(name);
    image::Image img = b.make();
    Checked c = check(img);
    CHECK_MESSAGE(c.read, c.err.message); // the structure (and the CRC) is fine
    CHECK_FALSE(c.verified);
    std::string msg = c.err.message;
    CAPTURE(msg);
    CHECK(msg.find(b.expect) != std::string::npos);
    // the in-memory verifier (no layout from a reader) agrees
    image::ImageError direct;
    CHECK_FALSE(image::verifyImage(img, direct));
    CHECK(direct.message == c.err.message);
    CHECK(direct.offset == c.err.offset);
    // disassembler and hex dump cope with it
    CHECK_FALSE(image::disassemble(img).empty());
    CHECK_FALSE(image::hexDump(img).empty());
  }
}

TEST_CASE("image: bad image names are unique") {
  std::set<std::string> names;
  for (const BadImage& b : badImages())
    CHECK(names.insert(b.name).second);
}

TEST_CASE("image: verifier error offsets point at the broken bytes") {
  // jump at code 0x0001 of the only procedure: the offset is the code section + 1
  image::Image img = mainOnly(Asm().stmt().jump(Op::Jump, "@2").stmt().op(Op::End));
  image::Layout lay;
  auto bytes = image::writeImage(img, &lay);
  Checked c = check(bytes);
  CHECK(c.err.offset == lay.of(image::SectionId::Code) + 1);
  CHECK(bytes[c.err.offset] == static_cast<uint8_t>(Op::Jump));
  // a procedure record
  img = mainOnly(Asm().stmt().op(Op::End));
  img.procs[0].name = 9;
  bytes = image::writeImage(img, &lay);
  c = check(bytes);
  CHECK(c.err.offset == lay.procs[0]);
  // an axis letter
  img = mainOnly(Asm().stmt().op(Op::End));
  img.axes[2] = 'X';
  bytes = image::writeImage(img, &lay);
  c = check(bytes);
  CHECK(c.err.offset == lay.axes + 2);
  CHECK(bytes[c.err.offset] == 'X');
}

TEST_CASE("image: verifier rules the reader already enforces") {
  image::Image img = mainOnly(Asm().stmt().op(Op::End));
  image::ImageError err;
  img.flags = 4;
  CHECK_FALSE(image::verifyImage(img, err));
  CHECK(err.message == "unknown image flags 0x00000004");
  CHECK(err.offset == image::kOffFlags);
  img.flags = image::Image::kFlagStripped;
  CHECK_FALSE(image::verifyImage(img, err));
  CHECK(err.message == "a stripped image has line table entries");
  img.lines.clear();
  CHECK(image::verifyImage(img, err));
  // unsorted line table (not encodable: the writer refuses it)
  img = mainOnly(Asm().stmt().op(Op::M0).stmt().op(Op::End));
  std::swap(img.lines[0], img.lines[1]);
  CHECK_THROWS_AS(image::writeImage(img), std::invalid_argument);
  CHECK_FALSE(image::verifyImage(img, err));
  CHECK(err.message.find("must be sorted by strictly increasing code offset") != std::string::npos);
  // invalid kinds cannot come from the reader
  img = mainOnly(Asm().stmt().op(Op::End));
  img.procs[0].kind = static_cast<image::UnitKind>(3);
  CHECK_FALSE(image::verifyImage(img, err));
  // N values
  img = mainOnly(Asm().stmt().op(Op::End));
  img.lines[0].hasN = true;
  img.lines[0].n = -1;
  CHECK_FALSE(image::verifyImage(img, err));
  CHECK(err.message == "line entry 0: N-1 is not a non-negative number");
}

TEST_CASE("image: verifier accepts what it should") {
  image::ImageError err;
  // unreachable code is decoded and checked, but needs no stack discipline
  image::Image img = mainOnly(Asm().stmt().op(Op::End).op(Op::Add).op(Op::End));
  CHECK_MESSAGE(image::verifyImage(img, err), err.message);
  // a WHEN body with an IF (jumps inside the body)
  img = mainOnly(Asm()
                     .stmt()
                     .op(Op::When)
                     .ref("c")
                     .ref("b")
                     .jump(Op::Jump, "after")
                     .label("c")
                     .loadR(1)
                     .op(Op::CondEnd)
                     .label("b")
                     .stmt()
                     .loadR(2)
                     .jump(Op::JumpFalse, "fi")
                     .stmt()
                     .push(1)
                     .storeR(3)
                     .label("fi")
                     .stmt()
                     .op(Op::BodyEnd)
                     .label("after")
                     .stmt()
                     .op(Op::End));
  CHECK_MESSAGE(image::verifyImage(img, err), err.message);
  // two WHENs sharing one condition
  img = mainOnly(Asm()
                     .stmt()
                     .op(Op::When)
                     .ref("c")
                     .ref("b")
                     .op(Op::When)
                     .ref("c")
                     .ref("b")
                     .jump(Op::Jump, "after")
                     .label("c")
                     .loadR(1)
                     .op(Op::CondEnd)
                     .label("b")
                     .stmt()
                     .op(Op::BodyEnd)
                     .label("after")
                     .stmt()
                     .op(Op::End));
  CHECK_MESSAGE(image::verifyImage(img, err), err.message);
  // stack depth 256 exactly
  Asm a;
  a.stmt();
  for (int k = 0; k < 256; ++k)
    a.push(0);
  for (int k = 0; k < 255; ++k)
    a.op(Op::Add);
  a.storeR(1).op(Op::End);
  CHECK_MESSAGE(image::verifyImage(mainOnly(a), err), err.message);
  // R2880, every sysvar and move kind
  img = mainOnly(Asm()
                     .stmt()
                     .loadR(2880)
                     .storeR(2880)
                     .op(Op::LoadAxVar)
                     .byte(0)
                     .byte(2)
                     .op(Op::LoadAxVar)
                     .byte(4)
                     .byte(0)
                     .op(Op::Add)
                     .storeR(1)
                     .push(1)
                     .op(Op::LoadIo)
                     .byte(7)
                     .push(2)
                     .op(Op::StoreIo)
                     .byte(7)
                     .push(1)
                     .push(1)
                     .push(1)
                     .push(1)
                     .push(1)
                     .push(1)
                     .push(1)
                     .move({0x00, 0x11, 0x22, 0x02, 0x30, 0x40, 0x50})
                     .push(1)
                     .move({0x60})
                     .op(Op::End));
  CHECK_MESSAGE(image::verifyImage(img, err), err.message);
}

// Writes the golden fixtures tests/golden/images/bad-<name>.hex from the table when
// ISO_WRITE_BAD_IMAGES names a directory (a maintenance aid; the fixtures are checked in).
TEST_CASE("image: write bad image fixtures (ISO_WRITE_BAD_IMAGES)") {
  const char* dir = std::getenv("ISO_WRITE_BAD_IMAGES");
  if (!dir) return;
  for (const BadImage& b : badImages()) {
    image::Image img = b.make();
    image::ImageError err;
    REQUIRE_FALSE(image::verifyImage(img, err));
    std::string dump = image::hexDump(img);
    // mark the line holding the offset of the error
    std::string out =
        fmt::format("# bad-{}.hex: an image that breaks one verifier rule (isoimage(5), VERIFIER RULES):\n"
                    "#   {}\n"
                    "# The line marked <<< holds the offending field. The fixture converter recomputes the\n"
                    "# CRC (bytes 0x14..0x17), so the image passes the reader and fails in the verifier.\n",
                    b.name, b.rule);
    size_t pos = 0;
    bool marked = false;
    while (pos < dump.size()) {
      size_t eol = dump.find('\n', pos);
      std::string line = dump.substr(pos, eol - pos);
      pos = eol + 1;
      if (!marked && line.size() > 5 && line[4] == ':') {
        uint32_t off = static_cast<uint32_t>(std::stoul(line.substr(0, 4), nullptr, 16));
        std::istringstream data(line.substr(5, line.find('#') - 5));
        std::string tok;
        uint32_t nbytes = 0;
        while (data >> tok)
          ++nbytes;
        if (err.offset >= off && err.offset < off + nbytes) {
          line += "  <<<";
          marked = true;
        }
      }
      out += line + "\n";
    }
    std::ofstream(std::filesystem::path(dir) / fmt::format("bad-{}.hex", b.name)) << out;
  }
}

TEST_CASE("image: 50,000 WHENs verify (the region lookup is a sorted table - its time is measured, not asserted)") {
  // 50,000 WHENs, each with its condition and body: a linear search of the WHEN regions made
  // this take about 15 s; a sorted table of region roots takes a fraction of a second.
  Asm a;
  for (int i = 0; i < 50000; ++i) {
    const std::string n = std::to_string(i);
    a.stmt()
        .op(Op::When)
        .ref("c" + n)
        .ref("b" + n)
        .jump(Op::Jump, "a" + n)
        .label("c" + n)
        .push(1)
        .op(Op::CondEnd)
        .label("b" + n)
        .stmt()
        .op(Op::BodyEnd)
        .label("a" + n)
        .stmt()
        .push(i % 100)
        .move({0x00});
  }
  a.stmt().op(Op::End);
  image::Image img = mainOnly(a, false);
  const auto bytes = image::writeImage(img);
  Checked c = check(bytes); // its time and memory: measured, not asserted (see the closing notes)
  INFO(c.err.message);
  CHECK(c.verified);
  // a region still may not be entered from another one: body 1's code jumps into body 0
  Asm bad;
  bad.stmt()
      .op(Op::When)
      .ref("c")
      .ref("b0")
      .jump(Op::Jump, "w1")
      .label("c")
      .push(1)
      .op(Op::CondEnd)
      .label("b0")
      .stmt()
      .op(Op::BodyEnd)
      .label("w1")
      .stmt()
      .op(Op::When)
      .ref("c")
      .ref("b1")
      .jump(Op::Jump, "t")
      .label("b1")
      .stmt()
      .jump(Op::Jump, "b0")
      .label("t")
      .stmt()
      .push(1)
      .move({0x00})
      .stmt()
      .op(Op::End);
  Checked b = check(mainOnly(bad, false));
  CHECK_FALSE(b.verified);
  CHECK(b.err.message.find("reached from a WHEN body at") != std::string::npos);
}
