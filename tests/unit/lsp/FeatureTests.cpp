//! @file FeatureTests.cpp
//! @brief The language features through the protocol: diagnostics on open, change (full and
//!        incremental) and save with UTF-16 ranges, hover, definition across files,
//!        references, symbols, completion, the colon quick fix.
#include <string>

#include <doctest/doctest.h>

#include "LspTestUtil.h"
#include "lsp/TextDocument.h"

using namespace iso;
using namespace iso::test;

namespace {
// Line 1 has a G code that does not exist after a comment with two-byte and four-byte
// characters: its UTF-16 column differs from its byte column.
const char* kMain = "G90 G01 F=100\n"
                    "Start: X10 (\xC3\xA8\xF0\x9F\x98\x80) G7\n"
                    "Lift\n"
                    "R5 = $aa_iw[X]\n"
                    "GOTOF Fine\n"
                    "Fine: M30\n";
const char* kLift = "PROC Lift SAVE\nZ=10\nM17\n";
const char* kFixed = "G90 G01 F=100\nStart: X10\nLift\nR5 = $aa_iw[X]\nGOTOF Fine\nFine: M30\n";

json didChangeFull(const std::string& uri, int version, const std::string& text) {
  return {{"textDocument", {{"uri", uri}, {"version", version}}}, {"contentChanges", {{{"text", text}}}}};
}

/// The codes of a publishDiagnostics params object.
std::vector<std::string> codes(const json& published) {
  std::vector<std::string> out;
  for (const auto& d : published["diagnostics"])
    out.push_back(d["code"].get<std::string>());
  return out;
}

struct Folder {
  TempDir dir;
  std::string main, lift;
  Folder() {
    dir.write("main.mpf", kMain);
    dir.write("lift.spf", kLift);
    main = uriIn(dir, "main.mpf");
    lift = uriIn(dir, "lift.spf");
  }
};
} // namespace

TEST_CASE("lsp: diagnostics on open: code, severity, UTF-16 range, no link, source") {
  Folder f;
  Session s = runSession(initialize() + didOpen(f.main, kMain) + shutdownExit());
  auto pub = s.published(f.main);
  REQUIRE(pub.size() == 1);
  CHECK(pub[0]["version"] == 1);
  REQUIRE(codes(pub[0]) == std::vector<std::string>{"E310"});
  const json& d = pub[0]["diagnostics"][0];
  CHECK(d["severity"] == 1);
  CHECK(d["source"] == "isolint");
  CHECK_FALSE(d.contains("codeDescription")); // no rule web page exists to link to
  // "Start: X10 (" 12 units, è 1 unit, the emoji 2 units, ") " 2 units: G7 at 17.
  CHECK(d["range"] == range(1, 17, 1, 19));
  CHECK(d["message"].get<std::string>().find("G7") != std::string::npos);
}

TEST_CASE("lsp: the program set is the folder - open buffers win over the disk") {
  Folder f;
  SUBCASE("a call resolved by a sibling on disk") {
    Session s = runSession(initialize() + didOpen(f.main, kFixed) + shutdownExit());
    REQUIRE(s.published(f.main).size() == 1);
    CHECK(codes(s.published(f.main)[0]).empty());
  }
  SUBCASE("a buffer that renames the PROC breaks the call, without saving") {
    Session s =
        runSession(initialize() + didOpen(f.main, kFixed) + didOpen(f.lift, "PROC Lower SAVE\nM17\n") + shutdownExit());
    auto pub = s.published(f.main);
    REQUIRE(!pub.empty());
    CHECK(codes(pub.back()) == std::vector<std::string>{"E210"});
    REQUIRE(!s.published(f.lift).empty());
    CHECK(codes(s.published(f.lift).back()).empty());
  }
}

