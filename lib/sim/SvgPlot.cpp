//! @file SvgPlot.cpp
//! @brief SVG rendering of position/velocity plots.
#include "sim/SvgPlot.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <functional>
#include <utility>

#include <fmt/format.h>

#include "lang/Axes.h"
#include "lang/GCodes.h"

#include "machine/Machine.h"
#include "sim/TraceWriter.h"
#include "support/Text.h"

namespace iso::sim {

namespace {

using support::escapeMarkup;

constexpr const char* kColors[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e",
                                   "#8c564b", "#e377c2", "#17becf", "#7f7f7f"};
/// How each MarkerKind is drawn, and its name in the legend.
struct MarkerStyle {
  const char* color;
  double width;
  const char* dash; ///< a stroke-dasharray attribute, or ""
  const char* name;
};
constexpr std::array<MarkerStyle, 4> kMarkerStyles{{
    {"#bbbbbb", 1, " stroke-dasharray=\"2,3\"", "block"},
    {"#bcbd22", 1.5, " stroke-dasharray=\"4,2\"", "M, WHEN, dwell"},
    {"#7b3294", 1.5, " stroke-dasharray=\"8,3\"", "M0 stop"},
    {"#d62728", 2, "", "error, emergency"},
}};
constexpr size_t kMaxMarkers = 2000;
constexpr double kWidth = 960, kPanelH = 260, kLeft = 80, kRight = 170, kTop = 50, kGap = 60, kPathH = 560,
                 kPathGap = 90;

/// A "nice" tick step for a range (1, 2 or 5 times a power of ten), about `n` ticks.
double niceStep(double range, int n) {
  if (!(range > 0)) return 1;
  double raw = range / n;
  double p = std::pow(10.0, std::floor(std::log10(raw)));
  double m = raw / p;
  double step = m < 1.5 ? 1 : m < 3.5 ? 2 : m < 7.5 ? 5 : 10;
  return step * p;
}

std::string tickLabel(double v) {
  if (std::abs(v) < 1e-12) v = 0;
  std::string s = fmt::format("{:.6g}", v);
  return s;
}

struct Scale {
  double lo, hi, px0, px1;
  double operator()(double v) const { return hi > lo ? px0 + (v - lo) / (hi - lo) * (px1 - px0) : (px0 + px1) / 2; }
};

} // namespace

PlotRecorder::PlotRecorder(std::vector<std::string> axisNames, size_t maxBuckets)
    : names_(std::move(axisNames)), max_(std::max<size_t>(maxBuckets, 16)), firstPos_(names_.size()),
      firstVel_(names_.size()), lastPos_(names_.size()), lastVel_(names_.size()) {}

size_t PlotRecorder::sampleCount() const {
  return static_cast<size_t>(std::count(used_.begin(), used_.end(), uint8_t{1}));
}

void PlotRecorder::merge() {
  // Bucket k and k+1 become bucket k/2: the minimum of the minima, the maximum of the maxima.
  const size_t na = names_.size();
  const size_t n = used_.size();
  auto lower = [](const Extreme& a, const Extreme& b) { return b.v < a.v ? b : a; };
  auto upper = [](const Extreme& a, const Extreme& b) { return b.v > a.v ? b : a; };
  for (size_t k = 0; 2 * k < n; ++k) {
    const size_t l = 2 * k, r = 2 * k + 1;
    const bool hasR = r < n && used_[r];
    for (size_t a = 0; a < na; ++a) {
      Cell c = used_[l] ? cells_[l * na + a] : cells_[r * na + a];
      if (used_[l] && hasR) {
        const Cell& o = cells_[r * na + a];
        c.pmin = lower(c.pmin, o.pmin);
        c.pmax = upper(c.pmax, o.pmax);
        c.vmin = lower(c.vmin, o.vmin);
        c.vmax = upper(c.vmax, o.vmax);
      }
      if (used_[l] || hasR) cells_[k * na + a] = c;
    }
    used_[k] = static_cast<uint8_t>(used_[l] || hasR);
  }
  const size_t half = (n + 1) / 2;
  used_.resize(half);
  cells_.resize(half * na);
  width_ *= 2;
}

void PlotRecorder::addSample(double t, const double* pos, const double* vel) {
  const size_t na = names_.size();
  if (offered_++ == 0) {
    firstT_ = t;
    std::copy(pos, pos + na, firstPos_.begin());
    std::copy(vel, vel + na, firstVel_.begin());
  }
  lastT_ = t;
  std::copy(pos, pos + na, lastPos_.begin());
  std::copy(vel, vel + na, lastVel_.begin());
  const double tt = t > 0 && std::isfinite(t) ? t : 0.0; // sample times are k·dt; never trust a NaN
  while (tt / width_ >= static_cast<double>(max_))
    merge();
  const auto k = static_cast<size_t>(tt / width_);
  if (k >= used_.size()) {
    used_.resize(k + 1, 0);
    cells_.resize((k + 1) * na);
  }
  for (size_t a = 0; a < na; ++a) {
    Cell& c = cells_[k * na + a];
    const Extreme p{t, pos[a]}, v{t, vel[a]};
    if (!used_[k]) {
      c = {p, p, v, v};
      continue;
    }
    if (p.v < c.pmin.v) c.pmin = p;
    if (p.v > c.pmax.v) c.pmax = p;
    if (v.v < c.vmin.v) c.vmin = v;
    if (v.v > c.vmax.v) c.vmax = v;
  }
  used_[k] = 1;
}

bool PlotRecorder::moves(size_t axis) const {
  if (offered_ == 0 || axis >= names_.size()) return false;
  const size_t na = names_.size();
  const double p0 = firstPos_[axis];
  bool m = std::abs(lastPos_[axis] - p0) > 1e-12 || std::abs(lastVel_[axis]) > 1e-12;
  for (size_t k = 0; k < used_.size() && !m; ++k) {
    if (!used_[k]) continue;
    const Cell& c = cells_[k * na + axis];
    m = std::abs(c.pmin.v - p0) > 1e-12 || std::abs(c.pmax.v - p0) > 1e-12 || std::abs(c.vmin.v) > 1e-12 ||
        std::abs(c.vmax.v) > 1e-12;
  }
  return m;
}

std::vector<std::pair<double, double>> PlotRecorder::curve(size_t axis, bool velocity, double t1, double plotW) const {
  std::vector<std::pair<double, double>> pts;
  if (offered_ == 0) return pts;
  const size_t na = names_.size();
  pts.emplace_back(firstT_, velocity ? firstVel_[axis] : firstPos_[axis]);
  // one column per pixel: its extremes, the earlier first
  long long col = -1;
  Extreme lo, hi;
  auto flush = [&] {
    if (col < 0) return;
    const Extreme& e1 = lo.t <= hi.t ? lo : hi;
    const Extreme& e2 = lo.t <= hi.t ? hi : lo;
    if (e1.t >= pts.back().first) pts.emplace_back(e1.t, e1.v);
    if ((e2.t != e1.t || e2.v != e1.v) && e2.t >= pts.back().first) pts.emplace_back(e2.t, e2.v);
  };
  for (size_t k = 0; k < used_.size(); ++k) {
    if (!used_[k]) continue;
    const Cell& c = cells_[k * na + axis];
    const Extreme& mn = velocity ? c.vmin : c.pmin;
    const Extreme& mx = velocity ? c.vmax : c.pmax;
    const auto kc = static_cast<long long>(std::floor(static_cast<double>(k) * width_ / t1 * plotW));
    if (kc != col) {
      flush();
      col = kc;
      lo = mn;
      hi = mx;
      continue;
    }
    if (mn.v < lo.v) lo = mn;
    if (mx.v > hi.v) hi = mx;
  }
  flush();
  if (lastT_ >= pts.back().first) pts.emplace_back(lastT_, velocity ? lastVel_[axis] : lastPos_[axis]);
  return pts;
}

void PlotRecorder::addMarker(double t, MarkerKind kind, std::string label) {
  if (kind == MarkerKind::Block && ++blocks_ > kMaxBlockMarkers) {
    // too many blocks to mark each: none at all (the curves and the path show the motion)
    if (blocks_ == kMaxBlockMarkers + 1)
      std::erase_if(markers_, [](const Marker& m) { return m.kind == MarkerKind::Block; });
    return;
  }
  if (kind != MarkerKind::Error) {
    Thinning& th = markerThin_[static_cast<size_t>(kind)];
    if (th.offered++ % th.stride != 0) return;
  }
  markers_.push_back({t, kind, std::move(label)});
  if (markers_.size() >= kMaxMarkers) thinMarkers();
}

void PlotRecorder::thinMarkers() {
  // Halve the most numerous kind (blocks, usually): every other one stays.
  std::array<size_t, 3> count{};
  for (const auto& m : markers_)
    if (m.kind != MarkerKind::Error) ++count[static_cast<size_t>(m.kind)];
  size_t most = static_cast<size_t>(std::max_element(count.begin(), count.end()) - count.begin());
  std::vector<Marker> kept;
  size_t k = 0;
  for (auto& m : markers_)
    if (static_cast<size_t>(m.kind) != most || (k++ % 2 == 0)) kept.push_back(std::move(m));
  markers_ = std::move(kept);
  markerThin_[most].stride *= 2;
}

std::string PlotRecorder::legend(const std::vector<size_t>& axes, double lx, double ly) const {
  std::string s;
  for (size_t k = 0; k < axes.size(); ++k) {
    s += fmt::format("<line x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\" stroke=\"{}\" stroke-width=\"3\"/>\n", lx, ly,
                     lx + 24, ly, kColors[k % 9]);
    s += fmt::format("<text x=\"{}\" y=\"{}\">axis {}</text>\n", lx + 30, ly + 4, escapeMarkup(names_[axes[k]]));
    ly += 18;
  }
  ly += 14;
  for (size_t kind = 0; kind < kMarkerStyles.size(); ++kind) {
    if (std::none_of(markers_.begin(), markers_.end(),
                     [&](const Marker& m) { return static_cast<size_t>(m.kind) == kind; }))
      continue;
    const MarkerStyle& st = kMarkerStyles[kind];
    s += fmt::format("<line x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\" stroke=\"{}\" stroke-width=\"{}\"{}/>\n", lx, ly,
                     lx + 24, ly, st.color, st.width, st.dash);
    s += fmt::format("<text x=\"{}\" y=\"{}\">{}</text>\n", lx + 30, ly + 4, st.name);
    ly += 18;
  }
  return s;
}

namespace {
/// The red line under the title that says what the plot leaves out ("" when nothing).
/// As many notes as fit the width (about 6 px a character at 11 px), at least the first; the
/// others are counted, and the whole list is the line's tooltip.
std::string capNoteLine(const std::vector<std::string>& notes) {
  if (notes.empty()) return "";
  constexpr size_t kChars = static_cast<size_t>((kWidth - kLeft - 10) / 6);
  std::string all, shown = "not everything is drawn: ";
  size_t fit = 0;
  for (const auto& n : notes) {
    all += (all.empty() ? "" : "; ") + n;
    if (fit == 0 || shown.size() + 2 + n.size() + 20 <= kChars) {
      shown += (fit ? "; " : "") + n;
      ++fit;
    }
  }
  if (fit == notes.size())
    return fmt::format("<text x=\"{}\" y=\"40\" font-size=\"11\" fill=\"#d62728\" class=\"cap-note\">{}</text>\n",
                       kLeft, escapeMarkup(shown));
  shown += fmt::format("; and {} more", notes.size() - fit);
  return fmt::format("<text x=\"{}\" y=\"40\" font-size=\"11\" fill=\"#d62728\" class=\"cap-note\">{}<title>{}</title>"
                     "</text>\n",
                     kLeft, escapeMarkup(shown), escapeMarkup("not everything is drawn: " + all));
}
} // namespace

std::vector<std::string> PlotRecorder::capNotes() const {
  std::vector<std::string> notes;
  if (blocks_ > kMaxBlockMarkers)
    notes.push_back(fmt::format("no block marker ({} lines run; they are drawn up to {})", blocks_, kMaxBlockMarkers));
  for (size_t kind = 0; kind < markerThin_.size(); ++kind) {
    const Thinning& th = markerThin_[kind];
    if (kind == static_cast<size_t>(MarkerKind::Block) && blocks_ > kMaxBlockMarkers) continue;
    if (th.stride > 1)
      notes.push_back(fmt::format("1 {} marker in {} is drawn ({} in all; at most {} markers)",
                                  kMarkerStyles[kind].name, th.stride, th.offered, kMaxMarkers));
  }
  return notes;
}

/// The markers as lines from `top` to `bottom`: one per kind and pixel column, its tooltip the
/// labels of the markers there (the first four).
std::string PlotRecorder::markerLines(const std::function<double(double)>& toX, double top, double bottom) const {
  std::string s;
  struct Drawn {
    double x;
    size_t kind, count;
    std::string title;
  };
  std::vector<Drawn> drawn;
  std::array<size_t, 4> lastOf{SIZE_MAX, SIZE_MAX, SIZE_MAX, SIZE_MAX};
  for (const auto& m : markers_) {
    const auto kind = static_cast<size_t>(m.kind);
    const double x = toX(m.t);
    size_t& last = lastOf[kind];
    if (last != SIZE_MAX && std::floor(drawn[last].x) == std::floor(x) && m.kind != MarkerKind::Error) {
      if (++drawn[last].count <= 4) drawn[last].title += "; " + m.label;
      continue;
    }
    last = drawn.size();
    drawn.push_back({x, kind, 1, m.label});
  }
  for (const Drawn& d : drawn) {
    const MarkerStyle& st = kMarkerStyles[d.kind];
    const std::string more = d.count > 4 ? fmt::format("; and {} more", d.count - 4) : "";
    s += fmt::format("<line x1=\"{:.2f}\" y1=\"{}\" x2=\"{:.2f}\" y2=\"{}\" stroke=\"{}\" stroke-width=\"{}\"{}>"
                     "<title>{}</title></line>\n",
                     d.x, top, d.x, bottom, st.color, st.width, st.dash, escapeMarkup(d.title + more));
  }
  return s;
}

std::string PlotRecorder::render(const std::string& title, const PathView* path,
                                 const std::vector<std::string>& notes) const {
  const double plotW = kWidth - kLeft - kRight;
  double t1 = offered_ == 0 ? 0 : lastT_;
  for (const auto& m : markers_)
    t1 = std::max(t1, m.t);
  if (!(t1 > 1e-9)) t1 = 1; // a run that ends at 0 s: a one-second axis, not a nanosecond one
  const double t0 = 0;
  // Only axes that move; the curves of each, decimated per pixel column.
  std::vector<size_t> axes;
  std::vector<std::array<std::vector<std::pair<double, double>>, 2>> curves;
  for (size_t a = 0; a < names_.size(); ++a) {
    if (!moves(a)) continue;
    std::array<std::vector<std::pair<double, double>>, 2> c{curve(a, false, t1, plotW), curve(a, true, t1, plotW)};
    axes.push_back(a);
    curves.push_back(std::move(c));
  }
  double plo = 0, phi = 0, vlo = 0, vhi = 0;
  bool first = true;
  for (const auto& c : curves) {
    for (const auto& [t, p] : c[0]) {
      if (first) plo = phi = p;
      first = false;
      plo = std::min(plo, p);
      phi = std::max(phi, p);
    }
    for (const auto& [t, v] : c[1]) {
      vlo = std::min(vlo, v);
      vhi = std::max(vhi, v);
    }
  }
  if (phi - plo < 1e-9) {
    plo -= 1;
    phi += 1;
  }
  if (vhi - vlo < 1e-9) {
    vlo -= 1;
    vhi += 1;
  }
  const double pathTop = kTop + 2 * kPanelH + kGap + 90;
  const size_t nPanels = path && path->path ? path->panels.size() : 0;
  const double height = nPanels ? pathTop + static_cast<double>(nPanels) * (kPathH + kPathGap) - kPathGap + 50
                                : kTop + 2 * kPanelH + kGap + 50;
  std::string s;
  s += fmt::format("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{}\" height=\"{}\" viewBox=\"0 0 {} {}\" "
                   "font-family=\"DejaVu Sans, Arial, sans-serif\" font-size=\"12\">\n",
                   kWidth, height, kWidth, height);
  const std::string shown = escapeMarkup(title);
  s += fmt::format("<title>{}</title>\n<rect width=\"{}\" height=\"{}\" fill=\"white\"/>\n", shown, kWidth, height);
  s += fmt::format("<text x=\"{}\" y=\"24\" font-size=\"16\" font-weight=\"bold\">{}</text>\n", kLeft, shown);
  s += capNoteLine(notes);
  Scale tx{t0, t1, kLeft, kLeft + plotW};
  auto panel = [&](double top, double lo, double hi, const char* ylabel, bool velocity) {
    double bottom = top + kPanelH;
    double step = niceStep(hi - lo, 6);
    double glo = std::floor(lo / step) * step, ghi = std::ceil(hi / step) * step;
    Scale ys{glo, ghi, bottom, top};
    // the scale as data too, so that a reader (or a test) can turn a y back into a value
    s += fmt::format("<rect class=\"panel\" data-kind=\"{}\" data-lo=\"{}\" data-hi=\"{}\" data-t1=\"{}\" x=\"{}\" "
                     "y=\"{}\" width=\"{}\" height=\"{}\" fill=\"none\" stroke=\"#333\"/>\n",
                     velocity ? "velocity" : "position", tickLabel(glo), tickLabel(ghi), tickLabel(t1), kLeft, top,
                     plotW, kPanelH);
    // Ticks as k·step, not by repeated addition (no drift, no missing last tick).
    const long long kLo = std::llround(glo / step), kHi = std::llround(ghi / step);
    for (long long k = kLo; k <= kHi; ++k) {
      double v = static_cast<double>(k) * step;
      double y = ys(v);
      s += fmt::format("<line x1=\"{}\" y1=\"{:.2f}\" x2=\"{}\" y2=\"{:.2f}\" stroke=\"#ddd\"/>\n", kLeft, y,
                       kLeft + plotW, y);
      s += fmt::format("<text x=\"{}\" y=\"{:.2f}\" text-anchor=\"end\">{}</text>\n", kLeft - 6, y + 4, tickLabel(v));
    }
    double tstep = niceStep(t1 - t0, 10);
    const auto tHi = static_cast<long long>(std::floor(t1 / tstep + 1e-9));
    for (long long k = 0; k <= tHi; ++k) {
      double v = static_cast<double>(k) * tstep;
      double x = tx(v);
      s += fmt::format("<line x1=\"{:.2f}\" y1=\"{}\" x2=\"{:.2f}\" y2=\"{}\" stroke=\"#eee\"/>\n", x, top, x, bottom);
      s += fmt::format("<text x=\"{:.2f}\" y=\"{}\" text-anchor=\"middle\">{}</text>\n", x, bottom + 16, tickLabel(v));
    }
    s += markerLines(tx, top, bottom);
    for (size_t k = 0; k < axes.size(); ++k) {
      s += fmt::format("<polyline class=\"curve\" fill=\"none\" stroke=\"{}\" stroke-width=\"1.5\" points=\"",
                       kColors[k % 9]);
      bool sep = false;
      for (const auto& [t, v] : curves[k][velocity ? 1 : 0]) {
        s += fmt::format("{}{:.2f},{:.2f}", sep ? " " : "", tx(t), ys(v));
        sep = true;
      }
      s += "\"/>\n";
    }
    s += fmt::format(
        "<text x=\"20\" y=\"{:.2f}\" transform=\"rotate(-90 20 {:.2f})\" text-anchor=\"middle\">{}</text>\n",
        (top + bottom) / 2, (top + bottom) / 2, ylabel);
    s += fmt::format("<text x=\"{:.2f}\" y=\"{}\" text-anchor=\"middle\">time (s)</text>\n", kLeft + plotW / 2,
                     bottom + 32);
  };
  panel(kTop, plo, phi, "position (mm, rotary axes: deg)", false);
  panel(kTop + kPanelH + kGap, vlo, vhi, "velocity (mm/s, rotary axes: deg/s)", true);
  s += legend(axes, kLeft + plotW + 16, kTop + 10);
  if (axes.empty())
    s += fmt::format("<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">no axis moves</text>\n", kLeft + plotW / 2,
                     kTop + kPanelH / 2);
  for (size_t k = 0; k < nPanels; ++k) {
    // square boxes as wide as the panels allow, centred under them, one under the other; the
    // legend beside the first
    const double side = std::min(plotW, kPathH);
    const PathPanel& pp = path->panels[k];
    s +=
        path->path->render(pp.plane, kLeft + (plotW - side) / 2, pathTop + static_cast<double>(k) * (kPathH + kPathGap),
                           side, kPathH, kLeft + plotW + 16, pp.missing, k == 0);
  }
  s += "</svg>\n";
  return s;
}

// ============================================================================================
// PlotSink

void PlotSink::begin(const machine::Machine& m) {
  std::vector<std::string> names;
  for (const auto& a : m.axes)
    names.emplace_back(1, a.letter);
  rec_.emplace(std::move(names), max_);
  const size_t n = m.axes.size();
  prevPos_.assign(n, 0.0);
  vel_.assign(n, 0.0);
  havePrev_ = false;
  xyz_ = {-1, -1, -1};
  lastPos_.assign(n, 0.0);
  lastVel_.assign(n, 0.0);
  target_.assign(n, 0.0);
  moveMotion_.assign(n, 1);
  lastT_ = 0;
  letters_.clear();
  for (size_t i = 0; i < n; ++i) {
    letters_.push_back(m.axes[i].letter);
    lastPos_[i] = target_[i] = m.axes[i].start;
    if (const size_t k = lang::kPlaneAxisLetters.find(m.axes[i].letter); k != std::string_view::npos)
      xyz_[k] = static_cast<int>(i);
  }
  path_ = PathRecorder();
  std::array<double, 3> at{};
  for (size_t c = 0; c < 3; ++c)
    at[c] = xyz_[c] >= 0 ? lastPos_[static_cast<size_t>(xyz_[c])] : 0.0;
  path_.start(at);
}

void PlotSink::sample(double t, const double* positions) {
  for (size_t a = 0; a < prevPos_.size(); ++a)
    vel_[a] = havePrev_ && t > prevT_ ? (positions[a] - prevPos_[a]) / (t - prevT_) : 0.0;
  sampleWithVelocity(t, positions, vel_.data());
}

void PlotSink::sampleWithVelocity(double t, const double* positions, const double* velocities) {
  if (!rec_) return;
  rec_->addSample(t, positions, velocities);
  std::copy(positions, positions + prevPos_.size(), prevPos_.begin());
  prevT_ = t;
  havePrev_ = true;
  std::copy(positions, positions + lastPos_.size(), lastPos_.begin());
  std::copy(velocities, velocities + lastVel_.size(), lastVel_.begin());
  lastT_ = t;
  pathPoint(false);
}

void PlotSink::pathPoint(bool corner) {
  std::array<double, 3> at{};
  double speed2 = 0;
  bool rapid = false;
  for (size_t c = 0; c < 3; ++c) {
    if (xyz_[c] < 0) continue;
    const auto a = static_cast<size_t>(xyz_[c]);
    at[c] = lastPos_[a];
    speed2 += lastVel_[a] * lastVel_[a];
    if (moveMotion_[a] == 0 && (lastVel_[a] != 0 || lastPos_[a] != target_[a])) rapid = true;
  }
  path_.add(at, std::sqrt(speed2), rapid, corner);
}

void PlotSink::event(const Event& e) {
  if (!rec_) return;
  using Kind = PlotRecorder::MarkerKind;
  // "prog.mpf:12", or "line 12" without a file name (never in practice); "?" for an unknown line
  auto where = [&] {
    std::string line = e.line ? std::to_string(e.line) : "?";
    return e.file.empty() ? "line " + line : fmt::format("{}:{}", e.file, line);
  };
  // The path gets a vertex where a move of X, Y or Z starts or ends: the positions of the
  // other axes then are those of the latest sample carried on at its velocity, never past
  // their targets.
  if ((e.kind == EventKind::MoveStart || e.kind == EventKind::MoveEnd) && e.t >= lastT_) {
    const double dt = e.t - lastT_;
    for (size_t a = 0; a < lastPos_.size(); ++a) {
      const double p = lastPos_[a] + lastVel_[a] * dt;
      lastPos_[a] = std::clamp(p, std::min(lastPos_[a], target_[a]), std::max(lastPos_[a], target_[a]));
    }
    lastT_ = e.t;
    const auto ax = static_cast<size_t>(std::find(letters_.begin(), letters_.end(), e.axis) - letters_.begin());
    if (ax < lastPos_.size()) {
      const bool inPath = std::find(xyz_.begin(), xyz_.end(), static_cast<int>(ax)) != xyz_.end();
      if (e.kind == EventKind::MoveEnd) {
        lastPos_[ax] = e.target;
        lastVel_[ax] = 0;
        if (inPath) pathPoint(true);
      } else {
        if (inPath) {
          path_.countPlane(static_cast<PathPlane>(e.plane >= 17 && e.plane <= 19 ? e.plane : 17));
          pathPoint(true);
        }
        moveMotion_[ax] = e.motion;
        target_[ax] = e.target;
      }
    }
  }
  switch (e.kind) {
  case EventKind::Line:
    if (e.thread == 0) path_.setLine(e.file, e.line);
    rec_->addMarker(e.t, Kind::Block, e.hasN ? fmt::format("{} N{}", where(), formatNumber(e.n)) : where());
    break;
  case EventKind::MStart:
    rec_->addMarker(e.t, Kind::Event, e.blocking ? fmt::format("M{} start", e.m) : fmt::format("M=NB({}) start", e.m));
    break;
  case EventKind::MEnd: rec_->addMarker(e.t, Kind::Event, fmt::format("M{} end", e.m)); break;
  case EventKind::When: rec_->addMarker(e.t, Kind::Event, fmt::format("WHEN {} {}", where(), e.action)); break;
  case EventKind::Dwell: rec_->addMarker(e.t, Kind::Event, fmt::format("dwell {} s", formatNumber(e.duration))); break;
  case EventKind::Stop: rec_->addMarker(e.t, Kind::Stop, fmt::format("M0 stop {} s", formatNumber(e.duration))); break;
  case EventKind::Error:
    rec_->addMarker(e.t, Kind::Error, e.message.empty() ? statusName(e.status) : std::string(e.message));
    break;
  default: break; // moves are in the curves; I/O is left to the JSON trace
  }
}

std::string PlotSink::render(const std::string& title) const {
  if (!rec_) return PlotRecorder({}).render(title);
  PathView view;
  view.path = &path_;
  std::vector<PathPlane> planes;
  if (plane_) {
    planes.push_back(*plane_);
  } else {
    // a panel per plane whose two axes move, the plane most moves used first
    const PathPlane active = path_.activePlane();
    const std::array<bool, 3> moved = path_.moved();
    auto inUse = [&](PathPlane p) {
      const lang::PlaneAxes pa = lang::planeAxes(static_cast<int>(p));
      return moved[static_cast<size_t>(pa.pWord)] && moved[static_cast<size_t>(pa.qWord)];
    };
    planes.push_back(active);
    for (PathPlane p : {PathPlane::XY, PathPlane::ZX, PathPlane::YZ})
      if (p != active && inUse(p)) planes.push_back(p);
    if (planes.size() > 1 && !inUse(active)) planes.erase(planes.begin());
  }
  for (PathPlane p : planes) {
    PathPanel panel{p, ""};
    for (const char* c = pathPlaneName(p); *c; ++c)
      if (xyz_[lang::kPlaneAxisLetters.find(*c)] < 0) panel.missing += *c;
    view.panels.push_back(std::move(panel));
  }
  return rec_->render(title, &view, capNotes());
}

std::vector<std::string> PlotSink::capNotes() const {
  if (!rec_) return {};
  std::vector<std::string> notes = rec_->capNotes();
  if (std::string p = path_.capNote(); !p.empty()) notes.push_back(std::move(p));
  return notes;
}

} // namespace iso::sim
