//! @file Calibrate.cpp
//! @brief isosim --calibrate: the calibration file, the bounded Levenberg-Marquardt fit, the
//!        runs of each evaluation on threads, the report and the fitted machine file.
#include "driver/Calibrate.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "driver/Batch.h"
#include "driver/MachineOverrides.h"
#include "driver/Settings.h"
#include "driver/Sources.h"
#include "sim/TraceWriter.h"
#include "support/CaseFold.h"
#include "support/File.h"
#include "support/Text.h"

namespace iso::driver {

namespace {

/// The fields of one CSV line, each with its 1-based column; false with `col` at the fault
/// when a quoted field is not closed or text follows its closing quote.
struct CalibField {
  std::string text;
  size_t col = 0;
};

bool calibSplit(std::string_view line, std::vector<CalibField>& out, size_t& col) {
  size_t i = 0;
  for (;;) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t'))
      ++i;
    CalibField f;
    f.col = i + 1;
    if (i < line.size() && line[i] == '"') {
      for (++i;; ++i) {
        if (i >= line.size()) {
          col = f.col;
          return false;
        }
        if (line[i] == '"') {
          if (i + 1 < line.size() && line[i + 1] == '"') {
            f.text += '"';
            ++i;
            continue;
          }
          ++i;
          break;
        }
        f.text += line[i];
      }
      while (i < line.size() && (line[i] == ' ' || line[i] == '\t'))
        ++i;
      if (i < line.size() && line[i] != ',') {
        col = i + 1;
        return false;
      }
    } else {
      const size_t end = std::min(line.find(',', i), line.size());
      f.text = std::string(line.substr(i, end - i));
      while (!f.text.empty() && (f.text.back() == ' ' || f.text.back() == '\t'))
        f.text.pop_back();
      i = end;
    }
    out.push_back(std::move(f));
    if (i >= line.size()) return true;
    ++i; // the comma
  }
}

/// The cycle time of a row: a number > 0; nullopt when it is not one.
std::optional<double> calibSeconds(const std::string& text) {
  double v = 0;
  const char* end = text.data() + text.size();
  auto r = std::from_chars(text.data(), end, v);
  if (r.ec != std::errc() || r.ptr != end || !std::isfinite(v)) return std::nullopt;
  return v;
}

/// One measurement line (its fields split) into `out`: an error or nothing.
std::optional<support::Error> calibRow(const std::string& path, size_t lineNo, const std::vector<CalibField>& fields,
                                       CalibrationData& out) {
  auto at = [&](size_t col) { return fmt::format("{}:{}:{}", path, lineNo, col); };
  if (fields.size() != 2)
    return support::Error{at(fields.size() > 2 ? fields[2].col : 1),
                          fmt::format("expected 2 fields (program,cycle_time_s), found {}", fields.size())};
  if (fields[0].text.empty()) return support::Error{at(fields[0].col), "the program is empty"};
  const auto t = calibSeconds(fields[1].text);
  if (!t)
    return support::Error{at(fields[1].col),
                          fmt::format("the cycle time '{}' is not a number (seconds)", fields[1].text)};
  if (!(*t > 0))
    return support::Error{at(fields[1].col), fmt::format("the cycle time must be above 0 s, not {}", fields[1].text)};
  if (out.rows.size() == kMaxCalibrationRows)
    return support::Error{at(1), fmt::format("more than {} measurements", kMaxCalibrationRows)};
  Measurement m{pathBeside(path, fields[0].text), *t, at(fields[0].col)};
  auto known = std::find(out.programs.begin(), out.programs.end(), m.program);
  out.programOf.push_back(static_cast<size_t>(known - out.programs.begin()));
  if (known == out.programs.end()) out.programs.push_back(m.program);
  out.rows.push_back(std::move(m));
  return std::nullopt;
}

} // namespace

