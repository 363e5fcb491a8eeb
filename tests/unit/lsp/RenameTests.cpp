//! @file RenameTests.cpp
//! @brief prepareRename and rename through the protocol: what can be renamed (labels and
//!        subprogram names) and what not, the edits of a label in its file and of a
//!        subprogram across the set (changes or documentChanges, the file named after it),
//!        the names refused, and the jumps found on lines with errors.
#include <algorithm>
#include <sstream>
#include <string>
#include <vector>

#include <doctest/doctest.h>

#include "LspTestUtil.h"

using namespace iso;
using namespace iso::test;

namespace {

const char* kMain = "Start: G90 G01 F=100 X10 (a comment)\n" // 0
                    "R5 = 2\n"                               // 1
                    "Lift\n"                                 // 2
                    "IF R5 > 1 GOTOF Fine\n"                 // 3
                    "CASE R5 OF 1 GOTOF Fine DEFAULT GOTOF Next\n"
                    "Next:\n" // 5
                    "GOTOF Fine\n"
                    "\n"                  // 7
                    "Fine: GOTOB Start\n" // 8
                    "M30\n";
const char* kLift = "PROC Lift SAVE\nZ=10\nM17\n";
// Another main program of the set: it calls Lift too, and has labels of its own named Fine.
const char* kOther = "Lift\nGOTOF Fine\nFine: M30\n";

struct Folder {
  TempDir dir;
  std::string main, lift, other;
  Folder(const char* liftFile = "lift.spf") {
    dir.write("main.mpf", kMain);
    dir.write(liftFile, kLift);
    dir.write("other.mpf", kOther);
    main = uriIn(dir, "main.mpf");
    lift = uriIn(dir, liftFile);
    other = uriIn(dir, "other.mpf");
  }
};

std::string renameAt(int id, const std::string& uri, uint32_t line, uint32_t character, const std::string& name) {
  return at(id, "textDocument/rename", uri, line, character, {{"newName", name}});
}

/// The (line, character) starts of the edits of `uri` in a `changes` WorkspaceEdit, each edit's
/// text checked to be `name`.
std::vector<std::pair<int, int>> editStarts(const json& edit, const std::string& uri, const std::string& name) {
  std::vector<std::pair<int, int>> out;
  if (!edit.contains("changes") || !edit["changes"].contains(uri)) return out;
  for (const auto& e : edit["changes"][uri]) {
    CHECK(e["newText"] == name);
    out.emplace_back(e["range"]["start"]["line"].get<int>(), e["range"]["start"]["character"].get<int>());
  }
  return out;
}

std::string errorOf(const Session& s, int id) {
  const json r = s.response(id);
  if (!r.contains("error")) return "(no error: " + r.dump() + ")";
  CHECK(r["error"]["code"] == -32803); // RequestFailed
  return r["error"]["message"].get<std::string>();
}

/// Request `id` failed with a message that holds `part`.
void checkRefused(const Session& s, int id, const std::string& part) {
  const std::string message = errorOf(s, id);
  CHECK_MESSAGE(message.find(part) != std::string::npos, message);
}

} // namespace

TEST_CASE("lsp: rename is advertised with prepareRename") {
  Session s = runSession(initialize() + shutdownExit());
  CHECK(s.response(0)["result"]["capabilities"]["renameProvider"] == json{{"prepareProvider", true}});
}

TEST_CASE("lsp: prepareRename on labels and subprogram names gives the range and the name") {
  Folder f;
  Session s = runSession(initialize() + didOpen(f.main, kMain) + didOpen(f.lift, kLift) +
                         at(1, "textDocument/prepareRename", f.main, 8, 2) +  // Fine: (definition)
                         at(2, "textDocument/prepareRename", f.main, 6, 8) +  // GOTOF Fine
                         at(3, "textDocument/prepareRename", f.main, 4, 21) + // a CASE branch
                         at(4, "textDocument/prepareRename", f.main, 2, 4) +  // just after the call Lift
                         at(5, "textDocument/prepareRename", f.lift, 0, 6) +  // PROC Lift
                         at(6, "textDocument/prepareRename", f.main, 3, 16) + // IF ... GOTOF Fine
                         shutdownExit());
  CHECK(s.response(1)["result"] == json{{"range", range(8, 0, 8, 4)}, {"placeholder", "Fine"}});
  CHECK(s.response(2)["result"] == json{{"range", range(6, 6, 6, 10)}, {"placeholder", "Fine"}});
  CHECK(s.response(3)["result"] == json{{"range", range(4, 19, 4, 23)}, {"placeholder", "Fine"}});
  CHECK(s.response(4)["result"] == json{{"range", range(2, 0, 2, 4)}, {"placeholder", "Lift"}});
  CHECK(s.response(5)["result"] == json{{"range", range(0, 5, 0, 9)}, {"placeholder", "Lift"}});
  CHECK(s.response(6)["result"] == json{{"range", range(3, 16, 3, 20)}, {"placeholder", "Fine"}});
}

