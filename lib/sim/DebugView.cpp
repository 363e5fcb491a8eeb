//! @file DebugView.cpp
//! @brief The debugger's view of a run (Debug.h): the Simulator's state read at a stop, and
//!        the hook calls of the scheduler and the interpreter.
#include "sim/Debug.h"

#include "sim/Simulator.h"
#include "support/CaseFold.h"

namespace iso::sim {

const char* debugFrameKindName(DebugFrameKind k) {
  switch (k) {
  case DebugFrameKind::Main: return "main";
  case DebugFrameKind::Call: return "call";
  case DebugFrameKind::SpecialM: return "special M";
  case DebugFrameKind::Range: return "GO range";
  case DebugFrameKind::Replaced: return "KG";
  case DebugFrameKind::Body: return "WHEN body";
  }
  return "?";
}

namespace {
/// A whole number in [lo, hi] as an index, or -1.
int64_t wholeIndex(double v, int64_t lo, int64_t hi) {
  if (!(v >= static_cast<double>(lo) && v <= static_cast<double>(hi)) || v != std::floor(v)) return -1;
  return static_cast<int64_t>(v);
}
} // namespace

class Simulator::View final : public RunView {
public:
  View(const Simulator& s, double t) : s_(s), t_(t) {}

  double time() const override { return t_; }
  uint64_t blocks() const override { return s_.blocks_; }
  uint64_t statements() const override { return s_.steps_; }

  std::vector<DebugThread> threads() const override {
    std::vector<DebugThread> out;
    for (const Thread& th : s_.threads_) {
      if (th.state == TState::Done) continue;
      DebugThread d;
      d.id = th.serial + 1;
      d.name = th.body ? fmt::format("WHEN {}", s_.locationOf(th.when)) : std::string("main");
      out.push_back(std::move(d));
    }
    std::sort(out.begin(), out.end(), [](const DebugThread& a, const DebugThread& b) { return a.id < b.id; });
    return out;
  }

  std::vector<DebugFrame> stack(uint32_t id) const override {
    const Thread* th = find(id);
    if (!th) return {};
    std::vector<DebugFrame> out;
    // innermost: where the thread is now
    out.push_back(frameAt(th->stmt != kNoIndex ? th->stmt : th->pc));
    for (size_t k = th->frames.size(); k-- > 0;) {
      const Frame& f = th->frames[k];
      DebugFrame& callee = out.back();
      callee.kind = f.kind == FrameKind::Range          ? DebugFrameKind::Range
                    : f.kind == FrameKind::MainReplaced ? DebugFrameKind::Replaced
                    : f.special                         ? DebugFrameKind::SpecialM
                                                        : DebugFrameKind::Call;
      out.push_back(frameAt(f.ret > 0 ? f.ret - 1 : 0));
    }
    out.back().kind = th->body ? DebugFrameKind::Body : DebugFrameKind::Main;
    return out;
  }

  DebugModal modal(uint32_t id) const override {
    DebugModal d;
    if (const Thread* th = find(id)) {
      d.motion = th->modal.motion;
      d.incremental = th->modal.incremental;
      d.continuous = th->modal.continuous;
      d.plane = th->modal.plane;
      d.feed = th->modal.feed;
    }
    return d;
  }

  std::vector<std::pair<uint32_t, double>> rParameters() const override {
    std::vector<std::pair<uint32_t, double>> out;
    for (uint32_t i = 1; i <= lang::kMaxRIndex; ++i)
      if (s_.ms_.written(i)) out.emplace_back(i, s_.ms_.r(i));
    return out;
  }

  std::vector<DebugValue> z32Parameters() const override {
    std::vector<DebugValue> out;
    if (!s_.z32_) return out;
    for (size_t i = 0; i < image::kParCount; ++i)
      if (s_.ms_.par(i) != 0) out.push_back({fmt::format("PAR[{}]", i), formatNumber(s_.ms_.par(i))});
    for (size_t i = 0; i < image::kPalCount; ++i)
      if (s_.ms_.pal(i) != 0) out.push_back({fmt::format("PAL[{}]", i), formatNumber(s_.ms_.pal(i))});
    for (const std::string& name : s_.m_.parameters)
      out.push_back({name, formatNumber(userParameter(name).value_or(0))});
    return out;
  }

