//! @file Timeline.cpp
//! @brief The trace-event JSON of `isosim --timeline`.
#include "sim/Timeline.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "machine/Machine.h"
#include "sim/TraceWriter.h"

namespace iso::sim {

namespace {
constexpr uint32_t kMainTid = 1, kIoTid = 2, kAxisTid = 10;

const char* motionName(uint8_t motion) {
  switch (motion) {
  case 0: return "G00";
  case 1: return "G01";
  case 2: return "G02";
  default: return "G03";
  }
}

/// "prog.mpf:12", "prog.mpf" when the line is unknown (stripped image).
std::string where(std::string_view file, uint32_t line) {
  return line ? fmt::format("{}:{}", file, line) : std::string(file);
}
} // namespace

int64_t micros(double t) {
  const double scaled = t * 1e6;
  if (!(std::fabs(scaled) < 9.0e15)) return scaled > 0 ? INT64_C(9'000'000'000'000'000) : 0;
  return std::llround(scaled);
}

TimelineSink::TimelineSink(const TimeProfile* profile, size_t maxEvents)
    : profile_(profile), max_(std::max<size_t>(maxEvents, 16)) {}

void TimelineSink::begin(const machine::Machine& m) {
  machine_ = m.name;
  axisLetters_.clear();
  for (const auto& a : m.axes)
    axisLetters_.push_back(a.letter);
  std::vector<std::string> names;
  for (const auto& a : m.axes)
    names.emplace_back(1, a.letter);
  counters_.emplace(std::move(names), 4096);
  prevPos_.assign(m.axes.size(), 0.0);
  vel_.assign(m.axes.size(), 0.0);
  havePrev_ = false;
  trackNames_[kMainTid] = "main program";
  trackNames_[kIoTid] = "I/O";
}

void TimelineSink::sample(double t, const double* positions) {
  for (size_t a = 0; a < prevPos_.size(); ++a)
    vel_[a] = havePrev_ && t > prevT_ ? (positions[a] - prevPos_[a]) / (t - prevT_) : 0.0;
  sampleWithVelocity(t, positions, vel_.data());
}

void TimelineSink::sampleWithVelocity(double t, const double* positions, const double* velocities) {
  if (!counters_ || ended_) return;
  counters_->addSample(t, positions, velocities);
  std::copy(positions, positions + prevPos_.size(), prevPos_.begin());
  prevT_ = t;
  havePrev_ = true;
}

std::string TimelineSink::counterEvents(size_t& count) const {
  std::string out;
  count = 0;
  if (!counters_) return out;
  const double t1 = summary_.cycleTimeS > 1e-9 ? summary_.cycleTimeS : 1;
  const auto& names = counters_->axisNames();
  for (size_t a = 0; a < names.size(); ++a) {
    if (!counters_->moves(a)) continue;
    for (const bool velocity : {false, true}) {
      int64_t lastTs = -1;
      for (const auto& [t, v] : counters_->series(a, velocity, t1, static_cast<double>(kCounterColumns))) {
        const int64_t ts = micros(t);
        if (ts == lastTs) continue; // one value per microsecond
        lastTs = ts;
        out += ",\n{\"name\":";
        appendJsonString(out, fmt::format("{} {}", names[a], velocity ? "velocity" : "position"));
        out += fmt::format(",\"cat\":\"counter\",\"ph\":\"C\",\"ts\":{},\"pid\":1,\"args\":{{", ts);
        appendJsonString(out, names[a]);
        out += ':';
        appendNumber(out, v);
        out += "}}";
        ++count;
      }
    }
  }
  return out;
}

uint32_t TimelineSink::track(const std::string& key, uint32_t base, const std::string& name) {
  auto it = tracks_.find(key);
  if (it != tracks_.end()) return it->second.tid;
  uint32_t& next = base == 100 ? nextWhenTid_ : nextMTid_;
  Track t{next++, name};
  trackNames_[t.tid] = name;
  tracks_.emplace(key, t);
  return t.tid;
}

uint32_t TimelineSink::fileIndex(std::string_view file) {
  for (size_t i = 0; i < files_.size(); ++i)
    if (files_[i] == file) return static_cast<uint32_t>(i);
  files_.emplace_back(file);
  return static_cast<uint32_t>(files_.size() - 1);
}

bool TimelineSink::push(Rec r) {
  if (recs_.size() >= max_) {
    ++dropped_;
    return false;
  }
  recs_.push_back(std::move(r));
  return true;
}

void TimelineSink::close(size_t& open, int64_t ts) {
  if (open != kNone && recs_[open].dur < 0) recs_[open].dur = std::max<int64_t>(0, ts - recs_[open].ts);
  open = kNone;
}

namespace {
/// What bounds a line: its motion bounds, else its longest wait that is not motion ("" = none).
std::string limitOf(const LineProfile& lp) {
  if (!lp.bounds.empty()) {
    std::string s;
    for (const auto& b : lp.bounds)
      s += fmt::format("{}{}", s.empty() ? "" : ", ", b);
    return s;
  }
  TimeCat best = TimeCat::Count;
  double bestT = 0;
  for (size_t c = static_cast<size_t>(TimeCat::Dwell); c < kTimeCats; ++c) {
    const double v = lp.time.part(static_cast<TimeCat>(c));
    if (v > bestT) {
      bestT = v;
      best = static_cast<TimeCat>(c);
    }
  }
  return best == TimeCat::Count ? "" : timeCatName(best);
}
} // namespace

std::string TimelineSink::lineArgs(const Event& e) const {
  std::string a = "\"file\":";
  appendJsonString(a, e.file);
  a += fmt::format(",\"line\":{}", e.line);
  if (e.hasN) {
    a += ",\"n\":";
    appendNumber(a, e.n);
  }
  return a;
}

void TimelineSink::event(const Event& e) {
  if (ended_) return;
  const int64_t ts = micros(e.t);
  switch (e.kind) {
  case EventKind::Line: {
    std::string name = e.hasN ? fmt::format("N{} {}", formatNumber(e.n), where(e.file, e.line)) : where(e.file, e.line);
    if (e.thread == 0) {
      close(mainOpen_, ts);
      if (mainDropped_) {
        ++mainDroppedLines_;
        break;
      }
      Rec r{RecKind::Slice, kMainTid, ts, -1, std::move(name), "line", lineArgs(e)};
      r.limit = true;
      r.file = fileIndex(e.file);
      r.line = e.line;
      if (push(std::move(r))) {
        mainOpen_ = recs_.size() - 1;
      } else {
        mainDropped_ = true;
        mainDroppedTs_ = ts;
        mainDroppedLines_ = 1;
      }
      break;
    }
    auto it = bodies_.find(e.thread);
    if (it == bodies_.end()) break;
    close(it->second.second, ts);
    const uint32_t tid = it->second.first != kNone ? recs_[it->second.first].track : 0;
    if (tid && push({RecKind::Slice, tid, ts, -1, std::move(name), "line", lineArgs(e)}))
      it->second.second = recs_.size() - 1;
    break;
  }
  case EventKind::When: {
    const std::string action = e.action;
    if (action == "fired") {
      const std::string w = where(e.file, e.line);
      const uint32_t tid = track(fmt::format("when {}", w), 100, fmt::format("WHEN {}", w));
      std::string args = "\"file\":";
      appendJsonString(args, e.file);
      args += fmt::format(",\"line\":{},\"body\":{}", e.line, e.thread);
      size_t open = kNone;
      if (push({RecKind::Slice, tid, ts, -1, fmt::format("WHEN {}", w), "when", std::move(args)}))
        open = recs_.size() - 1;
      bodies_[e.thread] = {open, kNone};
    } else if (action == "ended") {
      auto it = bodies_.find(e.thread);
      if (it == bodies_.end()) break;
      close(it->second.second, ts);
      close(it->second.first, ts);
      bodies_.erase(it);
    }
    break;
  }
  case EventKind::MStart: {
    const uint32_t tid = track(fmt::format("m {:020}", e.m), 1000, fmt::format("PLC M{}", e.m));
    close(mOpen_[e.m], ts);
    std::string args =
        fmt::format("\"m\":{},\"blocking\":{},\"thread\":{}", e.m, e.blocking ? "true" : "false", e.thread);
    if (push({RecKind::Slice, tid, ts, -1, e.blocking ? fmt::format("M{}", e.m) : fmt::format("M=NB({})", e.m), "m",
              std::move(args)}))
      mOpen_[e.m] = recs_.size() - 1;
    break;
  }
  case EventKind::MEnd: {
    auto it = mOpen_.find(e.m);
    if (it != mOpen_.end()) close(it->second, ts);
    break;
  }
  case EventKind::MoveStart: {
    auto ax = std::find(axisLetters_.begin(), axisLetters_.end(), e.axis);
    const auto tid = kAxisTid + static_cast<uint32_t>(ax - axisLetters_.begin());
    trackNames_[tid] = fmt::format("axis {}", e.axis);
    auto& open = moveOpen_.try_emplace(e.axis, kNone).first->second;
    close(open, ts);
    std::string args = "\"target\":";
    appendNumber(args, e.target);
    args += fmt::format(",\"motion\":\"{}\",\"thread\":{}", motionName(e.motion), e.thread);
    if (push({RecKind::Slice, tid, ts, -1, fmt::format("{} to {}", e.axis, formatNumber(e.target)), "move",
              std::move(args)}))
      open = recs_.size() - 1;
    break;
  }
  case EventKind::MoveEnd: {
    auto it = moveOpen_.find(e.axis);
    if (it != moveOpen_.end()) close(it->second, ts);
    break;
  }
  case EventKind::Input:
  case EventKind::Output:
  case EventKind::Marker: {
    const char* what = e.kind == EventKind::Input ? "input" : e.kind == EventKind::Output ? "output" : "marker";
    push({RecKind::Instant, kIoTid, ts, 0, fmt::format("{} {} = {}", what, e.index, e.value), what,
          fmt::format("\"index\":{},\"value\":{},\"thread\":{}", e.index, e.value, e.thread)});
    break;
  }
  case EventKind::Error: {
    std::string args = "\"status\":";
    appendJsonString(args, statusName(e.status));
    args += ",\"message\":";
    appendJsonString(args, e.message);
    push({RecKind::Instant, kMainTid, ts, 0, statusName(e.status), "error", std::move(args)});
    break;
  }
  default: break; // dwell, M0 and the end are inside the main track's slices
  }
}

void TimelineSink::end(const Summary& s) {
  summary_ = s;
  const int64_t te = micros(s.cycleTimeS);
  close(mainOpen_, te);
  for (auto& [thread, open] : bodies_) {
    close(open.second, te);
    close(open.first, te);
  }
  for (auto& [m, open] : mOpen_)
    close(open, te);
  for (auto& [axis, open] : moveOpen_)
    close(open, te);
  // Slices the run never closed (an emergency stops everything at once) end with it.
  for (Rec& r : recs_)
    if (r.kind == RecKind::Slice && r.dur < 0) r.dur = std::max<int64_t>(0, te - r.ts);
  ended_ = true;
}

std::string TimelineSink::capNote() const {
  if (dropped_ == 0) return "";
  return fmt::format("the timeline holds its first {} events; {} more were left out (the main track's last slice "
                     "covers {} lines not recorded)",
                     max_, dropped_, mainDroppedLines_);
}

std::string TimelineSink::render(const std::string& program) const {
  const int64_t te = micros(summary_.cycleTimeS);
  std::string out = "{\n\"displayTimeUnit\": \"ms\",\n\"otherData\": {\"format\": \"isosim-timeline\", "
                    "\"format_version\": 1, \"program\": ";
  appendJsonString(out, program);
  out += ", \"machine\": ";
  appendJsonString(out, machine_);
  out += fmt::format(", \"status\": \"{}\", \"cycle_time_s\": ", statusName(summary_.status));
  appendNumber(out, summary_.cycleTimeS);
  size_t counts = 0;
  const std::string counters = counterEvents(counts);
  out += fmt::format(", \"cycle_time_us\": {}, \"events\": {}, \"dropped\": {}, \"max_events\": {}, "
                     "\"counter_values\": {}, \"warnings\": [",
                     te, recs_.size() + (mainDropped_ ? 1 : 0), dropped_, max_, counts);
  if (const std::string note = capNote(); !note.empty()) appendJsonString(out, note);
  out += "]},\n\"traceEvents\": [\n";
  out += "{\"name\":\"process_name\",\"ph\":\"M\",\"pid\":1,\"tid\":0,\"args\":{\"name\":";
  appendJsonString(out, fmt::format("isosim {}", program));
  out += "}}";
  for (const auto& [tid, name] : trackNames_) {
    out += fmt::format(",\n{{\"name\":\"thread_name\",\"ph\":\"M\",\"pid\":1,\"tid\":{},\"args\":{{\"name\":", tid);
    appendJsonString(out, name);
    out += fmt::format("}}}},\n{{\"name\":\"thread_sort_index\",\"ph\":\"M\",\"pid\":1,\"tid\":{},\"args\":{{"
                       "\"sort_index\":{}}}}}",
                       tid, tid);
  }
  std::map<std::pair<std::string, uint32_t>, std::string> limits;
  if (profile_)
    for (const LineProfile& lp : profile_->lines)
      limits[{lp.file, lp.line}] = limitOf(lp);
  auto emitRec = [&](const Rec& r) {
    out += ",\n{\"name\":";
    appendJsonString(out, r.name);
    out += ",\"cat\":";
    appendJsonString(out, r.cat);
    if (r.kind == RecKind::Slice)
      out += fmt::format(",\"ph\":\"X\",\"ts\":{},\"dur\":{},\"pid\":1,\"tid\":{}", r.ts, r.dur, r.track);
    else
      out += fmt::format(",\"ph\":\"i\",\"s\":\"t\",\"ts\":{},\"pid\":1,\"tid\":{}", r.ts, r.track);
    out += ",\"args\":{";
    out += r.args;
    if (r.limit) {
      // what bounds the line, from the profile (complete only now); no key when nothing is known
      auto it = limits.find({files_[r.file], r.line});
      if (it != limits.end() && !it->second.empty()) {
        out += ",\"limit\":";
        appendJsonString(out, it->second);
      }
    }
    out += "}}";
  };
  for (const Rec& r : recs_)
    emitRec(r);
  if (mainDropped_) {
    Rec r{RecKind::Slice,
          kMainTid,
          mainDroppedTs_,
          std::max<int64_t>(0, te - mainDroppedTs_),
          fmt::format("{} more lines (not recorded)", mainDroppedLines_),
          "line",
          fmt::format("\"lines\":{}", mainDroppedLines_)};
    emitRec(r);
  }
  out += counters;
  out += "\n]\n}\n";
  return out;
}

} // namespace iso::sim
