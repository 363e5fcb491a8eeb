//! @file Interpreter.cpp
//! @brief The interpreter switch of isosim, one line a case, and the cases (SPEC §4, §4.6).
#include "sim/Simulator.h"

#include <algorithm>
#include <cassert>
#include <cmath>

#include <fmt/format.h>

namespace iso::sim {

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
  for (;;) {
    Thread& th = *tp;
    const Ins in = prog_[th.pc]; // a copy: a handler may decode other windows
    countWork(1);
    if (++th.sinceStmt > kNoProgressLimit)
      fault(fmt::format("{} instructions without a statement: a loop that never reaches a statement (or skips "
                        "every one with --block-skip)",
                        kNoProgressLimit));
    if (chain_.collecting() && endsChain(in.op)) {
      rollbackChain(id);
      return;
    }
    if (searching_ && searchOp(th, in)) continue;
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
    case Op::Ret:
      if (opRet(th)) return;
      break;
    case Op::EndImplicit:
      if (leaveRange(th)) break;
      opEnd(th, in);
      return;
    case Op::End: opEnd(th, in); return;
    case Op::GoRange: opGoRange(th, in); break;
    case Op::Kg: opKg(th, in); break;
    case Op::AxisCtl: opAxisCtl(th, in); break;
    case Op::Origin: opOrigin(th, in); break;
    case Op::Nm: opNm(th, in); break;
    case Op::StorePar:
    case Op::StorePal:
    case Op::StoreUser: opStoreZ32(th, in); break;
    case Op::Sync:
      ++th.pc;
      waitUntil(th, nextTick(now_), TimeCat::Inputs);
      return;
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
      th.specialM = static_cast<int64_t>(in.value());
      ++th.pc;
      break;
    case Op::When:
      th.pending.push_back(th.pc);
      ++th.pc;
      break;
    case Op::CondEnd: internal("condition end reached outside a WHEN condition (malformed image)");
    case Op::BodyEnd: opBodyEnd(id); return;
    default: opValue(th, in); break; // values, and the modal G of lang/GCodes.def
    }
  }
}

void Simulator::opStoreR(Thread& th, const Ins& in) {
  ms_.setR(in.a, pop(th), chain_.collecting());
  ++th.pc;
}

void Simulator::opStoreRInd(Thread& th) {
  double v = pop(th);
  double i = pop(th);
  const auto ri = static_cast<size_t>(intIndex(i, 1, lang::kMaxRIndex, "R"));
  ms_.setR(ri, v, chain_.collecting());
  ++th.pc;
}

