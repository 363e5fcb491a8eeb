//! @file Simulate.cpp
//! @brief The isosim driver: load (or compile) the program, run it, write trace and summary.
#include "driver/Simulate.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <ostream>
#include <thread>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "compiler/Compiler.h"
#include "diag/Render.h"
#include "driver/Compile.h"
#include "driver/Lint.h"
#include "frontend/ProgramSet.h"
#include "image/ImageReader.h"
#include "image/ImageVerifier.h"
#include "image/ImageWriter.h"
#include "sim/Simulator.h"
#include "sim/SvgPlot.h"
#include "sim/TimeProfile.h"
#include "sim/TraceWriter.h"

namespace iso::driver {

namespace {

bool endsWithNoCase(const std::string& s, const std::string& suffix) {
  if (s.size() < suffix.size()) return false;
  for (size_t i = 0; i < suffix.size(); ++i)
    if (std::tolower(static_cast<unsigned char>(s[s.size() - suffix.size() + i])) !=
        std::tolower(static_cast<unsigned char>(suffix[i])))
      return false;
  return true;
}

/// An output file of the run (trace, plot) that could not be created when the run started.
struct CannotCreate {
  std::string path;
  const char* what; ///< "trace" | "plot"
};

/// A trace sink that opens its output file only when the run starts, so that a run refused
/// before it starts (missing axis, unknown entry) leaves no file behind.
class FileTraceSink : public sim::TraceSink {
public:
  FileTraceSink(std::string path, bool json) : path_(std::move(path)), json_(json) {}
  bool open() {
    out_.open(path_, std::ios::binary | std::ios::trunc);
    if (!out_) return false;
    if (json_) inner_ = std::make_unique<sim::JsonTraceWriter>(out_);
    else inner_ = std::make_unique<sim::CsvTraceWriter>(out_);
    return true;
  }
  void begin(const machine::Machine& m) override {
    if (!open()) throw CannotCreate{path_, "trace"};
    inner_->begin(m);
  }
  void sample(double t, const double* p) override { inner_->sample(t, p); }
  void event(const sim::Event& e) override { inner_->event(e); }
  void end(const sim::Summary& s) override {
    inner_->end(s);
    out_.close();
    if (!out_) failed_ = true;
  }
  bool wantsEvents() const override { return json_; }
  bool failed() const { return failed_; }
  /// Removes the file again when it was created (the run could not start after all).
  void discard() {
    if (!out_.is_open()) return;
    out_.close();
    std::error_code ec;
    std::filesystem::remove(path_, ec);
  }

private:
  std::string path_;
  bool json_;
  std::ofstream out_;
  std::unique_ptr<sim::TraceSink> inner_;
  bool failed_ = false;
};

/// The plot of --plot. Its file is created when the run starts, as the trace file is, and
/// written when the run is over, whatever its outcome.
class PlotFileSink : public sim::PlotSink {
public:
  explicit PlotFileSink(std::string path) : path_(std::move(path)) {}
  void begin(const machine::Machine& m) override {
    out_.open(path_, std::ios::binary | std::ios::trunc);
    if (!out_) throw CannotCreate{path_, "plot"};
    sim::PlotSink::begin(m);
  }
  /// False on a write error.
  bool write(const std::string& title) {
    out_ << render(title);
    out_.close();
    return !out_.fail();
  }

private:
  std::string path_;
  std::ofstream out_;
};

/// "prog.mpf - cycle time 2.25 s", or "prog.mpf - emergency at t=0.5 s".
std::string plotTitle(const SimulateOptions& opts, const std::string& entry, const sim::Summary& s) {
  std::string name = std::filesystem::path(opts.program).filename().string();
  if (!entry.empty()) name += " (" + entry + ")";
  if (s.status == sim::Status::Ok) return fmt::format("{} - cycle time {} s", name, sim::formatNumber(s.cycleTimeS));
  return fmt::format("{} - {} at t={} s", name, sim::statusName(s.status), sim::formatNumber(s.cycleTimeS));
}

/// True when a and b name the same file (existing or not).
bool sameFile(const std::string& a, const std::string& b) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::equivalent(a, b, ec)) return true;
  return fs::absolute(a, ec).lexically_normal() == fs::absolute(b, ec).lexically_normal();
}

sim::Summary compileFailureSummary(const machine::Machine& m, std::string message) {
  sim::Summary s;
  s.status = sim::Status::Error;
  for (const auto& a : m.axes) s.finalPosition.emplace_back(a.letter, a.start);
  s.message = std::move(message);
  return s;
}

} // namespace

