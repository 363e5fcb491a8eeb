//! @file CorruptionTests.cpp
//! @brief Real sample images: every truncation and every single-bit flip is rejected, and
//!        flips behind a recomputed CRC never crash the reader, the verifier or the listing.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <doctest/doctest.h>

#include "ImageTestUtil.h"
#include "TestUtil.h"
#include "compiler/Compiler.h"
#include "image/Disassembler.h"
#include "machine/Machine.h"

using namespace iso;

namespace {

/// Compiles samples/<set>/ as isocc does (the directory as the only path).
std::vector<uint8_t> compileSample(const std::string& set, bool strip = false) {
  // A set that comes with machine.json is compiled with it (dialect z32, special M).
  const std::string machineFile = std::string(ISO_SOURCE_DIR) + "/samples/" + set + "/machine.json";
  static machine::Machine m;
  m = test::builtin();
  if (std::filesystem::exists(machineFile)) {
    std::ifstream in(machineFile);
    std::stringstream ss;
    ss << in.rdbuf();
    auto r = machine::parseMachine(ss.str());
    REQUIRE(r.ok());
    m = *r;
  }
  frontend::LoadOptions lo;
  lo.machine = &m;
  lo.dialect = m.dialect;
  frontend::ProgramSet ps;
  frontend::SetError serr;
  std::string dir = std::string(ISO_SOURCE_DIR) + "/samples/" + set;
  REQUIRE_MESSAGE(frontend::loadProgramSet({dir}, lo, ps, serr), serr.message);
  REQUIRE_FALSE(ps.diags.hasErrors());
  compiler::CompileOptions co;
  co.strip = strip;
  co.dialect = m.dialect;
  co.specialM = &m.specialM;
  image::Image img;
  compiler::CompileError cerr;
  REQUIRE_MESSAGE(compiler::compileProgramSet(ps, co, img, cerr), cerr.message);
  return image::writeImage(img);
}

std::vector<std::string> sampleSets() {
  std::vector<std::string> v;
  for (const auto& e : std::filesystem::directory_iterator(std::string(ISO_SOURCE_DIR) + "/samples"))
    if (e.is_directory()) v.push_back(e.path().filename().string());
  std::sort(v.begin(), v.end());
  return v;
}

} // namespace

TEST_CASE("image: every sample compiles to a verified image that round trips") {
  auto sets = sampleSets();
  REQUIRE(sets.size() >= 7);
  for (const auto& s : sets) {
    CAPTURE(s);
    for (bool strip : {false, true}) {
      auto bytes = compileSample(s, strip);
      test::Checked c = test::check(bytes);
      CHECK_MESSAGE(c.verified, c.err.message);
      image::Image img;
      image::ImageError err;
      REQUIRE(image::readImage(bytes, img, err));
      CHECK(image::writeImage(img) == bytes);
      CHECK(img.stripped() == strip);
      CHECK_FALSE(image::disassemble(img).empty());
    }
  }
}

TEST_CASE("image: every truncation and bit flip of a sample image is rejected") {
  for (const std::string& s : {std::string("drilling_when"), std::string("recipe_case"), std::string("semi_auto")}) {
    CAPTURE(s);
    const auto bytes = compileSample(s);
    size_t rejectedTrunc = 0, rejectedFlip = 0;
    for (size_t n = 0; n < bytes.size(); ++n) {
      std::vector<uint8_t> t(bytes.begin(), bytes.begin() + static_cast<long>(n));
      if (!test::check(t).verified) ++rejectedTrunc;
    }
    CHECK(rejectedTrunc == bytes.size());
    std::vector<uint8_t> f = bytes;
    for (size_t i = 0; i < f.size(); ++i)
      for (int bit = 0; bit < 8; ++bit) {
        f[i] ^= static_cast<uint8_t>(1u << bit);
        test::Checked c = test::check(f);
        if (!c.verified && !c.err.message.empty() && c.err.offset <= f.size()) ++rejectedFlip;
        f[i] ^= static_cast<uint8_t>(1u << bit);
      }
    CHECK(rejectedFlip == bytes.size() * 8);
  }
}

TEST_CASE("image: bit flips behind a valid CRC never crash and never slip through inconsistently") {
  for (const std::string& s : {std::string("drilling_when"), std::string("recipe_case")}) {
    CAPTURE(s);
    const auto bytes = compileSample(s);
    size_t accepted = 0, rejected = 0;
    std::vector<uint8_t> f = bytes;
    for (size_t i = 0; i < f.size(); ++i) {
      if (i >= image::kOffCrc && i < image::kOffCrc + 4) continue;
      for (int bit = 0; bit < 8; ++bit) {
        f[i] ^= static_cast<uint8_t>(1u << bit);
        image::fixCrc(f);
        image::Image img;
        image::ImageError err;
        image::Layout lay;
        if (image::readImage(f, img, err, &lay)) {
          if (bit == 0) { // the listings are slow-ish in Debug builds: one flip per byte
            (void)image::disassemble(img);
            (void)image::hexDump(img);
          }
          if (image::verifyImage(img, err, &lay)) {
            ++accepted;
            // an accepted image re-encodes to the bytes isocc writes for it, which read back
            // to the same image (format 2 may code one statement in several ways; isocc
            // always picks the same)
            const std::vector<uint8_t> again = image::writeImage(img);
            image::Image back;
            REQUIRE(image::readImage(again, back, err));
            CHECK(back.code == img.code);
            CHECK(image::writeImage(back) == again);
          } else {
            ++rejected;
          }
        } else {
          ++rejected;
          CHECK(err.offset <= f.size());
        }
        f[i] ^= static_cast<uint8_t>(1u << bit);
      }
    }
    image::fixCrc(f);
    CHECK(f == bytes);
    MESSAGE(s << ": " << rejected << " flips rejected, " << accepted
              << " accepted (valid images with another constant, R index, M number, line, ...)");
    CHECK(rejected > accepted);
  }
}
