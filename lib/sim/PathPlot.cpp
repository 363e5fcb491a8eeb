//! @file PathPlot.cpp
//! @brief The tool path view: recording with bounded memory, and SVG rendering.
#include "sim/PathPlot.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <unordered_set>

#include <fmt/format.h>

#include "lang/GCodes.h"

#include "sim/TraceWriter.h"
#include "support/CaseFold.h"
#include "support/Text.h"

namespace iso::sim {

namespace {
using support::escapeMarkup;

/// Slow to fast feed: blue through green and orange to red, each hue distinct and dark enough to
/// read on white.
constexpr const char* kSpeedColors[] = {"#313695", "#4575b4", "#1b9e77", "#66a61e",
                                        "#e6ab02", "#f46d43", "#d73027", "#a50026"};
constexpr int kBins = 8;
/// Rapids: thin, grey, dashed, apart from the feed scale.
constexpr const char* kRapidColor = "#8c8c8c";
constexpr const char* kRapidDash = "4,3";
/// A point closer than this to the last one drawn of its polyline is left out (pixels).
constexpr double kMinStepPx = 0.75;

double chebyshev(const std::array<double, 3>& a, const std::array<double, 3>& b) {
  return std::max({std::abs(a[0] - b[0]), std::abs(a[1] - b[1]), std::abs(a[2] - b[2])});
}

std::string tick(double v) {
  if (std::abs(v) < 1e-12) v = 0;
  return fmt::format("{:.6g}", v);
}
} // namespace

const char* pathPlaneName(PathPlane p) {
  switch (p) {
  case PathPlane::ZX: return "ZX";
  case PathPlane::YZ: return "YZ";
  case PathPlane::XY: break;
  }
  return "XY";
}

std::optional<PathPlane> parsePathPlane(std::string_view name) {
  const std::string n = support::lowerCopy(name);
  if (n == "xy") return PathPlane::XY;
  if (n == "zx") return PathPlane::ZX;
  if (n == "yz") return PathPlane::YZ;
  return std::nullopt;
}

PathRecorder::PathRecorder(size_t maxPoints) : max_(std::max<size_t>(maxPoints, 16)) {}

void PathRecorder::start(const std::array<double, 3>& xyz) {
  started_ = true;
  start_ = xyz;
  pts_.clear();
  pts_.push_back({xyz, 0.0f, false, true, file_, line_});
  pending_ = {};
}

void PathRecorder::setLine(std::string_view file, uint32_t line) {
  line_ = line;
  if (files_[file_] == file) return;
  const auto it = std::find(files_.begin(), files_.end(), file);
  if (it != files_.end()) {
    file_ = static_cast<uint16_t>(it - files_.begin());
  } else if (files_.size() < 65535) {
    files_.emplace_back(file);
    file_ = static_cast<uint16_t>(files_.size() - 1);
  }
}

std::array<bool, 3> PathRecorder::moved() const {
  std::array<bool, 3> m{};
  if (pts_.empty()) return m;
  std::array<double, 3> lo = pts_.front().p, hi = lo;
  auto widen = [&](const Point& pt) {
    for (size_t c = 0; c < 3; ++c) {
      lo[c] = std::min(lo[c], pt.p[c]);
      hi[c] = std::max(hi[c], pt.p[c]);
    }
  };
  for (const Point& pt : pts_)
    widen(pt);
  if (hasLast_) widen(last_);
  for (size_t c = 0; c < 3; ++c)
    m[c] = hi[c] - lo[c] > 1e-3;
  return m;
}

void PathRecorder::add(const std::array<double, 3>& xyz, double speed, bool rapid, bool corner) {
  if (!started_) start(xyz);
  last_ = {xyz, std::max(static_cast<float>(speed), pending_[rapid ? 1 : 0]), rapid, corner, file_, line_};
  hasLast_ = true;
  const Point& prev = pts_.back();
  const double d = chebyshev(prev.p, xyz);
  const bool special = corner || rapid != prev.rapid;
  if (d >= tol_ || (special && d >= tol_ / 2)) {
    pts_.push_back(last_);
    pending_ = {};
    hasLast_ = false;
    if (pts_.size() >= max_) thin();
  } else {
    // merged into the next point kept: the segment's colour is its fastest instant
    // (a feed point never takes the speed of a rapid merged into it, nor the other way round)
    float& p = pending_[rapid ? 1 : 0];
    p = std::max(p, static_cast<float>(speed));
  }
}

std::string PathRecorder::capNote() const {
  if (!(tol_ > kInitialTolerance)) return "";
  return fmt::format("the tool path is drawn to within {} mm (at most {} points)", formatNumber(tol_), max_);
}

void PathRecorder::thin() {
  while (pts_.size() > max_ / 2) {
    tol_ *= 2;
    std::vector<Point> kept;
    kept.reserve(pts_.size());
    std::array<float, 2> carried{}; // per style: feed, rapid
    for (const Point& pt : pts_) {
      if (kept.empty()) {
        kept.push_back(pt);
        continue;
      }
      const double d = chebyshev(kept.back().p, pt.p);
      const bool special = pt.corner || pt.rapid != kept.back().rapid;
      if (d >= tol_ || (special && d >= tol_ / 2)) {
        kept.push_back(pt);
        kept.back().speed = std::max(kept.back().speed, carried[kept.back().rapid ? 1 : 0]);
        carried = {};
      } else {
        float& c = carried[pt.rapid ? 1 : 0];
        c = std::max(c, pt.speed);
      }
    }
    pts_ = std::move(kept);
  }
}

PathPlane PathRecorder::activePlane() const {
  size_t best = 0;
  for (size_t i = 1; i < 3; ++i)
    if (planeMoves_[i] > planeMoves_[best]) best = i;
  return static_cast<PathPlane>(17 + best);
}

namespace {
/// The legend of the path view: the feed speed classes (the scale of the feed moves only), the
/// rapid style, the start and end marks.
std::string pathLegend(double legendX, double y, double flo, double fhi, bool feeds, bool rapids) {
  std::string s;
  double ly = y + 10;
  s += fmt::format("<g class=\"path-legend\">\n<text x=\"{}\" y=\"{}\">path speed (mm/s)</text>\n", legendX, ly + 4);
  s += fmt::format("<text x=\"{}\" y=\"{}\">of the feed moves</text>\n", legendX, ly + 20);
  ly += 34;
  const bool one = !(fhi - flo > 1e-9);
  if (!feeds) {
    s += fmt::format("<text x=\"{}\" y=\"{}\">no feed move</text>\n", legendX, ly + 4);
    ly += 16;
  }
  for (int c = kBins - 1; feeds && c >= 0; --c) {
    if (one && c != 0) continue;
    auto at = [&](int k) { return formatNumber(std::round((flo + (fhi - flo) * k / kBins) * 10) / 10); };
    s += fmt::format("<rect class=\"speed-class\" x=\"{}\" y=\"{}\" width=\"24\" height=\"12\" fill=\"{}\"/>\n",
                     legendX, ly - 6, kSpeedColors[c]);
    s += fmt::format("<text x=\"{}\" y=\"{}\">{}</text>\n", legendX + 30, ly + 4,
                     one ? at(0) : fmt::format("{} - {}", at(c), at(c + 1)));
    ly += 16;
  }
  ly += 10;
  if (rapids) {
    s += fmt::format("<line x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\" stroke=\"{}\" stroke-width=\"1\" "
                     "stroke-dasharray=\"{}\"/>\n",
                     legendX, ly, legendX + 24, ly, kRapidColor, kRapidDash);
    s += fmt::format("<text x=\"{}\" y=\"{}\">rapid (G00)</text>\n", legendX + 30, ly + 4);
    ly += 18;
  }
  s += fmt::format("<circle cx=\"{}\" cy=\"{}\" r=\"5\" fill=\"#2ca02c\" stroke=\"black\"/>\n", legendX + 12, ly);
  s += fmt::format("<text x=\"{}\" y=\"{}\">start</text>\n", legendX + 30, ly + 4);
  ly += 18;
  s += fmt::format("<rect x=\"{}\" y=\"{}\" width=\"10\" height=\"10\" fill=\"#d62728\" stroke=\"black\"/>\n",
                   legendX + 7, ly - 5);
  s += fmt::format("<text x=\"{}\" y=\"{}\">end</text>\n</g>\n", legendX + 30, ly + 4);
  return s;
}

/// The pixel a point of the view falls in, as one key.
uint64_t pixelCell(double x, double y) {
  return (static_cast<uint64_t>(static_cast<uint32_t>(static_cast<int32_t>(std::floor(x)))) << 32) |
         static_cast<uint32_t>(static_cast<int32_t>(std::floor(y)));
}

/// The grid of the path view: nice steps in mm, the same step both ways, and the axis names.
std::string pathGrid(double x, double y, double w, double h, double k, double mh, double mv, const std::string& nh,
                     const std::string& nv) {
  std::string s;
  const double cx = x + w / 2, cy = y + h / 2;
  const double raw = 100 / k; // about one line per 100 px
  const double p10 = std::pow(10.0, std::floor(std::log10(raw)));
  const double m = raw / p10;
  const double step = (m < 1.5 ? 1 : m < 3.5 ? 2 : m < 7.5 ? 5 : 10) * p10;
  const double h0 = mh - (w / 2) / k, h1 = mh + (w / 2) / k, v0 = mv - (h / 2) / k, v1 = mv + (h / 2) / k;
  for (auto kk = static_cast<long long>(std::ceil(h0 / step)); static_cast<double>(kk) * step <= h1; ++kk) {
    const double xv = cx + (static_cast<double>(kk) * step - mh) * k;
    s += fmt::format("<line x1=\"{:.2f}\" y1=\"{}\" x2=\"{:.2f}\" y2=\"{}\" stroke=\"#eee\"/>\n", xv, y, xv, y + h);
    s += fmt::format("<text x=\"{:.2f}\" y=\"{}\" text-anchor=\"middle\">{}</text>\n", xv, y + h + 16,
                     tick(static_cast<double>(kk) * step));
  }
  for (auto kk = static_cast<long long>(std::ceil(v0 / step)); static_cast<double>(kk) * step <= v1; ++kk) {
    const double yv = cy - (static_cast<double>(kk) * step - mv) * k;
    s += fmt::format("<line x1=\"{}\" y1=\"{:.2f}\" x2=\"{}\" y2=\"{:.2f}\" stroke=\"#eee\"/>\n", x, yv, x + w, yv);
    s += fmt::format("<text x=\"{}\" y=\"{:.2f}\" text-anchor=\"end\">{}</text>\n", x - 6, yv + 4,
                     tick(static_cast<double>(kk) * step));
  }
  s += fmt::format("<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">{} (mm)</text>\n", x + w / 2, y + h + 32, nh);
  s += fmt::format("<text x=\"{}\" y=\"{}\" transform=\"rotate(-90 {} {})\" text-anchor=\"middle\">{} (mm)</text>\n",
                   x - 50, y + h / 2, x - 50, y + h / 2, nv);
  return s;
}
} // namespace

std::string PathRecorder::render(PathPlane plane, double x, double y, double w, double h, double legendX,
                                 const std::string& missing, bool legend) const {
  // across and up: the plane's first and second axis (G17 X Y, G18 Z X, G19 Y Z); the path's
  // coordinates are X Y Z, in the order of the arc-centre words I J K
  const lang::PlaneAxes pa = lang::planeAxes(static_cast<int>(plane));
  const auto ih = static_cast<size_t>(pa.pWord), iv = static_cast<size_t>(pa.qWord);
  const std::string nh(1, pa.p), nv(1, pa.q);
  std::vector<Point> pts = pts_;
  if (hasLast_) pts.push_back(last_);
  std::string s;
  s += fmt::format("<g class=\"path-view\" data-plane=\"{}\">\n", pathPlaneName(plane));
  s += fmt::format("<text x=\"{}\" y=\"{}\" font-size=\"14\" font-weight=\"bold\">tool path, plane {} (G{}): {} "
                   "right, {} up, same scale</text>\n",
                   x, y - 10, pathPlaneName(plane), static_cast<int>(plane), nh, nv);
  s += fmt::format("<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"none\" stroke=\"#333\"/>\n", x, y, w, h);
  if (!missing.empty())
    s += fmt::format("<text x=\"{}\" y=\"{}\">no axis {}: at 0</text>\n", legendX, y + h - 6, missing);
  double hlo = 0, hhi = 0, vlo = 0, vhi = 0, flo = 0, fhi = 0;
  bool feeds = false, rapids = false;
  for (size_t i = 0; i < pts.size(); ++i) {
    const double a = pts[i].p[ih], b = pts[i].p[iv];
    if (i == 0) {
      hlo = hhi = a;
      vlo = vhi = b;
    }
    hlo = std::min(hlo, a);
    hhi = std::max(hhi, a);
    vlo = std::min(vlo, b);
    vhi = std::max(vhi, b);
    if (i == 0) continue;
    rapids = rapids || pts[i].rapid;
    if (pts[i].rapid) continue;
    // the feed scale: the speeds of feed segments only, rapids apart
    const auto v = static_cast<double>(pts[i].speed);
    flo = feeds ? std::min(flo, v) : v;
    fhi = feeds ? std::max(fhi, v) : v;
    feeds = true;
  }
  bool moves = false;
  for (size_t i = 1; i < pts.size() && !moves; ++i)
    moves = std::abs(pts[i].p[ih] - pts[0].p[ih]) > 1e-9 || std::abs(pts[i].p[iv] - pts[0].p[iv]) > 1e-9;
  if (!moves) {
    s += fmt::format("<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">no motion in the {} plane</text>\n</g>\n",
                     x + w / 2, y + h / 2, pathPlaneName(plane));
    return s;
  }
  // Equal scales: one mm is the same length across and up; the range is centred in the box.
  const double pad = 12;
  const double span = std::max({hhi - hlo, vhi - vlo, 1e-6});
  const double k =
      std::min((w - 2 * pad) / std::max(hhi - hlo, span * 1e-3), (h - 2 * pad) / std::max(vhi - vlo, span * 1e-3));
  const double cx = x + w / 2, cy = y + h / 2, mh = (hlo + hhi) / 2, mv = (vlo + vhi) / 2;
  auto px = [&](const Point& p) { return cx + (p.p[ih] - mh) * k; };
  auto py = [&](const Point& p) { return cy - (p.p[iv] - mv) * k; };
  s += pathGrid(x, y, w, h, k, mh, mv, nh, nv);
  // the path: polylines of one style (rapid, or a feed speed class), and of one line while
  // there are not too many line changes
  auto bin = [&](const Point& p) {
    if (p.rapid) return -1;
    if (!(fhi - flo > 1e-9)) return 0;
    return std::clamp(static_cast<int>((static_cast<double>(p.speed) - flo) / (fhi - flo) * kBins), 0, kBins - 1);
  };
  size_t lineChanges = 0;
  for (size_t i = 2; i < pts.size(); ++i)
    lineChanges += pts[i].line != pts[i - 1].line || pts[i].file != pts[i - 1].file;
  const bool byLine = lineChanges <= kMaxLineRuns;
  auto same = [&](size_t a, size_t b) {
    return bin(pts[a]) == bin(pts[b]) && (!byLine || (pts[a].line == pts[b].line && pts[a].file == pts[b].file));
  };
  // Per pixel and class: a short step between two pixels the class has painted already adds
  // nothing the eye can see (a pass over the same ground): the pen lifts there.
  std::array<std::unordered_set<uint64_t>, kBins + 1> painted;
  size_t i = 1;
  while (i < pts.size()) {
    const size_t first = i;
    const int b = bin(pts[i]);
    std::unordered_set<uint64_t>& seen = painted[static_cast<size_t>(b + 1)];
    double lx = px(pts[i - 1]), ly = py(pts[i - 1]); // the pen
    bool down = false;
    for (; i < pts.size() && same(i, first); ++i) {
      const double xx = px(pts[i]), yy = py(pts[i]);
      const double step = std::hypot(xx - lx, yy - ly);
      const bool lastOfRun = i + 1 == pts.size() || !same(i + 1, first);
      const uint64_t c0 = pixelCell(lx, ly), c1 = pixelCell(xx, yy);
      if (step <= 2 && seen.count(c0) && seen.count(c1)) {
        if (down) s += "\"/>\n";
        down = false;
        lx = xx;
        ly = yy;
        continue;
      }
      if (down && !lastOfRun && step < kMinStepPx) continue;
      if (!down)
        s += fmt::format("<polyline class=\"path\" data-kind=\"{}\" data-file=\"{}\" data-line=\"{}\" fill=\"none\" "
                         "stroke=\"{}\" stroke-width=\"{}\"{} points=\"{:.2f},{:.2f}",
                         b < 0 ? "rapid" : "feed", escapeMarkup(files_[pts[first].file]), pts[first].line,
                         b < 0 ? kRapidColor : kSpeedColors[b], b < 0 ? 1 : 2.5,
                         b < 0 ? fmt::format(" stroke-dasharray=\"{}\"", kRapidDash) : std::string(), lx, ly);
      down = true;
      s += fmt::format(" {:.2f},{:.2f}", xx, yy);
      seen.insert(c0);
      seen.insert(c1);
      lx = xx;
      ly = yy;
    }
    if (down) s += "\"/>\n";
  }
  const Point& first = pts.front();
  const Point& last = pts.back();
  s += fmt::format("<circle class=\"start\" cx=\"{:.2f}\" cy=\"{:.2f}\" r=\"6\" fill=\"#2ca02c\" stroke=\"black\">"
                   "<title>start</title></circle>\n",
                   px(first), py(first));
  s += fmt::format("<rect class=\"end\" x=\"{:.2f}\" y=\"{:.2f}\" width=\"10\" height=\"10\" fill=\"#d62728\" "
                   "stroke=\"black\"><title>end</title></rect>\n",
                   px(last) - 5, py(last) - 5);
  if (legend) s += pathLegend(legendX, y, flo, fhi, feeds, rapids);
  s += "</g>\n";
  return s;
}

} // namespace iso::sim
