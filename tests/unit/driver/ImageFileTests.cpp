//! @file ImageFileTests.cpp
//! @brief Loading an image file: a large one is mapped, and the verifier's message for it is the
//!        one it gives for the same bytes held in memory.
#include <algorithm>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <doctest/doctest.h>
#include <fmt/format.h>

#include "driver/ImageFile.h"
#include "image/ImageReader.h"
#include "image/ImageWriter.h"
#include "image/Opcode.h"
#include "sim/SimTestUtil.h"
#include "support/SourceText.h"

using namespace iso;
using namespace iso::test;

TEST_CASE("image file: a large image the verifier rejects gets the message of its bytes held in memory") {
  std::string text = "R1 = 0\n";
  for (int64_t i = 0; i < 80000; ++i) // numbers that change a lot: about 20 bytes a statement
    text += fmt::format("G01 X{}.{} Y{}.{} Z{}.{} F{}\n", (i * 7919) % 99991, i % 997, (i * 104729) % 99989, i % 991,
                        (i * 1299709) % 99971, i % 983, 100 + i % 9973);
  text += "M30\n";
  auto set = loadSource(text, "big.mpf", builtin(), builtin().dialect, false); // (loadText: slow at this size)
  std::string diags;
  image::Image img = compileSet(*set, builtin(), &diags);
  REQUIRE_MESSAGE(diags.empty(), diags);
  std::vector<uint8_t> bytes = image::writeImage(img);
  REQUIRE(bytes.size() > support::kMapSourcesFrom); // mapped, not read
  REQUIRE(bytes.size() % 4096 != 0);
  // R1 = 0, the first statement, is coded instruction by instruction: its R index becomes 0
  const std::array<uint8_t, 5> r1 = {static_cast<uint8_t>(image::Op::Stmt), static_cast<uint8_t>(image::Op::PushD0), 0,
                                     static_cast<uint8_t>(image::Op::StoreR), 1};
  auto at = std::search(bytes.begin(), bytes.end(), r1.begin(), r1.end());
  REQUIRE(at != bytes.end());
  at[4] = 0;
  image::fixCrc(bytes);
  image::Image back;
  image::ImageError err;
  image::Layout layout;
  REQUIRE(image::readImage(bytes, back, err, &layout));
  REQUIRE_FALSE(image::verifyImage(back, err, &layout));
  CHECK(err.message.find("R0 outside") != std::string::npos);

  TempDir dir;
  const std::string path = dir.write("big.isob", std::string(bytes.begin(), bytes.end()));
  const driver::LoadedImage loaded = driver::loadImageFile(path, "invalid image: ");
  CHECK_FALSE(loaded.verified);
  REQUIRE(loaded.unverified);
  CHECK(loaded.unverified->code == back.code);
  CHECK(loaded.error == fmt::format("{}+0x{:04X}: error: invalid image: {}", path, err.offset, err.message));
}
