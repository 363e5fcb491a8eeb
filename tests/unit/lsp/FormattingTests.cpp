//! @file FormattingTests.cpp
//! @brief textDocument/formatting and rangeFormatting: the edits the server sends, applied to
//!        the document, give what `isofmt FILE` prints for that file (its folder's
//!        isotools.toml, its machine file and dialect); range formatting changes only the lines
//!        the range touches; a document with syntax errors is not changed; no renumbering.
#include <algorithm>
#include <sstream>
#include <string>
#include <vector>

#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include "LspTestUtil.h"
#include "driver/Format.h"

using namespace iso;
using namespace iso::test;

namespace {

/// What `isofmt PATH` prints (run in-process), and its exit code.
std::string isofmt(const std::string& path, int expectRc = 0) {
  driver::FormatOptions o;
  o.paths = {path};
  std::ostringstream out, err;
  driver::Io io{out, err, false, false};
  const int rc = driver::runFormat(o, io);
  INFO(err.str());
  CHECK(rc == expectRc);
  return out.str();
}

/// Applies LSP TextEdits (UTF-16 positions, not overlapping) to `text`.
std::string applyEdits(const std::string& text, const json& edits) {
  lsp::TextDocument doc(text, 1);
  std::vector<std::pair<lsp::Range, std::string>> sorted;
  for (const auto& e : edits) {
    const auto& r = e["range"];
    sorted.push_back({{{r["start"]["line"].get<uint32_t>(), r["start"]["character"].get<uint32_t>()},
                       {r["end"]["line"].get<uint32_t>(), r["end"]["character"].get<uint32_t>()}},
                      e["newText"].get<std::string>()});
  }
  // From the last to the first: the earlier positions stay valid.
  std::sort(sorted.begin(), sorted.end(),
            [&](const auto& a, const auto& b) { return doc.offset(a.first.start) > doc.offset(b.first.start); });
  for (const auto& [range, newText] : sorted)
    doc.edit(range, newText);
  return doc.text();
}

std::vector<std::string> linesOf(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);)
    out.push_back(l);
  return out;
}

json formatParams(const std::string& uri) {
  return {{"textDocument", {{"uri", uri}}}, {"options", {{"tabSize", 8}, {"insertSpaces", true}}}};
}

/// The result of textDocument/formatting for `path` opened with `text`, under isolint --lsp's
/// policy (the folder's isotools.toml and machine file).
json formatted(const std::string& path, const std::string& text, const std::string& method = "textDocument/formatting",
               json extra = json::object()) {
  const std::string uri = lsp::pathToUri(path);
  json params = formatParams(uri);
  params.update(extra);
  driver::CommonOptions common;
  Session s =
      runSession(initialize() + didOpen(uri, text) + request(1, method, params) + shutdownExit(), {}, {}, &common);
  json r = s.response(1);
  REQUIRE(r.is_object());
  INFO(r.dump());
  REQUIRE(r.contains("result"));
  return r["result"];
}

const char* kMessy = "n10 g90 g01    x10 y 20 f1000   \n"
                     "r1=5\n"
                     "if r1>3\n"
                     "g1 x=r1+2 y-.5\n"
                     "if (r1 == 11) and ($aa_in[1]==0)\n"
                     "$aa_out[2]=1\n"
                     "endif\n"
                     "\n"
                     "\n"
                     "\n"
                     "endif\n"
                     "m30\n";

} // namespace

TEST_CASE("lsp formatting: the capabilities advertise document and range formatting") {
  Session s = runSession(initialize() + shutdownExit());
  const json caps = s.response(0)["result"]["capabilities"];
  CHECK(caps["documentFormattingProvider"] == true);
  CHECK(caps["documentRangeFormattingProvider"] == true);
}

TEST_CASE("lsp formatting: the edits give what isofmt prints for the file, default style") {
  TempDir dir;
  const std::string path = dir.write("messy.mpf", kMessy);
  const std::string expected = isofmt(path);
  REQUIRE(expected != kMessy);
  const json edits = formatted(path, kMessy);
  REQUIRE(edits.is_array());
  CHECK(!edits.empty());
  CHECK(applyEdits(kMessy, edits) == expected);
  // The editor's indentation options do not change the layout (tabSize 8 was sent): isofmt's 2.
  CHECK(expected.find("\n  G1 X=R1 + 2") != std::string::npos);
  // Whole lines: every edit starts at the start of a line.
  for (const auto& e : edits)
    CHECK(e["range"]["start"]["character"] == 0);
}

TEST_CASE("lsp formatting: the [format] table of the folder's isotools.toml is the style, as for isofmt") {
  TempDir dir;
  dir.write("isotools.toml", "[format]\ncase = \"lower\"\nspaces = false\noperator-spaces = false\nindent = 4\n"
                             "numbers = \"normalised\"\nblank-lines = 0\n");
  const std::string path = dir.write("messy.mpf", kMessy);
  const std::string expected = isofmt(path);
  CHECK(expected.find("\n    g1 x=r1+2 y-0.5\n") != std::string::npos);
  CHECK(applyEdits(kMessy, formatted(path, kMessy)) == expected);
}

TEST_CASE("lsp formatting: the buffer is formatted, not the file on disk, and its CRLF line ends stay") {
  TempDir dir;
  std::string crlf;
  for (const char* p = kMessy; *p; ++p)
    crlf += *p == '\n' ? std::string("\r\n") : std::string(1, *p);
  const std::string path = dir.write("messy.mpf", crlf);
  const std::string expected = isofmt(path);
  CHECK(expected.find("\r\n") != std::string::npos);
  dir.write("messy.mpf", "M30\n"); // the disk lags the buffer
  CHECK(applyEdits(crlf, formatted(path, crlf)) == expected);
}

