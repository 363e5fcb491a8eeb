//! @file RoundTripTests.cpp
//! @brief Writer and reader agree; the encoding is deterministic; the listing names things.
#include <cstring>
#include <functional>
#include <string>

#include <doctest/doctest.h>

#include "ImageTestUtil.h"
#include "image/Crc32.h"
#include "image/Disassembler.h"

using namespace iso;
using namespace iso::test;

namespace {

bool sameImage(const image::Image& a, const image::Image& b) {
  if (a.flags != b.flags || a.strings != b.strings || a.code != b.code || a.axes != b.axes) return false;
  if (a.constants.size() != b.constants.size()) return false;
  for (size_t i = 0; i < a.constants.size(); ++i)
    if (std::memcmp(&a.constants[i], &b.constants[i], sizeof(double)) != 0) return false;
  if (a.procs.size() != b.procs.size() || a.entries.size() != b.entries.size() || a.lines.size() != b.lines.size())
    return false;
  for (size_t i = 0; i < a.procs.size(); ++i) {
    const auto &p = a.procs[i], &q = b.procs[i];
    if (p.name != q.name || p.file != q.file || p.kind != q.kind || p.entry != q.entry || p.size != q.size)
      return false;
  }
  for (size_t i = 0; i < a.entries.size(); ++i) {
    const auto &p = a.entries[i], &q = b.entries[i];
    if (p.kind != q.kind || p.name != q.name || p.proc != q.proc) return false;
  }
  for (size_t i = 0; i < a.lines.size(); ++i) {
    const auto &p = a.lines[i], &q = b.lines[i];
    if (p.offset != q.offset || p.file != q.file || p.line != q.line || p.hasN != q.hasN ||
        std::memcmp(&p.n, &q.n, sizeof(double)) != 0)
      return false;
  }
  return true;
}

uint32_t le32(const std::vector<uint8_t>& b, size_t at) {
  return static_cast<uint32_t>(b[at] | b[at + 1] << 8 | b[at + 2] << 16 | static_cast<uint32_t>(b[at + 3]) << 24);
}

} // namespace

TEST_CASE("image: crc32 check value") {
  const char* s = "123456789";
  CHECK(image::crc32(reinterpret_cast<const uint8_t*>(s), 9) == 0xCBF43926u);
  // incremental
  uint32_t c = image::crc32(reinterpret_cast<const uint8_t*>(s), 4);
  CHECK(image::crc32(reinterpret_cast<const uint8_t*>(s) + 4, 5, c) == 0xCBF43926u);
  CHECK(image::crc32(nullptr, 0) == 0);
}

TEST_CASE("image: crc32 of any length and split equals the bit-by-bit definition") {
  auto bitwise = [](const std::vector<uint8_t>& d) {
    uint32_t c = 0xFFFFFFFFu;
    for (uint8_t b : d) {
      c ^= b;
      for (int k = 0; k < 8; ++k)
        c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
    }
    return ~c;
  };
  std::vector<uint8_t> d;
  uint32_t x = 12345;
  for (size_t n = 0; n < 70; ++n) {
    CAPTURE(n);
    CHECK(image::crc32(d.data(), d.size()) == bitwise(d));
    for (size_t cut : {size_t{0}, n / 3, n}) // incremental, any split
      CHECK(image::crc32(d.data() + cut, n - cut, image::crc32(d.data(), cut)) == bitwise(d));
    x = x * 1103515245u + 12345u;
    d.push_back(static_cast<uint8_t>(x >> 16));
  }
}

TEST_CASE("image: the sample image is valid") {
  image::Image img = sampleImage();
  image::ImageError err;
  CHECK_MESSAGE(image::verifyImage(img, err), err.message);
}

TEST_CASE("image: writer and reader round trip") {
  image::Image img = sampleImage();
  std::vector<uint8_t> bytes = image::writeImage(img);
  image::Image back;
  image::ImageError err;
  image::Layout lay;
  REQUIRE_MESSAGE(image::readImage(bytes, back, err, &lay), err.message);
  CHECK(sameImage(img, back));
  CHECK(image::writeImage(back) == bytes); // canonical: bytes -> image -> bytes is the identity
  CHECK(image::verifyImage(back, err, &lay));
  // header fields
  CHECK(std::memcmp(bytes.data(), "ISOB\r\n\x1A\n", 8) == 0);
  CHECK(bytes[8] == 2); // format 2
  CHECK(bytes[9] == 0);
  CHECK(bytes[10] == 7); // seven sections
  CHECK(le32(bytes, 16) == bytes.size());
  std::vector<uint8_t> z = bytes;
  z[20] = z[21] = z[22] = z[23] = 0;
  CHECK(le32(bytes, 20) == image::crc32(z.data(), z.size()));
  // the layout the reader reports is the one the writer produced
  image::Layout wl;
  image::writeImage(img, &wl);
  CHECK(wl.section == lay.section);
  CHECK(wl.procs == lay.procs);
  CHECK(wl.lines == lay.lines);
  CHECK(wl.strings == lay.strings);
}

