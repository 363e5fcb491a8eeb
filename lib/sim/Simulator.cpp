//! @file Simulator.cpp
//! @brief The event-driven scheduler and the interpreter of isosim (SPEC §4–§6).
//!
//! The simulator's rooms (lib/sim/):
//!   InstructionStream the verified code decoded into the interpreter's instructions, window by window
//!   RunMath         pure value arithmetic, §3.2 comparisons, integer indexes, Fault
//!   MovePlanner     pure: a Move's words + modal state + machine limits → a path block (line or
//!                   arc) or independent axis segments; Motion/MotionProfile/PathPlanner do the math
//!   MachineState    R (with the journal a G64 read-ahead rolls back), I/O, markers, the input
//!                   schedule, running PLC sequences
//!   WhenWatch       the WHEN root search (sample points, bisection to adjacent doubles) behind
//!                   a condition oracle
//!   ProfileRecorder the --profile journal (with its own mark/rollback for the read-ahead)
//!   Z32State        z32 spindle, coolants, tool (SPEC §4.6)
//!   Thread          the thread and frame model (pc, stack, frames, modal state, WHEN groups)
//!   G64Chain        the G64 chain: blocks read ahead, the snapshot to roll back to, its plan
//!   Simulator.h     the Simulator's state and members, implemented in five files:
//!     Interpreter.cpp   the interpreter switch (runThreadBody, one line a case, each case a
//!                       named member) and the z32 machine functions
//!     MoveStart.cpp     starting moves and running a G64 chain (read ahead, roll back, junctions)
//!     WhenArm.cpp       arming, checking, firing and dropping WHENs
//!     Search.cpp        block search (--search): the lines before the found one in search mode
//!     this file         setup, the scheduler (time, events, inputs, samples), threads, entry
//!                       selection and the public API (Run.h)
//!
//! Structure of a run:
//!   loop:  run every runnable thread at `now` until it waits  →  check armed WHENs at `now`
//!          (fire or drop; fired bodies become runnable)  →  repeat until quiet;
//!          tNext = earliest wake / input step / PLC end / WHEN window end;
//!          search armed WHENs in (now, tNext) for a firing instant tf → advance to tf, fire;
//!          else advance to tNext (samples k·dt <= tNext, move_end events), apply input steps,
//!          then PLC sequence ends (an M effect wins a tie), then wake threads.
#include "sim/Simulator.h"

#include <algorithm>
#include <cassert>
#include <cmath>

#include <fmt/format.h>

#include "image/ImageVerifier.h"
#include "support/CaseFold.h"

