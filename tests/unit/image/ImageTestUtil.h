//! @file ImageTestUtil.h
//! @brief Hand-built images for the image tests: a tiny assembler with labels, a builder for
//!        valid images, and helpers that push an image through writer, reader and verifier.
#pragma once

#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "image/Image.h"
#include "image/ImageReader.h"
#include "image/ImageVerifier.h"
#include "image/ImageWriter.h"
#include "image/Opcode.h"

namespace iso::test {

using image::Op;

/// Assembles one procedure. Labels are resolved when the procedure is placed in an image.
class Asm {
public:
  Asm& op(Op o) {
    b.push_back(static_cast<uint8_t>(o));
    return *this;
  }
  Asm& byte(uint8_t v) {
    b.push_back(v);
    return *this;
  }
  Asm& uleb(uint64_t v) {
    image::writeUleb(b, v);
    return *this;
  }
  Asm& sleb(int64_t v) {
    image::writeSleb(b, v);
    return *this;
  }
  Asm& u32(uint32_t v) {
    image::writeU32(b, v);
    return *this;
  }
  /// A u32 code address of `name` (absolute, resolved at placement).
  Asm& ref(const std::string& name) {
    refs.emplace_back(b.size(), name);
    return u32(0);
  }
  Asm& label(const std::string& name) {
    labels[name] = static_cast<uint32_t>(b.size());
    return *this;
  }
  // shorthands
  Asm& stmt() { return op(Op::Stmt); }
  Asm& push(int64_t v) { return op(Op::PushD0).sleb(v); }
  Asm& pushConst(uint64_t i) { return op(Op::PushConst).uleb(i); }
  Asm& storeR(uint64_t r) { return op(Op::StoreR).uleb(r); }
  Asm& loadR(uint64_t r) { return op(Op::LoadR).uleb(r); }
  Asm& jump(Op o, const std::string& l) { return op(o).ref(l); }
  Asm& call(uint64_t p) { return op(Op::Call).uleb(p); }
  Asm& move(std::vector<uint8_t> d) {
    op(Op::Move).byte(static_cast<uint8_t>(d.size()));
    b.insert(b.end(), d.begin(), d.end());
    return *this;
  }
  uint32_t here() const { return static_cast<uint32_t>(b.size()); }

  std::vector<uint8_t> b;
  std::vector<std::pair<size_t, std::string>> refs;
  std::map<std::string, uint32_t> labels;
};

/// Builds an image procedure by procedure. Strings are interned; the line table gets one
/// entry per stmt/stmt.skip offset listed with `line`.
class Builder {
public:
  Builder() { img.axes = {'X', 'Y', 'Z'}; }

  uint32_t str(const std::string& s) {
    for (size_t i = 0; i < img.strings.size(); ++i)
      if (img.strings[i] == s) return static_cast<uint32_t>(i);
    img.strings.push_back(s);
    return static_cast<uint32_t>(img.strings.size() - 1);
  }

  /// Appends a procedure; returns its index. Label references resolve to absolute offsets;
  /// a label "@N" is the raw absolute offset N. With `lines`, each stmt/stmt.skip gets a line
  /// entry (lines 1, 2, ... of `file`).
  uint32_t proc(image::UnitKind kind, const std::string& name, const std::string& file, const Asm& a,
                bool lines = true) {
    image::Proc p;
    p.kind = kind;
    p.name = str(name);
    p.file = str(file);
    p.entry = static_cast<uint32_t>(img.code.size());
    p.size = static_cast<uint32_t>(a.b.size());
    std::vector<uint8_t> code = a.b;
    for (const auto& [at, l] : a.refs) {
      uint32_t target;
      if (!l.empty() && l[0] == '@')
        target = static_cast<uint32_t>(std::stoul(l.substr(1)));
      else {
        auto it = a.labels.find(l);
        if (it == a.labels.end()) throw std::logic_error("undefined label " + l);
        target = p.entry + it->second;
      }
      image::patchU32(code, at, target);
    }
    img.code.insert(img.code.end(), code.begin(), code.end());
    uint32_t line = 1;
    for (uint32_t off = p.entry; lines && off < p.entry + p.size;) {
      image::Instr in;
      if (!image::decode(img.code.data(), p.entry + p.size, off, in)) break;
      if (in.op == Op::Stmt || in.op == Op::StmtSkip) img.lines.push_back({off, p.file, line++, false, 0});
      off += in.length;
    }
    img.procs.push_back(p);
    auto idx = static_cast<uint32_t>(img.procs.size() - 1);
    if (kind != image::UnitKind::Sub) img.entries.push_back({kind, p.name, idx});
    return idx;
  }

