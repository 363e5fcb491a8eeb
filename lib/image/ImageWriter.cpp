//! @file ImageWriter.cpp
//! @brief Image -> bytes, optionally explaining every field.
#include "image/ImageWriter.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <iterator>
#include <stdexcept>

#include <fmt/format.h>

#include "image/Crc32.h"
#include "image/Opcode.h"
#include "support/Bytes.h"
#include "support/Memory.h"

namespace iso::image {

const char* sectionName(uint16_t id) {
  switch (id) {
#define X(i, name, str, opt)                                                                                           \
  case i: return str;
    ISO_IMAGE_SECTIONS(X)
#undef X
  default: return nullptr;
  }
}

bool sectionOptional(uint16_t id) {
  switch (id) {
#define X(i, name, str, opt)                                                                                           \
  case i: return opt;
    ISO_IMAGE_SECTIONS(X)
#undef X
  default: return false;
  }
}

namespace {

/// Escapes a string for a one-line comment.
std::string quoted(const std::string& s) {
  std::string r = "\"";
  for (char ch : s) {
    const auto c = static_cast<unsigned char>(ch);
    if (c == '"' || c == '\\') {
      r += '\\';
      r += static_cast<char>(c);
    } else if (c < 0x20 || c >= 0x7F) {
      r += fmt::format("\\x{:02X}", c);
    } else {
      r += static_cast<char>(c);
    }
  }
  return r + "\"";
}

/// Appends fields to the buffer and, when asked, records what each one is.
class Out {
public:
  explicit Out(std::vector<Field>* fields) : fields_(fields) {}
  std::vector<uint8_t> b;
  support::ByteWriter w{b};

  uint32_t pos() const { return static_cast<uint32_t>(b.size()); }