support::Expected<CalibrationData> parseCalibration(std::string_view text, const std::string& path) {
  CalibrationData out;
  out.path = path;
  if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3); // the byte order mark spreadsheets write
  bool header = false;
  size_t lineNo = 0;
  for (size_t from = 0; from <= text.size();) {
    size_t nl = text.find('\n', from);
    if (nl == std::string_view::npos) nl = text.size();
    std::string_view line = text.substr(from, nl - from);
    from = nl + 1;
    ++lineNo;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    const size_t first = line.find_first_not_of(" \t");
    if (first == std::string_view::npos || line[first] == '#') continue;
    std::vector<CalibField> fields;
    size_t col = 0;
    if (!calibSplit(line, fields, col))
      return support::Error{fmt::format("{}:{}:{}", path, lineNo, col),
                            "a quoted field must end with '\"' before the next ',' or the end of the line"};
    if (!header) {
      if (fields.size() != 2 || fields[0].text != "program" || fields[1].text != "cycle_time_s")
        return support::Error{fmt::format("{}:{}:{}", path, lineNo, first + 1),
                              "the first line must be the header 'program,cycle_time_s'"};
      header = true;
      continue;
    }
    if (auto e = calibRow(path, lineNo, fields, out)) return *e;
  }
  if (!header) return support::Error{path, "the file is empty: expected the header 'program,cycle_time_s'"};
  if (out.rows.empty()) return support::Error{path, "no measurement after the header: expected rows PROGRAM,SECONDS"};
  return out;
}

support::Expected<CalibrationData> loadCalibration(const std::string& path) {
  auto text = readBatchFile(path, "calibration");
  if (!text) return text.error();
  auto data = parseCalibration(*text, path);
  if (!data) return data;
  for (const Measurement& m : data->rows) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(m.program, ec))
      return support::Error{m.where, fmt::format("no such program file: {}", m.program)};
  }
  return data;
}

// ---------------------------------------------------------------------------------------
// The solver

namespace {

using Matrix = std::vector<std::vector<double>>; ///< by column: m[j][i] is row i of column j

/// Solves a·x = b (a square, by rows) by Gaussian elimination with partial pivoting; false
/// when a pivot is (about) zero.
bool calibSolve(std::vector<std::vector<double>> a, std::vector<double> b, std::vector<double>& x) {
  const size_t n = b.size();
  for (size_t c = 0; c < n; ++c) {
    size_t p = c;
    for (size_t r = c + 1; r < n; ++r)
      if (std::fabs(a[r][c]) > std::fabs(a[p][c])) p = r;
    if (!(std::fabs(a[p][c]) > 1e-300)) return false;
    std::swap(a[p], a[c]);
    std::swap(b[p], b[c]);
    for (size_t r = c + 1; r < n; ++r) {
      const double f = a[r][c] / a[c][c];
      for (size_t k = c; k < n; ++k)
        a[r][k] -= f * a[c][k];
      b[r] -= f * b[c];
    }
  }
  x.assign(n, 0);
  for (size_t c = n; c-- > 0;) {
    double s = b[c];
    for (size_t k = c + 1; k < n; ++k)
      s -= a[c][k] * x[k];
    x[c] = s / a[c][c];
  }
  return true;
}

double calibNorm(const std::vector<double>& v) {
  double s = 0;
  for (double e : v)
    s += e * e;
  return std::sqrt(s);
}

double calibDot(const std::vector<double>& a, const std::vector<double>& b) {
  double s = 0;
  for (size_t i = 0; i < a.size(); ++i)
    s += a[i] * b[i];
  return s;
}

/// The part of unit column `cols[j]` outside the span of the other columns of `use`: its norm.
double calibOutsideSpan(const Matrix& cols, const std::vector<bool>& use, size_t j) {
  Matrix basis;
  for (size_t k = 0; k < cols.size(); ++k) {
    if (k == j || !use[k]) continue;
    std::vector<double> v = cols[k];
    for (const auto& q : basis) {
      const double d = calibDot(v, q);
      for (size_t i = 0; i < v.size(); ++i)
        v[i] -= d * q[i];
    }
    const double n = calibNorm(v);
    if (n < 1e-9) continue;
    for (double& e : v)
      e /= n;
    basis.push_back(std::move(v));
  }
  std::vector<double> v = cols[j];
  for (int pass = 0; pass < 2; ++pass) // twice: Gram-Schmidt loses orthogonality once
    for (const auto& q : basis) {
      const double d = calibDot(v, q);
      for (size_t i = 0; i < v.size(); ++i)
        v[i] -= d * q[i];
    }
  return calibNorm(v);
}

/// The fit's working state: values in the fit's coordinates (log for log-scale parameters).
struct FitSpace {
  const std::vector<FitParameter>& params;
  std::vector<double> lo{}, hi{};

