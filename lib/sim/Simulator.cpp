//! @file Simulator.cpp
//! @brief The event-driven scheduler and the interpreter of isosim (SPEC §4–§6).
//!
//! The simulator's rooms (lib/sim/):
//!   RunMath         pure value arithmetic, §3.2 comparisons, integer indexes, Fault
//!   MovePlanner     pure: a Move's words + modal state + machine limits → a path block (line or
//!                   arc) or independent axis segments; Motion/Profile/PathPlanner do the math
//!   MachineState    R (with the journal a G64 read-ahead rolls back), I/O, markers, the input
//!                   schedule, running PLC sequences
//!   WhenWatch       the WHEN root search (sample points, bisection to adjacent doubles) behind
//!                   a condition oracle
//!   ProfileRecorder the --profile journal (with its own mark/rollback for the read-ahead)
//!   Z32State        z32 spindle, coolants, tool (SPEC §4.6)
//!   this file       threads and frames, the scheduler, the interpreter switch (runThreadBody,
//!                   one line a case, each case a named member), starting moves, the G64 chain
//!                   (read-ahead, snapshot, rollback, junctions), arming and firing WHENs, events.
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
#include <limits>
#include <map>
#include <set>
#include <stdexcept>

#include <fmt/format.h>

#include "image/ImageVerifier.h"
#include "lang/GCodes.h"
#include "lang/Limits.h"
#include "sim/MachineState.h"
#include "sim/Motion.h"
#include "sim/MovePlanner.h"
#include "sim/PathPlanner.h"
#include "sim/ProfileRecorder.h"
#include "sim/Program.h"
#include "sim/RunMath.h"
#include "sim/TimeProfile.h"
#include "sim/TraceWriter.h"
#include "sim/WhenWatch.h"
#include "sim/Z32State.h"

namespace iso::sim {

using image::Op;
using image::SysVarId;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr int kMaxAxes = lang::kMaxImageAxes;
constexpr uint64_t kMaxR = lang::kMaxRIndex;
constexpr int kMaxMarker = lang::kMaxMarker;
constexpr uint64_t kNoProgressLimit = 10'000'000; ///< instructions a thread may run without a statement
/// Instructions a run may execute (statements, WHEN conditions) per statement of --max-steps:
/// every instruction counts, so no program runs longer than the step limit allows.
constexpr uint64_t kInstructionsPerStep = 16;
/// A G64 chain reads ahead at most this many statements per block of `lookahead_blocks` (§5.2):
/// statements that do not move (R assignments, jumps) count too, so read-ahead memory is bounded.
constexpr uint64_t kReadAheadPerBlock = 16;

/// Instructions that touch the machine or wait: reading ahead in a G64 chain stops before them.
bool endsChain(Op op) {
  switch (op) {
  case Op::Sync:
  case Op::Dwell:
  case Op::M:
  case Op::MNb:
  case Op::M0:
  case Op::M1:
  case Op::MSpecial:
  case Op::Aux:
  case Op::ZWord:
  case Op::When:
  case Op::End:
  case Op::EndImplicit:
  case Op::LoadIo:
  case Op::StoreIo:
  case Op::BodyEnd: return true;
  default: return false;
  }
}

struct Modal {
  uint8_t motion = 0;       ///< 0..3 (G00..G03)
  bool incremental = false; ///< G91
  bool continuous = false;  ///< G64: interpolated blocks blend into chains
  uint8_t plane = 17;       ///< 17, 18, 19
  double feed = kNaN;       ///< F, mm/s; NaN = never set
};

struct Frame {
  uint32_t ret = 0;
  Modal saved;
  bool toolChange = false; ///< z32: the call of a special M6; the tool changes on return
};

enum class TState : uint8_t { Runnable, Waiting, Joining, Done };

struct Thread {
  uint32_t pc = 0;
  std::vector<double> stack;
  std::vector<Frame> frames;
  Modal modal;
  TState state = TState::Done;
  double wake = 0;
  int group = -1;                ///< body threads: the WHEN group they belong to
  int join = -1;                 ///< after the current wait, wait for this group to finish
  std::vector<uint32_t> pending; ///< When instructions registered for the next path instruction
  uint32_t stmt = kNoIndex;      ///< the statement being executed (error locations)
  int64_t specialM = -1;         ///< z32: the special M whose call comes next
  bool body = false;
  uint64_t sinceStmt = 0;
  uint32_t serial = 0;      ///< events: 0 the main program, else the body's number (Event::thread)
  uint32_t when = kNoIndex; ///< body threads: their When instruction
};

/// The threads a trigger's WHEN chain started; its joiner waits until it is empty.
struct Group {
  int live = 0;  ///< body threads still running
  int armed = 0; ///< WHENs still watching
  int joiner = -1;
  bool inUse = false;
};

struct Armed {
  uint32_t when = 0;           ///< When instruction
  std::vector<uint32_t> chain; ///< the WHENs the body's path instruction arms
  double windowEnd = 0;        ///< end of the trigger's blocking motion
  Modal modal;                 ///< modal state of the trigger (the body starts with it)
  int group = -1;
  bool readsIw = false; ///< the condition can change between events
};

struct PendingMoveEnd {
  double t = 0;
  uint64_t order = 0;
  int axis = 0;
  double target = 0;
};

/// The thread state to return to when reading ahead meets a line that ends the chain.
struct ChainSnapshot {
  uint32_t pc = 0;
  std::vector<double> stack;
  std::vector<Frame> frames;
  Modal modal;
  uint32_t stmt = kNoIndex;
  size_t undo = 0;
  uint64_t steps = 0;
  size_t after = 0;
  size_t profUndo = 0;
};

struct Chain {
  bool collecting = false; ///< reading ahead (no time passes)
  bool active = false;     ///< running its blocks
  std::vector<PathBlock> blocks;
  std::vector<PlannedBlock> planned; ///< speeds and trapezoid of each block
  size_t cur = 0;
  uint64_t readAhead = 0;     ///< statements read ahead so far
  double pred[kMaxAxes] = {}; ///< axis targets after the blocks read so far
  ChainSnapshot snap;
};

class Simulator {
public:
  Simulator(const image::Image& img, const Program& prog, const machine::Machine& m, const SimOptions& opts,
            TraceSink* sink, std::vector<int> axisMap)
      : img_(img), prog_(prog), m_(m), opts_(opts), sink_(sink), axisMap_(std::move(axisMap)) {
    nAxes_ = static_cast<int>(m.axes.size());
    samples_ = sink && sink->wantsSamples() && opts.dt > 0;
    events_ = sink && sink->wantsEvents();
    velocities_ = samples_ && sink->wantsVelocities();
    prof_ = opts.profile;
    z32_ = img.z32();
    callLimit_ = static_cast<size_t>(
        lang::maxNesting(z32_ || m.dialect == machine::Dialect::Z32 ? lang::Dialect::Z32 : lang::Dialect::Sidac));
    names_.reserve(img.strings.size());
    for (const std::string& s : img.strings)
      names_.push_back(image::printableName(s));
    const uint64_t maxSteps = std::max<uint64_t>(opts.maxSteps, 1);
    workLimit_ = maxSteps > std::numeric_limits<uint64_t>::max() / kInstructionsPerStep
                     ? std::numeric_limits<uint64_t>::max()
                     : maxSteps * kInstructionsPerStep;
  }

  Summary run(uint32_t proc);

private:
  // ---- setup / teardown
  void init();
  Summary finish();

