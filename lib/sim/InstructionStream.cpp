//! @file InstructionStream.cpp
//! @brief Translating a verified image's code into the interpreter's instruction array.
#include "sim/InstructionStream.h"

#include <algorithm>
#include <stdexcept>

#include "support/BitSet.h"
#include "support/Bytes.h"

namespace iso::sim {

using image::Op;

uint32_t InstructionStream::procOf(uint32_t ins) const {
  auto it = std::upper_bound(procEntry.begin(), procEntry.end(), ins);
  return it == procEntry.begin() ? 0 : static_cast<uint32_t>(it - procEntry.begin() - 1);
}

bool InstructionStream::readsIw(uint32_t condIndex) const {
  for (uint32_t i = condIndex; i < code.size(); ++i) {
    const Ins& in = code[i];
    if (static_cast<uint8_t>(in.op) == kOpFallOff || in.op == Op::CondEnd) return false;
    if (in.op == Op::LoadAxVar && in.a8 == static_cast<uint8_t>(image::SysVarId::AaIw)) return true;
  }
  return false;
}

namespace {

/// The uleb opcodes whose operand the interpreter reads from Ins::a as it is (an R index, a
/// procedure, a string, an origin, a G code, an axis mask).
bool uintOperandInA(Op op) {
  switch (op) {
  case Op::LoadR:
  case Op::StoreR:
  case Op::Call:
  case Op::Kg:
  case Op::AxisCtl:
  case Op::Origin:
  case Op::Nm:
  case Op::LoadUser:
  case Op::StoreUser: return true;
  default: return false;
  }
}

/// Builds the program: the operands of each instruction, then the targets, which are
/// instruction indices: the instruction at byte offset o of procedure p is the rank of o among
/// the instruction boundaries plus p (each procedure before p ends with its fall-off sentinel).
class Translator {
public:
  explicit Translator(const image::VerifiedImage& img)
      : img_(img.image()), instructions_(img.instructions()), starts_(img.boundaries()) {}

  InstructionStream run() {
    out_.code.reserve(instructions_ + img_.procs.size()); // and a fall-off sentinel each
    for (size_t p = 0; p < img_.procs.size(); ++p)
      proc(static_cast<uint32_t>(p));
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
  InstructionStream out_;
  const support::RankedBits& starts_; ///< instruction boundaries (byte offsets), from the verifier
  std::vector<Fix> fixes_;
  size_t nextLine_ = 0; ///< the line table is sorted by offset, like the code we walk

  /// Translates procedure p: one switch on the operand shape per instruction, the operands
  /// read where the shape puts them (the verifier decoded every instruction: nothing can fail).
  /// A case is decoded in full (translate()).
  void proc(uint32_t p) {
    using image::Shape;
    const image::Proc& pr = img_.procs[p];
    const uint8_t* code = img_.code.data();
    const uint32_t end = pr.entry + pr.size;
    out_.procEntry.push_back(static_cast<uint32_t>(out_.code.size()));
    image::Instr d;
    for (uint32_t off = pr.entry; off < end;) {
      const auto idx = static_cast<uint32_t>(out_.code.size());
      const auto op = static_cast<Op>(code[off]);
      Ins& in = out_.code.emplace_back();
      in.op = op;
      support::ByteCursor c(code, size_t{off} + 1, end);
      switch (image::opInfo(code[off]).shape) {
      case Shape::None:
        if (op == Op::Stmt) in.c = lineAt(off);
        break;
      case Shape::Dec: {
        int64_t m = 0;
        c.sleb(m, image::detail::kMaxOperandLeb);
        in.setValue(image::decValue(op, m));
        break;
      }
      case Shape::Uleb: {
        uint64_t u = 0;
        c.uleb(u, image::detail::kMaxOperandLeb);
        switch (op) {
        case Op::PushConst: in.setValue(img_.constants[u]); break;
        case Op::M:
        case Op::MNb:
        case Op::MSpecial: in.setValue(static_cast<double>(u)); break;
        default:
          if (!uintOperandInA(op)) throw std::logic_error("isosim: translation: a uleb opcode without a rule");
          in.a = static_cast<uint32_t>(u);
          break;
        }
        break;
      }
      case Shape::U8: // load.io, store.io, zword
        in.a8 = code[off + 1];
        c.skip(1);
        break;
      case Shape::U8U8: // load.axvar, aux
        in.a8 = code[off + 1];
        in.b8 = code[off + 2];
        c.skip(2);
        break;
      case Shape::Addr: // jumps, stmt.skip
        fixes_.push_back({idx, 0, 0, support::loadU32(code + off + 1)});
        c.skip(4);
        if (op == Op::StmtSkip) in.c = lineAt(off);
        break;
      case Shape::When:
      case Shape::Range: // go.range: a = start, b = end (the end line's statement header)
        fixes_.push_back({idx, 0, 0, support::loadU32(code + off + 1)});
        fixes_.push_back({idx, 1, 0, support::loadU32(code + off + 5)});
        c.skip(8);
        if (op == Op::When) in.c = lineAt(off);
        break;
      case Shape::Move:
        in.a = off + 2; // the descriptors stay in the image
        in.b = code[off + 1];
        c.skip(1 + size_t{code[off + 1]});
        break;
      case Shape::Case:
        if (const image::DecodeStatus st = image::decode(code, end, off, d); !st)
          throw std::logic_error("isosim: a verified image: " + st.message());
        in = translate(d, idx);
        c.skip(d.length - 1);
        break;
      }
      off = static_cast<uint32_t>(c.pos());
    }
    Ins fall;
    fall.op = static_cast<Op>(kOpFallOff);
    out_.code.push_back(fall);
  }

  /// The line of the statement at `offset`: the last line entry at or before it (offsets
  /// ascend, as the line table does).
  uint32_t lineAt(uint32_t offset) {
    while (nextLine_ < img_.lines.size() && img_.lines[nextLine_].offset <= offset)
      ++nextLine_;
    return nextLine_ > 0 ? static_cast<uint32_t>(nextLine_ - 1) : kNoIndex;
  }

  Ins translate(const image::Instr& d, uint32_t idx) {
    Ins in;
    in.op = d.op;
    switch (d.op) {
    case Op::PushConst: in.setValue(img_.constants[d.u]); break;
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
    case Op::GoRange:
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
      if (uintOperandInA(d.op)) in.a = static_cast<uint32_t>(d.u);
      break;
    }
    if (d.op == Op::Stmt || d.op == Op::StmtSkip || d.op == Op::When) in.c = lineAt(d.offset);
    return in;
  }
};

} // namespace

InstructionStream buildInstructionStream(const image::VerifiedImage& img) { return Translator(img).run(); }

} // namespace iso::sim