  explicit FitSpace(const std::vector<FitParameter>& p) : params(p) {
    for (const FitParameter& q : p) {
      if (q.logScale) {
        const double x0 = std::log(q.start);
        lo.push_back(x0 - std::log(1000.0));
        hi.push_back(std::min(x0 + std::log(1000.0), q.upper ? std::log(*q.upper) : HUGE_VAL));
      } else {
        lo.push_back(q.lower);
        hi.push_back(q.upper ? *q.upper : HUGE_VAL);
      }
    }
  }
  double value(size_t j, double x) const { return params[j].logScale ? std::exp(x) : x; }
  double coord(size_t j, double v) const { return params[j].logScale ? std::log(v) : v; }
  std::vector<double> values(const std::vector<double>& x) const {
    std::vector<double> v(x.size());
    for (size_t j = 0; j < x.size(); ++j)
      v[j] = value(j, x[j]);
    return v;
  }
  /// The difference step of parameter j at x: 1e-6 of its value (log scale: of the factor),
  /// at least 1e-6, backwards when forwards would leave the bounds.
  double step(size_t j, double x) const {
    const double h = params[j].logScale ? 1e-6 : 1e-6 * std::max(1.0, std::fabs(x));
    return x + h <= hi[j] ? h : -h;
  }
};

double calibCost(const std::vector<double>& r) { return 0.5 * calibDot(r, r); }

/// The Jacobian columns of the `free` parameters at x (zero where a point failed).
Matrix calibJacobian(const FitSpace& space, const FitModel& model, const std::vector<double>& x,
                     const std::vector<double>& r, const std::vector<bool>& free) {
  std::vector<std::vector<double>> points;
  std::vector<size_t> which;
  std::vector<double> steps;
  for (size_t j = 0; j < x.size(); ++j) {
    if (!free[j]) continue;
    std::vector<double> p = x;
    steps.push_back(space.step(j, x[j]));
    p[j] += steps.back();
    points.push_back(space.values(p));
    which.push_back(j);
  }
  Matrix cols(x.size(), std::vector<double>(r.size(), 0.0));
  if (points.empty()) return cols;
  const auto res = model(points);
  for (size_t k = 0; k < which.size(); ++k) {
    if (!res[k]) continue;
    for (size_t i = 0; i < r.size(); ++i)
      cols[which[k]][i] = ((*res[k])[i] - r[i]) / steps[k];
  }
  return cols;
}

/// Which parameters the Jacobian at the start determines; `alone` marks those no residual
/// depends on.
void calibDetermined(const Matrix& cols, std::vector<bool>& determined, std::vector<bool>& alone) {
  const size_t n = cols.size();
  determined.assign(n, true);
  alone.assign(n, false);
  Matrix unit = cols;
  for (size_t j = 0; j < n; ++j) {
    double largest = 0;
    for (double e : cols[j])
      largest = std::max(largest, std::fabs(e));
    const double norm = calibNorm(cols[j]);
    if (!(largest > 1e-9)) { // a change of 1 (a factor e) moves no residual by 1 ns
      determined[j] = false;
      alone[j] = true;
      continue;
    }
    for (double& e : unit[j])
      e /= norm;
  }
  const std::vector<bool> nonzero = determined;
  for (size_t j = 0; j < n; ++j)
    if (nonzero[j] && calibOutsideSpan(unit, nonzero, j) < 1e-6) determined[j] = false;
}

/// One Levenberg-Marquardt step on the free parameters, the ones at a bound that the step
/// would push out held: the new point, or nullopt when the system cannot be solved.
std::optional<std::vector<double>> calibStep(const FitSpace& space, const Matrix& cols, const std::vector<double>& r,
                                             const std::vector<double>& x, std::vector<bool> free, double lambda) {
  for (size_t round = 0; round <= x.size(); ++round) {
    std::vector<size_t> idx;
    for (size_t j = 0; j < x.size(); ++j)
      if (free[j]) idx.push_back(j);
    if (idx.empty()) return x;
    std::vector<std::vector<double>> a(idx.size(), std::vector<double>(idx.size()));
    std::vector<double> g(idx.size());
    for (size_t p = 0; p < idx.size(); ++p) {
      for (size_t q = 0; q < idx.size(); ++q)
        a[p][q] = calibDot(cols[idx[p]], cols[idx[q]]);
      g[p] = -calibDot(cols[idx[p]], r);
    }
    for (size_t p = 0; p < idx.size(); ++p)
      a[p][p] += lambda * std::max(a[p][p], 1e-12);
    std::vector<double> d;
    if (!calibSolve(a, g, d)) return std::nullopt;
    bool held = false;
    for (size_t p = 0; p < idx.size(); ++p) {
      const size_t j = idx[p];
      if ((x[j] <= space.lo[j] && d[p] < 0) || (x[j] >= space.hi[j] && d[p] > 0)) {
        free[j] = false;
        held = true;
      }
    }
    if (held) continue;
    std::vector<double> out = x;
    for (size_t p = 0; p < idx.size(); ++p)
      out[idx[p]] = std::clamp(x[idx[p]] + d[p], space.lo[idx[p]], space.hi[idx[p]]);
    return out;
  }
  return x;
}

/// The largest relative change of a value between x and y.
double calibRelativeStep(const FitSpace& space, const std::vector<double>& x, const std::vector<double>& y) {
  double most = 0;
  for (size_t j = 0; j < x.size(); ++j) {
    const double a = space.value(j, x[j]), b = space.value(j, y[j]);
    if (a == b) continue;
    most = std::max(most, std::fabs(b - a) / std::max({std::fabs(a), std::fabs(b), 1e-300}));
  }
  return most;
}

} // namespace

