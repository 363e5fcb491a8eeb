//! @file Z32FlowTests.cpp
//! @brief The instructions of dialect z32's program flow and parameters (go.range, kg,
//!        axis.ctl, origin, PAR/PAL/user parameters, nm, zword TA/TB): they round trip through
//!        both formats (format 2 recalls their statements), the disassembler names their
//!        operands, and the verifier rejects each bad operand.
#include <functional>
#include <string>
#include <vector>

#include <doctest/doctest.h>

#include "BadImages.h"
#include "image/CodeFormat2.h"
#include "image/Disassembler.h"

using namespace iso;
using namespace iso::test;

namespace {

/// A z32 main program using every new instruction, a subprogram "S" (procedure 1) that the
/// main program continues in with kg, and the user parameter name "HA" (string 0).
image::Image flowImage() {
  Builder b;
  b.img.flags = image::Image::kFlagZ32;
  b.img.constants = {2.5};
  b.str("HA");
  Asm m;
  m.stmt().op(Op::GoRange).ref("from").ref("to"); // GON1-N2
  m.stmt().op(Op::Jump).ref("after");
  m.label("from").stmt().push(3).push(7).op(Op::StorePar);                                // PAR[3]=7
  m.label("to").stmt().push(4).op(Op::LoadPar).op(Op::StoreUser).uleb(0);                 // HA=PAR[4]
  m.label("after").stmt().push(1).op(Op::LoadUser).uleb(0).op(Op::StorePal).op(Op::Sync); // PAL[1]=HA
  m.stmt().push(1).op(Op::LoadPal).op(Op::StoreR).uleb(1);                                // R1=PAL[1]
  m.stmt().op(Op::Nm).uleb(84).op(Op::Origin).uleb(1).op(Op::AxisCtl).uleb(image::axisCtlOperand(0b011, false));
  m.stmt().op(Op::AxisCtl).uleb(image::axisCtlOperand(0, true));
  m.stmt().push(5).op(Op::ZWord).byte(static_cast<uint8_t>(image::ZAddr::TA));
  m.stmt().push(6).op(Op::ZWord).byte(static_cast<uint8_t>(image::ZAddr::TB));
  m.stmt().op(Op::Kg).uleb(1);
  b.proc(image::UnitKind::Main, "m", "m.mpf", m);
  b.proc(image::UnitKind::Sub, "S", "s.spf", Asm().stmt().op(Op::Ret));
  return b.img;
}

/// The operand text of the first instruction `op` in the disassembly of `img`.
std::string operandsOf(const image::Image& img, Op op) {
  const image::Proc& p = img.procs[0];
  for (uint32_t off = p.entry; off < p.entry + p.size;) {
    image::Instr in;
    REQUIRE(image::decode(img.code.data(), p.entry + p.size, off, in));
    if (in.op == op) return image::formatOperands(img, in);
    off += in.length;
  }
  return "(none)";
}

/// The verifier's message for `img`, "" when it is accepted.
std::string verdict(const image::Image& img) {
  image::ImageError err;
  return image::verifyImage(img, err) ? std::string() : err.message;
}

/// A z32 main program with `body` as its second statement, and the subprogram S.
image::Image z32With(const std::function<void(Asm&)>& body, bool z32 = true) {
  Builder b;
  b.img.flags = z32 ? image::Image::kFlagZ32 : 0;
  b.img.constants = {2.5};
  b.str("HA");
  b.str("H1");
  Asm m;
  m.stmt();
  body(m);
  m.label("last").stmt().op(Op::End);
  b.proc(image::UnitKind::Main, "m", "m.mpf", m);
  b.proc(image::UnitKind::Sub, "S", "s.spf", Asm().stmt().op(Op::Ret));
  return b.img;
}

} // namespace

