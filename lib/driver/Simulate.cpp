//! @file Simulate.cpp
//! @brief The isosim driver: load (or compile) the program, run it, write trace and summary.
#include "driver/Simulate.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <ostream>
#include <set>
#include <stdexcept>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "compiler/Compiler.h"
#include "diag/Render.h"
#include "driver/Compare.h"
#include "driver/Compile.h"
#include "driver/ImageFile.h"
#include "driver/Lint.h"
#include "driver/MachineOverrides.h"
#include "driver/Report.h"
#include "driver/Settings.h"
#include "driver/Sources.h"
#include "frontend/GoTarget.h"
#include "frontend/ProgramSet.h"
#include "image/ImageReader.h"
#include "image/ImageVerifier.h"
#include "image/ImageWriter.h"
#include "sim/Run.h"
#include "sim/SvgPlot.h"
#include "sim/TimeProfile.h"
#include "sim/Timeline.h"
#include "sim/TraceWriter.h"
#include "support/CaseFold.h"
#include "support/File.h"
#include "support/Text.h"

namespace iso::driver {

namespace {

/// An output file of the run (trace, plot) that could not be created when the run started.
struct CannotCreate {
  std::string path;
  const char* what; ///< "trace" | "plot" | "timeline" | "report"
  std::string why;
};

/// A trace sink that opens its output file only when the run starts, so that a run refused
/// before it starts (missing axis, unknown entry) leaves no file behind. The file is written
/// through a temporary file and replaces FILE only at commit().
class FileTraceSink : public sim::TraceSink {
public:
  FileTraceSink(std::string path, bool json) : file_(std::move(path)), json_(json) {}
  void begin(const machine::Machine& m) override {
    if (support::Status opened = file_.open(); !opened) throw CannotCreate{file_.target(), "trace", opened.why()};
    if (json_)
      inner_ = std::make_unique<sim::JsonTraceWriter>(file_.stream());
    else
      inner_ = std::make_unique<sim::CsvTraceWriter>(file_.stream());
    inner_->begin(m);
  }
  void sample(double t, const double* p) override { inner_->sample(t, p); }
  void event(const sim::Event& e) override { inner_->event(e); }
  void end(const sim::Summary& s) override { inner_->end(s); }
  bool wantsEvents() const override { return json_; }
  support::Status commit() { return file_.commit(); }
  /// Removes the temporary file (the run could not start after all); FILE is untouched.
  void discard() { file_.discard(); }

private:
  support::AtomicFile file_;
  bool json_;
  std::unique_ptr<sim::TraceSink> inner_;
};

/// An output file of the run other than the trace (plot, timeline, report): created when the
/// run starts, as the trace file is (a run refused before it starts leaves nothing behind),
/// and written whole when the run is over, whatever its outcome. An empty path: no file.
class RunOutput {
public:
  RunOutput(std::string path, const char* what) : file_(std::move(path)), what_(what) {}
  void open() {
    if (file_.target().empty()) return;
    if (support::Status opened = file_.open(); !opened) throw CannotCreate{file_.target(), what_, opened.why()};
  }
  /// Writes `text` and replaces FILE with it, or says why it could not.
  support::Status write(const std::string& text) {
    if (file_.target().empty()) return {};
    file_.stream() << text;
    return file_.commit();
  }

private:
  support::AtomicFile file_;
  const char* what_;
};

/// The plot of --plot (also drawn, without a file, for --report).
class PlotFileSink : public sim::PlotSink {
public:
  explicit PlotFileSink(std::string path) : out_(std::move(path), "plot") {}
  void begin(const machine::Machine& m) override {
    out_.open();
    sim::PlotSink::begin(m);
  }
  support::Status write(const std::string& title) { return out_.write(render(title)); }

private:
  RunOutput out_;
};

/// The trace-event JSON of --timeline.
class TimelineFileSink : public sim::TimelineSink {
public:
  TimelineFileSink(std::string path, const sim::TimeProfile* profile)
      : sim::TimelineSink(profile), out_(std::move(path), "timeline") {}
  void begin(const machine::Machine& m) override {
    out_.open();
    sim::TimelineSink::begin(m);
  }
  support::Status write(const std::string& program) { return out_.write(render(program)); }

private:
  RunOutput out_;
};

/// The page of --report: its file is created when the run starts; it wants nothing of the run
/// (the plot and the profile provide its contents).
class ReportFile : public sim::TraceSink {
public:
  explicit ReportFile(std::string path) : out_(std::move(path), "report") {}
  void begin(const machine::Machine&) override { out_.open(); }
  void sample(double, const double*) override {}
  void event(const sim::Event&) override {}
  void end(const sim::Summary&) override {}
  bool wantsSamples() const override { return false; }
  bool wantsEvents() const override { return false; }
  support::Status write(const std::string& html) { return out_.write(html); }

private:
  RunOutput out_;
};

/// Simulated seconds per second of computing: a whole number from 10, else one decimal.
std::string speedText(double ratio) {
  return sim::formatNumber(ratio >= 10 ? std::floor(ratio) : std::floor(ratio * 10) / 10);
}

/// The progress line of a long run on a terminal (standard error): shown after the first
/// second, refreshed at most ten times a second, erased when the run is over. The speed is
/// simulated seconds per second of computing.
class ProgressLine {
public:
  explicit ProgressLine(std::ostream& err) : err_(err), start_(Clock::now()), last_(start_) {}
  void update(double simTime, uint64_t blocks, uint64_t lines) {
    const auto now = Clock::now();
    if (now - start_ < std::chrono::seconds(1) || now - last_ < std::chrono::milliseconds(100)) return;
    last_ = now;
    const double wall = std::chrono::duration<double>(now - start_).count();
    err_ << fmt::format("\risosim: running... t={} simulated, {} blocks, {} lines, {}x real time\x1b[K",
                        sim::clockTime(std::floor(simTime * 10) / 10), blocks, lines, speedText(simTime / wall))
         << std::flush;
    shown_ = true;
  }
  void erase() {
    if (shown_) err_ << "\r\x1b[K" << std::flush;
    shown_ = false;
  }

private:
  using Clock = std::chrono::steady_clock;
  std::ostream& err_;
  Clock::time_point start_, last_;
  bool shown_ = false;
};

/// "prog.mpf - cycle time 2.25 s", or "prog.mpf - emergency at t=0.5 s".
std::string plotTitle(const SimulateOptions& opts, const std::string& entry, const sim::Summary& s) {
  std::string name = std::filesystem::path(opts.program).filename().string();
  if (!entry.empty()) name += " (" + entry + ")";
  if (s.status == sim::Status::Ok) return fmt::format("{} - cycle time {} s", name, sim::formatNumber(s.cycleTimeS));
  return fmt::format("{} - {} at t={} s", name, sim::statusName(s.status), sim::formatNumber(s.cycleTimeS));
}

/// A program set compiled in memory goes through the verifier like an image file; the offsets
/// of a failure would be those of the tables (no file), and a failure is a compiler bug.
image::VerifiedImage verifyCompiled(image::Image&& img) {
  image::ImageError err;
  const image::Layout tables; // no file: offsets count from each table
  auto verified = image::verifyImage(std::move(img), err, &tables);
  if (!verified) throw std::logic_error(fmt::format("the compiled program fails the image verifier: {}", err.message));
  return std::move(*verified);
}

sim::Summary compileFailureSummary(const machine::Machine& m, std::string message) {
  sim::Summary s;
  s.status = sim::Status::Error;
  for (const auto& a : m.axes)
    s.finalPosition.emplace_back(a.letter, a.start);
  s.message = std::move(message);
  return s;
}

/// The 1-based line of `f` that a block search for `text` starts at, 0 when none: in z32 a
/// text shaped as a GO target finds its line by the GO rule, any other text (and every text in
/// sidac) names a label, in any case. `blanks`: a line that would match but for blanks before it.
uint32_t searchedLine(const frontend::ProgramSet& set, const frontend::File& f, const std::string& text, bool z32,
                      uint32_t* blanks = nullptr) {
  if (f.binary) return 0;
  if (z32 && frontend::isGoTargetText(text)) {
    const frontend::GoLineMatch found = frontend::findGoLine(set.sources.file(f.id).text.view(), text);
    if (blanks) *blanks = found.blankCandidate;
    return found.line;
  }
  for (const frontend::StmtLabel& l : f.labels)
    if (support::iequals(l.text, text)) return f.stmts[l.stmt].line;
  return 0;
}

/// --search TEXT names no line of the entry program `f`: why, naming the file that has it when
/// another file of the set does (a subprogram, another main program).
std::string searchNotFound(const frontend::ProgramSet& set, const frontend::File& f, const std::string& text,
                           bool z32) {
  const std::string file = support::escapeForTerminal(f.path);
  for (const frontend::File& g : set.files) {
    if (&g == &f) continue;
    if (uint32_t line = searchedLine(set, g, text, z32); line > 0) {
      const std::string where = fmt::format("{}:{}", support::escapeForTerminal(g.path), line);
      if (g.kind == frontend::UnitKind::Sub)
        return fmt::format("the line is in subprogram {} ({}), not in the entry program {}: a block search starts at "
                           "a line of the entry program",
                           support::escapeForTerminal(std::string(g.procName)), where, file);
      return fmt::format("the line is in {}, not in the entry program {} (--entry picks the entry program)", where,
                         file);
    }
  }
  uint32_t blanks = 0;
  if (z32 && frontend::isGoTargetText(text)) {
    searchedLine(set, f, text, z32, &blanks);
    std::string why = fmt::format("no line of {} begins with {}", file, support::escapeForTerminal(text));
    if (blanks > 0)
      why += fmt::format(
          " (line {} would but for the blanks before it: a searched line begins at the start of the line)", blanks);
    return why;
  }
  return fmt::format("{} has no label {}", file, support::escapeForTerminal(text));
}

/// searchNotFound over every file of the program set: the siblings that `set` did not read
/// (it reads only what the image links) are read for it, as a set of every sibling.
std::string searchNotFoundInSet(const frontend::ProgramSet& set, const frontend::File& f, const std::string& text,
                                bool z32, const std::vector<std::string>& paths, const machine::Machine& m) {
  if (set.unread.empty()) return searchNotFound(set, f, text, z32);
  frontend::ProgramSet whole;
  loadSources(paths, m, SourceOptions{}, whole);
  for (const frontend::File& g : whole.files)
    if (g.path == f.path) return searchNotFound(whole, g, text, z32);
  return searchNotFound(set, f, text, z32);
}

/// Resolves --search in the entry program of the compiled set of `paths`: kExitOk (with
/// rq.found set, or an entry that names no program, which the run reports), else kExitUsage
/// with the reason.
int resolveSearch(const frontend::ProgramSet& set, const std::vector<std::string>& paths, const machine::Machine& m,
                  const compiler::CompileOptions& co, const image::Image& img, const std::string& entry,
                  SearchRequest& rq, Io& io) {
  auto refuse = [&](const std::string& why) {
    io.err << fmt::format("isosim: error: --search {}: {}\n", support::escapeForTerminal(rq.text), why);
    return kExitUsage;
  };
  if (rq.text.empty()) {
    io.err << "isosim: error: --search needs a label (or, in dialect z32, a line number such as N20)\n";
    return kExitUsage;
  }
  const std::optional<uint32_t> proc = sim::entryProc(img, entry);
  if (!proc) return kExitOk;
  compiler::CompileError cerr;
  const std::vector<size_t> units = compiler::linkedUnits(set, co, cerr);
  if (*proc >= units.size()) throw std::logic_error("--search: the entry procedure has no source file");
  const frontend::File& f = set.files[units[*proc]];
  const bool z32 = img.z32();
  const uint32_t line = searchedLine(set, f, rq.text, z32);
  if (line == 0) return refuse(searchNotFoundInSet(set, f, rq.text, z32, paths, m));
  // the first statement at or after the line (a label alone on its line starts at the next one)
  const image::Proc& p = img.procs[*proc];
  const image::LineEntry* best = nullptr;
  for (const image::LineEntry& le : img.lines)
    if (le.file == p.file && le.offset >= p.entry && le.offset - p.entry < p.size && le.line >= line &&
        (!best || le.line < best->line || (le.line == best->line && le.offset < best->offset)))
      best = &le;
  if (!best) return refuse(fmt::format("{}:{} has no statement at or after it to start at", f.path, line));
  rq.found = sim::SimOptions::Search{best->offset, {rq.text, image::printableName(img.strings[p.file]), line}};
  return kExitOk;
}

} // namespace

int loadProgram(const std::string& program, const std::vector<std::string>& paths, const CommonOptions& common,
                const Settings& settings, const machine::Machine& m, Io& io,
                const std::function<int(const std::vector<std::string>&)>& checkInputs,
                std::optional<image::VerifiedImage>& img, std::string& entry, std::string& compileError,
                SearchRequest* search) {
  compileError.clear();
  std::vector<std::string> inputs;
  if (isImageFile(program)) {
    if (!paths.empty())
      return usageError(io, "isosim", "PATH... can only follow a source program (.mpf), not an image");
    if (search)
      return usageError(io, "isosim",
                        "--search needs the source program (a .mpf), not an image: an image keeps no labels");
    inputs = {program};
    if (!common.machinePath.empty()) inputs.push_back(common.machinePath);
    if (!common.settingsFile.empty()) inputs.push_back(common.settingsFile);
    if (int rc = checkInputs(inputs); rc != kExitOk) return rc;
    LoadedImage loaded = loadImageFile(program, "invalid image: ");
    if (!loaded.verified) {
      io.err << loaded.error << "\n";
      return kExitUsage;
    }
    img = std::move(loaded.verified);
    return kExitOk;
  }
  frontend::ProgramSet set;
  std::vector<std::string> all{program};
  all.insert(all.end(), paths.begin(), paths.end());
  if (int rc = loadToolSources(all, m, std::min(4u, hardwareJobs()), settings, set, io, "isosim", /*compact=*/true);
      rc != kExitOk)
    return rc;
  if (int rc = checkInputs(inputPaths(set, common)); rc != kExitOk) return rc;
  printToolDiagnostics(set, common, settings, io);
  if (diag::countOf(set.diags.items()).errors > 0) {
    compileError = fmt::format("{}: the program set has errors; nothing was run", program);
    return kExitErrors;
  }
  compiler::CompileOptions co;
  co.dialect = m.dialect;
  co.specialM = &m.specialM;
  co.parameters = &m.parameters;
  const frontend::LexOptions lex = sourceLexOptions(m);
  co.reparse = &lex; // a line at a time: no unit's tree is held whole
  compiler::CompileError cerr;
  image::Image compiled;
  if (!compiler::compileProgramSet(set, co, compiled, cerr)) {
    io.err << fmt::format("isosim: error: {}\n", cerr.message);
    compileError = cerr.message;
    return kExitErrors;
  }
  img = verifyCompiled(std::move(compiled));
  // A semi-automatic program named as PROGRAM runs itself (unless --entry says otherwise).
  if (entry.empty() && !set.namedOrder.empty()) {
    const frontend::File& f = set.files[set.namedOrder.front()];
    if (f.kind == frontend::UnitKind::Semi) entry = f.semiName;
  }
  if (search) return resolveSearch(set, all, m, co, img->image(), entry, *search, io);
  return kExitOk;
}

std::optional<double> overridePercent(const std::string& text, double max) {
  std::string t = text;
  if (!t.empty() && t.back() == '%') t.pop_back();
  if (t.empty() || t.find_first_not_of("0123456789.") != std::string::npos || t.find('.') != t.rfind('.') || t == ".")
    return std::nullopt;
  const double v = std::strtod(t.c_str(), nullptr); // no throw: a huge number is HUGE_VAL, refused below
  if (!(v >= 1 && v <= max)) return std::nullopt;
  return v;
}

sim::SimOptions simOptions(const SimulateOptions& opts, const std::string& entry) {
  sim::SimOptions so;
  so.dt = opts.dt;
  so.blockSkip = opts.blockSkip;
  so.maxSteps = opts.maxSteps;
  so.maxTime = opts.maxTime;
  so.maxRows = opts.maxRows;
  so.entry = entry;
  // checked by checkRunOptions: here only the value
  if (auto f = overridePercent(opts.feedOverride, kMaxFeedOverride)) so.feedScale = *f / 100.0;
  if (auto r = overridePercent(opts.rapidOverride, kMaxRapidOverride)) so.rapidScale = *r / 100.0;
  return so;
}

namespace {
constexpr double kMinDt = 1e-6; ///< s: the smallest --dt (a microsecond, the resolution of every output)

/// The option checks of a run (after --print-machine and --compare's own): exit code.
int checkRunOptions(const SimulateOptions& opts, const std::string& output, Io& io, bool& json,
                    std::optional<sim::PathPlane>& plane) {
  if (opts.program.empty()) return usageError(io, "isosim", "no program (give an image from isocc or a .mpf file)");
  if (!(opts.dt > 0) || !std::isfinite(opts.dt))
    return usageError(io, "isosim", "--dt must be a number of seconds > 0");
  if (opts.dt < kMinDt)
    return usageError(
        io, "isosim",
        fmt::format("--dt {:g} s is too small: the sample period is at least 1e-6 s (a microsecond)", opts.dt));
  if (opts.maxRows == 0) return usageError(io, "isosim", "--max-rows must be at least 1");
  if (!(opts.maxTime > 0) || std::isnan(opts.maxTime))
    return usageError(io, "isosim", "--max-time must be a number of seconds > 0");
  if (opts.maxSteps == 0) return usageError(io, "isosim", "--max-steps must be at least 1");
  if (!opts.feedOverride.empty() && !overridePercent(opts.feedOverride, kMaxFeedOverride))
    return usageError(io, "isosim",
                      fmt::format("--feed-override '{}': expected a percent of the programmed feed from 1 to {}",
                                  support::escapeForTerminal(opts.feedOverride), kMaxFeedOverride));
  if (!opts.rapidOverride.empty() && !overridePercent(opts.rapidOverride, kMaxRapidOverride))
    return usageError(io, "isosim",
                      fmt::format("--rapid-override '{}': expected a percent of the rapid speed from 1 to {}",
                                  support::escapeForTerminal(opts.rapidOverride), kMaxRapidOverride));
  if (!opts.budget.empty() && opts.compare.empty())
    return usageError(io, "isosim", "--budget applies to --compare OLD (the growth of the cycle time it allows)");
  if (opts.search && !opts.compare.empty())
    return usageError(io, "isosim", "--search cannot be combined with --compare");
  std::string format = opts.format;
  if (format.empty()) format = support::iendsWith(output, ".json") ? "json" : "csv";
  if (format != "csv" && format != "json" && !(format == "github" && !opts.compare.empty()))
    return usageError(io, "isosim", fmt::format("unknown format '{}' (csv or json; github with --compare)", format));
  json = format == "json";
  if (!opts.plotPlane.empty()) {
    plane = sim::parsePathPlane(opts.plotPlane);
    if (!plane)
      return usageError(io, "isosim", fmt::format("unknown --plot-plane '{}' (xy, zx or yz)", opts.plotPlane));
  }
  return kExitOk;
}

/// Everything a run writes to: the trace (file or standard output), the plot, the timeline,
/// the report; sink() is one sink for all of them (or none).
struct RunSinks {
  RunSinks(const SimulateOptions& opts, const std::string& output, bool json, bool noTrace,
           const std::optional<sim::PathPlane>& plane, sim::TimeProfile& profile, Io& io) {
    if (!noTrace) {
      if (!output.empty()) {
        auto fs = std::make_unique<FileTraceSink>(output, json);
        fileSink = fs.get();
        trace = std::move(fs);
      } else if (json) {
        trace = std::make_unique<sim::JsonTraceWriter>(io.out);
      } else {
        trace = std::make_unique<sim::CsvTraceWriter>(io.out);
      }
    }
    if (!opts.plot.empty() || !opts.report.empty()) plot = std::make_unique<PlotFileSink>(opts.plot);
    if (plot && plane) plot->setPlane(*plane);
    if (!opts.timeline.empty()) timeline = std::make_unique<TimelineFileSink>(opts.timeline, &profile);
    if (!opts.report.empty()) report = std::make_unique<ReportFile>(opts.report);
    // The plot samples at --dt with or without a trace (also with --summary).
    for (sim::TraceSink* k : {static_cast<sim::TraceSink*>(trace.get()), static_cast<sim::TraceSink*>(plot.get()),
                              static_cast<sim::TraceSink*>(timeline.get()), static_cast<sim::TraceSink*>(report.get())})
      if (k) sinks.push_back(k);
    if (sinks.size() > 1) tee.emplace(sinks);
  }
  sim::TraceSink* sink() { return tee ? &*tee : sinks.empty() ? nullptr : sinks.front(); }

