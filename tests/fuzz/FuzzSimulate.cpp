//! @file FuzzSimulate.cpp
//! @brief Fuzz target: source text -> frontend -> compiler -> image bytes -> reader + verifier
//!        -> interpreter with small step and time budgets (STYLE habit 13: a verified image
//!        must run without a crash, a hang or an internal error, whatever it does).
//!
//! Input format: the main program's text. A line that is exactly `@@` starts another file of
//! the set, a subprogram (sub1.spf, sub2.spf, ...; at most 7), so that calls can be fuzzed too
//! (`@` cannot occur in a program outside comments and strings). An input starting with `;@`,
//! a digit and optionally `s` (strip the line table) and `k` (block skip on) picks the machine
//! variant (machineVariants) and those options; without it the sum of the bytes picks them.
//! Either way the choice is deterministic. The dictionary tests/fuzz/simulate.dict helps.
//!
//! Each input runs twice: once with a profile and a TeeSink feeding three sinks — a checking
//! sink without velocities, one with velocities, a PlotSink whose SVG is rendered — and once
//! summary-only; both runs must agree. Checked invariants:
//!   - trace: sample times strictly increase, event times never decrease, the run ends once at
//!     or after its last sample and event; positions stay within the soft limits; velocities
//!     are finite and within each axis' max velocity; no axis moves faster between two samples;
//!     both sample sinks see the same samples;
//!   - profile (isosim --profile): every part is finite and >= 0; the line totals, the total
//!     row and the first program's total (see kProcTotalsAcrossCalls) all equal the cycle time
//!     (1e-9 relative + 1e-12); the line counts add up to at least the summary's blocks (read-ahead included); the text
//!     and JSON renderings work and the JSON parses;
//!   - plot: the SVG is one document whose attribute values hold no nan/inf.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "Support.h"
#include "compiler/Compiler.h"
#include "frontend/Parser.h"
#include "frontend/ProgramSet.h"
#include "frontend/Sema.h"
#include "machine/Machine.h"
#include "sim/Run.h"
#include "sim/SvgPlot.h"
#include "sim/TimeProfile.h"
#include "sim/TraceWriter.h"

namespace {

/// An invariant does not hold: says which (the fuzzer shows stderr with the crash) and aborts.
[[noreturn]] void fail(const char* what) {
  std::fprintf(stderr, "FuzzSimulate: %s\n", what);
  std::abort();
}

/// a == b within 1e-9 relative plus 1e-12 absolute.
bool nearlyEqual(double a, double b) { return std::fabs(a - b) <= 1e-9 * std::max(std::fabs(a), std::fabs(b)) + 1e-12; }

class CheckingSink : public iso::sim::TraceSink {
public:
  explicit CheckingSink(bool velocities) : velocities_(velocities) {}
  void begin(const iso::machine::Machine& m) override {
    if (begun_) fail("begin twice");
    begun_ = true;
    m_ = &m;
    last_.assign(m.axes.size(), 0.0);
  }
  void sample(double t, const double* p) override {
    // TeeSink gives each sink what it asks for
    if (velocities_) fail("sample() on a sink that wants velocities");
    check(t, p);
  }
  void sampleWithVelocity(double t, const double* p, const double* v) override {
    if (!velocities_) fail("sampleWithVelocity() on a sink that wants none");
    check(t, p);
    for (size_t i = 0; i < m_->axes.size(); ++i) {
      const double vmax = m_->axes[i].maxVelocity;
      if (!std::isfinite(v[i]) || std::fabs(v[i]) > vmax * (1 + 1e-9) + 1e-9)
        fail("velocity not finite or above the axis' max velocity");
    }
  }
  void event(const iso::sim::Event& e) override {
    if (!begun_ || ended_ || e.t < lastEvent_ || !std::isfinite(e.t)) fail("event out of order or not finite");
    lastEvent_ = e.t;
  }
  void end(const iso::sim::Summary& s) override {
    if (!begun_ || ended_ || s.cycleTimeS < lastEvent_ || s.cycleTimeS < lastSample_)
      fail("end twice or before the last sample/event");
    if (s.finalPosition.size() != m_->axes.size()) fail("final position size");
    if ((s.status == iso::sim::Status::Ok) != s.message.empty()) fail("status ok iff no message");
    ended_ = true;
  }
  bool wantsVelocities() const override { return velocities_; }

