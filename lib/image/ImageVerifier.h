//! @file ImageVerifier.h
//! @brief The meaning half of loading an image: proves that the interpreter can run the code
//!        without checking anything again (wabt's validator, for our format). Rules: man/isoimage.5,
//!        VERIFIER RULES.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>

#include "image/Image.h"
#include "image/ImageReader.h"
#include "lang/Limits.h"
#include "support/BitSet.h"

namespace iso::image {

/// The value stack never holds more values than this in a verified image.
constexpr unsigned kMaxStackDepth = 256;
/// R parameters R1..R<lang::kMaxRIndex> (SPEC §3.1).
constexpr auto kMaxRIndex = static_cast<uint32_t>(lang::kMaxRIndex);
/// The axis table's size limit (a Move descriptor's axis is a nibble).
constexpr unsigned kMaxAxes = lang::kMaxImageAxes;

/// Checks every rule; on the first violation returns false with the file offset (from
/// `layout`, as filled by readImage; without one, the layout the writer would produce) and the
/// reason. Deterministic: the same image always gives the same first error.
///
/// What a verified image guarantees to the interpreter:
/// - every instruction reachable from a procedure entry, a WHEN condition or a WHEN body
///   decodes, and its operands are in range (constants, R indices 1..kMaxRIndex, axes, system
///   variables, procedures to call, Move descriptors);
/// - control stays inside its region: the procedure's own code, or one WHEN condition (ends
///   with cond.end, one value on the stack), or one WHEN body (ends with body.end); no
///   instruction falls through past the end of its procedure;
/// - the stack depth at each instruction is the same on every path, never negative, at most
///   kMaxStackDepth, and zero at stmt/stmt.skip, jump targets, calls and terminators;
/// - `entries[0]` is the main program; the other entries are semi-automatic programs.
bool verifyImage(const Image& img, ImageError& err, const Layout* layout = nullptr);

class VerifiedImage;

/// The same check; on success the image moves into the result, which the interpreter runs
/// without checking anything again. On failure `img` is left as it was (a listing can still
/// show it) and `err` says why.
std::optional<VerifiedImage> verifyImage(Image&& img, ImageError& err, const Layout* layout = nullptr);

/// An image that passed every rule above. Only verifyImage makes one, and it cannot be
/// changed afterwards: holding one is the proof (isosim takes this type).
class VerifiedImage {
public:
  const Image& image() const { return img_; }
  const Image* operator->() const { return &img_; }
  /// Instructions in the code (what a translation of it holds).
  size_t instructions() const { return boundaries_.count(); }
  /// The code offsets at which the instructions start, as the verifier decoded them (every
  /// procedure from its entry to its end), with rank and select: a translation needs not find
  /// them again.
  const support::RankedBits& boundaries() const { return boundaries_; }

private:
  VerifiedImage(Image&& img, support::RankedBits&& boundaries)
      : img_(std::move(img)), boundaries_(std::move(boundaries)) {}
  friend std::optional<VerifiedImage> verifyImage(Image&& img, ImageError& err, const Layout* layout);
  Image img_;
  support::RankedBits boundaries_;
};

} // namespace iso::image
