//! @file ImageFile.cpp
//! @brief Loading image files for isocc and isosim.
#include "driver/ImageFile.h"

#include <algorithm>
#include <fstream>

#include <fmt/format.h>

#include "image/ImageReader.h"
#include "image/ImageWriter.h"
#include "support/File.h"
#include "support/SourceText.h"
#include "support/Text.h"

namespace iso::driver {

bool isImageFile(const std::string& path) {
  bool whole = false;
  auto m = support::readFilePrefix(path, image::kMagic.size(), whole); // a pipe is read once, and kept
  return m && m->size() == image::kMagic.size() &&
         std::equal(image::kMagic.begin(), image::kMagic.end(), reinterpret_cast<const uint8_t*>(m->data()));
}

LoadedImage loadImageFile(const std::string& path, const char* what) {
  LoadedImage out;
  const std::string shown = support::escapeForTerminal(path);
  // a large file is mapped, not copied (at most support::kMaxInputBytes); the layout points into
  // it for the verifier's messages, and it is unmapped on return
  support::Expected<support::SourceText> bytes = support::readSource(path);
  if (!bytes) {
    out.error = fmt::format("{}: error: {}", shown, bytes.error().message);
    return out;
  }
  image::Image img;
  image::ImageError err;
  image::Layout layout;
  layout.borrowCode = true;
  const bool read = image::readImage(reinterpret_cast<const uint8_t*>(bytes->data()), bytes->size(), img, err, &layout);
  if (read) {
    bytes->dropPages(); // read again only for a message of the verifier
    out.verified = image::verifyImage(std::move(img), err, &layout);
    if (out.verified) return out;
    out.unverified = std::move(img); // left as it was by the failed verification
  }
  out.error = fmt::format("{}+0x{:04X}: error: {}{}", shown, err.offset, what, support::escapeForTerminal(err.message));
  return out;
}

} // namespace iso::driver
