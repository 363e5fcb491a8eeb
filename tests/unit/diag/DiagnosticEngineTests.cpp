//! @file DiagnosticEngineTests.cpp
//! @brief The one place that decides what users see: disable, per-file rules, inline
//!        suppressions, werror, errors kept for isocc/isosim, files shown, limits, counts.
#include <vector>

#include <doctest/doctest.h>

#include "diag/DiagnosticEngine.h"

using namespace iso::diag;

namespace {
Diagnostic make(Code c, uint32_t file, uint32_t line) {
  Diagnostic d;
  d.code = c;
  d.severity = info(c).severity;
  d.loc = {file, line, 1};
  d.message = info(c).name;
  return d;
}
std::vector<Diagnostic> sample() {
  return {make(Code::Syntax, 0, 1), make(Code::FeedUnset, 0, 2), make(Code::FeedUnset, 0, 3),
          make(Code::MBeforeMotion, 1, 1), make(Code::FeedUnset, 1, 4)};
}
} // namespace

TEST_CASE("diagnostic engine: disable everywhere and per file") {
  auto v = sample();
  DiagnosticEngine({{Code::FeedUnset}, false, false, {}}).apply(v);
  REQUIRE(v.size() == 2);
  CHECK(v[0].code == Code::Syntax);
  CHECK(v[1].code == Code::MBeforeMotion);

  auto w = sample();
  DiagnosticEngine({{}, false, false, [](uint32_t file, Code c) { return file == 1 && c == Code::FeedUnset; }})
      .apply(w);
  CHECK(w.size() == 4);
  CHECK(w.back().code == Code::MBeforeMotion);
}

TEST_CASE("diagnostic engine: inline suppressions by line range and by file - werror") {
  auto v = sample();
  DiagnosticEngine e({{}, true, false, {}});
  e.addSuppression({0, 2, 2, Code::FeedUnset}); // line 2 only
  e.addSuppression({1, 0, 0, Code::FeedUnset}); // the whole of file 1
  e.apply(v);
  REQUIRE(v.size() == 3);
  CHECK(v[1].loc.line == 3);
  CHECK(v[1].severity == Severity::Error); // werror
  CHECK(v[2].severity == Severity::Info);  // infos stay infos
  CHECK(countOf(v).errors == 2);
  CHECK(countOf(v).infos == 1);
}

TEST_CASE("diagnostic engine: isocc/isosim keep a silenced error, with a note") {
  auto v = sample();
  DiagnosticEngine e({{}, false, true, {}});
  e.addSuppression({0, 1, 1, Code::Syntax});
  e.addSuppression({0, 2, 3, Code::FeedUnset});
  e.apply(v);
  REQUIRE(v.size() == 3);
  CHECK(v[0].code == Code::Syntax);
  REQUIRE(v[0].notes.size() == 1);
  CHECK(v[0].notes[0].message.find("still prevents compiling") != std::string::npos);
}

TEST_CASE("diagnostic engine: files not shown, and the per-file limit") {
  auto v = sample();
  DiagnosticEngine e({});
  e.setShownFiles({0, 1});
  e.apply(v);
  CHECK(v.size() == 2);
  auto w = sample();
  DiagnosticEngine::limitPerFile(w, 1);
  REQUIRE(w.size() == 2);
  CHECK(w[0].loc.file == 0);
  CHECK(w[1].loc.file == 1);
  auto all = sample();
  DiagnosticEngine::limitPerFile(all, 100);
  CHECK(all.size() == 5);
}
