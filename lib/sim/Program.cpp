//! @file Program.cpp
//! @brief Translating a verified image's code into the interpreter's instruction array.
#include "sim/Program.h"

#include <algorithm>
#include <stdexcept>

#include "support/BitSet.h"

namespace iso::sim {

using image::Op;

uint32_t Program::procOf(uint32_t ins) const {
  auto it = std::upper_bound(procEntry.begin(), procEntry.end(), ins);
  return it == procEntry.begin() ? 0 : static_cast<uint32_t>(it - procEntry.begin() - 1);
}

bool Program::readsIw(uint32_t condIndex) const {
  for (uint32_t i = condIndex; i < code.size(); ++i) {
    const Ins& in = code[i];
    if (static_cast<uint8_t>(in.op) == kOpFallOff || in.op == Op::CondEnd) return false;
    if (in.op == Op::LoadAxVar && in.a8 == static_cast<uint8_t>(image::SysVarId::AaIw)) return true;
  }
  return false;
}

namespace {

/// Builds the program: the operands of each instruction, then the targets, which are
/// instruction indices: the instruction at byte offset o of procedure p is the rank of o among
/// the instruction boundaries plus p (each procedure before p ends with its fall-off sentinel).
class Translator {
public:
  explicit Translator(const image::VerifiedImage& img)
      : img_(img.image()), instructions_(img.instructions()), starts_(img_.code.size()) {}

  Program run() {
    out_.code.reserve(instructions_ + img_.procs.size()); // and a fall-off sentinel each
    for (size_t p = 0; p < img_.procs.size(); ++p)
      proc(static_cast<uint32_t>(p));
    starts_.freeze();
    for (const Fix& f : fixes_) {
      const auto t = static_cast<uint32_t>(starts_.rank(f.addr) + out_.procOf(f.ins));
      Ins& in = out_.code[f.ins];
      switch (f.which) {
      case 0: in.a = t; break;
      case 1: in.b = t; break;
      case 2: in.c = t; break;
      default: out_.arms[f.arm].target = t; break;
      }
    }
    return std::move(out_);
  }

private:
  struct Fix {
    uint32_t ins;
    uint8_t which; // 0: a, 1: b, 2: c, 3: an arm
    uint32_t arm;
    uint32_t addr;
  };
  const image::Image& img_;
  const size_t instructions_;
  Program out_;
  support::RankedBits starts_; ///< instruction boundaries (byte offsets)
  std::vector<Fix> fixes_;
  size_t nextLine_ = 0; ///< the line table is sorted by offset, like the code we walk

  void proc(uint32_t p) {
    const image::Proc& pr = img_.procs[p];
    const uint32_t end = pr.entry + pr.size;
    out_.procEntry.push_back(static_cast<uint32_t>(out_.code.size()));
    image::Instr d;
    std::string why;
    for (uint32_t off = pr.entry; off < end; off += d.length) {
      if (!image::decode(img_.code.data(), end, off, d, why))
        throw std::logic_error("isosim: a verified image: " + why);
      starts_.set(off);
      out_.code.push_back(translate(d, static_cast<uint32_t>(out_.code.size())));
    }
    Ins fall;
    fall.op = static_cast<Op>(kOpFallOff);
    out_.code.push_back(fall);
  }

  Ins translate(const image::Instr& d, uint32_t idx) {
    Ins in;
    in.op = d.op;
    switch (d.op) {
    case Op::PushConst: in.setValue(img_.constants[d.u]); break;
    case Op::LoadR:
    case Op::StoreR:
    case Op::Call: in.a = static_cast<uint32_t>(d.u); break;
    case Op::LoadAxVar:
      in.a8 = static_cast<uint8_t>(d.u);
      in.b8 = d.u2;
      break;
    case Op::LoadIo:
    case Op::StoreIo:
    case Op::ZWord: in.a8 = static_cast<uint8_t>(d.u); break;
    case Op::Aux:
      in.a8 = static_cast<uint8_t>(d.u);
      in.b8 = d.u2;
      break;
    case Op::Jump:
    case Op::JumpFalse:
    case Op::JumpTrue:
    case Op::StmtSkip: fixes_.push_back({idx, 0, 0, d.addr}); break;
    case Op::When:
      fixes_.push_back({idx, 0, 0, d.addr});
      fixes_.push_back({idx, 1, 0, d.addr2});
      break;
    case Op::Case:
      in.a = static_cast<uint32_t>(out_.arms.size());
      in.b = static_cast<uint32_t>(d.arms.size());
      for (const auto& [ci, target] : d.arms) {
        fixes_.push_back({idx, 3, static_cast<uint32_t>(out_.arms.size()), target});
        out_.arms.push_back({img_.constants[ci], 0});
      }
      if (d.caseDefault != image::kNoTarget) fixes_.push_back({idx, 2, 0, d.caseDefault});
      break;
    case Op::Move:
      in.a = static_cast<uint32_t>(d.moves.data() - img_.code.data()); // the descriptors stay in the image
      in.b = static_cast<uint32_t>(d.moves.size());
      break;
    case Op::M:
    case Op::MNb:
    case Op::MSpecial: in.setValue(static_cast<double>(d.u)); break;
    default:
      if (image::isPushDec(d.op)) in.setValue(image::decValue(d.op, d.s));
      break;
    }
    if (d.op == Op::Stmt || d.op == Op::StmtSkip || d.op == Op::When) {
      // The statement's line: the last line entry at or before this offset.
      while (nextLine_ < img_.lines.size() && img_.lines[nextLine_].offset <= d.offset)
        ++nextLine_;
      if (nextLine_ > 0) in.c = static_cast<uint32_t>(nextLine_ - 1);
    }
    return in;
  }
};

} // namespace

Program buildProgram(const image::VerifiedImage& img) { return Translator(img).run(); }

} // namespace iso::sim
