//! @file Opcode.cpp
//! @brief Opcode table and decoder.
#include "image/Opcode.h"

#include <array>

#include <fmt/format.h>

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

bool readUleb(const uint8_t* code, size_t end, uint32_t& p, uint64_t& v) {
  v = 0;
  for (int shift = 0; shift < 35; shift += 7) {
    if (p >= end) return false;
    uint8_t b = code[p++];
    v |= static_cast<uint64_t>(b & 0x7F) << shift;
    if (!(b & 0x80)) return true;
  }
  return false; // more than 5 bytes
}

bool readSleb(const uint8_t* code, size_t end, uint32_t& p, int64_t& v) {
  uint64_t r = 0;
  int shift = 0;
  uint8_t b = 0;
  for (; shift < 35; shift += 7) {
    if (p >= end) return false;
    b = code[p++];
    r |= static_cast<uint64_t>(b & 0x7F) << shift;
    if (!(b & 0x80)) break;
  }
  if (b & 0x80) return false;
  shift += 7;
  if (shift < 64 && (b & 0x40)) r |= ~uint64_t{0} << shift;
  v = static_cast<int64_t>(r);
  return true;
}

bool readU32(const uint8_t* code, size_t end, uint32_t& p, uint32_t& v) {
  if (end < 4 || p > end - 4) return false;
  v = static_cast<uint32_t>(code[p]) | static_cast<uint32_t>(code[p + 1]) << 8 |
      static_cast<uint32_t>(code[p + 2]) << 16 | static_cast<uint32_t>(code[p + 3]) << 24;
  p += 4;
  return true;
}
} // namespace

const OpInfo& opInfo(uint8_t byte) { return kTable[byte]; }

const char* sysVarIdName(uint8_t v) {
  // the spellings are string literals of lang/SysVars.def: NUL-terminated
  return lang::isSysVarId(v) ? lang::kSysVars[v].name.data() : "?";
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
  out.arms.clear();
  out.moves.clear();
  uint32_t p = offset + 1;
  switch (info.shape) {
  case Shape::None: break;
  case Shape::Uleb:
    if (!readUleb(code, end, p, out.u)) { why = "truncated or overlong uleb operand"; return false; }
    break;
  case Shape::Dec:
    if (!readSleb(code, end, p, out.s)) { why = "truncated or overlong sleb operand"; return false; }
    break;
  case Shape::U8:
    if (p >= end) { why = "truncated u8 operand"; return false; }
    out.u = code[p++];
    break;
  case Shape::U8U8:
    if (end < 2 || p > end - 2) { why = "truncated u8 operands"; return false; }
    out.u = code[p];
    out.u2 = code[p + 1];
    p += 2;
    break;
  case Shape::Addr:
    if (!readU32(code, end, p, out.addr)) { why = "truncated u32 address operand"; return false; }
    break;
  case Shape::When:
    if (!readU32(code, end, p, out.addr) || !readU32(code, end, p, out.addr2)) {
      why = "truncated u32 address operands";
      return false;
    }
    break;
  case Shape::Case: {
    uint64_t n;
    if (!readUleb(code, end, p, n)) { why = "truncated case count"; return false; }
    if (n == 0 || n > kMaxCaseArms) { why = fmt::format("case count {} outside 1..{}", n, kMaxCaseArms); return false; }
    for (uint64_t i = 0; i < n; ++i) {
      uint64_t c;
      uint32_t t;
      if (!readUleb(code, end, p, c) || !readU32(code, end, p, t)) { why = "truncated case arm"; return false; }
      if (c > 0xFFFFFFFFu) { why = "case constant index too large"; return false; }
      out.arms.emplace_back(static_cast<uint32_t>(c), t);
    }
    if (!readU32(code, end, p, out.caseDefault)) { why = "truncated case default"; return false; }
    break;
  }
  case Shape::Move: {
    if (p >= end) { why = "truncated move count"; return false; }
    uint8_t n = code[p++];
    if (n == 0 || n > kMaxMoveOperands) { why = fmt::format("move count {} outside 1..{}", n, kMaxMoveOperands); return false; }
    if (end - p < n) { why = "truncated move descriptors"; return false; }
    out.moves.assign(code + p, code + p + n);
    p += n;
    break;
  }
  }
  out.length = p - offset;
  return true;
}

void writeUleb(std::vector<uint8_t>& out, uint64_t v) {
  do {
    uint8_t b = v & 0x7F;
    v >>= 7;
    if (v) b |= 0x80;
    out.push_back(b);
  } while (v);
}

void writeSleb(std::vector<uint8_t>& out, int64_t v) {
  bool more = true;
  while (more) {
    uint8_t b = v & 0x7F;
    v >>= 7;
    if ((v == 0 && !(b & 0x40)) || (v == -1 && (b & 0x40))) more = false;
    else b |= 0x80;
    out.push_back(b);
  }
}

void writeU32(std::vector<uint8_t>& out, uint32_t v) {
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<uint8_t>(v >> (8 * i)));
}

void patchU32(std::vector<uint8_t>& out, size_t at, uint32_t v) {
  for (int i = 0; i < 4; ++i) out[at + static_cast<size_t>(i)] = static_cast<uint8_t>(v >> (8 * i));
}

} // namespace iso::image