FitResult fitLeastSquares(const std::vector<FitParameter>& params, const FitModel& model, size_t maxIterations) {
  FitResult out;
  const FitSpace space(params);
  std::vector<double> x;
  for (size_t j = 0; j < params.size(); ++j)
    x.push_back(space.coord(j, params[j].start));
  out.values = space.values(x);
  auto r0 = model({out.values})[0];
  if (!r0) {
    out.failed = true;
    return out;
  }
  std::vector<double> r = std::move(*r0);
  double cost = calibCost(r);
  Matrix cols = calibJacobian(space, model, x, r, std::vector<bool>(x.size(), true));
  calibDetermined(cols, out.determined, out.alone);
  double lambda = 1e-3;
  const bool any = std::find(out.determined.begin(), out.determined.end(), true) != out.determined.end();
  while (any && out.iterations < maxIterations && cost > 0) {
    ++out.iterations;
    if (out.iterations > 1) cols = calibJacobian(space, model, x, r, out.determined);
    bool moved = false;
    while (lambda <= 1e12) {
      auto next = calibStep(space, cols, r, x, out.determined, lambda);
      if (!next || *next == x) {
        lambda *= 10;
        if (!next) continue;
        break;
      }
      auto rn = model({space.values(*next)})[0];
      if (rn && calibCost(*rn) < cost) {
        const double rel = calibRelativeStep(space, x, *next);
        x = std::move(*next);
        r = std::move(*rn);
        cost = calibCost(r);
        lambda = std::max(lambda / 10, 1e-12);
        moved = true;
        out.converged = rel < 1e-10;
        break;
      }
      lambda *= 10;
    }
    if (!moved) out.converged = true; // no step lowers the sum of squares
    if (!moved || out.converged) break;
  }
  if (cost == 0 || !any) out.converged = true;
  out.values = space.values(x);
  for (size_t j = 0; j < params.size(); ++j)
    if (!out.determined[j]) out.values[j] = params[j].start; // exactly (exp(log(v)) may differ)
  return out;
}

// ---------------------------------------------------------------------------------------
// isosim --calibrate

