//! @file OpClassTests.cpp
//! @brief The class column of Opcodes.def against the verifier: every opcode of each class,
//!        with valid operands, placed in a WHEN condition, a WHEN body and a procedure's own
//!        code, is accepted exactly where its class allows it.
#include <string>

#include <doctest/doctest.h>

#include "ImageTestUtil.h"

using namespace iso;
using namespace iso::test;
using image::OpClass;
using image::Shape;

namespace {

enum class Where : uint8_t { Cond, Body, Proc };

/// What the class column says (Opcodes.def, Classes): where each class may stand.
struct Allowed {
  OpClass cls;
  bool cond, body, proc;
};
constexpr Allowed kAllowed[] = {
    {OpClass::Expr, true, true, true},      {OpClass::Effect, false, true, true},
    {OpClass::Flow, false, true, true},     {OpClass::Control, false, false, true},
    {OpClass::CondEnd, true, false, false}, {OpClass::BodyEnd, false, true, false},
};
bool classAllows(OpClass c, Where w) {
  for (const Allowed& a : kAllowed)
    if (a.cls == c) return w == Where::Cond ? a.cond : w == Where::Body ? a.body : a.proc;
  FAIL("a class without a row in kAllowed");
  return false;
}

/// The values `op` takes from the stack in the instructions emit() writes.
int popsOf(Op op) {
  const int pops = image::opInfo(static_cast<uint8_t>(op)).pops;
  return pops < 0 ? 1 : pops; // a move with one descriptor, a case
}

/// `op` with operands the verifier accepts; a target is the label `next`, which the caller
/// places right after it (an m.special is followed by the call of its subprogram).
void emit(Asm& a, Op op) {
  a.op(op);
  switch (image::opInfo(static_cast<uint8_t>(op)).shape) {
  case Shape::None: break;
  case Shape::Uleb: // constant 0, R1, procedure 1, M1, origin 1, G84, the name HA (string 0)
    a.uleb(op == Op::PushConst || op == Op::LoadUser || op == Op::StoreUser ? 0 : op == Op::Nm ? 84 : 1);
    break;
  case Shape::Dec: a.sleb(1); break;
  case Shape::U8:
    a.byte(op == Op::LoadIo    ? static_cast<uint8_t>(image::SysVarId::AaIn)
           : op == Op::StoreIo ? static_cast<uint8_t>(image::SysVarId::AaOut)
                               : 0);
    break;
  case Shape::U8U8: a.byte(0).byte(0); break;
  case Shape::Addr: a.ref("next"); break;
  case Shape::Case: a.uleb(1).uleb(0).ref("next").u32(image::kNoTarget); break;
  case Shape::Move: a.byte(1).byte(0); break;
  case Shape::When: a.ref("c").ref("b"); break;
  case Shape::Range: a.ref("after").ref("after"); break; // a statement header
  }
  if (op == Op::MSpecial) a.call(1);
}

/// `op` behind the values it pops, then whatever leaves the stack empty again.
void emitBalanced(Asm& a, Op op) {
  for (int i = 0; i < popsOf(op); ++i)
    a.push(1);
  emit(a, op);
  a.label("next");
  if (image::opInfo(static_cast<uint8_t>(op)).pushes > 0) a.storeR(1);
}

/// A z32 main program with a WHEN and the subprogram 1; `op` stands in `w`.
image::Image placed(Op op, Where w) {
  Asm a;
  a.stmt().op(Op::When).ref("c").ref("b").jump(Op::Jump, "after");
  a.label("c");
  if (w == Where::Cond) {
    for (int i = 0; i < popsOf(op); ++i)
      a.push(1);
    emit(a, op);
    a.label("next");
  } else {
    a.loadR(1);
  }
  a.op(Op::CondEnd).label("b").stmt();
  if (w == Where::Body) emitBalanced(a, op);
  a.stmt().op(Op::BodyEnd).label("after").stmt();
  if (w == Where::Proc) emitBalanced(a, op);
  a.stmt().op(Op::End);
  Builder b;
  b.img.flags = image::Image::kFlagZ32;
  b.img.constants = {2.5};
  b.str("HA");
  b.proc(image::UnitKind::Main, "m", "m.mpf", a, false);
  b.proc(image::UnitKind::Sub, "S", "s.spf", Asm().stmt().op(Op::Ret), false);
  return b.img;
}

/// The verifier's verdict on `img` (the check that keeps the image where it is).
bool verifies(const image::Image& img, image::ImageError& err) { return image::verifyImage(img, err); }

const char* whereName(Where w) { return w == Where::Cond ? "condition" : w == Where::Body ? "body" : "procedure"; }

} // namespace

