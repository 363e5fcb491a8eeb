//! @file SvgPlot.cpp
//! @brief SVG rendering of position/velocity plots.
#include "sim/SvgPlot.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <fmt/format.h>

#include "machine/Machine.h"
#include "sim/TraceWriter.h"

namespace iso::sim {

namespace {

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
constexpr double kWidth = 960, kPanelH = 260, kLeft = 80, kRight = 170, kTop = 50, kGap = 60;

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

/// Text for XML: the five specials escaped; control characters and bytes that are not UTF-8
/// (a file name can hold anything) become '?', so that the document stays well-formed.
std::string esc(const std::string& s) {
  std::string o;
  size_t i = 0;
  while (i < s.size()) {
    auto c = static_cast<unsigned char>(s[i]);
    auto at = [&](size_t k) { return i + k < s.size() ? static_cast<unsigned char>(s[i + k]) : 0; };
    if (c < 0x80) {
      switch (c) {
      case '&': o += "&amp;"; break;
      case '<': o += "&lt;"; break;
      case '>': o += "&gt;"; break;
      case '"': o += "&quot;"; break;
      default: o.push_back(c < 0x20 && c != '\t' && c != '\n' ? '?' : static_cast<char>(c));
      }
      ++i;
      continue;
    }
    // Well-formed UTF-8 only (RFC 3629): no overlong forms, no surrogates, nothing past U+10FFFF.
    size_t len = c >= 0xC2 && c <= 0xDF ? 2 : c >= 0xE0 && c <= 0xEF ? 3 : c >= 0xF0 && c <= 0xF4 ? 4 : 0;
    unsigned char lo = 0x80, hi = 0xBF;
    if (c == 0xE0) lo = 0xA0;
    if (c == 0xED) hi = 0x9F;
    if (c == 0xF0) lo = 0x90;
    if (c == 0xF4) hi = 0x8F;
    bool ok = len > 0 && at(1) >= lo && at(1) <= hi;
    for (size_t k = 2; ok && k < len; ++k) ok = at(k) >= 0x80 && at(k) <= 0xBF;
    if (!ok) {
      o.push_back('?');
      ++i;
      continue;
    }
    o.append(s, i, len);
    i += len;
  }
  return o;
}

struct Scale {
  double lo, hi, px0, px1;
  double operator()(double v) const { return hi > lo ? px0 + (v - lo) / (hi - lo) * (px1 - px0) : (px0 + px1) / 2; }
};

} // namespace

PlotRecorder::PlotRecorder(std::vector<std::string> axisNames, size_t maxSamples)
    : names_(std::move(axisNames)), max_(std::max<size_t>(maxSamples, 16)), pos_(names_.size()), vel_(names_.size()),
      tailPos_(names_.size()), tailVel_(names_.size()) {}

void PlotRecorder::thin() {
  auto half = [](std::vector<double>& v) {
    size_t j = 0;
    for (size_t i = 0; i < v.size(); i += 2) v[j++] = v[i];
    v.resize(j);
  };
  // The newest sample may fall out; it stays as the tail until a newer one comes.
  if (t_.size() % 2 == 0 && !t_.empty()) {
    hasTail_ = true;
    tailT_ = t_.back();
    for (size_t a = 0; a < names_.size(); ++a) {
      tailPos_[a] = pos_[a].back();
      tailVel_[a] = vel_[a].back();
    }
  }
  half(t_);
  for (auto& v : pos_) half(v);
  for (auto& v : vel_) half(v);
  stride_ *= 2;
}

void PlotRecorder::addSample(double t, const double* pos, const double* vel) {
  if (offered_++ % stride_ != 0) {
    hasTail_ = true;
    tailT_ = t;
    std::copy(pos, pos + names_.size(), tailPos_.begin());
    std::copy(vel, vel + names_.size(), tailVel_.begin());
    return;
  }
  hasTail_ = false;
  t_.push_back(t);
  for (size_t a = 0; a < names_.size(); ++a) {
    pos_[a].push_back(pos[a]);
    vel_[a].push_back(vel[a]);
  }
  if (t_.size() >= max_) thin();
}

void PlotRecorder::addMarker(double t, MarkerKind kind, std::string label) {
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

std::string PlotRecorder::render(const std::string& title) const {
  // The samples kept, then the tail.
  const size_t n = t_.size() + (hasTail_ ? 1 : 0);
  auto timeAt = [&](size_t i) { return i < t_.size() ? t_[i] : tailT_; };
  auto valueAt = [&](bool velocity, size_t a, size_t i) {
    if (i < t_.size()) return velocity ? vel_[a][i] : pos_[a][i];
    return velocity ? tailVel_[a] : tailPos_[a];
  };
  // Only axes that move.
  std::vector<size_t> axes;
  for (size_t a = 0; a < names_.size(); ++a) {
    bool moves = false;
    for (size_t i = 0; i < n && !moves; ++i)
      moves = std::abs(valueAt(false, a, i) - valueAt(false, a, 0)) > 1e-12 ||
              std::abs(valueAt(true, a, i)) > 1e-12;
    if (moves) axes.push_back(a);
  }
  const double t0 = 0;
  double t1 = n == 0 ? 0 : timeAt(n - 1);
  for (const auto& m : markers_) t1 = std::max(t1, m.t);
  if (!(t1 > 1e-9)) t1 = 1; // a run that ends at 0 s: a one-second axis, not a nanosecond one
  double plo = 0, phi = 0, vlo = 0, vhi = 0;
  bool first = true;
  for (size_t a : axes) {
    for (size_t i = 0; i < n; ++i) {
      double p = valueAt(false, a, i), v = valueAt(true, a, i);
      if (first) plo = phi = p;
      first = false;
      plo = std::min(plo, p);
      phi = std::max(phi, p);
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
  s += fmt::format("<title>{}</title>\n", esc(title));
  s += fmt::format("<rect width=\"{}\" height=\"{}\" fill=\"white\"/>\n", kWidth, height);
  s += fmt::format("<text x=\"{}\" y=\"24\" font-size=\"16\" font-weight=\"bold\">{}</text>\n", kLeft, esc(title));
  Scale tx{t0, t1, kLeft, kLeft + plotW};
  auto panel = [&](double top, double lo, double hi, const char* ylabel, bool velocity) {
    double bottom = top + kPanelH;
    double step = niceStep(hi - lo, 6);
    double glo = std::floor(lo / step) * step, ghi = std::ceil(hi / step) * step;
    Scale ys{glo, ghi, bottom, top};
    s += fmt::format("<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"none\" stroke=\"#333\"/>\n", kLeft, top,
                     plotW, kPanelH);
    // Ticks as k·step, not by repeated addition (no drift, no missing last tick).
    const long long kLo = std::llround(glo / step), kHi = std::llround(ghi / step);
    for (long long k = kLo; k <= kHi; ++k) {
      double v = static_cast<double>(k) * step;
      double y = ys(v);
      s += fmt::format("<line x1=\"{}\" y1=\"{:.2f}\" x2=\"{}\" y2=\"{:.2f}\" stroke=\"#ddd\"/>\n", kLeft, y,
                       kLeft + plotW, y);
      s += fmt::format("<text x=\"{}\" y=\"{:.2f}\" text-anchor=\"end\">{}</text>\n", kLeft - 6, y + 4, num(v));
    }
    double tstep = niceStep(t1 - t0, 10);
    const auto tHi = static_cast<long long>(std::floor(t1 / tstep + 1e-9));
    for (long long k = 0; k <= tHi; ++k) {
      double v = static_cast<double>(k) * tstep;
      double x = tx(v);
      s += fmt::format("<line x1=\"{:.2f}\" y1=\"{}\" x2=\"{:.2f}\" y2=\"{}\" stroke=\"#eee\"/>\n", x, top, x, bottom);
      s += fmt::format("<text x=\"{:.2f}\" y=\"{}\" text-anchor=\"middle\">{}</text>\n", x, bottom + 16, num(v));
    }
    // block boundaries and events
    for (const auto& m : markers_) {
      const MarkerStyle& st = kMarkerStyles[static_cast<size_t>(m.kind)];
      double x = tx(m.t);
      s += fmt::format("<line x1=\"{:.2f}\" y1=\"{}\" x2=\"{:.2f}\" y2=\"{}\" stroke=\"{}\" stroke-width=\"{}\"{}>"
                       "<title>{}</title></line>\n",
                       x, top, x, bottom, st.color, st.width, st.dash, esc(m.label));
    }
    for (size_t k = 0; k < axes.size(); ++k) {
      size_t a = axes[k];
      s += fmt::format("<polyline fill=\"none\" stroke=\"{}\" stroke-width=\"1.5\" points=\"", kColors[k % 9]);
      for (size_t i = 0; i < n; ++i)
        s += fmt::format("{}{:.2f},{:.2f}", i ? " " : "", tx(timeAt(i)), ys(valueAt(velocity, a, i)));
      s += "\"/>\n";
    }
    s += fmt::format("<text x=\"20\" y=\"{:.2f}\" transform=\"rotate(-90 20 {:.2f})\" text-anchor=\"middle\">{}</text>\n",
                     (top + bottom) / 2, (top + bottom) / 2, ylabel);
    s += fmt::format("<text x=\"{:.2f}\" y=\"{}\" text-anchor=\"middle\">time (s)</text>\n", kLeft + plotW / 2,
                     bottom + 32);
  };
  panel(kTop, plo, phi, "position (mm, rotary axes: deg)", false);
  panel(kTop + kPanelH + kGap, vlo, vhi, "velocity (mm/s, rotary axes: deg/s)", true);
  // legend: the axes drawn, then the kinds of markers there are
  double lx = kLeft + plotW + 16, ly = kTop + 10;
  for (size_t k = 0; k < axes.size(); ++k) {
    s += fmt::format("<line x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\" stroke=\"{}\" stroke-width=\"3\"/>\n", lx, ly,
                     lx + 24, ly, kColors[k % 9]);
    s += fmt::format("<text x=\"{}\" y=\"{}\">axis {}</text>\n", lx + 30, ly + 4, esc(names_[axes[k]]));
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
  if (axes.empty())
    s += fmt::format("<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">no axis moves</text>\n", kLeft + plotW / 2,
                     kTop + kPanelH / 2);
  s += "</svg>\n";
  return s;
}

// ============================================================================================
// PlotSink

void PlotSink::begin(const machine::Machine& m) {
  std::vector<std::string> names;
  for (const auto& a : m.axes) names.emplace_back(1, a.letter);
  rec_.emplace(std::move(names), max_);
  prevPos_.assign(m.axes.size(), 0.0);
  vel_.assign(m.axes.size(), 0.0);
  havePrev_ = false;
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
}

void PlotSink::event(const Event& e) {
  if (!rec_) return;
  using Kind = PlotRecorder::MarkerKind;
  // "prog.mpf:12", or "line 12" without a file name (never in practice); "?" for an unknown line
  auto where = [&] {
    std::string line = e.line ? std::to_string(e.line) : "?";
    return e.file.empty() ? "line " + line : fmt::format("{}:{}", e.file, line);
  };
  switch (e.kind) {
  case EventKind::Line:
    rec_->addMarker(e.t, Kind::Block, e.hasN ? fmt::format("{} N{}", where(), formatNumber(e.n)) : where());
    break;
  case EventKind::MStart:
    rec_->addMarker(e.t, Kind::Event, e.blocking ? fmt::format("M{} start", e.m) : fmt::format("M=NB({}) start", e.m));
    break;
  case EventKind::MEnd: rec_->addMarker(e.t, Kind::Event, fmt::format("M{} end", e.m)); break;
  case EventKind::When: rec_->addMarker(e.t, Kind::Event, fmt::format("WHEN {} {}", where(), e.action)); break;
  case EventKind::Dwell:
    rec_->addMarker(e.t, Kind::Event, fmt::format("dwell {} s", formatNumber(e.duration)));
    break;
  case EventKind::Stop: rec_->addMarker(e.t, Kind::Stop, fmt::format("M0 stop {} s", formatNumber(e.duration))); break;
  case EventKind::Error:
    rec_->addMarker(e.t, Kind::Error, e.message.empty() ? statusName(e.status) : std::string(e.message));
    break;
  default: break; // moves are in the curves; I/O is left to the JSON trace
  }
}

std::string PlotSink::render(const std::string& title) const {
  if (rec_) return rec_->render(title);
  return PlotRecorder({}).render(title);
}

} // namespace iso::sim