TEST_CASE("lsp: diagnostics after a full change, an incremental change and a save") {
  Folder f;
  // Incremental: delete " (è😀) G7" on line 2 (UTF-16 columns 10..19).
  json incremental = {{"textDocument", {{"uri", f.main}, {"version", 3}}},
                      {"contentChanges", {{{"range", range(2, 10, 2, 19)}, {"text", ""}}}}};
  Session s = runSession(initialize() + didOpen(f.main, kMain) +
                         request(1, "textDocument/documentSymbol", {{"textDocument", {{"uri", f.main}}}}) +
                         notify("textDocument/didChange", didChangeFull(f.main, 2, "G7\n" + std::string(kMain))) +
                         request(2, "textDocument/documentSymbol", {{"textDocument", {{"uri", f.main}}}}) +
                         notify("textDocument/didChange", incremental) +
                         request(3, "textDocument/documentSymbol", {{"textDocument", {{"uri", f.main}}}}) +
                         notify("textDocument/didSave", {{"textDocument", {{"uri", f.main}}}}) + shutdownExit());
  auto pub = s.published(f.main);
  REQUIRE(pub.size() == 4);
  CHECK(codes(pub[0]) == std::vector<std::string>{"E310"});
  CHECK(codes(pub[1]) == std::vector<std::string>{"E310", "E310"});
  CHECK(pub[1]["version"] == 2);
  CHECK(pub[1]["diagnostics"][0]["range"] == range(0, 0, 0, 2));
  CHECK(pub[1]["diagnostics"][1]["range"] == range(2, 17, 2, 19));
  CHECK(codes(pub[2]) == std::vector<std::string>{"E310"});
  CHECK(pub[2]["version"] == 3);
  CHECK(pub[2]["diagnostics"][0]["range"]["start"]["line"] == 0);
  CHECK(codes(pub[3]) == std::vector<std::string>{"E310"}); // the save lints again
}

TEST_CASE("lsp: a burst of changes is linted once - closing clears the diagnostics") {
  Folder f;
  Session s = runSession(initialize() + didOpen(f.main, kMain) +
                         notify("textDocument/didChange", didChangeFull(f.main, 2, "G7\nM30\n")) +
                         notify("textDocument/didChange", didChangeFull(f.main, 3, kFixed)) +
                         notify("textDocument/didClose", {{"textDocument", {{"uri", f.main}}}}) + shutdownExit());
  auto pub = s.published(f.main);
  REQUIRE(pub.size() == 1);
  CHECK(pub[0]["diagnostics"].empty());
  CHECK(!pub[0].contains("version"));
}

TEST_CASE("lsp: relatedInformation from the notes") {
  TempDir dir;
  std::string uri = uriIn(dir, "dup.mpf");
  Session s = runSession(initialize() + didOpen(uri, "A1: G90\nA1: M30\n") + shutdownExit());
  auto pub = s.published(uri);
  REQUIRE(pub.size() == 1);
  REQUIRE(codes(pub[0]) == std::vector<std::string>{"E203"});
  const json& rel = pub[0]["diagnostics"][0]["relatedInformation"];
  REQUIRE(rel.size() == 1);
  CHECK(rel[0]["location"]["uri"] == uri);
  CHECK(rel[0]["location"]["range"]["start"]["line"] == 0);
}

TEST_CASE("lsp: --disable and --werror apply to published diagnostics") {
  TempDir dir;
  std::string uri = uriIn(dir, "w.mpf");
  Session s = runSession(initialize() + didOpen(uri, "G01 X10\nM30\n") + shutdownExit(), {diag::Code::FeedUnset});
  REQUIRE(s.published(uri).size() == 1);
  CHECK(codes(s.published(uri)[0]).empty());
}