namespace {

/// A key to fit, as it is in the starting machine.
struct CalibKey {
  std::string key;
  NumberKey number;
};

/// What the calibration runs on: the programs compiled once, the starting machine.
struct CalibSetup {
  CalibrationData data;
  std::vector<BatchProgram> programs;
  std::vector<BatchMachine> bases; ///< one: the starting machine (with --set)
  std::vector<CalibKey> keys;
  std::string machinePath; ///< "" = built in
};

/// The options that have no meaning in a calibration: exit code; `format` the report's.
int checkCalibrateOptions(const CalibrateOptions& opts, Io& io, std::string& format) {
  const SimulateOptions& ro = opts.run;
  const std::pair<bool, const char*> refused[] = {
      {!ro.program.empty() || !ro.paths.empty(), "PROGRAM (the calibration file names the programs)"},
      {!ro.entry.empty(), "--entry"},
      {ro.m0Wait.has_value(), "--m0-wait (use --set m0_wait_s=S)"},
      {!ro.optionalStop.empty(), "--optional-stop (use --set optional_stop=true)"},
      {!ro.compare.empty() || !ro.budget.empty(), "--compare"},
      {!ro.plot.empty() || !ro.timeline.empty() || !ro.report.empty(), "--plot, --timeline and --report"},
      {ro.profile, "--profile"},
      {ro.summary, "--summary"},
      {ro.search.has_value(), "--search"},
      {ro.printMachine, "--print-machine"},
  };
  for (const auto& [given, what] : refused)
    if (given) return usageError(io, "isosim", fmt::format("--calibrate cannot be combined with {}", what));
  format = ro.format.empty() ? "text" : ro.format;
  if (format != "text" && format != "json")
    return usageError(io, "isosim", fmt::format("unknown format '{}' for --calibrate (text or json)", format));
  if (ro.output == "-")
    return usageError(io, "isosim", "with --calibrate, -o names the fitted machine file: '-' is not one");
  if (!ro.feedOverride.empty() && !overridePercent(ro.feedOverride, kMaxFeedOverride))
    return usageError(
        io, "isosim",
        fmt::format("--feed-override: expected a percent of the programmed feed from 1 to {}", kMaxFeedOverride));
  if (!ro.rapidOverride.empty() && !overridePercent(ro.rapidOverride, kMaxRapidOverride))
    return usageError(
        io, "isosim",
        fmt::format("--rapid-override: expected a percent of the rapid speed from 1 to {}", kMaxRapidOverride));
  if (opts.fit.empty())
    return usageError(io, "isosim", "--calibrate needs --fit KEY: the machine keys to fit (axes.X.max_accel, ...)");
  for (size_t i = 0; i < opts.fit.size(); ++i) {
    if (opts.fit[i].empty()) return usageError(io, "isosim", "--fit: an empty key");
    if (std::find(opts.fit.begin(), opts.fit.begin() + static_cast<std::ptrdiff_t>(i), opts.fit[i]) !=
        opts.fit.begin() + static_cast<std::ptrdiff_t>(i))
      return usageError(io, "isosim", fmt::format("--fit {}: given twice", support::escapeForTerminal(opts.fit[i])));
  }
  return kExitOk;
}

/// Reads the calibration file, the settings and the machine, the keys, and compiles the
/// programs: exit code.
int calibSetup(const CalibrateOptions& opts, CalibSetup& out, Io& io) {
  auto data = loadCalibration(opts.file);
  if (!data) {
    io.err << fmt::format("{}: error: {}\n", support::escapeForTerminal(data.error().where),
                          support::escapeForTerminal(data.error().message));
    return kExitUsage;
  }
  out.data = std::move(*data);
  if (int rc = batchMachines(out.data.programs, opts.run.common, "", out.programs, out.bases, io); rc != kExitOk)
    return rc;
  if (out.bases.size() != 1)
    return usageError(io, "isosim",
                      "the programs of the calibration file run on different machines (their settings files name "
                      "them): calibrate one machine at a time, or give --machine FILE");
  out.machinePath = out.programs[0].common.machinePath;
  if (!opts.run.sets.empty()) {
    auto changed = overrideMachine(out.bases[0].m, opts.run.sets, io);
    if (!changed) return kExitUsage;
    out.bases[0].m = std::move(*changed);
  }
  for (const std::string& key : opts.fit) {
    auto number = machineNumberKey(out.bases[0].m, key);
    if (!number)
      return usageError(io, "isosim",
                        fmt::format("--fit {}: {}", support::escapeForTerminal(key),
                                    support::escapeForTerminal(number.error().message)));
    out.keys.push_back({key, *number});
  }
  const std::vector<OutputPath> outs = {{"-o", opts.run.output}};
  if (int rc = loadBatchPrograms(out.programs, out.bases, outs, {out.data.path}, io); rc != kExitOk) return rc;
  for (const BatchProgram& p : out.programs)
    if (!p.img) {
      io.err << fmt::format("isosim: error: {}: the program has errors; nothing was fitted\n",
                            support::escapeForTerminal(p.path));
      return kExitErrors;
    }
  return kExitOk;
}

/// The machine with the keys at `values`: its "KEY=VALUE" changes.
std::vector<std::string> calibSets(const CalibSetup& setup, const std::vector<double>& values) {
  std::vector<std::string> sets;
  for (size_t k = 0; k < setup.keys.size(); ++k)
    sets.push_back(fmt::format("{}={}", setup.keys[k].key, values[k]));
  return sets;
}

/// The runs of every program at each point, on threads: per point, per program.
std::vector<std::vector<BatchRun>> calibRuns(const CalibSetup& setup, const CalibrateOptions& opts,
                                             const std::vector<std::vector<double>>& points) {
  const unsigned jobs = opts.jobs == 0 ? hardwareJobs() : opts.jobs;
  std::vector<std::optional<machine::Machine>> machines(points.size());
  std::vector<std::string> why(points.size());
  parallelFor(points.size(), jobs, [&](size_t p) {
    auto m = overriddenMachine(setup.bases[0].m, calibSets(setup, points[p]));
    if (m)
      machines[p] = std::move(*m);
    else
      why[p] = m.error().message;
  });
  const size_t n = setup.programs.size();
  std::vector<std::vector<BatchRun>> runs(points.size(), std::vector<BatchRun>(n));
  parallelFor(points.size() * n, jobs, [&](size_t i) {
    BatchRun& run = runs[i / n][i % n];
    if (!machines[i / n]) {
      run.status = sim::Status::Error;
      run.message = why[i / n];
      return;
    }
    run = runBatchProgram(setup.programs[i % n], *machines[i / n], opts.run);
  });
  return runs;
}

/// The residual of each measurement (model minus measured, s); nullopt when a run was not ok.
std::optional<std::vector<double>> calibResiduals(const CalibSetup& setup, const std::vector<BatchRun>& runs) {
  std::vector<double> r;
  for (const BatchRun& run : runs)
    if (run.status != sim::Status::Ok) return std::nullopt;
  for (size_t i = 0; i < setup.data.rows.size(); ++i)
    r.push_back(runs[setup.data.programOf[i]].cycleTimeS - setup.data.rows[i].cycleTimeS);
  return r;
}

/// A fitted value as it is written: a time (a key >= 0) to the microsecond, else to 6
/// significant digits.
double calibRounded(const FitParameter& p, double v) {
  if (!p.logScale) return std::max(p.lower, std::round(v * 1e6) / 1e6);
  return std::stod(fmt::format("{:.6g}", v));
}

} // namespace

