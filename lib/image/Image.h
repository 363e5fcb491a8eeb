//! @file Image.h
//! @brief The in-memory model of a compiled image (the contract between isocc and isosim).
//!        The byte format is documented in man/isoimage.5 and implemented by ImageWriter /
//!        ImageReader; ImageVerifier proves the code safe to run.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "lang/UnitKind.h"

namespace iso::image {

/// The unit kinds of lang/UnitKind.h; their values are the image encoding.
using UnitKind = lang::UnitKind;
/// "main", "semi" or "sub" (listings and messages).
const char* kindName(UnitKind k);

/// An image string (a file, procedure or entry name) as it may reach a terminal, a listing or a
/// JSON trace: control bytes (0x00-0x1F, 0x7F) and bytes that are not part of a valid UTF-8
/// sequence become `\xNN`; valid UTF-8 stays as it is. With `quoteEscapes`, `"` and `\` get a
/// backslash too (for a name printed between double quotes).
std::string printableName(std::string_view s, bool quoteEscapes = false);

struct Proc {
  uint32_t name = 0; ///< string index: PROC name, or the file stem for main/semi programs
  uint32_t file = 0; ///< string index: source file path (as given to isocc)
  UnitKind kind = UnitKind::Main;
  uint32_t entry = 0; ///< code offset of the first instruction
  uint32_t size = 0;  ///< bytes of code: [entry, entry + size)
  friend bool operator==(const Proc&, const Proc&) = default;
};

struct EntryPoint {
  UnitKind kind = UnitKind::Main; ///< Main or Semi
  uint32_t name = 0;              ///< string index: the SEMI display name, or the main program's file stem
  uint32_t proc = 0;              ///< procedure index
  friend bool operator==(const EntryPoint&, const EntryPoint&) = default;
};

/// One row of the line table: the statement starting at `offset` came from `file`:`line`.
struct LineEntry {
  uint32_t offset = 0;
  uint32_t file = 0; ///< string index
  uint32_t line = 0; ///< 1-based physical line
  bool hasN = false; ///< the line carries an N number
  double n = 0;      ///< its value
};

struct Image {
  static constexpr uint16_t kFormatVersion = 2;       ///< what isocc writes
  static constexpr uint16_t kOldestFormatVersion = 1; ///< the oldest a reader reads
  uint16_t formatVersion = kFormatVersion;            ///< read from / written as (1: code as is)
  uint32_t flags = 0;                                 ///< bit 0: stripped (no line table); bit 1: dialect z32
  std::vector<std::string> strings;                   ///< string table (unique)
  std::vector<double> constants;                      ///< constant pool (unique bit patterns)
  std::vector<uint8_t> code;                          ///< every procedure's code, concatenated (format 1's
                                                      ///< instructions: format 2 codes them, see CodeFormat2.h)
  std::vector<Proc> procs;                            ///< sorted by entry; procedures do not overlap
  std::vector<EntryPoint> entries;                    ///< exactly one Main first, then Semi programs
  std::vector<char> axes;                             ///< axis letters used by the code (Move/LoadAxVar index here)
  std::vector<LineEntry> lines;                       ///< sorted by offset (empty when stripped)

  static constexpr uint32_t kFlagStripped = 1;
  static constexpr uint32_t kFlagZ32 = 2; ///< compiled for dialect z32 (SPEC §4.6)
  bool stripped() const { return (flags & kFlagStripped) != 0; }
  bool z32() const { return (flags & kFlagZ32) != 0; }
  /// The line entry of the statement containing `offset`, or nullptr.
  const LineEntry* lineAt(uint32_t offset) const;
  /// The procedure containing `offset`, or nullptr.
  const Proc* procAt(uint32_t offset) const;
};

/// A fingerprint of a line table (FNV-1a over every field, N values by their bits): two tables
/// with the same rows have the same one.
uint64_t lineTableHash(const std::vector<LineEntry>& lines);

/// Whether `a` and `b` hold the same image: every field equal, and `b`'s line table has the
/// fingerprint `bLines` (lineTableHash) rather than being compared row by row (`b`'s may be gone).
bool sameImage(const Image& a, const Image& b, uint64_t bLines);

} // namespace iso::image