  std::unique_ptr<sim::TraceSink> trace;
  FileTraceSink* fileSink = nullptr;
  std::unique_ptr<PlotFileSink> plot;
  std::unique_ptr<TimelineFileSink> timeline;
  std::unique_ptr<ReportFile> report;
  std::vector<sim::TraceSink*> sinks;
  std::optional<sim::TeeSink> tee;
};
/// What the views of a run leave out, as summary warnings named by their option (views never
/// drop data silently). `profileText`: --profile prints its text table (JSON is complete).
std::vector<std::string> viewWarnings(const SimulateOptions& opts, const RunSinks& rs, const sim::TimeProfile& profile,
                                      bool profileText) {
  std::vector<std::string> w;
  if (rs.timeline)
    if (std::string n = rs.timeline->capNote(); !n.empty()) w.push_back("--timeline: " + n);
  if (rs.plot)
    for (const std::string& n : rs.plot->capNotes())
      w.push_back(opts.plot.empty() ? "--report: the plot: " + n : "--plot: " + n);
  const size_t lines = profile.lines.size();
  if (rs.report && lines > kReportMaxRows)
    w.push_back(fmt::format("--report: the page lists the {} slowest of {} lines", kReportMaxRows, lines));
  if (profileText && opts.profileLines != 0 && lines > opts.profileLines)
    w.push_back(fmt::format("--profile: the table shows the {} slowest of {} lines (--profile-lines 0 shows all)",
                            opts.profileLines, lines));
  return w;
}

/// Adds `more` after the simulator's warnings, each once.
void addWarnings(sim::Summary& s, const std::vector<std::string>& more) {
  for (const std::string& w : more)
    if (std::find(s.warnings.begin(), s.warnings.end(), w) == s.warnings.end()) s.warnings.push_back(w);
}

/// Passes a run on to `inner`, adding what the views leave out to the summary's warnings
/// before the trace (and every view) receives it: the views have seen every event by then.
class NotingSink : public sim::TraceSink {
public:
  NotingSink(sim::TraceSink& inner, std::function<std::vector<std::string>()> notes)
      : inner_(inner), notes_(std::move(notes)) {}
  void begin(const machine::Machine& m) override { inner_.begin(m); }
  void sample(double t, const double* p) override { inner_.sample(t, p); }
  void sampleWithVelocity(double t, const double* p, const double* v) override { inner_.sampleWithVelocity(t, p, v); }
  void event(const sim::Event& e) override { inner_.event(e); }
  void end(const sim::Summary& s) override {
    sim::Summary noted = s;
    addWarnings(noted, notes_());
    inner_.end(noted);
  }
  bool wantsSamples() const override { return inner_.wantsSamples(); }
  bool wantsEvents() const override { return inner_.wantsEvents(); }
  bool wantsVelocities() const override { return inner_.wantsVelocities(); }

private:
  sim::TraceSink& inner_;
  std::function<std::vector<std::string>()> notes_;
};

/// The source texts the report links to: each file of the profile, read next to the program
/// (the run names files as the image stores them, without their folder); a file that cannot be
/// read is left out (the page says "source not available").
std::map<std::string, std::string> reportSources(const std::string& program, const sim::TimeProfile& profile) {
  std::map<std::string, std::string> sources;
  std::set<std::string> tried;
  const std::filesystem::path dir = std::filesystem::path(program).parent_path();
  for (const sim::LineProfile& lp : profile.lines) {
    if (lp.file.empty() || !tried.insert(lp.file).second) continue;
    if (auto text = support::readFile((dir / lp.file).string())) sources.emplace(lp.file, std::move(*text));
  }
  return sources;
}

/// Writes the plot, timeline, report and trace files of a finished run, each whole; a failing
/// one leaves the trace's previous file in place. Returns the exit code.
int writeOutputs(const SimulateOptions& opts, const std::string& output, const std::string& entry,
                 const sim::SimResult& res, sim::TimeProfile& profile, RunSinks& rs, Io& io) {
  // Outputs replace their files only now, whole: the plot first, so that a failing plot leaves
  // the previous trace in place too.
  support::Status written;
  const std::string title = plotTitle(opts, entry, res.summary);
  auto failed = [&](const std::string& path, const char* what) {
    if (rs.fileSink) rs.fileSink->discard();
    io.err << fmt::format("{}: error: cannot write the {} file: {}\n", support::escapeForTerminal(path), what,
                          written.why());
    return kExitUsage;
  };
  if (rs.plot && !opts.plot.empty() && !(written = rs.plot->write(title))) return failed(opts.plot, "plot");
  if (rs.timeline && !(written = rs.timeline->write(std::filesystem::path(opts.program).filename().string())))
    return failed(opts.timeline, "timeline");
  if (rs.report) {
    ReportInput ri;
    ri.title = title;
    ri.program = opts.program;
    ri.summary = &res.summary;
    ri.profile = &profile;
    ri.plotSvg = rs.plot->render(title);
    ri.sources = reportSources(opts.program, profile);
    if (!(written = rs.report->write(renderReport(ri)))) return failed(opts.report, "report");
  }
  if (rs.fileSink && !(written = rs.fileSink->commit())) {
    io.err << fmt::format("{}: error: cannot write the trace: {}\n", support::escapeForTerminal(output), written.why());
    return kExitUsage;
  }
  return kExitOk;
}
} // namespace

namespace {
/// PROGRAM or a PATH "-" is standard input, read once (readStandardInput).
bool readStandardInput(SimulateOptions& opts, Io& io) {
  if (opts.program.empty()) return true;
  std::vector<std::string> inputs{opts.program};
  inputs.insert(inputs.end(), opts.paths.begin(), opts.paths.end());
  if (!driver::readStandardInput(inputs, io, "isosim")) return false;
  opts.program = inputs.front();
  opts.paths.assign(inputs.begin() + 1, inputs.end());
  return true;
}
} // namespace

namespace {
/// --m0-wait, --optional-stop and --set: the machine of this run (opts.sets then lists every change); false with
/// the reason printed.
bool applyOverrides(SimulateOptions& opts, std::optional<machine::Machine>& m, Io& io) {
  if (opts.m0Wait) opts.sets.push_back(fmt::format("m0_wait_s={}", sim::formatNumber(*opts.m0Wait)));
  if (!opts.optionalStop.empty()) {
    const bool on = support::iequals(opts.optionalStop, "on");
    if (!on && !support::iequals(opts.optionalStop, "off")) {
      usageError(
          io, "isosim",
          fmt::format("--optional-stop '{}': expected on or off", support::escapeForTerminal(opts.optionalStop)));
      return false;
    }
    opts.sets.push_back(on ? "optional_stop=true" : "optional_stop=false");
  }
  if (opts.sets.empty()) return true;
  m = overrideMachine(*m, opts.sets, io);
  return m.has_value();
}

} // namespace

std::vector<std::string> summaryOverrides(const SimulateOptions& opts, const sim::SimOptions& so) {
  std::vector<std::string> all = opts.sets;
  if (so.feedScale != 1.0) all.push_back("feed_override=" + sim::formatNumber(so.feedScale * 100));
  if (so.rapidScale != 1.0) all.push_back("rapid_override=" + sim::formatNumber(so.rapidScale * 100));
  return all;
}

namespace {

/// The settings file of the program's folder, the machine and the --set overrides a run uses:
/// kExitOk, or kExitUsage after printing why.
int setUpMachine(SimulateOptions& opts, Settings& settings, std::optional<machine::Machine>& m, Io& io) {
  if (!applySettings(opts.common, opts.program.empty() ? std::string(".") : opts.program, settings, io))
    return kExitUsage;
  m = loadMachine(opts.common, io);
  return m && applyOverrides(opts, m, io) ? kExitOk : kExitUsage;
}

} // namespace

int prepareRun(const SimulateOptions& optsIn, Io& io, PreparedRun& out) {
  SimulateOptions opts = optsIn;
  Settings settings;
  if (int rc = setUpMachine(opts, settings, out.machine, io); rc != kExitOk) return rc;
  bool json = false;
  std::optional<sim::PathPlane> plane;
  if (int rc = checkRunOptions(opts, "", io, json, plane); rc != kExitOk) return rc;
  out.entry = opts.entry;
  std::string compileError;
  std::optional<SearchRequest> search;
  if (opts.search) search = SearchRequest{*opts.search, std::nullopt};
  auto noOutputs = [](const std::vector<std::string>&) { return kExitOk; };
  if (int rc = loadProgram(opts.program, opts.paths, opts.common, settings, *out.machine, io, noOutputs, out.image,
                           out.entry, compileError, search ? &*search : nullptr);
      rc != kExitOk) {
    if (!compileError.empty()) io.err << "isosim: " << support::escapeForTerminal(compileError) << "\n";
    return rc;
  }
  out.options = simOptions(opts, out.entry);
  if (search) out.options.search = search->found;
  out.overrides = summaryOverrides(opts, out.options);
  return kExitOk;
}

int runSimulate(const SimulateOptions& optsIn, Io& io) {
  SimulateOptions opts = optsIn;
  if (!readStandardInput(opts, io)) return kExitUsage;
  Settings settings;
  std::optional<machine::Machine> m;
  if (int rc = setUpMachine(opts, settings, m, io); rc != kExitOk) return rc;
  if (opts.printMachine) {
    io.out << machine::machineToJson(*m) << "\n";
    return kExitOk;
  }
  // -o - is standard output
  const std::string output = opts.output == "-" ? std::string() : opts.output;
  bool json = false;
  std::optional<sim::PathPlane> plane;
  if (int rc = checkRunOptions(opts, output, io, json, plane); rc != kExitOk) return rc;
  if (!opts.compare.empty()) return runCompare(opts, *m, settings, io);
  const std::vector<OutputPath> outs = {
      {"-o", output}, {"--plot", opts.plot}, {"--timeline", opts.timeline}, {"--report", opts.report}};
  auto checkOut = [&](const std::vector<std::string>& inputs) { return checkOutputs(io, "isosim", outs, inputs); };
  if (int rc = checkOut({}); rc != kExitOk) return rc;

  // Where the summary goes (see Simulate.h); the profile follows it. A terminal on standard
  // output gets the summary and a hint instead of thousands of trace rows.
  const bool terminal = io.outIsTty && output.empty() && !opts.summary && !opts.profile;
  const bool noTrace = opts.summary || (opts.profile && output.empty()) || terminal;
  sim::TimeProfile profile;
  bool profiled = false;
  auto printSummary = [&](const sim::Summary& s) -> int {
    const bool jsonOut = json && (noTrace || !output.empty());
    std::string text = jsonOut ? sim::summaryJson(s, 2) + "\n" : sim::summaryText(s);
    if (opts.profile && (profiled || jsonOut)) {
      if (jsonOut) {
        // always the documented {"summary", "profile"} object; profile null when nothing ran
        nlohmann::ordered_json j;
        j["summary"] = sim::summaryValue(s);
        j["profile"] = profiled ? sim::profileValue(profile) : nullptr;
        text = j.dump(2) + "\n";
      } else {
        text += "\n" + sim::renderProfileText(profile, opts.profileLines);
      }
    }
    if (opts.summary && !output.empty()) {
      if (support::Status w = support::writeFileAtomically(output, text); !w) {
        io.err << fmt::format("{}: error: cannot write the summary: {}\n", support::escapeForTerminal(output), w.why());
        return kExitUsage;
      }
    } else if (noTrace || !output.empty()) {
      io.out << text;
    } else {
      io.err << text;
    }
    if (terminal && !opts.quiet)
      io.err << "isosim: the trace is not printed on a terminal: write it with -o FILE (or --format csv > FILE)\n";
    return kExitOk;
  };
  const bool summaryOnStderr = !noTrace && output.empty();

  // ---- the program: an image, or a source program set compiled in memory
  std::optional<image::VerifiedImage> img;
  std::string entry = opts.entry;
  std::string compileError;
  std::optional<SearchRequest> search;
  if (opts.search) search = SearchRequest{*opts.search, std::nullopt};
  if (int rc = loadProgram(opts.program, opts.paths, opts.common, settings, *m, io, checkOut, img, entry, compileError,
                           search ? &*search : nullptr);
      rc != kExitOk) {
    if (compileError.empty()) return rc;
    int src = printSummary(compileFailureSummary(*m, compileError));
    return src != kExitOk ? src : kExitErrors;
  }

  // ---- run
  sim::SimOptions so = simOptions(opts, entry);
  if (search) so.search = search->found;
  // the timeline's limits and the report's table come from the profile
  if (opts.profile || !opts.timeline.empty() || !opts.report.empty()) so.profile = &profile;
  ProgressLine progress(io.err);
  if (io.errIsTty && !opts.quiet) so.progress = [&](double t, uint64_t b, uint64_t n) { progress.update(t, b, n); };
  RunSinks rs(opts, output, json, noTrace, plane, profile, io);
  FileTraceSink* fileSink = rs.fileSink;
  const bool profileText = opts.profile && !(json && (noTrace || !output.empty()));
  auto notes = [&] { return viewWarnings(opts, rs, profile, profileText); };
  std::optional<NotingSink> noting;
  if (rs.sink()) noting.emplace(*rs.sink(), notes);
  sim::TraceSink* sink = noting ? &*noting : nullptr;
  sim::SimResult res;
  try {
    res = sim::simulate(*img, *m, so, sink);
  } catch (const CannotCreate& e) {
    progress.erase();
    if (fileSink) fileSink->discard(); // no trace left behind when the plot file fails
    io.err << fmt::format("{}: error: cannot create the {} file: {}\n", support::escapeForTerminal(e.path), e.what,
                          e.why);
    return kExitUsage;
  }
  progress.erase();
  if (res.setupError != sim::SetupError::None) {
    io.err << fmt::format("{}: error: {}\n", support::escapeForTerminal(opts.program),
                          support::escapeForTerminal(res.setupMessage));
    return kExitUsage;
  }
  addWarnings(res.summary, notes());
  res.summary.overrides = summaryOverrides(opts, so);
  if (int rc = writeOutputs(opts, output, entry, res, profile, rs, io); rc != kExitOk) return rc;
  profiled = opts.profile;
  const sim::Summary& s = res.summary;
  if (s.status != sim::Status::Ok && !summaryOnStderr)
    io.err << "isosim: " << support::escapeForTerminal(s.message) << "\n";
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
