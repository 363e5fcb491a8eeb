//! @file ImageVerifier.cpp
//! @brief Table checks, a linear decode of every procedure, then a flow analysis per region.
#include "image/ImageVerifier.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <deque>
#include <map>
#include <optional>
#include <stdexcept>

#include <fmt/format.h>

#include "image/Opcode.h"
#include "lang/Addresses.h"
#include "support/BitSet.h"
#include "support/Bytes.h"

namespace iso::image {

namespace {

enum class Region : uint8_t { Proc, Cond, Body };

const char* regionName(Region r) {
  switch (r) {
  case Region::Proc: return "the procedure";
  case Region::Cond: return "a WHEN condition";
  case Region::Body: return "a WHEN body";
  }
  return "?";
}

/// The class of an opcode byte (Opcodes.def).
OpClass classOf(Op op) { return opInfo(static_cast<uint8_t>(op)).cls; }

/// Whether the verifier allows an instruction of class `c` in a region of kind `r`.
constexpr bool allowedIn(OpClass c, Region r) {
  switch (c) {
  case OpClass::Expr: return true;
  case OpClass::Effect:
  case OpClass::Flow: return r != Region::Cond;
  case OpClass::Control: return r == Region::Proc;
  case OpClass::CondEnd: return r == Region::Cond;
  case OpClass::BodyEnd: return r == Region::Body;
  }
  return false;
}

class Verifier {
public:
  Verifier(const Image& img, const Layout& lay, ImageError& err) : img_(img), lay_(lay), err_(err) {}

  bool run() {
    return checkFlags() && checkStrings() && checkConstants() && checkAxes() && checkProcs() && checkEntries() &&
           decodeAll() && checkLines() && flowAll();
  }
  /// The instruction boundaries (after a successful run).
  support::RankedBits takeBoundaries() { return std::move(start_); }

private:
  const Image& img_;
  const Layout& lay_;
  ImageError& err_;
  // Memory is a few bits per instruction, whatever the image: one boundary bit per code byte
  // (with a rank directory: instruction k is the k-th boundary), and per instruction whether
  // the flow reached it, with a non-empty stack, first by a jump (a head); per WHEN two region
  // roots. Instructions are decoded again where needed instead of being kept.
  support::RankedBits start_; ///< code offset -> an instruction starts here
  Instr in_;                  ///< scratch for the instruction being looked at
  /// The roots of the WHEN regions: the code offsets of conditions, then of bodies, each
  /// sorted and unique; region id of a root = procedure count + its index in that order.
  struct WhenRoots {
    std::vector<uint32_t> cond, body;
    size_t size() const { return cond.size() + body.size(); }
    void finish() {
      for (auto* v : {&cond, &body}) {
        std::sort(v->begin(), v->end());
        v->erase(std::unique(v->begin(), v->end()), v->end());
      }
    }
    /// The index of a root known to exist.
    size_t index(bool isBody, uint32_t root) const {
      const auto& v = isBody ? body : cond;
      const size_t i = static_cast<size_t>(std::lower_bound(v.begin(), v.end(), root) - v.begin());
      return isBody ? cond.size() + i : i;
    }
    /// The index of a root, or SIZE_MAX if there is none at `root`.
    size_t find(bool isBody, uint32_t root) const {
      const auto& v = isBody ? body : cond;
      const auto it = std::lower_bound(v.begin(), v.end(), root);
      return it != v.end() && *it == root ? index(isBody, root) : SIZE_MAX;
    }
    bool isBody(size_t i) const { return i >= cond.size(); }
    uint32_t root(size_t i) const { return i < cond.size() ? cond[i] : body[i - cond.size()]; }
  };
  WhenRoots whenRoots_;

  /// Decodes the instruction at `off` of procedure p, known to decode (decodeAll).
  const Instr& instrAt(uint32_t off, uint32_t p) { return instrAt(off, p, in_); }
  const Instr& instrAt(uint32_t off, uint32_t p, Instr& into) const {
    const Proc& pr = img_.procs[p];
    if (const DecodeStatus st = decode(img_.code.data(), pr.entry + pr.size, off, into); !st)
      throw std::logic_error("verifier: " + st.message());
    return into;
  }

  bool fail(uint32_t offset, std::string msg) {
    err_ = {offset, std::move(msg)};
    return false;
  }
  static uint32_t rec(const std::vector<uint32_t>& v, size_t i, uint32_t fallback) {
    return i < v.size() ? v[i] : fallback;
  }
  uint32_t secOff(SectionId id) const { return lay_.of(id); }
  std::string procLabel(size_t p) const {
    const Proc& pr = img_.procs[p];
    return pr.name < img_.strings.size() ? fmt::format("procedure {} ({})", p, img_.strings[pr.name])
                                         : fmt::format("procedure {}", p);
  }
  bool failAt(const Instr& in, std::string msg) {
    return fail(lay_.code(in.offset),
                fmt::format("{} at code 0x{:04X}: {}", opInfo(static_cast<uint8_t>(in.op)).mnemonic, in.offset, msg));
  }

  // ---- tables -------------------------------------------------------------------------------

  bool checkFlags() {
    if (img_.flags & ~kKnownImageFlags)
      return fail(kOffFlags, fmt::format("unknown image flags 0x{:08X}", img_.flags & ~kKnownImageFlags));
    if (img_.stripped() && !img_.lines.empty()) return fail(kOffFlags, "a stripped image has line table entries");
    return true;
  }