bool Simulator::opLoadAxVar(size_t id, const Ins& in) {
  Thread& th = threads_[id];
  if (chain_.collecting() &&
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
  if (leaveRange(th)) return false;                   // a GO range returns before the statement after its end line
  if (searching_ && searchFound(in)) endSearch(true); // the found line runs as usual
  if (in.op == Op::StmtSkip && opts_.blockSkip) {
    noteRangeEnd(th); // a skipped end line still ends its range
    th.pc = in.a;
    return false;
  }
  if (chain_.collecting()) {
    snapshotChain(th);
    const uint64_t cap = kReadAheadPerBlock * static_cast<uint64_t>(std::max(1, m_.lookaheadBlocks));
    if (!chain_.countReadAhead(cap)) {
      rollbackChain(id); // as at any chain end: this statement runs when the path has stopped
      return true;
    }
  }
  noteRangeEnd(th); // after the snapshot: a rollback runs the end line again
  th.stmt = th.pc;
  if (debug_ && !debugStatement(id, in)) throw DebugAbort{};
  // SPEC §6.3: the statement that would be number --max-steps stops the run (it does not run).
  if (++steps_ >= opts_.maxSteps)
    fault(
        fmt::format("the program reached {} statements, the limit of --max-steps; a runaway program?", opts_.maxSteps));
  th.sinceStmt = 0;
  ++th.pc;
  if (searching_) return false; // search mode: no block time, no line event, not in blocks or the profile
  ++lines_;                     // read ahead and WHEN bodies included (the summary's lines_executed)
  if (prof_) rec_.count(th.stmt, chain_.collecting());
  if (chain_.collecting()) {
    // read ahead: its line event comes when the path reaches this point; no block time
    if (events_) chain_.noteStatement(th.stmt);
    return false;
  }
  if (!z32_ || !inSpecialM(th)) ++blocks_; // the lines charged with block_time_s (SPEC §5.3, §4.7)
  if (events_) emitLine(th.stmt);
  return m_.blockTimeS > 0 && waitUntil(th, now_ + m_.blockTimeS, TimeCat::Block);
}

void Simulator::opCase(Thread& th, const Ins& in) {
  double v = pop(th);
  uint32_t next = in.c != kNoIndex ? in.c : th.pc + 1;
  const CaseArm* arms = prog_.arms(th.pc) + in.a;
  for (uint32_t k = 0; k < in.b; ++k)
    if (cmpEqual(v, arms[k].value)) {
      next = arms[k].target;
      break;
    }
  th.pc = next;
}

void Simulator::checkNesting(const Thread& th, const std::string& what) const {
  // a main program replaced by KG keeps a frame that is no nesting level
  const size_t levels = th.frames.size() - (!th.frames.empty() && th.frames[0].kind == FrameKind::MainReplaced);
  if (levels >= callLimit_)
    fault(fmt::format("{}call nesting deeper than {} levels ({})",
                      callLimit_ == static_cast<size_t>(lang::kMaxNestingZ32) ? "too many subroutines: " : "",
                      callLimit_, what));
}

void Simulator::opCall(Thread& th, const Ins& in) {
  checkNesting(th, "calling " + names_[img_.procs[in.a].name]);
  th.frames.push_back(
      {.ret = th.pc + 1, .saved = th.modal, .toolChange = th.specialM == 6, .special = th.specialM >= 0});
  th.specialM = -1;
  th.pc = prog_.procEntry[in.a];
  if (prof_ && !th.body) rec_.call(in.a, chain_.collecting());
}

bool Simulator::opRet(Thread& th) {
  if (leaveRange(th)) return false; // the range's end line was its last: the range returns first
  popRanges(th);                    // an M17/G26 inside a range leaves the range with its subprogram
  if (th.frames.empty()) fault(fmt::format("M{} outside a subprogram", lang::kMReturn));
  if (th.frames.back().kind == FrameKind::MainReplaced) {
    // KG replaced the main program: this return ends the program like M30
    Ins end;
    end.op = Op::End;
    opEnd(th, end);
    return true;
  }
  if (th.frames.back().toolChange) z32Report(zs_.changeTool(now_), th.stmt);
  th.modal = th.frames.back().saved;
  th.pc = th.frames.back().ret;
  th.frames.pop_back();
  return false;
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
  if (in.op == Op::EndImplicit) {
    // the last statement may be a subprogram's M17: the place is then the main program's end
    const bool here = th.stmt != kNoIndex && th.pc < prog_.size() && prog_.procOf(th.stmt) == prog_.procOf(th.pc);
    warnOnce(fmt::format("the main program ended without M30 ({})", locationOf(here ? th.stmt : th.pc)));
  }
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
  if (!(d >= 0) || !std::isfinite(d)) fault(fmt::format("G04 dwell time {} s is not a duration >= 0", valueText(d)));
  if (events_) emit({.kind = EventKind::Dwell, .duration = d});
  ++th.pc;
  return waitUntil(th, now_ + d, TimeCat::Dwell);
}

bool Simulator::opStop(Thread& th, const Ins& in) {
  if (in.op == Op::M1 && !m_.optionalStop) {
    ++th.pc;
    return false;
  }
  if (events_) emit({.kind = EventKind::Stop, .duration = m_.m0WaitS});
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
  if (image::gCodeOf(in.op)) {
    opModalG(th, in);
    return;
  }
  if (static_cast<uint8_t>(in.op) == kOpFallOff) internal("the code ran off the end of a procedure (malformed image)");
  internal(fmt::format("unknown opcode 0x{:02x}", static_cast<unsigned>(in.op)));
}

bool Simulator::doM(Thread& th, const Ins& in, bool blocking) {
  const auto mnum = static_cast<uint64_t>(in.value());
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
  if (events_) emit({.kind = EventKind::MStart, .m = mnum, .blocking = blocking});
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
    if (events_) emit({.kind = EventKind::MEnd, .m = mnum});
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
    if (!std::isfinite(v) || v < 0) fault(fmt::format("spindle speed S{} is not a speed >= 0 (rpm)", valueText(v)));
    z32Report(zs_.setSpeed(v, now_), th.stmt);
  } else if (in.a8 == static_cast<uint8_t>(image::ZAddr::T) || in.a8 == static_cast<uint8_t>(image::ZAddr::TA) ||
             in.a8 == static_cast<uint8_t>(image::ZAddr::TB)) {
    const char* word = image::zAddrName(in.a8);
    if (!std::isfinite(v) || v < 0 || v != std::floor(v) || v > lang::kMaxToolNumber)
      fault(fmt::format("tool number {}{} is not a whole number >= 0", word, valueText(v)));
    const auto tool = static_cast<int64_t>(v);
    if (in.a8 == static_cast<uint8_t>(image::ZAddr::T)) {
      zs_.setProgrammedTool(tool);
      return;
    }
    if (in.a8 == static_cast<uint8_t>(image::ZAddr::TA)) zs_.mountTool(tool); // TB: the next tool, reported only
    if (events_) emit({.kind = EventKind::Tool, .state = word, .tool = tool});
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
    e.state = "T"; // M6 mounts the programmed tool
    e.tool = zs_.tool().value_or(0);
    emit(e);
  }
}

double Simulator::takeAux(Thread& th, const Ins& in) {
  const size_t depth = in.b8;
  if (th.stack.size() <= depth) internal("value stack underflow in an aux function");
  const auto at = th.stack.end() - static_cast<std::ptrdiff_t>(depth) - 1;
  const double v = *at;
  th.stack.erase(at);
  if (!std::isfinite(v)) fault(fmt::format("{} value is not a finite number", image::auxWordName(in.a8)));
  ++th.pc;
  return v;
}