TEST_CASE("lsp: prepareRename refuses keywords, words, numbers, parameters, comments and blanks") {
  Folder f;
  // GOTOF, G90, X10, 100 (a number after F=), R5, the comment, a blank line, CASE, M30
  const std::vector<std::pair<uint32_t, uint32_t>> places = {{6, 2},  {0, 8}, {0, 22}, {0, 18}, {1, 1},
                                                             {0, 28}, {7, 0}, {4, 1},  {9, 1}};
  std::string input = initialize() + didOpen(f.main, kMain);
  for (size_t i = 0; i < places.size(); ++i)
    input += at(static_cast<int>(i + 1), "textDocument/prepareRename", f.main, places[i].first, places[i].second);
  Session s = runSession(input + shutdownExit());
  for (size_t i = 0; i < places.size(); ++i) {
    CAPTURE(i);
    checkRefused(s, static_cast<int>(i + 1), "only labels and subprogram names can be renamed");
  }
}

TEST_CASE("lsp: renaming a label edits its definition and every jump to it in its file only") {
  Folder f;
  Session s = runSession(initialize() + didOpen(f.main, kMain) + didOpen(f.other, kOther) +
                         renameAt(1, f.main, 6, 7, "Done") +  // from a use
                         renameAt(2, f.main, 0, 1, "Begin") + // from the definition
                         renameAt(3, f.main, 8, 1, "FINE") +  // the same name in another case
                         shutdownExit());
  const json e1 = s.response(1)["result"];
  CHECK(editStarts(e1, f.main, "Done") == std::vector<std::pair<int, int>>{{3, 16}, {4, 19}, {6, 6}, {8, 0}});
  CHECK(e1["changes"].size() == 1); // other.mpf's Fine is another label
  CHECK(editStarts(s.response(2)["result"], f.main, "Begin") == std::vector<std::pair<int, int>>{{0, 0}, {8, 12}});
  CHECK(editStarts(s.response(3)["result"], f.main, "FINE").size() == 4);
}