namespace {

/// What a calibration found.
struct CalibReport {
  std::vector<double> start{}, fitted{};
  FitResult fit{};
  std::vector<double> model{}; ///< per measurement: the cycle time on the fitted machine
  std::vector<std::string> warnings{};
};

/// The warnings of a fit: the keys it could not determine, no convergence.
std::vector<std::string> calibWarnings(const CalibSetup& setup, const CalibReport& rep) {
  std::vector<std::string> out;
  std::vector<std::string> together;
  for (size_t k = 0; k < setup.keys.size(); ++k)
    if (!rep.fit.determined[k] && !rep.fit.alone[k]) together.push_back(setup.keys[k].key);
  for (size_t k = 0; k < setup.keys.size(); ++k) {
    if (rep.fit.determined[k]) continue;
    std::string why = "no cycle time depends on it";
    if (!rep.fit.alone[k]) {
      std::string others;
      for (const std::string& o : together)
        if (o != setup.keys[k].key) others += (others.empty() ? "" : ", ") + o;
      why = "it changes the cycle times only together with " + others;
    }
    out.push_back(fmt::format("{} is not determined by these programs ({}): left at {}", setup.keys[k].key, why,
                              sim::formatNumber(rep.start[k])));
  }
  if (!rep.fit.converged)
    out.push_back(
        fmt::format("the fit did not converge in {} iterations: the values are the best it found", rep.fit.iterations));
  return out;
}

/// The shortest text of a key's value ("3000", "0.004", "1.23457e-07").
std::string calibValueText(double v) { return fmt::format("{}", v); }

/// A share in percent to 3 decimals ("-0.000" printed "0.000").
std::string calibPercentText(double pct) {
  std::string s = fmt::format("{:.3f}", pct);
  return s == "-0.000" ? "0.000" : s;
}

std::string calibPercent(double residual, double measured) { return calibPercentText(100 * residual / measured); }

/// The root mean square of the residuals, in seconds and in percent of the measured times.
std::pair<double, double> calibRms(const CalibSetup& setup, const CalibReport& rep) {
  double s = 0, p = 0;
  const auto& rows = setup.data.rows;
  for (size_t i = 0; i < rows.size(); ++i) {
    const double r = rep.model[i] - rows[i].cycleTimeS;
    s += r * r;
    p += (100 * r / rows[i].cycleTimeS) * (100 * r / rows[i].cycleTimeS);
  }
  return {std::sqrt(s / static_cast<double>(rows.size())), std::sqrt(p / static_cast<double>(rows.size()))};
}

std::string calibText(const CalibSetup& setup, const CalibReport& rep) {
  const auto& rows = setup.data.rows;
  std::string out = fmt::format(
      "{}: {} measurement{} of {} program{}, {} key{}, {} iteration{}{}\n", support::escapeForTerminal(setup.data.path),
      rows.size(), rows.size() == 1 ? "" : "s", setup.programs.size(), setup.programs.size() == 1 ? "" : "s",
      setup.keys.size(), setup.keys.size() == 1 ? "" : "s", rep.fit.iterations, rep.fit.iterations == 1 ? "" : "s",
      rep.fit.converged ? " (converged)" : " (not converged)");
  size_t keyWidth = 3, startWidth = 5;
  for (size_t k = 0; k < setup.keys.size(); ++k) {
    keyWidth = std::max(keyWidth, setup.keys[k].key.size());
    startWidth = std::max(startWidth, calibValueText(rep.start[k]).size());
  }
  out += fmt::format("{:<{}}  {:>{}}    {}\n", "key", keyWidth, "start", startWidth, "fitted");
  for (size_t k = 0; k < setup.keys.size(); ++k)
    out += fmt::format("{:<{}}  {:>{}} -> {}{}\n", setup.keys[k].key, keyWidth, calibValueText(rep.start[k]),
                       startWidth, calibValueText(rep.fitted[k]), rep.fit.determined[k] ? "" : " (not determined)");
  size_t progWidth = 7;
  for (const Measurement& m : rows)
    progWidth = std::max(progWidth, support::escapeForTerminal(m.program).size());
  out += fmt::format("{:<{}}  {:>12}  {:>12}  {:>12}  {:>10}\n", "program", progWidth, "measured_s", "model_s",
                     "residual_s", "residual_%");
  for (size_t i = 0; i < rows.size(); ++i) {
    const double r = rep.model[i] - rows[i].cycleTimeS;
    out += fmt::format("{:<{}}  {:>12}  {:>12}  {:>12}  {:>10}\n", support::escapeForTerminal(rows[i].program),
                       progWidth, sim::formatNumber(rows[i].cycleTimeS), sim::formatNumber(rep.model[i]),
                       sim::formatNumber(r), calibPercent(r, rows[i].cycleTimeS));
  }
  const auto [rmsS, rmsPct] = calibRms(setup, rep);
  out += fmt::format("rms residual: {} s ({} %)\n", sim::formatNumber(rmsS), calibPercentText(rmsPct));
  for (const std::string& w : rep.warnings)
    out += "warning: " + support::escapeForTerminal(w) + "\n";
  return out;
}

std::string calibJson(const CalibSetup& setup, const CalibReport& rep, const std::string& output) {
  using J = nlohmann::ordered_json;
  J j;
  j["format_version"] = 1;
  j["calibration"] = setup.data.path;
  j["machine"] = setup.machinePath.empty() ? J(nullptr) : J(setup.machinePath);
  j["output"] = output.empty() ? J(nullptr) : J(output);
  j["iterations"] = rep.fit.iterations;
  j["converged"] = rep.fit.converged;
  j["keys"] = J::array();
  for (size_t k = 0; k < setup.keys.size(); ++k)
    j["keys"].push_back({{"key", setup.keys[k].key},
                         {"start", rep.start[k]},
                         {"fitted", rep.fitted[k]},
                         {"determined", static_cast<bool>(rep.fit.determined[k])}});
  j["rows"] = J::array();
  const auto& rows = setup.data.rows;
  for (size_t i = 0; i < rows.size(); ++i) {
    const double r = rep.model[i] - rows[i].cycleTimeS;
    j["rows"].push_back({{"program", rows[i].program},
                         {"measured_s", rows[i].cycleTimeS},
                         {"model_s", sim::jsonNumber(rep.model[i])},
                         {"residual_s", sim::jsonNumber(r)},
                         {"residual_pct", J::parse(calibPercent(r, rows[i].cycleTimeS))}});
  }
  const auto [rmsS, rmsPct] = calibRms(setup, rep);
  j["rms_s"] = sim::jsonNumber(rmsS);
  j["rms_pct"] = J::parse(calibPercentText(rmsPct));
  j["warnings"] = rep.warnings;
  return j.dump(2) + "\n";
}

/// The fit of the setup's keys: the report, or the exit code of a run that is not ok on the
/// starting machine (printed).
int calibFit(const CalibSetup& setup, const CalibrateOptions& opts, CalibReport& rep, Io& io) {
  std::vector<FitParameter> params;
  for (const CalibKey& k : setup.keys) {
    FitParameter p;
    p.start = k.number.value;
    p.logScale = k.number.positive && k.number.lower == 0 && k.number.value > 0;
    p.lower = k.number.lower;
    p.upper = k.number.upper;
    params.push_back(p);
    rep.start.push_back(k.number.value);
  }
  const auto startRuns = calibRuns(setup, opts, {rep.start});
  for (size_t p = 0; p < setup.programs.size(); ++p)
    if (startRuns[0][p].status != sim::Status::Ok) {
      io.err << fmt::format("isosim: error: {}: the run on the starting machine ended in {}: {}; nothing was "
                            "fitted\n",
                            support::escapeForTerminal(setup.programs[p].path), sim::statusName(startRuns[0][p].status),
                            support::escapeForTerminal(startRuns[0][p].message));
      return startRuns[0][p].status == sim::Status::Emergency ? kExitEmergency : kExitErrors;
    }
  const FitModel model = [&](const std::vector<std::vector<double>>& points) {
    const auto runs = calibRuns(setup, opts, points);
    std::vector<std::optional<std::vector<double>>> out;
    for (const auto& r : runs)
      out.push_back(calibResiduals(setup, r));
    return out;
  };
  rep.fit = fitLeastSquares(params, model);
  if (rep.fit.failed) throw std::logic_error("a calibration whose start runs ok failed at its start");
  rep.fitted = rep.fit.values;
  for (size_t k = 0; k < params.size(); ++k)
    rep.fitted[k] = rep.fit.determined[k] ? calibRounded(params[k], rep.fitted[k]) : rep.start[k];
  auto finalRuns = calibRuns(setup, opts, {rep.fitted});
  if (!calibResiduals(setup, finalRuns[0])) { // the rounded values fail where the fitted ones ran
    rep.fitted = rep.fit.values;
    finalRuns = calibRuns(setup, opts, {rep.fitted});
  }
  for (size_t i = 0; i < setup.data.rows.size(); ++i)
    rep.model.push_back(finalRuns[0][setup.data.programOf[i]].cycleTimeS);
  rep.warnings = calibWarnings(setup, rep);
  return kExitOk;
}

} // namespace

int runCalibrate(const CalibrateOptions& opts, Io& io) {
  std::string format;
  if (int rc = checkCalibrateOptions(opts, io, format); rc != kExitOk) return rc;
  CalibSetup setup;
  if (int rc = calibSetup(opts, setup, io); rc != kExitOk) return rc;
  CalibReport rep;
  if (int rc = calibFit(setup, opts, rep, io); rc != kExitOk) return rc;
  const std::string& output = opts.run.output;
  if (!output.empty()) {
    auto fitted = overriddenMachine(setup.bases[0].m, calibSets(setup, rep.fitted));
    if (!fitted) throw std::logic_error("the fitted machine is not valid: " + fitted.error().message);
    fitted->builtin = false;
    if (support::Status w = support::writeFileAtomically(output, machine::machineToJson(*fitted)); !w) {
      io.err << fmt::format("{}: error: cannot write the fitted machine file: {}\n", support::escapeForTerminal(output),
                            w.why());
      return kExitUsage;
    }
  }
  io.out << (format == "json" ? calibJson(setup, rep, output) : calibText(setup, rep));
  return kExitOk;
}

} // namespace iso::driver
