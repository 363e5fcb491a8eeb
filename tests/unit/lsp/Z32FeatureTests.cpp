//! @file Z32FeatureTests.cpp
//! @brief The language server in dialect z32: hover and completion of the z32 words (GO, GOP,
//!        KG, G26, G28, G29, O, TA, TB, PAR, PAL, the not-modelled codes, user parameters) and
//!        go-to-definition from a GO target and a range end to the line they find, references and
//!        rename of a subprogram through GOP and KG.
#include <sstream>
#include <string>

#include <doctest/doctest.h>

#include "LspTestUtil.h"

using namespace iso;
using namespace iso::test;

namespace {
const machine::Machine& z32() {
  static const machine::Machine m = [] {
    machine::Machine x = machine::builtinMachine();
    x.dialect = machine::Dialect::Z32;
    x.parameters = {"HA"};
    return x;
  }();
  return m;
}
Session runZ32(const std::string& input, const machine::Machine& m = z32()) {
  std::istringstream in(input);
  std::ostringstream out;
  lsp::Server server(in, out, {&m, {}, false, {}});
  Session s;
  s.exitCode = server.run();
  std::istringstream back(out.str());
  lsp::MessageReader reader(back);
  std::string body, error;
  while (reader.read(body, error) == lsp::MessageReader::Status::Message)
    s.messages.push_back(json::parse(body));
  return s;
}
std::string hoverOf(const Session& s, int id) {
  const json r = s.response(id)["result"]; // a copy: the response is a temporary
  return r.is_null() ? "" : r["contents"]["value"].get<std::string>();
}
const char* kProgram = "N10 G0 X0\n"         // 0
                       "GON10\n"             // 1
                       "GON10-N30\n"         // 2
                       "G29AB G84\n"         // 3
                       "O1 TA5 PAR[2]=HA\n"  // 4
                       "GOPLIFT\n"           // 5
                       "N30 G0 X1 KGLIFT\n"; // 6
} // namespace

TEST_CASE("lsp z32: hover texts of the z32 words") {
  TempDir dir;
  dir.write("main.mpf", kProgram);
  std::string uri = uriIn(dir, "main.mpf");
  std::string in = initialize() + didOpen(uri, kProgram) + at(1, "textDocument/hover", uri, 1, 1) +
                   at(2, "textDocument/hover", uri, 3, 1) + at(3, "textDocument/hover", uri, 3, 7) +
                   at(4, "textDocument/hover", uri, 4, 0) + at(5, "textDocument/hover", uri, 4, 4) +
                   at(6, "textDocument/hover", uri, 4, 8) + at(7, "textDocument/hover", uri, 4, 15) +
                   at(8, "textDocument/hover", uri, 5, 2) + at(9, "textDocument/hover", uri, 6, 12) + shutdownExit();
  Session s = runZ32(in);
  CHECK(hoverOf(s, 1).find("**GO**") != std::string::npos);
  CHECK(hoverOf(s, 2).find("**G29**") != std::string::npos);
  CHECK(hoverOf(s, 2).find("release") != std::string::npos);
  CHECK(hoverOf(s, 3).find("not modelled") != std::string::npos); // G84
  CHECK(hoverOf(s, 4).find("origin") != std::string::npos);
  CHECK(hoverOf(s, 5).find("**TA**") != std::string::npos);
  CHECK(hoverOf(s, 6).find("**PAR**") != std::string::npos);
  CHECK(hoverOf(s, 7).find("user parameter") != std::string::npos);
  CHECK(hoverOf(s, 8).find("**GOP**") != std::string::npos);
  CHECK(hoverOf(s, 9).find("**KG**") != std::string::npos);
  for (int id = 1; id <= 9; ++id)
    CHECK(hoverOf(s, id).find("reference point") == std::string::npos);
}

TEST_CASE("lsp z32: definition from a GO target and a range end") {
  TempDir dir;
  dir.write("main.mpf", kProgram);
  std::string uri = uriIn(dir, "main.mpf");
  std::string in = initialize() + didOpen(uri, kProgram) + at(1, "textDocument/definition", uri, 1, 3) +
                   at(2, "textDocument/definition", uri, 2, 7) + shutdownExit();
  Session s = runZ32(in);
  json go = s.response(1)["result"];
  REQUIRE(go.size() == 1);
  CHECK(go[0]["range"]["start"]["line"] == 0);
  json end = s.response(2)["result"];
  REQUIRE(end.size() == 1);
  CHECK(end[0]["range"]["start"]["line"] == 6);
}

