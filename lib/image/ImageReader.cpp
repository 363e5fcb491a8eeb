//! @file ImageReader.cpp
//! @brief The structural half of loading an image (wabt's binary reader, for our format).
#include "image/ImageReader.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <fmt/format.h>

#include "image/CodeFormat2.h"
#include "image/Crc32.h"
#include "image/Opcode.h"
#include "support/Bytes.h"
#include "support/Memory.h"

namespace iso::image {

namespace {

using support::LebError;
using support::loadU16;
using support::loadU32;

std::string secLabel(uint16_t id) {
  const char* n = sectionName(id);
  return n ? fmt::format("section {} ({})", id, n) : fmt::format("section {}", id);
}

/// What a read is for, in messages: What{"string count"}, or "string 2 length" (head, index, tail).
/// Kept as parts and formatted only when a read fails.
struct What {
  static constexpr uint32_t kNone = 0xFFFFFFFFu;
  const char* head;
  uint32_t index = kNone;
  const char* tail = "";
  std::string str() const { return index == kNone ? std::string(head) : fmt::format("{} {}{}", head, index, tail); }
};

/// A bounded reader over one section (support::ByteCursor). Every read names what it reads, so
/// a failure says "truncated uleb at 0x0031: string 2 length".
class Cursor {
public:
  Cursor(const uint8_t* data, uint32_t pos, uint32_t end, ImageError& err) : c_(data, pos, end), err_(err) {}

  uint32_t pos() const { return static_cast<uint32_t>(c_.pos()); }
  uint32_t left() const { return static_cast<uint32_t>(c_.left()); }

  bool fail(uint32_t at, std::string msg) {
    err_ = {at, std::move(msg)};
    return false;
  }

  bool u8(uint8_t& v, const What& what) {
    if (!c_.u8(v))
      return fail(pos(), fmt::format("unable to read u8 at 0x{:04X}: {}: end of section", pos(), what.str()));
    return true;
  }

  bool f64(double& v, const What& what) {
    if (!c_.f64(v))
      return fail(pos(), fmt::format("unable to read f64 at 0x{:04X}: {}: end of section", pos(), what.str()));
    return true;
  }

  /// An unsigned LEB128 of at most `maxBits` bits, minimally encoded.
  bool uleb(uint64_t& v, unsigned maxBits, const What& what) {
    const uint32_t start = pos();
    switch (c_.uleb(v)) {
    case LebError::None: break;
    case LebError::Truncated: return fail(start, fmt::format("truncated uleb at 0x{:04X}: {}", start, what.str()));
    case LebError::TooLong:
    case LebError::TooLarge: return fail(start, fmt::format("uleb at 0x{:04X} too large: {}", start, what.str()));
    case LebError::NonMinimal: return fail(start, fmt::format("non-minimal uleb at 0x{:04X}: {}", start, what.str()));
    }
    if (maxBits < 64 && (v >> maxBits) != 0)
      return fail(start,
                  fmt::format("value {} at 0x{:04X} does not fit in {} bits: {}", v, start, maxBits, what.str()));
    return true;
  }

  bool uleb32(uint32_t& v, const What& what) {
    uint64_t w;
    if (!uleb(w, 32, what)) return false;
    v = static_cast<uint32_t>(w);
    return true;
  }

  /// A signed LEB128 of at most 5 bytes (35 bits), minimally encoded.
  bool sleb(int64_t& v, const What& what) {
    const uint32_t start = pos();
    switch (c_.sleb(v, 5)) {
    case LebError::None: return true;
    case LebError::Truncated: return fail(start, fmt::format("truncated sleb at 0x{:04X}: {}", start, what.str()));
    case LebError::TooLong:
    case LebError::TooLarge:
      return fail(start, fmt::format("sleb at 0x{:04X} longer than 5 bytes: {}", start, what.str()));
    case LebError::NonMinimal: return fail(start, fmt::format("non-minimal sleb at 0x{:04X}: {}", start, what.str()));
    }
    return true;
  }

  /// n bytes known to be left.
  void bytes(std::string& s, uint32_t n) {
    s.assign(reinterpret_cast<const char*>(c_.data() + c_.pos()), n);
    c_.skip(n);
  }

