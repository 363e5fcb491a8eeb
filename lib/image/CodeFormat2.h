//! @file CodeFormat2.h
//! @brief The code section of image format 2 (man/isoimage.5, FORMAT 2 CODE). It holds the
//!        code of format 1 (the instructions of Opcodes.def, which the verifier checks and
//!        isosim runs), coded statement by statement: a statement is either written instruction
//!        by instruction (jump targets relative), or as a reference to one of the 32 statements
//!        of the same procedure seen most recently, with the same instructions (its shape) and
//!        new values for its numbers, R indices, M numbers and jump distances (its fields), each
//!        coded as a zigzag varint: the change from that statement's value or the value itself.
//!        Everything a decoder needs is known from the bytes before, in one linear pass.
//!
//!        decodeCode2 is the one decoder: the reader runs it once, and the verifier, the
//!        disassembler and isosim's translation read the code it gives back. encodeCode2 is its
//!        exact inverse for any bytes: decodeCode2(encodeCode2(code)) == code.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "image/Image.h"

namespace iso::image {

/// One unit of format-2 code: where it starts in the code section and where its first
/// instruction starts in the decoded code.
struct CodeUnit {
  uint32_t decoded = 0;
  uint32_t encoded = 0;
};

namespace code2 {
constexpr uint8_t kRaw = 0x00;                     ///< uleb n, then n bytes of decoded code as they are
constexpr uint8_t kRecall = 0x80;                  ///< 0x80 + j: recent statement j, then every field
constexpr uint8_t kRecallMasked = 0xA0;            ///< 0xA0 + j: recent statement j, a mask, the changed fields
constexpr uint8_t kRecallEnd = 0xC0;               ///< 0xC0..0xFF: no unit
constexpr unsigned kRecent = 32;                   ///< statements kept per procedure, most recent first
constexpr unsigned kMaxFields = 32;                ///< a statement with more fields is never recalled
constexpr unsigned kMaxStatementBytes = 255;       ///< nor one of more decoded bytes
constexpr int64_t kMaxMantissa = int64_t{1} << 33; ///< |mantissa| of a recalled number
/// Decoded code is at most this many times the size of the code section.
constexpr unsigned kMaxExpansion = 256;
} // namespace code2

/// Where the coder starts afresh: every procedure's entry and end (decoded offsets), sorted.
std::vector<uint32_t> codeBoundaries(const std::vector<Proc>& procs);

/// Encodes decoded code. Any bytes encode (those that are no instruction as raw units); units
/// never cross a boundary. Deterministic. Fills `units` when given.
std::vector<uint8_t> encodeCode2(const std::vector<uint8_t>& code, const std::vector<uint32_t>& boundaries,
                                 std::vector<CodeUnit>* units = nullptr);

/// Why a format-2 code section does not decode: where (an offset into its bytes) and what.
struct Code2Error {
  uint32_t at = 0;
  std::string message;
};

/// Decodes a format-2 code section into `out`; nullopt when it decodes, else where and why it
/// does not. Never reads outside [data, data + size). Fills `units` when given.
std::optional<Code2Error> decodeCode2(const uint8_t* data, size_t size, const std::vector<uint32_t>& boundaries,
                                      std::vector<uint8_t>& out, std::vector<CodeUnit>* units = nullptr);

} // namespace iso::image