  // ---- scheduler
  void loop();
  bool runRunnable();
  double nextTime() const;
  void advanceTo(double t);
  void processEventsAt(double t);
  void stopWith(Status st, const std::string& what, uint32_t ctx);
  uint32_t mainContext() const { return threads_.empty() ? kNoIndex : threads_[0].stmt; }

  // ---- threads
  void runThread(size_t id);
  /// Makes `th` wait until t (> now). For --profile the wait is `cat`, after the phases of
  /// `mot` when it is a motion wait; `m` names the M sequence waited for.
  bool waitUntil(Thread& th, double t, TimeCat cat, int64_t m = -1, const AxisMotion* mot = nullptr) {
    if (t > now_) {
      th.state = TState::Waiting;
      th.wake = t;
      if (prof_ && !th.body) profBegin(th, cat, m, mot);
      return true;
    }
    return false;
  }
  bool mustJoin(size_t id);
  size_t spawn();
  void finishBody(size_t id);
  void groupCheck(int g);
  int newGroup();

  // ---- instructions
  /// The value operations that statements and WHEN conditions share: constants, R reads,
  /// I/O reads, arithmetic, comparisons (each seen by `onCmp(a, b)` first), logic. Returns
  /// false for any other opcode.
  template <class Push, class Pop, class OnCmp>
  bool valueOp(const Ins& in, Push&& push, Pop&& pop, OnCmp&& onCmp) const {
    switch (in.op) {
    case Op::PushConst:
    case Op::PushD0:
    case Op::PushD1:
    case Op::PushD2:
    case Op::PushD3:
    case Op::PushD4:
    case Op::PushD5:
    case Op::PushD6:
    case Op::PushD7:
    case Op::PushD8:
    case Op::PushD9: push(prog_.values[in.a]); return true;
    case Op::LoadR: push(ms_.r(in.a)); return true;
    case Op::LoadRInd: push(ms_.r(static_cast<size_t>(intIndex(pop(), 1, kMaxR, "R")))); return true;
    case Op::LoadIo: push(ms_.ioRead(in.a8, pop())); return true;
    case Op::Add:
    case Op::Sub:
    case Op::Mul:
    case Op::Div: {
      const double b = pop();
      const double a = pop();
      push(arith(in.op, a, b));
      return true;
    }
    case Op::Neg: push(-pop()); return true;
    case Op::CmpGt:
    case Op::CmpLt:
    case Op::CmpEq:
    case Op::CmpGe:
    case Op::CmpLe:
    case Op::CmpNe: {
      const double b = pop();
      const double a = pop();
      onCmp(a, b);
      push(compare(in.op, a, b));
      return true;
    }
    case Op::And: {
      const double b = pop();
      const double a = pop();
      push((a != 0 && b != 0) ? 1.0 : 0.0);
      return true;
    }
    case Op::Or: {
      const double b = pop();
      const double a = pop();
      push((a != 0 || b != 0) ? 1.0 : 0.0);
      return true;
    }
    case Op::Not: push(pop() != 0 ? 0.0 : 1.0); return true;
    default: return false;
    }
  }
  /// Where a move's axes arrive: the blocking ones (the last of them: lastAxis), and all.
  struct MoveEnd {
    double tBlock = 0;
    double tAll = 0;
    int lastAxis = -1;
  };
  bool doMove(size_t id, const Ins& in);
  void startSegment(int ax, const AxisMotion& seg, bool blocking, const Modal& md, MoveEnd& end);
  void startIndependent(const Thread& th, MovePlan& plan, const MoveWords& w, MoveEnd& end);
  void startPathBlock(const Thread& th, PathBlock& pb, const MoveWords& w, MoveEnd& end);
  bool readAheadBlock(size_t id, PathBlock pb);
  bool beginChain(size_t id, PathBlock pb);
  double curTarget(int ax) const;
  void checkNotMoving(int ax) const;
  void checkLimit(int ax, double lo, double hi) const;
  void checkBlock(const PathBlock& pb) const { checkAxes(pb.check, pb.limits); }
  void checkAxes(uint32_t mask, const std::vector<PathBlock::Limit>& limits) const;
  void stackProcs(const Thread& th, std::vector<uint32_t>& out) const;
  void startAxis(int ax, const AxisMotion& seg, uint8_t motion, uint8_t plane);

  // ---- G64 chains
  void appendChainBlock(const Thread& th, PathBlock pb);
  void snapshotChain(const Thread& th);
  void rollbackChain(size_t id);
  void finalizeChain(size_t id);
  void startChainBlock(size_t id);
  bool chainJunction(size_t id);
  void runThreadBody(size_t id);
  // ---- the interpreter switch's cases (runThreadBody); true: the thread stops for now
  double pop(Thread& th);
  void push(Thread& th, double v);
  void opStoreR(Thread& th, const Ins& in);
  void opStoreRInd(Thread& th);
  bool opLoadAxVar(size_t id, const Ins& in);
  void opStoreIo(Thread& th, const Ins& in);
  bool opStmt(size_t id, const Ins& in);
  void opCase(Thread& th, const Ins& in);
  void opCall(Thread& th, const Ins& in);
  void opRet(Thread& th);
  void opEnd(Thread& th, const Ins& in);
  void opModalG(Thread& th, const Ins& in);
  bool opDwell(Thread& th);
  bool opStop(Thread& th, const Ins& in);
  void opZWord(Thread& th, const Ins& in);
  void opBodyEnd(size_t id);
  void opValue(Thread& th, const Ins& in);
  bool doM(Thread& th, const Ins& in, bool blocking);
  // ---- z32 machine functions (SPEC §4.6)
  void z32Word(Thread& th, const Ins& in, double v);
  void z32Report(const Z32State::Change& c, uint32_t stmt);
  bool doAux(Thread& th, const Ins& in);
  double nextTick(double t) const;
  double axVar(uint8_t sv, uint8_t imgAxis, double t) const;
  void ioWrite(uint8_t sv, double index, double value);
  void setInput(int index, int value);

  // ---- WHEN
  void arm(size_t id, double windowEnd);
  bool checkWhensAt();
  void fire(size_t i);
  void drop(size_t i);
  bool evalCond(uint32_t pc, double t, int* classes, size_t* nClasses) const;
  struct Found {
    bool found = false;
    double t = 0;
    size_t index = 0;
    bool error = false;
    Fault fault{Status::Error, ""};
  };
  Found searchWhens(double a, double b);
  Found searchOne(size_t i, double a, double b);

  // ---- events
  void emit(Event& e) {
    e.t = now_;
    if (e.thread == 0) e.thread = curThread_;
    sink_->event(e);
  }
  void emitLine(const Ins& in);
  void flushMoveEnds(double t);
  void emitSample(double t);
  std::string locationOf(uint32_t ins) const;
  void fileLineOf(uint32_t ins, std::string_view& file, uint32_t& line) const;
  void warnOnce(const std::string& w) {
    if (warnSeen_.insert(w).second) warnings_.push_back(w);
  }

  const image::Image& img_;
  const Program& prog_;
  const machine::Machine& m_;
  const SimOptions& opts_;
  TraceSink* sink_;
  std::vector<int> axisMap_;       ///< image axis -> machine axis
  std::vector<std::string> names_; ///< the image's strings as text (image::printableName)
  int nAxes_ = 0;
  bool samples_ = false;
  bool events_ = false;
  bool velocities_ = false;
  size_t callLimit_ = 30;
  bool z32_ = false; ///< the image was compiled for dialect z32 (SPEC §4.6)
  Z32State zs_;      ///< z32: spindle, coolants, tool

