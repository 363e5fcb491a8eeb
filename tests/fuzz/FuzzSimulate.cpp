//! @file FuzzSimulate.cpp
//! @brief Fuzz target: source text -> frontend -> compiler -> image bytes -> reader + verifier
//!        -> interpreter with small step and time budgets (STYLE habit 13: a verified image
//!        must run without a crash, a hang or an internal error, whatever it does).
//!        The sink checks the trace invariants: sample times strictly increase, event times
//!        never decrease, the run ends once, at or after its last event.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "compiler/Compiler.h"
#include "frontend/ProgramSet.h"
#include "image/ImageReader.h"
#include "image/ImageVerifier.h"
#include "image/ImageWriter.h"
#include "machine/Machine.h"
#include "sim/Simulator.h"

namespace {

class CheckingSink : public iso::sim::TraceSink {
public:
  void begin(const iso::machine::Machine& m) override {
    if (begun_) std::abort();
    begun_ = true;
    axes_ = m.axes.size();
  }
  void sample(double t, const double* p) override {
    if (!begun_ || ended_ || !(t > lastSample_) || !std::isfinite(t)) std::abort();
    for (size_t i = 0; i < axes_; ++i)
      if (!std::isfinite(p[i])) std::abort();
    lastSample_ = t;
  }
  void event(const iso::sim::Event& e) override {
    if (!begun_ || ended_ || e.t < lastEvent_ || !std::isfinite(e.t)) std::abort();
    lastEvent_ = e.t;
  }
  void end(const iso::sim::Summary& s) override {
    if (!begun_ || ended_ || s.cycleTimeS < lastEvent_ || s.cycleTimeS < lastSample_) std::abort();
    if (s.finalPosition.size() != axes_) std::abort();
    if ((s.status == iso::sim::Status::Ok) != s.message.empty()) std::abort();
    ended_ = true;
  }

private:
  bool begun_ = false, ended_ = false;
  size_t axes_ = 0;
  double lastSample_ = -1, lastEvent_ = 0;
};

iso::machine::Machine fuzzMachine() {
  iso::machine::Machine m = iso::machine::builtinMachine();
  m.mSequences[23] = {0.25, {{3, 1}}};
  m.mSequences[24] = {0.5, {{3, 0}}};
  m.inputs[5] = {{0.1, 1}, {0.7, 0}};
  m.m0WaitS = 0.05;
  m.blockTimeS = 0.001;
  return m;
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const iso::machine::Machine machine = fuzzMachine();
  if (size > 64 * 1024) return 0;
  std::string text(reinterpret_cast<const char*>(data), size);
  iso::frontend::LoadOptions lo;
  lo.machine = &machine;
  lo.dialect = machine.dialect;
  iso::frontend::ProgramSet set;
  iso::frontend::loadSingleSource("fuzz.mpf", text, lo, set);
  for (const auto& d : set.diags.items())
    if (d.severity == iso::diag::Severity::Error) return 0;
  iso::image::Image compiled;
  iso::compiler::CompileError cerr;
  if (!iso::compiler::compileProgramSet(set, {}, compiled, cerr)) return 0;
  // through the bytes, the reader and the verifier, as isosim loads an image
  std::vector<uint8_t> bytes = iso::image::writeImage(compiled);
  iso::image::Image img;
  iso::image::ImageError ierr;
  iso::image::Layout layout;
  if (!iso::image::readImage(bytes, img, ierr, &layout) || !iso::image::verifyImage(img, ierr, &layout))
    std::abort(); // the compiler wrote an image its own loader refuses
  iso::sim::SimOptions opts;
  opts.maxSteps = 20000;
  opts.maxTime = 30;
  opts.dt = 0.05;
  CheckingSink sink;
  iso::sim::SimResult r = iso::sim::simulate(img, machine, opts, &sink); // internal errors throw: a crash
  if (r.setupError != iso::sim::SetupError::None) std::abort();
  // summary only: the same outcome
  iso::sim::SimResult q = iso::sim::simulate(img, machine, opts, nullptr);
  if (q.summary.status != r.summary.status || q.summary.cycleTimeS != r.summary.cycleTimeS ||
      q.summary.message != r.summary.message)
    std::abort();
  return 0;
}
