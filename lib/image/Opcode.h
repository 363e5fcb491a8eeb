//! @file Opcode.h
//! @brief Opcodes of the image (from Opcodes.def) and a bounds-checked instruction decoder.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "lang/GCodes.h"
#include "lang/Limits.h"
#include "lang/SysVars.h"
#include "lang/Z32GCodes.h"
#include "support/Bytes.h"

namespace iso::image {

enum class Op : uint8_t {
#define OP(byte, name, mn, shape, pops, pushes, cls) name = byte,
#include "image/Opcodes.def"
};

enum class Shape : uint8_t { None, Uleb, Dec, U8, U8U8, Addr, Case, Move, When, Range };

/// Where the verifier allows an instruction and how the flow leaves it (Opcodes.def, Classes).
enum class OpClass : uint8_t { Expr, Effect, Flow, Control, CondEnd, BodyEnd };

struct OpInfo {
  bool valid = false;
  const char* name = nullptr;     ///< "PushConst"
  const char* mnemonic = nullptr; ///< "push.const"
  Shape shape = Shape::None;
  int pops = 0; ///< -1: given by the operands
  int pushes = 0;
  OpClass cls = OpClass::Expr;
};
namespace detail {
constexpr std::array<OpInfo, 256> makeOpTable() {
  std::array<OpInfo, 256> t{};
#define OP(byte, nm, mn, shape, po, pu, cl) t[byte] = OpInfo{true, #nm, mn, Shape::shape, po, pu, OpClass::cl};
#include "image/Opcodes.def"
  return t;
}
inline constexpr std::array<OpInfo, 256> kOpTable = makeOpTable();
} // namespace detail

/// Info for any byte value; `valid` is false for bytes that are no opcode.
inline const OpInfo& opInfo(uint8_t byte) { return detail::kOpTable[byte]; }

/// System variable numbers used by LoadAxVar (0..4) and LoadIo/StoreIo (5..7): the values of
/// lang/SysVars.def.
using SysVarId = lang::SysVar;
const char* sysVarIdName(uint8_t v);
constexpr auto kSysVarCount = static_cast<uint8_t>(lang::kSysVarCount);

/// The opcode that sets the modal state of G`g`; nullopt for G04 (a dwell is Op::Dwell).
constexpr std::optional<Op> modalOp(lang::GCode g) {
  switch (g) {
  case lang::GCode::G0: return Op::G0;
  case lang::GCode::G1: return Op::G1;
  case lang::GCode::G2: return Op::G2;
  case lang::GCode::G3: return Op::G3;
  case lang::GCode::G4: return std::nullopt;
  case lang::GCode::G17: return Op::G17;
  case lang::GCode::G18: return Op::G18;
  case lang::GCode::G19: return Op::G19;
  case lang::GCode::G60: return Op::G60;
  case lang::GCode::G64: return Op::G64;
  case lang::GCode::G90: return Op::G90;
  case lang::GCode::G91: return Op::G91;
  }
  return std::nullopt;
}
/// The G function a modal opcode sets (G0..G91), or nullopt for any other opcode.
namespace detail {
/// gCodeOf as a table by opcode byte (-1: not a modal G), built once at compile time.
constexpr std::array<int8_t, 256> kGCodeByOp = [] {
  std::array<int8_t, 256> t{};
  t.fill(-1);
  for (const lang::GInfo& g : lang::kGCodes)
    if (auto op = modalOp(g.id)) t[static_cast<uint8_t>(*op)] = static_cast<int8_t>(g.id);
  return t;
}();
} // namespace detail
constexpr std::optional<lang::GCode> gCodeOf(Op op) {
  const int8_t g = detail::kGCodeByOp[static_cast<uint8_t>(op)];
  if (g < 0) return std::nullopt;
  return static_cast<lang::GCode>(g);
}

/// Move descriptor kinds (high nibble); the low nibble is an index into the image's axis table
/// (for Target/TargetNb/Fa) and 0 for the arc words.
enum class MoveKind : uint8_t { Target = 0, TargetNb = 1, Fa = 2, I = 3, J = 4, K = 5, CR = 6 };
constexpr uint8_t kMoveKindCount = 7;
const char* moveKindName(uint8_t k);

/// ZWord address codes (dialect z32: S and T set the spindle speed and the programmed tool; TA
/// mounts the actual tool, TB reports the next one; MA MB MC are Aux words).
enum class ZAddr : uint8_t { S = 0, T, MA, MB, MC, TA, TB };
constexpr uint8_t kZAddrCount = 7;
/// Aux words (z32 MA MB MC): the first operand of Aux.
constexpr uint8_t kAuxWordCount = 3;
const char* zAddrName(uint8_t a);
/// "MA", "MB" or "MC" for an aux word (an out-of-range word reads as MA).
inline const char* auxWordName(uint64_t w) {
  return zAddrName(static_cast<uint8_t>(static_cast<uint8_t>(ZAddr::MA) + (w < kAuxWordCount ? w : 0)));
}

/// Dialect z32 (SPEC §4.7): PAR[0..kParCount-1], PAL[0..kPalCount-1], origins 0..kMaxOrigin.
constexpr uint32_t kParCount = lang::kMaxParIndex + 1;
constexpr uint32_t kPalCount = lang::kMaxPalIndex + 1;
constexpr uint32_t kMaxOrigin = lang::kMaxOrigin;
/// The G codes that `nm` may carry: valid Z32 that isotools does not model.
constexpr bool isNotModelledG(uint64_t g) {
  const lang::Z32GCode* z = g <= 1000 ? lang::findZ32G(static_cast<int>(g)) : nullptr;
  return z && !z->modelled;
}
/// The operand of axis.ctl: the axis mask (bit k = image axis k; 0 = every axis) and on (G28)
/// or off (G29).
constexpr uint64_t axisCtlOperand(uint32_t mask, bool on) { return uint64_t{mask} << 1 | (on ? 1u : 0u); }
constexpr uint32_t axisCtlMask(uint64_t operand) { return static_cast<uint32_t>(operand >> 1); }
constexpr bool axisCtlOn(uint64_t operand) { return (operand & 1) != 0; }

constexpr uint32_t kNoTarget = 0xFFFFFFFFu;
constexpr unsigned kMaxMoveOperands = 32;
constexpr unsigned kMaxCaseArms = 255;

/// One decoded instruction. Operands are filled according to the shape.
struct Instr {
  Op op = Op::Stmt;
  uint32_t offset = 0; ///< of the opcode byte
  uint32_t length = 0; ///< total bytes
  bool minimal = true; ///< every LEB128 operand has its minimal encoding (the verifier's rule)
  uint64_t u = 0;      ///< Uleb / U8 / first U8 of U8U8
  uint8_t u2 = 0;      ///< second byte of U8U8
  int64_t s = 0;       ///< Dec mantissa
  uint32_t addr = 0;   ///< Addr; When: condition; Range: start
  uint32_t addr2 = 0;  ///< When: body; Range: end
  uint32_t caseDefault = kNoTarget;
  std::vector<std::pair<uint32_t, uint32_t>> arms; ///< Case: (constant index, target)
  std::span<const uint8_t> moves;                  ///< Move descriptors (in the decoded code)
};

/// Whether an instruction decoded, and if not why: a fixed text, a count out of its range or an
/// unknown opcode. Trivially copyable; the message is formatted only when asked for, since the
/// verifier and isosim's translation decode every instruction.
class DecodeStatus {
public:
  constexpr DecodeStatus() = default; ///< decoded
  static constexpr DecodeStatus failure(const char* text) { return DecodeStatus(Kind::Text, text, 0, 0, 0); }
  static constexpr DecodeStatus badCount(const char* what, uint64_t n, unsigned max) {
    return DecodeStatus(Kind::Count, what, n, max, 0);
  }
  static constexpr DecodeStatus unknownOpcode(uint8_t byte) { return DecodeStatus(Kind::Opcode, nullptr, 0, 0, byte); }
  constexpr bool ok() const { return kind_ == Kind::Ok; }
  constexpr explicit operator bool() const { return ok(); }
  /// e.g. "truncated uleb operand", "case count 0 outside 1..1024", "unknown opcode 0xEE".
  std::string message() const;

private:
  enum class Kind : uint8_t { Ok, Text, Count, Opcode };
  constexpr DecodeStatus(Kind k, const char* text, uint64_t n, unsigned max, uint8_t byte)
      : text_(text), n_(n), max_(max), kind_(k), byte_(byte) {}
  const char* text_ = nullptr;
  uint64_t n_ = 0;
  unsigned max_ = 0;
  Kind kind_ = Kind::Ok;
  uint8_t byte_ = 0;
};

/// Decodes the instruction at `offset` of `code` (bounded by `end`) into `out`, or says why it
/// does not decode; never reads past end. LEB128 operands are read by support::ByteCursor (at
/// most 5 bytes); a non-minimal one decodes with `minimal` false.
inline DecodeStatus decode(const uint8_t* code, size_t end, uint32_t offset, Instr& out);

/// The value of a PushD<k> instruction: mantissa / 10^k, computed as one correctly rounded
/// division, so it equals the decimal literal it came from.
double decValue(Op op, int64_t mantissa);
inline bool isPushDec(Op op) { return op >= Op::PushD0 && op <= Op::PushD9; }

// Appending to code (support::ByteWriter on a vector).
void writeUleb(std::vector<uint8_t>& out, uint64_t v);
void writeSleb(std::vector<uint8_t>& out, int64_t v);
void writeU32(std::vector<uint8_t>& out, uint32_t v);
void patchU32(std::vector<uint8_t>& out, size_t at, uint32_t v);

namespace detail {
/// Operands are LEB128 numbers of at most 5 bytes (35 bits).
constexpr size_t kMaxOperandLeb = 5;
/// A non-minimal operand decodes (the disassembler shows it) and clears Instr::minimal (the
/// verifier rejects it).
inline bool operandLeb(support::LebError e, Instr& out) {
  if (e == support::LebError::NonMinimal) out.minimal = false;
  return e == support::LebError::None || e == support::LebError::NonMinimal;
}
// Out of line: the two variable-length shapes.
DecodeStatus decodeCase(support::ByteCursor& c, Instr& out);
DecodeStatus decodeMove(support::ByteCursor& c, Instr& out);
} // namespace detail

// Inline: the verifier and the translation for isosim decode every instruction.
[[gnu::always_inline]] inline DecodeStatus decode(const uint8_t* code, size_t end, uint32_t offset, Instr& out) {
  using namespace detail;
  if (offset >= end) return DecodeStatus::failure("instruction starts past the end of the code");
  const OpInfo& info = kOpTable[code[offset]];
  if (!info.valid) return DecodeStatus::unknownOpcode(code[offset]);
  out.op = static_cast<Op>(code[offset]);
  out.offset = offset;
  out.minimal = true;
  if (!out.arms.empty()) out.arms.clear();
  out.moves = {};
  support::ByteCursor c(code, offset + size_t{1}, end);
  switch (info.shape) {
  case Shape::None: break;
  case Shape::Uleb:
    if (!operandLeb(c.uleb(out.u, kMaxOperandLeb), out))
      return DecodeStatus::failure("truncated or overlong uleb operand");
    break;
  case Shape::Dec:
    if (!operandLeb(c.sleb(out.s, kMaxOperandLeb), out))
      return DecodeStatus::failure("truncated or overlong sleb operand");
    break;
  case Shape::U8: {
    uint8_t b;
    if (!c.u8(b)) return DecodeStatus::failure("truncated u8 operand");
    out.u = b;
    break;
  }
  case Shape::U8U8: {
    uint16_t h;
    if (!c.u16(h)) return DecodeStatus::failure("truncated u8 operands");
    out.u = h & 0xFF;
    out.u2 = static_cast<uint8_t>(h >> 8);
    break;
  }
  case Shape::Addr:
    if (!c.u32(out.addr)) return DecodeStatus::failure("truncated u32 address operand");
    break;
  case Shape::When:
  case Shape::Range:
    if (!c.u32(out.addr) || !c.u32(out.addr2)) return DecodeStatus::failure("truncated u32 address operands");
    break;
  case Shape::Case:
    if (DecodeStatus st = decodeCase(c, out); !st) return st;
    break;
  case Shape::Move:
    if (DecodeStatus st = decodeMove(c, out); !st) return st;
    break;
  }
  out.length = static_cast<uint32_t>(c.pos() - offset);
  return {};
}

} // namespace iso::image
