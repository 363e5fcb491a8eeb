//! @file Disassembler.cpp
//! @brief Listing and annotated hex dump.
#include "image/Disassembler.h"

#include <algorithm>
#include <cctype>
#include <set>

#include <fmt/format.h>

#include "image/ImageWriter.h"

namespace iso::image {

namespace {

/// A string in double quotes, escaped as printableName does (quotes and backslashes too).
std::string quote(const std::string& s) {
  std::string out(1, '"');
  out += printableName(s, true);
  out += '"';
  return out;
}

/// A name that is an identifier prints bare, anything else quoted.
std::string name(const Image& img, uint32_t s) {
  if (s >= img.strings.size()) return fmt::format("?string{}", s);
  const std::string& v = img.strings[s];
  bool ident = !v.empty();
  for (char c : v)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.' || c == '/' || c == '-')) ident = false;
  return ident ? v : quote(v);
}

std::string label(uint32_t off) { return fmt::format("L{:04X}", off); }

std::string axisName(const Image& img, unsigned a) {
  return a < img.axes.size() && img.axes[a] > 0x20 && img.axes[a] < 0x7F ? std::string(1, img.axes[a])
                                                                         : fmt::format("?axis{}", a);
}

std::string constant(const Image& img, uint64_t c) {
  return c < img.constants.size() ? fmt::format("{}", img.constants[c]) : fmt::format("?const{}", c);
}

std::string procName(const Image& img, uint64_t p) {
  if (p >= img.procs.size()) return fmt::format("?proc{}", p);
  return fmt::format("{} (procedure {})", name(img, img.procs[p].name), p);
}

std::string sourceOf(const Image& img, uint32_t off) {
  auto it = std::lower_bound(img.lines.begin(), img.lines.end(), off,
                             [](const LineEntry& e, uint32_t o) { return e.offset < o; });
  if (it == img.lines.end() || it->offset != off) return {};
  std::string s =
      fmt::format("{}:{}", it->file < img.strings.size() ? printableName(img.strings[it->file]) : "?", it->line);
  if (it->hasN) s += fmt::format(" N{}", it->n);
  return s;
}

/// Code offsets that some instruction of [begin, end) jumps to.
std::set<uint32_t> targetsOf(const Image& img, uint32_t begin, uint32_t end) {
  std::set<uint32_t> t;
  for (uint32_t off = begin; off < end;) {
    Instr in;
    if (!decode(img.code.data(), end, off, in)) {
      ++off;
      continue;
    }
    switch (in.op) {
    case Op::Jump:
    case Op::JumpFalse:
    case Op::JumpTrue:
    case Op::StmtSkip: t.insert(in.addr); break;
    case Op::When:
    case Op::GoRange:
      t.insert(in.addr);
      t.insert(in.addr2);
      break;
    case Op::Case:
      for (const auto& a : in.arms)
        t.insert(a.second);
      if (in.caseDefault != kNoTarget) t.insert(in.caseDefault);
      break;
    default: break;
    }
    off += in.length;
  }
  return t;
}

/// Procedure ranges clamped to the code (an unverified image may claim anything).
std::pair<uint32_t, uint32_t> rangeOf(const Image& img, const Proc& p) {
  uint64_t size = img.code.size();
  uint64_t b = std::min<uint64_t>(p.entry, size);
  uint64_t e = std::min<uint64_t>(static_cast<uint64_t>(p.entry) + p.size, size);
  return {static_cast<uint32_t>(b), static_cast<uint32_t>(e)};
}

/// The operands of the z32 program-flow and parameter instructions; empty for the others.
std::string formatZ32Operands(const Image& img, const Instr& in) {
  switch (in.op) {
  case Op::GoRange: return fmt::format("{}..{}", label(in.addr), label(in.addr2));
  case Op::Kg: return procName(img, in.u);
  case Op::AxisCtl: {
    const char* g = axisCtlOn(in.u) ? "G28" : "G29";
    const uint32_t mask = axisCtlMask(in.u);
    if (mask == 0) return fmt::format("{} (every axis)", g);
    std::string axes;
    for (unsigned a = 0; a < 32; ++a)
      if (mask & (1u << a)) axes += fmt::format(" {}", axisName(img, a));
    return fmt::format("{}{}", g, axes);
  }
  case Op::Origin: return fmt::format("{}", in.u);
  case Op::Nm: return fmt::format("G{}", in.u);
  case Op::LoadUser:
  case Op::StoreUser: return name(img, static_cast<uint32_t>(std::min<uint64_t>(in.u, 0xFFFFFFFFu)));
  case Op::LoadPar:
  case Op::StorePar: return "PAR[index]";
  case Op::LoadPal:
  case Op::StorePal: return "PAL[index]";
  default:
    if (isPushDec(in.op)) return fmt::format("{}", decValue(in.op, in.s));
    return {};
  }
}

} // namespace

std::string formatOperands(const Image& img, const Instr& in) {
  switch (in.op) {
  case Op::PushConst: return fmt::format("#{} ({})", in.u, constant(img, in.u));
  case Op::LoadR:
  case Op::StoreR: return fmt::format("R{}", in.u);
  case Op::LoadRInd:
  case Op::StoreRInd: return "R[index]";
  case Op::LoadAxVar: return fmt::format("{}[{}]", sysVarIdName(static_cast<uint8_t>(in.u)), axisName(img, in.u2));
  case Op::LoadIo:
  case Op::StoreIo: return fmt::format("{}[index]", sysVarIdName(static_cast<uint8_t>(in.u)));
  case Op::StmtSkip:
  case Op::Jump:
  case Op::JumpFalse:
  case Op::JumpTrue: return label(in.addr);
  case Op::Case: {
    std::string s;
    for (const auto& a : in.arms)
      s += fmt::format("{} -> {}, ", constant(img, a.first), label(a.second));
    return s + "default -> " + (in.caseDefault == kNoTarget ? std::string("next") : label(in.caseDefault));
  }
  case Op::Call: return procName(img, in.u);
  case Op::M: return fmt::format("M{}", in.u);
  case Op::MNb: return fmt::format("M=NB({})", in.u);
  case Op::MSpecial: return fmt::format("M{}", in.u);
  case Op::Aux: return fmt::format("{} (value {} below the top)", auxWordName(in.u), in.u2);
  case Op::ZWord: return zAddrName(static_cast<uint8_t>(in.u));
  case Op::Move: {
    std::string s;
    for (uint8_t d : in.moves) {
      if (!s.empty()) s += ", ";
      unsigned kind = d >> 4, axis = d & 0xF;
      switch (kind) {
      case static_cast<unsigned>(MoveKind::Target): s += fmt::format("Pos[{}]", axisName(img, axis)); break;
      case static_cast<unsigned>(MoveKind::TargetNb): s += fmt::format("Posa[{}]", axisName(img, axis)); break;
      case static_cast<unsigned>(MoveKind::Fa): s += fmt::format("Fa[{}]", axisName(img, axis)); break;
      default:
        s +=
            kind < kMoveKindCount && axis == 0 ? moveKindName(static_cast<uint8_t>(kind)) : fmt::format("?0x{:02X}", d);
      }
    }
    return s;
  }
  case Op::When: return fmt::format("cond {}, body {}", label(in.addr), label(in.addr2));
  default: return formatZ32Operands(img, in);
  }
}

std::string disassemble(const Image& img) {
  std::string o;
  o += fmt::format("; isoimage format {}{}{}\n", img.formatVersion, img.stripped() ? ", stripped (no line table)" : "",
                   img.z32() ? ", dialect z32" : "");
  o += fmt::format("; {} strings, {} constants, {} bytes of code, {} procedures, {} line entries\n", img.strings.size(),
                   img.constants.size(), img.code.size(), img.procs.size(), img.lines.size());
  std::string axes;
  for (size_t a = 0; a < img.axes.size(); ++a) {
    axes += ' ';
    axes += axisName(img, static_cast<unsigned>(a));
  }
  o += fmt::format("; axes:{}\n", axes.empty() ? " (none)" : axes);
  for (size_t i = 0; i < img.entries.size(); ++i) {
    const EntryPoint& e = img.entries[i];
    o += fmt::format("; entry {}: {} {} -> {}\n", i, kindName(e.kind),
                     e.name < img.strings.size() ? quote(img.strings[e.name]) : "?", procName(img, e.proc));
  }
  for (size_t i = 0; i < img.constants.size(); ++i)
    o += fmt::format("; constant #{} = {}\n", i, img.constants[i]);
  for (size_t p = 0; p < img.procs.size(); ++p) {
    const Proc& pr = img.procs[p];
    auto [begin, end] = rangeOf(img, pr);
    o += fmt::format("\n; procedure {}: {} {}, file {}, code 0x{:04X}..0x{:04X} ({} bytes)\n", p, kindName(pr.kind),
                     name(img, pr.name), name(img, pr.file), pr.entry, pr.entry + static_cast<uint64_t>(pr.size),
                     pr.size);
    std::set<uint32_t> labels = targetsOf(img, begin, end);
    for (uint32_t off = begin; off < end;) {
      if (labels.count(off)) o += label(off) + ":\n";
      Instr in;
      std::string line;
      if (const DecodeStatus st = decode(img.code.data(), end, off, in); !st) {
        line = fmt::format("  {:04X}  {:<11} 0x{:02X}", off, ".byte", img.code[off]);
        line = fmt::format("{:<40}; {}", line, st.message());
        o += line + "\n";
        ++off;
        continue;
      }
      std::string ops = formatOperands(img, in);
      line = fmt::format("  {:04X}  {:<11} {}", off, opInfo(static_cast<uint8_t>(in.op)).mnemonic, ops);
      while (!line.empty() && line.back() == ' ')
        line.pop_back();
      std::string src = sourceOf(img, off);
      if (!src.empty()) line = fmt::format("{:<40}; {}", line, src);
      o += line + "\n";
      off += in.length;
    }
  }
  return o;
}

std::string hexDump(const Image& img) {
  std::vector<Field> fields;
  std::vector<uint8_t> bytes = writeImage(img, nullptr, &fields);
  std::string o =
      fmt::format("# isoimage, {} bytes, format version {}; '#' starts a comment\n", bytes.size(), img.formatVersion);
  auto emit = [&](uint32_t off, uint32_t size, const std::string& what) {
    for (uint32_t k = 0; k < size; k += 8) {
      std::string hex;
      for (uint32_t j = k; j < size && j < k + 8; ++j)
        hex += fmt::format("{}{:02X}", j == k ? "" : " ", bytes[off + j]);
      std::string line = fmt::format("{:04X}: {:<23}", off + k, hex);
      if (k == 0 && !what.empty()) line += "  # " + what;
      while (!line.empty() && line.back() == ' ')
        line.pop_back();
      o += line + "\n";
    }
  };
  std::set<uint32_t> unitLabels; // format 2: the jump targets of the current procedure
  for (const Field& f : fields) {
    if (f.size == 0) {
      o += "# " + f.what + "\n";
      continue;
    }
    if (!f.code) {
      emit(f.offset, f.size, f.what);
      continue;
    }
    if (f.decodedEnd > f.decoded) { // format 2: one unit, with the instructions it decodes to
      for (size_t p = 0; p < img.procs.size(); ++p)
        if (img.procs[p].entry == f.decoded) {
          o += fmt::format("# procedure {}: {} {}\n", p, kindName(img.procs[p].kind), name(img, img.procs[p].name));
          unitLabels = targetsOf(img, rangeOf(img, img.procs[p]).first, rangeOf(img, img.procs[p]).second);
        }
      std::string what;
      if (const uint8_t b = bytes[f.offset]; b >= code2::kRecall && b < code2::kRecallEnd)
        what = fmt::format("recall {}{}: ", b & 0x1F, b >= code2::kRecallMasked ? " (masked)" : "");
      else if (b == code2::kRaw)
        what = "raw: ";
      for (uint32_t off = f.decoded; off < f.decodedEnd;) {
        Instr in;
        if (off > f.decoded) what += "; ";
        if (const DecodeStatus st = decode(img.code.data(), f.decodedEnd, off, in); !st) {
          what += fmt::format("{:04X} .byte 0x{:02X} ({})", off, img.code[off], st.message());
          ++off;
          continue;
        }
        what += fmt::format("{}{:04X} {}", unitLabels.count(off) ? label(off) + ": " : "", off,
                            opInfo(static_cast<uint8_t>(in.op)).mnemonic);
        std::string ops = formatOperands(img, in);
        if (!ops.empty()) what += " " + ops;
        std::string src = sourceOf(img, off);
        if (!src.empty()) what += "  (" + src + ")";
        off += in.length;
      }
      emit(f.offset, f.size, what);
      continue;
    }
    // the code: one line per instruction, procedure by procedure
    uint32_t covered = 0;
    for (size_t p = 0; p < img.procs.size(); ++p) {
      auto [begin, end] = rangeOf(img, img.procs[p]);
      if (begin < covered) continue;
      if (begin > covered) emit(f.offset + covered, begin - covered, "code outside every procedure");
      o += fmt::format("# procedure {}: {} {}\n", p, kindName(img.procs[p].kind), name(img, img.procs[p].name));
      std::set<uint32_t> labels = targetsOf(img, begin, end);
      for (uint32_t off = begin; off < end;) {
        Instr in;
        if (const DecodeStatus st = decode(img.code.data(), end, off, in); !st) {
          emit(f.offset + off, 1, fmt::format("code {:04X} .byte ({})", off, st.message()));
          ++off;
          continue;
        }
        std::string what = fmt::format("{}{:04X} {}", labels.count(off) ? label(off) + ": " : "", off,
                                       opInfo(static_cast<uint8_t>(in.op)).mnemonic);
        std::string ops = formatOperands(img, in);
        if (!ops.empty()) what += " " + ops;
        std::string src = sourceOf(img, off);
        if (!src.empty()) what += "  (" + src + ")";
        emit(f.offset + off, in.length, what);
        off += in.length;
      }
      covered = end;
    }
    if (covered < img.code.size())
      emit(f.offset + covered, static_cast<uint32_t>(img.code.size()) - covered, "code outside every procedure");
  }
  return o;
}

} // namespace iso::image
