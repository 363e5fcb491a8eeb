//! @file ReaderTests.cpp
//! @brief The reader rejects every structural defect with the offset and the reason.
#include <doctest/doctest.h>
#include <fmt/format.h>

#include "ImageTestUtil.h"

using namespace iso;
using namespace iso::test;

namespace {

std::vector<uint8_t> good() { return image::writeImage(sampleImage()); }

/// Reads `b` after recomputing its CRC; returns the error (empty message: accepted).
image::ImageError readFixed(std::vector<uint8_t> b, bool fix = true) {
  if (fix) image::fixCrc(b);
  image::Image img;
  image::ImageError err;
  if (image::readImage(b, img, err)) return {};
  return err;
}

void put16(std::vector<uint8_t>& b, size_t at, uint16_t v) {
  b[at] = static_cast<uint8_t>(v);
  b[at + 1] = static_cast<uint8_t>(v >> 8);
}
uint32_t get32(const std::vector<uint8_t>& b, size_t at) {
  return static_cast<uint32_t>(b[at] | b[at + 1] << 8 | b[at + 2] << 16 | static_cast<uint32_t>(b[at + 3]) << 24);
}
size_t entry(unsigned i) { return image::kHeaderSize + i * image::kSectionEntrySize; }

/// Rebuilds an image with the payload of one section replaced (sizes and offsets fixed up).
std::vector<uint8_t> withSection(const image::Image& img, image::SectionId id, std::vector<uint8_t> payload) {
  image::Layout lay;
  std::vector<uint8_t> b = image::writeImage(img, &lay);
  auto idx = static_cast<size_t>(id);
  uint32_t off = lay.section[idx], size = lay.sectionSize[idx];
  std::vector<uint8_t> out(b.begin(), b.begin() + off);
  out.insert(out.end(), payload.begin(), payload.end());
  out.insert(out.end(), b.begin() + off + size, b.end());
  int64_t delta = static_cast<int64_t>(payload.size()) - size;
  uint16_t count = static_cast<uint16_t>(b[10] | b[11] << 8);
  for (unsigned i = 0; i < count; ++i) {
    uint16_t sid = static_cast<uint16_t>(out[entry(i)] | out[entry(i) + 1] << 8);
    if (sid == idx) image::patchU32(out, entry(i) + 8, static_cast<uint32_t>(payload.size()));
    if (sid > idx) image::patchU32(out, entry(i) + 4, static_cast<uint32_t>(get32(out, entry(i) + 4) + delta));
  }
  image::patchU32(out, image::kOffTotalSize, static_cast<uint32_t>(out.size()));
  return out;
}

} // namespace

TEST_CASE("image: reader rejects bad headers") {
  auto b = good();
  SUBCASE("empty") {
    auto e = readFixed({}, false);
    CHECK(e.message == "truncated header: the image is 0 bytes, the header needs 24");
  }
  SUBCASE("magic") {
    b[3] = 'C';
    auto e = readFixed(b, false);
    CHECK(e.offset == 0);
    CHECK(e.message.find("not an isotools image (bad magic") == 0);
    // text-mode damage (CRLF -> LF) is caught by the magic
    std::vector<uint8_t> t = {'I', 'S', 'O', 'B', 0x0A, 0x1A, 0x0A};
    CHECK(readFixed(t, false).message.find("bad magic") != std::string::npos);
  }
  SUBCASE("short header") {
    b.resize(20);
    auto e = readFixed(b, false);
    CHECK(e.offset == 20);
    CHECK(e.message == "truncated header: the image is 20 bytes, the header needs 24");
  }
  SUBCASE("version") {
    put16(b, 8, 3);
    auto e = readFixed(b);
    CHECK(e.offset == 8);
    CHECK(e.message == "unsupported format version 3 (this reader reads versions 1 and 2)");
    put16(b, 8, 0);
    CHECK(readFixed(b).message == "unsupported format version 0 (this reader reads versions 1 and 2)");
  }
  SUBCASE("truncated") {
    size_t n = b.size();
    b.pop_back();
    auto e = readFixed(b);
    CHECK(e.offset == n - 1);
    CHECK(e.message == fmt::format("truncated image: {} bytes, the header says {}", n - 1, n));
  }
  SUBCASE("trailing bytes") {
    size_t n = b.size();
    b.push_back(0);
    auto e = readFixed(b, false);
    CHECK(e.offset == n);
    CHECK(e.message == fmt::format("1 bytes after the end of the image (the header says {} bytes)", n));
  }
  SUBCASE("crc") {
    b.back() ^= 1;
    auto e = readFixed(b, false);
    CHECK(e.offset == image::kOffCrc);
    CHECK(e.message.find("CRC-32 mismatch: the header says 0x") == 0);
  }
  SUBCASE("flags") {
    b[image::kOffFlags] = 4;
    auto e = readFixed(b);
    CHECK(e.offset == image::kOffFlags);
    CHECK(e.message == "unknown image flags 0x00000004");
  }
  SUBCASE("section count zero") {
    put16(b, 10, 0);
    CHECK(readFixed(b).message == "section count 0 outside 1..64");
  }
  SUBCASE("section table too large") {
    put16(b, 10, 64);
    image::patchU32(b, image::kOffTotalSize, 100);
    b.resize(100);
    auto e = readFixed(b);
    CHECK(e.offset == 10);
    CHECK(e.message == "section table of 64 entries (768 bytes) does not fit in the image");
  }
}

