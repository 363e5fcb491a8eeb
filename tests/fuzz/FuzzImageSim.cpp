//! @file FuzzImageSim.cpp
//! @brief Fuzz target: bytes -> ImageReader -> ImageVerifier -> interpreter (sim::simulate) on
//!        the built-in machine with small budgets. A verified image, whatever its code, must run
//!        to an end (ok, error or emergency) within its budgets: no crash, no exception, no hang
//!        (the interpreter counts instructions too, 16 per statement of --max-steps).
//!
//! Input format: image bytes (see lib/image). The total size and the CRC are fixed up before
//! reading, so that mutations get past the checksum (FuzzImage checks the checksum itself).
//! The main program runs; an image with semi-automatic programs also runs its first one (by
//! the name entryNames() gives), with block skip on. Run libFuzzer with -timeout=10: a run that takes longer is a hang.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "Support.h"
#include "image/ImageReader.h"
#include "image/ImageVerifier.h"
#include "image/ImageWriter.h"
#include "image/Opcode.h"
#include "machine/Machine.h"
#include "sim/Run.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const iso::machine::Machine machine = iso::machine::builtinMachine();
  if (size < iso::image::kHeaderSize || size > (1u << 20)) return 0;
  std::vector<uint8_t> bytes(data, data + size);
  iso::image::patchU32(bytes, iso::image::kOffTotalSize, static_cast<uint32_t>(size));
  iso::image::fixCrc(bytes);
  iso::image::Image img;
  iso::image::ImageError err;
  iso::image::Layout layout;
  if (!iso::image::readImage(bytes, img, err, &layout)) return 0;
  const std::optional<iso::image::VerifiedImage> verified = iso::image::verifyImage(std::move(img), err, &layout);
  if (!verified) return 0;
  const iso::fuzz::Budget budget;
  (void)iso::fuzz::runBounded(*verified, machine, "", false, budget, "FuzzImageSim");
  const std::vector<std::string> entries = iso::sim::entryNames(verified->image());
  // the listed (escaped) name selects its entry too (a finding of this target, now fixed)
  if (entries.size() > 1) (void)iso::fuzz::runBounded(*verified, machine, entries[1], true, budget, "FuzzImageSim");
  return 0;
}
