//! @file TimeProfile.h
//! @brief `isosim --profile`: where the cycle time goes. The simulator attributes every instant
//!        of the main program to the statement it is executing and to why it waits; this file
//!        holds the result and renders it as a text table or JSON. The library never prints.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

namespace iso::sim {

/// Why the main program is waiting. Every instant of a run falls in exactly one category.
enum class TimeCat : uint8_t {
  Accel,  ///< its motion block accelerates (the axis that arrives last, or the path)
  Cruise, ///< ... runs at constant speed
  Decel,  ///< ... decelerates
  Dwell,  ///< G04
  Plc,    ///< a blocking M sequence (or one still running that must end before it restarts)
  Inputs, ///< the interpolation-cycle wait of a real-time read or write (SPEC §6.2): polling
  Block,  ///< block_time_s
  Stop,   ///< M0 (m0_wait_s)
  When,   ///< WHEN bodies still running after their trigger has arrived
  Count
};
constexpr size_t kTimeCats = static_cast<size_t>(TimeCat::Count);
const char* timeCatName(TimeCat c); ///< "accel", "cruise", ...

/// A compensated (Neumaier) sum: adding thousands of durations keeps the last bits.
class ExactSum {
public:
  void add(double x);
  double value() const { return sum_ + comp_; }

private:
  double sum_ = 0, comp_ = 0;
};

/// Time split by category.
struct TimeSplit {
  std::array<ExactSum, kTimeCats> parts;
  void add(TimeCat c, double dt) { parts[static_cast<size_t>(c)].add(dt); }
  double part(TimeCat c) const { return parts[static_cast<size_t>(c)].value(); }
  /// The sum of the parts.
  double total() const;
};

/// One source line (statement) of the program set.
struct LineProfile {
  std::string file;                ///< file name as stored in the image
  uint32_t line = 0;               ///< 0 in a stripped image (then one row per procedure)
  uint64_t count = 0;              ///< how often it ran (read-ahead in G64 and WHEN bodies included)
  TimeSplit time;                  ///< main-program time spent on it
  std::vector<std::string> bounds; ///< motion lines: what bounded the block, each once, in order seen
};

/// One procedure: the main program, a subprogram or a semi-automatic program.
struct ProcProfile {
  std::string name;
  std::string file;
  uint64_t calls = 0; ///< 1 for the program that ran; calls for subprograms
  TimeSplit time;     ///< inclusive: time while it was on the main program's call stack
};

/// One M number.
struct MProfile {
  uint64_t m = 0;
  uint64_t count = 0; ///< starts, blocking or not, by any thread
  ExactSum running;   ///< total duration of its sequences
  TimeSplit time;     ///< main-program time spent waiting for it (category plc)
};

struct TimeProfile {
  double cycleTimeS = 0;
  TimeSplit total;                ///< every line together: total() == cycleTimeS
  std::vector<LineProfile> lines; ///< in file order, then line order
  std::vector<ProcProfile> procs; ///< the program that ran first, then by name
  std::vector<MProfile> ms;       ///< by M number
};

/// The profile as a text table: one row per line that ran, the slowest first (most total time;
/// ties by file, then line), at most `maxLines` of them (0 = all) followed by
/// "... and N more lines (--profile-lines 0 shows all)" when some are left out; the total row
/// (of every line), then procedures, then M numbers.
std::string renderProfileText(const TimeProfile& p, size_t maxLines = 0);
/// The lines of renderProfileText's table, slowest first: indexes into p.lines.
std::vector<size_t> linesBySlowest(const TimeProfile& p);
/// The profile as a JSON value (schemas/isosim-profile.schema.json).
nlohmann::ordered_json profileValue(const TimeProfile& p);
/// profileValue printed with an indent of 2 (no trailing newline).
std::string renderProfileJson(const TimeProfile& p);

} // namespace iso::sim
