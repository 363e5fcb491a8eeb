//! @file RenderTests.cpp
//! @brief Diagnostic rendering details: SARIF columns are UTF-16 code units (columnKind), while
//!        the diagnostics themselves count bytes.
#include <doctest/doctest.h>

#include <sstream>

#include "diag/Render.h"
#include "diag/SourceManager.h"

using iso::diag::utf16Column;

TEST_CASE("sarif: byte columns become UTF-16 columns") {
  // ASCII: the same column
  CHECK(utf16Column("G01 X10", 5) == 5);
  CHECK(utf16Column("G01 X10", 1) == 1);
  // "è" is 2 bytes and 1 unit: the X after "; caffè " is byte column 10, unit column 9
  CHECK(utf16Column("; caff\xC3\xA8 X", 10) == 9);
  // a 4-byte code point (U+1F600) is 2 units
  CHECK(utf16Column("\xF0\x9F\x98\x80X", 5) == 3);
  // Latin-1 bytes that are not UTF-8 count one unit each
  CHECK(utf16Column("caff\xE8 X", 7) == 7);
  // a column just past the end of the line (an end column) keeps its distance
  CHECK(utf16Column("\xC3\xA8", 3) == 2);
  CHECK(utf16Column("ab", 5) == 5);
}

// ---- the text format's source window ---------------------------------------------------------

using iso::diag::sourceWindow;

TEST_CASE("text: a short line is shown whole, the caret under its column") {
  size_t caret = 0, ul = 0;
  CHECK(sourceWindow("G01 X10 Y20", 5, 3, 100, caret, ul) == "G01 X10 Y20");
  CHECK(caret == 4);
  CHECK(ul == 3);
}

TEST_CASE("text: a long line is cut to a window around the caret with … marks") {
  std::string line(5000, 'a');
  line[2500] = 'X';
  size_t caret = 0, ul = 0;
  std::string w = sourceWindow(line, 2501, 1, 100, caret, ul);
  CHECK(w.substr(0, 3) == "\xE2\x80\xA6");
  CHECK(w.substr(w.size() - 3) == "\xE2\x80\xA6");
  CHECK(w.size() == 100 + 6);
  // the caret points at the X
  CHECK(w.substr(3 + caret - 1, 1) == "X");
  // at the end of the line: only a leading mark
  w = sourceWindow(line, 5001, 1, 100, caret, ul);
  CHECK(w.substr(0, 3) == "\xE2\x80\xA6");
  CHECK(w.back() == 'a');
  CHECK(caret == 101);
}

TEST_CASE("text: control bytes are escaped in the window and the caret accounts for them") {
  size_t caret = 0, ul = 0;
  std::string w = sourceWindow("\x1b[31mX", 6, 1, 100, caret, ul);
  CHECK(w == "\\x1b[31mX");
  CHECK(caret == 8); // 4 columns for the escape, 4 for "[31m"
  CHECK(ul == 1);
  // an underlined escaped byte is 4 columns wide
  w = sourceWindow("A\x01"
                   "B",
                   2, 1, 100, caret, ul);
  CHECK(w == "A\\x01B");
  CHECK(caret == 1);
  CHECK(ul == 4);
}

TEST_CASE("text: renderText escapes messages and file names") {
  iso::diag::SourceManager sm;
  uint32_t id = sm.add("caff\xE8\x1b.mpf", "G01 X1\n");
  iso::diag::Diagnostic d;
  d.code = iso::diag::Code::Syntax;
  d.loc = {id, 1, 1};
  d.message = "bad \x1b[2J byte";
  std::string out = iso::diag::renderText({d}, sm, false);
  CHECK(out.find('\x1b') == std::string::npos);
  CHECK(out.find("caff\\xe8\\x1b.mpf:1:1: error: bad \\x1b[2J byte") != std::string::npos);
}

TEST_CASE("json: file names and messages that are not UTF-8 still give valid JSON") {
  iso::diag::SourceManager sm;
  uint32_t id = sm.add("caff\xE8.mpf", "G01 X1\n");
  iso::diag::Diagnostic d;
  d.code = iso::diag::Code::Syntax;
  d.loc = {id, 1, 1};
  d.message = "quoted \xFF byte";
  auto j = iso::diag::renderJson({d}, sm, 1);
  CHECK(j["diagnostics"][0]["file"] == "caff\\xe8.mpf");
  CHECK(j["diagnostics"][0]["message"] == "quoted \\xff byte");
  auto s = iso::diag::renderSarif({d}, sm, "isolint", "1");
  CHECK(s["runs"][0]["results"][0]["message"]["text"] == "quoted \\xff byte");
  CHECK(s["runs"][0]["results"][0]["locations"][0]["physicalLocation"]["artifactLocation"]["uri"] == "caff%E8.mpf");
}

// ---- rule documentation (one source: man/isolint.1) ------------------------------------------

#include "diag/RuleDocs.h"

TEST_CASE("rules: every code has its documentation and example from man/isolint.1") {
  for (size_t i = 0; i < iso::diag::codeCount(); ++i) {
    auto code = static_cast<iso::diag::Code>(i);
    CAPTURE(iso::diag::info(code).code);
    const auto& d = iso::diag::ruleDoc(code);
    CHECK(d.text.size() > 20);
    // E211 needs 31 files: its entry describes the chain instead of showing it
    if (code != iso::diag::Code::NestingDepth) CHECK_FALSE(d.example.empty());
    CHECK(d.text.find("\\f") == std::string::npos); // no roff left
    CHECK(d.markdown.find("\\f") == std::string::npos);
  }
  const auto& e108 = iso::diag::ruleDoc(iso::diag::Code::LogicOperand);
  CHECK(e108.markdown.find("`(R1 > 2) AND (R2 < 3)`") != std::string::npos);
  CHECK(e108.text.find("(R1 > 2) AND (R2 < 3)") != std::string::npos);
  CHECK(iso::diag::explainRule(iso::diag::Code::CaseBackwardJump).find("    CASE R1 OF 1 GOTOB Su\n") !=
        std::string::npos);
}