  /// The first index i of `n` items equal to an earlier one (n if none), with 4 bytes per item:
  /// the indices sorted by (value, index); the later of each equal neighbour pair is a duplicate.
  template <class Less> static size_t firstDuplicate(size_t n, Less less) {
    std::vector<uint32_t> order(n);
    for (size_t i = 0; i < n; ++i)
      order[i] = static_cast<uint32_t>(i);
    std::stable_sort(order.begin(), order.end(), less);
    size_t first = n;
    for (size_t k = 1; k < n; ++k)
      if (!less(order[k - 1], order[k])) first = std::min<size_t>(first, order[k]);
    return first;
  }

  bool checkStrings() {
    const auto& str = img_.strings;
    const size_t i = firstDuplicate(str.size(), [&](uint32_t a, uint32_t b) { return str[a] < str[b]; });
    if (i < str.size())
      return fail(rec(lay_.strings, i, secOff(SectionId::Strings)),
                  fmt::format("string {} is a duplicate (the string table holds each string once)", i));
    return true;
  }

  bool checkConstants() {
    const auto& c = img_.constants;
    auto bits = [&](uint32_t i) {
      uint64_t b;
      std::memcpy(&b, &c[i], sizeof b);
      return b;
    };
    size_t dup = firstDuplicate(c.size(), [&](uint32_t a, uint32_t b) { return bits(a) < bits(b); });
    for (size_t i = 0; i < c.size(); ++i) {
      uint32_t at = rec(lay_.constants, i, secOff(SectionId::Constants));
      if (!std::isfinite(c[i])) return fail(at, fmt::format("constant {} is not a finite number", i));
      if (i == dup)
        return fail(at, fmt::format("constant {} ({}) is a duplicate (the pool holds each value once)", i, c[i]));
    }
    return true;
  }

  bool checkAxes() {
    if (img_.axes.size() > kMaxAxes)
      return fail(secOff(SectionId::Axes), fmt::format("{} axes; at most {}", img_.axes.size(), kMaxAxes));
    for (size_t i = 0; i < img_.axes.size(); ++i) {
      char c = img_.axes[i];
      uint32_t at = lay_.axes + static_cast<uint32_t>(i);
      if (c < 'A' || c > 'Z' || lang::isFixedAddress(c))
        return fail(at, fmt::format("axis {} (byte 0x{:02X}) is not an axis letter (A-Z except {})", i,
                                    static_cast<uint8_t>(c), lang::spacedLetters(lang::kFixedAddresses)));
      for (size_t j = 0; j < i; ++j)
        if (img_.axes[j] == c) return fail(at, fmt::format("axis {} '{}' is listed twice", i, c));
    }
    return true;
  }

  bool checkProcs() {
    if (img_.procs.empty()) return fail(secOff(SectionId::Procs), "no procedures");
    uint32_t expected = 0;
    for (size_t i = 0; i < img_.procs.size(); ++i) {
      const Proc& p = img_.procs[i];
      uint32_t at = rec(lay_.procs, i, secOff(SectionId::Procs));
      if (static_cast<uint8_t>(p.kind) > 2) return fail(at, fmt::format("procedure {}: invalid kind", i));
      if (p.name >= img_.strings.size())
        return fail(
            at, fmt::format("procedure {}: name string {} out of range ({} strings)", i, p.name, img_.strings.size()));
      if (p.file >= img_.strings.size())
        return fail(
            at, fmt::format("procedure {}: file string {} out of range ({} strings)", i, p.file, img_.strings.size()));
      if (p.size == 0) return fail(at, fmt::format("{} is empty", procLabel(i)));
      if (p.entry != expected)
        return fail(at, p.entry < expected
                            ? fmt::format("{} at 0x{:04X} overlaps the previous one (which ends at 0x{:04X})",
                                          procLabel(i), p.entry, expected)
                            : fmt::format("{} at 0x{:04X} leaves code 0x{:04X}..0x{:04X} outside every procedure",
                                          procLabel(i), p.entry, expected, p.entry));
      if (p.size > img_.code.size() - p.entry)
        return fail(at, fmt::format("{} (0x{:04X}, {} bytes) ends past the end of the code ({} bytes)", procLabel(i),
                                    p.entry, p.size, img_.code.size()));
      expected = p.entry + p.size;
    }
    if (expected != img_.code.size())
      return fail(lay_.code(expected),
                  fmt::format("code 0x{:04X}..0x{:04X} is outside every procedure", expected, img_.code.size()));
    return true;
  }

  bool checkEntries() {
    if (img_.entries.empty()) return fail(secOff(SectionId::Entries), "no entry points (the main program is missing)");
    std::vector<bool> named(img_.procs.size(), false); // procedures named by an entry so far
    for (size_t i = 0; i < img_.entries.size(); ++i) {
      const EntryPoint& e = img_.entries[i];
      uint32_t at = rec(lay_.entries, i, secOff(SectionId::Entries));
      if (i == 0 && e.kind != UnitKind::Main)
        return fail(at,
                    fmt::format("entry 0 is a {} program; the first entry must be the main program", kindName(e.kind)));
      if (i > 0 && e.kind != UnitKind::Semi)
        return fail(at, fmt::format("entry {} is a {} program; entries after the first must be semi-automatic", i,
                                    kindName(e.kind)));
      if (e.name >= img_.strings.size())
        return fail(at,
                    fmt::format("entry {}: name string {} out of range ({} strings)", i, e.name, img_.strings.size()));
      if (e.proc >= img_.procs.size())
        return fail(at,
                    fmt::format("entry {}: procedure {} out of range ({} procedures)", i, e.proc, img_.procs.size()));
      if (img_.procs[e.proc].kind != e.kind)
        return fail(at, fmt::format("entry {} ({}) names {}, a {} procedure", i, kindName(e.kind), procLabel(e.proc),
                                    kindName(img_.procs[e.proc].kind)));
      if (named[e.proc]) return fail(at, fmt::format("entry {} names {} a second time", i, procLabel(e.proc)));
      named[e.proc] = true;
    }
    return true;
  }

