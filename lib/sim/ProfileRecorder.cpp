//! @file ProfileRecorder.cpp
//! @brief The --profile journal of isosim (ProfileRecorder.h).
#include "sim/ProfileRecorder.h"

#include <algorithm>
#include <utility>

#include <fmt/format.h>

namespace iso::sim {

std::string boundLabel(const Trapezoid& prof, SpeedBound vb, char vAxis, char aAxis, bool corner) {
  const double ramp = prof.tAccelEnd + (prof.tEnd - prof.tCruiseEnd);
  const double cruise = prof.tCruiseEnd - prof.tAccelEnd;
  if (corner && (!prof.cruises() || ramp > cruise)) return "corner";
  if (!prof.cruises()) return fmt::format("short (accel {})", aAxis);
  if (ramp > cruise) return fmt::format("accel {}", aAxis);
  switch (vb) {
  case SpeedBound::Feed: return "feed";
  case SpeedBound::AxisVelocity: return fmt::format("velocity {}", vAxis);
  case SpeedBound::Centripetal: return "centripetal";
  case SpeedBound::None: break;
  }
  return "none";
}

void ProfileRecorder::start(size_t codeSize, size_t nProcs) {
  codeSize_ = codeSize;
  pcToAcc_.assign(codeSize, -1);
  procCalls_.assign(nProcs, 0);
  procTime_.assign(nProcs, TimeSplit{});
}

ProfileRecorder::LineAcc& ProfileRecorder::lineAcc(uint32_t stmt) {
  int32_t& k = pcToAcc_[stmt];
  if (k < 0) {
    k = static_cast<int32_t>(lineAcc_.size());
    lineAcc_.emplace_back();
    lineAcc_.back().stmt = stmt;
  }
  return lineAcc_[static_cast<size_t>(k)];
}

void ProfileRecorder::count(uint32_t stmt, bool journaled) {
  ++lineAcc(stmt).count;
  if (journaled) undo_.push_back(stmt);
}

void ProfileRecorder::call(uint32_t proc, bool journaled) {
  ++procCalls_[proc];
  if (journaled) undo_.push_back(kCallUndo | proc);
}

void ProfileRecorder::bound(uint32_t stmt, std::string label) {
  if (stmt == kNoIndex) return;
  auto& b = lineAcc(stmt).bounds;
  if (std::find(b.begin(), b.end(), label) == b.end()) b.push_back(std::move(label));
}

void ProfileRecorder::mStarted(uint64_t m, double duration) {
  MProfile& mp = mProf_[m];
  mp.m = m;
  ++mp.count;
  if (duration > 0) mp.running.add(duration);
}

void ProfileRecorder::rollback(size_t mark) {
  while (undo_.size() > mark) {
    const uint32_t u = undo_.back();
    undo_.pop_back();
    if (u & kCallUndo)
      --procCalls_[u & ~kCallUndo];
    else
      --lineAcc_[static_cast<size_t>(pcToAcc_[u])].count;
  }
}

std::vector<uint32_t>& ProfileRecorder::begin(uint32_t stmt, TimeCat cat, int64_t m, double t0, const AxisMotion* mot) {
  if (act_.open) end(t0);
  Activity& a = act_;
  a.open = true;
  a.stmt = stmt;
  a.cat = cat;
  a.m = m;
  a.t0 = t0;
  if (mot && mot->tEnd > t0) {
    a.p1 = phaseEnd1(*mot);
    a.p2 = phaseEnd2(*mot);
    a.mEnd = mot->tEnd;
  } else {
    a.p1 = a.p2 = a.mEnd = t0;
  }
  return a.procs;
}

void ProfileRecorder::end(double t1) {
  Activity& a = act_;
  a.open = false;
  if (!(t1 > a.t0)) return;
  // Pieces [t0, p1) accel, [p1, p2) cruise, [p2, mEnd) decel, [mEnd, t1) cat; each piece is the
  // difference of two consecutive cut points, so the pieces telescope to t1 - t0.
  const double c1 = std::clamp(a.p1, a.t0, t1);
  const double c2 = std::clamp(a.p2, c1, t1);
  const double c3 = std::clamp(a.mEnd, c2, t1);
  const std::pair<TimeCat, double> pieces[4] = {
      {TimeCat::Accel, c1 - a.t0}, {TimeCat::Cruise, c2 - c1}, {TimeCat::Decel, c3 - c2}, {a.cat, t1 - c3}};
  LineAcc* line = a.stmt != kNoIndex && a.stmt < codeSize_ ? &lineAcc(a.stmt) : nullptr;
  MProfile* mp = a.m >= 0 ? &mProf_[static_cast<uint64_t>(a.m)] : nullptr;
  for (const auto& [cat, dt] : pieces) {
    if (!(dt > 0)) continue;
    total_.add(cat, dt);
    if (line) line->time.add(cat, dt);
    if (mp) mp->time.add(cat, dt);
    for (uint32_t p : a.procs)
      procTime_[p].add(cat, dt);
  }
}

void ProfileRecorder::build(TimeProfile& out, const image::Image& img, const InstructionStream& prog,
                            const std::vector<std::string>& names, uint32_t first, double cycleTime) const {
  out = TimeProfile{};
  out.cycleTimeS = cycleTime;
  out.total = total_;
  // lines, merged by (file, line): a stripped image gives one row per file
  struct Key {
    uint32_t file;
    uint32_t line;
    bool operator<(const Key& o) const { return file < o.file || (file == o.file && line < o.line); }
  };
  std::map<Key, size_t> rows;
  for (const LineAcc& la : lineAcc_) {
    const Ins in = prog[la.stmt];
    Key k{img.procs[prog.procOf(la.stmt)].file, 0};
    if (in.c != kNoIndex) k = {img.lines[in.c].file, img.lines[in.c].line};
    auto [it, fresh] = rows.emplace(k, out.lines.size());
    if (fresh) {
      out.lines.emplace_back();
      out.lines.back().file = names[k.file];
      out.lines.back().line = k.line;
    }
    LineProfile& lp = out.lines[it->second];
    lp.count += la.count;
    for (size_t c = 0; c < kTimeCats; ++c)
      lp.time.parts[c].add(la.time.parts[c].value());
    for (const auto& b : la.bounds)
      if (std::find(lp.bounds.begin(), lp.bounds.end(), b) == lp.bounds.end()) lp.bounds.push_back(b);
  }
  std::vector<LineProfile> sorted;
  sorted.reserve(out.lines.size());
  for (const auto& [k, idx] : rows)
    sorted.push_back(std::move(out.lines[idx]));
  out.lines = std::move(sorted);
  // procedures: the one that ran first, then the subprograms called, by name
  std::vector<uint32_t> order;
  for (uint32_t p = 0; p < procCalls_.size(); ++p)
    if (p != first && procCalls_[p] > 0) order.push_back(p);
  std::sort(order.begin(), order.end(),
            [&](uint32_t a, uint32_t b) { return img.strings[img.procs[a].name] < img.strings[img.procs[b].name]; });
  order.insert(order.begin(), first);
  for (uint32_t p : order) {
    ProcProfile pp;
    pp.name = names[img.procs[p].name];
    pp.file = names[img.procs[p].file];
    pp.calls = p == first ? 1 : procCalls_[p];
    pp.time = procTime_[p];
    out.procs.push_back(std::move(pp));
  }
  for (const auto& [m, mp] : mProf_)
    out.ms.push_back(mp);
}

} // namespace iso::sim
