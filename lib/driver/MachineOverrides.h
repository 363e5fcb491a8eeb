//! @file MachineOverrides.h
//! @brief isosim --set KEY=VALUE (and --m0-wait, --optional-stop): a what-if run on a machine
//!        changed for this run only. Each KEY is a path into the machine file's JSON, dots
//!        between the parts, an axis by its name (`axes.X.max_accel`, `m_sequences.23.duration_s`,
//!        `block_time_s`); the changed machine is validated as a machine file is.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "driver/Common.h"
#include "machine/Machine.h"
#include "support/Expected.h"

namespace iso::driver {

/// `m` with every assignment of `sets` ("KEY=VALUE"; VALUE is JSON — a number, true, false,
/// null, an object — or else a string) applied in order. nullopt, with the reason printed as
/// "isosim: error: --set KEY=VALUE: ..." to io.err, when a KEY names nothing that can be set or
/// the result is not a valid machine.
std::optional<machine::Machine> overrideMachine(const machine::Machine& m, const std::vector<std::string>& sets,
                                                Io& io);

/// overrideMachine without printing: the changed machine, or why not (`where`: the "KEY=VALUE"
/// at fault, "" when the changed machine as a whole is not valid; `message`: the reason, with
/// the machine-file errors as "at /json/path: reason" joined by "; ").
support::Expected<machine::Machine> overriddenMachine(const machine::Machine& m, const std::vector<std::string>& sets);

/// A number key of the machine file with a lower bound (a time, a speed, an acceleration, a
/// tolerance), as --set names it: what isosim --calibrate fits.
struct NumberKey {
  double value = 0;              ///< its value in the machine (a missing m_sequences entry: its default)
  bool positive = false;         ///< the bound is "> lower" (else ">= lower")
  double lower = 0;              ///< the lower bound
  std::optional<double> upper{}; ///< the upper bound ("<= upper"), if any
};

/// The key KEY of `m` (`axes.X.max_accel`, `block_time_s`, `m_sequences.23.duration_s`); an
/// Error (`where` KEY) when it names no number key with a lower bound that --set could change
/// in `m`.
support::Expected<NumberKey> machineNumberKey(const machine::Machine& m, const std::string& key);

} // namespace iso::driver