  // ---- code: decoding and operands ----------------------------------------------------------

  /// Jumps, WHENs and CASEs (the shapes with code targets): their operands are checked once
  /// every boundary is known.
  static bool hasTargets(Op op) {
    const Shape shape = opInfo(static_cast<uint8_t>(op)).shape;
    return shape == Shape::Addr || shape == Shape::Case || shape == Shape::When || shape == Shape::Range;
  }

  /// The instructions without operands that only a z32 image may hold (checkOperands).
  static bool z32Only(Op op) {
    return op == Op::M1 || op == Op::LoadPar || op == Op::StorePar || op == Op::LoadPal || op == Op::StorePal;
  }

  /// The length of the instruction at `off` when it has no operand a rule looks at: no
  /// operand, or a decimal push with a minimal sleb inside [off, end). 0 for any other.
  uint32_t plainLength(uint32_t off, uint32_t end) const {
    const OpInfo& info = opInfo(img_.code[off]);
    if (!info.valid) return 0;
    if (info.shape == Shape::None) return z32Only(static_cast<Op>(img_.code[off])) ? 0 : 1;
    if (info.shape != Shape::Dec) return 0;
    support::ByteCursor c(img_.code.data(), size_t{off} + 1, end);
    int64_t mantissa;
    if (c.sleb(mantissa, detail::kMaxOperandLeb) != support::LebError::None) return 0;
    return static_cast<uint32_t>(c.pos() - off);
  }

  /// Decodes every procedure once, marking the boundaries and checking the operands of the
  /// instructions without targets; then checks those with targets. The first error is the same
  /// as if each instruction were checked in code order after decoding all: a decoding error
  /// first, then the operand error at the lowest offset.
  bool decodeAll() {
    start_ = support::RankedBits(img_.code.size());
    support::Bits targeted(img_.code.size()); // code offsets of instructions with targets
    std::optional<ImageError> operandError;   // the first error of the others
    uint32_t operandErrorAt = static_cast<uint32_t>(img_.code.size());
    size_t whens = 0;
    for (size_t p = 0; p < img_.procs.size(); ++p) {
      const Proc& pr = img_.procs[p];
      uint32_t end = pr.entry + pr.size;
      for (uint32_t off = pr.entry; off < end;) {
        if (const uint32_t n = plainLength(off, end)) { // nothing to check but where it ends
          start_.set(off);
          off += n;
          continue;
        }
        if (DecodeStatus st = decode(img_.code.data(), end, off, in_); !st) {
          bool crosses = false;
          if (end < img_.code.size()) { // does it decode when the code goes on?
            const DecodeStatus whole = decode(img_.code.data(), img_.code.size(), off, in_);
            crosses = whole.ok();
            if (!crosses) st = whole;
          }
          return fail(lay_.code(off),
                      crosses ? fmt::format("instruction at code 0x{:04X} runs past the end of {} (0x{:04X})", off,
                                            procLabel(p), end)
                              : fmt::format("{} at code 0x{:04X} in {}", st.message(), off, procLabel(p)));
        }
        start_.set(off);
        if (hasTargets(in_.op)) {
          targeted.set(off);
          whens += in_.op == Op::When;
        } else if (!operandError && !checkOperands(in_, static_cast<uint32_t>(p))) {
          operandError = err_;
          operandErrorAt = off;
        }
        off += in_.length;
      }
    }
    start_.freeze();
    whenRoots_.cond.reserve(whens);
    whenRoots_.body.reserve(whens);
    for (size_t p = 0; p < img_.procs.size(); ++p) {
      const Proc& pr = img_.procs[p];
      const uint32_t end = std::min(pr.entry + pr.size, operandErrorAt);
      for (size_t off = targeted.next(pr.entry); off < end; off = targeted.next(off + 1)) {
        const Instr& in = instrAt(static_cast<uint32_t>(off), static_cast<uint32_t>(p));
        if (!checkOperands(in, static_cast<uint32_t>(p))) return false;
        if (in.op == Op::When) {
          whenRoots_.cond.push_back(in.addr);
          whenRoots_.body.push_back(in.addr2);
        }
      }
    }
    if (operandError) {
      err_ = *operandError;
      return false;
    }
    whenRoots_.finish();
    return true;
  }

  /// A jump target: an instruction boundary inside procedure p.
  bool checkTarget(const Instr& in, uint32_t target, uint32_t p, const char* what) {
    const Proc& pr = img_.procs[p];
    if (target < pr.entry || target - pr.entry >= pr.size)
      return failAt(in, fmt::format("{} 0x{:04X} is outside {} (0x{:04X}..0x{:04X})", what, target, procLabel(p),
                                    pr.entry, pr.entry + pr.size));
    if (!start_.test(target))
      return failAt(in, fmt::format("{} 0x{:04X} is not an instruction boundary", what, target));
    return true;
  }