TEST_CASE("image: reader rejects bad section tables") {
  auto b = good();
  SUBCASE("id 0") {
    put16(b, entry(0), 0);
    CHECK(readFixed(b).message == "section id 0 is reserved");
  }
  SUBCASE("duplicate") {
    put16(b, entry(1), 1);
    auto e = readFixed(b);
    CHECK(e.offset == entry(1));
    CHECK(e.message == "duplicate section 1 (strings)");
  }
  SUBCASE("out of order") {
    put16(b, entry(0), 2);
    put16(b, entry(1), 1);
    CHECK(readFixed(b).message == "section 1 (strings) after section 2: the table must be sorted by id");
  }
  SUBCASE("unknown flags") {
    put16(b, entry(2) + 2, 6);
    CHECK(readFixed(b).message == "section 3 (code): unknown section flags 0x0006");
  }
  SUBCASE("required marked optional") {
    put16(b, entry(2) + 2, 1);
    CHECK(readFixed(b).message == "section 3 (code) is required but marked optional");
  }
  SUBCASE("lines not marked optional") {
    put16(b, entry(6) + 2, 0);
    CHECK(readFixed(b).message == "section 7 (lines) must be marked optional");
  }
  SUBCASE("unknown required id") {
    put16(b, entry(6), 9);
    put16(b, entry(6) + 2, 0);
    CHECK(readFixed(b).message == "unknown section id 9 (not marked optional)");
  }
  SUBCASE("past the end") {
    image::patchU32(b, entry(6) + 8, get32(b, entry(6) + 8) + 1);
    auto e = readFixed(b);
    CHECK(e.offset == entry(6) + 4);
    CHECK(e.message.find("ends past the end of the image") != std::string::npos);
  }
  SUBCASE("huge size does not wrap") {
    image::patchU32(b, entry(6) + 8, 0xFFFFFFFFu);
    CHECK(readFixed(b).message.find("ends past the end of the image") != std::string::npos);
  }
  SUBCASE("overlap") {
    image::patchU32(b, entry(1) + 4, get32(b, entry(1) + 4) - 1);
    CHECK(readFixed(b).message.find("overlaps the previous section") != std::string::npos);
  }
  SUBCASE("overlaps the table") {
    image::patchU32(b, entry(0) + 4, get32(b, entry(0) + 4) - 2);
    CHECK(readFixed(b).message.find("overlaps the section table") != std::string::npos);
  }
  SUBCASE("gap") {
    image::patchU32(b, entry(0) + 8, get32(b, entry(0) + 8) - 1);
    auto e = readFixed(b);
    CHECK(e.offset == entry(1) + 4);
    CHECK(e.message == "gap of 1 bytes before section 2 (constants): sections must follow each other");
  }
  SUBCASE("bytes after the last section") {
    image::patchU32(b, entry(6) + 8, get32(b, entry(6) + 8) - 1);
    CHECK(readFixed(b).message == "1 bytes after the last section");
  }
  SUBCASE("missing section") {
    // drop the axes entry: its bytes join the entries section
    put16(b, 10, 6);
    image::patchU32(b, entry(4) + 8, get32(b, entry(4) + 8) + get32(b, entry(5) + 8));
    std::copy(b.begin() + static_cast<long>(entry(6)), b.begin() + static_cast<long>(entry(7)),
              b.begin() + static_cast<long>(entry(5)));
    // the table is one entry shorter: move every payload offset back by 12
    std::vector<uint8_t> c(b.size() - (entry(7) - entry(6)));
    std::copy(b.begin(), b.begin() + static_cast<long>(entry(6)), c.begin());
    std::copy(b.begin() + static_cast<long>(entry(7)), b.end(), c.begin() + static_cast<long>(entry(6)));
    for (unsigned i = 0; i < 6; ++i)
      image::patchU32(c, entry(i) + 4, get32(c, entry(i) + 4) - 12);
    image::patchU32(c, image::kOffTotalSize, static_cast<uint32_t>(c.size()));
    auto e = readFixed(c);
    CHECK(e.offset == image::kHeaderSize);
    CHECK(e.message == "missing section 6 (axes)");
  }
  SUBCASE("stripped with lines") {
    b[image::kOffFlags] = 1;
    CHECK(readFixed(b).message == "a stripped image (flags bit 0) has a lines section");
  }
  SUBCASE("not stripped, no lines") {
    image::Image img = sampleImage();
    img.flags = image::Image::kFlagStripped;
    img.lines.clear();
    auto s = image::writeImage(img);
    s[image::kOffFlags] = 0;
    CHECK(readFixed(s).message == "missing section 7 (lines) (the image is not stripped)");
  }
}

