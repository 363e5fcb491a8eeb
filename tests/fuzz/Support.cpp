//! @file Support.cpp
#include "Support.h"

#include <cstdio>
#include <exception>
#include <vector>

#include "image/ImageReader.h"
#include "image/ImageVerifier.h"
#include "image/ImageWriter.h"

namespace iso::fuzz {

void fail(const char* target, const char* what, const std::string& detail) {
  std::fprintf(stderr, "%s: %s%s\n", target, what, detail.c_str());
  __builtin_trap();
}

bool hasErrors(const frontend::ProgramSet& set) {
  for (const auto& d : set.diags.items())
    if (d.severity == diag::Severity::Error) return true;
  return false;
}

bool compileAndLoad(const frontend::ProgramSet& set, const compiler::CompileOptions& opts, image::Image& out,
                    const char* target) {
  image::Image compiled;
  compiler::CompileError cerr;
  if (!compiler::compileProgramSet(set, opts, compiled, cerr)) return false;
  const std::vector<uint8_t> bytes = image::writeImage(compiled);
  image::ImageError ierr;
  image::Layout layout;
  if (!image::readImage(bytes, out, ierr, &layout) || !image::verifyImage(out, ierr, &layout))
    fail(target, "the compiler wrote an image its own loader refuses: ", ierr.message);
  return true;
}

sim::SimResult runBounded(const image::Image& img, const machine::Machine& m, const std::string& entry, bool blockSkip,
                          const Budget& budget, const char* target) {
  sim::SimOptions opts;
  opts.maxSteps = budget.maxSteps;
  opts.maxTime = budget.maxTime;
  opts.dt = budget.dt;
  opts.entry = entry;
  opts.blockSkip = blockSkip;
  sim::SimResult r;
  try {
    r = sim::simulate(img, m, opts, nullptr);
  } catch (const std::exception& e) {
    fail(target, "simulate threw: ", e.what());
  } catch (...) {
    fail(target, "simulate threw a non-standard exception");
  }
  switch (r.setupError) {
  case sim::SetupError::None: break;
  case sim::SetupError::AxisMissing: return r; // an axis the machine lacks: exit 2, fine
  case sim::SetupError::InvalidImage: fail(target, "a verified image does not decode: ", r.setupMessage);
  case sim::SetupError::UnknownEntry: fail(target, "an entry the image names is unknown: ", r.setupMessage);
  }
  const sim::Summary& s = r.summary;
  if (s.status != sim::Status::Ok && s.status != sim::Status::Error && s.status != sim::Status::Emergency)
    fail(target, "status not ok/error/emergency");
  if (s.blocks >= budget.maxSteps) fail(target, "--max-steps statements or more ran (SPEC §6.3: the last one stops)");
  if (!(s.cycleTimeS >= 0) || s.cycleTimeS > budget.maxTime * (1 + 1e-9) + 1e-9)
    fail(target, "cycle time negative or over --max-time");
  if ((s.status == sim::Status::Ok) != s.message.empty()) fail(target, "status ok iff no message");
  if (s.finalPosition.size() != m.axes.size()) fail(target, "final position of the wrong size");
  return r;
}

} // namespace iso::fuzz