namespace iso::sim {

// ============================================================================================
// setup and teardown

void Simulator::init() {
  axes_.assign(static_cast<size_t>(nAxes_), AxisMotion{});
  for (int i = 0; i < nAxes_; ++i)
    axes_[static_cast<size_t>(i)].stopAt(0, m_.axes[static_cast<size_t>(i)].start);
  posBuf_.assign(static_cast<size_t>(nAxes_), 0.0);
  velBuf_.assign(static_cast<size_t>(nAxes_), 0.0);
  ms_.start(m_, z32_ ? img_.strings.size() : 0);
  originOffset_.assign(static_cast<size_t>(nAxes_), 0.0);
  releasedAt_.assign(static_cast<size_t>(nAxes_), kNoIndex);
  if (prof_) {
    rec_.start(prog_.size(), img_.procs.size());
  }
  axisStmt_.assign(static_cast<size_t>(nAxes_), kNoIndex);
  zoneDue_.assign(m_.zones.size(), kInf);
  zoneIn_.assign(m_.zones.size(), 0);
  zoneWarned_.assign(m_.zones.size(), 0);
  zoneMask_.assign(m_.zones.size(), 0);
  for (size_t z = 0; z < m_.zones.size(); ++z)
    for (const machine::ZoneAxis& za : m_.zones[z].axes)
      if (const int ax = m_.axisIndex(za.letter); ax >= 0) zoneMask_[z] |= 1u << ax;
  vmax_.resize(static_cast<size_t>(nAxes_));
  amax_.resize(static_cast<size_t>(nAxes_));
  for (int i = 0; i < nAxes_; ++i) {
    vmax_[static_cast<size_t>(i)] = m_.axes[static_cast<size_t>(i)].maxVelocity;
    amax_[static_cast<size_t>(i)] = m_.axes[static_cast<size_t>(i)].maxAccel;
  }
}

Summary Simulator::run(uint32_t proc) {
  firstProc_ = proc;
  init();
  if (sink_) sink_->begin(m_);
  size_t id = spawn();
  Thread& th = threads_[id];
  th.pc = prog_.procEntry[proc];
  th.state = TState::Runnable;
  processEventsAt(0); // input steps at t = 0
  try {
    loop();
  } catch (const Fault& f) {
    // Raised outside a thread (WHEN watch, time limit): the context was set by the thrower.
    stopWith(f.status, f.what, mainContext());
  } catch (const DebugAbort&) {
    stopWith(Status::Error, std::string(kDebuggerEndedRun), mainContext());
  }
  if (searching_ && !stopped_) stopWith(Status::Error, searchNotReached(), mainContext()); // ended another way
  return finish();
}

Summary Simulator::finish() {
  if (prof_) {
    if (rec_.open()) rec_.end(now_);
    rec_.build(*prof_, img_, prog_, names_, threads_.empty() ? 0 : firstProc_, now_);
  }
  if (sink_ && samples_ && !rowLimitHit_) {
    // The exact end gets its own row unless it is a sample time. Times are sums of many
    // durations, so "is a sample time" allows for their rounding: within 1e-9 relative of the
    // last sample time, and never more than dt/1000.
    const double tol = std::min(1e-9 * std::max(1.0, now_), 1e-3 * opts_.dt);
    if (!(std::fabs(now_ - lastSampleT_) <= tol)) {
      if (rows_ >= opts_.maxRows)
        stopForRows();
      else
        emitSample(now_);
    }
  }
  Summary s;
  s.status = status_;
  s.cycleTimeS = now_;
  s.blocks = blocks_;
  s.linesExecuted = lines_;
  s.message = message_;
  for (int i = 0; i < nAxes_; ++i)
    s.finalPosition.emplace_back(m_.axes[static_cast<size_t>(i)].letter,
                                 axes_[static_cast<size_t>(i)].positionAt(now_));
  for (uint64_t m : unmodeledM_)
    s.warnings.push_back(fmt::format("M{} has no model in the machine file: default_m_duration_s ({} s) was used", m,
                                     num(m_.defaultMDurationS)));
  s.warnings.insert(s.warnings.end(), warnings_.begin(), warnings_.end());
  if (std::string w = feedCappedWarning(); !w.empty()) s.warnings.push_back(std::move(w));
  if (z32_) {
    zs_.finish(now_);
    s.z32 = true;
    s.spindleOnS = zs_.spindleOnS();
    s.toolChanges = zs_.toolChanges() - searchToolChanges_;
    s.tool = zs_.tool();
    s.origin = origin_;
  }
  if (opts_.search) s.search = opts_.search->where;
  if (sink_) {
    if (events_ && status_ == Status::Ok) emit({.kind = EventKind::End});
    sink_->end(s);
  }
  return s;
}

// ============================================================================================
// scheduler

void Simulator::loop() {
  for (uint64_t round = 1;; ++round) {
    if (opts_.progress && (round & 0xF) == 0) opts_.progress(now_, blocks_, lines_);
    for (;;) {
      const bool ran = runRunnable();
      if (stopped_ || mainDone_) return;
      bool changed = false;
      try {
        changed = checkWhensAt();
      } catch (const Fault& f) {
        stopWith(f.status, f.what, armed_.empty() ? mainContext() : armed_.front().when);
        return;
      }
      if (!ran && !changed) break;
    }
    updateZones();
    const double tNext = nextTime();
    const double limit = opts_.maxTime;
    const double searchEnd = std::min(tNext, limit);
    if (!armed_.empty() && searchEnd > now_) {
      Found f = searchWhens(now_, searchEnd);
      if (f.found) {
        if (debug_) debugTimeUpTo(f.t);
        if (!advanceTo(f.t)) return stopForRows();
        if (f.error) {
          stopWith(f.fault.status, f.fault.what, armed_[f.index].when);
          return;
        }
        fire(f.index);
        continue;
      }
    }
    if (debug_) debugTimeUpTo(std::min(tNext, limit));
    if (tNext >= limit) { // SPEC §6.3: reaching the limit stops the run
      if (!advanceTo(limit)) return stopForRows();
      stopWith(
          Status::Error,
          fmt::format("the run reached the simulated time limit of {} s (--max-time); a runaway program?", num(limit)),
          mainContext());
      return;
    }
    if (tNext == kInf) internal("nothing left to wait for (scheduler deadlock)");
    if (!advanceTo(tNext)) return stopForRows();
    processEventsAt(tNext);
  }
}

bool Simulator::runRunnable() {
  bool any = false;
  for (;;) {
    size_t pick = threads_.size();
    for (size_t i = 0; i < threads_.size(); ++i)
      if (threads_[i].state == TState::Runnable) {
        pick = i;
        break;
      }
    if (pick == threads_.size()) return any;
    any = true;
    try {
      curThread_ = threads_[pick].serial;
      debugThread_ = curThread_ + 1;
      runThread(pick);
      curThread_ = 0;
      debugThread_ = 0;
    } catch (const Fault& f) {
      curThread_ = 0;
      const Thread& th = threads_[pick];
      stopWith(f.status, f.what, th.stmt != kNoIndex ? th.stmt : th.pc);
      debugThread_ = 0;
      return true;
    }
    if (mainDone_) return true;
  }
}

double Simulator::nextTime() const {
  double t = kInf;
  for (const Thread& th : threads_)
    if (th.state == TState::Waiting) t = std::min(t, th.wake);
  t = std::min(t, ms_.nextInputTime());
  for (const RunningSeq& s : ms_.seqs())
    t = std::min(t, s.end);
  for (const Armed& a : armed_)
    t = std::min(t, a.windowEnd);
  for (double due : zoneDue_)
    t = std::min(t, due);
  return t;
}

void Simulator::emitSample(double t) {
  for (int i = 0; i < nAxes_; ++i)
    posBuf_[static_cast<size_t>(i)] = axes_[static_cast<size_t>(i)].positionAt(t);
  if (velocities_) {
    for (int i = 0; i < nAxes_; ++i)
      velBuf_[static_cast<size_t>(i)] = axes_[static_cast<size_t>(i)].velocityAt(t);
    sink_->sampleWithVelocity(t, posBuf_.data(), velBuf_.data());
  } else {
    sink_->sample(t, posBuf_.data());
  }
  lastSampleT_ = t;
  ++rows_;
}

bool Simulator::advanceTo(double t) {
  if (t < now_) internal("time went backwards");
  if (samples_) {
    for (;;) {
      const double ts = static_cast<double>(nextSample_) * opts_.dt;
      if (ts > t) break;
      if (rows_ >= opts_.maxRows) {
        // the run stops at the time of the row it may not write
        if (events_) flushMoveEnds(ts);
        now_ = std::max(now_, ts);
        return false;
      }
      emitSample(ts);
      ++nextSample_;
    }
  }
  if (events_) flushMoveEnds(t);
  now_ = t;
  return true;
}

void Simulator::stopForRows() {
  rowLimitHit_ = true;
  stopWith(Status::Error,
           fmt::format("the trace reached its limit of {} rows (--max-rows), {} rows written; a larger --dt or "
                       "--max-rows lets the run go on",
                       opts_.maxRows, rows_),
           mainContext());
}

void Simulator::flushMoveEnds(double t) {
  while (!moveEnds_.empty()) {
    size_t best = 0;
    for (size_t i = 1; i < moveEnds_.size(); ++i)
      if (moveEnds_[i].t < moveEnds_[best].t ||
          (moveEnds_[i].t == moveEnds_[best].t && moveEnds_[i].order < moveEnds_[best].order))
        best = i;
    if (moveEnds_[best].t > t) return;
    Event e;
    e.t = moveEnds_[best].t;
    e.kind = EventKind::MoveEnd;
    e.axis = m_.axes[static_cast<size_t>(moveEnds_[best].axis)].letter;
    e.target = moveEnds_[best].target;
    sink_->event(e);
    moveEnds_.erase(moveEnds_.begin() + static_cast<std::ptrdiff_t>(best));
  }
}

void Simulator::setInput(int index, int value) {
  if (!ms_.setInput(index, value)) return;
  if (events_) emit({.kind = EventKind::Input, .index = index, .value = static_cast<uint8_t>(value != 0)});
}

void Simulator::processEventsAt(double t) {
  // 0. the crash zones entered now (a forbidden one stops the run here)
  enterZonesAt(t);
  if (stopped_) return;
  // 1. the machine's input schedule
  for (InputStep step; ms_.takeInputStep(t, step);)
    setInput(step.index, step.value);
  // 2. PLC sequences ending now: their input effects win a tie with the schedule
  for (RunningSeq s; ms_.takeEndedSeq(t, s);) {
    if (events_) emit({.kind = EventKind::MEnd, .m = s.m});
    if (s.model)
      for (const auto& [idx, v] : s.model->setInputs)
        setInput(idx, v);
  }
  // 3. threads whose wait is over
  for (Thread& th : threads_)
    if (th.state == TState::Waiting && th.wake <= t) th.state = TState::Runnable;
}

std::string Simulator::feedCappedWarning() const {
  constexpr size_t kListed = 10;
  std::set<std::pair<std::string_view, uint32_t>> lines; // by file, then line; a line once
  for (uint32_t stmt : feedCapped_) {
    std::string_view file;
    uint32_t line = 0;
    fileLineOf(stmt, file, line);
    lines.emplace(file, line);
  }
  if (lines.empty()) return {};
  std::string w = fmt::format("feed capped by an axis max_velocity (F is in mm/s) on {} line{}:", lines.size(),
                              lines.size() == 1 ? "" : "s");
  size_t k = 0;
  for (const auto& [file, line] : lines) {
    if (k++ == kListed) break;
    w += fmt::format("{} {}:{}", k == 1 ? "" : ",", file, line);
  }
  if (lines.size() > kListed) w += fmt::format(" and {} more", lines.size() - kListed);
  return w;
}

void Simulator::fileLineOf(uint32_t ins, std::string_view& file, uint32_t& line) const {
  file = "?";
  line = 0;
  if (ins == kNoIndex || ins >= prog_.size()) return;
  const Ins in = prog_[ins];
  if (in.c != kNoIndex) {
    const image::LineEntry& le = img_.lines[in.c];
    file = names_[le.file];
    line = le.line;
    return;
  }
  file = names_[img_.procs[prog_.procOf(ins)].file];
}

std::string Simulator::locationOf(uint32_t ins) const {
  std::string_view file;
  uint32_t line = 0;
  fileLineOf(ins, file, line);
  return line ? fmt::format("{}:{}", file, line) : std::string(file);
}

void Simulator::stopWith(Status st, const std::string& what, uint32_t ctx) {
  if (stopped_) return;
  if (searching_) endSearch(false);
  stopped_ = true;
  status_ = st;
  message_ = fmt::format("{}: {} at t={} s: {}", locationOf(ctx),
                         st == Status::Emergency ? "emergency" : "runtime error", num(now_), what);
  // The machine stops at once (no braking model): every axis freezes where it is.
  for (AxisMotion& a : axes_)
    if (a.moving(now_)) a.stopAt(now_, a.positionAt(now_));
  moveEnds_.clear();
  ms_.stopSeqs();
  armed_.clear();
  if (events_) emit({.kind = EventKind::Error, .status = st, .message = message_});
  if (debug_ && what != kDebuggerEndedRun) debugFault(st);
}

// ============================================================================================
// threads

size_t Simulator::spawn() {
  for (size_t i = 0; i < threads_.size(); ++i)
    if (threads_[i].state == TState::Done && i != 0) {
      Thread& th = threads_[i];
      th.stack.clear();
      th.frames.clear();
      th.pending.clear();
      th.group = th.join = -1;
      th.body = false;
      th.sinceStmt = 0;
      th.stmt = kNoIndex;
      th.serial = 0;
      th.when = kNoIndex;
      return i;
    }
  threads_.emplace_back();
  threads_.back().stack.reserve(64);
  return threads_.size() - 1;
}

int Simulator::newGroup() {
  for (size_t i = 0; i < groups_.size(); ++i)
    if (!groups_[i].inUse) {
      groups_[i] = Group{};
      groups_[i].inUse = true;
      return static_cast<int>(i);
    }
  groups_.push_back(Group{});
  groups_.back().inUse = true;
  return static_cast<int>(groups_.size() - 1);
}

void Simulator::groupCheck(int g) {
  Group& gr = groups_[static_cast<size_t>(g)];
  if (gr.live > 0 || gr.armed > 0) return;
  if (gr.joiner >= 0) {
    Thread& j = threads_[static_cast<size_t>(gr.joiner)];
    if (j.state == TState::Joining) j.state = TState::Runnable;
  }
}

bool Simulator::mustJoin(size_t id) {
  Thread& th = threads_[id];
  if (th.join < 0) return false;
  Group& g = groups_[static_cast<size_t>(th.join)];
  if (g.live > 0 || g.armed > 0) {
    g.joiner = static_cast<int>(id);
    th.state = TState::Joining;
    if (prof_ && !th.body) profBegin(th, TimeCat::When, -1, nullptr);
    return true;
  }
  g.inUse = false;
  th.join = -1;
  return false;
}

void Simulator::finishBody(size_t id) {
  Thread& th = threads_[id];
  if (events_) emitWhen(th.when, "ended", th.serial);
  th.state = TState::Done;
  th.pending.clear();
  if (th.group >= 0) {
    --groups_[static_cast<size_t>(th.group)].live;
    groupCheck(th.group);
  }
}

void Simulator::emitLine(uint32_t stmt) {
  const Ins in = prog_[stmt];
  Event e;
  e.kind = EventKind::Line;
  if (in.c != kNoIndex) {
    const image::LineEntry& le = img_.lines[in.c];
    e.file = names_[le.file];
    e.line = le.line;
    e.hasN = le.hasN;
    e.n = le.n;
  } else {
    e.file = names_[img_.procs[prog_.procOf(stmt)].file];
  }
  emit(e);
}

double Simulator::nextTick(double t) const {
  // Boundaries are k·ipo with k an integer; a time within a hair of boundary k counts as k, so
  // that 3.0 s computed as 2.9999999999999996 is not read as lying before tick 1500.
  const double ipo = m_.ipoCycleS;
  const double tol = 1e-9 * ipo + std::fabs(t) * 1e-15;
  double k = std::floor(t / ipo);
  if (k < 0) k = 0;
  while ((k + 1) * ipo <= t + tol)
    k += 1;
  while (k > 0 && k * ipo > t + tol)
    k -= 1;
  return (k + 1) * ipo;
}

double Simulator::axVar(uint8_t sv, uint8_t imgAxis, double t) const {
  const auto ax = static_cast<size_t>(axisMap_[imgAxis]);
  switch (static_cast<SysVarId>(sv)) {
  case SysVarId::MaxVelo: return m_.axes[ax].maxVelocity;
  case SysVarId::PosLimitPlus: return m_.axes[ax].limitPlus;
  case SysVarId::PosLimitMinus: return m_.axes[ax].limitMinus;
  // z32: program coordinates, the machine position minus the selected origin's offset
  case SysVarId::AaIw: return axes_[ax].positionAt(t) - (z32_ ? originOffset_[ax] : 0.0);
  case SysVarId::AaFw: return axes_[ax].target - (z32_ ? originOffset_[ax] : 0.0);
  default: internal("axis variable id");
  }
}

void Simulator::ioWrite(uint8_t sv, double index, double value) {
  const IoWrite w = ms_.ioWrite(sv, index, value);
  if (searching_) searchIo_[{!w.output, w.index}] = w.value;
  if (events_) emit({.kind = w.output ? EventKind::Output : EventKind::Marker, .index = w.index, .value = w.value});
}

void Simulator::runThread(size_t id) {
  if (id == 0 && rec_.open()) rec_.end(now_);
  if (id == 0 && chain_.active() && chainJunction(id)) return;
  try {
    runThreadBody(id);
  } catch (const Fault&) {
    // A statement read ahead fails: the chain ends before its line, which runs again (and
    // fails at its own instant) when the path has stopped.
    if (!chain_.collecting()) throw;
    rollbackChain(id);
  }
}

// ============================================================================================
// --profile: every instant of the main program goes to one statement and one category

void Simulator::profBegin(const Thread& th, TimeCat cat, int64_t m, const AxisMotion* mot) {
  stackProcs(th, rec_.begin(th.stmt, cat, m, now_, mot));
}

void Simulator::stackProcs(const Thread& th, std::vector<uint32_t>& out) const {
  out.clear();
  auto addProc = [&](uint32_t pc) {
    if (pc >= prog_.size()) return;
    const uint32_t p = prog_.procOf(pc);
    if (std::find(out.begin(), out.end(), p) == out.end()) out.push_back(p);
  };
  addProc(th.stmt != kNoIndex ? th.stmt : th.pc);
  addProc(th.pc); // the procedure running now: a main program that ends after a call is still on the stack
  for (const Frame& f : th.frames)
    if (f.ret > 0) addProc(f.ret - 1);
}

std::string Simulator::pathBoundLabel(const PathBlock& pb, const Trapezoid& prof, bool corner) const {
  auto letter = [&](int ax) { return ax >= 0 ? m_.axes[static_cast<size_t>(ax)].letter : '?'; };
  return boundLabel(prof, pb.vBound, letter(pb.vAxis), letter(pb.aAxis), corner);
}

// ============================================================================================
// public API

std::vector<std::string> entryNames(const image::Image& img) {
  std::vector<std::string> out;
  for (const auto& e : img.entries)
    if (e.name < img.strings.size()) out.push_back(image::printableName(img.strings[e.name]));
  return out;
}

namespace {
/// The entry point of --entry NAME (SPEC §6): main by default; else a SEMI name, then a file
/// stem, case-insensitive, as stored or as listed (escaped: "Caff\xE8 manuale" for a Latin-1
/// byte). Null when nothing matches.
const image::EntryPoint* selectEntry(const image::Image& img, const std::string& name) {
  if (name.empty()) {
    for (const auto& e : img.entries)
      if (e.kind == image::UnitKind::Main) return &e;
    return &img.entries.front();
  }
  auto matches = [&](const std::string& stored) {
    return support::iequals(stored, name) || support::iequals(image::printableName(stored), name);
  };
  for (const auto& e : img.entries)
    if (matches(img.strings[e.name])) return &e;
  for (const auto& e : img.entries)
    if (matches(img.strings[img.procs[e.proc].name])) return &e;
  return nullptr;
}
} // namespace

std::optional<uint32_t> entryProc(const image::Image& img, const std::string& entry) {
  const image::EntryPoint* e = selectEntry(img, entry);
  if (!e) return std::nullopt;
  return e->proc;
}

SimResult simulate(const image::VerifiedImage& verified, const machine::Machine& m, const SimOptions& opts,
                   TraceSink* sink) {
  SimResult res;
  const image::Image& img = verified.image();
  const InstructionStream prog(verified);
  std::vector<int> axisMap;
  for (char letter : img.axes) {
    int idx = m.axisIndex(letter);
    if (idx < 0) {
      res.setupError = SetupError::AxisMissing;
      res.setupMessage = fmt::format("the program uses axis {}, which machine '{}' does not have", letter, m.name);
      return res;
    }
    axisMap.push_back(idx);
  }
  if (m.axes.empty() || m.axes.size() > static_cast<size_t>(lang::kMaxMachineAxes)) {
    res.setupError = SetupError::InvalidImage;
    res.setupMessage = fmt::format("the machine must have 1 to {} axes", lang::kMaxMachineAxes);
    return res;
  }
  const image::EntryPoint* entry = selectEntry(img, opts.entry);
  if (!entry) {
    std::string names;
    for (const auto& n : entryNames(img))
      names += (names.empty() ? "\"" : ", \"") + n + "\"";
    res.setupError = SetupError::UnknownEntry;
    res.setupMessage = fmt::format("no program called \"{}\" in the image; entries: {}", opts.entry, names);
    return res;
  }
  Simulator sim(img, prog, m, opts, sink, std::move(axisMap));
  res.summary = sim.run(entry->proc);
  return res;
}

} // namespace iso::sim
