//! @file SvgPlot.h
//! @brief `isosim --plot`: position and velocity against time for the axes that move, with
//!        block boundaries and events marked, as a self-contained SVG. Deterministic bytes.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "sim/PathPlot.h"
#include "sim/Trace.h"

namespace iso::sim {

/// One panel of the path view: a plane, and the axes of it the machine does not have.
struct PathPanel {
  PathPlane plane = PathPlane::XY;
  std::string missing; ///< "" = none
};
/// The path view drawn below the time panels (sim/PathPlot.h): one panel per plane, stacked.
struct PathView {
  const PathRecorder* path = nullptr;
  std::vector<PathPanel> panels{};
};

/// Collects samples while a simulation runs, in bounded memory, for panels of position and
/// velocity against time. Samples fall in time buckets (at most `maxBuckets`; when the run
/// outgrows them, neighbours merge and the bucket width doubles), and each bucket keeps, per
/// axis, the minimum and the maximum of position and velocity with their times. At render()
/// the buckets are merged again per pixel column and each column draws its minimum and its
/// maximum: a peak of any length stays in the plot, however long the run (no aliasing). The
/// first and the latest sample are always drawn, so the curves span the run.
class PlotRecorder {
public:
  PlotRecorder(std::vector<std::string> axisNames, size_t maxBuckets = 8192);

  /// A sample at time t (seconds, increasing): positions (mm) and velocities (mm/s) per axis.
  void addSample(double t, const double* pos, const double* vel);
  /// A block boundary (Block), an event (Event: M, WHEN, dwell), an M0 stop (Stop) or the
  /// error that ended the run (Error) at time t; the label is the marker's tooltip. A run of
  /// more than kMaxBlockMarkers blocks draws no block marker (they would fill the panels);
  /// past 2000 markers the most numerous kind keeps every other marker; Error markers are
  /// always kept. Markers of one kind in one pixel column are drawn once.
  enum class MarkerKind : uint8_t { Block, Event, Stop, Error };
  void addMarker(double t, MarkerKind kind, std::string label);

  /// The SVG document. `title` is shown on top (e.g. the program name and cycle time); with a
  /// path, the tool path view is drawn below the time panels.
  /// `notes`: what the plot leaves out (capNotes()), drawn under the title.
  std::string render(const std::string& title, const PathView* path = nullptr,
                     const std::vector<std::string>& notes = {}) const;
  /// What the plot leaves out, one note per kind of marker thinned (past 2000 markers): "" none.
  std::vector<std::string> capNotes() const;

  static constexpr size_t kMaxBlockMarkers = 2000;

  /// The curve of an axis decimated to `columns` columns over [0, t1]: per column its minimum
  /// and maximum in time order, between the first and the latest sample (for --timeline's
  /// counter tracks).
  std::vector<std::pair<double, double>> series(size_t axis, bool velocity, double t1, double columns) const {
    return curve(axis, velocity, t1, columns);
  }
  /// Whether the axis moves: its position changes or its velocity is not 0 somewhere.
  bool moves(size_t axis) const;
  const std::vector<std::string>& axisNames() const { return names_; }

  size_t sampleCount() const;                        ///< buckets holding samples
  size_t samplesOffered() const { return offered_; } ///< samples given to addSample
  size_t markerCount() const { return markers_.size(); }

private:
  struct Extreme {
    double t = 0, v = 0;
  };
  /// Per bucket and axis: minimum and maximum of position and of velocity.
  struct Cell {
    Extreme pmin, pmax, vmin, vmax;
  };
  void merge();
  void thinMarkers();
  /// The points of one curve: per pixel column its extremes in time order, between the first
  /// and the latest sample. `toX` maps a time to its pixel column.
  std::vector<std::pair<double, double>> curve(size_t axis, bool velocity, double t1, double plotW) const;
  std::string markerLines(const std::function<double(double)>& toX, double top, double bottom) const;
  /// The legend of the time panels: the axes drawn, then the kinds of markers there are.
  std::string legend(const std::vector<size_t>& axes, double lx, double ly) const;

  std::vector<std::string> names_;
  size_t max_;
  double width_ = 1.0 / 1024; ///< bucket width (s), a power of two
  size_t offered_ = 0;
  std::vector<uint8_t> used_; ///< per bucket
  std::vector<Cell> cells_;   ///< bucket-major, names_.size() per bucket
  double firstT_ = 0, lastT_ = 0;
  std::vector<double> firstPos_, firstVel_, lastPos_, lastVel_;
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
  uint64_t blocks_ = 0;                  ///< block markers offered
};

/// A TraceSink that feeds a PlotRecorder: samples with the exact axis velocities, `line` events
/// as block boundaries, M sequences, WHEN and dwells as events, M0 as stops, and the error of a
/// run that does not end well; and a PathRecorder: the path of X, Y and Z, a vertex at each
/// move's start and end, rapids from the G code of each move. It writes nothing; render() once
/// the run is over.
class PlotSink : public TraceSink {
public:
  explicit PlotSink(size_t maxSamples = 8192) : max_(maxSamples) {}
  /// The plane of the path view; without it, a panel per plane whose two axes move (the plane
  /// most moves were programmed in first), or that plane alone when no two axes move.
  void setPlane(PathPlane p) { plane_ = p; }
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
  /// What the plot leaves out (thinned markers, a simplified tool path), as render() prints it
  /// under the title; empty when it shows everything. The driver adds these to the summary's
  /// warnings.
  std::vector<std::string> capNotes() const;

private:
  void pathPoint(bool corner);

  size_t max_;
  std::optional<PlotRecorder> rec_;
  std::vector<double> prevPos_, vel_;
  double prevT_ = 0;
  bool havePrev_ = false;
  // the path: X, Y, Z as machine axis indexes (-1: not on the machine)
  std::optional<PathPlane> plane_;
  PathRecorder path_;
  std::array<int, 3> xyz_{-1, -1, -1};
  std::vector<double> lastPos_, lastVel_, target_; ///< per machine axis, at lastT_
  std::vector<uint8_t> moveMotion_;                ///< per machine axis: the G code of its move
  std::vector<char> letters_;                      ///< machine axis names
  double lastT_ = 0;
};

} // namespace iso::sim
