//! @file InstructionStream.h
//! @brief A verified image's code decoded once into a flat instruction array for the
//!        interpreter: a plain translation (the verifier has proved every operand, index and
//!        target; nothing is checked here).
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <new>
#include <string>
#include <vector>

#include "support/Memory.h"

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
                         ///< code; Case: first arm
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

/// The allocator of the instruction array, which takes 16 bytes per instruction (64 MiB for a
/// million motion blocks) and is written once, front to back: an array of 4 MiB or more is
/// aligned to 2 MiB and, on Linux, asks for transparent huge pages (madvise), so that filling
/// it takes one page fault per 2 MiB instead of one per 4 KiB. Smaller ones are plain
/// allocations.
template <class T> struct BigArrayAllocator {
  using value_type = T;
  static constexpr size_t kHugePage = size_t{2} << 20;
  static constexpr size_t kHugeFrom = size_t{4} << 20; ///< bytes

  BigArrayAllocator() = default;
  template <class U> BigArrayAllocator(const BigArrayAllocator<U>&) {}

  T* allocate(size_t n) {
    if (n > SIZE_MAX / sizeof(T) - kHugePage) throw std::bad_array_new_length();
    const size_t bytes = n * sizeof(T);
    if (bytes < kHugeFrom) return static_cast<T*>(::operator new(bytes));
    const size_t rounded = (bytes + kHugePage - 1) / kHugePage * kHugePage;
    void* p = std::aligned_alloc(kHugePage, rounded);
    if (!p) throw std::bad_alloc();
    support::adviseHugePages(p, rounded);
    return static_cast<T*>(p);
  }
  void deallocate(T* p, size_t n) {
    if (n * sizeof(T) < kHugeFrom)
      ::operator delete(p);
    else
      std::free(p);
  }
  template <class U> bool operator==(const BigArrayAllocator<U>&) const { return true; }
};

/// The instruction stream the interpreter runs: the code as `Ins`, the case arms, where each
/// procedure starts.
struct InstructionStream {
  std::vector<Ins, BigArrayAllocator<Ins>> code;
  std::vector<CaseArm> arms;
  std::vector<uint32_t> procEntry; ///< instruction index of each procedure's entry (ascending)
  /// The procedure an instruction belongs to.
  uint32_t procOf(uint32_t ins) const;
  /// The condition code starting here reads $aa_iw.
  bool readsIw(uint32_t condIndex) const;
};

/// Translates the code of a verified image.
InstructionStream buildInstructionStream(const image::VerifiedImage& img);

} // namespace iso::sim
