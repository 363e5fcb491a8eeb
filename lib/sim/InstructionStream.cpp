//! @file InstructionStream.cpp
//! @brief Translating a verified image's code into the interpreter's instructions, a window at a
//!        time.
#include "sim/InstructionStream.h"

#include <algorithm>
#include <stdexcept>

#include "support/BitSet.h"
#include "support/Bytes.h"

namespace iso::sim {

using image::Op;

InstructionStream::InstructionStream(const image::VerifiedImage& img, uint32_t window, size_t slots)
    : img_(&img), window_(std::max<uint32_t>(window, 1)), maxSlots_(std::max<size_t>(slots, 1)) {
  const image::Image& im = img.image();
  procEntry.reserve(im.procs.size());
  for (size_t p = 0; p < im.procs.size(); ++p) // each procedure before p ends with its sentinel
    procEntry.push_back(static_cast<uint32_t>(img.boundaries().rank(im.procs[p].entry) + p));
  size_ = img.instructions() + im.procs.size();
}

InstructionStream::InstructionStream(std::vector<Ins> code, std::vector<uint32_t> entries)
    : procEntry(std::move(entries)), size_(code.size()), given_(std::move(code)) {}

uint32_t InstructionStream::procOf(uint32_t ins) const {
  auto it = std::upper_bound(procEntry.begin(), procEntry.end(), ins);
  return it == procEntry.begin() ? 0 : static_cast<uint32_t>(it - procEntry.begin() - 1);
}

bool InstructionStream::readsIw(uint32_t condIndex) const {
  for (uint32_t i = condIndex; i < size_; ++i) {
    const Ins in = (*this)[i];
    if (static_cast<uint8_t>(in.op) == kOpFallOff || in.op == Op::CondEnd) return false;
    if (in.op == Op::LoadAxVar && in.a8 == static_cast<uint8_t>(image::SysVarId::AaIw)) return true;
  }
  return false;
}

const CaseArm* InstructionStream::arms(uint32_t i) const {
  (void)(*this)[i]; // its window is the current one
  return cur_.arms;
}

const Ins& InstructionStream::load(uint32_t i) const {
  if (!given_.empty() || !img_) {
    cur_ = {0, static_cast<uint32_t>(given_.size()), given_.data(), nullptr};
    return given_[i];
  }
  const uint32_t base = i / window_ * window_;
  Window* slot = nullptr;
  for (Window& w : slots_)
    if (w.base == base) slot = &w;
  if (!slot) {
    if (slots_.size() < maxSlots_) {
      slot = &slots_.emplace_back();
    } else {
      slot = &*std::min_element(slots_.begin(), slots_.end(),
                                [](const Window& a, const Window& b) { return a.stamp < b.stamp; });
    }
    decode(base, *slot);
    slot->base = base;
  }
  slot->stamp = ++clock_;
  cur_ = {base, static_cast<uint32_t>(slot->ins.size()), slot->ins.data(), slot->arms.data()};
  return cur_.ins[i - base];
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

/// Decodes the instructions of one window: from instruction index `base` of procedure `p` at
/// code offset `off` on, crossing into the next procedures at their sentinels. Targets become
/// instruction indices: the rank of the target among the instruction boundaries plus the
/// procedure (each procedure before it ends with its fall-off sentinel).
class WindowDecoder {
public:
  WindowDecoder(const image::VerifiedImage& img, const std::vector<uint32_t>& procEntry, std::vector<Ins>& out,
                std::vector<CaseArm>& arms)
      : img_(img.image()), starts_(img.boundaries()), procEntry_(procEntry), out_(out), arms_(arms) {}

  void run(uint32_t base, uint32_t count) {
    out_.clear();
    arms_.clear();
    auto it = std::upper_bound(procEntry_.begin(), procEntry_.end(), base);
    p_ = static_cast<uint32_t>(it - procEntry_.begin() - 1);
    // instruction `base` has rank base - p among the boundaries, unless it is the sentinel
    const image::Proc& first = img_.procs[p_];
    uint32_t off = first.entry;
    if (base != procEntry_[p_])
      off = base - p_ < starts_.rank(size_t{first.entry} + first.size)
                ? static_cast<uint32_t>(starts_.select(base - p_))
                : first.entry + first.size;
    const auto firstLine = std::upper_bound(img_.lines.begin(), img_.lines.end(), off,
                                            [](uint32_t o, const image::LineEntry& l) { return o < l.offset; });
    nextLine_ = static_cast<size_t>(firstLine - img_.lines.begin());
    while (out_.size() < count) {
      const image::Proc& pr = img_.procs[p_];
      const uint32_t end = pr.entry + pr.size;
      if (off >= end) { // the procedure's sentinel
        Ins fall;
        fall.op = static_cast<Op>(kOpFallOff);
        out_.push_back(fall);
        if (++p_ == img_.procs.size()) break;
        off = img_.procs[p_].entry;
        continue;
      }
      off = one(off, end);
    }
  }

private:
  const image::Image& img_;
  const support::RankedBits& starts_;
  const std::vector<uint32_t>& procEntry_;
  std::vector<Ins>& out_;
  std::vector<CaseArm>& arms_;
  uint32_t p_ = 0;
  size_t nextLine_ = 0; ///< the line table is sorted by offset, like the code we walk

  uint32_t target(uint32_t addr) const { return static_cast<uint32_t>(starts_.rank(addr) + p_); }

  /// Translates the instruction at `off`, returns the offset after it: one switch on the
  /// operand shape, the operands read where the shape puts them (the verifier decoded every
  /// instruction: nothing can fail). A case is decoded in full (translateCase()).
  uint32_t one(uint32_t off, uint32_t end) {
    using image::Shape;
    const uint8_t* code = img_.code.data();
    const auto op = static_cast<Op>(code[off]);
    Ins& in = out_.emplace_back();
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
      in.a = target(support::loadU32(code + off + 1));
      c.skip(4);
      if (op == Op::StmtSkip) in.c = lineAt(off);
      break;
    case Shape::When:
    case Shape::Range: // go.range: a = start, b = end (the end line's statement header)
      in.a = target(support::loadU32(code + off + 1));
      in.b = target(support::loadU32(code + off + 5));
      c.skip(8);
      if (op == Op::When) in.c = lineAt(off);
      break;
    case Shape::Move:
      in.a = off + 2; // the descriptors stay in the image
      in.b = code[off + 1];
      c.skip(1 + size_t{code[off + 1]});
      break;
    case Shape::Case: return translateCase(in, off, end);
    }
    return static_cast<uint32_t>(c.pos());
  }

  uint32_t translateCase(Ins& in, uint32_t off, uint32_t end) {
    image::Instr d;
    if (const image::DecodeStatus st = image::decode(img_.code.data(), end, off, d); !st)
      throw std::logic_error("isosim: a verified image: " + st.message());
    in.a = static_cast<uint32_t>(arms_.size());
    in.b = static_cast<uint32_t>(d.arms.size());
    for (const auto& [ci, t] : d.arms)
      arms_.push_back({img_.constants[ci], target(t)});
    if (d.caseDefault != image::kNoTarget) in.c = target(d.caseDefault);
    return off + d.length;
  }

  /// The line of the statement at `offset`: the last line entry at or before it (offsets
  /// ascend, as the line table does).
  uint32_t lineAt(uint32_t offset) {
    while (nextLine_ < img_.lines.size() && img_.lines[nextLine_].offset <= offset)
      ++nextLine_;
    return nextLine_ > 0 ? static_cast<uint32_t>(nextLine_ - 1) : kNoIndex;
  }
};

} // namespace

void InstructionStream::decode(uint32_t base, Window& w) const {
  const auto n = static_cast<uint32_t>(std::min<size_t>(window_, size_ - base));
  w.ins.reserve(n);
  WindowDecoder(*img_, procEntry, w.ins, w.arms).run(base, n);
}

} // namespace iso::sim