TEST_CASE("image: the z32 flow instructions verify and round trip in both formats") {
  const image::Image img = flowImage();
  REQUIRE(verdict(img) == "");
  for (uint16_t version : {uint16_t{1}, uint16_t{2}}) {
    CAPTURE(version);
    image::Image v = img;
    v.formatVersion = version;
    const std::vector<uint8_t> bytes = image::writeImage(v);
    image::Image back;
    image::ImageError err;
    image::Layout lay;
    REQUIRE_MESSAGE(image::readImage(bytes, back, err, &lay), err.message);
    CHECK(back.code == img.code);
    CHECK(back.lines.size() == img.lines.size());
    CHECK(back.formatVersion == version);
    CHECK(image::writeImage(back) == bytes);
    CHECK_MESSAGE(image::verifyImage(back, err, &lay), err.message);
  }
}

TEST_CASE("image: format 2 recalls statements with go.range, kg and the z32 operands") {
  Asm a;
  for (int i = 0; i < 30; ++i) {
    const std::string n = std::to_string(i);
    a.label("s" + n).stmt().op(Op::GoRange).ref("s" + n).ref("e" + n);
    a.label("e" + n).stmt().op(Op::Origin).uleb(static_cast<uint64_t>(i % 99)).op(Op::Nm).uleb(i % 2 ? 84 : 110);
    a.stmt().op(Op::AxisCtl).uleb(image::axisCtlOperand(static_cast<uint32_t>(i % 8), i % 2 == 0));
    a.stmt().push(i).op(Op::LoadUser).uleb(0).op(Op::StorePal).push(i).op(Op::StoreUser).uleb(0);
  }
  a.stmt().op(Op::Kg).uleb(1);
  const uint32_t size = a.here();
  Builder b;
  b.img.flags = image::Image::kFlagZ32;
  b.str("HA");
  b.proc(image::UnitKind::Main, "m", "m.mpf", a);
  b.proc(image::UnitKind::Sub, "S", "s.spf", Asm().stmt().op(Op::Ret));
  const std::vector<uint32_t> bounds = image::codeBoundaries(b.img.procs);
  const std::vector<uint8_t> enc = image::encodeCode2(b.img.code, bounds);
  std::vector<uint8_t> back;
  const auto bad = image::decodeCode2(enc.data(), enc.size(), bounds, back);
  REQUIRE_MESSAGE(!bad, (bad ? bad->message : std::string()));
  CHECK(back == b.img.code);
  CHECK(enc.size() < size / 2); // the repeated statements are recalled
  CHECK_MESSAGE(verdict(b.img) == "", verdict(b.img));
}

TEST_CASE("image: the disassembler names the z32 flow operands") {
  image::Image img = flowImage();
  img.axes = {'A', 'B', 'Z'};
  CHECK(operandsOf(img, Op::Nm) == "G84");
  CHECK(operandsOf(img, Op::Origin) == "1");
  CHECK(operandsOf(img, Op::AxisCtl) == "G29 A B");
  CHECK(operandsOf(img, Op::LoadUser) == "HA");
  CHECK(operandsOf(img, Op::StoreUser) == "HA");
  CHECK(operandsOf(img, Op::LoadPar) == "PAR[index]");
  CHECK(operandsOf(img, Op::StorePal) == "PAL[index]");
  CHECK(operandsOf(img, Op::Kg) == "S (procedure 1)");
  CHECK(operandsOf(img, Op::ZWord) == "TA");
  const std::string range = operandsOf(img, Op::GoRange);
  REQUIRE(range.size() == 12); // L0001..L000F
  CHECK(range.substr(5, 2) == "..");
  const std::string listing = image::disassemble(img);
  CHECK(listing.find("axis.ctl    G28 (every axis)") != std::string::npos);
  CHECK(listing.find("go.range    " + range) != std::string::npos);
  CHECK(listing.find(range.substr(0, 5) + ":") != std::string::npos); // both ends are labelled
  CHECK(listing.find(range.substr(7) + ":") != std::string::npos);
  CHECK(listing.find("nm          G84") != std::string::npos);
}