  /// The descriptors of a move: kinds, axes in range, each axis and arc word at most once, a
  /// feed only for an axis that moves.
  bool checkMove(const Instr& in) {
    uint32_t targets = 0, fa = 0, arcs = 0;
    for (size_t k = 0; k < in.moves.size(); ++k) {
      uint8_t d = in.moves[k];
      unsigned kind = d >> 4, axis = d & 0xF;
      if (kind >= kMoveKindCount)
        return failAt(
            in, fmt::format("descriptor {} (0x{:02X}): kind {} out of range (0..{})", k, d, kind, kMoveKindCount - 1));
      auto mk = static_cast<MoveKind>(kind);
      if (mk == MoveKind::Target || mk == MoveKind::TargetNb || mk == MoveKind::Fa) {
        if (axis >= img_.axes.size())
          return failAt(in, fmt::format("descriptor {} (0x{:02X}): axis {} out of range ({} axes)", k, d, axis,
                                        img_.axes.size()));
        if (mk == MoveKind::Fa) {
          if (fa & (1u << axis))
            return failAt(in, fmt::format("descriptor {}: a second feed for axis {}", k, img_.axes[axis]));
          fa |= 1u << axis;
        } else {
          if (targets & (1u << axis))
            return failAt(in, fmt::format("descriptor {}: axis {} moves twice", k, img_.axes[axis]));
          targets |= 1u << axis;
        }
      } else {
        if (axis != 0)
          return failAt(in, fmt::format("descriptor {} (0x{:02X}): arc word {} with axis nibble {} (must be 0)", k, d,
                                        moveKindName(static_cast<uint8_t>(kind)), axis));
        if (arcs & (1u << kind))
          return failAt(in,
                        fmt::format("descriptor {}: arc word {} twice", k, moveKindName(static_cast<uint8_t>(kind))));
        arcs |= 1u << kind;
      }
    }
    if (fa & ~targets) {
      unsigned a = 0;
      while (!((fa & ~targets) & (1u << a)))
        ++a;
      return failAt(in, fmt::format("feed for axis {}, which does not move in this block", img_.axes[a]));
    }
    return true;
  }

  bool checkOperands(const Instr& in, uint32_t p) {
    if (!in.minimal) return failAt(in, "non-minimal LEB128 operand");
    switch (in.op) {
    case Op::PushConst:
      if (in.u >= img_.constants.size())
        return failAt(in, fmt::format("constant {} out of range ({} constants)", in.u, img_.constants.size()));
      break;
    case Op::LoadR:
    case Op::StoreR:
      if (in.u < 1 || in.u > kMaxRIndex) return failAt(in, fmt::format("R{} outside R1..R{}", in.u, kMaxRIndex));
      break;
    case Op::LoadAxVar:
      if (in.u > static_cast<uint8_t>(SysVarId::AaFw))
        return failAt(in, fmt::format("system variable {} ({}) is not an axis variable (0..4)", in.u,
                                      sysVarIdName(static_cast<uint8_t>(in.u))));
      if (in.u2 >= img_.axes.size())
        return failAt(in, fmt::format("axis {} out of range ({} axes)", in.u2, img_.axes.size()));
      break;
    case Op::LoadIo:
      if (in.u < static_cast<uint8_t>(SysVarId::AaIn) || in.u >= kSysVarCount)
        return failAt(in, fmt::format("system variable {} ({}) is not an I/O variable (5..7)", in.u,
                                      sysVarIdName(static_cast<uint8_t>(in.u))));
      break;
    case Op::StoreIo:
      if (in.u < static_cast<uint8_t>(SysVarId::AaOut) || in.u >= kSysVarCount)
        return failAt(in, fmt::format("system variable {} ({}) is not writable (6..7)", in.u,
                                      sysVarIdName(static_cast<uint8_t>(in.u))));
      break;
    case Op::Call:
      if (in.u >= img_.procs.size())
        return failAt(in, fmt::format("procedure {} out of range ({} procedures)", in.u, img_.procs.size()));
      if (img_.procs[in.u].kind != UnitKind::Sub)
        return failAt(in, fmt::format("calls {}, a {} program (only subprograms can be called)", procLabel(in.u),
                                      kindName(img_.procs[in.u].kind)));
      break;
    case Op::Aux:
      if (!img_.z32()) return failAt(in, "a dialect z32 instruction in an image without the z32 flag (flags bit 1)");
      if (in.u >= kAuxWordCount)
        return failAt(in, fmt::format("aux word {} out of range (0..{})", in.u, kAuxWordCount - 1));
      break;
    case Op::M1:
      if (!img_.z32()) return failAt(in, "a dialect z32 instruction in an image without the z32 flag (flags bit 1)");
      break;
    case Op::MSpecial: {
      if (!img_.z32()) return failAt(in, "a dialect z32 instruction in an image without the z32 flag (flags bit 1)");
      // its subprogram: the call that follows it, in the same procedure
      const size_t next = size_t{in.offset} + in.length;
      const Proc& pr = img_.procs[p];
      if (next >= size_t{pr.entry} + pr.size || img_.code[next] != static_cast<uint8_t>(Op::Call))
        return failAt(in, "m.special must be followed by the call of its subprogram");
      [[fallthrough]];
    }
    case Op::M:
    case Op::MNb:
      if (in.u > 0xFFFFFFFFu) return failAt(in, fmt::format("M number {} does not fit in 32 bits", in.u));
      break;
    case Op::ZWord:
      if (in.u >= kZAddrCount)
        return failAt(in, fmt::format("address code {} out of range (0..{})", in.u, kZAddrCount - 1));
      break;
    case Op::Move:
      if (!checkMove(in)) return false;
      break;
    case Op::Case:
      for (size_t k = 0; k < in.arms.size(); ++k) {
        if (in.arms[k].first >= img_.constants.size())
          return failAt(in, fmt::format("arm {}: constant {} out of range ({} constants)", k, in.arms[k].first,
                                        img_.constants.size()));
        if (!checkTarget(in, in.arms[k].second, p, "arm target")) return false;
      }
      if (in.caseDefault != kNoTarget && !checkTarget(in, in.caseDefault, p, "default target")) return false;
      break;
    case Op::StmtSkip:
    case Op::Jump:
    case Op::JumpFalse:
    case Op::JumpTrue:
      if (!checkTarget(in, in.addr, p, "target")) return false;
      break;
    case Op::When:
      if (!checkTarget(in, in.addr, p, "condition") || !checkTarget(in, in.addr2, p, "body")) return false;
      break;
    case Op::GoRange: return checkRange(in, p);
    default: return checkZ32Operands(in);
    }
    return true;
  }