TEST_CASE("lsp: hover") {
  Folder f;
  auto hoverText = [&](const Session& s, int id) {
    json r = s.response(id);
    return r["result"].is_null() ? std::string() : r["result"]["contents"]["value"].get<std::string>();
  };
  std::string in = initialize() + didOpen(f.main, kMain) + at(1, "textDocument/hover", f.main, 0, 5) +
                   at(2, "textDocument/hover", f.main, 5, 7) + at(3, "textDocument/hover", f.main, 3, 7) +
                   at(4, "textDocument/hover", f.main, 4, 2) + at(5, "textDocument/hover", f.main, 3, 1) +
                   at(6, "textDocument/hover", f.main, 2, 2) + at(7, "textDocument/hover", f.main, 4, 8) +
                   at(8, "textDocument/hover", f.main, 1, 17) + at(9, "textDocument/hover", f.main, 1, 13) +
                   shutdownExit();
  Session s = runSession(in);
  CHECK(hoverText(s, 1).find("**G01**") != std::string::npos);
  CHECK(hoverText(s, 1).find("motion") != std::string::npos);
  CHECK(s.response(1)["result"]["range"] == range(0, 4, 0, 7));
  CHECK(hoverText(s, 2).find("end of program") != std::string::npos); // M30
  CHECK(hoverText(s, 3).find("$aa_iw[axis]") != std::string::npos);
  CHECK(hoverText(s, 4).find("jump forward") != std::string::npos); // GOTOF
  CHECK(hoverText(s, 5).find("R parameter 5") != std::string::npos);
  CHECK(hoverText(s, 6).find("subprogram") != std::string::npos);    // Lift
  CHECK(hoverText(s, 7).find("label, line 6") != std::string::npos); // Fine
  CHECK(hoverText(s, 8).find("not a G code") != std::string::npos);  // G7
  CHECK(s.response(9)["result"].is_null());                          // inside a comment
  CHECK(s.response(1)["result"]["contents"]["kind"] == "markdown");
}

TEST_CASE("lsp: hover on PLC sequences, keywords and plain text clients") {
  TempDir dir;
  std::string uri = uriIn(dir, "m.mpf");
  std::string in = request(0, "initialize",
                           {{"capabilities", {{"textDocument", {{"hover", {{"contentFormat", {"plaintext"}}}}}}}}}) +
                   didOpen(uri, "M23\nIF R1 > 2\nENDIF\nM30\n") + at(1, "textDocument/hover", uri, 0, 1) +
                   at(2, "textDocument/hover", uri, 1, 0) + at(3, "textDocument/hover", uri, 2, 3) + shutdownExit();
  Session s = runSession(in);
  CHECK(s.response(1)["result"]["contents"]["value"].get<std::string>().find("PLC sequence 23") != std::string::npos);
  CHECK(s.response(1)["result"]["contents"]["kind"] == "plaintext");
  CHECK(s.response(2)["result"]["contents"]["value"].get<std::string>().find("**IF**") != std::string::npos);
  CHECK(s.response(3)["result"]["contents"]["value"].get<std::string>().find("ENDIF") != std::string::npos);
}

TEST_CASE("lsp: definition of labels and subprograms across the set") {
  Folder f;
  std::string in = initialize() + didOpen(f.main, kMain) + at(1, "textDocument/definition", f.main, 4, 7) +
                   at(2, "textDocument/definition", f.main, 2, 4) + at(3, "textDocument/definition", f.main, 0, 1) +
                   at(4, "textDocument/definition", f.main, 5, 1) + shutdownExit();
  Session s = runSession(in);
  json label = s.response(1)["result"];
  REQUIRE(label.size() == 1);
  CHECK(label[0]["uri"] == f.main);
  CHECK(label[0]["range"] == range(5, 0, 5, 4));
  json proc = s.response(2)["result"]; // the cursor just after "Lift" still finds it
  REQUIRE(proc.size() == 1);
  CHECK(proc[0]["uri"] == f.lift);
  CHECK(proc[0]["range"] == range(0, 5, 0, 9));
  CHECK(s.response(3)["result"].empty());
  CHECK(s.response(4)["result"].size() == 1); // a label definition is its own definition
}

TEST_CASE("lsp: references of a label and of a subprogram") {
  Folder f;
  TempDir& dir = f.dir;
  dir.write("other.mpf", "Lift\nIF R1 > 2 THEN Lift\nM30\n");
  std::string in = initialize() + didOpen(f.main, kMain) +
                   at(1, "textDocument/references", f.main, 5, 1, {{"context", {{"includeDeclaration", true}}}}) +
                   at(2, "textDocument/references", f.main, 2, 1, {{"context", {{"includeDeclaration", false}}}}) +
                   at(3, "textDocument/references", f.main, 2, 1, {{"context", {{"includeDeclaration", true}}}}) +
                   shutdownExit();
  Session s = runSession(in);
  json labels = s.response(1)["result"];
  REQUIRE(labels.size() == 2);
  CHECK(labels[0]["range"] == range(5, 0, 5, 4));
  CHECK(labels[1]["range"] == range(4, 6, 4, 10));
  CHECK(s.response(2)["result"].size() == 3); // main.mpf line 3, other.mpf lines 1 and 2
  CHECK(s.response(3)["result"].size() == 4);
}