  std::vector<DebugAxis> axes() const override {
    std::vector<DebugAxis> out;
    for (size_t i = 0; i < s_.axes_.size(); ++i) {
      const AxisMotion& a = s_.axes_[i];
      DebugAxis d;
      d.letter = s_.m_.axes[i].letter;
      d.position = a.positionAt(t_);
      d.target = a.target;
      d.velocity = a.velocityAt(t_);
      d.moving = a.moving(t_);
      d.released = i < s_.releasedAt_.size() && s_.releasedAt_[i] != kNoIndex;
      out.push_back(d);
    }
    return out;
  }

  std::vector<DebugValue> machineFunctions() const override {
    std::vector<DebugValue> out;
    if (!s_.z32_) return out;
    const Z32State& z = s_.zs_;
    const char* dir = z.dir() == SpindleDir::Cw ? " (M3)" : z.dir() == SpindleDir::Ccw ? " (M4)" : nullptr;
    out.push_back({"spindle", dir ? fmt::format("{} rpm{}", formatNumber(z.rpm()), dir)
                                  : std::string(z.dir() == SpindleDir::Orient ? "oriented (M19)" : "stopped")});
    out.push_back({"tool", z.tool() ? fmt::format("T{}", *z.tool()) : std::string("none")});
    out.push_back({"coolant 1", z.coolant1() ? "on" : "off"});
    out.push_back({"coolant 2", z.coolant2() ? "on" : "off"});
    out.push_back({"origin", s_.origin_ ? fmt::format("{}", s_.origin_) : std::string("none")});
    return out;
  }

  std::vector<DebugValue> io() const override {
    std::vector<DebugValue> out;
    auto add = [&](lang::SysVar sv, int count) {
      const std::string_view name = lang::sysVarInfo(sv).name;
      for (int i = 0; i < count; ++i)
        if (s_.ms_.ioRead(static_cast<uint8_t>(sv), i) != 0) out.push_back({fmt::format("{}[{}]", name, i), "1"});
    };
    add(lang::SysVar::AaIn, s_.m_.numInputs);
    add(lang::SysVar::AaOut, s_.m_.numOutputs);
    add(lang::SysVar::AaMarker, static_cast<int>(lang::kMaxMarker) + 1);
    return out;
  }

  std::optional<double> r(double index) const override {
    const int64_t i = wholeIndex(index, 1, lang::kMaxRIndex);
    if (i < 0) return std::nullopt;
    return s_.ms_.r(static_cast<size_t>(i));
  }
  std::optional<double> par(double index) const override {
    const int64_t i = wholeIndex(index, 0, image::kParCount - 1);
    if (!s_.z32_ || i < 0) return std::nullopt;
    return s_.ms_.par(static_cast<size_t>(i));
  }
  std::optional<double> pal(double index) const override {
    const int64_t i = wholeIndex(index, 0, image::kPalCount - 1);
    if (!s_.z32_ || i < 0) return std::nullopt;
    return s_.ms_.pal(static_cast<size_t>(i));
  }
  std::optional<double> userParameter(std::string_view name) const override {
    if (!s_.z32_) return std::nullopt;
    bool known = false;
    for (const std::string& p : s_.m_.parameters)
      known = known || support::iequals(p, name);
    if (!known) return std::nullopt;
    for (size_t i = 0; i < s_.img_.strings.size(); ++i)
      if (support::iequals(s_.img_.strings[i], name)) return s_.ms_.user(static_cast<uint32_t>(i));
    return 0.0; // the program never names it
  }
  std::optional<double> axisVariable(lang::SysVar sv, char axis) const override {
    for (size_t i = 0; i < s_.m_.axes.size(); ++i) {
      if (s_.m_.axes[i].letter != axis) continue;
      const double offset = s_.z32_ ? s_.originOffset_[i] : 0.0;
      switch (sv) {
      case lang::SysVar::MaxVelo: return s_.m_.axes[i].maxVelocity;
      case lang::SysVar::PosLimitPlus: return s_.m_.axes[i].limitPlus;
      case lang::SysVar::PosLimitMinus: return s_.m_.axes[i].limitMinus;
      case lang::SysVar::AaIw: return s_.axes_[i].positionAt(t_) - offset;
      case lang::SysVar::AaFw: return s_.axes_[i].target - offset;
      default: return std::nullopt;
      }
    }
    return std::nullopt;
  }
  std::optional<double> ioVariable(lang::SysVar sv, double index) const override {
    int count = 0;
    switch (sv) {
    case lang::SysVar::AaIn: count = s_.m_.numInputs; break;
    case lang::SysVar::AaOut: count = s_.m_.numOutputs; break;
    case lang::SysVar::AaMarker: count = static_cast<int>(lang::kMaxMarker) + 1; break;
    default: return std::nullopt;
    }
    const int64_t i = wholeIndex(index, 0, count - 1);
    if (i < 0) return std::nullopt;
    return s_.ms_.ioRead(static_cast<uint8_t>(sv), static_cast<double>(i));
  }

