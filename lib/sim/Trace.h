//! @file Trace.h
//! @brief What a simulation produces (SPEC §8): samples, events and the summary, handed to a
//!        TraceSink as they happen, in time order. The sim library never prints; sinks write.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace iso::machine {
struct Machine;
struct Zone;
} // namespace iso::machine

namespace iso::sim {

/// How a run ended.
enum class Status : uint8_t {
  Ok,        ///< M30 (or the end of the main program) reached and the machine idle
  Error,     ///< a runtime error (SPEC §6.4), a runaway bound (§6.3), or a program with errors
  Emergency, ///< soft limit, or an axis programmed while moving (SPEC §4.3)
};
const char* statusName(Status s); ///< "ok" | "error" | "emergency"

/// Where a block search (isosim --search) started the cycle: the searched text and the line
/// found for it in the entry program.
struct SearchInfo {
  std::string text; ///< as given
  std::string file; ///< as the line events name it
  uint32_t line = 0;
};

/// The summary of SPEC §8 (also the `summary` object of a JSON trace).
struct Summary {
  Status status = Status::Ok;
  double cycleTimeS = 0;                              ///< when the run ended or stopped
  std::vector<std::pair<char, double>> finalPosition; ///< machine axis order
  uint64_t blocks = 0;                                ///< statements charged with block_time_s
  uint64_t linesExecuted = 0;                         ///< statements run, read ahead and WHEN bodies included
  std::string message;                                ///< "" when ok; else file:line, time and reason
  std::vector<std::string> warnings;                  ///< sorted, each once
  // dialect z32 only (SPEC §4.6)
  bool z32 = false;            ///< the image was compiled for z32
  double spindleOnS = 0;       ///< time the spindle turned
  uint64_t toolChanges = 0;    ///< M6 that mounted a tool
  std::optional<int64_t> tool; ///< the mounted tool at the end
  int origin = 0;              ///< the selected origin at the end (0: none; SPEC §4.7)

  /// --search (both dialects): where the cycle started.
  std::optional<SearchInfo> search;
  /// The machine changes of this run only (isosim --set and the like), "KEY=VALUE" as applied.
  std::vector<std::string> overrides;
};

enum class EventKind : uint8_t {
  Line,        ///< a statement starts: file, line, N
  MoveStart,   ///< axis, target
  MoveEnd,     ///< axis, target
  MStart,      ///< m, blocking
  MEnd,        ///< m
  Output,      ///< index, value (every write)
  Marker,      ///< index, value (every write)
  Input,       ///< index, value (changes only)
  When,        ///< action armed|fired|dropped|ended (the body is done), file, line
  Dwell,       ///< duration
  Stop,        ///< M0: duration (m0_wait_s)
  Error,       ///< status, message
  End,         ///< the program ended (status ok); the cycle time is t
  Spindle,     ///< z32: spindle state, rpm
  Coolant,     ///< z32: c1, c2
  Tool,        ///< z32: tool (now mounted)
  Aux,         ///< z32: word, programmed, sent
  AxisControl, ///< z32: axis, on (G28 takes it under control, G29 releases it)
  Pal,         ///< z32: index, number (a PAL write)
  Zone,        ///< the tool entered a warn zone: zone, zonePosition, file, line (of the moving block)
};
const char* eventKindName(EventKind k); ///< "line", "move_start", ...

/// One event. Only the fields of its kind are meaningful; string views stay valid during the
/// sink call only.
struct Event {
  double t = 0;
  EventKind kind = EventKind::Line;
  std::string_view file{};     ///< Line, When
  uint32_t line = 0;           ///< Line, When (0: unknown, stripped image)
  bool hasN = false;           ///< Line: the line carries an N number
  double n = 0;                ///< Line: its value
  char axis = 0;               ///< MoveStart, MoveEnd
  double target = 0;           ///< MoveStart, MoveEnd
  uint64_t m = 0;              ///< MStart, MEnd
  bool blocking = true;        ///< MStart
  int index = 0;               ///< Output, Marker, Input
  int value = 0;               ///< Output, Marker, Input
  const char* action = "";     ///< When: "armed" | "fired" | "dropped" | "ended"
  double duration = 0;         ///< Dwell, Stop
  Status status = Status::Ok;  ///< Error
  std::string_view message{};  ///< Error
  const char* state = "";      ///< Spindle: "cw" | "ccw" | "stop" | "orient"; Aux: "MA" | "MB" | "MC"; Tool: the word
  double rpm = 0;              ///< Spindle
  bool c1 = false, c2 = false; ///< Coolant
  int64_t tool = 0;            ///< Tool (its word, T, TA or TB, in `state`)
  bool on = false;             ///< AxisControl
  double number = 0;           ///< Pal: the value written
  double programmed = 0;       ///< Aux
  int sent = 0;                ///< Aux
  const machine::Zone* zone = nullptr;  ///< Zone: the zone entered (its name, kind and axes)
  const double* zonePosition = nullptr; ///< Zone: the position on each of zone->axes, in their order
  /// The program thread that caused it: 0 the main program, n the n-th WHEN body fired (When
  /// fired/ended: the body's number). Events of the machine (move_end, m_end, input) carry 0.
  /// Not part of the JSON trace; used by the timeline (sim/Timeline.h).
  uint32_t thread = 0;
  uint8_t motion = 0; ///< MoveStart: the block's motion, 0..3 (G00..G03); not in the JSON trace
  uint8_t plane = 17; ///< MoveStart: the active plane, 17, 18 or 19; not in the JSON trace
};

/// Receives a run as it happens. Samples come in increasing time; events in non-decreasing
/// time. begin() is called once before anything else, end() once at the end.
class TraceSink {
public:
  virtual ~TraceSink() = default;
  /// The machine the run uses (axis columns in machine order).
  virtual void begin(const machine::Machine& m) = 0;
  /// Positions of every machine axis at time t (mm or degrees), machine order.
  virtual void sample(double t, const double* positions) = 0;
  /// Same, with the velocity of every axis (mm/s, signed); called instead of sample() when
  /// wantsVelocities() is true.
  virtual void sampleWithVelocity(double t, const double* positions, const double* velocities) {
    (void)velocities;
    sample(t, positions);
  }
  virtual void event(const Event& e) = 0;
  virtual void end(const Summary& s) = 0;
  /// A sink that wants no samples (or no events) lets the simulator skip producing them.
  virtual bool wantsSamples() const { return true; }
  virtual bool wantsEvents() const { return true; }
  virtual bool wantsVelocities() const { return false; }
};

} // namespace iso::sim
