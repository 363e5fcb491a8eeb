//! @file Opcode.h
//! @brief Opcodes of the image (from Opcodes.def) and a bounds-checked instruction decoder.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace iso::image {

enum class Op : uint8_t {
#define OP(byte, name, mn, shape, pops, pushes) name = byte,
#include "image/Opcodes.def"
};

enum class Shape : uint8_t { None, Uleb, Dec, U8, U8U8, Addr, Case, Move, When };

struct OpInfo {
  bool valid = false;
  const char* name = nullptr;     ///< "PushConst"
  const char* mnemonic = nullptr; ///< "push.const"
  Shape shape = Shape::None;
  int pops = 0;                   ///< -1: given by the operands
  int pushes = 0;
};
/// Info for any byte value; `valid` is false for bytes that are no opcode.
const OpInfo& opInfo(uint8_t byte);

/// System variable numbers used by LoadAxVar (0..4) and LoadIo/StoreIo (5..7).
enum class SysVarId : uint8_t { MaxVelo = 0, PosLimitPlus, PosLimitMinus, AaIw, AaFw, AaIn, AaOut, AaMarker };
const char* sysVarIdName(uint8_t v);
constexpr uint8_t kSysVarCount = 8;

/// Move descriptor kinds (high nibble); the low nibble is an index into the image's axis table
/// (for Target/TargetNb/Fa) and 0 for the arc words.
enum class MoveKind : uint8_t { Target = 0, TargetNb = 1, Fa = 2, I = 3, J = 4, K = 5, CR = 6 };
constexpr uint8_t kMoveKindCount = 7;
const char* moveKindName(uint8_t k);

/// ZWord address codes (dialect z32 words without a model).
enum class ZAddr : uint8_t { S = 0, T, MA, MB, MC };
constexpr uint8_t kZAddrCount = 5;
const char* zAddrName(uint8_t a);

constexpr uint32_t kNoTarget = 0xFFFFFFFFu;
constexpr unsigned kMaxMoveOperands = 32;
constexpr unsigned kMaxCaseArms = 255;

/// One decoded instruction. Operands are filled according to the shape.
struct Instr {
  Op op = Op::Stmt;
  uint32_t offset = 0;   ///< of the opcode byte
  uint32_t length = 0;   ///< total bytes
  bool minimal = true;   ///< every LEB128 operand has its minimal encoding (the verifier's rule)
  uint64_t u = 0;        ///< Uleb / U8 / first U8 of U8U8
  uint8_t u2 = 0;        ///< second byte of U8U8
  int64_t s = 0;         ///< Dec mantissa
  uint32_t addr = 0;     ///< Addr; When: condition
  uint32_t addr2 = 0;    ///< When: body
  uint32_t caseDefault = kNoTarget;
  std::vector<std::pair<uint32_t, uint32_t>> arms; ///< Case: (constant index, target)
  std::vector<uint8_t> moves;                       ///< Move descriptors
};

/// Decodes the instruction at `offset` of `code` (bounded by `end`). On failure returns false
/// and sets `why` (e.g. "truncated uleb operand", "unknown opcode 0xEE"); never reads past end.
/// LEB128 operands are read by support::ByteCursor (at most 5 bytes); a non-minimal one
/// decodes with `minimal` false.
bool decode(const uint8_t* code, size_t end, uint32_t offset, Instr& out, std::string& why);

/// The value of a PushD<k> instruction: mantissa / 10^k, computed as one correctly rounded
/// division, so it equals the decimal literal it came from.
double decValue(Op op, int64_t mantissa);
inline bool isPushDec(Op op) { return op >= Op::PushD0 && op <= Op::PushD9; }

// Appending to code (support::ByteWriter on a vector).
void writeUleb(std::vector<uint8_t>& out, uint64_t v);
void writeSleb(std::vector<uint8_t>& out, int64_t v);
void writeU32(std::vector<uint8_t>& out, uint32_t v);
void patchU32(std::vector<uint8_t>& out, size_t at, uint32_t v);

} // namespace iso::image