TEST_CASE("lsp formatting: positions are UTF-16 (a comment with a character outside the BMP)") {
  TempDir dir;
  const std::string text = "x1 ; \xF0\x9F\x94\xA7 chiave\ng01    x2 ; \xF0\x9F\x94\xA7\nM30\n";
  const std::string path = dir.write("utf.mpf", text);
  const json edits = formatted(path, text);
  CHECK(applyEdits(text, edits) == isofmt(path));
  // Lines 1 and 2 change (the comment of line 2 keeps its column): one edit, ending after the
  // wrench of line 2, a character of 4 bytes and 2 UTF-16 units.
  REQUIRE(edits.size() == 1);
  CHECK(edits[0]["range"] == range(0, 0, 1, 14));
}

TEST_CASE("lsp formatting: a document with syntax errors is not changed") {
  TempDir dir;
  const std::string text = "g01    x=(1\nr1=5\nm30\n";
  const std::string path = dir.write("bad.mpf", text);
  CHECK(isofmt(path) == text);
  const json edits = formatted(path, text);
  CHECK(edits == json::array());
}

TEST_CASE("lsp formatting: no renumbering, even when the settings renumber on every run") {
  TempDir dir;
  dir.write("isotools.toml", "[format]\nrenumber = \"100,5\"\n");
  const std::string text = "N10 g0 x1\nN20 m30\n";
  const std::string path = dir.write("num.mpf", text);
  CHECK(isofmt(path) == "N100 G0 X1\nN105 M30\n");
  CHECK(applyEdits(text, formatted(path, text)) == "N10 G0 X1\nN20 M30\n");
}

TEST_CASE("lsp formatting: range formatting changes only the lines the range touches") {
  TempDir dir;
  const std::string path = dir.write("messy.mpf", kMessy);
  const std::string all = isofmt(path);
  const std::vector<std::string> before = linesOf(kMessy);
  SUBCASE("lines 3 and 4 (0-based 2..3), the range ending inside line 4") {
    const json edits = formatted(path, kMessy, "textDocument/rangeFormatting", {{"range", range(2, 3, 3, 2)}});
    std::vector<std::string> want = before;
    want[2] = "IF R1 > 3";
    want[3] = "  G1 X=R1 + 2 Y-.5";
    CHECK(linesOf(applyEdits(kMessy, edits)) == want);
    for (const auto& e : edits) {
      CHECK(e["range"]["start"]["line"] >= 2);
      CHECK(e["range"]["end"]["line"] <= 3);
    }
  }
  SUBCASE("a range that ends at the start of a line leaves that line out") {
    const json edits = formatted(path, kMessy, "textDocument/rangeFormatting", {{"range", range(1, 0, 2, 0)}});
    std::vector<std::string> want = before;
    want[1] = "R1 = 5";
    CHECK(linesOf(applyEdits(kMessy, edits)) == want);
  }
  SUBCASE("the range of the whole document gives the document's formatting") {
    const json edits = formatted(path, kMessy, "textDocument/rangeFormatting", {{"range", range(0, 0, 12, 0)}});
    CHECK(applyEdits(kMessy, edits) == all);
  }
  SUBCASE("a run of blank lines in the range shrinks, one outside it stays") {
    const json in = formatted(path, kMessy, "textDocument/rangeFormatting", {{"range", range(7, 0, 10, 0)}});
    CHECK(applyEdits(kMessy, in).find("endif\n\nendif") != std::string::npos);
    const json out = formatted(path, kMessy, "textDocument/rangeFormatting", {{"range", range(0, 0, 1, 4)}});
    CHECK(applyEdits(kMessy, out).find("endif\n\n\n\nendif") != std::string::npos);
  }
}

TEST_CASE("lsp formatting: an invalid settings file is a failed request, with isofmt's message") {
  TempDir dir;
  dir.write("isotools.toml", "[format]\nindent = 99\n");
  const std::string path = dir.write("p.mpf", "m30\n");
  isofmt(path, 2);
  const std::string uri = lsp::pathToUri(path);
  driver::CommonOptions common;
  Session s = runSession(initialize() + didOpen(uri, "m30\n") +
                             request(1, "textDocument/formatting", formatParams(uri)) + shutdownExit(),
                         {}, {}, &common);
  const json r = s.response(1);
  REQUIRE(r.contains("error"));
  CHECK(r["error"]["code"] == -32803);
  const std::string message = r["error"]["message"].get<std::string>();
  CHECK(message.find("isotools.toml") != std::string::npos);
  CHECK(message.find("indent") != std::string::npos);
}

TEST_CASE("lsp formatting: a document that is not open, and one without a policy") {
  Session s = runSession(initialize() +
                         request(1, "textDocument/formatting", formatParams("file:///nowhere/never-opened.mpf")) +
                         didOpen("untitled:Untitled-1", "g01    x1\nm30\n") +
                         request(2, "textDocument/formatting", formatParams("untitled:Untitled-1")) + shutdownExit());
  CHECK(s.response(1)["result"] == json::array());
  const json edits = s.response(2)["result"];
  CHECK(applyEdits("g01    x1\nm30\n", edits) == "G01 X1\nM30\n");
}
