//! @file Thread.h
//! @brief isosim's thread and frame model: the main program and each fired WHEN body run as a
//!        thread with its own pc, value stack, call frames and modal state (SPEC §4.4, §6).
#pragma once

#include <cstdint>
#include <limits>
#include <vector>

#include "sim/InstructionStream.h"

namespace iso::sim {

/// The modal state a thread carries (and a call saves in its frame).
struct Modal {
  uint8_t motion = 0;                                     ///< 0..3 (G00..G03)
  bool incremental = false;                               ///< G91
  bool continuous = false;                                ///< G64: interpolated blocks blend into chains
  uint8_t plane = 17;                                     ///< 17, 18, 19
  double feed = std::numeric_limits<double>::quiet_NaN(); ///< F, mm/s; NaN = never set
};

/// What pushed a frame: a call (a call line, GOP, a special M), a z32 GO range, or the main
/// program replaced by a KG (its return ends the program).
enum class FrameKind : uint8_t { Call, Range, MainReplaced };

struct Frame {
  uint32_t ret = 0;
  Modal saved;
  bool toolChange = false; ///< z32: the call of a special M6; the tool changes on return
  bool special = false;    ///< z32: the call of a special M (its statements do not count in blocks)
  FrameKind kind = FrameKind::Call;
  uint32_t rangeEnd = kNoIndex; ///< Range: the instruction of the end line's statement header
  bool endRan = false;          ///< Range: that header has run in this frame
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

} // namespace iso::sim
