//! @file SvgPlot.cpp
//! @brief SVG rendering of position/velocity plots.
#include "sim/SvgPlot.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

namespace iso::sim {

namespace {

constexpr const char* kColors[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e",
                                   "#8c564b", "#e377c2", "#17becf", "#7f7f7f"};
constexpr double kWidth = 960, kPanelH = 260, kLeft = 80, kRight = 150, kTop = 50, kGap = 60;

/// A "nice" tick step for a range (1, 2 or 5 times a power of ten), about `n` ticks.
double niceStep(double range, int n) {
  if (!(range > 0)) return 1;
  double raw = range / n;
  double p = std::pow(10.0, std::floor(std::log10(raw)));
  double m = raw / p;
  double step = m < 1.5 ? 1 : m < 3.5 ? 2 : m < 7.5 ? 5 : 10;
  return step * p;
}

std::string num(double v) {
  if (std::abs(v) < 1e-12) v = 0;
  std::string s = fmt::format("{:.6g}", v);
  return s;
}

std::string esc(const std::string& s) {
  std::string o;
  for (char c : s) {
    switch (c) {
    case '&': o += "&amp;"; break;
    case '<': o += "&lt;"; break;
    case '>': o += "&gt;"; break;
    case '"': o += "&quot;"; break;
    default: o.push_back(c);
    }
  }
  return o;
}

struct Scale {
  double lo, hi, px0, px1;
  double operator()(double v) const { return hi > lo ? px0 + (v - lo) / (hi - lo) * (px1 - px0) : (px0 + px1) / 2; }
};

} // namespace

PlotRecorder::PlotRecorder(std::vector<std::string> axisNames, size_t maxSamples)
    : names_(std::move(axisNames)), max_(std::max<size_t>(maxSamples, 16)), pos_(names_.size()), vel_(names_.size()) {}

void PlotRecorder::thin() {
  auto half = [](std::vector<double>& v) {
    size_t j = 0;
    for (size_t i = 0; i < v.size(); i += 2) v[j++] = v[i];
    v.resize(j);
  };
  half(t_);
  for (auto& v : pos_) half(v);
  for (auto& v : vel_) half(v);
  stride_ *= 2;
}

void PlotRecorder::addSample(double t, const double* pos, const double* vel) {
  if (offered_++ % stride_ != 0) return;
  t_.push_back(t);
  for (size_t a = 0; a < names_.size(); ++a) {
    pos_[a].push_back(pos[a]);
    vel_[a].push_back(vel[a]);
  }
  if (t_.size() >= max_) thin();
}

void PlotRecorder::addMarker(double t, MarkerKind kind, std::string label) {
  if (kind == MarkerKind::Block && markersOffered_++ % markerStride_ != 0) return;
  markers_.push_back({t, kind, std::move(label)});
  if (markers_.size() >= 2000) {
    // keep every event and stop, every other block boundary
    std::vector<Marker> kept;
    size_t k = 0;
    for (auto& m : markers_)
      if (m.kind != MarkerKind::Block || (k++ % 2 == 0)) kept.push_back(std::move(m));
    markers_ = std::move(kept);
    markerStride_ *= 2;
  }
}

std::string PlotRecorder::render(const std::string& title) const {
  // Only axes that move.
  std::vector<size_t> axes;
  for (size_t a = 0; a < names_.size(); ++a) {
    if (pos_[a].empty()) continue;
    auto [mn, mx] = std::minmax_element(pos_[a].begin(), pos_[a].end());
    if (*mx - *mn > 1e-12) axes.push_back(a);
  }
  double t0 = 0, t1 = t_.empty() ? 1 : std::max(t_.back(), 1e-9);
  double plo = 0, phi = 0, vlo = 0, vhi = 0;
  bool first = true;
  for (size_t a : axes) {
    for (double v : pos_[a]) {
      if (first) plo = phi = v;
      plo = std::min(plo, v);
      phi = std::max(phi, v);
      first = false;
    }
    for (double v : vel_[a]) {
      vlo = std::min(vlo, v);
      vhi = std::max(vhi, v);
    }
  }
  if (phi - plo < 1e-9) { plo -= 1; phi += 1; }
  if (vhi - vlo < 1e-9) { vlo -= 1; vhi += 1; }
  double plotW = kWidth - kLeft - kRight;
  double height = kTop + 2 * kPanelH + kGap + 50;
  std::string s;
  s += fmt::format("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{}\" height=\"{}\" viewBox=\"0 0 {} {}\" "
                   "font-family=\"DejaVu Sans, Arial, sans-serif\" font-size=\"12\">\n",
                   kWidth, height, kWidth, height);
  s += fmt::format("<rect width=\"{}\" height=\"{}\" fill=\"white\"/>\n", kWidth, height);
  s += fmt::format("<text x=\"{}\" y=\"24\" font-size=\"16\" font-weight=\"bold\">{}</text>\n", kLeft, esc(title));
  Scale tx{t0, t1, kLeft, kLeft + plotW};
  auto panel = [&](double top, double lo, double hi, const char* ylabel, const std::vector<std::vector<double>>& data) {
    double bottom = top + kPanelH;
    double step = niceStep(hi - lo, 6);
    double glo = std::floor(lo / step) * step, ghi = std::ceil(hi / step) * step;
    Scale ys{glo, ghi, bottom, top};
    s += fmt::format("<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"none\" stroke=\"#333\"/>\n", kLeft, top,
                     plotW, kPanelH);
    for (double v = glo; v <= ghi + step * 1e-9; v += step) {
      double y = ys(v);
      s += fmt::format("<line x1=\"{}\" y1=\"{:.2f}\" x2=\"{}\" y2=\"{:.2f}\" stroke=\"#ddd\"/>\n", kLeft, y,
                       kLeft + plotW, y);
      s += fmt::format("<text x=\"{}\" y=\"{:.2f}\" text-anchor=\"end\">{}</text>\n", kLeft - 6, y + 4, num(v));
    }
    double tstep = niceStep(t1 - t0, 10);
    for (double v = 0; v <= t1 + tstep * 1e-9; v += tstep) {
      double x = tx(v);
      s += fmt::format("<line x1=\"{:.2f}\" y1=\"{}\" x2=\"{:.2f}\" y2=\"{}\" stroke=\"#eee\"/>\n", x, top, x, bottom);
      s += fmt::format("<text x=\"{:.2f}\" y=\"{}\" text-anchor=\"middle\">{}</text>\n", x, bottom + 16, num(v));
    }
    // block boundaries and events
    for (const auto& m : markers_) {
      double x = tx(m.t);
      const char* col = m.kind == MarkerKind::Block ? "#cccccc" : m.kind == MarkerKind::Stop ? "#d62728" : "#ff7f0e";
      s += fmt::format("<line x1=\"{:.2f}\" y1=\"{}\" x2=\"{:.2f}\" y2=\"{}\" stroke=\"{}\" stroke-dasharray=\"{}\">"
                       "<title>{}</title></line>\n",
                       x, top, x, bottom, col, m.kind == MarkerKind::Block ? "2,3" : "4,2", esc(m.label));
    }
    for (size_t k = 0; k < axes.size(); ++k) {
      size_t a = axes[k];
      s += fmt::format("<polyline fill=\"none\" stroke=\"{}\" stroke-width=\"1.5\" points=\"", kColors[k % 9]);
      for (size_t i = 0; i < t_.size(); ++i)
        s += fmt::format("{}{:.2f},{:.2f}", i ? " " : "", tx(t_[i]), ys(data[a][i]));
      s += "\"/>\n";
    }
    s += fmt::format("<text x=\"20\" y=\"{:.2f}\" transform=\"rotate(-90 20 {:.2f})\" text-anchor=\"middle\">{}</text>\n",
                     (top + bottom) / 2, (top + bottom) / 2, ylabel);
    s += fmt::format("<text x=\"{:.2f}\" y=\"{}\" text-anchor=\"middle\">time (s)</text>\n", kLeft + plotW / 2,
                     bottom + 32);
  };
  panel(kTop, plo, phi, "position (mm, rotary axes: deg)", pos_);
  panel(kTop + kPanelH + kGap, vlo, vhi, "velocity (mm/s, rotary axes: deg/s)", vel_);
  // legend
  double lx = kLeft + plotW + 16, ly = kTop + 10;
  for (size_t k = 0; k < axes.size(); ++k) {
    s += fmt::format("<line x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\" stroke=\"{}\" stroke-width=\"3\"/>\n", lx,
                     ly + 18 * static_cast<double>(k), lx + 24, ly + 18 * static_cast<double>(k), kColors[k % 9]);
    s += fmt::format("<text x=\"{}\" y=\"{}\">axis {}</text>\n", lx + 30, ly + 18 * static_cast<double>(k) + 4,
                     esc(names_[axes[k]]));
  }
  double ey = ly + 18 * static_cast<double>(axes.size()) + 14;
  s += fmt::format("<line x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\" stroke=\"#cccccc\" stroke-dasharray=\"2,3\"/>\n", lx,
                   ey, lx + 24, ey);
  s += fmt::format("<text x=\"{}\" y=\"{}\">block</text>\n", lx + 30, ey + 4);
  s += fmt::format("<line x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\" stroke=\"#ff7f0e\" stroke-dasharray=\"4,2\"/>\n", lx,
                   ey + 18, lx + 24, ey + 18);
  s += fmt::format("<text x=\"{}\" y=\"{}\">event</text>\n", lx + 30, ey + 22);
  if (axes.empty())
    s += fmt::format("<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">no axis moves</text>\n", kLeft + plotW / 2,
                     kTop + kPanelH / 2);
  s += "</svg>\n";
  return s;
}

} // namespace iso::sim