TEST_CASE("lsp: document symbols") {
  Folder f;
  Session s =
      runSession(initialize() + didOpen(f.lift, "PROC Lift SAVE\nUp: Z=10\nM17\n") +
                 request(1, "textDocument/documentSymbol", {{"textDocument", {{"uri", f.lift}}}}) + shutdownExit());
  json syms = s.response(1)["result"];
  REQUIRE(syms.size() == 2);
  CHECK(syms[0]["name"] == "Lift");
  CHECK(syms[0]["kind"] == 12);
  CHECK(syms[0]["selectionRange"] == range(0, 5, 0, 9));
  CHECK(syms[1]["name"] == "Up");
  CHECK(syms[1]["selectionRange"] == range(1, 0, 1, 2));
}

TEST_CASE("lsp: completion") {
  Folder f;
  std::string text = std::string(kMain) + "GOTOB \nR1 = $aa\n";
  std::string in = initialize() + didOpen(f.main, text) + at(1, "textDocument/completion", f.main, 6, 6) +
                   at(2, "textDocument/completion", f.main, 7, 8) + at(3, "textDocument/completion", f.main, 2, 0) +
                   shutdownExit();
  Session s = runSession(in);
  auto labels = [&](int id) {
    std::vector<std::string> out;
    json r = s.response(id);
    for (const auto& item : r["result"]["items"])
      out.push_back(item["label"].get<std::string>());
    return out;
  };
  CHECK(labels(1) == std::vector<std::string>{"Start", "Fine"});
  auto sys = labels(2);
  CHECK(std::find(sys.begin(), sys.end(), "$aa_iw") != sys.end());
  CHECK(std::find(sys.begin(), sys.end(), "GOTOF") == sys.end());
  // The whole "$aa" is replaced, so the client does not write "$$aa_iw".
  CHECK(s.response(2)["result"]["items"][0]["textEdit"]["range"] == range(7, 5, 7, 8));
  auto all = labels(3);
  for (const char* want : {"GOTOF", "CASE", "WHEN", "G00", "G91", "M30", "$aa_marker", "Lift"})
    CHECK_MESSAGE(std::find(all.begin(), all.end(), want) != all.end(), want);
}

TEST_CASE("lsp: the quick fix drops the colon after a jump's label") {
  TempDir dir;
  std::string uri = uriIn(dir, "c.mpf");
  std::string in = initialize() + didOpen(uri, "GOTOF Fine:\nFine: M30\n") +
                   request(1, "textDocument/codeAction",
                           {{"textDocument", {{"uri", uri}}},
                            {"range", range(0, 0, 0, 0)},
                            {"context", {{"diagnostics", json::array()}}}}) +
                   request(2, "textDocument/codeAction",
                           {{"textDocument", {{"uri", uri}}},
                            {"range", range(1, 0, 1, 0)},
                            {"context", {{"diagnostics", json::array()}}}}) +
                   shutdownExit();
  Session s = runSession(in);
  json actions = s.response(1)["result"];
  REQUIRE(actions.size() == 1);
  CHECK(actions[0]["kind"] == "quickfix");
  CHECK(actions[0]["diagnostics"][0]["code"] == "E100");
  json edits = actions[0]["edit"]["changes"][uri];
  REQUIRE(edits.size() == 1);
  CHECK(edits[0]["range"] == range(0, 10, 0, 11));
  CHECK(edits[0]["newText"] == "");
  CHECK(s.response(2)["result"].empty());
}

TEST_CASE("lsp: features on a document that is not open answer empty") {
  Session s = runSession(initialize() + at(1, "textDocument/hover", "file:///nowhere/x.mpf", 0, 0) +
                         at(2, "textDocument/definition", "file:///nowhere/x.mpf", 0, 0) + shutdownExit());
  CHECK(s.response(1)["result"].is_null());
  CHECK(s.response(2)["result"].empty());
}