TEST_CASE("image: a string count that distinct strings cannot fit is rejected before allocating") {
  // 300 strings in 300 bytes would all be empty: distinct, they need 1 + 256 x 2 + 43 x 3 bytes
  std::vector<uint8_t> sec{0xAC, 0x02}; // uleb 300
  sec.insert(sec.end(), 300, 0x00);
  CHECK(readFixed(withSection(sampleImage(), image::SectionId::Strings, sec)).message ==
        "string count 300: 300 distinct strings need at least 642 bytes, the section has 300 left");
  // the fewest bytes: one empty string, then 256 strings of one byte
  std::vector<uint8_t> ok{0x81, 0x02, 0x00}; // uleb 257, ""
  for (int c = 0; c < 256; ++c) {
    ok.push_back(0x01);
    ok.push_back(static_cast<uint8_t>(c));
  }
  CHECK(readFixed(withSection(sampleImage(), image::SectionId::Strings, ok)).message.empty());
}

TEST_CASE("image: reader rejects bad section contents") {
  image::Image img = sampleImage();
  using S = image::SectionId;
  CHECK(readFixed(withSection(img, S::Strings, {0x05, 0x01})).message ==
        "string count 5 exceeds the 1 bytes left in the section");
  CHECK(readFixed(withSection(img, S::Strings, {0x01, 0x05, 'a'})).message ==
        "string 0 length 5 exceeds the 1 bytes left in the section");
  CHECK(readFixed(withSection(img, S::Strings, {0x01, 0x01, 'a', 'b'})).message ==
        "1 unused bytes at the end of section 1 (strings)");
  CHECK(readFixed(withSection(img, S::Strings, {0x80, 0x00})).message.find("non-minimal uleb") == 0);
  CHECK(readFixed(withSection(img, S::Strings, {0x80})).message.find("truncated uleb") == 0);
  CHECK(
      readFixed(withSection(img, S::Strings, {0xFF, 0xFF, 0xFF, 0xFF, 0x7F})).message.find("does not fit in 32 bits") !=
      std::string::npos);
  CHECK(readFixed(withSection(img, S::Strings, {0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0x01}))
            .message.find("too large") != std::string::npos);
  CHECK(readFixed(withSection(img, S::Constants, {0x02, 0, 0, 0, 0, 0, 0, 0, 0})).message ==
        "constant count 2 needs 16 bytes, the section has 8 left");
  CHECK(readFixed(withSection(img, S::Procs, {0x03, 0, 0, 0, 0, 0})).message ==
        "procedure count 3 needs at least 15 bytes, the section has 5 left");
  CHECK(readFixed(withSection(img, S::Procs, {0x01, 3, 0, 0, 0, 1})).message ==
        "procedure 0 kind 3 is not 0 (main), 1 (semi) or 2 (sub)");
  CHECK(readFixed(withSection(img, S::Entries, {0x01, 7, 0, 0})).message ==
        "entry 0 kind 7 is not 0 (main), 1 (semi) or 2 (sub)");
  CHECK(readFixed(withSection(img, S::Entries, {0x02, 0, 0, 0})).message ==
        "entry count 2 needs at least 6 bytes, the section has 3 left");
  CHECK(readFixed(withSection(img, S::Axes, {0x02, 'X'})).message ==
        "axis count 2 does not match the 1 bytes left in the section");
  CHECK(readFixed(withSection(img, S::Lines, {0x01, 0x00, 0x07, 0x02})).message.find("N kind 3") != std::string::npos);
  CHECK(readFixed(withSection(img, S::Lines, {0x01, 0x00, 0x04, 0x7F})).message ==
        "line entry 0: line number -1 out of range");
  CHECK(readFixed(withSection(img, S::Lines, {0x01, 0x00, 0x04, 0x81, 0x00})).message.find("non-minimal sleb") == 0);
  CHECK(readFixed(withSection(img, S::Lines, {0x01, 0x00, 0x06, 0x01, 0, 0, 0, 0, 0, 0, 0x24, 0x40})).message ==
        "line entry 0: N10 must use the integer form");
  CHECK(readFixed(withSection(img, S::Lines, {0x02, 0xFF, 0xFF, 0xFF, 0xFF, 0x0F, 0x04, 0x01, 0x01, 0x04, 0x01}))
            .message == "line entry 1 code offset beyond 4 GiB");
}

TEST_CASE("image: reader errors name an offset inside the image") {
  // every truncation of a valid image: rejected, offset within the bytes given
  auto b = good();
  for (size_t n = 0; n < b.size(); ++n) {
    std::vector<uint8_t> t(b.begin(), b.begin() + static_cast<long>(n));
    image::Image img;
    image::ImageError err;
    REQUIRE_FALSE(image::readImage(t, img, err));
    CHECK(err.offset <= n);
    CHECK_FALSE(err.message.empty());
  }
}
