//! @file SvgPlot.h
//! @brief `isosim --plot`: position and velocity against time for the axes that move, with
//!        block boundaries and events marked, as a self-contained SVG. Deterministic bytes.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "sim/Trace.h"

namespace iso::sim {

/// Collects samples while a simulation runs, in bounded memory: past `maxSamples` it keeps every
/// other sample and doubles its stride, so a one-hour run costs no more than a one-minute one.
/// The latest sample offered is always drawn, so the plot reaches the end of the run.
class PlotRecorder {
public:
  PlotRecorder(std::vector<std::string> axisNames, size_t maxSamples = 8192);

  /// A sample at time t (seconds, increasing): positions (mm) and velocities (mm/s) per axis.
  void addSample(double t, const double* pos, const double* vel);
  /// A block boundary (Block), an event (Event: M, WHEN, dwell), an M0 stop (Stop) or the
  /// error that ended the run (Error) at time t; the label is the marker's tooltip. Past 2000
  /// markers the most numerous kind keeps every other marker; Error markers are always kept.
  enum class MarkerKind : uint8_t { Block, Event, Stop, Error };
  void addMarker(double t, MarkerKind kind, std::string label);

  /// The SVG document. `title` is shown on top (e.g. the program name and cycle time).
  std::string render(const std::string& title) const;

  size_t sampleCount() const { return t_.size(); }
  size_t markerCount() const { return markers_.size(); }

private:
  void thin();
  void thinMarkers();

  std::vector<std::string> names_;
  size_t max_;
  size_t stride_ = 1;   ///< keep one sample of every stride_ offered
  size_t offered_ = 0;
  std::vector<double> t_;
  std::vector<std::vector<double>> pos_, vel_;
  /// The latest sample offered when the stride did not keep it (drawn last).
  bool hasTail_ = false;
  double tailT_ = 0;
  std::vector<double> tailPos_, tailVel_;
  struct Marker {
    double t;
    MarkerKind kind;
    std::string label;
  };
  std::vector<Marker> markers_;
  struct Thinning {
    size_t stride = 1, offered = 0;
  };
  std::array<Thinning, 3> markerThin_{}; ///< Block, Event, Stop (Error markers are never thinned)
};

/// A TraceSink that feeds a PlotRecorder: samples with the exact axis velocities, `line` events
/// as block boundaries, M sequences, WHEN and dwells as events, M0 as stops, and the error of a
/// run that does not end well. It writes nothing; render() once the run is over.
class PlotSink : public TraceSink {
public:
  explicit PlotSink(size_t maxSamples = 8192) : max_(maxSamples) {}
  void begin(const machine::Machine& m) override;
  /// Without velocities (a caller that ignores wantsVelocities()): backward differences.
  void sample(double t, const double* positions) override;
  void sampleWithVelocity(double t, const double* positions, const double* velocities) override;
  void event(const Event& e) override;
  void end(const Summary&) override {}
  bool wantsVelocities() const override { return true; }

  /// The plot; before begin() (a run that never started) a plot of nothing.
  std::string render(const std::string& title) const;
  /// Null before begin().
  const PlotRecorder* recorder() const { return rec_ ? &*rec_ : nullptr; }

private:
  size_t max_;
  std::optional<PlotRecorder> rec_;
  std::vector<double> prevPos_, vel_;
  double prevT_ = 0;
  bool havePrev_ = false;
};

} // namespace iso::sim
