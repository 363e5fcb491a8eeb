//! @file Program.cpp
//! @brief Decoding an image into the interpreter's instruction array, with bounds checks.
#include "sim/Program.h"

#include <algorithm>

#include <fmt/format.h>

#include "lang/Limits.h"

namespace iso::sim {

using image::Op;

namespace {

constexpr uint64_t kMaxR = lang::kMaxRIndex;

std::string where(uint32_t offset) { return fmt::format("code+0x{:04x}", offset); }

} // namespace

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

bool buildProgram(const image::Image& img, Program& out, std::string& why) {
  out = Program{};
  const size_t codeSize = img.code.size();
  out.code.reserve(codeSize / 2 + img.procs.size());
  std::vector<uint32_t> offsets; // byte offset of each instruction (ascending), while building
  offsets.reserve(out.code.capacity());
  struct Fix {
    uint32_t ins;
    uint8_t which; // 0: a, 1: b, 2: c, 3: an arm
    uint32_t arm;
    uint32_t addr;
  };
  std::vector<Fix> fixes;
  std::vector<std::pair<uint32_t, uint32_t>> procRange; // [entry, end) in bytes, by procedure
  uint32_t prevEnd = 0;
  size_t nextLine = 0; // the line table is sorted by offset, like the code we walk
  for (size_t p = 0; p < img.procs.size(); ++p) {
    const image::Proc& pr = img.procs[p];
    if (pr.name >= img.strings.size() || pr.file >= img.strings.size()) {
      why = fmt::format("procedure {}: string index out of range", p);
      return false;
    }
    if (pr.entry > codeSize || pr.size > codeSize - pr.entry || pr.size == 0 || pr.entry < prevEnd) {
      why = fmt::format("procedure '{}': code range out of bounds or out of order",
                        image::printableName(img.strings[pr.name]));
      return false;
    }
    const uint32_t end = pr.entry + pr.size;
    prevEnd = end;
    procRange.emplace_back(pr.entry, end);
    out.procEntry.push_back(static_cast<uint32_t>(out.code.size()));
    image::Instr d;
    std::string reason;
    for (uint32_t off = pr.entry; off < end;) {
      if (!image::decode(img.code.data(), end, off, d, reason)) {
        why = fmt::format("{}: {}", where(off), reason);
        return false;
      }
      const auto idx = static_cast<uint32_t>(out.code.size());
      Ins in;
      in.op = d.op;
      auto bad = [&](const std::string& what) {
        why = fmt::format("{}: {} {}", where(off), image::opInfo(static_cast<uint8_t>(d.op)).mnemonic, what);
        return false;
      };
      switch (d.op) {
      case Op::PushConst:
        if (d.u >= img.constants.size()) return bad("constant index out of range");
        in.a = static_cast<uint32_t>(out.values.size());
        out.values.push_back(img.constants[d.u]);
        break;
      case Op::LoadR:
      case Op::StoreR:
        if (d.u < 1 || d.u > kMaxR) return bad(fmt::format("R index {} outside {}..{}", d.u, lang::kMinRIndex, kMaxR));
        in.a = static_cast<uint32_t>(d.u);
        break;
      case Op::LoadAxVar:
        if (d.u > static_cast<uint64_t>(image::SysVarId::AaFw)) return bad("system variable is not an axis variable");
        if (d.u2 >= img.axes.size()) return bad("axis index out of range");
        in.a8 = static_cast<uint8_t>(d.u);
        in.b8 = d.u2;
        break;
      case Op::LoadIo:
      case Op::StoreIo: {
        auto sv = static_cast<image::SysVarId>(d.u);
        bool ok = sv == image::SysVarId::AaOut || sv == image::SysVarId::AaMarker ||
                  (d.op == Op::LoadIo && sv == image::SysVarId::AaIn);
        if (d.u >= image::kSysVarCount || !ok) return bad("system variable is not an I/O variable");
        in.a8 = static_cast<uint8_t>(d.u);
        break;
      }
      case Op::Jump:
      case Op::JumpFalse:
      case Op::JumpTrue:
      case Op::StmtSkip: fixes.push_back({idx, 0, 0, d.addr}); break;
      case Op::When:
        fixes.push_back({idx, 0, 0, d.addr});
        fixes.push_back({idx, 1, 0, d.addr2});
        break;
      case Op::Case:
        in.a = static_cast<uint32_t>(out.arms.size());
        in.b = static_cast<uint32_t>(d.arms.size());
        for (const auto& [ci, target] : d.arms) {
          if (ci >= img.constants.size()) return bad("constant index out of range");
          fixes.push_back({idx, 3, static_cast<uint32_t>(out.arms.size()), target});
          out.arms.push_back({img.constants[ci], 0});
        }
        if (d.caseDefault != image::kNoTarget) fixes.push_back({idx, 2, 0, d.caseDefault});
        break;
      case Op::Call:
        if (d.u >= img.procs.size() || img.procs[d.u].kind != image::UnitKind::Sub)
          return bad("procedure index is not a subprogram");
        in.a = static_cast<uint32_t>(d.u);
        break;
      case Op::Move:
        if (d.moves.empty() || d.moves.size() > image::kMaxMoveOperands) return bad("descriptor count out of range");
        in.a = static_cast<uint32_t>(out.moves.size());
        in.b = static_cast<uint32_t>(d.moves.size());
        for (uint8_t m : d.moves) {
          uint8_t kind = m >> 4, axis = m & 0x0F;
          if (kind >= image::kMoveKindCount) return bad("unknown descriptor kind");
          if (kind <= static_cast<uint8_t>(image::MoveKind::Fa) && axis >= img.axes.size())
            return bad("axis index out of range");
          out.moves.push_back(m);
        }
        break;
      case Op::ZWord:
        if (d.u >= image::kZAddrCount) return bad("unknown address");
        in.a8 = static_cast<uint8_t>(d.u);
        break;
      case Op::Aux:
        if (d.u >= image::kAuxWordCount) return bad("unknown aux word");
        in.a8 = static_cast<uint8_t>(d.u);
        in.b8 = d.u2;
        break;
      case Op::M:
      case Op::MNb:
      case Op::MSpecial:
        in.a = static_cast<uint32_t>(out.values.size());
        out.values.push_back(static_cast<double>(d.u));
        break;
      default:
        if (image::isPushDec(d.op)) {
          in.a = static_cast<uint32_t>(out.values.size());
          out.values.push_back(image::decValue(d.op, d.s));
        }
        break;
      }
      if (d.op == Op::Stmt || d.op == Op::StmtSkip || d.op == Op::When) {
        // The statement's line: the last line entry at or before this offset.
        while (nextLine < img.lines.size() && img.lines[nextLine].offset <= off) ++nextLine;
        if (nextLine > 0 && img.lines[nextLine - 1].file < img.strings.size())
          in.c = static_cast<uint32_t>(nextLine - 1);
      }
      out.code.push_back(in);
      offsets.push_back(off);
      off += d.length;
    }
    Ins fall;
    fall.op = static_cast<Op>(kOpFallOff);
    out.code.push_back(fall);
    offsets.push_back(end);
  }
  for (const Fix& f : fixes) {
    Ins& in = out.code[f.ins];
    const uint32_t p = out.procOf(f.ins);
    const auto& range = procRange[p];
    // the procedure's own instructions, without its fall-off sentinel
    const auto first = offsets.begin() + out.procEntry[p];
    const auto last = offsets.begin() + (p + 1 < out.procEntry.size() ? out.procEntry[p + 1] : out.code.size()) - 1;
    auto it = std::lower_bound(first, last, f.addr);
    if (f.addr < range.first || f.addr >= range.second || it == last || *it != f.addr) {
      why = fmt::format("{}: target 0x{:04x} is not an instruction of the same procedure", where(offsets[f.ins]),
                        f.addr);
      return false;
    }
    const auto t = static_cast<uint32_t>(it - offsets.begin());
    switch (f.which) {
    case 0: in.a = t; break;
    case 1: in.b = t; break;
    case 2: in.c = t; break;
    default: out.arms[f.arm].target = t; break;
    }
  }
  if (img.entries.empty()) {
    why = "the image has no entry point";
    return false;
  }
  for (const auto& e : img.entries)
    if (e.proc >= img.procs.size() || e.name >= img.strings.size()) {
      why = "entry point out of range";
      return false;
    }
  return true;
}

} // namespace iso::sim
