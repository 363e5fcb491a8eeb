//! @file InstructionStream.h
//! @brief A verified image's code as the interpreter's instructions, decoded window by window
//!        on demand: a plain translation (the verifier has proved every operand, index and
//!        target; nothing is checked here).
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "image/Image.h"
#include "image/ImageVerifier.h"
#include "image/Opcode.h"

namespace iso::sim {

constexpr uint32_t kNoIndex = 0xFFFFFFFFu;
/// Pseudo-opcode appended after each procedure: reaching it means the code ran off the end.
constexpr uint8_t kOpFallOff = 0xFF;

/// One decoded instruction, 16 bytes. Targets are instruction indices (not byte offsets).
struct Ins {
  image::Op op = image::Op::Stmt;
  uint8_t a8 = 0; ///< U8 operand / first of U8U8 (system variable id, z-address)
  uint8_t b8 = 0; ///< second of U8U8 (image axis index)
  uint8_t pad = 0;
  uint32_t a = kNoIndex; ///< Jump/JumpFalse/JumpTrue/StmtSkip: target; Call, Kg: procedure; GoRange: start;
                         ///< AxisCtl, Origin, Nm: the operand; LoadUser/StoreUser: name string;
                         ///< When: condition; LoadR/StoreR: R index; Move: byte offset of its descriptors in the image
                         ///< code; Case: its first arm in its window (InstructionStream::arms)
  uint32_t b = kNoIndex; ///< When: body; GoRange: end (its statement header); Move, Case: count
  uint32_t c = kNoIndex; ///< Stmt/StmtSkip/When: index into Image::lines (kNoIndex: none);
                         ///< Case: default target (kNoIndex: none)

  /// Pushes, M, MNb and MSpecial carry their value (the M number: exact below 2^53) in the
  /// bits of b and c, which they do not use otherwise: no value table to look up.
  void setValue(double v) {
    const auto u = std::bit_cast<uint64_t>(v);
    b = static_cast<uint32_t>(u);
    c = static_cast<uint32_t>(u >> 32);
  }
  double value() const { return std::bit_cast<double>(static_cast<uint64_t>(c) << 32 | b); }
};
static_assert(sizeof(Ins) == 16);

struct CaseArm {
  double value = 0;
  uint32_t target = 0;
};

/// The instructions the interpreter runs, by instruction index: instruction k of procedure p
/// (its code in order, then a fall-off sentinel) is index procEntry[p] + k. They are decoded
/// from the verified image's code on demand, a window of kWindow instructions at a time, into
/// a small cache of kSlots windows: the memory is the same whatever the size of the program,
/// and the image's code is the only copy of it. Jump targets are instruction indices (the
/// rank of the target among the instruction boundaries the verifier found, plus the
/// procedure's sentinels before it).
class InstructionStream {
public:
  static constexpr uint32_t kWindow = 1024; ///< instructions decoded at once
  static constexpr size_t kSlots = 32;      ///< windows kept (a least recently decoded one goes)

  InstructionStream() = default;
  /// The code of a verified image (it must outlive the stream), decoded `window` instructions
  /// at a time into at most `slots` windows (tests try other sizes).
  explicit InstructionStream(const image::VerifiedImage& img, uint32_t window = kWindow, size_t slots = kSlots);
  /// Instructions given decoded (tests): `code` holds every procedure's, sentinels included.
  InstructionStream(std::vector<Ins> code, std::vector<uint32_t> entries);
  InstructionStream(const InstructionStream&) = delete;
  InstructionStream& operator=(const InstructionStream&) = delete;

  /// Instruction i (i < size()). The reference stays valid until the next call of operator[]
  /// or arms() (a copy is safe across them).
  const Ins& operator[](uint32_t i) const {
    if (i - cur_.base < cur_.n) return cur_.ins[i - cur_.base];
    return load(i);
  }
  /// Instructions, sentinels included.
  size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  /// The arms of the case at index i (Ins::b of them; Ins::a is their place in its window).
  const CaseArm* arms(uint32_t i) const;

  std::vector<uint32_t> procEntry; ///< instruction index of each procedure's entry (ascending)
  /// The procedure an instruction belongs to.
  uint32_t procOf(uint32_t ins) const;
  /// The condition code starting here reads $aa_iw.
  bool readsIw(uint32_t condIndex) const;

private:
  struct Window {
    uint32_t base = kNoIndex;
    uint64_t stamp = 0;
    std::vector<Ins> ins;
    std::vector<CaseArm> arms;
  };
  struct Current {
    uint32_t base = 0;
    uint32_t n = 0;
    const Ins* ins = nullptr;
    const CaseArm* arms = nullptr;
  };
  const image::VerifiedImage* img_ = nullptr;
  size_t size_ = 0;
  uint32_t window_ = kWindow;
  size_t maxSlots_ = kSlots;
  std::vector<Ins> given_; ///< the decoded instructions of the test constructor
  mutable Current cur_;    ///< the window used last
  mutable std::vector<Window> slots_;
  mutable uint64_t clock_ = 0;

  const Ins& load(uint32_t i) const;
  void decode(uint32_t base, Window& w) const;
};

} // namespace iso::sim