TEST_CASE("sarif: rules carry fullDescription and help (text and markdown), no helpUri") {
  iso::diag::SourceManager sm;
  auto s = iso::diag::renderSarif({}, sm, "isolint", "1");
  const auto& rules = s["runs"][0]["tool"]["driver"]["rules"];
  REQUIRE(rules.size() == iso::diag::codeCount());
  for (const auto& r : rules) {
    CAPTURE(r["id"].get<std::string>());
    CHECK(r["fullDescription"]["text"].get<std::string>().size() > 20);
    CHECK(r["help"]["markdown"].get<std::string>().find("isolint: disable=") != std::string::npos);
    CHECK(r["help"]["text"].get<std::string>().find(r["id"].get<std::string>()) == 0);
    // the rules have no web page: their documentation travels in `help` instead of a link
    CHECK_FALSE(r.contains("helpUri"));
  }
  CHECK(rules[0]["help"]["markdown"].get<std::string>().find("```") != std::string::npos);
}

// ---- SARIF fingerprints -----------------------------------------------------------------------

TEST_CASE("sarif: fingerprints survive edits elsewhere and tell identical lines apart") {
  using iso::diag::sarifFingerprint;
  auto a = sarifFingerprint("W402", "p.mpf", "G01 X10", 0);
  CHECK(a == sarifFingerprint("W402", "p.mpf", "   G01    X10  ", 0)); // indentation and blanks
  CHECK(a != sarifFingerprint("W402", "p.mpf", "G01 X10", 1));         // the second identical finding
  CHECK(a != sarifFingerprint("W401", "p.mpf", "G01 X10", 0));
  CHECK(a != sarifFingerprint("W402", "q.mpf", "G01 X10", 0));
  CHECK(a != sarifFingerprint("W402", "p.mpf", "G01 X11", 0));
  // a line inserted above moves the finding but keeps its fingerprint
  auto fingerprintsOf = [](const std::string& text) {
    iso::diag::SourceManager sm;
    uint32_t id = sm.add("p.mpf", text);
    std::vector<iso::diag::Diagnostic> ds;
    for (uint32_t line = 1; line <= 3; ++line) {
      if (sm.lineText(id, line) != "G01 X10") continue;
      iso::diag::Diagnostic d;
      d.code = iso::diag::Code::FeedUnset;
      d.severity = iso::diag::Severity::Warning;
      d.loc = {id, line, 1};
      ds.push_back(d);
    }
    auto s = iso::diag::renderSarif(ds, sm, "isolint", "1");
    std::vector<std::string> out;
    for (const auto& r : s["runs"][0]["results"])
      out.push_back(r["partialFingerprints"]["isolint/v1"]);
    return out;
  };
  auto before = fingerprintsOf("G01 X10\nG01 X10\n");
  auto after = fingerprintsOf("R1 = 1\nG01 X10\nG01 X10\n");
  REQUIRE(before.size() == 2);
  CHECK(before == after);
  CHECK(before[0] != before[1]);
}

TEST_CASE("github: workflow commands with escaped properties and messages") {
  iso::diag::SourceManager sm;
  uint32_t id = sm.add("a,b:c.mpf", "G01 X10\n");
  iso::diag::Diagnostic d;
  d.code = iso::diag::Code::FeedUnset;
  d.severity = iso::diag::Severity::Warning;
  d.loc = {id, 1, 5};
  d.endLine = 1;
  d.endCol = 8;
  d.message = "100% wrong\nreally";
  std::ostringstream os;
  iso::diag::writeGithub(os, {d}, sm);
  CHECK(os.str() == "::warning file=a%2Cb%3Ac.mpf,line=1,col=5,endLine=1,endColumn=8,title=W402 feed-unset::100%25 "
                    "wrong\\x0areally\n"); // control bytes of a message are escaped first
}

// ---- the source's line index ------------------------------------------------------------------

TEST_CASE("source manager: lines are found in any order, as far as the index has to go") {
  iso::diag::SourceManager sm;
  const uint32_t id = sm.add("p.mpf", "N1 G0\r\nN2 X1\n\nN4 Y2\nN5 M30\n");
  const uint32_t tail = sm.add("q.mpf", "A\nB"); // no line end at the end
  const uint32_t none = sm.add("e.mpf", "");
  // a line near the start first: the index stops there
  CHECK(sm.lineText(id, 2) == "N2 X1");
  CHECK_FALSE(sm.file(id).indexed);
  CHECK(sm.file(id).lineStarts.size() == 3);
  // further on, then back, then past the end
  CHECK(sm.lineText(id, 5) == "N5 M30");
  CHECK(sm.lineText(id, 1) == "N1 G0");
  CHECK(sm.lineText(id, 3) == "");
  CHECK(sm.lineText(id, 4) == "N4 Y2");
  CHECK(sm.lineText(id, 6) == "");
  CHECK(sm.file(id).indexed);
  CHECK(sm.file(id).lineStarts.size() == 5); // the last line end starts no line
  CHECK(sm.lineText(id, 0) == "");
  CHECK(sm.lineText(tail, 2) == "B");
  CHECK(sm.lineText(tail, 3) == "");
  CHECK(sm.lineText(none, 1) == "");
  CHECK(sm.lineText(none, 2) == "");
}
