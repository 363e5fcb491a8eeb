//! @file Opcode.cpp
//! @brief Opcode table and decoder.
#include "image/Opcode.h"

#include <array>

#include <fmt/format.h>

#include "support/Bytes.h"

namespace iso::image {

namespace {
constexpr std::array<OpInfo, 256> makeTable() {
  std::array<OpInfo, 256> t{};
#define OP(byte, nm, mn, shape, po, pu) t[byte] = OpInfo{true, #nm, mn, Shape::shape, po, pu};
#include "image/Opcodes.def"
  return t;
}
constexpr std::array<OpInfo, 256> kTable = makeTable();

// Compile-time checks: every byte value appears once (a duplicate would be a duplicate enum
// value and fail to compile above), and the decimal pushes are contiguous.
static_assert(static_cast<int>(Op::PushD9) - static_cast<int>(Op::PushD0) == 9);

/// Operands are LEB128 numbers of at most 5 bytes (35 bits). A non-minimal one decodes (the
/// disassembler shows it) and clears Instr::minimal (the verifier rejects it).
constexpr size_t kMaxOperandLeb = 5;

bool leb(support::LebError e, Instr& out) {
  if (e == support::LebError::NonMinimal) out.minimal = false;
  return e == support::LebError::None || e == support::LebError::NonMinimal;
}
} // namespace

const OpInfo& opInfo(uint8_t byte) { return kTable[byte]; }

const char* sysVarIdName(uint8_t v) {
  static const char* names[] = {"$MAX_VELO", "$POS_LIMIT_PLUS", "$POS_LIMIT_MINUS", "$aa_iw",
                                "$aa_fw",    "$aa_in",          "$aa_out",          "$aa_marker"};
  return v < kSysVarCount ? names[v] : "?";
}

const char* moveKindName(uint8_t k) {
  static const char* names[] = {"pos", "posa", "fa", "I", "J", "K", "CR"};
  return k < kMoveKindCount ? names[k] : "?";
}

const char* zAddrName(uint8_t a) {
  static const char* names[] = {"S", "T", "MA", "MB", "MC"};
  return a < kZAddrCount ? names[a] : "?";
}

double decValue(Op op, int64_t mantissa) {
  static const double pow10[] = {1, 10, 100, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9};
  int k = static_cast<int>(op) - static_cast<int>(Op::PushD0);
  return static_cast<double>(mantissa) / pow10[k];
}

namespace {
bool decodeCase(support::ByteCursor& c, Instr& out, std::string& why) {
  uint64_t n;
  if (!leb(c.uleb(n, kMaxOperandLeb), out)) { why = "truncated case count"; return false; }
  if (n == 0 || n > kMaxCaseArms) { why = fmt::format("case count {} outside 1..{}", n, kMaxCaseArms); return false; }
  for (uint64_t i = 0; i < n; ++i) {
    uint64_t k;
    uint32_t t;
    if (!leb(c.uleb(k, kMaxOperandLeb), out) || !c.u32(t)) { why = "truncated case arm"; return false; }
    if (k > 0xFFFFFFFFu) { why = "case constant index too large"; return false; }
    out.arms.emplace_back(static_cast<uint32_t>(k), t);
  }
  if (!c.u32(out.caseDefault)) { why = "truncated case default"; return false; }
  out.length = static_cast<uint32_t>(c.pos() - out.offset);
  return true;
}
} // namespace

bool decode(const uint8_t* code, size_t end, uint32_t offset, Instr& out, std::string& why) {
  if (offset >= end) {
    why = "instruction starts past the end of the code";
    return false;
  }
  const OpInfo& info = kTable[code[offset]];
  if (!info.valid) {
    why = fmt::format("unknown opcode 0x{:02X}", code[offset]);
    return false;
  }
  out.op = static_cast<Op>(code[offset]);
  out.offset = offset;
  out.minimal = true;
  out.arms.clear();
  out.moves.clear();
  support::ByteCursor c(code, offset + size_t{1}, end);
  switch (info.shape) {
  case Shape::None: break;
  case Shape::Uleb:
    if (!leb(c.uleb(out.u, kMaxOperandLeb), out)) { why = "truncated or overlong uleb operand"; return false; }
    break;
  case Shape::Dec:
    if (!leb(c.sleb(out.s, kMaxOperandLeb), out)) { why = "truncated or overlong sleb operand"; return false; }
    break;
  case Shape::U8: {
    uint8_t b;
    if (!c.u8(b)) { why = "truncated u8 operand"; return false; }
    out.u = b;
    break;
  }
  case Shape::U8U8: {
    uint16_t h;
    if (!c.u16(h)) { why = "truncated u8 operands"; return false; }
    out.u = h & 0xFF;
    out.u2 = static_cast<uint8_t>(h >> 8);
    break;
  }
  case Shape::Addr:
    if (!c.u32(out.addr)) { why = "truncated u32 address operand"; return false; }
    break;
  case Shape::When:
    if (!c.u32(out.addr) || !c.u32(out.addr2)) { why = "truncated u32 address operands"; return false; }
    break;
  case Shape::Case: return decodeCase(c, out, why);
  case Shape::Move: {
    uint8_t n;
    if (!c.u8(n)) { why = "truncated move count"; return false; }
    if (n == 0 || n > kMaxMoveOperands) { why = fmt::format("move count {} outside 1..{}", n, kMaxMoveOperands); return false; }
    if (c.left() < n) { why = "truncated move descriptors"; return false; }
    out.moves.assign(code + c.pos(), code + c.pos() + n);
    c.skip(n);
    break;
  }
  }
  out.length = static_cast<uint32_t>(c.pos() - offset);
  return true;
}

void writeUleb(std::vector<uint8_t>& out, uint64_t v) { support::ByteWriter(out).uleb(v); }
void writeSleb(std::vector<uint8_t>& out, int64_t v) { support::ByteWriter(out).sleb(v); }
void writeU32(std::vector<uint8_t>& out, uint32_t v) { support::ByteWriter(out).u32(v); }
void patchU32(std::vector<uint8_t>& out, size_t at, uint32_t v) { support::ByteWriter(out).patchU32(at, v); }

} // namespace iso::image
