//! @file Timeline.h
//! @brief `isosim --timeline`: the run as Chrome/Perfetto trace-event JSON (the "JSON Object
//!        Format" that chrome://tracing and ui.perfetto.dev open), one track per program
//!        thread, PLC sequence and axis. Deterministic bytes; bounded size; never prints.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "sim/SvgPlot.h"
#include "sim/TimeProfile.h"
#include "sim/Trace.h"

namespace iso::sim {

/// A time of the simulator in whole microseconds, rounded exactly as every isosim output
/// rounds its seconds (sim/TraceWriter.h appendNumber): `micros(t)` µs is the printed `t` s.
int64_t micros(double t);

/// Collects a run's events (no samples) and renders them as a trace-event document
/// (schemas/isosim-timeline.schema.json):
/// - track "main program": one complete slice ("ph": "X") per line the main program executes,
///   from its `line` event to the next one (the last to the end of the run), so that the slices
///   tile [0, cycle time] and their durations add up to the cycle time exactly (integer µs);
///   args: file, line, n (when the line has an N number), limit (what bounds the line, from
///   the profile when one is given: the motion bounds, else its longest wait);
/// - one track per WHEN (file:line): a slice per body run, with the body's lines nested in it;
/// - one track per M number: a slice per sequence (start to end);
/// - one track per axis: a slice per move (start to arrival), with its target and G code;
/// - track "I/O": instant events for input changes, output and marker writes; the error of a
///   run that stops is an instant event on the main track;
/// - counter tracks ("ph": "C") "X position" and "X velocity" per axis that moves: the samples
///   decimated to kCounterColumns columns over the run, each column its minimum and maximum
///   (PlotRecorder), so at most about 2·kCounterColumns + 2 values per counter.
/// At most `maxEvents` events are kept: past that the others are counted (otherData.dropped)
/// and the main track ends with one slice that covers the lines not recorded, so that its
/// slices still add up to the cycle time; otherData.max_events gives the cap and
/// otherData.warnings says what was left out (capNote()).
class TimelineSink : public TraceSink {
public:
  /// `profile` (may be null) is read at render(): --profile's per-line bounds and waits.
  explicit TimelineSink(const TimeProfile* profile = nullptr, size_t maxEvents = 100'000);
  void begin(const machine::Machine& m) override;
  /// Without velocities (a caller that ignores wantsVelocities()): backward differences.
  void sample(double t, const double* positions) override;
  void sampleWithVelocity(double t, const double* positions, const double* velocities) override;
  void event(const Event& e) override;
  void end(const Summary& s) override;
  bool wantsVelocities() const override { return true; }

  /// The columns of the counter tracks over the run.
  static constexpr size_t kCounterColumns = 1000;

  /// The document; `program` names the run (e.g. the program file) in its metadata.
  std::string render(const std::string& program) const;

  size_t eventCount() const { return recs_.size(); }
  /// What the document leaves out, for its otherData.warnings and the summary's warnings: ""
  /// when every event is in it.
  std::string capNote() const;
  uint64_t dropped() const { return dropped_; }

private:
  enum class RecKind : uint8_t { Slice, Instant };
  struct Rec {
    RecKind kind = RecKind::Slice;
    uint32_t track = 0;
    int64_t ts = 0, dur = -1; ///< µs; dur -1 while the slice is open
    std::string name;
    std::string cat;
    std::string args;   ///< a JSON object's members, without braces ("" = none)
    bool limit = false; ///< a main-track line: its limit is looked up in the profile at render()
    uint32_t file = 0;  ///< ... its file (index in files_) and line
    uint32_t line = 0;
  };
  struct Track {
    uint32_t tid = 0;
    std::string name;
  };
  uint32_t track(const std::string& key, uint32_t base, const std::string& name);
  bool push(Rec r); ///< false (and counted) past the cap
  void close(size_t& open, int64_t ts);
  std::string lineArgs(const Event& e) const;
  uint32_t fileIndex(std::string_view file);
  /// The counter events, each after ",\n"; `count` is how many.
  std::string counterEvents(size_t& count) const;

  const TimeProfile* profile_;
  size_t max_;
  std::string machine_;
  std::vector<char> axisLetters_;
  std::vector<Rec> recs_;
  std::vector<std::string> files_;      ///< the files of main-track lines (a program set has few)
  std::map<std::string, Track> tracks_; ///< by key ("when prog.mpf:12", "m 23")
  std::map<uint32_t, std::string> trackNames_;
  uint32_t nextWhenTid_ = 100, nextMTid_ = 1000;
  static constexpr size_t kNone = static_cast<size_t>(-1);
  size_t mainOpen_ = kNone;
  std::map<uint32_t, std::pair<size_t, size_t>> bodies_; ///< thread -> (body slice, line slice)
  std::map<uint64_t, size_t> mOpen_;                     ///< M number -> open slice
  std::map<char, size_t> moveOpen_;                      ///< axis -> open slice
  uint64_t dropped_ = 0;
  bool mainDropped_ = false; ///< a main line was not recorded: the catch-all slice starts at mainDroppedTs_
  int64_t mainDroppedTs_ = 0;
  uint64_t mainDroppedLines_ = 0;
  Summary summary_;
  bool ended_ = false;
  std::optional<PlotRecorder> counters_; ///< the samples of the counter tracks
  std::vector<double> prevPos_, vel_;
  double prevT_ = 0;
  bool havePrev_ = false;
};

} // namespace iso::sim
