//! @file Simulator.h
//! @brief The Simulator of isosim: one run of a verified image on a machine, its state and
//!        members. Internal to lib/sim: nothing outside includes it (the public door is Run.h).
//!
//! Why one class in five files: the scheduler, the interpreter, the move starter and the WHEN
//! machinery act on the same run state in the same instant (the clock, the axes, the threads,
//! the armed WHENs) and call into each other on the hot path, so they are members of one class
//! that shares that state instead of handing it around; the files split it by the state each
//! part changes, and the state is declared here, once. Simulator.cpp owns time and the run:
//! setup, entry selection, the scheduler (now_, samples and rows, the pending move ends, input
//! steps, PLC ends), threads and their groups (threads_, groups_), the status and the summary.
//! Interpreter.cpp owns what an instruction does to a thread: its stack, frames and modal
//! state, R and I/O (ms_), the z32 machine functions (zs_). MoveStart.cpp owns the axes: it
//! starts moves on axes_ and runs the G64 chain (chain_: read ahead, roll back, junctions).
//! WhenArm.cpp owns the anticipations: arming, checking, firing and dropping (armed_).
#pragma once

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
#include "lang/MFunctions.h"
#include "sim/Debug.h"
#include "sim/G64Chain.h"
#include "sim/InstructionStream.h"
#include "sim/MachineState.h"
#include "sim/Motion.h"
#include "sim/MovePlanner.h"
#include "sim/PathPlanner.h"
#include "sim/ProfileRecorder.h"
#include "sim/Run.h"
#include "sim/RunMath.h"
#include "sim/Thread.h"
#include "sim/TimeProfile.h"
#include "sim/TraceWriter.h"
#include "sim/WhenWatch.h"
#include "sim/Z32State.h"

namespace iso::sim {

using image::Op;
using image::SysVarId;

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
inline constexpr int kMaxAxes = lang::kMaxImageAxes;
inline constexpr uint64_t kNoProgressLimit = 10'000'000; ///< instructions a thread may run without a statement
/// Instructions a run may execute (statements, WHEN conditions) per statement of --max-steps:
/// every instruction counts, so no program runs longer than the step limit allows.
inline constexpr uint64_t kInstructionsPerStep = 16;
/// A G64 chain reads ahead at most this many statements per block of `lookahead_blocks` (§5.2):
/// statements that do not move (R assignments, jumps) count too, so read-ahead memory is bounded.
inline constexpr uint64_t kReadAheadPerBlock = 16;

/// Instructions that touch the machine or wait: reading ahead in a G64 chain stops before them.
inline bool endsChain(image::Op op) {
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
  case Op::BodyEnd:
  case Op::AxisCtl: return true;
  default: return false;
  }
}

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

