//! @file Calibrate.h
//! @brief isosim --calibrate MEASURED.csv --fit KEY...: machine keys fitted by least squares
//!        to the cycle times measured on a real machine; the fitted values, each program's
//!        residual, the keys the programs cannot determine; the fitted machine file (-o).
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "driver/Common.h"
#include "driver/Simulate.h"
#include "support/Expected.h"

namespace iso::driver {

/// The most measurement rows a calibration file may have.
inline constexpr size_t kMaxCalibrationRows = 10'000;
/// The most iterations of the fit.
inline constexpr size_t kMaxFitIterations = 100;

/// One row of a calibration file: a program and the cycle time measured for it.
struct Measurement {
  std::string program; ///< resolved from the folder of the calibration file
  double cycleTimeS = 0;
  std::string where{}; ///< "FILE:LINE:COL" of the program field
};

/// A calibration file, read and checked.
struct CalibrationData {
  std::string path;
  std::vector<Measurement> rows{};
  std::vector<std::string> programs{}; ///< the distinct programs, in order of first appearance
  std::vector<size_t> programOf{};     ///< per row: its index in `programs`
};

/// Reads calibration text: CSV with the header `program,cycle_time_s`, then one row per
/// measurement (a program may have several); blank lines and lines starting with '#' are
/// skipped; a field may be double-quoted ("" for a quote); a leading byte order mark is
/// skipped. Errors: `where` "FILE:LINE:COL".
support::Expected<CalibrationData> parseCalibration(std::string_view text, const std::string& path);
/// parseCalibration of the file PATH (at most 16 MiB), with every program checked to exist.
support::Expected<CalibrationData> loadCalibration(const std::string& path);

/// One parameter of a bounded least-squares fit.
struct FitParameter {
  double start = 0;
  bool logScale = false;         ///< fitted as log(value): a value > 0 (its lower bound is 0)
  double lower = 0;              ///< value >= lower (log scale: > 0)
  std::optional<double> upper{}; ///< value <= upper
};

/// The residuals at each of several points (a point: one value per parameter); nullopt at a
/// point where the model cannot be evaluated. Points come in batches so that they can be run
/// at once.
using FitModel =
    std::function<std::vector<std::optional<std::vector<double>>>(const std::vector<std::vector<double>>& points)>;

/// The outcome of a fit.
struct FitResult {
  std::vector<double> values{};   ///< one per parameter (an undetermined one: its start)
  std::vector<bool> determined{}; ///< false: no residual depends on it, or only together with others
  std::vector<bool> alone{};      ///< for an undetermined one: true when no residual depends on it at all
  size_t iterations = 0;
  bool converged = false; ///< the last relative step was below 1e-10, or no step could lower the cost
  bool failed = false;    ///< the model could not be evaluated at the start
};

/// Levenberg-Marquardt on the parameters (log scale where asked), each held within its bounds
/// and within a factor of 1000 of its start (log scale), the Jacobian by forward differences
/// (relative step 1e-6). Parameters whose Jacobian column is about zero, or about a
/// combination of the others', at the start are left at their start. Stops when the largest
/// relative change of a value is below 1e-10, when no step lowers the sum of squares, or after
/// maxIterations.
FitResult fitLeastSquares(const std::vector<FitParameter>& params, const FitModel& model,
                          size_t maxIterations = kMaxFitIterations);

struct CalibrateOptions {
  SimulateOptions run;          ///< --machine, --dialect, --config, --set, -o, --format, --block-skip, ...
  std::string file;             ///< --calibrate FILE
  std::vector<std::string> fit; ///< --fit KEY (repeatable, or a comma list)
  unsigned jobs = 0;            ///< -j N (0 = every core)
};

/// isosim --calibrate. Every program is loaded and compiled once; each evaluation of the model
/// runs every program on one machine variant, on `jobs` threads. Output: the report (text, or
/// JSON with --format json) on stdout; with -o FILE the fitted machine file, written whole.
/// Exit codes: 0 fitted (warnings included), 1 a program with errors or a run that does not
/// end ok on the starting machine, 2 usage, an unreadable input, an invalid calibration file
/// or key.
int runCalibrate(const CalibrateOptions& opts, Io& io);

} // namespace iso::driver