TEST_CASE("image: stripped images have no lines section") {
  image::Image img = sampleImage();
  img.flags = image::Image::kFlagStripped;
  img.lines.clear();
  std::vector<uint8_t> bytes = image::writeImage(img);
  CHECK(bytes[10] == 6);
  image::Image back;
  image::ImageError err;
  REQUIRE_MESSAGE(image::readImage(bytes, back, err), err.message);
  CHECK(back.stripped());
  CHECK(back.lines.empty());
  CHECK(sameImage(img, back));
  CHECK(image::writeImage(sampleImage()).size() > bytes.size());
}

TEST_CASE("image: empty tables and extreme values round trip") {
  Builder b;
  b.img.axes.clear();
  Asm a;
  a.stmt().op(Op::End);
  b.proc(image::UnitKind::Main, "m", "m.mpf", a);
  b.img.constants = {0.0, -0.0, 1e300, -5e-324};
  b.img.strings.push_back(std::string("\0\xFF\n\"", 4));
  b.img.strings.push_back(std::string(300, 'x')); // two-byte length
  b.img.lines[0].line = 4000000000u;
  b.img.lines[0].hasN = true;
  b.img.lines[0].n = 4294967295.0;
  image::Image back;
  image::ImageError err;
  auto bytes = image::writeImage(b.img);
  REQUIRE_MESSAGE(image::readImage(bytes, back, err), err.message);
  CHECK(sameImage(b.img, back));
  b.img.lines[0].n = 4294967296.0; // no longer the integer form
  REQUIRE(image::readImage(image::writeImage(b.img), back, err));
  CHECK(back.lines[0].n == 4294967296.0);
}

TEST_CASE("image: deterministic bytes") { CHECK(image::writeImage(sampleImage()) == image::writeImage(sampleImage())); }

TEST_CASE("image: unknown optional sections are skipped, unknown required ones rejected") {
  image::Image img = sampleImage();
  std::vector<uint8_t> bytes = image::writeImage(img);
  // Append a section with id 9 at the end: grow the table by one entry and shift everything.
  auto withExtra = [&](uint16_t flags) {
    std::vector<uint8_t> b(bytes.begin(), bytes.begin() + image::kHeaderSize);
    uint16_t count = static_cast<uint16_t>(bytes[10] | bytes[11] << 8);
    uint32_t oldTableEnd = image::kHeaderSize + count * image::kSectionEntrySize;
    b[10] = static_cast<uint8_t>(count + 1);
    for (uint16_t i = 0; i < count; ++i) {
      size_t at = image::kHeaderSize + i * image::kSectionEntrySize;
      b.insert(b.end(), bytes.begin() + static_cast<long>(at), bytes.begin() + static_cast<long>(at) + 12);
      image::patchU32(b, b.size() - 8, le32(bytes, at + 4) + image::kSectionEntrySize);
    }
    uint32_t extraAt = static_cast<uint32_t>(bytes.size()) + image::kSectionEntrySize;
    b.push_back(9);
    b.push_back(0);
    b.push_back(static_cast<uint8_t>(flags));
    b.push_back(0);
    image::writeU32(b, extraAt);
    image::writeU32(b, 3);
    b.insert(b.end(), bytes.begin() + oldTableEnd, bytes.end());
    b.push_back(1);
    b.push_back(2);
    b.push_back(3);
    image::patchU32(b, image::kOffTotalSize, static_cast<uint32_t>(b.size()));
    image::fixCrc(b);
    return b;
  };
  image::Image back;
  image::ImageError err;
  image::Layout lay;
  CHECK_MESSAGE(image::readImage(withExtra(image::kSectionFlagOptional), back, err, &lay), err.message);
  CHECK(sameImage(img, back));
  CHECK(image::verifyImage(back, err, &lay));
  CHECK_FALSE(image::readImage(withExtra(0), back, err));
  CHECK(err.message == "unknown section id 9 (not marked optional)");
  CHECK(err.offset == image::kHeaderSize + 7 * image::kSectionEntrySize);
}

TEST_CASE("image: hex dump explains every byte") {
  image::Image img = sampleImage();
  std::string dump = image::hexDump(img);
  std::vector<uint8_t> bytes = image::writeImage(img);
  // Reassemble the bytes from the dump: every byte is listed once, in order.
  std::vector<uint8_t> back;
  size_t pos = 0;
  while (pos < dump.size()) {
    size_t eol = dump.find('\n', pos);
    std::string line = dump.substr(pos, eol - pos);
    pos = eol + 1;
    if (line.empty() || line[0] == '#') continue;
    size_t hash = line.find('#');
    std::string data = line.substr(0, hash);
    REQUIRE(data.size() > 6);
    CHECK(std::stoul(data.substr(0, 4), nullptr, 16) == back.size());
    for (size_t k = 6; k + 1 < data.size(); k += 3)
      if (data[k] != ' ') back.push_back(static_cast<uint8_t>(std::stoul(data.substr(k, 2), nullptr, 16)));
  }
  CHECK(back == bytes);
  CHECK(dump.find("# magic") != std::string::npos);
  CHECK(dump.find("CRC-32 0x") != std::string::npos);
  CHECK(dump.find("call Sub (procedure 1)") != std::string::npos);
  CHECK(dump.find("string 1 length 8") != std::string::npos);
}

