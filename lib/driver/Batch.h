//! @file Batch.h
//! @brief Programs loaded and compiled once, then run on many machines on threads: what
//!        isosim --sweep and --calibrate share.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "driver/Common.h"
#include "driver/Settings.h"
#include "driver/Simulate.h"
#include "image/ImageVerifier.h"
#include "machine/Machine.h"
#include "sim/Trace.h"
#include "support/Expected.h"

namespace iso::driver {

/// A path written in the file `file`, relative to the file's folder (an absolute one as it is),
/// lexically normal.
std::string pathBeside(const std::string& file, const std::string& path);

/// The text of a sweep or calibration file (`what`: "sweep", "calibration"): an error naming
/// the file when it cannot be read, is over kMaxSettingsBytes or is not UTF-8.
support::Expected<std::string> readBatchFile(const std::string& path, const char* what);

/// Runs fn(i) for every i below n on `jobs` threads (each takes the next index); rethrows
/// the first exception a call threw once every thread is done.
void parallelFor(size_t n, unsigned jobs, const std::function<void(size_t)>& fn);

/// A base machine: the machine one or more programs run on before any change.
struct BatchMachine {
  std::string key; ///< the machine file and dialect it was loaded from
  machine::Machine m;
};

/// A program of a batch: its settings, its base machine, its image.
struct BatchProgram {
  std::string path; ///< as given (resolved from the folder of the file that names it)
  CommonOptions common;
  Settings settings;
  size_t base = 0;
  std::optional<image::VerifiedImage> img{};
  std::string entry{};
  std::string compileError{}; ///< set when the program set has errors: every run of it is an error
};

/// The settings and base machine of every program of `paths` (common's --machine, else
/// `machine`, else the program's settings', else the built-in one): exit code.
int batchMachines(const std::vector<std::string>& paths, const CommonOptions& common, const std::string& machine,
                  std::vector<BatchProgram>& programs, std::vector<BatchMachine>& bases, Io& io);

/// Whether a program compiled for `a` is the same image for `b`: the same dialect, special M
/// functions, parameters and axis names.
bool compilesAlike(const machine::Machine& a, const machine::Machine& b);

/// Loads and compiles every program once: exit code (a program with errors is not one: its
/// compileError is set and its runs are errors). Every file read, and `inputs`, is checked
/// against `outputs` first (outputs never destroy inputs).
int loadBatchPrograms(std::vector<BatchProgram>& programs, const std::vector<BatchMachine>& bases,
                      const std::vector<OutputPath>& outputs, const std::vector<std::string>& inputs, Io& io);

/// The outcome of one run.
struct BatchRun {
  sim::Status status = sim::Status::Ok;
  double cycleTimeS = 0;
  uint64_t blocks = 0;
  double spindleOnS = 0;
  uint64_t toolChanges = 0;
  size_t warnings = 0;
  std::string message{}; ///< "" when ok; else the summary's message (or why the run could not start)
};

/// One run of `p` on `m` (a machine that compiles alike its base) with the options of `ro`
/// (--dt, --block-skip, the limits, the overrides).
BatchRun runBatchProgram(const BatchProgram& p, const machine::Machine& m, const SimulateOptions& ro);

} // namespace iso::driver
