//! @file SvgPlotTests.cpp
//! @brief The SVG plot: moving axes only, bounded memory, deterministic bytes, well-formed XML,
//!        and it renders; the plot sink's markers; the tee sink.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include <doctest/doctest.h>

#include "SimTestUtil.h"
#include "XmlCheck.h"
#include "sim/SvgPlot.h"

using namespace iso;
using iso::sim::PlotRecorder;

namespace {
PlotRecorder makePlot(size_t n, size_t maxSamples = 8192, bool markers = true) {
  PlotRecorder r({"X", "Y", "Z"}, maxSamples);
  for (size_t i = 0; i < n; ++i) {
    double t = static_cast<double>(i) * 0.01;
    double pos[3] = {100 * std::sin(t), 0.0, 5 * t};
    double vel[3] = {100 * std::cos(t), 0.0, 5.0};
    r.addSample(t, pos, vel);
  }
  if (!markers) return r;
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

TEST_CASE("plot: deterministic bytes") { CHECK(makePlot(500).render("t") == makePlot(500).render("t")); }

TEST_CASE("plot: memory stays bounded for long runs") {
  PlotRecorder r = makePlot(200000, 1000);
  CHECK(r.sampleCount() <= 1000); // buckets of min/max, at most maxBuckets
  CHECK(r.sampleCount() > 400);
}

TEST_CASE("plot: well-formed XML, also with markup and bytes that are not UTF-8 in labels") {
  PlotRecorder r = makePlot(50);
  r.addMarker(0.2, PlotRecorder::MarkerKind::Event, "M1 <start> & \"go\"");
  r.addMarker(0.3, PlotRecorder::MarkerKind::Block, std::string("caf\xc3\xa9.mpf:2 \xff\xc0\x80\xed\xa0\x80 \x01"));
  std::string svg = r.render("a < b & \"c\"");
  CHECK(test::xmlProblem(svg) == "");
  CHECK(svg.find("M1 &lt;start&gt; &amp; &quot;go&quot;") != std::string::npos);
  CHECK(svg.find("caf\xc3\xa9.mpf:2 ?????? ?") != std::string::npos); // é kept; the rest replaced
  CHECK(svg.find("<title>a &lt; b &amp; &quot;c&quot;</title>") != std::string::npos);
  CHECK(test::xmlProblem(PlotRecorder({"X"}).render("empty")) == "");
  CHECK(test::xmlProblem("<svg><a></svg>") != ""); // the checker itself
  CHECK(test::xmlProblem("<svg x=\"&\"/>") != "");
}

TEST_CASE("plot: the last sample is drawn, also when thinning left it out") {
  // A marker at the end of the run makes the time axis end there, at x = 790 (80 + 960 - 80
  // - 170): the curves must reach it, in both panels.
  for (size_t n : {17u, 100u, 1001u, 1234u, 4097u}) {
    CAPTURE(n);
    PlotRecorder r = makePlot(n, 16, false);
    r.addMarker(static_cast<double>(n - 1) * 0.01, PlotRecorder::MarkerKind::Event, "end");
    std::string svg = r.render("t");
    size_t first = svg.find(" 790.00,");
    CHECK(first != std::string::npos);
    CHECK(svg.find(" 790.00,", first + 1) != std::string::npos);
  }
}

TEST_CASE("plot: markers stay bounded - the error that ends a run is always kept") {
  PlotRecorder r = makePlot(100);
  for (int i = 0; i < 20000; ++i)
    r.addMarker(i * 1e-4, PlotRecorder::MarkerKind::Block, "b");
  for (int i = 0; i < 5000; ++i)
    r.addMarker(1 + i * 1e-4, PlotRecorder::MarkerKind::Event, "e");
  r.addMarker(1.5, PlotRecorder::MarkerKind::Error, "p.mpf:9: emergency at t=1.5 s: soft limit");
  CHECK(r.markerCount() < 2000);
  std::string svg = r.render("t");
  CHECK(svg.find("soft limit") != std::string::npos);
  CHECK(svg.find(">error, emergency<") != std::string::npos);
  // past 2000 blocks no block marker at all: thousands of them would grey the panels
  CHECK(svg.find(">block<") == std::string::npos);
  CHECK(svg.find("<title>b</title>") == std::string::npos);
  REQUIRE(!r.capNotes().empty());
  CHECK(r.capNotes().front().rfind("no block marker (2000", 0) == 0);
  CHECK(svg.find(">M, WHEN, dwell<") != std::string::npos);
  CHECK(svg.find(">M0 stop<") == std::string::npos); // only the kinds there are
}

TEST_CASE("plot sink: block boundaries and events become markers with labels") {
  sim::PlotSink sink;
  sink.begin(test::builtin());
  double pos[9] = {}, vel[9] = {};
  sink.sampleWithVelocity(0, pos, vel);
  pos[0] = 10;
  vel[0] = 100;
  sink.sampleWithVelocity(0.1, pos, vel);
  auto ev = [&](sim::EventKind k, double t) {
    sim::Event e;
    e.kind = k;
    e.t = t;
    e.file = "p.mpf";
    e.line = 3;
    return e;
  };
  sim::Event line = ev(sim::EventKind::Line, 0);
  line.hasN = true;
  line.n = 10;
  sink.event(line);
  sim::Event m = ev(sim::EventKind::MStart, 0.01);
  m.m = 23;
  sink.event(m);
  m.blocking = false;
  m.m = 7;
  sink.event(m);
  m.kind = sim::EventKind::MEnd;
  sink.event(m);
  sim::Event w = ev(sim::EventKind::When, 0.02);
  w.action = "fired";
  sink.event(w);
  sim::Event d = ev(sim::EventKind::Dwell, 0.03);
  d.duration = 0.5;
  sink.event(d);
  sim::Event st = ev(sim::EventKind::Stop, 0.04);
  sink.event(st);
  sim::Event out = ev(sim::EventKind::Output, 0.05);
  sink.event(out); // not a marker
  sim::Event err = ev(sim::EventKind::Error, 0.1);
  err.status = sim::Status::Error;
  err.message = "p.mpf:3: runtime error at t=0.1 s: division by zero";
  sink.event(err);
  REQUIRE(sink.recorder() != nullptr);
  CHECK(sink.recorder()->markerCount() == 8);
  std::string svg = sink.render("p.mpf - error at t=0.1 s");
  CHECK(test::xmlProblem(svg) == "");
  // markers of one kind in one pixel column are one line, its tooltip their labels
  for (const char* label : {"<title>p.mpf:3 N10</title>", "<title>M23 start; M=NB(7) start; M7 end</title>",
                            "<title>WHEN p.mpf:3 fired</title>", "<title>dwell 0.5 s</title>",
                            "<title>M0 stop 0 s</title>", "division by zero</title>"}) {
    CAPTURE(label);
    CHECK(svg.find(label) != std::string::npos);
  }
  CHECK(svg.find("axis X") != std::string::npos);
  CHECK(svg.find("axis Y") == std::string::npos);
  // a sink that never began draws an empty plot
  CHECK(test::xmlProblem(sim::PlotSink().render("nothing")) == "");
}

namespace {
/// Counts what a sink that wants samples but no events is handed.
struct SamplesOnly : sim::TraceSink {
  void begin(const machine::Machine&) override { ++begins; }
  void sample(double, const double*) override { ++samples; }
  void event(const sim::Event&) override { ++events; }
  void end(const sim::Summary&) override { ++ends; }
  bool wantsEvents() const override { return false; }
  int begins = 0, samples = 0, events = 0, ends = 0;
};

sim::SimResult runWith(const std::string& text, sim::TraceSink* sink) {
  auto set = test::loadText(text);
  std::string diags;
  image::Image img = test::compileSet(*set, test::builtin(), &diags);
  REQUIRE(diags.empty());
  sim::SimOptions so;
  so.dt = 0.05;
  return test::runImage(img, test::builtin(), so, sink);
}
} // namespace

TEST_CASE("tee sink: each sink gets what it wants, and the trace is the same as without the plot") {
  const std::string prog = "N10 G00 X100\nG01 Y20 F50\nM23\nM30\n";
  test::Recorder alone;
  runWith(prog, &alone);
  test::Recorder rec;
  SamplesOnly quiet;
  sim::PlotSink plot;
  sim::TeeSink tee({&rec, &quiet, &plot});
  CHECK(tee.wantsVelocities());
  CHECK(tee.wantsEvents());
  sim::SimResult res = runWith(prog, &tee);
  CHECK(res.summary.status == sim::Status::Ok);
  CHECK(rec.samples == alone.samples);
  CHECK(rec.events.size() == alone.events.size());
  CHECK(quiet.begins == 1);
  CHECK(quiet.ends == 1);
  CHECK(quiet.events == 0);
  CHECK(static_cast<size_t>(quiet.samples) == alone.samples.size());
  REQUIRE(plot.recorder() != nullptr);
  CHECK(plot.recorder()->samplesOffered() == alone.samples.size());
  std::string svg = plot.render("t");
  CHECK(svg.find("<title>t.mpf:1 N10</title>") != std::string::npos);
  CHECK(svg.find("<title>M23 start") != std::string::npos);
  // nobody wants events: the tee says so, and the simulator may skip them
  SamplesOnly a, b;
  sim::TeeSink none({&a, &b});
  CHECK_FALSE(none.wantsEvents());
  CHECK_FALSE(none.wantsVelocities());
  CHECK(none.wantsSamples());
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