  size_t samples = 0;
  double lastSample() const { return lastSample_; }
  const std::vector<double>& lastPosition() const { return last_; }

private:
  void check(double t, const double* p) {
    if (!begun_ || ended_ || !(t > lastSample_) || !std::isfinite(t)) fail("sample time not increasing or not finite");
    for (size_t i = 0; i < m_->axes.size(); ++i) {
      const auto& a = m_->axes[i];
      if (!std::isfinite(p[i])) fail("position not finite");
      // soft limits are checked before anything moves (arcs at their extreme points)
      if (p[i] < a.limitMinus - 1e-6 || p[i] > a.limitPlus + 1e-6) fail("position outside the soft limits");
      if (samples > 0 && std::fabs(p[i] - last_[i]) > a.maxVelocity * (t - lastSample_) * (1 + 1e-9) + 1e-9)
        fail("axis faster than its max velocity between two samples");
      last_[i] = p[i];
    }
    lastSample_ = t;
    ++samples;
  }

  bool velocities_;
  bool begun_ = false, ended_ = false;
  const iso::machine::Machine* m_ = nullptr;
  std::vector<double> last_;
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

/// The machine variants: the look-ahead window and the corner deviation of G64 chains
/// (SPEC §5.2), axes with different limits, the block time.
std::vector<iso::machine::Machine> machineVariants() {
  std::vector<iso::machine::Machine> v;
  auto add = [&](int lookahead, double delta, auto&& edit) {
    iso::machine::Machine m = fuzzMachine();
    m.lookaheadBlocks = lookahead;
    m.cornerDeviationMm = delta;
    edit(m);
    v.push_back(std::move(m));
  };
  auto none = [](iso::machine::Machine&) {};
  add(64, 0.05, none);
  add(1, 0.05, none);
  add(2, 0.05, none);
  add(3, 0.2, none);
  add(4, 1, [](iso::machine::Machine& m) { m.blockTimeS = 0; });
  add(64, 0.001, [](iso::machine::Machine& m) {
    m.axes[1].maxAccel = 1000;
    m.axes[2].maxVelocity = 100;
  });
  add(64, 5, [](iso::machine::Machine& m) {
    m.axes[0].maxAccel = 50;
    m.axes[1].maxVelocity = 20;
    m.blockTimeS = 0;
  });
  add(2, 0.5, [](iso::machine::Machine& m) {
    m.blockTimeS = 0.01;
    m.axes[0].limitPlus = 200;
    m.axes[1].limitMinus = -50;
  });
  add(3, 0.05, [](iso::machine::Machine& m) { m.dialect = iso::machine::Dialect::Z32; });
  add(64, 0.05, [](iso::machine::Machine& m) {
    m.ipoCycleS = 0.01;
    m.defaultMDurationS = 0.1;
    m.rPreset[1] = 2.5;
  });
  return v;
}

/// What an input chooses besides its program: the machine, a stripped image, block skip.
struct Choice {
  size_t machine = 0;
  bool strip = false;
  bool blockSkip = false;
};

/// `;@<digit>[s][k]` at the start (s: strip the line table, k: block skip on), else the sum
/// of the bytes.
Choice pick(std::string_view text, size_t machines) {
  Choice c;
  if (text.size() >= 3 && text[0] == ';' && text[1] == '@' && text[2] >= '0' && text[2] <= '9') {
    c.machine = static_cast<size_t>(text[2] - '0') % machines;
    size_t i = 3;
    for (; i < text.size() && (text[i] == 's' || text[i] == 'k'); ++i)
      (text[i] == 's' ? c.strip : c.blockSkip) = true;
    return c;
  }
  size_t sum = 0;
  for (unsigned char ch : text)
    sum += ch;
  c.machine = sum % machines;
  c.strip = (sum / 16) % 5 == 0;
  c.blockSkip = (sum / 128) % 2 == 0;
  return c;
}

/// The input split at `@@` lines: the main program, then the subprograms.
std::vector<std::string> splitFiles(std::string_view text) {
  std::vector<std::string> files(1);
  size_t pos = 0;
  while (pos <= text.size()) {
    size_t eol = text.find('\n', pos);
    std::string_view line = text.substr(pos, eol == std::string_view::npos ? std::string_view::npos : eol - pos);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (line == "@@" && files.size() < 8) {
      files.emplace_back();
    } else {
      files.back().append(line);
      if (eol != std::string_view::npos) files.back().push_back('\n');
    }
    if (eol == std::string_view::npos) break;
    pos = eol + 1;
  }
  return files;
}

/// A program set of in-memory files, parsed and checked as ProgramSet.cpp does for files on
/// disk: the first is the named main program, the others are its siblings.
void loadFiles(std::vector<std::string> texts, const iso::frontend::LoadOptions& lo, iso::frontend::ProgramSet& set) {
  if (texts.size() == 1) {
    iso::frontend::loadSingleSource("fuzz.mpf", std::move(texts[0]), lo, set);
    return;
  }
  using namespace iso::frontend;
  const LexOptions lex = lexOptionsFor(lo); // the machine's axis letters and, in z32, its user parameters
  const SemaOptions so{lo.machine, lo.dialect};
  for (size_t i = 0; i < texts.size(); ++i) {
    const std::string path = i == 0 ? "fuzz.mpf" : "sub" + std::to_string(i) + ".spf";
    const uint32_t id = set.sources.add(path, std::move(texts[i]));
    File f;
    f.id = id;
    f.path = path;
    set.files.push_back(std::move(f));
    set.reported.push_back(i == 0 ? 1 : 0);
    set.named.push_back(i == 0 ? 1 : 0);
    if (i == 0) set.namedOrder.push_back(id);
  }
  for (size_t i = 0; i < set.files.size(); ++i) {
    File& f = set.files[i];
    parseFile(f, set.sources.file(static_cast<uint32_t>(i)).text, lex, set.diags);
    f.kind = classifyUnit(f);
    set.flows.push_back(checkFile(f, so, set.diags));
  }
  checkSet(set.files, so, set.diags);
  set.diags.sort();
}

void checkSplit(const iso::sim::TimeSplit& s) {
  for (const auto& p : s.parts)
    if (!std::isfinite(p.value()) || p.value() < 0) fail("profile part negative or not finite");
  if (!std::isfinite(s.total())) fail("profile total not finite");
}

/// The first program's total is checked also for inputs with subprograms (a G64 chain that reads
/// ahead through calls charges each block to the call stack it was read under).
constexpr bool kProcTotalsAcrossCalls = true;

void checkProfile(const iso::sim::TimeProfile& p, const iso::sim::Summary& s, bool calls) {
  if (p.cycleTimeS != s.cycleTimeS) fail("profile cycle time differs from the summary");
  checkSplit(p.total);
  iso::sim::ExactSum lines;
  uint64_t count = 0;
  for (const auto& l : p.lines) {
    checkSplit(l.time);
    lines.add(l.time.total());
    count += l.count;
  }
  // The counts include the statements read ahead in G64 chains, which blocks leaves out (SPEC §5.3).
  if (count < s.blocks) fail("profile: the line counts add up to fewer than the blocks executed");
  if (!nearlyEqual(lines.value(), s.cycleTimeS) || !nearlyEqual(p.total.total(), s.cycleTimeS))
    fail("profile: line totals or total row differ from the cycle time");
  for (const auto& pr : p.procs)
    checkSplit(pr.time);
  if (p.procs.empty()) fail("profile without programs");
  if ((kProcTotalsAcrossCalls || !calls) && !nearlyEqual(p.procs.front().time.total(), s.cycleTimeS))
    fail("profile: first program's total differs from the cycle time");
  for (const auto& m : p.ms) {
    checkSplit(m.time);
    if (!std::isfinite(m.running.value()) || m.running.value() < 0) fail("profile: M running time");
  }
  (void)iso::sim::renderProfileText(p);
  const std::string json = iso::sim::renderProfileJson(p);
  const auto j = nlohmann::json::parse(json, nullptr, false);
  if (j.is_discarded() || !j.is_object() || !j.contains("lines") || j.at("lines").size() != p.lines.size())
    fail("profile JSON does not parse");
}

void checkSvg(const std::string& svg) {
  if (svg.rfind("<svg ", 0) != 0 || svg.size() < 7 || svg.compare(svg.size() - 7, 7, "</svg>\n") != 0)
    fail("SVG not one document");
  if (svg.find("<svg ", 1) != std::string::npos) fail("SVG: two documents");
  // every attribute value: no non-finite number (titles and labels are element text)
  for (size_t k = svg.find("=\""); k != std::string::npos; k = svg.find("=\"", k)) {
    const size_t e = svg.find('"', k + 2);
    if (e == std::string::npos) fail("SVG: unterminated attribute");
    const std::string_view v(svg.data() + k + 2, e - k - 2);
    if (v.find("nan") != std::string_view::npos || v.find("inf") != std::string_view::npos)
      fail("SVG: nan/inf in an attribute");
    k = e + 1;
  }
}

bool sameSummary(const iso::sim::Summary& a, const iso::sim::Summary& b) {
  return a.status == b.status && a.cycleTimeS == b.cycleTimeS && a.message == b.message && a.blocks == b.blocks &&
         a.finalPosition == b.finalPosition && a.warnings == b.warnings;
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::vector<iso::machine::Machine> machines = machineVariants();
  if (size > 64 * 1024) return 0;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const Choice choice = pick(text, machines.size());
  const iso::machine::Machine& machine = machines[choice.machine];
  iso::frontend::LoadOptions lo;
  lo.machine = &machine;
  lo.dialect = machine.dialect;
  iso::frontend::ProgramSet set;
  std::vector<std::string> files = splitFiles(text);
  const bool calls = files.size() > 1;
  loadFiles(std::move(files), lo, set);
  if (iso::fuzz::hasErrors(set)) return 0;
  iso::compiler::CompileOptions co;
  co.dialect = machine.dialect;
  co.specialM = &machine.specialM; // as isocc compiles for this machine
  co.parameters = &machine.parameters;
  co.strip = choice.strip;
  // through the bytes, the reader and the verifier, as isosim loads an image
  std::optional<iso::image::VerifiedImage> img;
  if (!iso::fuzz::compileAndLoad(set, co, img, "FuzzSimulate")) return 0;
  iso::sim::SimOptions opts;
  opts.maxSteps = 20000;
  opts.maxTime = 30;
  opts.dt = 0.05;
  opts.blockSkip = choice.blockSkip;
  // with a profile and three sinks behind a tee
  iso::sim::TimeProfile profile;
  opts.profile = &profile;
  CheckingSink plain(false), withVel(true);
  iso::sim::PlotSink plot(64); // small: thinning happens
  iso::sim::TeeSink tee({&plain, &plot, &withVel});
  iso::sim::SimResult r = iso::sim::simulate(*img, machine, opts, &tee); // internal errors throw: a crash
  if (r.setupError != iso::sim::SetupError::None) fail("setup error");
  if (plain.samples != withVel.samples || plain.lastSample() != withVel.lastSample() ||
      plain.lastPosition() != withVel.lastPosition())
    fail("the two sample sinks saw different samples");
  checkProfile(profile, r.summary, calls);
  checkSvg(plot.render("fuzz.mpf"));
  // summary only, no profile: the same outcome
  opts.profile = nullptr;
  iso::sim::SimResult q = iso::sim::simulate(*img, machine, opts, nullptr);
  if (!sameSummary(q.summary, r.summary)) fail("summary-only run differs");
  return 0;
}