TEST_CASE("lsp z32: completion offers the z32 words, sidac does not") {
  TempDir dir;
  dir.write("main.mpf", "G0 X0\n");
  std::string uri = uriIn(dir, "main.mpf");
  std::string in =
      initialize() + didOpen(uri, "G0 X0\n") + at(1, "textDocument/completion", uri, 0, 0) + shutdownExit();
  auto labels = [](const Session& s) {
    std::string all;
    const json r = s.response(1); // (a loop over a part of the temporary would outlive it)
    for (const auto& item : r["result"]["items"])
      all += item["label"].get<std::string>() + " ";
    return all;
  };
  std::string z = labels(runZ32(in));
  for (const char* w : {"GO ", "GOP ", "KG ", "G26 ", "G28 ", "G29 ", "O ", "TA ", "TB ", "PAR ", "PAL ", "G110 "})
    CHECK_MESSAGE(z.find(std::string(" ") + w) != std::string::npos, w);
  std::string sidac = labels(runSession(in));
  CHECK(sidac.find(" GOP ") == std::string::npos);
}

TEST_CASE("lsp z32: references and rename of a subprogram through GOP and KG - GO targets are not renamed") {
  TempDir dir;
  dir.write("main.mpf", kProgram);
  dir.write("up.spf", "PROC Lift SAVE\nM17\n");
  const std::string uri = uriIn(dir, "main.mpf"), up = uriIn(dir, "up.spf");
  auto rename = [&](int id, uint32_t line, uint32_t character, const std::string& name) {
    return at(id, "textDocument/rename", uri, line, character, {{"newName", name}});
  };
  Session s = runZ32(initialize() + didOpen(uri, kProgram) +
                     at(1, "textDocument/references", uri, 6, 13, {{"context", {{"includeDeclaration", true}}}}) +
                     rename(2, 5, 4, "Raise") + rename(3, 6, 14, "GOPX") + rename(4, 5, 4, "KGA") +
                     at(5, "textDocument/prepareRename", uri, 1, 3) + shutdownExit());
  const json refs = s.response(1)["result"];
  REQUIRE(refs.size() == 3);
  CHECK(refs[0]["uri"] == up); // the definition first
  CHECK(refs[1]["range"] == range(5, 3, 5, 7));
  CHECK(refs[2]["range"] == range(6, 12, 6, 16));
  const json changes = s.response(2)["result"]["changes"];
  auto edit = [](json r) { return json{{"range", std::move(r)}, {"newText", "Raise"}}; };
  CHECK(changes[uri] == json::array({edit(range(5, 3, 5, 7)), edit(range(6, 12, 6, 16))}));
  CHECK(changes[up] == json::array({edit(range(0, 5, 0, 9))}));
  for (int id : {3, 4}) {
    const json e = s.response(id);
    CHECK(e["error"]["message"].get<std::string>().find("in dialect z32") != std::string::npos);
  }
  CHECK(s.response(5)["error"]["message"].get<std::string>().find("only labels and subprogram names") !=
        std::string::npos);
}

TEST_CASE("lsp z32: a subprogram that a special M calls is not renamed") {
  TempDir dir;
  dir.write("up.spf", "PROC Lift SAVE\nM17\n");
  dir.write("main.mpf", "M6\nM30\n");
  const std::string up = uriIn(dir, "up.spf");
  machine::Machine m = z32();
  m.name = "z32test";
  m.specialM = {{6, "LIFT"}};
  auto rename = [&](int id, const std::string& name) {
    return at(id, "textDocument/rename", up, 0, 6, {{"newName", name}});
  };
  Session s = runZ32(initialize() + didOpen(up, "PROC Lift SAVE\nM17\n") + rename(1, "Raise") + rename(2, "Lift_") +
                         rename(3, "lift") + shutdownExit(),
                     m);
  CHECK(s.response(1)["error"]["message"].get<std::string>().find(
            "M6 of machine 'z32test' calls the subprogram 'LIFT'") != std::string::npos);
  CHECK(s.response(2).contains("error"));
  CHECK(s.response(3)["result"]["changes"][up].size() == 1); // another case: M6 still finds it
}

TEST_CASE("lsp z32: a label split by a continuation is not renamed") {
  TempDir dir;
  const std::string text = "GOTOF Fi$\nne\nFine: M30\n";
  dir.write("main.mpf", text);
  const std::string uri = uriIn(dir, "main.mpf");
  Session s =
      runZ32(initialize() + didOpen(uri, text) + at(1, "textDocument/rename", uri, 2, 1, {{"newName", "Done"}}) +
             at(2, "textDocument/prepareRename", uri, 0, 7) + shutdownExit());
  CHECK(s.response(1)["error"]["message"].get<std::string>().find(
            "'Fine' on line 1 of main.mpf is not written on one line") != std::string::npos);
  CHECK(s.response(2)["error"]["message"].get<std::string>().find("not written on one line") != std::string::npos);
}