bool Simulator::doAux(Thread& th, const Ins& in) {
  const double v = takeAux(th, in);
  const char* word = image::auxWordName(in.a8);
  if (events_) emit({.kind = EventKind::Aux, .state = word, .programmed = v, .sent = lang::auxSent(v)});
  return m_.auxDurationS > 0 && waitUntil(th, now_ + m_.auxDurationS, TimeCat::Plc);
}

// ============================================================================================
// z32 program flow, axes under control, origins, parameters (SPEC §4.7)

bool Simulator::inSpecialM(const Thread& th) {
  return std::any_of(th.frames.begin(), th.frames.end(), [](const Frame& f) { return f.special; });
}

bool Simulator::leaveRange(Thread& th) {
  if (th.frames.empty() || th.frames.back().kind != FrameKind::Range || !th.frames.back().endRan) return false;
  th.pc = th.frames.back().ret;
  th.frames.pop_back();
  return true;
}

void Simulator::noteRangeEnd(Thread& th) {
  if (!th.frames.empty() && th.frames.back().kind == FrameKind::Range && th.pc == th.frames.back().rangeEnd)
    th.frames.back().endRan = true;
}

void Simulator::popRanges(Thread& th) {
  while (!th.frames.empty() && th.frames.back().kind == FrameKind::Range)
    th.frames.pop_back();
}

void Simulator::opGoRange(Thread& th, const Ins& in) {
  checkNesting(th, "a GO range");
  th.frames.push_back({.ret = th.pc + 1, .saved = th.modal, .kind = FrameKind::Range, .rangeEnd = in.b});
  th.pc = in.a;
}

void Simulator::opKg(Thread& th, const Ins& in) {
  popRanges(th); // a KG inside a range leaves the range
  // the replaced frame keeps its return and its SAVE state; the main program keeps a frame
  // whose return ends the program
  if (th.frames.empty()) th.frames.push_back({.ret = th.pc, .saved = th.modal, .kind = FrameKind::MainReplaced});
  th.pc = prog_.procEntry[in.a];
  if (prof_ && !th.body) rec_.call(in.a, chain_.collecting());
}

void Simulator::opAxisCtl(Thread& th, const Ins& in) {
  const uint32_t mask = image::axisCtlMask(in.a);
  const bool on = image::axisCtlOn(in.a);
  for (int ax = 0; ax < nAxes_; ++ax) {
    bool named = mask == 0;
    for (size_t k = 0; k < axisMap_.size() && !named; ++k)
      named = (mask & (1u << k)) != 0 && axisMap_[k] == ax;
    if (!named) continue;
    releasedAt_[static_cast<size_t>(ax)] = on ? kNoIndex : th.stmt;
    if (events_) emit({.kind = EventKind::AxisControl, .axis = m_.axes[static_cast<size_t>(ax)].letter, .on = on});
  }
  ++th.pc;
}

void Simulator::checkUnderControl(uint32_t prog) const {
  for (int ax = 0; ax < nAxes_; ++ax)
    if ((prog & (1u << ax)) != 0 && releasedAt_[static_cast<size_t>(ax)] != kNoIndex)
      fault(fmt::format("axis {} is not under control: released by G29 at {}", m_.axes[static_cast<size_t>(ax)].letter,
                        locationOf(releasedAt_[static_cast<size_t>(ax)])));
}

void Simulator::opOrigin(Thread& th, const Ins& in) {
  std::fill(originOffset_.begin(), originOffset_.end(), 0.0);
  if (in.a != 0) {
    const auto it = m_.origins.find(static_cast<int>(in.a));
    if (it == m_.origins.end()) fault(fmt::format("origin O{} is not in the origins of machine '{}'", in.a, m_.name));
    for (const auto& [letter, offset] : it->second)
      if (const int ax = m_.axisIndex(letter); ax >= 0) originOffset_[static_cast<size_t>(ax)] = offset;
  }
  origin_ = static_cast<int>(in.a);
  ++th.pc;
}

void Simulator::opNm(Thread& th, const Ins& in) {
  warnOnce(fmt::format("G{} not modelled: 0 s", in.a));
  ++th.pc;
}

void Simulator::opStoreZ32(Thread& th, const Ins& in) {
  const double v = pop(th);
  if (in.op == Op::StoreUser) {
    ms_.setUser(in.a, v, chain_.collecting());
  } else if (in.op == Op::StorePar) {
    ms_.setPar(static_cast<size_t>(intIndex(pop(th), 0, image::kParCount - 1, "PAR")), v, chain_.collecting());
  } else {
    const auto i = intIndex(pop(th), 0, image::kPalCount - 1, "PAL");
    ms_.setPal(static_cast<size_t>(i), v);
    if (events_) emit({.kind = EventKind::Pal, .index = static_cast<int>(i), .number = v});
  }
  ++th.pc;
}

} // namespace iso::sim
