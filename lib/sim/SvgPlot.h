//! @file SvgPlot.h
//! @brief `isosim --plot`: position and velocity against time for the axes that move, with
//!        block boundaries and events marked, as a self-contained SVG. Deterministic bytes.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace iso::sim {

/// Collects samples while a simulation runs, in bounded memory: past `maxSamples` it keeps every
/// other sample and doubles its stride, so a one-hour run costs no more than a one-minute one.
class PlotRecorder {
public:
  PlotRecorder(std::vector<std::string> axisNames, size_t maxSamples = 8192);

  /// A sample at time t (seconds, increasing): positions (mm) and velocities (mm/s) per axis.
  void addSample(double t, const double* pos, const double* vel);
  /// A block boundary (kind Block) or an event (M, WHEN, dwell, stop, error) at time t.
  enum class MarkerKind : uint8_t { Block, Event, Stop };
  void addMarker(double t, MarkerKind kind, std::string label);

  /// The SVG document. `title` is shown on top (e.g. the program name and cycle time).
  std::string render(const std::string& title) const;

  size_t sampleCount() const { return t_.size(); }

private:
  void thin();

  std::vector<std::string> names_;
  size_t max_;
  size_t stride_ = 1;   ///< keep one sample of every stride_ offered
  size_t offered_ = 0;
  std::vector<double> t_;
  std::vector<std::vector<double>> pos_, vel_;
  struct Marker {
    double t;
    MarkerKind kind;
    std::string label;
  };
  std::vector<Marker> markers_;
  size_t markerStride_ = 1, markersOffered_ = 0;
};

} // namespace iso::sim