class Simulator {
public:
  Simulator(const image::Image& img, const InstructionStream& prog, const machine::Machine& m, const SimOptions& opts,
            TraceSink* sink, std::vector<int> axisMap)
      : img_(img), prog_(prog), m_(m), opts_(opts), sink_(sink), axisMap_(std::move(axisMap)) {
    nAxes_ = static_cast<int>(m.axes.size());
    samples_ = sink && sink->wantsSamples() && opts.dt > 0;
    events_ = sink && sink->wantsEvents();
    velocities_ = samples_ && sink->wantsVelocities();
    prof_ = opts.profile;
    debug_ = opts.debug;
    z32_ = img.z32();
    if (opts.search) { // block search: no events until the found line (Search.cpp)
      searching_ = true;
      searchEvents_ = events_;
      events_ = false;
    }
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
  /// Advances the time to t, writing the samples due; false when --max-rows stopped it first
  /// (the time is then that of the row not written).
  [[nodiscard]] bool advanceTo(double t);
  /// The runtime error of a run that needs more than --max-rows rows.
  void stopForRows();
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
    case Op::PushD9: push(in.value()); return true;
    case Op::LoadR: push(ms_.r(in.a)); return true;
    case Op::LoadRInd: push(ms_.r(static_cast<size_t>(intIndex(pop(), 1, lang::kMaxRIndex, "R")))); return true;
    case Op::LoadIo: push(ms_.ioRead(in.a8, pop())); return true;
    case Op::LoadPar: push(ms_.par(static_cast<size_t>(intIndex(pop(), 0, image::kParCount - 1, "PAR")))); return true;
    case Op::LoadPal: push(ms_.pal(static_cast<size_t>(intIndex(pop(), 0, image::kPalCount - 1, "PAL")))); return true;
    case Op::LoadUser: push(ms_.user(in.a)); return true;
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
  /// Starts axis ax on the geometry of `geom` with `prof` from now to tEnd, and notes where
  /// the move ends.
  void startSegment(int ax, const AxisMotion& geom, const Trapezoid& prof, double tEnd, bool blocking, const Modal& md,
                    MoveEnd& end);
  void startIndependent(const Thread& th, const MovePlan& plan, const MoveWords& w, MoveEnd& end);
  void startPathBlock(const Thread& th, const PathBlock& pb, const MoveWords& w, MoveEnd& end);
  bool readAheadBlock(size_t id, PathBlock pb);
  bool beginChain(size_t id, PathBlock pb);
  double curTarget(int ax) const;
  void checkNotMoving(int ax) const;
  void checkLimit(int ax, double lo, double hi) const;
  void checkBlock(const PathBlock& pb) const { checkAxes(pb.check, pb.limits); }
  void checkAxes(uint32_t mask, const PathBlock::LimitList& limits) const;
  void stackProcs(const Thread& th, std::vector<uint32_t>& out) const;
  /// Axis ax runs the geometry and target of `geom` with `prof` from now to tEnd.
  void startAxis(int ax, const AxisMotion& geom, const Trapezoid& prof, double tEnd, uint8_t motion, uint8_t plane);

  // ---- crash zones (MoveStart.cpp): each zone's next entry, recomputed when its axes restart
  void updateZones();
  void planZone(size_t z);
  /// The zone entries due at t (<= t): an emergency (forbidden) or a warning and an event.
  void enterZonesAt(double t);
  std::vector<double> zoneDue_;     ///< by zone: the time of its next entry (kInf: none)
  std::vector<uint8_t> zoneIn_;     ///< by zone: the tool is in it and its entry was reported
  std::vector<uint8_t> zoneWarned_; ///< by zone: its summary warning was given
  std::vector<uint32_t> zoneMask_;  ///< by zone: the machine axes it bounds
  std::vector<uint32_t> axisStmt_;  ///< by machine axis: the statement of its current segment
  uint32_t zoneDirty_ = ~0u;        ///< machine axes restarted since the zones were planned
  uint32_t moveStmt_ = kNoIndex;    ///< the statement of the moves being started

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
  void checkNesting(const Thread& th, const std::string& what) const;
  void opCall(Thread& th, const Ins& in);
  bool opRet(Thread& th);
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
  /// An MA/MB/MC value, taken off the stack (it lies below the line's later operands).
  double takeAux(Thread& th, const Ins& in);
  // ---- z32 program flow, axes under control, origins, parameters (SPEC §4.7)
  static bool inSpecialM(const Thread& th);
  /// At a statement header, end.implicit or ret of a GO range whose end line has run: the
  /// range returns (true; the instruction does not run).
  static bool leaveRange(Thread& th);
  /// The statement header at th.pc is the end line of the range running in the top frame.
  static void noteRangeEnd(Thread& th);
  /// The range frames above the running subprogram's (or main program's) frame.
  static void popRanges(Thread& th);
  void opGoRange(Thread& th, const Ins& in);
  void opKg(Thread& th, const Ins& in);
  void opAxisCtl(Thread& th, const Ins& in);
  /// Faults when a move programs (machine axis mask `prog`) an axis that G29 released.
  void checkUnderControl(uint32_t prog) const;
  void opOrigin(Thread& th, const Ins& in);
  void opNm(Thread& th, const Ins& in);
  void opStoreZ32(Thread& th, const Ins& in);
  double nextTick(double t) const;
  double axVar(uint8_t sv, uint8_t imgAxis, double t) const;
  void ioWrite(uint8_t sv, double index, double value);
  void setInput(int index, int value);

  // ---- block search (Search.cpp, SPEC §4.8): the lines before the found one run in zero time
  /// An instruction in search mode; false when it runs as usual (the found line's statement,
  /// and everything search mode does not change).
  bool searchOp(Thread& th, const Ins& in);
  /// The statement `in` is the found line's.
  bool searchFound(const Ins& in) const;
  /// The run ended (or stopped) before the found line: why.
  std::string searchNotReached() const;
  /// A move in search mode: each programmed axis takes its target at once.
  bool searchMove(size_t id, const MoveWords& w, uint32_t n);
  void searchM(Thread& th, const Ins& in);
  /// Search mode ends: at the found line (`found`: the collected state is output), or because
  /// the run stopped before it.
  void endSearch(bool found);

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
  void emit(Event&& e) { emit(e); }
  void emitLine(uint32_t stmt);
  /// A `when` event: `action` of the WHEN at instruction `when` (thread 0: the one running).
  void emitWhen(uint32_t when, const char* action, uint32_t thread = 0);
  void flushMoveEnds(double t);
  void emitSample(double t);
  std::string locationOf(uint32_t ins) const;
  void fileLineOf(uint32_t ins, std::string_view& file, uint32_t& line) const;
  void warnOnce(const std::string& w) {
    if (warnSeen_.insert(w).second) warnings_.push_back(w);
  }

  const image::Image& img_;
  const InstructionStream& prog_;
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
  bool z32_ = false;                 ///< the image was compiled for dialect z32 (SPEC §4.6)
  Z32State zs_;                      ///< z32: spindle, coolants, tool
  int origin_ = 0;                   ///< z32: the selected origin (0: none)
  std::vector<double> originOffset_; ///< z32: its offset, by machine axis
  std::vector<uint32_t>
      releasedAt_; ///< z32: by machine axis, the G29 statement that released it (kNoIndex: under control)
  // ---- block search (Search.cpp)
  bool searching_ = false;         ///< the lines before the found one are running
  bool searchEvents_ = false;      ///< events_ after the search
  uint64_t searchToolChanges_ = 0; ///< the tool changes made while searching (not counted)
  /// The outputs (false) and markers (true) written while searching: their last values.
  std::map<std::pair<bool, int>, uint8_t> searchIo_;

  double now_ = 0;
  std::vector<AxisMotion> axes_;
  MachineState ms_; ///< R, I/O, markers, the input schedule, PLC sequences
  std::vector<Thread> threads_;
  std::vector<Group> groups_;
  std::vector<Armed> armed_;

  uint64_t nextSample_ = 0;
  double lastSampleT_ = -1;
  uint64_t rows_ = 0;        ///< sample rows written (--max-rows)
  bool rowLimitHit_ = false; ///< the run needed more rows than --max-rows
  std::vector<double> posBuf_, velBuf_;
  std::vector<PendingMoveEnd> moveEnds_;
  uint64_t moveOrder_ = 0;
  uint32_t curThread_ = 0;  ///< Event::thread of the thread running now (0 between threads)
  uint32_t bodySerial_ = 0; ///< WHEN bodies fired so far

  uint64_t steps_ = 0;        ///< statements run, read ahead included (--max-steps)
  uint64_t lines_ = 0;        ///< statements run outside search mode, read ahead included (lines_executed)
  uint64_t blocks_ = 0;       ///< statements charged with block_time_s: not those read ahead (the summary's blocks)
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
  std::set<uint32_t> feedCapped_; ///< statements whose feed an axis max_velocity capped
  /// The summary warning listing the lines of feedCapped_ ("" when there are none).
  std::string feedCappedWarning() const;

  std::vector<double> vmax_, amax_; ///< by machine axis (the planner's limits)

  G64Chain chain_;
  // ---- --profile
  void profBegin(const Thread& th, TimeCat cat, int64_t m, const AxisMotion* mot);
  std::string pathBoundLabel(const PathBlock& pb, const Trapezoid& prof, bool corner) const;

  TimeProfile* prof_ = nullptr;
  uint32_t firstProc_ = 0;
  ProfileRecorder rec_;

  // ---- the debugger (DebugView.cpp)
  class View;
  struct DebugAbort {}; ///< the hook ended the run
  /// Before a statement: the hook's call (false: it ends the run).
  bool debugStatement(size_t id, const Ins& in);
  /// The time stops the hook asks for up to t, before the scheduler advances to t.
  void debugTimeUpTo(double t);
  void debugFault(Status st);
  DebugHook* debug_ = nullptr;
  uint32_t debugThread_ = 0; ///< the DebugThread id of the thread running now (0: none)
  struct {
    uint32_t serial = kNoIndex;
    uint32_t pc = kNoIndex;
    uint64_t rollbacks = 0;
  } debugLast_;                 ///< the statement the hook saw last
  uint64_t debugRollbacks_ = 0; ///< G64 rollbacks so far
};

} // namespace iso::sim