TEST_CASE("lsp: renaming a subprogram edits its PROC line and every call of the set") {
  SUBCASE("a file named otherwise: changes of every file, open or on disk") {
    Folder f("up.spf");
    Session s = runSession(initialize() + didOpen(f.main, kMain) + renameAt(1, f.main, 2, 1, "Raise") + shutdownExit());
    const json e = s.response(1)["result"];
    CHECK(editStarts(e, f.main, "Raise") == std::vector<std::pair<int, int>>{{2, 0}});
    CHECK(editStarts(e, f.other, "Raise") == std::vector<std::pair<int, int>>{{0, 0}});
    CHECK(editStarts(e, f.lift, "Raise") == std::vector<std::pair<int, int>>{{0, 5}});
    CHECK(e["changes"].size() == 3);
  }
  SUBCASE("documentChanges when the client takes them: the version of open documents, null for files") {
    Folder f("up.spf");
    json caps = {{"workspace", {{"workspaceEdit", {{"documentChanges", true}}}}}};
    Session s = runSession(request(0, "initialize", {{"capabilities", caps}}) + notify("initialized") +
                           didOpen(f.main, kMain, 7) + renameAt(1, f.main, 2, 1, "Raise") + shutdownExit());
    const json dc = s.response(1)["result"]["documentChanges"];
    REQUIRE(dc.size() == 3);
    CHECK(dc[0]["textDocument"] == json{{"uri", f.main}, {"version", 7}});
    CHECK(dc[0]["edits"] == json::array({{{"range", range(2, 0, 2, 4)}, {"newText", "Raise"}}}));
    CHECK(dc[1]["textDocument"] == json{{"uri", f.other}, {"version", nullptr}});
    CHECK(dc[2]["textDocument"] == json{{"uri", f.lift}, {"version", nullptr}});
  }
  SUBCASE("a file named after it is refused unless the client renames files, then renamed too") {
    Folder f;
    json caps = {
        {"workspace", {{"workspaceEdit", {{"documentChanges", true}, {"resourceOperations", {"create", "rename"}}}}}}};
    Session plain = runSession(initialize() + didOpen(f.main, kMain) + renameAt(1, f.main, 2, 1, "Raise") +
                               renameAt(2, f.main, 2, 1, "LIFT") + shutdownExit());
    checkRefused(plain, 1, "lift.spf is named after the subprogram 'Lift'");
    CHECK(editStarts(plain.response(2)["result"], f.lift, "LIFT").size() == 1); // the file still fits
    Session files = runSession(request(0, "initialize", {{"capabilities", caps}}) + notify("initialized") +
                               didOpen(f.main, kMain) + renameAt(1, f.main, 2, 1, "Raise") + shutdownExit());
    const json dc = files.response(1)["result"]["documentChanges"];
    REQUIRE(dc.size() == 4);
    CHECK(dc[0]["textDocument"]["uri"] == f.lift); // the files in path order, then the file itself
    CHECK(dc[3] == json{{"kind", "rename"}, {"oldUri", f.lift}, {"newUri", uriIn(f.dir, "Raise.spf")}});
    // Neovim 0.7 names the resource operations, not documentChanges: they come all the same.
    json nvim = {{"workspace", {{"workspaceEdit", {{"resourceOperations", {"rename"}}}}}}};
    Session n = runSession(request(0, "initialize", {{"capabilities", nvim}}) + notify("initialized") +
                           didOpen(f.main, kMain) + renameAt(1, f.main, 2, 1, "Raise") + shutdownExit());
    CHECK(n.response(1)["result"]["documentChanges"] == dc);
    // A capability of the wrong type is no capability.
    json odd = {{"workspace", {{"workspaceEdit", {{"documentChanges", "yes"}, {"resourceOperations", 3}}}}}};
    Session o = runSession(request(0, "initialize", {{"capabilities", odd}}) + notify("initialized") +
                           didOpen(f.main, kMain) + renameAt(1, f.main, 0, 1, "Begin") + shutdownExit());
    CHECK(o.response(0).contains("result"));
    CHECK(editStarts(o.response(1)["result"], f.main, "Begin").size() == 2);
    f.dir.write("Raise.spf", "M30\n");
    Session taken = runSession(request(0, "initialize", {{"capabilities", caps}}) + notify("initialized") +
                               didOpen(f.main, kMain) + renameAt(1, f.main, 2, 1, "Raise") + shutdownExit());
    checkRefused(taken, 1, "Raise.spf already exists");
  }
}

TEST_CASE("lsp: rename refuses names that are no label or subprogram name, or that change meaning") {
  Folder f("up.spf");
  struct Case {
    uint32_t line, character;
    std::string name, why;
  };
  const std::vector<Case> cases = {
      {6, 7, "", "the new name is empty"},
      {6, 7, "1abc", "a name is letters, digits and '_'"},
      {6, 7, "Do-ne", "a name is letters, digits and '_'"},
      {6, 7, "GOTOF", "'GOTOF' is a keyword"},
      {6, 7, "pos", "'pos' is a keyword"},
      {6, 7, std::string(240, 'L'), "a line holds at most 240 characters"},
      {6, 7, "next", "a label 'Next' is already defined on line 6"},
      {2, 1, "X5", "'X5' cannot be a subprogram name: it reads as address words"},
      {2, 1, "G1X2", "reads as address words"},
      {2, 1, "IF", "'IF' is a keyword"},
  };
  std::string input = initialize() + didOpen(f.main, kMain);
  for (size_t i = 0; i < cases.size(); ++i)
    input += renameAt(static_cast<int>(i + 1), f.main, cases[i].line, cases[i].character, cases[i].name);
  input += renameAt(100, f.main, 6, 7, "A1"); // a label may read as words: the colon and GOTOF decide
  Session s = runSession(input + shutdownExit());
  for (size_t i = 0; i < cases.size(); ++i) {
    CAPTURE(cases[i].name);
    checkRefused(s, static_cast<int>(i + 1), cases[i].why);
  }
  CHECK(editStarts(s.response(100)["result"], f.main, "A1").size() == 4);
}