  double now_ = 0;
  std::vector<AxisMotion> axes_;
  MachineState ms_; ///< R, I/O, markers, the input schedule, PLC sequences
  std::vector<Thread> threads_;
  std::vector<Group> groups_;
  std::vector<Armed> armed_;

  uint64_t nextSample_ = 0;
  double lastSampleT_ = -1;
  std::vector<double> posBuf_, velBuf_;
  std::vector<PendingMoveEnd> moveEnds_;
  uint64_t moveOrder_ = 0;
  uint32_t curThread_ = 0;  ///< Event::thread of the thread running now (0 between threads)
  uint32_t bodySerial_ = 0; ///< WHEN bodies fired so far

  uint64_t steps_ = 0;
  mutable uint64_t work_ = 0; ///< instructions executed so far (statements and WHEN conditions)
  uint64_t workLimit_ = 0;    ///< the most the run may execute
  void countWork(uint64_t n) const {
    work_ += n;
    if (work_ > workLimit_)
      fault(fmt::format("the program executed over {} instructions ({} per statement of --max-steps); a runaway "
                        "program?",
                        workLimit_, kInstructionsPerStep));
  }
  bool mainDone_ = false;
  bool stopped_ = false;
  Status status_ = Status::Ok;
  std::string message_;
  std::set<uint64_t> unmodeledM_;
  std::set<std::string> warnSeen_;
  std::vector<std::string> warnings_;

  std::vector<double> vmax_, amax_; ///< by machine axis (the planner's limits)

  Chain chain_;
  // ---- --profile
  void profBegin(const Thread& th, TimeCat cat, int64_t m, const AxisMotion* mot);
  std::string pathBoundLabel(const PathBlock& pb, const Trapezoid& prof, bool corner) const;

  TimeProfile* prof_ = nullptr;
  uint32_t firstProc_ = 0;
  ProfileRecorder rec_;
};

// ============================================================================================
// setup and teardown

void Simulator::init() {
  axes_.assign(static_cast<size_t>(nAxes_), AxisMotion{});
  for (int i = 0; i < nAxes_; ++i)
    axes_[static_cast<size_t>(i)].stopAt(0, m_.axes[static_cast<size_t>(i)].start);
  posBuf_.assign(static_cast<size_t>(nAxes_), 0.0);
  velBuf_.assign(static_cast<size_t>(nAxes_), 0.0);
  ms_.start(m_);
  if (prof_) {
    rec_.start(prog_.code.size(), img_.procs.size());
  }
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
  }
  return finish();
}

Summary Simulator::finish() {
  if (prof_) {
    if (rec_.open()) rec_.end(now_);
    rec_.build(*prof_, img_, prog_, names_, threads_.empty() ? 0 : firstProc_, now_);
  }
  Summary s;
  s.status = status_;
  s.cycleTimeS = now_;
  s.blocks = steps_;
  s.message = message_;
  for (int i = 0; i < nAxes_; ++i)
    s.finalPosition.emplace_back(m_.axes[static_cast<size_t>(i)].letter,
                                 axes_[static_cast<size_t>(i)].positionAt(now_));
  for (uint64_t m : unmodeledM_)
    s.warnings.push_back(fmt::format("M{} has no model in the machine file: default_m_duration_s ({} s) was used", m,
                                     num(m_.defaultMDurationS)));
  s.warnings.insert(s.warnings.end(), warnings_.begin(), warnings_.end());
  if (z32_) {
    zs_.finish(now_);
    s.z32 = true;
    s.spindleOnS = zs_.spindleOnS();
    s.toolChanges = zs_.toolChanges();
    s.tool = zs_.tool();
  }
  if (sink_) {
    // The exact end gets its own row unless it is a sample time. Times are sums of many
    // durations, so "is a sample time" allows for their rounding: within 1e-9 relative of the
    // last sample time, and never more than dt/1000.
    const double tol = std::min(1e-9 * std::max(1.0, now_), 1e-3 * opts_.dt);
    if (samples_ && !(std::fabs(now_ - lastSampleT_) <= tol)) emitSample(now_);
    if (events_ && status_ == Status::Ok) {
      Event e;
      e.kind = EventKind::End;
      emit(e);
    }
    sink_->end(s);
  }
  return s;
}

// ============================================================================================
// scheduler