  image::Image img;
};

/// The result of pushing an image through writer, reader and verifier.
struct Checked {
  bool read = false;     ///< the reader accepted the bytes
  bool verified = false; ///< and the verifier too
  image::ImageError err; ///< the rejection
};

inline Checked check(const std::vector<uint8_t>& bytes) {
  Checked c;
  image::Image img;
  image::Layout lay;
  c.read = image::readImage(bytes, img, c.err, &lay);
  if (c.read) c.verified = image::verifyImage(img, c.err, &lay);
  return c;
}

inline Checked check(const image::Image& img) { return check(image::writeImage(img)); }

/// A small valid image using most instructions: a main program, a subprogram, a
/// semi-automatic program, a WHEN with condition and body, a CASE, jumps, moves.
inline image::Image sampleImage() {
  Builder b;
  b.img.constants = {12.5, 3, -0.25};
  Asm m;
  m.stmt()
      .push(5)
      .storeR(1) // 0: R1 = 5
      .stmt()
      .op(Op::G90)
      .op(Op::G1)
      .push(100)
      .op(Op::SetF) // F100
      .label("loop")
      .stmt()
      .op(Op::Sync)
      .loadR(1)
      .pushConst(0)
      .op(Op::Add)
      .op(Op::LoadRInd)
      .storeR(2)
      .stmt()
      .op(Op::G0)
      .loadR(2)
      .push(-50)
      .move({0x00, 0x11}) // G0 X=R2 Posa[Y]=-50
      .stmt()
      .op(Op::When)
      .ref("cond")
      .ref("body")
      .jump(Op::Jump, "after")
      .label("cond")
      .op(Op::LoadAxVar)
      .byte(3)
      .byte(0)
      .push(10)
      .op(Op::CmpGt)
      .op(Op::CondEnd)
      .label("body")
      .stmt()
      .push(12)
      .push(1)
      .op(Op::StoreIo)
      .byte(6)
      .op(Op::BodyEnd)
      .label("after")
      .stmt()
      .op(Op::G1)
      .push(200)
      .push(15)
      .move({0x00, 0x20}) // X200 Fa[X]=15
      .stmt()
      .loadR(1)
      .pushConst(1)
      .op(Op::CmpLt)
      .push(3)
      .op(Op::LoadIo)
      .byte(5)
      .push(1)
      .op(Op::CmpEq)
      .op(Op::And)
      .jump(Op::JumpFalse, "else")
      .stmt()
      .call(1)
      .stmt()
      .jump(Op::Jump, "endif")
      .label("else")
      .stmt()
      .op(Op::M)
      .uleb(23)
      .op(Op::MNb)
      .uleb(34)
      .label("endif")
      .stmt()
      .loadR(1)
      .op(Op::Case)
      .uleb(2)
      .uleb(0)
      .ref("c1")
      .uleb(1)
      .ref("c2")
      .u32(image::kNoTarget)
      .stmt()
      .op(Op::G2)
      .push(10)
      .push(0)
      .op(Op::PushD1)
      .sleb(-25)
      .push(0)
      .move({0x00, 0x01, 0x30, 0x40}) // G2 X10 Y0 I-2.5 J
      .label("c1")
      .stmt()
      .op(Op::PushD2)
      .sleb(125)
      .op(Op::Dwell)
      .label("c2")
      .op(Op::StmtSkip)
      .ref("last")
      .push(7)
      .op(Op::ZWord)
      .byte(0)
      .label("last")
      .stmt()
      .loadR(1)
      .push(10)
      .op(Op::CmpLt)
      .jump(Op::JumpTrue, "loop")
      .stmt()
      .op(Op::M0)
      .op(Op::End);
  b.proc(image::UnitKind::Main, "main", "main.mpf", m);
  Asm s;
  s.stmt().op(Op::G91).push(1).op(Op::Neg).move({0x02}).stmt().op(Op::Ret);
  b.proc(image::UnitKind::Sub, "Sub", "sub.spf", s);
  Asm semi;
  semi.stmt().op(Op::M0).stmt().op(Op::EndImplicit);
  b.proc(image::UnitKind::Semi, "semi", "semi.mpf", semi);
  b.img.entries.back().name = b.str("Semi program");
  b.img.lines[1].hasN = true; // N numbers: the integer and the double form
  b.img.lines[1].n = 10;
  b.img.lines[2].hasN = true;
  b.img.lines[2].n = 20.5;
  return b.img;
}

} // namespace iso::test