  /// A GO range: z32; both ends statement headers of the procedure, the end not before the start.
  bool checkRange(const Instr& in, uint32_t p) {
    if (!img_.z32()) return failZ32(in);
    for (const auto& [target, what] : {std::pair{in.addr, "range start"}, std::pair{in.addr2, "range end"}}) {
      if (!checkTarget(in, target, p, what)) return false;
      const auto op = static_cast<Op>(img_.code[target]);
      if (op != Op::Stmt && op != Op::StmtSkip)
        return failAt(in, fmt::format("{} 0x{:04X} is a {} instruction, not stmt or stmt.skip", what, target,
                                      opInfo(static_cast<uint8_t>(op)).mnemonic));
    }
    if (in.addr2 < in.addr)
      return failAt(in, fmt::format("range end 0x{:04X} is before its start 0x{:04X}", in.addr2, in.addr));
    return true;
  }

  bool failZ32(const Instr& in) {
    return failAt(in, "a dialect z32 instruction in an image without the z32 flag (flags bit 1)");
  }

  /// The operands of the z32 program-flow and parameter instructions (SPEC §4.7).
  bool checkZ32Operands(const Instr& in) {
    switch (in.op) {
    case Op::Kg:
      if (!img_.z32()) return failZ32(in);
      if (in.u >= img_.procs.size())
        return failAt(in, fmt::format("procedure {} out of range ({} procedures)", in.u, img_.procs.size()));
      if (img_.procs[in.u].kind != UnitKind::Sub)
        return failAt(in, fmt::format("continues in {}, a {} program (only in a subprogram)", procLabel(in.u),
                                      kindName(img_.procs[in.u].kind)));
      return true;
    case Op::AxisCtl:
      if (!img_.z32()) return failZ32(in);
      if (axisCtlMask(in.u) >> img_.axes.size() != 0)
        return failAt(in, fmt::format("axis mask 0x{:X} names an axis beyond the image's {} axes", axisCtlMask(in.u),
                                      img_.axes.size()));
      return true;
    case Op::Origin:
      if (!img_.z32()) return failZ32(in);
      if (in.u > kMaxOrigin) return failAt(in, fmt::format("origin {} outside 0..{}", in.u, kMaxOrigin));
      return true;
    case Op::Nm:
      if (!img_.z32()) return failZ32(in);
      if (!isNotModelledG(in.u))
        return failAt(in, fmt::format("G{} is not a code that isotools leaves unmodelled", in.u));
      return true;
    case Op::LoadUser:
    case Op::StoreUser:
      if (!img_.z32()) return failZ32(in);
      if (in.u >= img_.strings.size())
        return failAt(in, fmt::format("name string {} out of range ({} strings)", in.u, img_.strings.size()));
      if (!isParameterName(img_.strings[in.u]))
        return failAt(in, fmt::format("string {} is no parameter name (one or two letters A-Z)", in.u));
      return true;
    case Op::LoadPar:
    case Op::StorePar:
    case Op::LoadPal:
    case Op::StorePal:
      if (!img_.z32()) return failZ32(in);
      return true;
    default: return true;
    }
  }

  static bool isParameterName(const std::string& s) {
    if (s.empty() || s.size() > 2) return false;
    for (char c : s)
      if (c < 'A' || c > 'Z') return false;
    return true;
  }

  // ---- line table ---------------------------------------------------------------------------

  bool checkLines() {
    for (size_t i = 0; i < img_.lines.size(); ++i) {
      const LineEntry& l = img_.lines[i];
      uint32_t at = rec(lay_.lines, i, secOff(SectionId::Lines));
      if (l.file >= img_.strings.size())
        return fail(
            at, fmt::format("line entry {}: file string {} out of range ({} strings)", i, l.file, img_.strings.size()));
      if (l.line == 0) return fail(at, fmt::format("line entry {}: line 0 (lines count from 1)", i));
      if (l.hasN && !(std::isfinite(l.n) && l.n >= 0))
        return fail(at, fmt::format("line entry {}: N{} is not a non-negative number", i, l.n));
      if (!l.hasN && l.n != 0) return fail(at, fmt::format("line entry {}: N value without the N flag", i));
      if (i > 0 && l.offset <= img_.lines[i - 1].offset)
        return fail(at, fmt::format("line entry {} (code 0x{:04X}) does not follow entry {} (code 0x{:04X}): the table "
                                    "must be sorted by strictly increasing code offset",
                                    i, l.offset, i - 1, img_.lines[i - 1].offset));
      if (l.offset >= img_.code.size())
        return fail(at, fmt::format("line entry {}: code 0x{:04X} is past the end of the code ({} bytes)", i, l.offset,
                                    img_.code.size()));
      if (!start_.test(l.offset))
        return fail(at, fmt::format("line entry {}: code 0x{:04X} is not an instruction boundary", i, l.offset));
      const auto op = static_cast<Op>(img_.code[l.offset]);
      if (op != Op::Stmt && op != Op::StmtSkip)
        return fail(at, fmt::format("line entry {}: code 0x{:04X} is a {} instruction, not stmt or stmt.skip", i,
                                    l.offset, opInfo(static_cast<uint8_t>(op)).mnemonic));
    }
    return true;
  }

