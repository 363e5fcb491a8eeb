//! @file SimTestUtil.h
//! @brief Helpers of the simulator tests: compile in-memory sources exactly as isosim does,
//!        run them with a recording sink, and query the recorded events and samples.
#pragma once

#include <cmath>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <doctest/doctest.h>

#include "TestUtil.h"
#include "compiler/Compiler.h"
#include "diag/Render.h"
#include "image/Image.h"
#include "image/ImageVerifier.h"
#include "machine/Machine.h"
#include "sim/Run.h"
#include "sim/TraceWriter.h"

namespace iso::test {

/// An event with owned strings.
struct RecEvent {
  double t = 0;
  sim::EventKind kind = sim::EventKind::Line;
  std::string file;
  uint32_t line = 0;
  char axis = 0;
  double target = 0;
  uint64_t m = 0;
  bool blocking = true;
  int index = 0;
  int value = 0;
  std::string action;
  double duration = 0;
  std::string message;
  std::string state; ///< z32 spindle state / aux word
  double rpm = 0;
  bool c1 = false, c2 = false;
  int64_t tool = 0;
  double programmed = 0;
  int sent = 0;
  bool on = false;   ///< z32 axis_control
  double number = 0; ///< z32 pal: the value written
  std::string zone;  ///< zone: its name
  bool forbidden = false;
  std::vector<double> zonePosition; ///< zone: the position on each of its axes
};

/// Records everything a run produces.
class Recorder : public sim::TraceSink {
public:
  void begin(const machine::Machine& m) override { axes = m.axes.size(); }
  void sample(double t, const double* p) override {
    std::vector<double> row{t};
    row.insert(row.end(), p, p + axes);
    samples.push_back(std::move(row));
  }
  void event(const sim::Event& e) override {
    RecEvent r;
    r.t = e.t;
    r.kind = e.kind;
    r.file = std::string(e.file);
    r.line = e.line;
    r.axis = e.axis;
    r.target = e.target;
    r.m = e.m;
    r.blocking = e.blocking;
    r.index = e.index;
    r.value = e.value;
    r.action = e.action;
    r.duration = e.duration;
    r.message = std::string(e.message);
    r.state = e.state;
    r.rpm = e.rpm;
    r.c1 = e.c1;
    r.c2 = e.c2;
    r.tool = e.tool;
    r.programmed = e.programmed;
    r.sent = e.sent;
    r.on = e.on;
    r.number = e.number;
    if (e.zone) {
      r.zone = e.zone->name;
      r.forbidden = e.zone->forbidden;
      if (e.zonePosition) r.zonePosition.assign(e.zonePosition, e.zonePosition + e.zone->axes.size());
    }
    events.push_back(std::move(r));
  }
  void end(const sim::Summary& s) override {
    ended = true;
    summary = s;
  }
  size_t axes = 0;
  std::vector<std::vector<double>> samples;
  std::vector<RecEvent> events;
  sim::Summary summary;
  bool ended = false;
};

struct SimRun {
  sim::SimResult result;
  Recorder rec;
  std::string diagnostics; ///< compile errors (the run did not happen when not empty)

