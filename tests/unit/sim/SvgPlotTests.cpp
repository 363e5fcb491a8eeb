//! @file SvgPlotTests.cpp
//! @brief The SVG plot: moving axes only, bounded memory, deterministic bytes, and it renders.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include <doctest/doctest.h>

#include "sim/SvgPlot.h"

using iso::sim::PlotRecorder;

namespace {
PlotRecorder makePlot(size_t n, size_t maxSamples = 8192) {
  PlotRecorder r({"X", "Y", "Z"}, maxSamples);
  for (size_t i = 0; i < n; ++i) {
    double t = static_cast<double>(i) * 0.01;
    double pos[3] = {100 * std::sin(t), 0.0, 5 * t};
    double vel[3] = {100 * std::cos(t), 0.0, 5.0};
    r.addSample(t, pos, vel);
  }
  r.addMarker(0.5, PlotRecorder::MarkerKind::Block, "line 3");
  r.addMarker(1.0, PlotRecorder::MarkerKind::Event, "M23 start");
  return r;
}
} // namespace

TEST_CASE("plot: only moving axes are drawn, with labels and legend") {
  std::string svg = makePlot(300).render("demo.mpf - cycle 2.99 s");
  CHECK(svg.find("<svg") == 0);
  CHECK(svg.find("axis X") != std::string::npos);
  CHECK(svg.find("axis Z") != std::string::npos);
  CHECK(svg.find("axis Y") == std::string::npos); // Y does not move
  CHECK(svg.find("time (s)") != std::string::npos);
  CHECK(svg.find("position (mm") != std::string::npos);
  CHECK(svg.find("velocity (mm/s") != std::string::npos);
  CHECK(svg.find("M23 start") != std::string::npos);
}

TEST_CASE("plot: deterministic bytes") {
  CHECK(makePlot(500).render("t") == makePlot(500).render("t"));
}

TEST_CASE("plot: memory stays bounded for long runs") {
  PlotRecorder r = makePlot(200000, 1000);
  CHECK(r.sampleCount() < 1000);
  CHECK(r.sampleCount() > 400);
}

TEST_CASE("plot: renders with rsvg-convert when available") {
  if (std::system("command -v rsvg-convert >/dev/null 2>&1") != 0) {
    MESSAGE("rsvg-convert not installed: render check skipped (apt-get install librsvg2-bin)");
    return;
  }
  std::string dir = "/tmp/iso_plot_test";
  std::system(("mkdir -p " + dir).c_str());
  {
    std::ofstream f(dir + "/p.svg");
    f << makePlot(300).render("render check");
  }
  int rc = std::system(("rsvg-convert -o " + dir + "/p.png " + dir + "/p.svg").c_str());
  CHECK(rc == 0);
  std::ifstream png(dir + "/p.png", std::ios::binary);
  char magic[4] = {};
  png.read(magic, 4);
  CHECK(std::string(magic + 1, 3) == "PNG");
}