void Simulator::loop() {
  for (uint64_t round = 1;; ++round) {
    if (opts_.progress && (round & 0xF) == 0) opts_.progress(now_, steps_);
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
    const double tNext = nextTime();
    const double limit = opts_.maxTime;
    const double searchEnd = std::min(tNext, limit);
    if (!armed_.empty() && searchEnd > now_) {
      Found f = searchWhens(now_, searchEnd);
      if (f.found) {
        advanceTo(f.t);
        if (f.error) {
          stopWith(f.fault.status, f.fault.what, armed_[f.index].when);
          return;
        }
        fire(f.index);
        continue;
      }
    }
    if (tNext > limit) {
      advanceTo(limit);
      stopWith(
          Status::Error,
          fmt::format("the run reached the simulated time limit of {} s (--max-time); a runaway program?", num(limit)),
          mainContext());
      return;
    }
    if (tNext == kInf) internal("nothing left to wait for (scheduler deadlock)");
    advanceTo(tNext);
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
      runThread(pick);
      curThread_ = 0;
    } catch (const Fault& f) {
      curThread_ = 0;
      const Thread& th = threads_[pick];
      stopWith(f.status, f.what, th.stmt != kNoIndex ? th.stmt : th.pc);
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
}

void Simulator::advanceTo(double t) {
  if (t < now_) internal("time went backwards");
  if (samples_) {
    for (;;) {
      const double ts = static_cast<double>(nextSample_) * opts_.dt;
      if (ts > t) break;
      emitSample(ts);
      ++nextSample_;
    }
  }
  if (events_) flushMoveEnds(t);
  now_ = t;
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
  if (events_) {
    Event e;
    e.kind = EventKind::Input;
    e.index = index;
    e.value = static_cast<uint8_t>(value != 0);
    emit(e);
  }
}

void Simulator::processEventsAt(double t) {
  // 1. the machine's input schedule
  for (InputStep step; ms_.takeInputStep(t, step);)
    setInput(step.index, step.value);
  // 2. PLC sequences ending now: their input effects win a tie with the schedule
  for (RunningSeq s; ms_.takeEndedSeq(t, s);) {
    if (events_) {
      Event e;
      e.kind = EventKind::MEnd;
      e.m = s.m;
      emit(e);
    }
    if (s.model)
      for (const auto& [idx, v] : s.model->setInputs)
        setInput(idx, v);
  }
  // 3. threads whose wait is over
  for (Thread& th : threads_)
    if (th.state == TState::Waiting && th.wake <= t) th.state = TState::Runnable;
}

void Simulator::fileLineOf(uint32_t ins, std::string_view& file, uint32_t& line) const {
  file = "?";
  line = 0;
  if (ins == kNoIndex || ins >= prog_.code.size()) return;
  const Ins& in = prog_.code[ins];
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
  if (events_) {
    Event e;
    e.kind = EventKind::Error;
    e.status = st;
    e.message = message_;
    emit(e);
  }
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
  if (events_) {
    Event e;
    e.kind = EventKind::When;
    e.action = "ended";
    e.thread = th.serial;
    fileLineOf(th.when, e.file, e.line);
    emit(e);
  }
  th.state = TState::Done;
  th.pending.clear();
  if (th.group >= 0) {
    --groups_[static_cast<size_t>(th.group)].live;
    groupCheck(th.group);
  }
}

void Simulator::emitLine(const Ins& in) {
  Event e;
  e.kind = EventKind::Line;
  if (in.c != kNoIndex) {
    const image::LineEntry& le = img_.lines[in.c];
    e.file = names_[le.file];
    e.line = le.line;
    e.hasN = le.hasN;
    e.n = le.n;
  } else {
    uint32_t idx = static_cast<uint32_t>(&in - prog_.code.data());
    e.file = names_[img_.procs[prog_.procOf(idx)].file];
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
  case SysVarId::AaIw: return axes_[ax].positionAt(t);
  case SysVarId::AaFw: return axes_[ax].target;
  default: internal("axis variable id");
  }
}

void Simulator::ioWrite(uint8_t sv, double index, double value) {
  const IoWrite w = ms_.ioWrite(sv, index, value);
  if (events_) {
    Event e;
    e.kind = w.output ? EventKind::Output : EventKind::Marker;
    e.index = w.index;
    e.value = w.value;
    emit(e);
  }
}

void Simulator::runThread(size_t id) {
  if (id == 0 && rec_.open()) rec_.end(now_);
  if (id == 0 && chain_.active && chainJunction(id)) return;
  try {
    runThreadBody(id);
  } catch (const Fault&) {
    // A statement read ahead fails: the chain ends before its line, which runs again (and
    // fails at its own instant) when the path has stopped.
    if (!chain_.collecting) throw;
    rollbackChain(id);
  }
}

// The verifier proved every stack depth (never below what an instruction pops, at most
// kMaxStackDepth): nothing is checked again here.
double Simulator::pop(Thread& th) {
  assert(!th.stack.empty());
  double v = th.stack.back();
  th.stack.pop_back();
  return v;
}

void Simulator::push(Thread& th, double v) {
  assert(th.stack.size() < image::kMaxStackDepth);
  th.stack.push_back(v);
}

// The interpreter switch: one line a case. A handler that returns true has made the thread
// wait (or end, or roll a G64 read-ahead back): the thread stops running for now.
void Simulator::runThreadBody(size_t id) {
  Thread* tp = &threads_[id];
  if (mustJoin(id)) return;
  tp->state = TState::Runnable;
  const Ins* code = prog_.code.data();
  for (;;) {
    Thread& th = *tp;
    const Ins& in = code[th.pc];
    countWork(1);
    if (++th.sinceStmt > kNoProgressLimit)
      fault(fmt::format("{} instructions without a statement: a loop that never reaches a statement (or skips "
                        "every one with --block-skip)",
                        kNoProgressLimit));
    if (chain_.collecting && endsChain(in.op)) {
      rollbackChain(id);
      return;
    }
    switch (in.op) {
    case Op::StoreR: opStoreR(th, in); break;
    case Op::StoreRInd: opStoreRInd(th); break;
    case Op::LoadAxVar:
      if (opLoadAxVar(id, in)) return;
      break;
    case Op::StoreIo: opStoreIo(th, in); break;
    case Op::Stmt:
    case Op::StmtSkip:
      if (opStmt(id, in)) return;
      break;
    case Op::Jump: th.pc = in.a; break;
    case Op::JumpFalse: th.pc = pop(th) == 0 ? in.a : th.pc + 1; break;
    case Op::JumpTrue: th.pc = pop(th) != 0 ? in.a : th.pc + 1; break;
    case Op::Case: opCase(th, in); break;
    case Op::Call: opCall(th, in); break;
    case Op::Ret: opRet(th); break;
    case Op::End:
    case Op::EndImplicit: opEnd(th, in); return;
    case Op::Sync:
      ++th.pc;
      waitUntil(th, nextTick(now_), TimeCat::Inputs);
      return;
    case Op::G0:
    case Op::G1:
    case Op::G2:
    case Op::G3:
    case Op::G90:
    case Op::G91:
    case Op::G60:
    case Op::G64:
    case Op::G17:
    case Op::G18:
    case Op::G19: opModalG(th, in); break;
    case Op::SetF:
      th.modal.feed = pop(th);
      ++th.pc;
      break;
    case Op::Move:
      if (doMove(id, in)) return;
      tp = &threads_[id];
      break;
    case Op::Dwell:
      if (opDwell(th)) return;
      break;
    case Op::M:
    case Op::MNb:
      if (doM(th, in, in.op == Op::M)) return;
      break;
    case Op::M1:
    case Op::M0:
      if (opStop(th, in)) return;
      break;
    case Op::ZWord: opZWord(th, in); break;
    case Op::Aux:
      if (doAux(th, in)) return;
      break;
    case Op::MSpecial:
      th.specialM = static_cast<int64_t>(prog_.values[in.a]);
      ++th.pc;
      break;
    case Op::When:
      th.pending.push_back(th.pc);
      ++th.pc;
      break;
    case Op::CondEnd: internal("condition end reached outside a WHEN condition (malformed image)");
    case Op::BodyEnd: opBodyEnd(id); return;
    default: opValue(th, in); break;
    }
  }
}

void Simulator::opStoreR(Thread& th, const Ins& in) {
  ms_.setR(in.a, pop(th), chain_.collecting);
  ++th.pc;
}

void Simulator::opStoreRInd(Thread& th) {
  double v = pop(th);
  double i = pop(th);
  const auto ri = static_cast<size_t>(intIndex(i, 1, kMaxR, "R"));
  ms_.setR(ri, v, chain_.collecting);
  ++th.pc;
}

bool Simulator::opLoadAxVar(size_t id, const Ins& in) {
  Thread& th = threads_[id];
  if (chain_.collecting &&
      (in.a8 == static_cast<uint8_t>(SysVarId::AaIw) || in.a8 == static_cast<uint8_t>(SysVarId::AaFw))) {
    rollbackChain(id);
    return true;
  }
  push(th, axVar(in.a8, in.b8, now_));
  ++th.pc;
  return false;
}

void Simulator::opStoreIo(Thread& th, const Ins& in) {
  double v = pop(th);
  double i = pop(th);
  ioWrite(in.a8, i, v);
  ++th.pc;
}

bool Simulator::opStmt(size_t id, const Ins& in) {
  Thread& th = threads_[id];
  if (in.op == Op::StmtSkip && opts_.blockSkip) {
    th.pc = in.a;
    return false;
  }
  if (chain_.collecting) {
    snapshotChain(th);
    const uint64_t cap = kReadAheadPerBlock * static_cast<uint64_t>(std::max(1, m_.lookaheadBlocks));
    if (++chain_.readAhead > cap) {
      rollbackChain(id); // as at any chain end: this statement runs when the path has stopped
      return true;
    }
  }
  th.stmt = th.pc;
  if (steps_ >= opts_.maxSteps)
    fault(fmt::format("the program executed {} statements, the limit of --max-steps; a runaway program?",
                      opts_.maxSteps));
  ++steps_;
  th.sinceStmt = 0;
  ++th.pc;
  if (prof_) rec_.count(th.stmt, chain_.collecting);
  if (chain_.collecting) {
    // read ahead: its line event comes when the path reaches this point; no block time
    if (events_) chain_.blocks.back().after.push_back(th.stmt);
    return false;
  }
  if (events_) emitLine(in);
  return m_.blockTimeS > 0 && waitUntil(th, now_ + m_.blockTimeS, TimeCat::Block);
}

void Simulator::opCase(Thread& th, const Ins& in) {
  double v = pop(th);
  uint32_t next = in.c != kNoIndex ? in.c : th.pc + 1;
  for (uint32_t k = 0; k < in.b; ++k)
    if (cmpEqual(v, prog_.arms[in.a + k].value)) {
      next = prog_.arms[in.a + k].target;
      break;
    }
  th.pc = next;
}

void Simulator::opCall(Thread& th, const Ins& in) {
  if (th.frames.size() >= callLimit_)
    fault(fmt::format("{}call nesting deeper than {} levels (calling {})",
                      callLimit_ == static_cast<size_t>(lang::kMaxNestingZ32) ? "too many subroutines: " : "",
                      callLimit_, names_[img_.procs[in.a].name]));
  th.frames.push_back({th.pc + 1, th.modal, th.specialM == 6});
  th.specialM = -1;
  th.pc = prog_.procEntry[in.a];
  if (prof_ && !th.body) rec_.call(in.a, chain_.collecting);
}

void Simulator::opRet(Thread& th) {
  if (th.frames.empty()) fault("M17 outside a subprogram");
  if (th.frames.back().toolChange) z32Report(zs_.changeTool(now_), th.stmt);
  th.modal = th.frames.back().saved;
  th.pc = th.frames.back().ret;
  th.frames.pop_back();
}

void Simulator::opEnd(Thread& th, const Ins& in) {
  if (th.body) fault("end of program inside a WHEN body");
  double t = now_;
  const AxisMotion* last = nullptr;
  for (const AxisMotion& a : axes_)
    if (a.tEnd > t) {
      t = a.tEnd;
      last = &a;
    }
  for (const RunningSeq& s : ms_.seqs())
    t = std::max(t, s.end);
  if (waitUntil(th, t, TimeCat::Plc, -1, last)) return; // the End runs again when the machine is idle
  if (in.op == Op::EndImplicit) warnOnce(fmt::format("the main program ended without M30 ({})", locationOf(th.stmt)));
  th.state = TState::Done;
  mainDone_ = true;
}

void Simulator::opModalG(Thread& th, const Ins& in) {
  const lang::GCode g = *image::gCodeOf(in.op); // the modal field and value: lang/GCodes.def
  const int v = lang::gModal(g);
  switch (lang::gGroup(g)) {
  case lang::GGroup::Motion: th.modal.motion = static_cast<uint8_t>(v); break;
  case lang::GGroup::Distance: th.modal.incremental = v != 0; break;
  case lang::GGroup::Path: th.modal.continuous = v != 0; break;
  case lang::GGroup::Plane: th.modal.plane = static_cast<uint8_t>(v); break;
  case lang::GGroup::None: break;
  }
  ++th.pc;
}

bool Simulator::opDwell(Thread& th) {
  double d = pop(th);
  if (!(d >= 0) || !std::isfinite(d)) fault(fmt::format("G04 dwell time {} s is not a duration >= 0", num(d)));
  if (events_) {
    Event e;
    e.kind = EventKind::Dwell;
    e.duration = d;
    emit(e);
  }
  ++th.pc;
  return waitUntil(th, now_ + d, TimeCat::Dwell);
}

bool Simulator::opStop(Thread& th, const Ins& in) {
  if (in.op == Op::M1 && !m_.optionalStop) {
    ++th.pc;
    return false;
  }
  if (events_) {
    Event e;
    e.kind = EventKind::Stop;
    e.duration = m_.m0WaitS;
    emit(e);
  }
  ++th.pc;
  return waitUntil(th, now_ + m_.m0WaitS, TimeCat::Stop);
}

void Simulator::opZWord(Thread& th, const Ins& in) {
  const double v = pop(th);
  ++th.pc;
  if (z32_)
    z32Word(th, in, v);
  else
    warnOnce(fmt::format("{} words have no model in isosim and were ignored", image::zAddrName(in.a8)));
}

void Simulator::opBodyEnd(size_t id) {
  if (!threads_[id].body) internal("WHEN body end reached outside a body (malformed image)");
  finishBody(id);
}

void Simulator::opValue(Thread& th, const Ins& in) {
  if (valueOp(
          in, [&](double v) { push(th, v); }, [&]() { return pop(th); }, [](double, double) {})) {
    ++th.pc;
    return;
  }
  if (static_cast<uint8_t>(in.op) == kOpFallOff) internal("the code ran off the end of a procedure (malformed image)");
  internal(fmt::format("unknown opcode 0x{:02x}", static_cast<unsigned>(in.op)));
}

bool Simulator::doM(Thread& th, const Ins& in, bool blocking) {
  const auto mnum = static_cast<uint64_t>(prog_.values[in.a]);
  // A sequence still running (started with M=NB) must end before it starts again.
  for (const RunningSeq& s : ms_.seqs())
    if (s.m == mnum) {
      th.state = TState::Waiting;
      th.wake = s.end;
      if (prof_ && !th.body) profBegin(th, TimeCat::Plc, static_cast<int64_t>(mnum), nullptr);
      return true; // the M runs again at that instant
    }
  const machine::MSequence* model = nullptr;
  if (mnum <= static_cast<uint64_t>(std::numeric_limits<int>::max())) {
    auto it = m_.mSequences.find(static_cast<int>(mnum));
    if (it != m_.mSequences.end()) model = &it->second;
  }
  const lang::MRole role = lang::mRole(static_cast<int64_t>(std::min<uint64_t>(mnum, lang::kMaxMNumber + 1)),
                                       z32_ ? lang::Dialect::Z32 : lang::Dialect::Sidac);
  if (!model && (!z32_ || role == lang::MRole::Plain)) unmodeledM_.insert(mnum);
  const double dur = model ? model->durationS : m_.defaultMDurationS;
  if (prof_) rec_.mStarted(mnum, dur);
  if (events_) {
    Event e;
    e.kind = EventKind::MStart;
    e.m = mnum;
    e.blocking = blocking;
    emit(e);
  }
  if (z32_) {
    if (role != lang::MRole::Plain) z32Report(zs_.apply(role, now_, m_.optionalStop), th.stmt);
    auto sp = m_.specialM.find(static_cast<int>(std::min<uint64_t>(mnum, lang::kMaxMNumber + 1)));
    if (sp != m_.specialM.end())
      warnOnce(fmt::format("M{} is a special M of machine '{}' (it calls {}), but the image runs it as a PLC sequence: "
                           "compile the program with this machine file (isocc --machine)",
                           mnum, m_.name, sp->second));
  }
  ++th.pc;
  if (!(dur > 0)) {
    if (events_) {
      Event e;
      e.kind = EventKind::MEnd;
      e.m = mnum;
      emit(e);
    }
    if (model)
      for (const auto& [idx, v] : model->setInputs)
        setInput(idx, v);
    return false;
  }
  ms_.startSeq(mnum, now_ + dur, model);
  return blocking && waitUntil(th, now_ + dur, TimeCat::Plc, static_cast<int64_t>(mnum));
}

// ============================================================================================
// z32 machine functions (SPEC §4.6)

void Simulator::z32Word(Thread& th, const Ins& in, double v) {
  if (in.a8 == static_cast<uint8_t>(image::ZAddr::S)) {
    if (!std::isfinite(v) || v < 0) fault(fmt::format("spindle speed S{} is not a speed >= 0 (rpm)", num(v)));
    z32Report(zs_.setSpeed(v, now_), th.stmt);
  } else if (in.a8 == static_cast<uint8_t>(image::ZAddr::T)) {
    if (!std::isfinite(v) || v < 0 || v != std::floor(v) || v > 999'999'999)
      fault(fmt::format("tool number T{} is not a whole number >= 0", num(v)));
    zs_.setProgrammedTool(static_cast<int64_t>(v));
  } else {
    warnOnce(fmt::format("{} words have no model in isosim and were ignored", image::zAddrName(in.a8)));
  }
}

void Simulator::z32Report(const Z32State::Change& c, uint32_t stmt) {
  if (c.speedUnset)
    warnOnce(fmt::format("the spindle was started with no S programmed and turns at 0 rpm ({})", locationOf(stmt)));
  if (c.toolUnset)
    warnOnce(fmt::format("M6 with no T programmed: the mounted tool did not change ({})", locationOf(stmt)));
  if (!events_) return;
  if (c.spindle) {
    Event e;
    e.kind = EventKind::Spindle;
    e.state = spindleDirName(zs_.dir());
    e.rpm = zs_.rpm();
    emit(e);
  }
  if (c.coolant) {
    Event e;
    e.kind = EventKind::Coolant;
    e.c1 = zs_.coolant1();
    e.c2 = zs_.coolant2();
    emit(e);
  }
  if (c.tool) {
    Event e;
    e.kind = EventKind::Tool;
    e.tool = zs_.tool().value_or(0);
    emit(e);
  }
}

bool Simulator::doAux(Thread& th, const Ins& in) {
  const size_t depth = in.b8;
  if (th.stack.size() <= depth) internal("value stack underflow in an aux function");
  const auto at = th.stack.end() - static_cast<std::ptrdiff_t>(depth) - 1;
  const double v = *at;
  th.stack.erase(at);
  const char* word = image::auxWordName(in.a8);
  if (!std::isfinite(v)) fault(fmt::format("{} value is not a finite number", word));
  ++th.pc;
  if (events_) {
    Event e;
    e.kind = EventKind::Aux;
    e.state = word;
    e.programmed = v;
    e.sent = lang::auxSent(v);
    emit(e);
  }
  return m_.auxDurationS > 0 && waitUntil(th, now_ + m_.auxDurationS, TimeCat::Plc);
}

// ============================================================================================
// motion

bool Simulator::doMove(size_t id, const Ins& in) {
  Thread& th = threads_[id];
  const uint32_t n = in.b;
  assert(th.stack.size() >= n); // verified
  const Modal& md = th.modal;
  double cur[kMaxAxes];
  for (int a = 0; a < nAxes_; ++a)
    cur[a] = curTarget(a);
  MoveRequest rq;
  rq.words =
      decodeMove(prog_.moves, in.a, n, th.stack.data() + (th.stack.size() - n), axisMap_, m_, md.incremental, cur);
  // A G64 chain holds interpolated feed blocks of the main program whose axes all block
  // (SPEC §5.2); anything else met while reading ahead ends the chain before its line.
  const MoveWords& w = rq.words;
  const bool chainable = id == 0 && !th.body && md.continuous && th.pending.empty() && w.faMask == 0 && !w.anyNb &&
                         (md.motion >= 2 || (md.motion == 1 && w.progCount <= 3));
  if (chain_.collecting && !chainable) {
    rollbackChain(id);
    return true;
  }
  th.stack.resize(th.stack.size() - n);
  rq.motion = md.motion;
  rq.plane = md.plane;
  rq.feed = md.feed;
  rq.cur = cur;
  MovePlan plan = planMove(rq, MoveLimits{&m_, &vmax_, &amax_});
  if (plan.faIgnored) warnOnce("Fa on a G00 line is ignored");
  MoveEnd end{now_, now_, -1};
  if (plan.path) {
    if (chain_.collecting) return readAheadBlock(id, std::move(plan.block));
    checkBlock(plan.block);
    if (plan.block.plan.length > 0) {
      if (chainable) return beginChain(id, std::move(plan.block));
      startPathBlock(th, plan.block, w, end);
    }
  } else {
    startIndependent(th, plan, w, end);
  }
  if (!th.pending.empty()) {
    // The trigger's window is its blocking motion (a trigger with none: the whole block).
    arm(id, end.tBlock > now_ ? end.tBlock : end.tAll);
  }
  Thread& t2 = threads_[id];
  ++t2.pc;
  const AxisMotion* last = end.lastAxis >= 0 ? &axes_[static_cast<size_t>(end.lastAxis)] : nullptr;
  if (waitUntil(t2, end.tBlock, TimeCat::Accel, -1, last)) return true;
  return mustJoin(id);
}

void Simulator::startSegment(int ax, const AxisMotion& seg, bool blocking, const Modal& md, MoveEnd& end) {
  startAxis(ax, seg, md.motion, md.plane);
  end.tAll = std::max(end.tAll, seg.tEnd);
  if (blocking && seg.tEnd >= end.tBlock) {
    end.tBlock = seg.tEnd;
    end.lastAxis = ax;
  }
}

void Simulator::startIndependent(const Thread& th, MovePlan& plan, const MoveWords& w, MoveEnd& end) {
  for (int a = 0; a < nAxes_; ++a)
    if ((plan.check >> a) & 1u) checkNotMoving(a);
  for (int a = 0; a < nAxes_; ++a)
    if ((plan.check >> a) & 1u) checkLimit(a, w.tgt[a], w.tgt[a]);
  for (auto& s : plan.segs) {
    s.seg.t0 = now_;
    s.seg.tEnd = now_ + s.seg.prof.duration();
    startSegment(s.axis, s.seg, s.blocking, th.modal, end);
  }
  if (prof_ && end.lastAxis >= 0) {
    const AxisMotion& la = axes_[static_cast<size_t>(end.lastAxis)];
    const char letter = m_.axes[static_cast<size_t>(end.lastAxis)].letter;
    const bool atVmax = la.prof.vPeak >= vmax_[static_cast<size_t>(end.lastAxis)];
    rec_.bound(th.stmt,
               boundLabel(la.prof, atVmax ? SpeedBound::AxisVelocity : SpeedBound::Feed, letter, letter, false));
  }
}

void Simulator::startPathBlock(const Thread& th, PathBlock& pb, const MoveWords& w, MoveEnd& end) {
  const Trapezoid prof = makeTrapezoid(pb.plan.length, pb.plan.vmax, pb.plan.accel);
  if (prof_) rec_.bound(th.stmt, pathBoundLabel(pb, prof, false));
  for (auto& s : pb.segs) {
    s.seg.t0 = now_;
    s.seg.prof = prof;
    s.seg.tEnd = now_ + prof.duration();
    startSegment(s.axis, s.seg, !w.nb[s.axis], th.modal, end);
  }
}

bool Simulator::readAheadBlock(size_t id, PathBlock pb) {
  // read ahead: the block joins the chain; its checks run when the path reaches it
  Thread& th = threads_[id];
  ++th.pc;
  if (pb.plan.length > 0)
    appendChainBlock(th, std::move(pb));
  else
    chain_.blocks.back().zeroChecks.push_back({th.stmt, pb.check, std::move(pb.limits)});
  snapshotChain(th);
  if (chain_.blocks.size() >= static_cast<size_t>(std::max(1, m_.lookaheadBlocks))) {
    finalizeChain(id);
    return true;
  }
  return false;
}

bool Simulator::beginChain(size_t id, PathBlock pb) {
  // the first block of a G64 chain: read ahead before anything moves
  Thread& th = threads_[id];
  ++th.pc;
  chain_ = Chain{};
  chain_.collecting = true;
  for (int a = 0; a < nAxes_; ++a)
    chain_.pred[a] = axes_[static_cast<size_t>(a)].target;
  appendChainBlock(th, std::move(pb));
  snapshotChain(th);
  if (m_.lookaheadBlocks <= 1) {
    finalizeChain(id);
    return true;
  }
  return false;
}

double Simulator::curTarget(int ax) const {
  return chain_.collecting ? chain_.pred[ax] : axes_[static_cast<size_t>(ax)].target;
}

void Simulator::checkNotMoving(int ax) const {
  const AxisMotion& a = axes_[static_cast<size_t>(ax)];
  if (a.moving(now_))
    emergency(fmt::format("axis {} programmed while moving (it moves to {} until t={} s)",
                          m_.axes[static_cast<size_t>(ax)].letter, num(a.target), num(a.tEnd)));
}

void Simulator::checkLimit(int ax, double lo, double hi) const {
  const machine::Axis& A = m_.axes[static_cast<size_t>(ax)];
  const bool below = lo < A.limitMinus - kLimitTolerance;
  if (below || hi > A.limitPlus + kLimitTolerance) {
    // shortest round-trip form: a target just past the limit must not print as the limit
    emergency(fmt::format("soft limit: axis {} would reach {}, outside [{}, {}]", A.letter, below ? lo : hi,
                          A.limitMinus, A.limitPlus));
  }
}

void Simulator::checkAxes(uint32_t mask, const std::vector<PathBlock::Limit>& limits) const {
  for (int a = 0; a < nAxes_; ++a)
    if ((mask >> a) & 1u) checkNotMoving(a);
  for (const auto& l : limits)
    checkLimit(l.axis, l.lo, l.hi);
}

void Simulator::startAxis(int ax, const AxisMotion& seg, uint8_t motion, uint8_t plane) {
  axes_[static_cast<size_t>(ax)] = seg;
  if (events_) {
    Event e;
    e.kind = EventKind::MoveStart;
    e.axis = m_.axes[static_cast<size_t>(ax)].letter;
    e.target = seg.target;
    e.motion = motion;
    e.plane = plane;
    emit(e);
    moveEnds_.push_back({seg.tEnd, moveOrder_++, ax, seg.target});
  }
}

// ============================================================================================
// G64 chains (SPEC §5.2): read ahead, plan, then run block by block

void Simulator::appendChainBlock(const Thread& th, PathBlock pb) {
  pb.stmt = th.stmt;
  if (prof_) stackProcs(th, pb.procs);
  for (const auto& s : pb.segs)
    chain_.pred[s.axis] = s.seg.target;
  chain_.blocks.push_back(std::move(pb));
}

void Simulator::snapshotChain(const Thread& th) {
  ChainSnapshot& s = chain_.snap;
  s.pc = th.pc;
  s.stack = th.stack;
  s.frames = th.frames;
  s.modal = th.modal;
  s.stmt = th.stmt;
  s.undo = ms_.markR();
  s.steps = steps_;
  s.after = chain_.blocks.back().after.size();
  s.profUndo = rec_.mark();
}

void Simulator::rollbackChain(size_t id) {
  Thread& th = threads_[id];
  const ChainSnapshot& s = chain_.snap;
  th.pc = s.pc;
  th.stack = s.stack;
  th.frames = s.frames;
  th.modal = s.modal;
  th.stmt = s.stmt;
  ms_.rollbackR(s.undo);
  steps_ = s.steps;
  chain_.blocks.back().after.resize(s.after);
  rec_.rollback(s.profUndo);
  finalizeChain(id);
}

void Simulator::finalizeChain(size_t id) {
  chain_.collecting = false;
  ms_.commitR();
  rec_.commit();
  auto& blocks = chain_.blocks;
  if (blocks.size() == 1) {
    // one block alone runs exactly as in G60 (from rest to rest)
    chain_.planned.assign(1, PlannedBlock{});
    chain_.planned[0].profile = makeTrapezoid(blocks[0].plan.length, blocks[0].plan.vmax, blocks[0].plan.accel);
  } else {
    std::vector<PlanBlock> plan;
    plan.reserve(blocks.size());
    for (auto& b : blocks)
      plan.push_back(std::move(b.plan)); // not needed after planning
    chain_.planned = planChain(plan, amax_, m_.cornerDeviationMm);
  }
  chain_.cur = 0;
  chain_.active = true;
  startChainBlock(id);
}

void Simulator::startChainBlock(size_t id) {
  Thread& th = threads_[id];
  PathBlock& b = chain_.blocks[chain_.cur];
  const PlannedBlock& planned = chain_.planned[chain_.cur];
  const Trapezoid& prof = planned.profile;
  const double tEnd = now_ + prof.duration();
  th.stmt = b.stmt;
  for (auto& s : b.segs) {
    s.seg.t0 = now_;
    s.seg.prof = prof;
    s.seg.tEnd = tEnd;
    startAxis(s.axis, s.seg, 1, th.modal.plane); // chains hold feed moves only (lines or arcs)
  }
  if (prof_) {
    const bool corner = planned.entryBound == JunctionBound::Corner || planned.exitBound == JunctionBound::Corner;
    rec_.bound(b.stmt, pathBoundLabel(b, prof, corner));
  }
  // (a block too short to take time at this instant is over at once: the thread stays runnable
  // and its next run is the junction)
  if (waitUntil(th, tEnd, TimeCat::Accel, -1, &axes_[static_cast<size_t>(b.segs.front().axis)]) && prof_)
    rec_.setProcs(b.procs); // the call stack when the block was read, not after reading ahead
}

bool Simulator::chainJunction(size_t id) {
  // The path has reached the end of block `cur`: the statements read ahead after it run now
  // (their line events carry this instant), then the next block starts (its checks first).
  {
    const PathBlock& b = chain_.blocks[chain_.cur];
    if (events_)
      for (uint32_t pc : b.after)
        emitLine(prog_.code[pc]);
    for (const auto& z : b.zeroChecks) {
      threads_[id].stmt = z.stmt;
      checkAxes(z.mask, z.limits);
    }
  }
  ++chain_.cur;
  if (chain_.cur < chain_.blocks.size()) {
    threads_[id].stmt = chain_.blocks[chain_.cur].stmt;
    checkBlock(chain_.blocks[chain_.cur]);
    startChainBlock(id);
    return true;
  }
  chain_.active = false;
  chain_.blocks.clear();
  return false;
}

// ============================================================================================
// WHEN anticipations

void Simulator::arm(size_t id, double windowEnd) {
  Thread& th = threads_[id];
  Armed a;
  a.when = th.pending.back();
  a.chain.assign(th.pending.begin(), th.pending.end() - 1);
  th.pending.clear();
  a.windowEnd = windowEnd;
  a.modal = th.modal;
  if (th.body) {
    a.group = th.group;
  } else {
    a.group = newGroup();
    th.join = a.group;
  }
  ++groups_[static_cast<size_t>(a.group)].armed;
  a.readsIw = prog_.readsIw(prog_.code[a.when].a);
  if (events_) {
    Event e;
    e.kind = EventKind::When;
    e.action = "armed";
    fileLineOf(a.when, e.file, e.line);
    emit(e);
  }
  armed_.push_back(std::move(a));
}

bool Simulator::evalCond(uint32_t pc, double t, int* classes, size_t* nClasses) const {
  // The verifier bounds every stack, conditions included, by the same constant.
  double st[image::kMaxStackDepth];
  size_t sp = 0;
  size_t nc = 0;
  const Ins* code = prog_.code.data();
  auto push = [&](double v) {
    assert(sp < image::kMaxStackDepth);
    st[sp++] = v;
  };
  auto pop = [&]() -> double {
    assert(sp > 0);
    return st[--sp];
  };
  auto onCmp = [&](double a, double b) {
    if (classes && nc < kMaxRecordedCmp) classes[nc] = cmpClass(a, b);
    ++nc;
  };
  for (;; ++pc) {
    const Ins& in = code[pc];
    countWork(1);
    if (valueOp(in, push, pop, onCmp)) continue;
    switch (in.op) {
    case Op::LoadAxVar: push(axVar(in.a8, in.b8, t)); break;
    case Op::CondEnd:
      if (nClasses) *nClasses = std::min(nc, kMaxRecordedCmp);
      return pop() != 0;
    default: internal("a WHEN condition holds an instruction that is not an expression (malformed image)");
    }
  }
}

bool Simulator::checkWhensAt() {
  bool changed = false;
  for (size_t i = 0; i < armed_.size();) {
    const uint32_t cond = prog_.code[armed_[i].when].a;
    if (evalCond(cond, now_, nullptr, nullptr)) {
      fire(i);
      changed = true;
      continue;
    }
    if (armed_[i].windowEnd <= now_) {
      drop(i);
      changed = true;
      continue;
    }
    ++i;
  }
  return changed;
}

void Simulator::fire(size_t i) {
  Armed a = std::move(armed_[i]);
  armed_.erase(armed_.begin() + static_cast<std::ptrdiff_t>(i));
  Group& g = groups_[static_cast<size_t>(a.group)];
  --g.armed;
  ++g.live;
  ++bodySerial_;
  if (events_) {
    Event e;
    e.kind = EventKind::When;
    e.action = "fired";
    e.thread = bodySerial_;
    fileLineOf(a.when, e.file, e.line);
    emit(e);
  }
  size_t id = spawn();
  Thread& th = threads_[id];
  th.serial = bodySerial_;
  th.when = a.when;
  th.pc = prog_.code[a.when].b;
  th.modal = a.modal;
  th.group = a.group;
  th.body = true;
  th.pending = std::move(a.chain);
  th.stmt = a.when;
  th.state = TState::Runnable;
}

void Simulator::drop(size_t i) {
  Armed a = std::move(armed_[i]);
  armed_.erase(armed_.begin() + static_cast<std::ptrdiff_t>(i));
  --groups_[static_cast<size_t>(a.group)].armed;
  if (events_) {
    Event e;
    e.kind = EventKind::When;
    e.action = "dropped";
    fileLineOf(a.when, e.file, e.line);
    emit(e);
  }
  groupCheck(a.group);
}

Simulator::Found Simulator::searchWhens(double a, double b) {
  Found best;
  for (size_t i = 0; i < armed_.size(); ++i) {
    if (!armed_[i].readsIw) continue; // nothing it reads changes between events
    const double end = std::min(b, armed_[i].windowEnd);
    if (!(end > a)) continue;
    Found f = searchOne(i, a, best.found ? std::min(end, std::nextafter(best.t, kInf)) : end);
    if (f.found && (!best.found || f.t < best.t)) best = std::move(f);
  }
  return best;
}

Simulator::Found Simulator::searchOne(size_t i, double a, double b) {
  // Watches the condition over the open interval (a, b), where only axis positions change.
  struct Condition final : WhenCondition {
    Condition(const Simulator& sim, uint32_t pc) : sim_(sim), pc_(pc) {}
    bool holds(double t, int* classes, size_t* n) const override { return sim_.evalCond(pc_, t, classes, n); }
    const Simulator& sim_;
    uint32_t pc_;
  };
  const WhenHit hit = searchCondition(Condition(*this, prog_.code[armed_[i].when].a), a, b, axes_, m_.ipoCycleS);
  Found out;
  out.index = i;
  out.found = hit.found;
  out.t = hit.t;
  out.error = hit.error;
  out.fault = hit.fault;
  return out;
}

// ============================================================================================
// --profile: every instant of the main program goes to one statement and one category

void Simulator::profBegin(const Thread& th, TimeCat cat, int64_t m, const AxisMotion* mot) {
  stackProcs(th, rec_.begin(th.stmt, cat, m, now_, mot));
}

void Simulator::stackProcs(const Thread& th, std::vector<uint32_t>& out) const {
  out.clear();
  auto addProc = [&](uint32_t pc) {
    if (pc >= prog_.code.size()) return;
    const uint32_t p = prog_.procOf(pc);
    if (std::find(out.begin(), out.end(), p) == out.end()) out.push_back(p);
  };
  addProc(th.stmt != kNoIndex ? th.stmt : th.pc);
  for (const Frame& f : th.frames)
    if (f.ret > 0) addProc(f.ret - 1);
}

std::string Simulator::pathBoundLabel(const PathBlock& pb, const Trapezoid& prof, bool corner) const {
  auto letter = [&](int ax) { return ax >= 0 ? m_.axes[static_cast<size_t>(ax)].letter : '?'; };
  return boundLabel(prof, pb.vBound, letter(pb.vAxis), letter(pb.aAxis), corner);
}

} // namespace

