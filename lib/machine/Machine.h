//! @file Machine.h
//! @brief The machine model of SPEC §5.1: axes, limits, PLC sequences, inputs, presets.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "lang/Limits.h"
#include "lang/MFunctions.h"
#include "support/Expected.h"

namespace iso::machine {

using Dialect = lang::Dialect;
const char* dialectName(Dialect d);
std::optional<Dialect> parseDialect(std::string_view s);

/// One axis. Units: mm, mm/s, mm/s^2 (rotary axes: degrees the same way).
struct Axis {
  char letter = 'X';         ///< upper-case single letter (SPEC §2)
  double maxVelocity = 500;  ///< > 0
  double maxAccel = 2000;    ///< > 0
  double limitMinus = -1000; ///< soft limit, inclusive
  double limitPlus = 3000;   ///< soft limit, inclusive, >= limitMinus
  double start = 0;          ///< within the limits
};

/// One axis of a zone: the box's bounds on it (inclusive; an unbounded side is infinite).
struct ZoneAxis {
  char letter = 'X';                                     ///< an axis of the machine
  double min = -std::numeric_limits<double>::infinity(); ///< "min" (absent: unbounded)
  double max = std::numeric_limits<double>::infinity();  ///< "max" (absent: unbounded), >= min
  bool operator==(const ZoneAxis&) const = default;
};

/// A crash zone: a box in machine coordinates over the axes it lists (an axis not listed is
/// unbounded). Entering a forbidden zone is an emergency; entering a warn zone, a warning.
struct Zone {
  std::string name{};           ///< unique among the zones
  bool forbidden = true;        ///< "kind": "forbidden" (true) or "warn"
  std::vector<ZoneAxis> axes{}; ///< at least one, machine order, each axis once
  bool operator==(const Zone&) const = default;
};

struct MSequence {
  double durationS = 0;                       ///< >= 0
  std::vector<std::pair<int, int>> setInputs; ///< (input index, 0|1), sorted by index
};

/// The z32 tables of the machine file (SPEC §4.7): origins 1..kMaxOrigin, PAL 0..kMaxPalIndex.
using lang::kMaxOrigin;
using lang::kMaxPalIndex;

struct Machine {
  std::string name = "default";
  bool builtin = false; ///< builtinMachine(): no machine file was given (O<n>: a runtime error, not E313)
  Dialect dialect = Dialect::Sidac;
  std::vector<Axis> axes;                                    ///< 1..9 axes, machine order = CSV column order
  double ipoCycleS = 0.002;                                  ///< > 0
  double blockTimeS = 0.0;                                   ///< >= 0
  double cornerDeviationMm = 0.05;                           ///< > 0
  int lookaheadBlocks = 64;                                  ///< >= 1
  std::map<int, MSequence> mSequences;                       ///< by M number (>= 0)
  double defaultMDurationS = 0.0;                            ///< >= 0
  double m0WaitS = 0.0;                                      ///< >= 0
  int numInputs = 256;                                       ///< >= 0
  int numOutputs = 256;                                      ///< >= 0
  std::map<int, std::vector<std::pair<double, int>>> inputs; ///< input -> [(t, value 0|1)], t ascending
  std::map<int, double> rPreset;                             ///< R index (1..lang::kMaxRIndex) -> value
  // dialect z32 (SPEC §4.6)
  std::map<int, std::string> specialM; ///< M number -> subprogram name (<= 48; see lang::mayBeSpecial)
  bool optionalStop = false;           ///< M1 acts as M0
  double auxDurationS = 0.0;           ///< each MA/MB/MC, >= 0
  // dialect z32 (SPEC §4.7)
  /// Origin number (1..99) -> (axis letter, offset) pairs, sorted by letter; an axis not
  /// listed has offset 0.
  std::map<int, std::vector<std::pair<char, double>>> origins;
  std::vector<std::string> parameters; ///< user parameter addresses, upper-case ("HA", "Q"), in file order
  std::map<int, double> palPreset;     ///< PAL index (0..255) -> value before any write
  std::vector<Zone> zones;             ///< the crash zones, in file order

  /// Index of the axis named by letter (case-insensitive), or -1.
  int axisIndex(char letter) const;
};

/// The built-in machine: 9 axes X Y Z A B C U V W, each max_velocity 500, max_accel 2000,
/// limits -1000..3000, start 0; every other key at its default.
Machine builtinMachine();

/// A machine file error: `where` is the JSON path ("/axes/2/max_accel"; "" for the document
/// itself), `message` what is wrong there ("must be a number > 0").
using MachineError = support::Error;

/// Parses and validates a machine file (JSON of SPEC §5.1). Unknown keys, wrong types,
/// non-positive velocities/accelerations, duplicate or invalid axis names, start outside the
/// limits, 0 or more than 9 axes: an error naming the JSON path. Never throws.
using MachineResult = support::Expected<Machine>;
MachineResult parseMachine(std::string_view jsonText);

/// The most errors of one machine file kept (and shown); the others are only counted.
inline constexpr size_t kMaxMachineErrors = 20;
/// The largest machine file read (16 MiB): a larger one is an error.
inline constexpr size_t kMaxMachineFileBytes = size_t{16} << 20;

/// Every error of a machine file: the first kMaxMachineErrors in the order the file is checked
/// (a key, an axis or an entry of a table that is wrong does not stop the check of the others;
/// invalid JSON, a duplicate key and nesting deeper than 64 levels are one error each), and how
/// many there are in all.
struct MachineErrors {
  std::vector<MachineError> shown;
  size_t count = 0;
};

/// The same as parseMachine(jsonText), with every error: nullopt when there is any.
std::optional<Machine> parseMachine(std::string_view jsonText, MachineErrors& errors);

/// The machine as JSON text in the §5.1 format (pretty, 2-space indent, keys in §5.1 order);
/// parseMachine(machineToJson(m)) gives m back.
std::string machineToJson(const Machine& m);

} // namespace iso::machine
