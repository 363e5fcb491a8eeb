//! @file Opcode.cpp
//! @brief Opcode table and decoder.
#include "image/Opcode.h"

#include <array>

#include <fmt/format.h>

#include "support/Bytes.h"

namespace iso::image {

namespace {
// Compile-time checks: every byte value appears once (a duplicate would be a duplicate enum
// value and fail to compile above), and the decimal pushes are contiguous.
static_assert(static_cast<int>(Op::PushD9) - static_cast<int>(Op::PushD0) == 9);

} // namespace

const char* sysVarIdName(uint8_t v) {
  // the spellings are string literals of lang/SysVars.def: NUL-terminated
  return lang::isSysVarId(v) ? lang::kSysVars[v].name.data() : "?";
}

const char* moveKindName(uint8_t k) {
  static const char* names[] = {"pos", "posa", "fa", "I", "J", "K", "CR"};
  return k < kMoveKindCount ? names[k] : "?";
}

const char* zAddrName(uint8_t a) {
  static const char* names[] = {"S", "T", "MA", "MB", "MC", "TA", "TB"};
  return a < kZAddrCount ? names[a] : "?";
}

double decValue(Op op, int64_t mantissa) {
  static const double pow10[] = {1, 10, 100, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9};
  int k = static_cast<int>(op) - static_cast<int>(Op::PushD0);
  return static_cast<double>(mantissa) / pow10[k];
}

namespace detail {

DecodeStatus decodeCase(support::ByteCursor& c, Instr& out) {
  uint64_t n;
  if (!operandLeb(c.uleb(n, kMaxOperandLeb), out)) return DecodeStatus::failure("truncated case count");
  if (n == 0 || n > kMaxCaseArms) return DecodeStatus::badCount("case", n, kMaxCaseArms);
  for (uint64_t i = 0; i < n; ++i) {
    uint64_t k;
    uint32_t t;
    if (!operandLeb(c.uleb(k, kMaxOperandLeb), out) || !c.u32(t)) return DecodeStatus::failure("truncated case arm");
    if (k > 0xFFFFFFFFu) return DecodeStatus::failure("case constant index too large");
    out.arms.emplace_back(static_cast<uint32_t>(k), t);
  }
  if (!c.u32(out.caseDefault)) return DecodeStatus::failure("truncated case default");
  return {};
}

DecodeStatus decodeMove(support::ByteCursor& c, Instr& out) {
  uint8_t n;
  if (!c.u8(n)) return DecodeStatus::failure("truncated move count");
  if (n == 0 || n > kMaxMoveOperands) return DecodeStatus::badCount("move", n, kMaxMoveOperands);
  if (c.left() < n) return DecodeStatus::failure("truncated move descriptors");
  out.moves = std::span<const uint8_t>(c.data() + c.pos(), n);
  c.skip(n);
  return {};
}

} // namespace detail

std::string DecodeStatus::message() const {
  switch (kind_) {
  case Kind::Ok: return {};
  case Kind::Text: return text_;
  case Kind::Count: return fmt::format("{} count {} outside 1..{}", text_, n_, max_);
  case Kind::Opcode: return fmt::format("unknown opcode 0x{:02X}", byte_);
  }
  return {};
}

void writeUleb(std::vector<uint8_t>& out, uint64_t v) { support::ByteWriter(out).uleb(v); }
void writeSleb(std::vector<uint8_t>& out, int64_t v) { support::ByteWriter(out).sleb(v); }
void writeU32(std::vector<uint8_t>& out, uint32_t v) { support::ByteWriter(out).u32(v); }
void patchU32(std::vector<uint8_t>& out, size_t at, uint32_t v) { support::ByteWriter(out).patchU32(at, v); }

} // namespace iso::image