TEST_CASE("image: the verifier checks the operands of the z32 flow instructions") {
  struct Case {
    const char* name;
    std::function<void(Asm&)> body;
    const char* expect; ///< "" = accepted
  };
  const std::vector<Case> cases = {
      {"range", [](Asm& a) { a.op(Op::GoRange).ref("r").ref("last").label("r").stmt(); }, ""},
      {"range end before start", [](Asm& a) { a.label("r").stmt().op(Op::GoRange).ref("last").ref("r"); },
       "is before its start"},
      {"range start not a statement",
       [](Asm& a) { a.op(Op::GoRange).ref("p").ref("last").stmt().label("p").push(1).op(Op::StoreR).uleb(1); },
       "is a push.d0 instruction, not stmt or stmt.skip"},
      {"range end outside", [](Asm& a) { a.op(Op::GoRange).ref("last").ref("@9999"); }, "range end 0x270F is outside"},
      {"range with a value on the stack", [](Asm& a) { a.push(1).op(Op::GoRange).ref("last").ref("last"); },
       "needs an empty stack"},
      {"kg", [](Asm& a) { a.op(Op::Kg).uleb(1); }, ""},
      {"kg to the main program", [](Asm& a) { a.op(Op::Kg).uleb(0); }, "continues in procedure 0 (m), a main program"},
      {"kg out of range", [](Asm& a) { a.op(Op::Kg).uleb(2); }, "procedure 2 out of range (2 procedures)"},
      {"axis mask", [](Asm& a) { a.op(Op::AxisCtl).uleb(image::axisCtlOperand(0b111, true)); }, ""},
      {"axis mask beyond the axes", [](Asm& a) { a.op(Op::AxisCtl).uleb(image::axisCtlOperand(0b1000, false)); },
       "axis mask 0x8 names an axis beyond the image's 3 axes"},
      {"origin 99", [](Asm& a) { a.op(Op::Origin).uleb(99); }, ""},
      {"origin 100", [](Asm& a) { a.op(Op::Origin).uleb(100); }, "origin 100 outside 0..99"},
      {"nm G27", [](Asm& a) { a.op(Op::Nm).uleb(27); }, ""},
      {"nm G28", [](Asm& a) { a.op(Op::Nm).uleb(28); }, "G28 is not a code that isotools leaves unmodelled"},
      {"user name", [](Asm& a) { a.op(Op::LoadUser).uleb(0).op(Op::StoreUser).uleb(0); }, ""},
      {"user name string out of range", [](Asm& a) { a.op(Op::LoadUser).uleb(9).op(Op::StoreR).uleb(1); },
       "name string 9 out of range"},
      {"user name not letters", [](Asm& a) { a.push(1).op(Op::StoreUser).uleb(1); }, "string 1 is no parameter name"},
      {"par store with one value", [](Asm& a) { a.push(1).op(Op::StorePar); }, "stack underflow: pops 2 value(s)"},
      {"pal", [](Asm& a) { a.push(1).op(Op::LoadPal).push(2).op(Op::StorePal); }, ""},
      {"zword TB", [](Asm& a) { a.push(1).op(Op::ZWord).byte(6); }, ""},
      {"zword 7", [](Asm& a) { a.push(1).op(Op::ZWord).byte(7); }, "address code 7 out of range (0..6)"},
  };
  for (const Case& c : cases) {
    CAPTURE(c.name);
    const std::string got = verdict(z32With(c.body));
    if (std::string(c.expect).empty())
      CHECK_MESSAGE(got == "", got);
    else
      CHECK_MESSAGE(got.find(c.expect) != std::string::npos, got);
  }
  SUBCASE("each needs the z32 flag") {
    for (const auto& body : std::vector<std::function<void(Asm&)>>{
             [](Asm& a) { a.op(Op::GoRange).ref("last").ref("last"); }, [](Asm& a) { a.op(Op::Kg).uleb(1); },
             [](Asm& a) { a.op(Op::AxisCtl).uleb(1); }, [](Asm& a) { a.op(Op::Origin).uleb(1); },
             [](Asm& a) { a.op(Op::Nm).uleb(84); }, [](Asm& a) { a.op(Op::LoadUser).uleb(0).op(Op::StoreR).uleb(1); },
             [](Asm& a) { a.push(1).op(Op::LoadPar).op(Op::StoreR).uleb(1); },
             [](Asm& a) { a.push(1).push(1).op(Op::StorePal); }}) {
      const std::string got = verdict(z32With(body, false));
      CHECK_MESSAGE(got.find("without the z32 flag") != std::string::npos, got);
      CHECK(verdict(z32With(body, true)) == "");
    }
  }
}