  template <typename F> void note(uint32_t start, F&& what) {
    if (fields_) fields_->push_back({start, pos() - start, what(), false});
  }
  /// Writes one field with `write` and explains its bytes with `what()` (when explaining).
  template <typename W, typename F> void field(W&& write, F&& what) {
    const uint32_t s = pos();
    write();
    note(s, what);
  }
  template <typename F> void u8(uint8_t v, F&& what) {
    field([&] { b.push_back(v); }, what);
  }
  template <typename F> void u16(uint16_t v, F&& what) {
    field([&] { w.u16(v); }, what);
  }
  template <typename F> void u32(uint32_t v, F&& what) {
    field([&] { w.u32(v); }, what);
  }
  template <typename F> void uleb(uint64_t v, F&& what) {
    field([&] { w.uleb(v); }, what);
  }
  template <typename F> void sleb(int64_t v, F&& what) {
    field([&] { w.sleb(v); }, what);
  }
  template <typename F> void f64(double v, F&& what) {
    field([&] { w.f64(v); }, what);
  }
  template <typename F> void bytes(const uint8_t* p, size_t n, F&& what, bool code = false) {
    uint32_t s = pos();
    b.insert(b.end(), p, p + n);
    if (fields_) fields_->push_back({s, pos() - s, what(), code});
  }
  void comment(std::string what) {
    if (fields_) fields_->push_back({pos(), 0, std::move(what), false});
  }

private:
  std::vector<Field>* fields_;
};

uint32_t checked32(size_t v, const char* what) {
  if (v > 0xFFFFFFFFu) throw std::invalid_argument(fmt::format("image too large: {}", what));
  return static_cast<uint32_t>(v);
}

bool integralN(double n) { return n >= 0 && n < 4294967296.0 && std::floor(n) == n && !std::signbit(n); }

/// The procs section after its header comment: count, then kind, name, file, entry, size.
void writeProcTable(Out& o, const Image& img, Layout& lay) {
  o.uleb(img.procs.size(), [&] { return fmt::format("procedure count {}", img.procs.size()); });
  for (size_t i = 0; i < img.procs.size(); ++i) {
    const Proc& p = img.procs[i];
    auto str = [&](uint32_t s) { return s < img.strings.size() ? quoted(img.strings[s]) : std::string("?"); };
    lay.procs.push_back(o.pos());
    o.u8(static_cast<uint8_t>(p.kind),
         [&] { return fmt::format("proc {} kind {} ({})", i, static_cast<unsigned>(p.kind), kindName(p.kind)); });
    o.uleb(p.name, [&] { return fmt::format("  name string {} {}", p.name, str(p.name)); });
    o.uleb(p.file, [&] { return fmt::format("  file string {} {}", p.file, str(p.file)); });
    o.uleb(p.entry, [&] { return fmt::format("  entry 0x{:04X}", p.entry); });
    o.uleb(p.size, [&] { return fmt::format("  size {}", p.size); });
  }
}

/// The entries section after its header comment: count, then kind, name, procedure.
void writeEntryTable(Out& o, const Image& img, Layout& lay) {
  o.uleb(img.entries.size(), [&] { return fmt::format("entry count {}", img.entries.size()); });
  for (size_t i = 0; i < img.entries.size(); ++i) {
    const EntryPoint& e = img.entries[i];
    lay.entries.push_back(o.pos());
    o.u8(static_cast<uint8_t>(e.kind),
         [&] { return fmt::format("entry {} kind {} ({})", i, static_cast<unsigned>(e.kind), kindName(e.kind)); });
    o.uleb(e.name, [&] {
      return fmt::format("  name string {} {}", e.name,
                         e.name < img.strings.size() ? quoted(img.strings[e.name]) : "?");
    });
    o.uleb(e.proc, [&] { return fmt::format("  procedure {}", e.proc); });
  }
}

/// The lines section after its header comment: delta-coded offsets, files, lines and N numbers.
void writeLineTable(Out& o, const Image& img, Layout& lay) {
  o.uleb(img.lines.size(), [&] { return fmt::format("line entry count {}", img.lines.size()); });
  uint32_t prevOff = 0;
  int64_t prevLine = 0;
  for (size_t i = 0; i < img.lines.size(); ++i) {
    const LineEntry& l = img.lines[i];
    if (l.offset < prevOff) throw std::invalid_argument("line table not sorted by code offset");
    lay.lines.push_back(o.pos());
    LineN nk = !l.hasN ? LineN::None : integralN(l.n) ? LineN::Integer : LineN::Double;
    o.uleb(l.offset - prevOff,
           [&] { return fmt::format("line entry {}: code 0x{:04X} (+{})", i, l.offset, l.offset - prevOff); });
    uint64_t fileAndN = (static_cast<uint64_t>(l.file) << 2) | static_cast<uint8_t>(nk);
    o.uleb(fileAndN, [&] {
      return fmt::format("  file string {} {}{}", l.file,
                         l.file < img.strings.size() ? quoted(img.strings[l.file]) : "?",
                         nk == LineN::None      ? ", no N"
                         : nk == LineN::Integer ? ", integer N"
                                                : ", double N");
    });
    int64_t delta = static_cast<int64_t>(l.line) - prevLine;
    o.sleb(delta, [&] { return fmt::format("  line {} ({:+})", l.line, delta); });
    if (nk == LineN::Integer)
      o.uleb(static_cast<uint64_t>(l.n), [&] { return fmt::format("  N{}", l.n); });
    else if (nk == LineN::Double)
      o.f64(l.n, [&] { return fmt::format("  N{}", l.n); });
    prevOff = l.offset;
    prevLine = l.line;
  }
}

/// The code section: format 1 as it is; format 2 coded (CodeFormat2.h), one field per unit.
void writeCode(Out& o, const Image& img, Layout& lay, std::vector<Field>* fields) {
  if (img.formatVersion == 1) {
    o.bytes(
        img.code.data(), img.code.size(), [&] { return fmt::format("code, {} bytes", img.code.size()); }, true);
    return;
  }
  std::vector<CodeUnit> units;
  lay.bounds2 = codeBoundaries(img.procs);
  lay.code2 = encodeCode2(img.code, lay.bounds2, fields ? &units : nullptr);
  const std::vector<uint8_t>& code2 = lay.code2;
  const uint32_t at = o.pos();
  // room for the rest of the image at once: the code, the tables and about 4 bytes a line entry
  support::reserveHuge(o.b, o.b.size() + code2.size() + img.procs.size() * 16 + img.entries.size() * 16 +
                                img.lines.size() * 4 + 4096);
  o.b.insert(o.b.end(), code2.begin(), code2.end());
  for (size_t u = 0; u < units.size(); ++u) {
    const bool last = u + 1 == units.size();
    const uint32_t next = last ? static_cast<uint32_t>(code2.size()) : units[u + 1].encoded;
    const uint32_t decodedEnd = last ? static_cast<uint32_t>(img.code.size()) : units[u + 1].decoded;
    fields->push_back({at + units[u].encoded, next - units[u].encoded, {}, true, units[u].decoded, decodedEnd});
  }
}

} // namespace

std::vector<uint8_t> writeImage(const Image& img, Layout* layoutOut, std::vector<Field>* fields) {
  Layout lay;
  Out o(fields);
  const bool withLines = !img.stripped();
  const uint16_t count = withLines ? 7 : 6;
  for (auto c : kMagic)
    o.b.push_back(c);
  o.note(0, [] { return std::string("magic \"ISOB\\r\\n\\x1A\\n\""); });
  if (img.formatVersion < Image::kOldestFormatVersion || img.formatVersion > Image::kFormatVersion)
    throw std::invalid_argument(fmt::format("format version {} cannot be written", img.formatVersion));
  o.u16(img.formatVersion, [&] { return fmt::format("format version {}", img.formatVersion); });
  o.u16(count, [&] { return fmt::format("section count {}", count); });
  o.u32(img.flags, [&] {
    return fmt::format("flags 0x{:08X}{}{}", img.flags, img.stripped() ? " (stripped)" : "",
                       img.z32() ? " (dialect z32)" : "");
  });
  o.u32(0, [] { return std::string("total size (patched below)"); });
  size_t totalField = fields ? fields->size() - 1 : 0;
  o.u32(0, [] { return std::string("CRC-32 (patched below)"); });
  size_t crcField = fields ? fields->size() - 1 : 0;
  lay.table = o.pos();
  o.comment("section table: id, flags, offset, size");
  std::vector<uint32_t> tableAt;
  for (uint16_t k = 0; k < count; ++k) {
    uint16_t id = static_cast<uint16_t>(k + 1);
    tableAt.push_back(o.pos());
    o.u16(id, [&] { return fmt::format("section {} id {} ({})", k, id, sectionName(id)); });
    o.u16(sectionOptional(id) ? kSectionFlagOptional : 0,
          [&] { return fmt::format("  flags{}", sectionOptional(id) ? " optional" : ""); });
    o.u32(0, [] { return std::string("  offset"); });
    o.u32(0, [] { return std::string("  size"); });
  }
  std::vector<size_t> tableFields;
  auto begin = [&](SectionId id) {
    lay.section[static_cast<size_t>(id)] = o.pos();
    o.comment(fmt::format("section {} ({})", static_cast<unsigned>(id), sectionName(static_cast<uint16_t>(id))));
  };
  auto end = [&](SectionId id) {
    size_t i = static_cast<size_t>(id);
    lay.sectionSize[i] = o.pos() - lay.section[i];
  };

  begin(SectionId::Strings);
  o.uleb(img.strings.size(), [&] { return fmt::format("string count {}", img.strings.size()); });
  for (size_t i = 0; i < img.strings.size(); ++i) {
    const std::string& s = img.strings[i];
    lay.strings.push_back(o.pos());
    o.uleb(s.size(), [&] { return fmt::format("string {} length {}", i, s.size()); });
    o.bytes(reinterpret_cast<const uint8_t*>(s.data()), s.size(), [&] { return fmt::format("  {}", quoted(s)); });
  }
  end(SectionId::Strings);

  begin(SectionId::Constants);
  o.uleb(img.constants.size(), [&] { return fmt::format("constant count {}", img.constants.size()); });
  for (size_t i = 0; i < img.constants.size(); ++i) {
    lay.constants.push_back(o.pos());
    o.f64(img.constants[i], [&] { return fmt::format("constant {} = {}", i, img.constants[i]); });
  }
  end(SectionId::Constants);

  begin(SectionId::Code);
  checked32(img.code.size(), "code");
  writeCode(o, img, lay, fields);
  end(SectionId::Code);

  begin(SectionId::Procs);
  writeProcTable(o, img, lay);
  end(SectionId::Procs);

  begin(SectionId::Entries);
  writeEntryTable(o, img, lay);
  end(SectionId::Entries);

  begin(SectionId::Axes);
  o.uleb(img.axes.size(), [&] { return fmt::format("axis count {}", img.axes.size()); });
  lay.axes = o.pos();
  for (size_t i = 0; i < img.axes.size(); ++i)
    o.u8(static_cast<uint8_t>(img.axes[i]), [&] {
      char c = img.axes[i];
      return c > 0x20 && c < 0x7F ? fmt::format("axis {} '{}'", i, c) : fmt::format("axis {}", i);
    });
  end(SectionId::Axes);

  if (withLines) {
    begin(SectionId::Lines);
    writeLineTable(o, img, lay);
    end(SectionId::Lines);
  }

  uint32_t total = checked32(o.b.size(), "total");
  for (uint16_t k = 0; k < count; ++k) {
    size_t id = k + 1u;
    patchU32(o.b, tableAt[k] + 4, lay.section[id]);
    patchU32(o.b, tableAt[k] + 8, lay.sectionSize[id]);
  }
  patchU32(o.b, kOffTotalSize, total);
  uint32_t crc = crc32(o.b.data(), o.b.size());
  patchU32(o.b, kOffCrc, crc);
  if (fields) {
    (*fields)[totalField].what = fmt::format("total size {}", total);
    (*fields)[crcField].what = fmt::format("CRC-32 0x{:08X} (of the image with this field zero)", crc);
    for (auto& f : *fields) {
      // describe the patched table entries
      for (uint16_t k = 0; k < count; ++k) {
        size_t id = k + 1u;
        if (f.offset == tableAt[k] + 4 && f.size == 4) f.what = fmt::format("  offset 0x{:04X}", lay.section[id]);
        if (f.offset == tableAt[k] + 8 && f.size == 4) f.what = fmt::format("  size {}", lay.sectionSize[id]);
      }
    }
  }
  if (layoutOut) *layoutOut = std::move(lay);
  return std::move(o.b);
}

uint32_t Layout::code(uint32_t codeOffset) const {
  const std::span<const uint8_t> bytes = codeSection();
  if (bytes.empty()) return of(SectionId::Code) + codeOffset;
  std::vector<uint8_t> decoded;
  std::vector<CodeUnit> units;
  (void)decodeCode2(bytes.data(), bytes.size(), bounds2, decoded, &units); // read before: it decodes
  auto it = std::upper_bound(units.begin(), units.end(), codeOffset,
                             [](uint32_t o, const CodeUnit& u) { return o < u.decoded; });
  return of(SectionId::Code) + (it == units.begin() ? 0 : std::prev(it)->encoded);
}

void fixCrc(std::vector<uint8_t>& bytes) {
  if (bytes.size() < kHeaderSize) return;
  for (uint32_t i = 0; i < 4; ++i)
    bytes[kOffCrc + i] = 0;
  patchU32(bytes, kOffCrc, crc32(bytes.data(), bytes.size()));
}

} // namespace iso::image
