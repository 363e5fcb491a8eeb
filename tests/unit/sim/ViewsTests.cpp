//! @file ViewsTests.cpp
//! @brief The views of a run: min/max decimation keeps peaks, the tool path stays bounded and
//!        picks the program's plane, the timeline tiles the run exactly, the report's sections.
#include <cmath>
#include <set>
#include <string>

#include <doctest/doctest.h>
#include <fmt/format.h>

#include "SimTestUtil.h"
#include "XmlCheck.h"
#include "driver/Report.h"
#include "sim/PathPlot.h"
#include "sim/SvgPlot.h"
#include "sim/Timeline.h"

using namespace iso;

namespace {
sim::SimResult runViews(const std::string& text, sim::TraceSink* sink, sim::TimeProfile* profile = nullptr) {
  auto set = test::loadText(text);
  std::string diags;
  image::Image img = test::compileSet(*set, test::builtin(), &diags);
  REQUIRE(diags.empty());
  sim::SimOptions so;
  so.dt = 0.01;
  so.profile = profile;
  return test::runImage(img, test::builtin(), so, sink);
}
} // namespace

TEST_CASE("plot: a one-sample spike in a million samples is still drawn") {
  sim::PlotRecorder r({"X"}, 1024);
  for (int i = 0; i < 1'000'000; ++i) {
    const double t = i * 0.01;
    const double p = 0, v = i == 654'321 ? 777.0 : 0.0;
    r.addSample(t, &p, &v);
  }
  CHECK(r.sampleCount() <= 1024);
  const std::string svg = r.render("spike");
  CHECK(test::xmlProblem(svg) == "");
  // the velocity panel spans 0..800 (step 100): 777 is at y = 370 + 260 - 777/800 * 260
  CHECK(svg.find("data-kind=\"velocity\" data-lo=\"0\" data-hi=\"800\"") != std::string::npos);
  const double y = 370 + 260 - 777.0 / 800 * 260;
  CHECK(svg.find(fmt::format(",{:.2f}", y)) != std::string::npos);
}

TEST_CASE("path: bounded points, corners kept, the plane most moves used") {
  sim::PathRecorder p(64);
  p.start({0, 0, 0});
  for (int i = 1; i <= 100'000; ++i) {
    const double a = i * 1e-3;
    p.add({100 * std::cos(a), 100 * std::sin(a), 0}, 50, false);
  }
  CHECK(p.pointCount() < 64);
  p.countPlane(sim::PathPlane::ZX);
  p.countPlane(sim::PathPlane::ZX);
  p.countPlane(sim::PathPlane::XY);
  CHECK(p.activePlane() == sim::PathPlane::ZX);
  CHECK(sim::parsePathPlane("YZ") == sim::PathPlane::YZ);
  CHECK_FALSE(sim::parsePathPlane("xz"));
  const std::string g = p.render(sim::PathPlane::XY, 80, 700, 500, 500, 800, "");
  CHECK(test::xmlProblem("<svg xmlns=\"http://www.w3.org/2000/svg\">" + g + "</svg>") == "");
  CHECK(g.find("class=\"start\"") != std::string::npos);
  CHECK(g.find("class=\"end\"") != std::string::npos);
}

TEST_CASE("plot sink: rapids are dashed, feeds solid, in the plane of the program") {
  sim::PlotSink sink;
  runViews("G18\nG00 X50 Z20\nG01 X80 F=100\nM30\n", &sink);
  const std::string svg = sink.render("t");
  CHECK(test::xmlProblem(svg) == "");
  CHECK(svg.find("data-plane=\"ZX\"") != std::string::npos);
  // a panel per plane whose two axes move: X and Z only, so ZX alone
  CHECK(svg.find("data-plane=\"XY\"") == std::string::npos);
  CHECK(svg.find("data-plane=\"YZ\"") == std::string::npos);
  // the feed: solid, coloured, tagged with its line; the rapid: thin, grey, dashed
  CHECK(svg.find("class=\"path\" data-kind=\"feed\" data-file=\"t.mpf\" data-line=\"3\" fill=\"none\" stroke=\"#") !=
        std::string::npos);
  CHECK(svg.find("data-kind=\"rapid\" data-file=\"t.mpf\" data-line=\"2\" fill=\"none\" stroke=\"#8c8c8c\" "
                 "stroke-width=\"1\" stroke-dasharray=\"4,3\" points=") != std::string::npos);
  sim::PlotSink xy;
  xy.setPlane(sim::PathPlane::XY);
  runViews("G18\nG00 X50 Z20\nM30\n", &xy);
  CHECK(xy.render("t").find("data-plane=\"XY\"") != std::string::npos);
}