  /// The section must be consumed exactly.
  bool finish(uint16_t id) {
    if (left() != 0) return fail(pos(), fmt::format("{} unused bytes at the end of {}", left(), secLabel(id)));
    return true;
  }

private:
  support::ByteCursor c_;
  ImageError& err_;
};

const char* kindRange = "0 (main), 1 (semi) or 2 (sub)";

/// The fewest bytes that `n` distinct strings take in the string table: one empty string (its
/// length byte), then 256 strings of 1 byte (2 bytes each), 65536 of 2 bytes (3 each), ...
uint64_t minStringBytes(uint64_t n) {
  uint64_t bytes = 0, ofLength = 1; // 256^length strings of each length
  for (uint64_t length = 0; n > 0; ++length, ofLength *= 256) {
    const uint64_t k = std::min(n, ofLength);
    bytes += k * (1 + length); // lengths below 128 take one uleb byte
    n -= k;
  }
  return bytes;
}

bool readStrings(Cursor& c, Image& img, Layout& lay) {
  uint32_t n;
  if (!c.uleb32(n, What{"string count"})) return false;
  // Strings are distinct (a verifier rule): a count that distinct strings cannot fit in the
  // section is rejected before anything is allocated from it.
  if (n > c.left())
    return c.fail(c.pos(), fmt::format("string count {} exceeds the {} bytes left in the section", n, c.left()));
  if (minStringBytes(n) > c.left())
    return c.fail(c.pos(),
                  fmt::format("string count {}: {} distinct strings need at least {} bytes, the section has {} "
                              "left",
                              n, n, minStringBytes(n), c.left()));
  img.strings.reserve(n);
  lay.strings.reserve(n);
  for (uint32_t i = 0; i < n; ++i) {
    lay.strings.push_back(c.pos());
    uint32_t len;
    if (!c.uleb32(len, What{"string", i, " length"})) return false;
    if (len > c.left())
      return c.fail(c.pos(),
                    fmt::format("string {} length {} exceeds the {} bytes left in the section", i, len, c.left()));
    std::string s;
    c.bytes(s, len);
    img.strings.push_back(std::move(s));
  }
  return c.finish(static_cast<uint16_t>(SectionId::Strings));
}

bool readConstants(Cursor& c, Image& img, Layout& lay) {
  uint32_t n;
  if (!c.uleb32(n, What{"constant count"})) return false;
  if (static_cast<uint64_t>(n) * 8 != c.left())
    return c.fail(c.pos(), fmt::format("constant count {} needs {} bytes, the section has {} left", n,
                                       static_cast<uint64_t>(n) * 8, c.left()));
  img.constants.reserve(n);
  lay.constants.reserve(n);
  for (uint32_t i = 0; i < n; ++i) {
    lay.constants.push_back(c.pos());
    double v;
    c.f64(v, What{"constant"});
    img.constants.push_back(v);
  }
  return c.finish(static_cast<uint16_t>(SectionId::Constants));
}

bool readProcs(Cursor& c, Image& img, Layout& lay) {
  uint32_t n;
  if (!c.uleb32(n, What{"procedure count"})) return false;
  if (static_cast<uint64_t>(n) * 5 > c.left())
    return c.fail(c.pos(), fmt::format("procedure count {} needs at least {} bytes, the section has {} left", n,
                                       static_cast<uint64_t>(n) * 5, c.left()));
  img.procs.reserve(n);
  lay.procs.reserve(n);
  for (uint32_t i = 0; i < n; ++i) {
    lay.procs.push_back(c.pos());
    Proc p;
    uint8_t kind = 0;
    uint32_t at = c.pos();
    if (!c.u8(kind, What{"procedure", i, " kind"})) return false;
    if (kind > 2) return c.fail(at, fmt::format("procedure {} kind {} is not {}", i, kind, kindRange));
    p.kind = static_cast<UnitKind>(kind);
    if (!c.uleb32(p.name, What{"procedure", i, " name"}) || !c.uleb32(p.file, What{"procedure", i, " file"}) ||
        !c.uleb32(p.entry, What{"procedure", i, " entry"}) || !c.uleb32(p.size, What{"procedure", i, " size"}))
      return false;
    img.procs.push_back(p);
  }
  return c.finish(static_cast<uint16_t>(SectionId::Procs));
}

bool readEntries(Cursor& c, Image& img, Layout& lay) {
  uint32_t n;
  if (!c.uleb32(n, What{"entry count"})) return false;
  if (static_cast<uint64_t>(n) * 3 > c.left())
    return c.fail(c.pos(), fmt::format("entry count {} needs at least {} bytes, the section has {} left", n,
                                       static_cast<uint64_t>(n) * 3, c.left()));
  img.entries.reserve(n);
  lay.entries.reserve(n);
  for (uint32_t i = 0; i < n; ++i) {
    lay.entries.push_back(c.pos());
    EntryPoint e;
    uint8_t kind = 0;
    uint32_t at = c.pos();
    if (!c.u8(kind, What{"entry", i, " kind"})) return false;
    if (kind > 2) return c.fail(at, fmt::format("entry {} kind {} is not {}", i, kind, kindRange));
    e.kind = static_cast<UnitKind>(kind);
    if (!c.uleb32(e.name, What{"entry", i, " name"}) || !c.uleb32(e.proc, What{"entry", i, " procedure"})) return false;
    img.entries.push_back(e);
  }
  return c.finish(static_cast<uint16_t>(SectionId::Entries));
}

bool readAxes(Cursor& c, Image& img, Layout& lay) {
  uint32_t n;
  if (!c.uleb32(n, What{"axis count"})) return false;
  if (n != c.left())
    return c.fail(c.pos(), fmt::format("axis count {} does not match the {} bytes left in the section", n, c.left()));
  lay.axes = c.pos();
  img.axes.reserve(n);
  for (uint32_t i = 0; i < n; ++i) {
    uint8_t b = 0;
    c.u8(b, What{"axis"});
    img.axes.push_back(static_cast<char>(b));
  }
  return c.finish(static_cast<uint16_t>(SectionId::Axes));
}

bool readLines(Cursor& c, Image& img, Layout& lay) {
  uint32_t n;
  if (!c.uleb32(n, What{"line entry count"})) return false;
  if (static_cast<uint64_t>(n) * 3 > c.left())
    return c.fail(c.pos(), fmt::format("line entry count {} needs at least {} bytes, the section has {} left", n,
                                       static_cast<uint64_t>(n) * 3, c.left()));
  support::reserveHuge(img.lines, n);
  support::reserveHuge(lay.lines, n);
  uint64_t off = 0;
  int64_t line = 0;
  for (uint32_t i = 0; i < n; ++i) {
    lay.lines.push_back(c.pos());
    LineEntry e;
    uint32_t delta;
    uint32_t at = c.pos();
    if (!c.uleb32(delta, What{"line entry", i, " offset delta"})) return false;
    off += delta;
    if (off > 0xFFFFFFFFu) return c.fail(at, fmt::format("line entry {} code offset beyond 4 GiB", i));
    uint64_t fileAndN;
    at = c.pos();
    if (!c.uleb(fileAndN, 34, What{"line entry", i, " file"})) return false;
    auto nk = static_cast<uint8_t>(fileAndN & 3);
    if (nk == 3)
      return c.fail(at, fmt::format("line entry {}: N kind 3 is not 0 (none), 1 (integer) or 2 (double)", i));
    int64_t ld;
    at = c.pos();
    if (!c.sleb(ld, What{"line entry", i, " line delta"})) return false;
    line += ld;
    if (line < 0 || line > 0xFFFFFFFFLL)
      return c.fail(at, fmt::format("line entry {}: line number {} out of range", i, line));
    e.offset = static_cast<uint32_t>(off);
    e.file = static_cast<uint32_t>(fileAndN >> 2);
    e.line = static_cast<uint32_t>(line);
    at = c.pos();
    if (nk == static_cast<uint8_t>(LineN::Integer)) {
      uint32_t v;
      if (!c.uleb32(v, What{"line entry", i, " N"})) return false;
      e.hasN = true;
      e.n = v;
    } else if (nk == static_cast<uint8_t>(LineN::Double)) {
      double v;
      if (!c.f64(v, What{"line entry", i, " N"})) return false;
      if (v >= 0 && v < 4294967296.0 && std::floor(v) == v && !std::signbit(v))
        return c.fail(at, fmt::format("line entry {}: N{} must use the integer form", i, v));
      e.hasN = true;
      e.n = v;
    }
    img.lines.push_back(e);
  }
  return c.finish(static_cast<uint16_t>(SectionId::Lines));
}

/// Format 2: the code section decoded (CodeFormat2.h), once the procedures are known.
bool readCode2(const uint8_t* data, Image& img, Layout& lay, ImageError& err) {
  const uint32_t at = lay.of(SectionId::Code);
  const uint32_t size = lay.sectionSize[static_cast<size_t>(SectionId::Code)];
  lay.bounds2 = codeBoundaries(img.procs);
  std::optional<Code2Error> bad = decodeCode2(data + at, size, lay.bounds2, img.code);
  if (!bad) {
    if (lay.borrowCode) // for the messages of the verifier
      lay.code2View = {data + at, size};
    else
      lay.code2.assign(data + at, data + at + size);
    return true;
  }
  err = {at + bad->at, std::move(bad->message)};
  return false;
}

} // namespace

bool readImage(const uint8_t* data, size_t size, Image& out, ImageError& err, Layout* layoutOut) {
  out = Image{};
  auto fail = [&](uint64_t at, std::string msg) {
    err = {static_cast<uint32_t>(at), std::move(msg)};
    return false;
  };
  for (size_t i = 0; i < kMagic.size() && i < size; ++i)
    if (data[i] != kMagic[i]) return fail(0, "not an isotools image (bad magic; expected \"ISOB\\r\\n\\x1A\\n\")");
  if (size < kHeaderSize)
    return fail(size, fmt::format("truncated header: the image is {} bytes, the header needs {}", size, kHeaderSize));
  uint16_t version = loadU16(data + kOffVersion);
  if (version < Image::kOldestFormatVersion || version > Image::kFormatVersion)
    return fail(kOffVersion, fmt::format("unsupported format version {} (this reader reads versions {} and {})",
                                         version, Image::kOldestFormatVersion, Image::kFormatVersion));
  out.formatVersion = version;
  uint32_t total = loadU32(data + kOffTotalSize);
  if (size > 0xFFFFFFFFu) return fail(kOffTotalSize, "image larger than 4 GiB");
  if (total > size) return fail(size, fmt::format("truncated image: {} bytes, the header says {}", size, total));
  if (total < size)
    return fail(total,
                fmt::format("{} bytes after the end of the image (the header says {} bytes)", size - total, total));
  uint32_t stored = loadU32(data + kOffCrc);
  static const uint8_t zero[4] = {0, 0, 0, 0};
  uint32_t crc = crc32(data, kOffCrc);
  crc = crc32(zero, 4, crc);
  crc = crc32(data + kHeaderSize, size - kHeaderSize, crc);
  if (crc != stored)
    return fail(kOffCrc,
                fmt::format("CRC-32 mismatch: the header says 0x{:08X}, the image gives 0x{:08X}", stored, crc));
  uint32_t flags = loadU32(data + kOffFlags);
  if (flags & ~kKnownImageFlags)
    return fail(kOffFlags, fmt::format("unknown image flags 0x{:08X}", flags & ~kKnownImageFlags));
  out.flags = flags;
  uint16_t count = loadU16(data + kOffSectionCount);
  if (count == 0 || count > kMaxSections)
    return fail(kOffSectionCount, fmt::format("section count {} outside 1..{}", count, kMaxSections));
  uint64_t tableEnd = kHeaderSize + static_cast<uint64_t>(count) * kSectionEntrySize;
  if (tableEnd > total)
    return fail(kOffSectionCount, fmt::format("section table of {} entries ({} bytes) does not fit in the image", count,
                                              count * kSectionEntrySize));

  Layout lay;
  lay.table = kHeaderSize;
  lay.borrowCode = layoutOut && layoutOut->borrowCode;
  struct Sec {
    uint16_t id;
    uint32_t at, off, size;
  };
  std::vector<Sec> known;
  uint32_t prevId = 0;
  uint64_t expected = tableEnd;
  for (uint32_t i = 0; i < count; ++i) {
    uint32_t at = kHeaderSize + i * kSectionEntrySize;
    uint16_t id = loadU16(data + at);
    uint16_t sflags = loadU16(data + at + 2);
    uint32_t off = loadU32(data + at + 4);
    uint32_t sz = loadU32(data + at + 8);
    if (id == 0) return fail(at, "section id 0 is reserved");
    if (id == prevId) return fail(at, fmt::format("duplicate {}", secLabel(id)));
    if (id < prevId)
      return fail(at, fmt::format("{} after section {}: the table must be sorted by id", secLabel(id), prevId));
    prevId = id;
    if (sflags & ~kSectionFlagOptional)
      return fail(at + 2,
                  fmt::format("{}: unknown section flags 0x{:04X}", secLabel(id), sflags & ~kSectionFlagOptional));
    bool optional = (sflags & kSectionFlagOptional) != 0;
    const char* name = sectionName(id);
    if (!name && !optional) return fail(at, fmt::format("unknown section id {} (not marked optional)", id));
    if (name && optional != sectionOptional(id))
      return fail(at + 2, sectionOptional(id) ? fmt::format("{} must be marked optional", secLabel(id))
                                              : fmt::format("{} is required but marked optional", secLabel(id)));
    if (off > total || sz > total - off)
      return fail(at + 4, fmt::format("{} at 0x{:04X}, {} bytes, ends past the end of the image ({} bytes)",
                                      secLabel(id), off, sz, total));
    if (off < expected)
      return fail(at + 4, fmt::format("{} at 0x{:04X} overlaps the {} (which ends at 0x{:04X})", secLabel(id), off,
                                      i == 0 ? "section table" : "previous section", expected));
    if (off > expected)
      return fail(at + 4, fmt::format("gap of {} bytes before {}: sections must follow each other", off - expected,
                                      secLabel(id)));
    expected = static_cast<uint64_t>(off) + sz;
    if (name) {
      lay.section[id] = off;
      lay.sectionSize[id] = sz;
      known.push_back({id, at, off, sz});
    }
  }
  if (expected != total) return fail(expected, fmt::format("{} bytes after the last section", total - expected));
  for (uint16_t id = 1; id <= kSectionIdMax; ++id) {
    if (lay.section[id] != 0) continue;
    if (id == static_cast<uint16_t>(SectionId::Lines) && out.stripped()) continue;
    return fail(kHeaderSize,
                fmt::format("missing {}{}", secLabel(id),
                            id == static_cast<uint16_t>(SectionId::Lines) ? " (the image is not stripped)" : ""));
  }
  for (const Sec& s : known) {
    if (s.id == static_cast<uint16_t>(SectionId::Lines) && out.stripped())
      return fail(s.at, "a stripped image (flags bit 0) has a lines section");
    Cursor c(data, s.off, s.off + s.size, err);
    bool ok = true;
    switch (static_cast<SectionId>(s.id)) {
    case SectionId::Strings: ok = readStrings(c, out, lay); break;
    case SectionId::Constants: ok = readConstants(c, out, lay); break;
    case SectionId::Code: // format 2: decoded below, once the procedures are known
      if (version == 1) out.code.assign(data + s.off, data + s.off + s.size);
      break;
    case SectionId::Procs: ok = readProcs(c, out, lay); break;
    case SectionId::Entries: ok = readEntries(c, out, lay); break;
    case SectionId::Axes: ok = readAxes(c, out, lay); break;
    case SectionId::Lines: ok = readLines(c, out, lay); break;
    }
    if (!ok) return false;
  }
  if (version >= 2 && !readCode2(data, out, lay, err)) return false;
  if (layoutOut) *layoutOut = std::move(lay);
  return true;
}

} // namespace iso::image
