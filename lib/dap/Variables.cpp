//! @file Variables.cpp
//! @brief isosim --dap's view of a stopped run: the call chain (stackTrace), the scopes and
//!        their variables (the run and its time, R parameters, axes, the modal state, the z32
//!        machine functions and parameters, I/O), and evaluate.
#include <cmath>

#include <fmt/format.h>

#include "dap/Session.h"
#include "sim/TraceWriter.h"

namespace iso::dap {

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {
constexpr uint32_t kFramesPerThread = 1024; ///< frame id = thread * this + level

enum Kind : int { Run = 1, RParams, Axes, Modal, Machine, Parameters, Io, Axis };

json variable(const std::string& name, const std::string& value, int ref = 0) {
  return {{"name", name}, {"value", value}, {"variablesReference", ref}};
}

std::string num(double v) { return sim::formatNumber(v); }

std::string axisSummary(const sim::DebugAxis& a) {
  if (a.released) return fmt::format("{} (released: G29)", num(a.position));
  if (!a.moving) return num(a.position);
  return fmt::format("{} → {} (moving at {})", num(a.position), num(a.target), num(a.velocity));
}
} // namespace

json Session::stackTrace(const json& args) const {
  const uint32_t thread =
      args.contains("threadId") && args["threadId"].is_number_integer() ? args["threadId"].get<uint32_t>() : 1;
  const std::vector<sim::DebugFrame> frames = view_->stack(thread);
  const size_t start =
      args.contains("startFrame") && args["startFrame"].is_number_unsigned() ? args["startFrame"].get<size_t>() : 0;
  size_t levels = args.contains("levels") && args["levels"].is_number_unsigned() ? args["levels"].get<size_t>() : 0;
  if (levels == 0) levels = frames.size();
  json out = json::array();
  for (size_t i = start; i < frames.size() && i < start + levels && i < kFramesPerThread; ++i) {
    const sim::DebugFrame& f = frames[i];
    std::string name = f.proc.empty() ? std::string("?") : f.proc;
    if (f.kind != sim::DebugFrameKind::Main && f.kind != sim::DebugFrameKind::Call)
      name += fmt::format(" ({})", sim::debugFrameKindName(f.kind));
    json frame = {{"id", thread * kFramesPerThread + i}, {"name", name}, {"line", f.line}, {"column", 1}};
    if (f.file != "?" && !f.file.empty()) {
      frame["source"] = {{"name", fs::path(f.file).filename().string()},
                         {"path", clientPath(std::string_view(f.file))}};
    }
    out.push_back(std::move(frame));
  }
  return {{"stackFrames", std::move(out)}, {"totalFrames", frames.size()}};
}

int Session::reference(uint32_t thread, int kind, int index) {
  constexpr size_t kMaxRefs = 1'000'000; // a client asking again and again at one stop gets no more
  if (refs_.size() >= kMaxRefs) return 0;
  refs_.push_back({thread, kind, index});
  return static_cast<int>(refs_.size());
}

json Session::scopes(const json& args) {
  const uint32_t frameId =
      args.contains("frameId") && args["frameId"].is_number_unsigned() ? args["frameId"].get<uint32_t>() : 0;
  uint32_t thread = frameId / kFramesPerThread;
  if (view_->stack(thread).empty()) thread = stoppedThread_;
  const bool z32 = prepared_.image->image().z32();
  json out = json::array();
  auto scope = [&](const char* name, int kind, bool expensive = false) {
    out.push_back({{"name", name}, {"variablesReference", reference(thread, kind, -1)}, {"expensive", expensive}});
  };
  scope("Run", Run);
  scope("R parameters", RParams);
  scope("Axes", Axes);
  scope("Modal state", Modal);
  if (z32) {
    scope("Machine functions", Machine);
    scope("Parameters", Parameters);
  }
  scope("Inputs, outputs, markers", Io);
  return {{"scopes", std::move(out)}};
}

json Session::variables(const json& args) {
  const int ref = args.contains("variablesReference") && args["variablesReference"].is_number_integer()
                      ? args["variablesReference"].get<int>()
                      : 0;
  if (ref < 1 || static_cast<size_t>(ref) > refs_.size()) return {{"variables", json::array()}};
  const Ref r = refs_[static_cast<size_t>(ref) - 1];
  if (r.kind == Axes) {
    json out = json::array();
    const std::vector<sim::DebugAxis> axes = view_->axes();
    for (size_t i = 0; i < axes.size(); ++i)
      out.push_back(variable(std::string(1, axes[i].letter), axisSummary(axes[i]),
                             reference(r.thread, Axis, static_cast<int>(i))));
    return {{"variables", std::move(out)}};
  }
  return {{"variables", scopeVariables(r.thread, r.kind, r.index)}};
}

json Session::scopeVariables(uint32_t thread, int kind, int index) const {
  json out = json::array();
  switch (kind) {
  case Run: {
    out.push_back(variable("time", num(view_->time()) + " s"));
    out.push_back(variable("blocks", std::to_string(view_->blocks())));
    out.push_back(variable("statements", std::to_string(view_->statements())));
    const std::vector<sim::DebugFrame> frames = view_->stack(thread);
    if (!frames.empty() && frames.front().line > 0)
      out.push_back(variable("line", fmt::format("{}:{}", frames.front().file, frames.front().line)));
    out.push_back(variable("program", prepared_.entry.empty() ? programName_ : prepared_.entry));
    out.push_back(variable("machine", prepared_.machine->name));
    break;
  }
  case RParams:
    for (const auto& [i, v] : view_->rParameters())
      out.push_back(variable(fmt::format("R{}", i), num(v)));
    break;
  case Axis: {
    const std::vector<sim::DebugAxis> axes = view_->axes();
    if (index < 0 || static_cast<size_t>(index) >= axes.size()) break;
    const sim::DebugAxis& a = axes[static_cast<size_t>(index)];
    out.push_back(variable("position", num(a.position)));
    out.push_back(variable("target", num(a.target)));
    out.push_back(variable("velocity", num(a.velocity)));
    out.push_back(variable("state", a.released ? "released (G29)" : a.moving ? "moving" : "at rest"));
    break;
  }
  case Modal: {
    const sim::DebugModal m = view_->modal(thread);
    out.push_back(variable("motion", fmt::format("G0{}", m.motion)));
    out.push_back(variable("distances", m.incremental ? "G91 (incremental)" : "G90 (absolute)"));
    out.push_back(variable("path", m.continuous ? "G64 (continuous)" : "G60 (exact stop)"));
    out.push_back(variable("plane", fmt::format("G{}", m.plane)));
    out.push_back(variable("F", std::isnan(m.feed) ? std::string("not set") : num(m.feed) + " mm/s"));
    break;
  }
  case Machine:
    for (const sim::DebugValue& v : view_->machineFunctions())
      out.push_back(variable(v.name, v.value));
    break;
  case Parameters:
    for (const sim::DebugValue& v : view_->z32Parameters())
      out.push_back(variable(v.name, v.value));
    break;
  case Io:
    for (const sim::DebugValue& v : view_->io())
      out.push_back(variable(v.name, v.value));
    break;
  default: break;
  }
  return out;
}

json Session::evaluate(const json& args) const {
  if (!args.contains("expression") || !args["expression"].is_string())
    return {{"error", "evaluate needs 'expression'"}};
  if (!view_)
    return {{"error", started_ && !ended_ ? "the program is running: pause it first" : "the program is not running"}};
  const std::string text = args["expression"].get<std::string>();
  auto e = Expression::parse(text, *prepared_.machine, prepared_.image->image().z32());
  if (!e) {
    const std::string where = e.error().where.empty() ? "" : e.error().where + ": ";
    return {{"error", where + e.error().message}};
  }
  const support::Expected<double> v = e->evaluate(*view_);
  if (!v) return {{"error", v.error().message}};
  std::string result = num(*v);
  if (e->isCondition()) result = *v != 0 ? "true" : "false";
  return {{"result", result}, {"variablesReference", 0}};
}

} // namespace iso::dap
