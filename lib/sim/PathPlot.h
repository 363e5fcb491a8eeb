//! @file PathPlot.h
//! @brief The tool path view of `isosim --plot`: the path of X, Y and Z drawn in a plane
//!        (G17 XY, G18 ZX, G19 YZ), feed moves coloured by path speed on a scale of the feed
//!        moves only, rapids thin, grey and dashed, start and end marked, equal scales on both
//!        axes, each segment tagged with its source line. Bounded memory and output whatever
//!        the length of the run.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace iso::sim {

/// A plane of the path view, named by its G code.
enum class PathPlane : uint8_t { XY = 17, ZX = 18, YZ = 19 };
const char* pathPlaneName(PathPlane p); ///< "XY", "ZX", "YZ"
/// "xy" | "zx" | "yz" (any case); nullopt for anything else.
std::optional<PathPlane> parsePathPlane(std::string_view name);

/// The tool path, as points of X, Y and Z (mm) with the path speed there. Successive points
/// closer than a tolerance (in every coordinate) to the last one kept are merged into it
/// unless the style changes (rapid or not); past `maxPoints` the tolerance doubles and the
/// points are thinned again, so a run of any length keeps at most `maxPoints` points.
class PathRecorder {
public:
  explicit PathRecorder(size_t maxPoints = 200000);

  /// The source line the next points belong to (the main program's current line).
  void setLine(std::string_view file, uint32_t line);
  /// The position at the start of the run (drawn as the start mark).
  void start(const std::array<double, 3>& xyz);
  /// The tool is at `xyz` moving at `speed` (mm/s, >= 0); `rapid`: the segment that ends here
  /// belongs to a G00 move. `corner`: keep this point whatever the tolerance (a move's end).
  void add(const std::array<double, 3>& xyz, double speed, bool rapid, bool corner = false);
  /// Counts a move of the plane `plane` (the view's plane is the one most moves used).
  void countPlane(PathPlane plane) { ++planeMoves_[static_cast<size_t>(plane) - 17]; }
  /// The plane most moves were programmed in (XY on a tie or when nothing moved).
  PathPlane activePlane() const;

  /// Which of X, Y and Z move at all (their range over the path exceeds 1 µm).
  std::array<bool, 3> moved() const;

  /// The view as SVG elements (no <svg> root) in the box (x, y, w, h) of the caller's
  /// document, with its legend to the right of the box at `legendX` (`legend` false: only the
  /// note on missing axes). `missing` names the axes of the plane the machine does not have
  /// (drawn at 0). Points closer than about a pixel to the last one drawn of their polyline
  /// are left out; each polyline has one style (a rapid, or a feed speed class) and carries
  /// data-file and data-line, the source line of its first segment. Polylines break at each
  /// line change unless there would be more than kMaxLineRuns of them.
  std::string render(PathPlane plane, double x, double y, double w, double h, double legendX,
                     const std::string& missing, bool legend = true) const;
  /// Past this many line changes along the path, polylines break only where the style changes.
  static constexpr size_t kMaxLineRuns = 3000;

  size_t pointCount() const { return pts_.size(); }
  /// The tolerance the path is drawn to (mm): 0.001, doubled each time it outgrew maxPoints.
  double tolerance() const { return tol_; }
  /// What the view leaves out, for its own output and the summary's warnings: "" when the path
  /// is drawn to the initial 0.001 mm, else the tolerance it grew to and the point limit.
  std::string capNote() const;

private:
  struct Point {
    std::array<double, 3> p{};
    float speed = 0;
    bool rapid = false;
    bool corner = false;
    uint16_t file = 0; ///< index in files_
    uint32_t line = 0; ///< 0: before the first line
  };
  void thin();

  static constexpr double kInitialTolerance = 1e-3; ///< mm
  size_t max_;
  double tol_ = kInitialTolerance; ///< mm; doubles when the points exceed max_
  bool started_ = false;
  std::array<double, 3> start_{};
  std::vector<Point> pts_;
  std::array<float, 2> pending_{}; ///< per style (feed, rapid): the fastest speed merged since the last kept point
  bool hasLast_ = false;           ///< the latest point offered, when not kept (drawn last)
  Point last_{};
  std::array<uint64_t, 3> planeMoves_{};
  std::vector<std::string> files_{""}; ///< source files of the points (a program set has few)
  uint16_t file_ = 0;
  uint32_t line_ = 0;
};

} // namespace iso::sim