  // ---- flow ---------------------------------------------------------------------------------

  // Each instruction has one region and one stack depth. Both are fixed by the first path
  // that reaches it: a jump or a region root gives depth 0 and the region of the jump (a head);
  // falling through gives those after the instruction before. So per instruction three bits
  // suffice: reached, non-empty stack, head; the region of a head that is not its procedure's
  // own code is its WHEN root's (rootEntered_) or, for a jump inside a WHEN body, in
  // otherHeads_. The region and depth of any reached instruction are those of the nearest head
  // before it, followed forward (only for messages).
  support::Bits reached_, nonEmpty_, whenHead_; ///< per instruction index
  support::PrevBits heads_;                     ///< per instruction index
  std::vector<bool> rootEntered_;               ///< per whenRoots_ entry: reached as its region
  std::map<size_t, int32_t> otherHeads_;        ///< instruction index -> WHEN region
  /// The instruction being visited and how it was reached.
  struct Work {
    uint32_t off;
    uint32_t index; ///< instruction index (the rank of off among the boundaries)
    int32_t region;
    int16_t depth;
    bool fallthrough; ///< from the instruction before (else a jump or a region root)
  };
  /// A queued visit: the stack is empty there (jump targets, region roots, the instruction
  /// after a WHEN). 8 bytes, so the work list stays small.
  struct Queued {
    uint32_t off;
    uint32_t regionAndFallthrough; ///< region << 1 | fallthrough
  };
  std::deque<Queued> work_; ///< grows in small blocks: no doubling of a large vector
  /// The visit that follows at once: the instruction after the one visited, when falling
  /// through to it is the last successor queued (the work list's order without a push and pop).
  /// Two buffers: the visit of one writes the next visit into the other (no copy between them).
  Work visits_[2]{};
  Work* next_ = &visits_[1];
  bool hasNext_ = false;

  /// Region ids: procedure p is p; a WHEN condition or body, the procedure count + the index
  /// of its root in whenRoots_ (a binary search: n log n for n WHENs).
  int32_t regionFor(Region kind, uint32_t root, uint32_t p) const {
    if (kind == Region::Proc) return static_cast<int32_t>(p);
    return static_cast<int32_t>(img_.procs.size() + whenRoots_.index(kind == Region::Body, root));
  }
  Region kindOf(int32_t r) const {
    const auto i = static_cast<size_t>(r);
    if (i < img_.procs.size()) return Region::Proc;
    return whenRoots_.isBody(i - img_.procs.size()) ? Region::Body : Region::Cond;
  }
  uint32_t rootOf(int32_t r) const {
    const auto i = static_cast<size_t>(r);
    if (i < img_.procs.size()) return img_.procs[i].entry;
    return whenRoots_.root(i - img_.procs.size());
  }

  std::string regionLabel(int32_t r) const {
    const Region kind = kindOf(r);
    return kind == Region::Proc ? std::string(regionName(kind))
                                : fmt::format("{} at 0x{:04X}", regionName(kind), rootOf(r));
  }

  bool flowAll() {
    const size_t n = start_.count();
    reached_ = support::Bits(n);
    nonEmpty_ = support::Bits(n);
    whenHead_ = support::Bits(n);
    heads_ = support::PrevBits(n);
    rootEntered_.assign(whenRoots_.size(), false);
    for (size_t p = 0; p < img_.procs.size(); ++p) {
      work_.clear();
      const uint32_t entry = img_.procs[p].entry;
      Work* w = &visits_[0];
      next_ = &visits_[1];
      *w = {entry, static_cast<uint32_t>(start_.rank(entry)), regionFor(Region::Proc, entry, static_cast<uint32_t>(p)),
            0, false};
      for (;;) {
        hasNext_ = false;
        if (w->fallthrough && static_cast<size_t>(w->region) < img_.procs.size())
          fallThrough(*w, static_cast<uint32_t>(p));
        if (!visit(*w, static_cast<uint32_t>(p))) return false;
        if (hasNext_) {
          std::swap(w, next_);
          continue;
        }
        if (work_.empty()) break;
        const Queued q = work_.back();
        work_.pop_back();
        *w = {q.off, static_cast<uint32_t>(start_.rank(q.off)), static_cast<int32_t>(q.regionAndFallthrough >> 1), 0,
              (q.regionAndFallthrough & 1) != 0};
      }
    }
    return true;
  }

  /// The fast path of the flow through a procedure's own code: visits instructions reached by
  /// falling through, for the first time, that can only fall through further (no jump, no
  /// terminator, no WHEN), as long as no rule could fail; `w` is then the first one that needs
  /// visit() (which reports any error exactly as it would have). The order is the work list's.
  void fallThrough(Work& w, uint32_t p) {
    const uint8_t* code = img_.code.data();
    const uint32_t end = img_.procs[p].entry + img_.procs[p].size;
    for (;;) {
      if (reached_.test(w.index)) return;
      const auto op = static_cast<Op>(code[w.off]);
      const OpInfo& info = opInfo(code[w.off]);
      int32_t popped = info.pops, needed = info.pops;
      if (op == Op::Stmt || op == Op::Call) {
        if (w.depth != 0) return;
      } else if (info.cls != OpClass::Expr && info.cls != OpClass::Effect) {
        return; // jumps, terminators, WHEN, region ends
      } else if (op == Op::Move) {
        popped = needed = code[w.off + 1];
      } else if (op == Op::Aux) {
        needed = code[w.off + 2] + 1; // the value d places below the top must be there
      }
      if (w.depth < needed) return;
      const int32_t after = w.depth - popped + info.pushes;
      if (after > static_cast<int32_t>(kMaxStackDepth)) return;
      const uint32_t next = w.off + decodedLength(w.off);
      if (next >= end) return; // falls off the end: visit() says so
      record(w.index, w);
      w = {next, w.index + 1, w.region, static_cast<int16_t>(after), true};
    }
  }