TEST_CASE("timeline: main slices tile the run in whole microseconds - a WHEN body has its track") {
  sim::TimeProfile prof;
  sim::TimelineSink tl(&prof);
  sim::SimResult r =
      runViews("N10 WHEN $aa_iw[X] > 10 DO $aa_out[2] = 1\nN20 G00 X100\nN30 G04 F0.3\nM30\n", &tl, &prof);
  REQUIRE(r.summary.status == sim::Status::Ok);
  const std::string doc = tl.render("p.mpf");
  CHECK(sim::micros(0.447214) == 447214);
  CHECK(sim::micros(r.summary.cycleTimeS) == 747214);
  CHECK(doc.find("\"cycle_time_us\": 747214") != std::string::npos);
  CHECK(doc.find(":1\",\"cat\":\"when\",\"ph\":\"X\",\"ts\":100000,\"dur\":0,\"pid\":1,\"tid\":100") !=
        std::string::npos);
  CHECK(doc.find(":2\",\"cat\":\"line\",\"ph\":\"X\",\"ts\":0,\"dur\":447214,\"pid\":1,\"tid\":1,") !=
        std::string::npos);
  CHECK(doc.find("\"limit\":\"dwell\"") != std::string::npos);
  CHECK(tl.dropped() == 0);
}

TEST_CASE("timeline: past its limit it counts what it drops and still ends at the cycle time") {
  sim::TimelineSink tl(nullptr, 16);
  sim::SimResult r = runViews("R1 = 0\nL:\nR1 = R1 + 1\nG04 F0.01\nIF R1 < 50 GOTOB L\nM30\n", &tl);
  REQUIRE(r.summary.status == sim::Status::Ok);
  CHECK(tl.eventCount() == 16);
  CHECK(tl.dropped() > 0);
  const std::string doc = tl.render("p.mpf");
  CHECK(doc.find("more lines (not recorded)") != std::string::npos);
}

TEST_CASE("report: sections, escaping, and the z32 figures when the summary has them") {
  sim::Summary s;
  s.cycleTimeS = 2.5;
  s.warnings = {"M41 <no model>"};
  s.finalPosition = {{'X', 1}};
  driver::ReportInput in;
  in.title = "p.mpf - cycle time 2.5 s";
  in.program = "p&q.mpf";
  in.summary = &s;
  in.plotSvg = "<svg xmlns=\"http://www.w3.org/2000/svg\"></svg>\n";
  std::string page = driver::renderReport(in);
  for (const char* id : {"summary", "warnings", "plot", "profile"})
    CHECK(page.find(fmt::format("<section id=\"{}\">", id)) != std::string::npos);
  CHECK(page.find("M41 &lt;no model&gt;") != std::string::npos);
  CHECK(page.find("p&amp;q.mpf") != std::string::npos);
  // one inline script, no external one
  CHECK(page.find("<script>") != std::string::npos);
  CHECK(page.find("<script src") == std::string::npos);
  CHECK(page.find("machine-state") == std::string::npos);
  in.summaryJson = R"({"status": "ok", "spindle_on_s": 1.25, "tool_changes": 2, "tool": 5})";
  page = driver::renderReport(in);
  CHECK(page.find("<section id=\"machine-state\">") != std::string::npos);
  CHECK(page.find("<td>1.25 s</td>") != std::string::npos);
  CHECK(page.find("<tr><th>tool changes</th><td>2</td></tr>") != std::string::npos);
}

namespace {
/// The distinct stroke colours of the path polylines of one kind (feed or rapid).
std::set<std::string> pathColours(const std::string& svg, const std::string& kind) {
  std::set<std::string> colours;
  const std::string key = "data-kind=\"" + kind + "\"";
  for (size_t at = svg.find(key); at != std::string::npos; at = svg.find(key, at + 1)) {
    const size_t s = svg.find("stroke=\"", at) + 8;
    colours.insert(svg.substr(s, svg.find('"', s) - s));
  }
  return colours;
}
} // namespace

TEST_CASE("plot: the feed colours span the feed moves only - rapids are grey and apart") {
  sim::PlotSink sink;
  // a slow and a ten times faster feed, and rapids far faster than both
  runViews("G00 X10\nG01 X110 F=200\nG01 X1110 F=2000\nG00 X0\nM30\n", &sink);
  const std::string svg = sink.render("t");
  CHECK(test::xmlProblem(svg) == "");
  const std::set<std::string> feed = pathColours(svg, "feed"), rapid = pathColours(svg, "rapid");
  CHECK(rapid == std::set<std::string>{"#8c8c8c"});
  // the slow feed's cruise is in the lowest class, the fast feed's in the highest (scaled by the
  // rapids, both would be in the lowest ones)
  CHECK(feed.count("#313695") == 1);
  CHECK(feed.count("#a50026") == 1);
  CHECK(feed.size() >= 4);
  CHECK(svg.find(">rapid (G00)<") != std::string::npos);
  CHECK(svg.find("class=\"path-legend\"") != std::string::npos);
}