  const sim::Summary& summary() const { return result.summary; }
  double cycle() const { return result.summary.cycleTimeS; }
  sim::Status status() const { return result.summary.status; }
  const std::string& message() const { return result.summary.message; }
  /// Final position of an axis.
  double pos(char axis) const {
    for (const auto& [a, p] : result.summary.finalPosition)
      if (a == axis) return p;
    return std::nan("");
  }
  /// Events of a kind (optionally of one axis / one line).
  std::vector<RecEvent> events(sim::EventKind k) const {
    std::vector<RecEvent> out;
    for (const auto& e : rec.events)
      if (e.kind == k) out.push_back(e);
    return out;
  }
  /// Time of the first `line` event of a source line (NaN if it never ran).
  double lineTime(uint32_t line, size_t nth = 0) const {
    for (const auto& e : rec.events)
      if (e.kind == sim::EventKind::Line && e.line == line && nth-- == 0) return e.t;
    return std::nan("");
  }
  /// The move_end time of an axis (the nth one).
  double moveEnd(char axis, size_t nth = 0) const {
    for (const auto& e : rec.events)
      if (e.kind == sim::EventKind::MoveEnd && e.axis == axis && nth-- == 0) return e.t;
    return std::nan("");
  }
  double moveStart(char axis, size_t nth = 0) const {
    for (const auto& e : rec.events)
      if (e.kind == sim::EventKind::MoveStart && e.axis == axis && nth-- == 0) return e.t;
    return std::nan("");
  }
  double whenTime(const std::string& action, size_t nth = 0) const {
    for (const auto& e : rec.events)
      if (e.kind == sim::EventKind::When && e.action == action && nth-- == 0) return e.t;
    return std::nan("");
  }
  size_t count(sim::EventKind k) const { return events(k).size(); }
};

/// Compiles a checked program set into an image (REQUIREs that it has no errors).
inline image::Image compileSet(const frontend::ProgramSet& set, const machine::Machine& m, std::string* diags) {
  image::Image img;
  std::vector<diag::Diagnostic> errors;
  for (const auto& d : set.diags.items())
    if (d.severity == diag::Severity::Error) errors.push_back(d);
  if (!errors.empty()) {
    if (diags) *diags = diag::renderText(errors, set.sources, false);
    return img;
  }
  compiler::CompileOptions co;
  co.dialect = m.dialect;
  co.specialM = &m.specialM;
  compiler::CompileError err;
  bool ok = compiler::compileProgramSet(set, co, img, err);
  if (!ok && diags) *diags = err.message;
  return img;
}

/// Verifies `img` and runs it: the one door to the simulator (a test image the verifier
/// refuses fails the test, with the verifier's reason).
inline sim::SimResult runImage(const image::Image& img, const machine::Machine& m, const sim::SimOptions& opts,
                               sim::TraceSink* sink) {
  image::ImageError err;
  std::optional<image::VerifiedImage> verified = image::verifyImage(image::Image(img), err);
  REQUIRE_MESSAGE(verified.has_value(), "invalid image: " << err.message);
  return sim::simulate(*verified, m, opts, sink);
}

/// Compiles and runs one main program held in memory.
inline std::unique_ptr<SimRun> simText(const std::string& text, const machine::Machine& m = builtin(),
                                       sim::SimOptions opts = {}) {
  auto run = std::make_unique<SimRun>();
  auto set = loadText(text, "t.mpf", m, m.dialect);
  image::Image img = compileSet(*set, m, &run->diagnostics);
  if (!run->diagnostics.empty()) return run;
  run->result = runImage(img, m, opts, &run->rec);
  return run;
}

/// Compiles and runs a program set of several files (written to a temporary directory).
inline std::unique_ptr<SimRun> simFiles(const std::vector<std::pair<std::string, std::string>>& files,
                                        const machine::Machine& m = builtin(), sim::SimOptions opts = {}) {
  auto run = std::make_unique<SimRun>();
  SetResult sr = lintFiles(files, m, m.dialect);
  REQUIRE(sr.loaded);
  image::Image img = compileSet(*sr.set, m, &run->diagnostics);
  if (!run->diagnostics.empty()) return run;
  run->result = runImage(img, m, opts, &run->rec);
  return run;
}

/// The built-in machine with a few changes applied by `edit`.
template <class F> machine::Machine machineWith(F edit) {
  machine::Machine m = machine::builtinMachine();
  edit(m);
  return m;
}

/// A machine from JSON text (REQUIREs that it parses).
inline machine::Machine machineFromJson(const std::string& text) {
  auto r = machine::parseMachine(text);
  INFO((r ? std::string() : r.error().where + ": " + r.error().message));
  REQUIRE(r.ok());
  return *r;
}

/// Rest-to-rest trapezoid time of SPEC §5.2.
inline double moveTime(double d, double v, double a) { return d >= v * v / a ? d / v + v / a : 2 * std::sqrt(d / a); }

/// Closeness for closed-form checks: 1e-9 relative (doctest adds 1e-9 absolute near 0).
inline doctest::Approx exact(double x) { return doctest::Approx(x).epsilon(1e-9); }

} // namespace iso::test
