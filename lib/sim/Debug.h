//! @file Debug.h
//! @brief The debugger's door into a run (isosim --dap, --single-block): a hook the run calls
//!        before each statement, at the simulated times the hook asks for and when the run
//!        faults, and a read-only view of the run's state during those calls.
//!
//! The hook only looks: it never changes the run, so a run with stops is the same run as one
//! without (the same cycle time, events and errors). It may stop the run (`false`): the run
//! then ends with a runtime error saying so.
#pragma once

#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "lang/SysVars.h"
#include "sim/Trace.h"

namespace iso::sim {

/// What pushed a frame of the call chain.
enum class DebugFrameKind : uint8_t {
  Main,     ///< the main (or semi-automatic) program
  Call,     ///< a subprogram call (a call line, GOP)
  SpecialM, ///< z32: the subprogram of a special M
  Range,    ///< z32: a GO range
  Replaced, ///< z32: the program a KG replaced the main program with
  Body,     ///< a WHEN body's first frame
};
/// "main", "call", "special M", "GO range", "KG", "WHEN body".
const char* debugFrameKindName(DebugFrameKind k);

/// One frame of a thread's call chain: the procedure, and where it is now.
struct DebugFrame {
  std::string proc; ///< the procedure's name (a subprogram's, or the program's file stem)
  std::string file; ///< as the image records it ("?" for a stripped image)
  uint32_t line = 0;
  uint32_t lineEntry = UINT32_MAX; ///< index into Image::lines (UINT32_MAX: none)
  DebugFrameKind kind = DebugFrameKind::Main;
};

/// A thread of the run: the main program (id 1) or a WHEN body (its id is 1 + its number).
struct DebugThread {
  uint32_t id = 1;
  std::string name; ///< "main" or "WHEN file:line"
};

/// An axis of the machine, at the view's time.
struct DebugAxis {
  char letter = 'X';
  double position = 0; ///< machine coordinates
  double target = 0;   ///< the end of the current move (at rest: the position)
  double velocity = 0; ///< mm/s, signed
  bool moving = false;
  bool released = false; ///< z32: G29 released it
};

/// The modal state of a thread.
struct DebugModal {
  int motion = 0;           ///< 0..3: G00..G03
  bool incremental = false; ///< G91
  bool continuous = false;  ///< G64
  int plane = 17;
  double feed = std::numeric_limits<double>::quiet_NaN(); ///< mm/s (NaN: never set)
};

/// A named value the view shows (PAR[3], HA, $aa_out[2], spindle, ...).
struct DebugValue {
  std::string name;
  std::string value;
};

/// The run's state during a hook call. Valid only during that call.
class RunView {
public:
  virtual ~RunView() = default;
  virtual double time() const = 0;         ///< the simulated time of the stop
  virtual uint64_t blocks() const = 0;     ///< as the summary counts them so far
  virtual uint64_t statements() const = 0; ///< statements executed so far
  virtual std::vector<DebugThread> threads() const = 0;
  /// The call chain of thread `id`, innermost first (empty: no such thread).
  virtual std::vector<DebugFrame> stack(uint32_t id) const = 0;
  virtual DebugModal modal(uint32_t id) const = 0;
  /// R parameters written so far (or preset by the machine), ascending, with their values.
  virtual std::vector<std::pair<uint32_t, double>> rParameters() const = 0;
  /// z32: PAR and PAL entries that are not 0, and the machine's user parameters.
  virtual std::vector<DebugValue> z32Parameters() const = 0;
  virtual std::vector<DebugAxis> axes() const = 0;
  /// z32: spindle, tool and coolants; the selected origin.
  virtual std::vector<DebugValue> machineFunctions() const = 0;
  /// Inputs, outputs and markers that are on.
  virtual std::vector<DebugValue> io() const = 0;
  /// The values an expression may read (SPEC §3): nullopt when the index or axis does not
  /// exist. `sv` with an axis letter, or with an index for $aa_in/$aa_out/$aa_marker.
  virtual std::optional<double> r(double index) const = 0;
  virtual std::optional<double> par(double index) const = 0;
  virtual std::optional<double> pal(double index) const = 0;
  virtual std::optional<double> userParameter(std::string_view name) const = 0;
  virtual std::optional<double> axisVariable(lang::SysVar sv, char axis) const = 0;
  virtual std::optional<double> ioVariable(lang::SysVar sv, double index) const = 0;
  /// The file and line of a line-table entry.
  virtual DebugFrame where(uint32_t lineEntry) const = 0;
};

/// Implemented by a debugger. Every call happens on the thread running simulate().
class DebugHook {
public:
  virtual ~DebugHook() = default;
  /// Before a statement of thread `thread` runs; `lineEntry` is its row in Image::lines
  /// (UINT32_MAX in a stripped image), `depth` the frames above the thread's first. In a G64
  /// chain a statement is reached when it is read ahead. False ends the run.
  virtual bool statement(const RunView& view, uint32_t thread, uint32_t lineEntry, size_t depth) = 0;
  /// The next simulated time at which timeReached must be called (infinity: none).
  virtual double nextTimeStop() const { return std::numeric_limits<double>::infinity(); }
  /// The run passes nextTimeStop(): view.time() is that time (the axes where they are then).
  /// False ends the run.
  virtual bool timeReached(const RunView& view) = 0;
  /// The run stops with a runtime error or an emergency (`message` as the summary says it),
  /// in thread `thread` (0: outside a thread). The state is the state at the fault.
  virtual void fault(const RunView& view, Status status, const std::string& message, uint32_t thread) = 0;
};

/// The message of a run the hook ended.
inline constexpr std::string_view kDebuggerEndedRun = "the debugger ended the run";

} // namespace iso::sim
