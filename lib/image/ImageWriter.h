//! @file ImageWriter.h
//! @brief The byte format of an image (constants shared with ImageReader) and its writer.
//!        The format is specified in man/isoimage.5; keep the two in step.
//!
//! Layout (all integers little-endian; uleb/sleb = LEB128, minimal encoding):
//!   0x00  8  magic "ISOB\r\n\x1A\n"
//!   0x08  u16 format version (Image::kFormatVersion)
//!   0x0A  u16 section count
//!   0x0C  u32 flags (bit 0: stripped)
//!   0x10  u32 total size of the image in bytes
//!   0x14  u32 CRC-32 (IEEE) of the whole image computed with these four bytes as zero
//!   0x18  section table: count x { u16 id, u16 flags (bit 0: optional), u32 offset, u32 size }
//!   then the sections, in table order, without gaps, the last one ending at the total size.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <iterator>
#include <span>
#include <string>
#include <vector>

#include "image/CodeFormat2.h"
#include "image/Image.h"

namespace iso::image {

/// X(id, Name, "name", optional): the sections of format version 1, in the order they are
/// written. `optional` is the value of the optional bit written (and required) for the section.
#define ISO_IMAGE_SECTIONS(X)                                                                                          \
  X(1, Strings, "strings", false)                                                                                      \
  X(2, Constants, "constants", false)                                                                                  \
  X(3, Code, "code", false)                                                                                            \
  X(4, Procs, "procs", false)                                                                                          \
  X(5, Entries, "entries", false)                                                                                      \
  X(6, Axes, "axes", false)                                                                                            \
  X(7, Lines, "lines", true)

enum class SectionId : uint16_t {
#define X(id, name, str, opt) name = id,
  ISO_IMAGE_SECTIONS(X)
#undef X
};
constexpr unsigned kSectionIdMax = 7; ///< highest known section id
/// "strings", ..., or nullptr for an unknown id.
const char* sectionName(uint16_t id);
/// The optional bit a known section carries.
bool sectionOptional(uint16_t id);

inline constexpr std::array<uint8_t, 8> kMagic = {'I', 'S', 'O', 'B', 0x0D, 0x0A, 0x1A, 0x0A};
constexpr uint32_t kHeaderSize = 24;
constexpr uint32_t kOffVersion = 8;
constexpr uint32_t kOffSectionCount = 10;
constexpr uint32_t kOffFlags = 12;
constexpr uint32_t kOffTotalSize = 16;
constexpr uint32_t kOffCrc = 20;
constexpr uint32_t kSectionEntrySize = 12;
constexpr uint32_t kMaxSections = 64;
constexpr uint16_t kSectionFlagOptional = 1;
constexpr uint32_t kKnownImageFlags = Image::kFlagStripped | Image::kFlagZ32;

/// Line table: low two bits of the "file and N" field.
enum class LineN : uint8_t { None = 0, Integer = 1, Double = 2 };

/// Where things are in the bytes of an image: file offsets of each section's payload and of
/// each record. Filled by the writer and by the reader; the verifier uses it to report file
/// offsets.
struct Layout {
  std::array<uint32_t, kSectionIdMax + 1> section{};               ///< payload offset by id (0: absent)
  std::array<uint32_t, kSectionIdMax + 1> sectionSize{};           ///< payload size by id
  uint32_t table = kHeaderSize;                                    ///< offset of the section table
  std::vector<uint32_t> strings, constants, procs, entries, lines; ///< record offsets
  uint32_t axes = 0;                                               ///< offset of the first axis letter

  uint32_t of(SectionId id) const { return section[static_cast<size_t>(id)]; }
  /// Format 2: the code section and the procedure boundaries, kept to find the unit of a code
  /// offset when a message needs it (decoded again then: nothing is kept per unit). The reader
  /// copies the section into code2, or, with borrowCode set before it runs, only points at it
  /// in the caller's bytes (code2View), which must then outlive every use of the layout.
  std::vector<uint8_t> code2;
  std::span<const uint8_t> code2View;
  std::vector<uint32_t> bounds2;
  bool borrowCode = false;
  /// The format-2 code section (held or borrowed; empty for format 1).
  std::span<const uint8_t> codeSection() const { return code2.empty() ? code2View : std::span<const uint8_t>(code2); }

  /// File offset of a code offset: in format 2, of the unit that holds its instruction.
  uint32_t code(uint32_t codeOffset) const;
};

/// One field of the encoding, for `isocc --dump=hex` (STYLE habit 6).
struct Field {
  uint32_t offset = 0;
  uint32_t size = 0;
  std::string what;
  bool code = false; ///< code: the dumper splits it into instructions (format 1: the whole
                     ///< section; format 2: one unit, decoding to [decoded, decodedEnd))
  uint32_t decoded = 0, decodedEnd = 0;
};

/// Encodes `img`. Deterministic: equal images give equal bytes. The image need not be
/// verified, but its tables must be encodable (the line table sorted by offset, sizes below
/// 4 GiB); otherwise throws std::invalid_argument. Fills `layout` and `fields` when given.
std::vector<uint8_t> writeImage(const Image& img, Layout* layout = nullptr, std::vector<Field>* fields = nullptr);

/// Recomputes the CRC field of an encoded image in place (tests and fixtures).
void fixCrc(std::vector<uint8_t>& bytes);

} // namespace iso::image
