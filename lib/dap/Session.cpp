//! @file Session.cpp
//! @brief isosim --dap's protocol: framing (the language server's), the requests, launch and
//!        the run, the stops.
#include "dap/Session.h"

#include <poll.h>

#include <cmath>
#include <sstream>

#include <fmt/format.h>

#include "driver/ExitCode.h"
#include "sim/Run.h"
#include "sim/TraceWriter.h"
#include "support/JsonDepth.h"
#include "support/Text.h"

namespace iso::dap {

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {
constexpr uint64_t kPollEvery = 4096; ///< statements between two looks at the input while running

/// A launch argument of type string ("" when absent); false when present with another type.
bool stringArg(const json& args, const char* key, std::string& out) {
  if (!args.contains(key) || args[key].is_null()) return true;
  if (!args[key].is_string()) return false;
  out = args[key].get<std::string>();
  return true;
}
bool boolArg(const json& args, const char* key, bool& out) {
  if (!args.contains(key) || args[key].is_null()) return true;
  if (!args[key].is_boolean()) return false;
  out = args[key].get<bool>();
  return true;
}
bool stringListArg(const json& args, const char* key, std::vector<std::string>& out) {
  if (!args.contains(key) || args[key].is_null()) return true;
  if (!args[key].is_array()) return false;
  for (const json& v : args[key]) {
    if (!v.is_string()) return false;
    out.push_back(v.get<std::string>());
  }
  return true;
}
/// An override percentage given as a number or a string ("80", "80%").
bool percentArg(const json& args, const char* key, std::string& out) {
  if (!args.contains(key) || args[key].is_null()) return true;
  if (args[key].is_number()) {
    out = sim::formatNumber(args[key].get<double>());
    return true;
  }
  return stringArg(args, key, out);
}

int exitCodeOf(sim::Status s) {
  switch (s) {
  case sim::Status::Ok: return driver::kExitOk;
  case sim::Status::Error: return driver::kExitErrors;
  case sim::Status::Emergency: return driver::kExitEmergency;
  }
  return driver::kExitInternal;
}
} // namespace

Session::Session(std::istream& in, std::ostream& out, const AdapterOptions& opts)
    : reader_(in, kMaxDapMessageBytes), out_(out), opts_(opts) {}

int Session::run() {
  for (;;) {
    std::string body, error;
    const lsp::MessageReader::Status st = reader_.read(body, error);
    if (st == lsp::MessageReader::Status::Eof) return disconnected_ ? 0 : 1;
    if (st == lsp::MessageReader::Status::Bad) {
      output("stderr", "isosim: " + error + "\n");
      continue;
    }
    handle(body);
    if (disconnected_) return 0;
    if (startRun_) {
      startRun_ = false;
      execute();
      if (disconnected_) return 0;
    }
  }
}

void Session::send(json message) {
  message["seq"] = seq_++;
  lsp::writeMessage(out_, message);
}

void Session::respond(const json& req, json body) {
  json r = {{"type", "response"},
            {"request_seq", req.value("seq", 0)},
            {"success", true},
            {"command", req.value("command", "")}};
  if (!body.is_null()) r["body"] = std::move(body);
  send(std::move(r));
}

void Session::fail(const json& req, const std::string& message) {
  send({{"type", "response"},
        {"request_seq", req.is_object() ? req.value("seq", 0) : 0},
        {"success", false},
        {"command", req.is_object() ? req.value("command", "") : ""},
        {"message", message},
        {"body", {{"error", {{"id", 1}, {"format", message}, {"showUser", true}}}}}});
}

void Session::event(const std::string& name, json body) {
  send({{"type", "event"}, {"event", name}, {"body", std::move(body)}});
}

void Session::output(const std::string& category, const std::string& text) {
  event("output", {{"category", category}, {"output", text}});
}

void Session::handle(const std::string& body) {
  static const json kNone = json::object();
  // nlohmann::json's parser recurses per level: deep input must not reach it.
  if (!support::jsonNestingWithin(body))
    return fail(kNone, fmt::format("the message nests arrays and objects deeper than the limit of {} levels",
                                   support::kMaxNesting));
  json msg = json::parse(body, nullptr, false);
  if (msg.is_discarded()) return fail(kNone, "the message is not valid JSON");
  if (!msg.is_object()) return fail(kNone, "a message must be a JSON object");
  if (!msg.contains("seq") || !msg["seq"].is_number_integer()) msg["seq"] = 0;
  if (msg.value("type", json()) != "request") return; // responses and events: we send no requests
  if (!msg.contains("command") || !msg["command"].is_string()) return fail(msg, "a request needs a 'command'");
  if (msg.contains("arguments") && !msg["arguments"].is_object() && !msg["arguments"].is_null())
    return fail(msg, "'arguments' must be an object");
  try {
    request(msg);
  } catch (const json::exception& e) {
    fail(msg, fmt::format("bad arguments: {}", e.what()));
  }
}

void Session::request(const json& req) {
  const std::string cmd = req["command"].get<std::string>();
  const json args = req.contains("arguments") && req["arguments"].is_object() ? req["arguments"] : json::object();
  if (cmd == "initialize") {
    initialized_ = true;
    return respond(req, initialize());
  }
  if (!initialized_) return fail(req, "the first request must be 'initialize'");
  if (cmd == "launch") return launch(req, args);
  if (cmd == "attach") return fail(req, "isosim runs the program itself: use 'launch'");
  if (cmd == "disconnect") {
    abort_ = true;
    resume_ = true;
    disconnected_ = true;
    return respond(req);
  }
  if (cmd == "terminate") {
    abort_ = true;
    resume_ = true;
    respond(req);
    if (!started_ && !ended_) {
      ended_ = true;
      event("terminated");
    }
    return;
  }
  if (cmd == "setBreakpoints") return respond(req, setBreakpoints(args));
  if (cmd == "setFunctionBreakpoints") return respond(req, setFunctionBreakpoints(args));
  if (cmd == "setExceptionBreakpoints") {
    setExceptionBreakpoints(args);
    return respond(req);
  }
  if (cmd == "configurationDone") {
    if (!launched_) return fail(req, "configurationDone before launch");
    respond(req);
    if (!started_) startRun_ = true;
    return;
  }
  if (cmd == "threads") return respond(req, threads());
  if (cmd == "continue") return resume(req, Step::None, args);
  if (cmd == "next") return resume(req, Step::Over, args);
  if (cmd == "stepIn") return resume(req, Step::In, args);
  if (cmd == "stepOut") return resume(req, Step::Out, args);
  if (cmd == "runToTime") return runToTime(req, args);
  if (cmd == "pause") {
    if (started_ && !ended_ && !view_) pauseRequested_ = true;
    return respond(req);
  }
  const bool stoppedOnly = cmd == "stackTrace" || cmd == "scopes" || cmd == "variables" || cmd == "exceptionInfo";
  if (stoppedOnly && !view_)
    return fail(req, started_ && !ended_ ? "the program is running" : "the program is not running");
  if (cmd == "stackTrace") return respond(req, stackTrace(args));
  if (cmd == "scopes") return respond(req, scopes(args));
  if (cmd == "variables") return respond(req, variables(args));
  if (cmd == "exceptionInfo") {
    if (!exception_) return fail(req, "the program did not stop at an exception");
    return respond(req, exceptionInfo());
  }
  if (cmd == "evaluate") {
    json r = evaluate(args);
    if (r.contains("error")) return fail(req, r["error"].get<std::string>());
    return respond(req, std::move(r));
  }
  fail(req, fmt::format("isosim does not support the request '{}'", support::escapeForTerminal(cmd)));
}

json Session::initialize() {
  json filters = json::array({
      {{"filter", "error"},
       {"label", "Runtime errors"},
       {"default", true},
       {"description", "Stop where the program hits a runtime error (the run then ends)"}},
      {{"filter", "emergency"},
       {"label", "Emergencies"},
       {"default", true},
       {"description", "Stop where the machine would stop in an emergency: a soft limit, an axis programmed while "
                       "moving"}},
  });
  return {{"supportsConfigurationDoneRequest", true},
          {"supportsFunctionBreakpoints", true},
          {"supportsConditionalBreakpoints", true},
          {"supportsHitConditionalBreakpoints", true},
          {"supportsEvaluateForHovers", true},
          {"supportsExceptionInfoRequest", true},
          {"supportsTerminateRequest", true},
          {"supportsSetVariable", false},
          {"supportsStepBack", false},
          {"supportsRestartRequest", false},
          {"supportsLogPoints", false},
          {"supportsDataBreakpoints", false},
          {"supportsSteppingGranularity", false},
          {"exceptionBreakpointFilters", std::move(filters)}};
}

void Session::launch(const json& req, const json& args) {
  if (launched_) return fail(req, "the session has launched its program already");
  driver::SimulateOptions o;
  std::string cwd, settings, feed, rapid;
  const bool typesOk = stringArg(args, "program", o.program) && stringArg(args, "machine", o.common.machinePath) &&
                       stringArg(args, "settings", settings) && stringArg(args, "dialect", o.common.dialect) &&
                       stringArg(args, "entry", o.entry) && stringArg(args, "cwd", cwd) &&
                       boolArg(args, "stopOnEntry", stopOnEntry_) && boolArg(args, "noDebug", noDebug_) &&
                       boolArg(args, "blockSkip", o.blockSkip) && stringListArg(args, "paths", o.paths) &&
                       stringListArg(args, "set", o.sets) && percentArg(args, "feedOverride", feed) &&
                       percentArg(args, "rapidOverride", rapid);
  if (!typesOk)
    return fail(req, "launch: program, machine, settings, dialect, entry, search and cwd are strings; paths and set "
                     "lists of strings; stopOnEntry, noDebug and blockSkip true or false");
  if (args.contains("search") && !args["search"].is_null()) {
    if (!args["search"].is_string()) return fail(req, "launch: 'search' must be a string (a label or a GO target)");
    o.search = args["search"].get<std::string>();
  }
  if (o.program.empty()) return fail(req, "launch: 'program' names no program (an image from isocc or a .mpf)");
  if (cwd.empty()) cwd = opts_.baseDir;
  o.common.config = settings;
  o.feedOverride = feed;
  o.rapidOverride = rapid;
  std::error_code ec;
  auto absolute = [&](std::string& p) {
    if (p.empty() || p == "-") return;
    fs::path path(p);
    if (path.is_relative() && !cwd.empty()) path = fs::path(cwd) / path;
    p = fs::absolute(path, ec).lexically_normal().string();
  };
  absolute(o.program);
  absolute(o.common.machinePath);
  absolute(o.common.config);
  for (std::string& p : o.paths)
    absolute(p);
  if (o.program == "-") return fail(req, "launch: the program must be a file (standard input is the protocol's)");
  std::ostringstream outText, errText;
  driver::Io io{outText, errText, false, false, nullptr};
  const int rc = driver::prepareRun(o, io, prepared_);
  if (!errText.str().empty()) output("stderr", errText.str());
  if (rc != driver::kExitOk) {
    std::string first = errText.str().substr(0, errText.str().find('\n'));
    return fail(req, first.empty() ? std::string("the program cannot run") : first);
  }
  launched_ = true;
  programName_ = fs::path(o.program).filename().string();
  base_ = fs::path(o.program).parent_path();
  respond(req);
  // breakpoints set before launch are resolved now
  for (auto& [path, list] : lineBps_)
    for (Breakpoint& bp : list) {
      resolveLine(bp);
      event("breakpoint", {{"reason", "changed"}, {"breakpoint", breakpointJson(bp)}});
    }
  for (Breakpoint& bp : functionBps_) {
    resolveFunction(bp);
    event("breakpoint", {{"reason", "changed"}, {"breakpoint", breakpointJson(bp)}});
  }
  rebuildIndex();
  event("initialized");
}

void Session::execute() {
  started_ = true;
  sim::SimOptions so = prepared_.options;
  so.debug = noDebug_ ? nullptr : this;
  entryPending_ = stopOnEntry_;
  event("thread", {{"reason", "started"}, {"threadId", 1}});
  sim::SimResult res = sim::simulate(*prepared_.image, *prepared_.machine, so);
  ended_ = true;
  if (disconnected_) return;
  if (res.setupError != sim::SetupError::None) {
    output("stderr", fmt::format("{}: error: {}\n", programName_, res.setupMessage));
    event("exited", {{"exitCode", driver::kExitUsage}});
    event("terminated");
    return;
  }
  sim::Summary& s = res.summary;
  s.overrides = prepared_.overrides;
  if (s.status != sim::Status::Ok) output("stderr", "isosim: " + s.message + "\n");
  output("console", sim::summaryText(s));
  event("exited", {{"exitCode", exitCodeOf(s.status)}});
  event("terminated");
}

void Session::resume(const json& req, Step step, const json& args) {
  if (!view_) {
    if (step == Step::None) return respond(req, {{"allThreadsContinued", true}}); // running already
    return fail(req, "the program is not stopped");
  }
  step_ = step;
  if (step != Step::None) {
    stepThread_ = args.contains("threadId") && args["threadId"].is_number_integer() ? args["threadId"].get<uint32_t>()
                                                                                    : stoppedThread_;
    const std::vector<sim::DebugFrame> frames = view_->stack(stepThread_);
    if (frames.empty()) {
      stepThread_ = stoppedThread_;
      stepDepth_ = view_->stack(stepThread_).size();
    } else {
      stepDepth_ = frames.size() - 1;
    }
  }
  resume_ = true;
  respond(req, step == Step::None ? json{{"allThreadsContinued", true}} : json::object());
}

void Session::runToTime(const json& req, const json& args) {
  if (!launched_) return fail(req, "runToTime before launch");
  if (!args.contains("time") || !args["time"].is_number())
    return fail(req, "runToTime needs 'time', the simulated time in seconds");
  const double t = args["time"].get<double>();
  const double now = view_ ? view_->time() : 0.0;
  if (!std::isfinite(t) || t <= now)
    return fail(req, fmt::format("runToTime: {} s is not after the current time, {} s", sim::formatNumber(t),
                                 sim::formatNumber(now)));
  runTo_ = t;
  step_ = Step::None;
  respond(req);
  if (view_) resume_ = true; // before the run starts, the time applies once it does
}

void Session::waitWhileStopped() {
  while (!resume_ && !abort_) {
    std::string body, error;
    const lsp::MessageReader::Status st = reader_.read(body, error);
    if (st == lsp::MessageReader::Status::Eof) {
      abort_ = true; // the client went away
      return;
    }
    if (st == lsp::MessageReader::Status::Bad) {
      output("stderr", "isosim: " + error + "\n");
      continue;
    }
    handle(body);
  }
}

void Session::pollWhileRunning() {
  if (opts_.pollFd < 0) return;
  for (int guard = 0; guard < 64 && !abort_; ++guard) {
    if (reader_.idle()) {
      pollfd p{opts_.pollFd, POLLIN, 0};
      if (::poll(&p, 1, 0) <= 0 || (p.revents & (POLLIN | POLLHUP)) == 0) return;
    }
    std::string body, error;
    const lsp::MessageReader::Status st = reader_.read(body, error);
    if (st == lsp::MessageReader::Status::Eof) {
      abort_ = true;
      return;
    }
    if (st == lsp::MessageReader::Status::Message) handle(body);
  }
}

// ---- the hook

bool Session::statement(const sim::RunView& view, uint32_t thread, uint32_t lineEntry, size_t depth) {
  if ((++calls_ % kPollEvery) == 0) pollWhileRunning();
  if (abort_) return false;
  std::string reason;
  if (entryPending_) {
    entryPending_ = false;
    reason = "entry";
  } else if (pauseRequested_) {
    reason = "pause";
  } else if (step_ != Step::None && stepDone(view, thread, depth)) {
    reason = "step";
  }
  std::vector<int> hit;
  if (lineEntry < marked_.size() && marked_[lineEntry]) {
    hit = breakpointsHit(view, lineEntry);
    if (!hit.empty()) reason = "breakpoint";
  }
  if (reason.empty()) return true;
  stop(view, reason, thread, hit, "");
  return !abort_;
}

double Session::nextTimeStop() const {
  double t = runTo_;
  for (const Breakpoint& bp : functionBps_)
    if (bp.time >= 0 && bp.verified && !bp.fired) t = std::min(t, bp.time);
  return t;
}

bool Session::timeReached(const sim::RunView& view) {
  if (abort_) return false;
  std::vector<int> hit;
  for (Breakpoint& bp : functionBps_)
    if (bp.time >= 0 && bp.verified && !bp.fired && bp.time <= view.time()) {
      bp.fired = true; // once: the run passes that time once
      if (stops(bp, view)) hit.push_back(bp.id);
    }
  const bool runTo = runTo_ <= view.time();
  if (runTo) runTo_ = std::numeric_limits<double>::infinity();
  if (hit.empty() && !runTo) return true;
  stop(view, hit.empty() ? "time" : "function breakpoint", 1, hit,
       fmt::format("Paused at t = {} s", sim::formatNumber(view.time())));
  return !abort_;
}

void Session::fault(const sim::RunView& view, sim::Status status, const std::string& message, uint32_t thread) {
  if (abort_) return;
  const bool emergency = status == sim::Status::Emergency;
  if (emergency ? !breakOnEmergency_ : !breakOnError_) return;
  exception_ = ExceptionStop{emergency ? "emergency" : "runtime error", message};
  stop(view, "exception", thread ? thread : 1, {}, message);
  exception_.reset();
}

void Session::stop(const sim::RunView& view, const std::string& reason, uint32_t thread, const std::vector<int>& hit,
                   const std::string& text) {
  view_ = &view;
  stoppedThread_ = thread;
  resume_ = false;
  pauseRequested_ = false;
  step_ = Step::None;
  refs_.clear();
  json body = {{"reason", reason}, {"threadId", thread}, {"allThreadsStopped", true}};
  if (!hit.empty()) body["hitBreakpointIds"] = hit;
  if (!text.empty()) {
    body["text"] = text;
    body["description"] = reason == "exception" ? (exception_ ? exception_->id : reason) : text;
  }
  event("stopped", std::move(body));
  waitWhileStopped();
  view_ = nullptr;
  refs_.clear();
}

json Session::threads() const {
  json list = json::array();
  if (view_) {
    for (const sim::DebugThread& t : view_->threads())
      list.push_back({{"id", t.id}, {"name", t.name}});
  }
  if (list.empty()) list.push_back({{"id", 1}, {"name", "main"}});
  return {{"threads", std::move(list)}};
}

json Session::exceptionInfo() const {
  return {{"exceptionId", exception_->id}, {"description", exception_->description}, {"breakMode", "always"}};
}

int runDebugAdapter(std::istream& in, std::ostream& out, const AdapterOptions& opts) {
  Session s(in, out, opts);
  return s.run();
}

} // namespace iso::dap