TEST_CASE("lsp: an untitled buffer is a set of its own") {
  Session s = runSession(initialize() + didOpen("untitled:Untitled-1", "G7\nM30\n") + shutdownExit());
  REQUIRE(s.published("untitled:Untitled-1").size() == 1);
  CHECK(codes(s.published("untitled:Untitled-1")[0]) == std::vector<std::string>{"E310"});
}

TEST_CASE("lsp: UTF-16 columns and byte offsets") {
  std::string_view line = "a\xC3\xA8"
                          "b\xF0\x9F\x98\x80"
                          "c";
  CHECK(lsp::utf16Column(line, 0) == 0);
  CHECK(lsp::utf16Column(line, 3) == 2);
  CHECK(lsp::utf16Column(line, 8) == 5);
  CHECK(lsp::utf16Column(line, 100) == 6);
  CHECK(lsp::byteColumn(line, 2) == 3);
  CHECK(lsp::byteColumn(line, 4) == 4); // inside the surrogate pair: the character's start
  CHECK(lsp::byteColumn(line, 5) == 8);
  CHECK(lsp::byteColumn(line, 99) == line.size());
  CHECK(lsp::utf16Column("\xFF\xFE", 2) == 2); // bytes that are not UTF-8: one unit each

  lsp::TextDocument doc("G01\r\n\xC3\xA8X1\n", 1);
  CHECK(doc.lineCount() == 3);
  CHECK(doc.line(0) == "G01");
  CHECK(doc.offset({0, 99}) == 3); // before the CR
  doc.edit({{1, 1}, {1, 2}}, "Y");
  CHECK(doc.text() == "G01\r\n\xC3\xA8Y1\n");
  doc.edit({{0, 3}, {1, 0}}, " ");
  CHECK(doc.text() == "G01 \xC3\xA8Y1\n");
  doc.edit({{9, 0}, {9, 0}}, "M30\n"); // past the end: appends
  CHECK(doc.text() == "G01 \xC3\xA8Y1\nM30\n");
}

TEST_CASE("lsp: file URIs") {
  CHECK(lsp::pathToUri("/a b/x#1.mpf") == "file:///a%20b/x%231.mpf");
  CHECK(lsp::uriToPath("file:///a%20b/x%231.mpf") == "/a b/x#1.mpf");
  CHECK(lsp::uriToPath("FILE:///x.mpf") == "/x.mpf");
  CHECK(!lsp::uriToPath("untitled:Untitled-1"));
  CHECK(!lsp::uriToPath("file://host/x.mpf"));
  CHECK(!lsp::uriToPath("file:///x%2"));
  CHECK(!lsp::uriToPath("file:///x%00y"));
}

TEST_CASE("lsp: semantic tokens - keywords, G codes, axes, R parameters, labels, numbers") {
  Folder f;
  Session s = runSession(initialize() + didOpen(f.main, "Top: G0 X1\nIF R1 == 2 GOTOB Top\nM30\n") +
                         request(1, "textDocument/semanticTokens/full", {{"textDocument", {{"uri", f.main}}}}) +
                         request(2, "textDocument/semanticTokens/full", {{"textDocument", 3}}) + shutdownExit());
  json legend = s.response(0)["result"]["capabilities"]["semanticTokensProvider"]["legend"]["tokenTypes"];
  CHECK(legend == json{"keyword", "function", "property", "parameter", "variable", "enumMember", "number"});
  // Top(label 5) G0(function 1) X1(property 2) / IF(keyword 0) R1(parameter 3) 2(number 6) GOTOB(keyword 0)
  // M30(function 1); Top after GOTOB is no label definition and gets no token
  std::vector<int> want = {0, 0, 3, 5, 0, 0, 5, 2, 1, 0, 0, 3, 2, 2, 0, 1, 0, 2, 0, 0,
                           0, 3, 2, 3, 0, 0, 6, 1, 6, 0, 0, 2, 5, 0, 0, 1, 0, 3, 1, 0};
  CHECK(s.response(1)["result"]["data"] == json(want));
  CHECK(s.response(2).contains("error"));
}