TEST_CASE("image: disassembly names operands") {
  std::string d = image::disassemble(sampleImage());
  INFO(d);
  CHECK(d.find("; entry 0: main \"main\" -> main (procedure 0)") != std::string::npos);
  CHECK(d.find("; entry 1: semi \"Semi program\" -> semi (procedure 2)") != std::string::npos);
  CHECK(d.find("; procedure 1: sub Sub, file sub.spf") != std::string::npos);
  CHECK(d.find("push.const  #0 (12.5)") != std::string::npos);
  CHECK(d.find("load.axvar  $aa_iw[X]") != std::string::npos);
  CHECK(d.find("store.io    $aa_out[index]") != std::string::npos);
  CHECK(d.find("load.io     $aa_in[index]") != std::string::npos);
  CHECK(d.find("move        Pos[X], Posa[Y]") != std::string::npos);
  CHECK(d.find("move        Pos[X], Fa[X]") != std::string::npos);
  CHECK(d.find("move        Pos[X], Pos[Y], I, J") != std::string::npos);
  CHECK(d.find("call        Sub (procedure 1)") != std::string::npos);
  CHECK(d.find("case        12.5 -> L") != std::string::npos);
  CHECK(d.find("default -> next") != std::string::npos);
  CHECK(d.find("m           M23") != std::string::npos);
  CHECK(d.find("m.nb        M=NB(34)") != std::string::npos);
  CHECK(d.find("push.d1     -2.5") != std::string::npos);
  CHECK(d.find("push.d2     1.25") != std::string::npos);
  CHECK(d.find("zword       S") != std::string::npos);
  CHECK(d.find("; main.mpf:1") != std::string::npos);
  CHECK(d.find("; main.mpf:2 N10") != std::string::npos);
  CHECK(d.find("; main.mpf:3 N20.5") != std::string::npos);
  CHECK(d.find("when        cond L") != std::string::npos);
  // every label printed is defined once
  size_t labels = 0;
  for (size_t p = d.find("\nL"); p != std::string::npos; p = d.find("\nL", p + 1))
    ++labels;
  CHECK(labels >= 8);
}

TEST_CASE("image: disassembler and hex dump survive nonsense") {
  image::Image img;
  img.code = {0xEE, 0x42, 0x01, 0x61, 0x05, 0x7F, 0x01, 0x46};
  img.procs.push_back({99, 98, image::UnitKind::Main, 0, 100});
  img.procs.push_back({0, 0, image::UnitKind::Sub, 0xFFFFFFF0u, 100});
  img.entries.push_back({image::UnitKind::Semi, 7, 9});
  img.lines.push_back({3, 77, 1, false, 0});
  std::string d = image::disassemble(img);
  CHECK(d.find(".byte       0xEE") != std::string::npos);
  std::string h = image::hexDump(img);
  CHECK(h.find("unknown opcode 0xEE") != std::string::npos);
}

TEST_CASE("image: sameImage tells an image from one with any field changed, its line table by fingerprint") {
  const image::Image a = sampleImage();
  REQUIRE_FALSE(a.lines.empty());
  CHECK(image::sameImage(a, a, image::lineTableHash(a.lines)));
  const std::vector<std::function<void(image::Image&)>> edits = {
      [](image::Image& i) { i.formatVersion = 1; },
      [](image::Image& i) { i.flags ^= image::Image::kFlagZ32; },
      [](image::Image& i) { i.strings.back() += "x"; },
      [](image::Image& i) { i.constants[0] = -i.constants[0]; },
      [](image::Image& i) { i.constants.push_back(0); },
      [](image::Image& i) { i.code.back() ^= 1; },
      [](image::Image& i) { i.procs[0].size += 1; },
      [](image::Image& i) { i.entries[0].name += 1; },
      [](image::Image& i) { i.axes.push_back('Q'); },
      [](image::Image& i) { i.lines[0].line += 1; },
      [](image::Image& i) { i.lines[0].file += 1; },
      [](image::Image& i) { i.lines.back().offset += 1; },
      [](image::Image& i) { i.lines[0].hasN = !i.lines[0].hasN; },
      [](image::Image& i) { i.lines.pop_back(); },
  };
  for (size_t k = 0; k < edits.size(); ++k) {
    CAPTURE(k);
    image::Image b = a;
    edits[k](b);
    CHECK_FALSE(image::sameImage(a, b, image::lineTableHash(b.lines)));
    CHECK_FALSE(image::sameImage(b, a, image::lineTableHash(a.lines)));
  }
  // N values by their bits: -0 is not 0, and a NaN equals itself
  image::Image z = a, m = a;
  z.lines[0].n = 0.0;
  m.lines[0].n = -0.0;
  CHECK(image::lineTableHash(z.lines) != image::lineTableHash(m.lines));
  CHECK(image::lineTableHash(z.lines) == image::lineTableHash(image::Image(z).lines));
  CHECK(image::sameImage(z, z, image::lineTableHash(z.lines)));
  CHECK_FALSE(image::sameImage(m, z, image::lineTableHash(z.lines)));
}