// ============================================================================================
// public API

std::vector<std::string> entryNames(const image::Image& img) {
  std::vector<std::string> out;
  for (const auto& e : img.entries)
    if (e.name < img.strings.size()) out.push_back(image::printableName(img.strings[e.name]));
  return out;
}

namespace {
bool equalsNoCase(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i) {
    auto x = static_cast<unsigned char>(a[i]), y = static_cast<unsigned char>(b[i]);
    if (std::tolower(x) != std::tolower(y)) return false;
  }
  return true;
}
} // namespace

SimResult simulate(const image::Image& img, const machine::Machine& m, const SimOptions& opts, TraceSink* sink) {
  image::ImageError err;
  image::Image copy = img;
  auto verified = image::verifyImage(std::move(copy), err);
  if (!verified) {
    SimResult res;
    res.setupError = SetupError::InvalidImage;
    res.setupMessage = fmt::format("invalid image: {}", err.message);
    return res;
  }
  return simulate(*verified, m, opts, sink);
}

SimResult simulate(const image::VerifiedImage& verified, const machine::Machine& m, const SimOptions& opts,
                   TraceSink* sink) {
  SimResult res;
  const image::Image& img = verified.image();
  const Program prog = buildProgram(verified);
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
  if (m.axes.empty() || m.axes.size() > static_cast<size_t>(kMaxAxes)) {
    res.setupError = SetupError::InvalidImage;
    res.setupMessage = "the machine must have 1 to 9 axes";
    return res;
  }
  // entry point: main by default; else a SEMI name, then a file stem (case-insensitive)
  const image::EntryPoint* entry = nullptr;
  if (opts.entry.empty()) {
    for (const auto& e : img.entries)
      if (e.kind == image::UnitKind::Main) {
        entry = &e;
        break;
      }
    if (!entry) entry = &img.entries.front();
  } else {
    // a name matches as stored, or as listed (escaped: "Caff\xE8 manuale" for a Latin-1 byte)
    auto matches = [&](const std::string& name) {
      return equalsNoCase(name, opts.entry) || equalsNoCase(image::printableName(name), opts.entry);
    };
    for (const auto& e : img.entries)
      if (matches(img.strings[e.name])) {
        entry = &e;
        break;
      }
    if (!entry)
      for (const auto& e : img.entries)
        if (matches(img.strings[img.procs[e.proc].name])) {
          entry = &e;
          break;
        }
    if (!entry) {
      std::string names;
      for (const auto& n : entryNames(img))
        names += (names.empty() ? "\"" : ", \"") + n + "\"";
      res.setupError = SetupError::UnknownEntry;
      res.setupMessage = fmt::format("no program called \"{}\" in the image; entries: {}", opts.entry, names);
      return res;
    }
  }
  Simulator sim(img, prog, m, opts, sink, std::move(axisMap));
  res.summary = sim.run(entry->proc);
  return res;
}

} // namespace iso::sim