  /// The length of the instruction at boundary `off`, which decodeAll decoded: the distance to
  /// the next boundary (procedures tile the code), or to the end of the code. Read from the
  /// operand shape (the end of a LEB128 operand is its first byte below 0x80) without a search
  /// of the boundary bits; a case, which has a count of them, by the search.
  uint32_t decodedLength(uint32_t off) const {
    const uint8_t* c = img_.code.data() + off;
    switch (opInfo(c[0]).shape) {
    case Shape::None: return 1;
    case Shape::Uleb:
    case Shape::Dec: {
      uint32_t n = 1;
      while (c[n] & 0x80)
        ++n;
      return n + 1;
    }
    case Shape::U8: return 2;
    case Shape::U8U8: return 3;
    case Shape::Addr: return 5;
    case Shape::When:
    case Shape::Range: return 9;
    case Shape::Move: return 2u + c[1];
    case Shape::Case: break;
    }
    const size_t nextStart = start_.next(size_t{off} + 1);
    return static_cast<uint32_t>((nextStart == support::kNoBit ? img_.code.size() : nextStart) - off);
  }

  /// Queues the instruction at code offset `target` (already known to be a boundary) with an
  /// empty stack.
  void push(uint32_t target, int32_t region, bool fallthrough) {
    work_.push_back({target, static_cast<uint32_t>(region) << 1 | (fallthrough ? 1u : 0u)});
  }

  /// Records the first path to instruction k.
  void record(size_t k, const Work& w) {
    reached_.set(k);
    if (w.depth != 0) nonEmpty_.set(k);
    if (w.fallthrough) return;
    heads_.set(k);
    if (static_cast<size_t>(w.region) < img_.procs.size()) return;
    whenHead_.set(k);
    if (rootOf(w.region) == w.off)
      rootEntered_[static_cast<size_t>(w.region) - img_.procs.size()] = true;
    else
      otherHeads_[k] = w.region;
  }

  /// The region instruction k was first reached in (k reached, in procedure p).
  int32_t recordedRegion(size_t k, uint32_t p) const {
    const size_t h = heads_.prev(k);
    if (!whenHead_.test(h)) return static_cast<int32_t>(p);
    const auto off = static_cast<uint32_t>(start_.select(h));
    for (bool isBody : {false, true}) {
      const size_t i = whenRoots_.find(isBody, off);
      if (i != SIZE_MAX && rootEntered_[i]) return static_cast<int32_t>(img_.procs.size() + i);
    }
    return otherHeads_.at(h);
  }

  /// The stack depth instruction k was first reached with: 0 at its head, then each
  /// instruction's effect up to k.
  int32_t recordedDepth(size_t k, uint32_t p) const {
    if (!nonEmpty_.test(k)) return 0;
    const auto end = static_cast<uint32_t>(start_.select(k));
    int32_t depth = 0;
    Instr in; // not in_: that is the instruction being reported
    for (auto off = static_cast<uint32_t>(start_.select(heads_.prev(k))); off < end;) {
      instrAt(off, p, in);
      depth += stackEffect(in);
      off += in.length;
    }
    return depth;
  }

  static int32_t pops(const Instr& in) {
    if (in.op == Op::Move) return static_cast<int32_t>(in.moves.size());
    return in.op == Op::Case ? 1 : opInfo(static_cast<uint8_t>(in.op)).pops;
  }
  static int32_t stackEffect(const Instr& in) { return opInfo(static_cast<uint8_t>(in.op)).pushes - pops(in); }

  /// A second path to an instruction: the same region and stack depth as the first.
  bool revisit(const Instr& in, size_t k, const Work& w, uint32_t p) {
    const int32_t region = recordedRegion(k, p);
    if (region != w.region)
      return failAt(in, fmt::format("reached from {} and from {}", regionLabel(region), regionLabel(w.region)));
    const int32_t depth = recordedDepth(k, p);
    if (depth != w.depth)
      return failAt(in, fmt::format("stack depth {} on one path and {} on another", depth, w.depth));
    return true;
  }

  /// The instruction at `off` as the flow needs it, without decoding it again when its operands
  /// are fixed-size: it decoded before, its length is the distance to the next boundary
  /// (procedures tile the code), its operands are where the shape says. LEB128 operands are
  /// decoded.
  const Instr& flowInstr(uint32_t off, uint32_t p) {
    const uint8_t* code = img_.code.data();
    const Shape shape = opInfo(code[off]).shape;
    if (shape == Shape::Case || shape == Shape::Uleb || shape == Shape::Dec) return instrAt(off, p); // LEB128
    in_.op = static_cast<Op>(code[off]);
    in_.offset = off;
    in_.length = decodedLength(off);
    switch (shape) {
    case Shape::U8: in_.u = code[off + 1]; break;
    case Shape::U8U8:
      in_.u = code[off + 1];
      in_.u2 = code[off + 2];
      break;
    case Shape::Addr: in_.addr = support::loadU32(code + off + 1); break;
    case Shape::When:
    case Shape::Range:
      in_.addr = support::loadU32(code + off + 1);
      in_.addr2 = support::loadU32(code + off + 5);
      break;
    case Shape::Move: in_.moves = std::span<const uint8_t>(code + off + 2, code[off + 1]); break;
    default: break;
    }
    return in_;
  }