bool isImageFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char m[8] = {};
  if (!in.read(m, 8)) return false;
  return std::equal(image::kMagic.begin(), image::kMagic.end(), reinterpret_cast<const uint8_t*>(m));
}

bool loadImageFile(const std::string& path, image::Image& out, std::string& error) {
  std::vector<uint8_t> bytes;
  std::string why;
  if (!readBinaryFile(path, bytes, why)) {
    error = fmt::format("{}: error: {}", path, why);
    return false;
  }
  image::ImageError err;
  image::Layout layout;
  if (!image::readImage(bytes, out, err, &layout) || !image::verifyImage(out, err, &layout)) {
    error = fmt::format("{}+0x{:04X}: error: invalid image: {}", path, err.offset, err.message);
    return false;
  }
  return true;
}

int runSimulate(const SimulateOptions& opts, Io& io) {
  auto m = loadMachine(opts.common, io);
  if (!m) return kExitUsage;
  if (opts.printMachine) {
    io.out << machine::machineToJson(*m) << "\n";
    return kExitOk;
  }
  if (opts.program.empty()) {
    io.err << "isosim: error: no program (give an image from isocc or a .mpf file)\n";
    return kExitUsage;
  }
  if (!(opts.dt > 0) || !std::isfinite(opts.dt)) {
    io.err << "isosim: error: --dt must be a number of seconds > 0\n";
    return kExitUsage;
  }
  if (!(opts.maxTime > 0) || std::isnan(opts.maxTime)) {
    io.err << "isosim: error: --max-time must be a number of seconds > 0\n";
    return kExitUsage;
  }
  if (opts.maxSteps == 0) {
    io.err << "isosim: error: --max-steps must be at least 1\n";
    return kExitUsage;
  }
  std::string format = opts.format;
  if (format.empty()) format = endsWithNoCase(opts.output, ".json") ? "json" : "csv";
  if (format != "csv" && format != "json") {
    io.err << fmt::format("isosim: error: unknown format '{}' (csv or json)\n", format);
    return kExitUsage;
  }
  const bool json = format == "json";
  if (!opts.plot.empty() && !opts.output.empty() && sameFile(opts.plot, opts.output)) {
    io.err << fmt::format("isosim: error: --plot and -o name the same file ({})\n", opts.plot);
    return kExitUsage;
  }

  // Where the summary goes (see Simulate.h); the profile follows it.
  const bool noTrace = opts.summary || (opts.profile && opts.output.empty());
  sim::TimeProfile profile;
  bool profiled = false;
  auto printSummary = [&](const sim::Summary& s) -> int {
    const bool jsonOut = json && (noTrace || !opts.output.empty());
    std::string text = jsonOut ? sim::summaryJson(s, 2) + "\n" : sim::summaryText(s);
    if (opts.profile && profiled) {
      if (jsonOut) {
        nlohmann::ordered_json j;
        j["summary"] = nlohmann::ordered_json::parse(sim::summaryJson(s, 0));
        j["profile"] = nlohmann::ordered_json::parse(sim::renderProfileJson(profile));
        text = j.dump(2) + "\n";
      } else {
        text += "\n" + sim::renderProfileText(profile);
      }
    }
    if (opts.summary && !opts.output.empty()) {
      std::ofstream out(opts.output, std::ios::binary | std::ios::trunc);
      out << text;
      out.close();
      if (!out) {
        io.err << fmt::format("{}: error: cannot write the summary\n", opts.output);
        return kExitUsage;
      }
    } else if (noTrace || !opts.output.empty()) {
      io.out << text;
    } else {
      io.err << text;
    }
    return kExitOk;
  };
  const bool summaryOnStderr = !noTrace && opts.output.empty();

  // ---- the program: an image, or a source program set compiled in memory
  image::Image img;
  std::string entry = opts.entry;
  if (isImageFile(opts.program)) {
    if (!opts.paths.empty()) {
      io.err << "isosim: error: PATH... can only follow a source program (.mpf), not an image\n";
      return kExitUsage;
    }
    std::string err;
    if (!loadImageFile(opts.program, img, err)) {
      io.err << err << "\n";
      return kExitUsage;
    }
  } else {
    frontend::LoadOptions lo;
    lo.machine = &*m;
    lo.dialect = m->dialect;
    lo.jobs = std::max(1u, std::min(4u, std::thread::hardware_concurrency()));
    frontend::ProgramSet set;
    frontend::SetError serr;
    std::vector<std::string> paths{opts.program};
    paths.insert(paths.end(), opts.paths.begin(), opts.paths.end());
    if (!frontend::loadProgramSet(paths, lo, set, serr)) {
      io.err << fmt::format("{}: error: {}\n", serr.path, serr.message);
      return kExitUsage;
    }
    auto diags = visibleDiagnostics(set, {}, false);
    if (diag::countOf(diags).errors > 0) {
      std::vector<diag::Diagnostic> errors;
      for (const auto& d : diags)
        if (d.severity == diag::Severity::Error) errors.push_back(d);
      printTextDiagnostics(errors, set, io.err, useColor(opts.common, io.errIsTty), true);
      int rc = printSummary(compileFailureSummary(*m, fmt::format("{}: the program set has errors; nothing was run",
                                                                   opts.program)));
      return rc != kExitOk ? rc : kExitErrors;
    }
    compiler::CompileOptions co;
    co.dialect = m->dialect;
    compiler::CompileError cerr;
    if (!compiler::compileProgramSet(set, co, img, cerr)) {
      io.err << fmt::format("isosim: error: {}\n", cerr.message);
      int rc = printSummary(compileFailureSummary(*m, cerr.message));
      return rc != kExitOk ? rc : kExitErrors;
    }
    // A semi-automatic program named as PROGRAM runs itself (unless --entry says otherwise).
    if (entry.empty() && !set.namedOrder.empty()) {
      const frontend::File& f = set.files[set.namedOrder.front()];
      if (f.kind == frontend::UnitKind::Semi) entry = f.semiName;
    }
  }

  // ---- run
  sim::SimOptions so;
  so.dt = opts.dt;
  so.blockSkip = opts.blockSkip;
  so.maxSteps = opts.maxSteps;
  so.maxTime = opts.maxTime;
  so.entry = entry;
  if (opts.profile) so.profile = &profile;
  std::unique_ptr<sim::TraceSink> trace;
  FileTraceSink* fileSink = nullptr;
  if (!noTrace) {
    if (!opts.output.empty()) {
      auto fs = std::make_unique<FileTraceSink>(opts.output, json);
      fileSink = fs.get();
      trace = std::move(fs);
    } else if (json) {
      trace = std::make_unique<sim::JsonTraceWriter>(io.out);
    } else {
      trace = std::make_unique<sim::CsvTraceWriter>(io.out);
    }
  }
  std::unique_ptr<PlotFileSink> plot;
  if (!opts.plot.empty()) plot = std::make_unique<PlotFileSink>(opts.plot);
  // The plot samples at --dt with or without a trace (also with --summary).
  std::optional<sim::TeeSink> tee;
  if (trace && plot) tee.emplace(std::vector<sim::TraceSink*>{trace.get(), plot.get()});
  sim::TraceSink* sink = tee ? &*tee : trace ? trace.get() : plot.get();
  sim::SimResult res;
  try {
    res = sim::simulate(img, *m, so, sink);
  } catch (const CannotCreate& e) {
    if (fileSink) fileSink->discard(); // no empty trace left behind when the plot file fails
    io.err << fmt::format("{}: error: cannot create the {} file\n", e.path, e.what);
    return kExitUsage;
  }
  if (res.setupError != sim::SetupError::None) {
    io.err << fmt::format("{}: error: {}\n", opts.program, res.setupMessage);
    return kExitUsage;
  }
  if (fileSink && fileSink->failed()) {
    io.err << fmt::format("{}: error: write error\n", opts.output);
    return kExitUsage;
  }
  if (plot && !plot->write(plotTitle(opts, entry, res.summary))) {
    io.err << fmt::format("{}: error: cannot write the plot file\n", opts.plot);
    return kExitUsage;
  }
  profiled = opts.profile;
  const sim::Summary& s = res.summary;
  if (s.status != sim::Status::Ok && !summaryOnStderr) io.err << "isosim: " << s.message << "\n";
  int rc = printSummary(s);
  if (rc != kExitOk) return rc;
  switch (s.status) {
  case sim::Status::Ok: return kExitOk;
  case sim::Status::Error: return kExitErrors;
  case sim::Status::Emergency: return kExitEmergency;
  }
  return kExitInternal;
}

} // namespace iso::driver
