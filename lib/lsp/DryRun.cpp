//! @file DryRun.cpp
//! @brief The language server's dry runs: driver::prepareRun, then the simulator with the
//!        time profile and a debug hook that only watches the wall clock and the editor.
#include "lsp/DryRun.h"

#include <chrono>
#include <cmath>
#include <filesystem>
#include <sstream>

#include <fmt/format.h>

#include "driver/ExitCode.h"
#include "driver/Simulate.h"
#include "sim/Debug.h"
#include "sim/Run.h"
#include "sim/TraceWriter.h"

namespace iso::lsp {

namespace {
/// Ends the run at the budget or when the editor sends something.
class Watch final : public sim::DebugHook {
public:
  Watch(double budget, const std::function<bool()>& cancel)
      : end_(std::chrono::steady_clock::now() +
             std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(budget))),
        cancel_(cancel) {}
  bool statement(const sim::RunView&, uint32_t, uint32_t, size_t) override {
    if ((++n_ & 0xFFF) != 0) return true;
    if (cancel_ && cancel_()) {
      cancelled = true;
      return false;
    }
    if (std::chrono::steady_clock::now() > end_) {
      overBudget = true;
      return false;
    }
    return true;
  }
  bool timeReached(const sim::RunView&) override { return true; }
  void fault(const sim::RunView&, sim::Status, const std::string&, uint32_t) override {}
  bool cancelled = false;
  bool overBudget = false;

private:
  std::chrono::steady_clock::time_point end_;
  const std::function<bool()>& cancel_;
  uint64_t n_ = 0;
};

std::string firstLine(const std::string& s) {
  const std::string l = s.substr(0, s.find('\n'));
  return l.size() > 200 ? l.substr(0, 200) + "…" : l;
}
} // namespace

const char* dryRunStateName(DryRun::State s) {
  switch (s) {
  case DryRun::State::Ok: return "ok";
  case DryRun::State::Error: return "error";
  case DryRun::State::Emergency: return "emergency";
  case DryRun::State::Failed: return "failed";
  case DryRun::State::OverBudget: return "over budget";
  case DryRun::State::Cancelled: return "cancelled";
  }
  return "?";
}

std::string readableSeconds(double s) {
  if (!(s >= 0) || !std::isfinite(s)) return sim::formatNumber(s) + " s";
  if (s < 60) return fmt::format("{:.3f} s", s);
  return sim::clockTime(s);
}

DryRun dryRun(const std::string& program, const driver::CommonOptions* policy, const DryRunOptions& opts,
              const std::function<bool()>& cancel) {
  DryRun out;
  out.program = program;
  out.folder = std::filesystem::path(program).parent_path().string();
  driver::SimulateOptions so;
  if (policy) so.common = *policy;
  so.common.color = "never";
  so.program = program;
  std::ostringstream sink, err;
  driver::Io io{sink, err, false, false, nullptr};
  driver::PreparedRun run;
  if (driver::prepareRun(so, io, run) != driver::kExitOk) {
    out.state = DryRun::State::Failed;
    out.title = "no dry run: " + firstLine(err.str());
    return out;
  }
  Watch watch(opts.budgetSeconds, cancel);
  sim::SimOptions sopts = run.options;
  sopts.profile = &out.profile;
  sopts.debug = &watch;
  sim::SimResult res = sim::simulate(*run.image, *run.machine, sopts);
  if (res.setupError != sim::SetupError::None) {
    out.state = DryRun::State::Failed;
    out.title = "no dry run: " + firstLine(res.setupMessage);
    return out;
  }
  out.summary = std::move(res.summary);
  const sim::Summary& s = out.summary;
  if (watch.cancelled) {
    out.state = DryRun::State::Cancelled;
    out.title = "dry run cancelled";
  } else if (watch.overBudget) {
    out.state = DryRun::State::OverBudget;
    out.title = fmt::format("dry run stopped after {} s of computing, at t = {} (cycle time not known)",
                            sim::formatNumber(opts.budgetSeconds), readableSeconds(s.cycleTimeS));
  } else if (s.status == sim::Status::Ok) {
    out.state = DryRun::State::Ok;
    out.title = fmt::format("cycle {} · {} blocks", readableSeconds(s.cycleTimeS), s.blocks);
  } else {
    out.state = s.status == sim::Status::Emergency ? DryRun::State::Emergency : DryRun::State::Error;
    out.title = firstLine(s.message);
  }
  return out;
}

} // namespace iso::lsp