TEST_CASE("image: each opcode class is accepted exactly where the verifier allows it") {
  int expressions = 0;
  for (unsigned byte = 0; byte < 256; ++byte) {
    const image::OpInfo& info = image::opInfo(static_cast<uint8_t>(byte));
    if (!info.valid) continue;
    const auto op = static_cast<Op>(byte);
    expressions += info.cls == OpClass::Expr;
    for (Where w : {Where::Cond, Where::Body, Where::Proc}) {
      // rules beside the class: only subprograms return; a WHEN in a procedure needs regions
      if (w == Where::Proc && (op == Op::Ret || op == Op::When)) continue;
      const std::string mnemonic = info.mnemonic;
      CAPTURE(mnemonic);
      CAPTURE(whereName(w));
      image::ImageError err;
      const bool ok = verifies(placed(op, w), err);
      CAPTURE(err.message);
      CHECK(ok == classAllows(info.cls, w));
      if (!ok)
        CHECK(err.message.find(w == Where::Proc ? "procedure's own code" : "not allowed in a WHEN") !=
              std::string::npos);
    }
  }
  CHECK(expressions == 32);
}

TEST_CASE("image: every expression-class opcode computes a WHEN condition") {
  for (unsigned byte = 0; byte < 256; ++byte) {
    const image::OpInfo& info = image::opInfo(static_cast<uint8_t>(byte));
    if (!info.valid || info.cls != OpClass::Expr) continue;
    const std::string mnemonic = info.mnemonic;
    CAPTURE(mnemonic);
    REQUIRE(info.pushes == 1);
    // the condition: the values it pops, the expression, cond.end
    Asm a;
    a.stmt().op(Op::When).ref("c").ref("b").jump(Op::Jump, "after").label("c");
    for (int i = 0; i < info.pops; ++i)
      a.push(1);
    emit(a, static_cast<Op>(byte));
    a.op(Op::CondEnd).label("b").stmt().op(Op::BodyEnd).label("after").stmt().op(Op::End);
    Builder b;
    b.img.flags = image::Image::kFlagZ32; // PAR, PAL and user parameters are z32's
    b.img.constants = {2.5};
    b.str("HA");
    b.proc(image::UnitKind::Main, "m", "m.mpf", a, false);
    image::ImageError err;
    CHECK_MESSAGE(image::verifyImage(b.img, err), err.message);
  }
}

TEST_CASE("image: a non-expression opcode is refused in a WHEN condition, a control one in a body") {
  image::ImageError err;
  CHECK_FALSE(verifies(placed(Op::Jump, Where::Cond), err));
  CHECK(err.message.find("not allowed in a WHEN condition") != std::string::npos);
  CHECK_FALSE(verifies(placed(Op::StoreR, Where::Cond), err));
  CHECK(err.message.find("not allowed in a WHEN condition") != std::string::npos);
  CHECK_FALSE(verifies(placed(Op::Call, Where::Body), err));
  CHECK(err.message.find("not allowed in a WHEN body") != std::string::npos);
  CHECK(verifies(placed(Op::Move, Where::Body), err));
  CHECK(verifies(placed(Op::Aux, Where::Proc), err));
}
