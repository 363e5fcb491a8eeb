//! @file FoldingTests.cpp
//! @brief textDocument/foldingRange through the protocol: IF/ELSE/ENDIF, WHEN/CANCEL, a
//!        subprogram's body, comment runs; unbalanced code and a document that is not open;
//!        workspace/symbol; semantic tokens delta.
#include <string>

#include <doctest/doctest.h>

#include "LspTestUtil.h"

using namespace iso;
using namespace iso::test;

namespace {
json foldsOf(const std::string& name, const std::string& text) {
  TempDir dir;
  dir.write(name, text);
  const std::string uri = uriIn(dir, name);
  Session s = runSession(initialize() + didOpen(uri, text) +
                         request(1, "textDocument/foldingRange", {{"textDocument", {{"uri", uri}}}}) + shutdownExit());
  return s.response(1)["result"];
}
json fold(uint32_t from, uint32_t to) { return {{"startLine", from}, {"endLine", to}}; }
} // namespace

TEST_CASE("lsp: folding ranges of IF ELSE ENDIF blocks, nested, keep the ELSE and ENDIF lines visible") {
  json r = foldsOf("main.mpf", "R1=1\n"         // 0
                               "IF R1 == 1\n"   // 1
                               "  X10\n"        // 2
                               "  IF R2 == 0\n" // 3
                               "    Y5\n"       // 4
                               "    Y6\n"       // 5
                               "  ENDIF\n"      // 6
                               "ELSE\n"         // 7
                               "  X20\n"        // 8
                               "  X30\n"        // 9
                               "ENDIF\n"        // 10
                               "IF R1 == 2 GOTOF E\n"
                               "E: M30\n");
  REQUIRE(r.is_array());
  CHECK(r == json::array({fold(3, 5), fold(1, 6), fold(7, 9)}));
}

TEST_CASE("lsp: folding ranges of a long WHEN, a subprogram body and comment runs") {
  json r = foldsOf("lift.spf", "PROC Lift SAVE\n"        // 0
                               "; first comment\n"       // 1
                               "; second comment\n"      // 2
                               "WHEN $AA_IW[X] > 5 DO\n" // 3
                               "  M=NB 12\n"             // 4
                               "  R3=1\n"                // 5
                               "CANCEL\n"                // 6
                               "POS[X]=10 FA[X]=100\n"   // 7
                               "; one comment\n"         // 8
                               "M17\n");                 // 9
  REQUIRE(r.is_array());
  json comment = fold(1, 2);
  comment["kind"] = "comment";
  CHECK(r == json::array({fold(3, 5), fold(0, 9), comment}));
}

TEST_CASE("lsp: folding ranges of unbalanced blocks are left out - a closed document has none") {
  json r = foldsOf("main.mpf", "ENDIF\nELSE\nIF R1 == 1\nX1\nX2\nM30\n");
  CHECK(r == json::array());
  TempDir dir;
  Session s = runSession(initialize() +
                         request(1, "textDocument/foldingRange", {{"textDocument", {{"uri", uriIn(dir, "x.mpf")}}}}) +
                         request(2, "textDocument/foldingRange", {{"textDocument", 5}}) + shutdownExit());
  CHECK(s.response(1)["result"] == json::array());
  CHECK(s.response(2)["error"]["code"] == -32602);
}

TEST_CASE("lsp: workspace symbols of the open program sets, filtered by the query without case") {
  TempDir dir;
  const std::string mainText = "G90 G01 F=100\nStart: X10\nLift\nGOTOB Start\nM30\n";
  dir.write("main.mpf", mainText);
  dir.write("lift.spf", "PROC Lift SAVE\nUp: Z=10\nM17\n");
  const std::string main = uriIn(dir, "main.mpf"), lift = uriIn(dir, "lift.spf");
  auto query = [](int id, json q) { return request(id, "workspace/symbol", {{"query", std::move(q)}}); };
  Session s = runSession(initialize() + query(1, "") + didOpen(main, mainText) + query(2, "") + query(3, "LI") +
                         query(4, "nothing") + query(5, 7) + request(6, "workspace/symbol") + shutdownExit());
  CHECK(s.response(1)["result"] == json::array()); // nothing open yet
  json all = s.response(2)["result"];
  REQUIRE(all.size() == 3); // Lift and Up of lift.spf, which main.mpf calls, and Start
  json start;
  for (const auto& sym : all)
    if (sym["name"] == "Start") start = sym;
  CHECK(start["location"]["uri"] == main);
  CHECK(start["location"]["range"] == range(1, 0, 1, 5));
  CHECK(start["containerName"] == "label");
  json lifts = s.response(3)["result"];
  REQUIRE(lifts.size() == 1);
  CHECK(lifts[0]["name"] == "Lift");
  CHECK(lifts[0]["kind"] == 12);
  CHECK(lifts[0]["containerName"] == "PROC");
  CHECK(lifts[0]["location"]["uri"] == lift);
  CHECK(lifts[0]["location"]["range"] == range(0, 5, 0, 9));
  CHECK(s.response(4)["result"] == json::array());
  CHECK(s.response(5)["error"]["code"] == -32602);
  CHECK(s.response(6)["error"]["code"] == -32602);
}

TEST_CASE("lsp: semantic tokens delta - one edit from the previous result, a full result for an unknown one") {
  TempDir dir;
  dir.write("main.mpf", "G0 X1\n");
  const std::string uri = uriIn(dir, "main.mpf");
  auto full = [&](int id) {
    return request(id, "textDocument/semanticTokens/full", {{"textDocument", {{"uri", uri}}}});
  };
  auto delta = [&](int id, json previous) {
    json params = {{"textDocument", {{"uri", uri}}}};
    if (!previous.is_null()) params["previousResultId"] = std::move(previous);
    return request(id, "textDocument/semanticTokens/full/delta", std::move(params));
  };
  auto change = [&](int version, const std::string& text) {
    return notify("textDocument/didChange",
                  {{"textDocument", {{"uri", uri}, {"version", version}}}, {"contentChanges", {{{"text", text}}}}});
  };
  // G0 (function 1) X1 (property 2); then M30 (function 1) on the next line
  Session s = runSession(initialize() + didOpen(uri, "G0 X1\n") + full(1) + change(2, "G0 X1\nM30\n") + delta(2, "1") +
                         change(3, "G0 X2\nM30\n") + delta(3, "2") + delta(4, "no such id") + delta(5, nullptr) +
                         shutdownExit());
  json r1 = s.response(1)["result"];
  CHECK(r1["data"] == json({0, 0, 2, 1, 0, 0, 3, 2, 2, 0}));
  REQUIRE(r1["resultId"] == "1");
  json r2 = s.response(2)["result"];
  CHECK(r2["resultId"] == "2");
  CHECK(r2["edits"] == json::array({{{"start", 10}, {"deleteCount", 0}, {"data", {1, 0, 3, 1, 0}}}}));
  CHECK(s.response(3)["result"]["edits"] == json::array()); // X1 -> X2: the same tokens
  CHECK(s.response(4)["result"]["data"] == json({0, 0, 2, 1, 0, 0, 3, 2, 2, 0, 1, 0, 3, 1, 0}));
  CHECK(s.response(5)["error"]["code"] == -32602);
}