  DebugFrame where(uint32_t lineEntry) const override {
    DebugFrame d;
    if (lineEntry >= s_.img_.lines.size()) {
      d.file.assign(1, '?');
      return d;
    }
    const image::LineEntry& le = s_.img_.lines[lineEntry];
    d.file = s_.names_[le.file];
    d.line = le.line;
    d.lineEntry = lineEntry;
    if (const image::Proc* p = s_.img_.procAt(le.offset)) d.proc = s_.names_[p->name];
    return d;
  }

private:
  const Thread* find(uint32_t id) const {
    for (const Thread& th : s_.threads_)
      if (th.state != TState::Done && th.serial + 1 == id) return &th;
    return nullptr;
  }
  /// The frame of the statement containing instruction `pc` (searching back for its header).
  DebugFrame frameAt(uint32_t pc) const {
    DebugFrame d;
    const InstructionStream& code = s_.prog_;
    if (code.empty()) return d;
    pc = std::min<uint32_t>(pc, static_cast<uint32_t>(code.size() - 1));
    const uint32_t proc = s_.prog_.procOf(pc);
    d.proc = s_.names_[s_.img_.procs[proc].name];
    const uint32_t entry = s_.prog_.procEntry[proc];
    for (uint32_t i = pc + 1; i-- > entry;) {
      const Ins in = code[i];
      if ((in.op == Op::Stmt || in.op == Op::StmtSkip) && in.c != kNoIndex) {
        DebugFrame w = where(in.c);
        w.proc = d.proc;
        return w;
      }
    }
    d.file = s_.names_[s_.img_.procs[proc].file];
    return d;
  }

  const Simulator& s_;
  double t_;
};

bool Simulator::debugStatement(size_t id, const Ins& in) {
  const Thread& th = threads_[id];
  // A statement that a G64 chain rolled back runs again: the debugger saw it already.
  if (debugLast_.serial == th.serial && debugLast_.pc == th.pc && debugLast_.rollbacks != debugRollbacks_) {
    debugLast_.rollbacks = debugRollbacks_;
    return true;
  }
  debugLast_ = {th.serial, th.pc, debugRollbacks_};
  const View v(*this, now_);
  return debug_->statement(v, th.serial + 1, in.c, th.frames.size());
}

void Simulator::debugTimeUpTo(double t) {
  for (int guard = 0; guard < 1000; ++guard) {
    const double at = debug_->nextTimeStop();
    if (!(at <= t)) return;
    const View v(*this, std::max(at, now_));
    if (!debug_->timeReached(v)) throw DebugAbort{};
    if (debug_->nextTimeStop() == at) return; // the hook keeps asking for the same time: once is enough
  }
}

void Simulator::debugFault(Status st) {
  const View v(*this, now_);
  debug_->fault(v, st, message_, debugThread_);
}

} // namespace iso::sim