  bool visit(const Work& w, uint32_t p) {
    const Instr& in = flowInstr(w.off, p);
    const size_t k = w.index;
    if (reached_.test(k)) return revisit(in, k, w, p);
    record(k, w);
    const struct {
      Region kind;
      uint32_t root;
    } ri{kindOf(w.region), rootOf(w.region)};
    const Proc& pr = img_.procs[p];

    // where the instruction may appear
    if (!allowedIn(classOf(in.op), ri.kind)) {
      switch (ri.kind) {
      case Region::Cond:
        return failAt(
            in, fmt::format("not allowed in a WHEN condition (only expressions and cond.end); condition at 0x{:04X}",
                            ri.root));
      case Region::Body: return failAt(in, fmt::format("not allowed in a WHEN body (body at 0x{:04X})", ri.root));
      case Region::Proc: return failAt(in, "reached from the procedure's own code (only WHEN regions end with it)");
      }
    }
    if (ri.kind == Region::Proc) {
      if (in.op == Op::Ret && pr.kind != UnitKind::Sub)
        return failAt(in,
                      fmt::format("in {}, a {} program (only subprograms return)", procLabel(p), kindName(pr.kind)));
      if (in.op == Op::EndImplicit && pr.kind == UnitKind::Sub)
        return failAt(in, fmt::format("in {}, a subprogram (subprograms end with ret)", procLabel(p)));
    }

    // stack
    const int32_t popped = pops(in);
    switch (in.op) {
    case Op::Stmt:
    case Op::StmtSkip:
    case Op::Jump:
    case Op::Call:
    case Op::Ret:
    case Op::End:
    case Op::EndImplicit:
    case Op::BodyEnd:
    case Op::When:
    case Op::GoRange:
    case Op::Kg:
      if (w.depth != 0) return failAt(in, fmt::format("needs an empty stack, has {} value(s)", w.depth));
      break;
    case Op::CondEnd:
      if (w.depth != 1)
        return failAt(in, fmt::format("needs exactly one value (the condition) on the stack, has {}", w.depth));
      break;
    case Op::Aux:
      if (w.depth <= static_cast<int32_t>(in.u2))
        return failAt(
            in, fmt::format("stack underflow: takes the value {} below the top, the stack has {}", in.u2, w.depth));
      break;
    default:
      if (w.depth < popped)
        return failAt(in, fmt::format("stack underflow: pops {} value(s), the stack has {}", popped, w.depth));
      break;
    }
    const int32_t after = w.depth + stackEffect(in);
    if (after > static_cast<int32_t>(kMaxStackDepth))
      return failAt(in, fmt::format("stack depth {} exceeds the limit of {}", after, kMaxStackDepth));

    // successors
    auto jumpTo = [&](uint32_t target) -> bool {
      if (after != 0) return failAt(in, fmt::format("jumps with {} value(s) on the stack (must be empty)", after));
      push(target, w.region, false);
      return true;
    };
    // falling through: the last successor, visited next (or queued, after a WHEN)
    auto next = [&](bool queue = false) -> bool {
      uint32_t n = in.offset + in.length;
      if (n >= pr.entry + pr.size)
        return failAt(in, fmt::format("execution falls off the end of {} (the last instruction must be end, ret, "
                                      "end.implicit or jump; of a WHEN region cond.end or body.end)",
                                      procLabel(p)));
      if (queue) {
        push(n, w.region, true); // after a WHEN: the stack is empty
      } else {
        *next_ = {n, w.index + 1, w.region, static_cast<int16_t>(after), true};
        hasNext_ = true;
      }
      return true;
    };
    switch (in.op) {
    case Op::Jump: return jumpTo(in.addr);
    case Op::JumpFalse:
    case Op::JumpTrue:
    case Op::StmtSkip: return jumpTo(in.addr) && next();
    case Op::Case:
      for (const auto& a : in.arms)
        if (!jumpTo(a.second)) return false;
      if (in.caseDefault != kNoTarget) return jumpTo(in.caseDefault);
      return next();
    case Op::Ret:
    case Op::End:
    case Op::EndImplicit:
    case Op::CondEnd:
    case Op::BodyEnd: return true;
    case Op::Kg: return true; // continues in another procedure: no successor here
    case Op::GoRange: return jumpTo(in.addr) && next();
    case Op::When:
      // The regions go on the work list last, so they are explored first: code that runs
      // into them from the procedure is then reported as a region conflict.
      if (!next(true)) return false;
      push(in.addr, regionFor(Region::Cond, in.addr, p), false);
      push(in.addr2, regionFor(Region::Body, in.addr2, p), false);
      return true;
    default: return next();
    }
  }
};

} // namespace

namespace {
/// Runs the verifier; on success `boundaries` holds the instruction boundaries of the code.
bool verify(const Image& img, ImageError& err, const Layout* layout, support::RankedBits& boundaries) {
  Layout computed;
  if (!layout) {
    try {
      writeImage(img, &computed);
    } catch (const std::invalid_argument&) {
      computed = Layout{}; // offsets then count from the start of each table
    }
    layout = &computed;
  }
  Verifier v(img, *layout, err);
  if (!v.run()) return false;
  boundaries = v.takeBoundaries();
  return true;
}
} // namespace

bool verifyImage(const Image& img, ImageError& err, const Layout* layout) {
  support::RankedBits boundaries;
  return verify(img, err, layout, boundaries);
}

std::optional<VerifiedImage> verifyImage(Image&& img, ImageError& err, const Layout* layout) {
  support::RankedBits boundaries;
  if (!verify(img, err, layout, boundaries)) return std::nullopt;
  return VerifiedImage(std::move(img), std::move(boundaries));
}

} // namespace iso::image
