//! @file ImageFile.h
//! @brief Image files as isocc and isosim load them: one test for "is this an image", one
//!        loader (read, reader, verifier) and one shape of its messages.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "image/Image.h"
#include "image/ImageVerifier.h"

namespace iso::driver {

/// True when the file starts with the image magic (an image, not a source).
bool isImageFile(const std::string& path);

/// An image file after loading: verified, or why not.
struct LoadedImage {
  std::optional<image::VerifiedImage> verified;
  /// The image when it reads but fails the verifier (listings show what is wrong with it).
  std::optional<image::Image> unverified;
  /// Why it is not verified, one line: "FILE: error: WHY" when the file cannot be read,
  /// "FILE+0xOFFSET: error: WHY" when the reader or the verifier rejects it.
  std::string error;

  /// The image as read (verified or not), or nullptr when it does not read.
  const image::Image* image() const { return verified ? &verified->image() : unverified ? &*unverified : nullptr; }
};

/// Loads an image file. `what` stands before the reason of a rejected image: isosim says
/// "invalid image: ", isocc says nothing.
LoadedImage loadImageFile(const std::string& path, const char* what = "");

} // namespace iso::driver