TEST_CASE("lsp: rename refuses a name that another subprogram or call, or a jump, already uses") {
  Folder f("up.spf");
  f.dir.write("lower.spf", "PROC Lower SAVE\nM17\n");
  f.dir.write("calls.mpf", "Lift\nMissing\nGOTOF Nowhere\nM30\n");
  const std::string calls = uriIn(f.dir, "calls.mpf");
  Session s = runSession(initialize() + didOpen(calls, "Lift\nMissing\nGOTOF Nowhere\nHere: M30\n") +
                         renameAt(1, calls, 0, 1, "LOWER") + renameAt(2, calls, 0, 1, "missing") +
                         renameAt(3, calls, 3, 1, "nowhere") + shutdownExit());
  checkRefused(s, 1, "'Lower' already names the subprogram of lower.spf (line 1)");
  checkRefused(s, 2, "line 2 of calls.mpf already calls 'missing'");
  checkRefused(s, 3, "line 3 already jumps to 'Nowhere'");
}

TEST_CASE("lsp: rename refuses a name that makes a line longer than 240 characters") {
  Folder f("up.spf");
  // line 2 is 239 characters long: "GOTOF Fine" and a comment after it
  const std::string longLine = "GOTOF Fine (" + std::string(226, 'c') + ")";
  REQUIRE(longLine.size() == 239);
  const std::string text = "M3\n" + longLine + "\nFine: M30\n";
  Session s = runSession(initialize() + didOpen(f.main, text) + renameAt(1, f.main, 2, 1, "Finest") +
                         renameAt(2, f.main, 2, 1, "Fin2") + renameAt(3, f.main, 2, 1, "Final") + shutdownExit());
  checkRefused(s, 1, "line 2 of main.mpf longer than 240 characters");
  CHECK(editStarts(s.response(2)["result"], f.main, "Fin2").size() == 2);
  CHECK(editStarts(s.response(3)["result"], f.main, "Final").size() == 2); // exactly 240
}

TEST_CASE("lsp: references and rename find the jumps of lines with errors") {
  Folder f("up.spf");
  const std::string text = "GOTOF Fine )\n"                    // 0: junk after the label
                           "IF R1 > GOTOF Fine\n"              // 1: a broken condition
                           "CASE R1 OF 1 GOTOF Fine 2 GOTOF\n" // 2: a branch without label
                           "IF R1 > 0 THEN GOTOF Fine X\n"     // 3: junk after a THEN jump
                           "GOTOF )\n"                         // 4: no label at all
                           "Fine: M30\n";
  Session s = runSession(initialize() + didOpen(f.main, text) +
                         at(1, "textDocument/references", f.main, 5, 1, {{"context", {{"includeDeclaration", true}}}}) +
                         renameAt(2, f.main, 1, 16, "Done") + at(3, "textDocument/prepareRename", f.main, 2, 20) +
                         shutdownExit());
  std::vector<std::pair<int, int>> refs;
  const json found = s.response(1)["result"]; // a copy: the response is a temporary
  for (const auto& l : found)
    refs.emplace_back(l["range"]["start"]["line"].get<int>(), l["range"]["start"]["character"].get<int>());
  std::sort(refs.begin(), refs.end());
  CHECK(refs == std::vector<std::pair<int, int>>{{0, 6}, {1, 14}, {2, 19}, {3, 21}, {5, 0}});
  CHECK(editStarts(s.response(2)["result"], f.main, "Done") ==
        std::vector<std::pair<int, int>>{{0, 6}, {1, 14}, {2, 19}, {3, 21}, {5, 0}});
  CHECK(s.response(3)["result"]["placeholder"] == "Fine");
}