TEST_CASE("plot: a panel per plane whose two axes move - or the plane asked for") {
  sim::PlotSink sink;
  runViews("G00 X50\nG01 Y40 F=500\nG01 Z-10\nM30\n", &sink);
  const std::string svg = sink.render("t");
  CHECK(test::xmlProblem(svg) == "");
  const size_t xy = svg.find("data-plane=\"XY\""), zx = svg.find("data-plane=\"ZX\""),
               yz = svg.find("data-plane=\"YZ\"");
  REQUIRE(xy != std::string::npos);
  REQUIRE(zx != std::string::npos);
  REQUIRE(yz != std::string::npos);
  CHECK((xy < zx && zx < yz)); // the plane the moves used (G17) first
  // one legend, beside the first panel; the document grows with the panels
  CHECK(svg.find("class=\"path-legend\"") == svg.rfind("class=\"path-legend\""));
  CHECK(svg.find("height=\"2630\"") != std::string::npos);
  sim::PlotSink one;
  one.setPlane(sim::PathPlane::YZ);
  runViews("G00 X50\nG01 Y40 F=500\nG01 Z-10\nM30\n", &one);
  const std::string only = one.render("t");
  CHECK(only.find("data-plane=\"XY\"") == std::string::npos);
  CHECK(only.find("data-plane=\"YZ\"") != std::string::npos);
}

TEST_CASE("timeline: counter tracks of position and velocity for each axis that moves, bounded") {
  sim::TimelineSink tl;
  sim::SimResult r = runViews("G00 X100\nG04 F30\nM30\n", &tl);
  REQUIRE(r.summary.status == sim::Status::Ok);
  const std::string doc = tl.render("p.mpf");
  CHECK(doc.find("{\"name\":\"X position\",\"cat\":\"counter\",\"ph\":\"C\",\"ts\":0,\"pid\":1,\"args\":{\"X\":0}}") !=
        std::string::npos);
  CHECK(doc.find("\"name\":\"X velocity\",\"cat\":\"counter\",\"ph\":\"C\"") != std::string::npos);
  CHECK(doc.find("\"name\":\"Y position\"") == std::string::npos); // Y does not move
  // the last position value is the target, at the end of the run
  const size_t last = doc.rfind("\"name\":\"X position\"");
  CHECK(doc.substr(last, doc.find('\n', last) - last).find("\"args\":{\"X\":100}") != std::string::npos);
  // 30 s at 0.01 s are 3000 samples; a counter keeps at most two per column and the ends
  size_t values = 0;
  for (size_t at = doc.find("\"name\":\"X position\""); at != std::string::npos;
       at = doc.find("\"name\":\"X position\"", at + 1))
    ++values;
  CHECK(values <= 2 * sim::TimelineSink::kCounterColumns + 2);
  CHECK(values > 10);
}

TEST_CASE("report: path segments and profile rows carry their line - the page embeds those source lines") {
  sim::Summary s;
  s.cycleTimeS = 1;
  sim::TimeProfile prof;
  prof.cycleTimeS = 1;
  sim::LineProfile a;
  a.file = "p.mpf";
  a.line = 1;
  a.count = 1;
  prof.lines.push_back(a);
  driver::ReportInput in;
  in.title = "p.mpf";
  in.program = "p.mpf";
  in.summary = &s;
  in.profile = &prof;
  in.plotSvg = "<svg xmlns=\"http://www.w3.org/2000/svg\"><polyline class=\"path\" data-kind=\"feed\" "
               "data-file=\"p.mpf\" data-line=\"9\" points=\"0,0 1,1\"/></svg>\n";
  in.sources["p.mpf"] = "G00 X1\n; </script> <!-- a comment\nX3\nX4\nX5\nX6\nX7\nX8\nG01 X9 F100\nX10\nX11\nX12\n";
  const std::string page = driver::renderReport(in);
  CHECK(page.find("<tr data-file=\"p.mpf\" data-line=\"1\">") != std::string::npos);
  CHECK(page.find("<table id=\"profile-table\">") != std::string::npos);
  CHECK(page.find("<div id=\"source-view\">") != std::string::npos);
  // lines 1 and 9 with two either side; nothing that would end the script early
  CHECK(page.find(R"("1":"G00 X1","2":"; \u003c/script> \u003c!-- a comment","3":"X3","7":"X7")") != std::string::npos);
  CHECK(page.find(R"("9":"G01 X9 F100","10":"X10","11":"X11"})") != std::string::npos);
  CHECK(page.find("\"12\"") == std::string::npos);
  CHECK(page.find("; </script>") == std::string::npos);
}
