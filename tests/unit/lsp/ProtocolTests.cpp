//! @file ProtocolTests.cpp
//! @brief The LSP base protocol and lifecycle: framing, malformed input, JSON-RPC errors,
//!        requests before initialize and after shutdown, exit codes.
#include <sstream>
#include <string>

#include <doctest/doctest.h>

#include "LspTestUtil.h"

using namespace iso;
using namespace iso::test;

namespace {
int errorCode(const json& response) { return response.is_null() ? 0 : response["error"]["code"].get<int>(); }
} // namespace

TEST_CASE("lsp: initialize, shutdown and exit - capabilities") {
  Session s = runSession(initialize() + shutdownExit());
  CHECK(s.exitCode == 0);
  json init = s.response(0);
  REQUIRE(init.contains("result"));
  const json& caps = init["result"]["capabilities"];
  CHECK(caps["positionEncoding"] == "utf-16");
  CHECK(caps["textDocumentSync"]["change"] == 2);
  CHECK(caps["textDocumentSync"]["openClose"] == true);
  CHECK(caps["hoverProvider"] == true);
  CHECK(caps["definitionProvider"] == true);
  CHECK(caps["referencesProvider"] == true);
  CHECK(caps["documentSymbolProvider"] == true);
  CHECK(caps["codeActionProvider"]["codeActionKinds"][0] == "quickfix");
  CHECK(init["result"]["serverInfo"]["name"] == "isolint");
  json shut = s.response(999);
  REQUIRE(shut.contains("result"));
  CHECK(shut["result"].is_null());
  CHECK(s.raw.rfind("Content-Length: ", 0) == 0);
}

TEST_CASE("lsp: exit without shutdown is exit code 1 - so is the end of the input") {
  CHECK(runSession(initialize() + notify("exit")).exitCode == 1);
  CHECK(runSession(initialize()).exitCode == 1);
  CHECK(runSession(notify("exit")).exitCode == 1);
  CHECK(runSession("").exitCode == 1);
  // exit stops reading: nothing after it is answered.
  Session s = runSession(initialize() + shutdownExit() + request(5, "shutdown"));
  CHECK(s.exitCode == 0);
  CHECK(s.response(5).is_null());
}

TEST_CASE("lsp: requests before initialize get ServerNotInitialized - notifications are dropped") {
  TempDir dir;
  std::string uri = uriIn(dir, "a.mpf");
  Session s =
      runSession(request(1, "textDocument/hover", {{"textDocument", {{"uri", uri}}}, {"position", position(0, 0)}}) +
                 didOpen(uri, "G7\nM30\n") + initialize() + shutdownExit());
  CHECK(errorCode(s.response(1)) == -32002);
  CHECK(s.published(uri).empty());
  CHECK(s.exitCode == 0);
}

TEST_CASE("lsp: requests after shutdown are invalid - a second initialize too") {
  Session s = runSession(initialize() + request(1, "initialize", {{"capabilities", json::object()}}) +
                         request(2, "shutdown") + request(3, "textDocument/documentSymbol") + notify("exit"));
  CHECK(errorCode(s.response(1)) == -32600);
  CHECK(s.response(2).contains("result"));
  CHECK(errorCode(s.response(3)) == -32600);
  CHECK(s.exitCode == 0);
}

TEST_CASE("lsp: unknown methods: requests get MethodNotFound, notifications nothing") {
  Session s = runSession(initialize() + request(1, "workspace/frobnicate") + request(2, "textDocument/frobnicate") +
                         notify("workspace/frobnicate") + notify("$/cancelRequest", {{"id", 1}}) + shutdownExit());
  CHECK(errorCode(s.response(1)) == -32601);
  CHECK(errorCode(s.response(2)) == -32601);
  // initialize, 1, 2, shutdown: nothing for the notifications.
  CHECK(s.messages.size() == 4);
  CHECK(s.exitCode == 0);
}

TEST_CASE("lsp: malformed messages are answered and the session goes on") {
  SUBCASE("invalid JSON") {
    Session s = runSession(initialize() + frameRaw("{\"jsonrpc\": \"2.0\", \"id\": 1,") + shutdownExit());
    REQUIRE(s.anonymousErrors().size() == 1);
    CHECK(errorCode(s.anonymousErrors()[0]) == -32700);
    CHECK(s.exitCode == 0);
  }
  SUBCASE("not an object") {
    Session s = runSession(initialize() + frameRaw("[1, 2]") + frameRaw("42") + shutdownExit());
    REQUIRE(s.anonymousErrors().size() == 2);
    CHECK(errorCode(s.anonymousErrors()[0]) == -32600);
    CHECK(s.exitCode == 0);
  }
  SUBCASE("a request without a method") {
    Session s =
        runSession(initialize() + frame({{"jsonrpc", "2.0"}, {"id", 7}, {"params", json::object()}}) + shutdownExit());
    CHECK(errorCode(s.response(7)) == -32600);
  }
  SUBCASE("a method that is not a string, a bad id, bad params") {
    Session s = runSession(initialize() + frame({{"jsonrpc", "2.0"}, {"id", 7}, {"method", 3}}) +
                           frame({{"jsonrpc", "2.0"}, {"id", {{"a", 1}}}, {"method", "shutdown"}}) +
                           frame({{"jsonrpc", "2.0"}, {"id", 8}, {"method", "textDocument/hover"}, {"params", 5}}) +
                           request(9, "textDocument/hover", {{"textDocument", {{"uri", 5}}}}) + shutdownExit());
    CHECK(errorCode(s.response(7)) == -32600);
    CHECK(s.anonymousErrors().size() == 1);
    CHECK(errorCode(s.response(8)) == -32602);
    CHECK(errorCode(s.response(9)) == -32602);
    CHECK(s.exitCode == 0);
  }
  SUBCASE("a client's response (no method) is ignored") {
    Session s = runSession(initialize() + frame({{"jsonrpc", "2.0"}, {"id", 3}, {"result", nullptr}}) + shutdownExit());
    CHECK(s.messages.size() == 2);
  }
  SUBCASE("wrong jsonrpc version") {
    Session s =
        runSession(initialize() + frame({{"jsonrpc", "1.0"}, {"id", 4}, {"method", "shutdown"}}) + shutdownExit());
    CHECK(errorCode(s.response(4)) == -32600);
  }
}

TEST_CASE("lsp: framing errors") {
  SUBCASE("non-numeric Content-Length: answered, then the next message is read") {
    std::string bad = "Content-Length: twelve\r\n\r\n{\"jsonrpc\":\"2.0\",\"id\":5,\"method\":\"shutdown\"}";
    Session s = runSession(initialize() + bad + request(6, "shutdown") + notify("exit"));
    REQUIRE(!s.anonymousErrors().empty());
    CHECK(errorCode(s.anonymousErrors()[0]) == -32700);
    CHECK(s.response(5).is_null());
    CHECK(s.response(6).contains("result"));
    CHECK(s.exitCode == 0);
  }
  SUBCASE("no Content-Length at all") {
    Session s = runSession(initialize() + "Content-Type: application/vscode-jsonrpc\r\n\r\n" + shutdownExit());
    CHECK(s.anonymousErrors().size() == 1);
    CHECK(s.exitCode == 0);
  }
  SUBCASE("a truncated header ends the session") {
    Session s = runSession(initialize() + "Content-Len");
    CHECK(s.exitCode == 1);
    CHECK(s.anonymousErrors().empty());
  }
  SUBCASE("a truncated body ends the session") {
    Session s = runSession(initialize() + "Content-Length: 100\r\n\r\n{\"jsonrpc\"");
    CHECK(s.exitCode == 1);
  }
  SUBCASE("a huge Content-Length is refused without allocating it") {
    Session s = runSession(initialize() + "Content-Length: 999999999999\r\n\r\n{}");
    REQUIRE(s.anonymousErrors().size() == 1);
    CHECK(s.anonymousErrors()[0]["error"]["message"].get<std::string>().find("over the limit") != std::string::npos);
    CHECK(s.exitCode == 1);
  }
  SUBCASE("an overflowing Content-Length is not a number") {
    Session s = runSession(initialize() + "Content-Length: 99999999999999999999999999\r\n\r\n" + shutdownExit());
    CHECK(!s.anonymousErrors().empty());
  }
  SUBCASE("an overlong header line") {
    Session s = runSession(initialize() + std::string(10000, 'x') + "\r\n\r\n" + shutdownExit());
    CHECK(s.anonymousErrors().size() == 1);
    CHECK(s.exitCode == 0);
  }
  SUBCASE("LF-only headers and other headers are accepted") {
    std::string body = json({{"jsonrpc", "2.0"}, {"id", 1}, {"method", "shutdown"}}).dump();
    Session s = runSession(initialize() + "content-length: " + std::to_string(body.size()) +
                           "\nContent-Type: application/vscode-jsonrpc; charset=utf-8\n\n" + body + notify("exit"));
    CHECK(s.response(1).contains("result"));
    CHECK(s.exitCode == 0);
  }
}

TEST_CASE("lsp: the reader skips a message over its limit and reads the next one") {
  std::string big = frameRaw(std::string(100, ' ') + "{}");
  std::string small = frameRaw("{}");
  std::istringstream in(big + small);
  lsp::MessageReader r(in, 50);
  std::string body, error;
  CHECK(r.read(body, error) == lsp::MessageReader::Status::Bad);
  CHECK(error.find("102 bytes") != std::string::npos);
  CHECK(r.read(body, error) == lsp::MessageReader::Status::Message);
  CHECK(body == "{}");
  CHECK(r.read(body, error) == lsp::MessageReader::Status::Eof);
}

TEST_CASE("lsp: shutdown and exit with null or absent params") {
  const std::string shutdownNull = frameRaw(R"({"jsonrpc":"2.0","id":1,"method":"shutdown","params":null})");
  const std::string exitNull = frameRaw(R"({"jsonrpc":"2.0","method":"exit","params":null})");
  SUBCASE("null params, as vim-lsc sends them") {
    Session s = runSession(initialize() + shutdownNull + exitNull + request(5, "shutdown"));
    REQUIRE(s.response(1).contains("result"));
    CHECK(s.response(1)["result"].is_null());
    CHECK(s.exitCode == 0);
    CHECK(s.response(5).is_null()); // exit ended the session
  }
  SUBCASE("absent params") {
    Session s = runSession(initialize() + frameRaw(R"({"jsonrpc":"2.0","id":1,"method":"shutdown"})") +
                           frameRaw(R"({"jsonrpc":"2.0","method":"exit"})"));
    CHECK(s.response(1).contains("result"));
    CHECK(s.exitCode == 0);
  }
  SUBCASE("exit with null params and no shutdown ends with 1") {
    Session s = runSession(initialize() + exitNull + request(5, "shutdown"));
    CHECK(s.exitCode == 1);
    CHECK(s.response(5).is_null());
  }
  SUBCASE("exit ends the session whatever its params") {
    Session s = runSession(initialize() + request(1, "shutdown") +
                           frameRaw(R"({"jsonrpc":"2.0","method":"exit","params":5})") + request(5, "shutdown"));
    CHECK(s.exitCode == 0);
    CHECK(s.response(5).is_null());
    CHECK(runSession(initialize() + frameRaw(R"({"jsonrpc":"2.0","method":"exit","params":"x"})")).exitCode == 1);
  }
  SUBCASE("null params where parameters are needed: InvalidParams naming what is missing") {
    Session s =
        runSession(initialize() + frameRaw(R"({"jsonrpc":"2.0","id":2,"method":"textDocument/hover","params":null})") +
                   shutdownExit());
    CHECK(errorCode(s.response(2)) == -32602);
    CHECK(s.response(2)["error"]["message"].get<std::string>().find("textDocument") != std::string::npos);
    CHECK(s.exitCode == 0);
  }
}

namespace {
/// A request of an unknown method whose params nest `depth` arrays below {"x": ...}: the
/// message is nested depth + 2 deep.
std::string deepRequest(int id, size_t depth) {
  return frameRaw(R"({"jsonrpc":"2.0","id":)" + std::to_string(id) +
                  R"(,"method":"workspace/frobnicate","params":{"x":)" + std::string(depth, '[') +
                  std::string(depth, ']') + "}}");
}
} // namespace

TEST_CASE("lsp: a message nested deeper than 64 levels is refused before it is parsed") {
  SUBCASE("300,000 deep: a parse error, and the session goes on") {
    // a request whose params nest 300,000 deep (copying them overflowed the stack), then
    // 300,000 unclosed arrays
    Session s = runSession(initialize() + deepRequest(2, 300000) + frameRaw(std::string(300000, '[')) +
                           request(3, "shutdown") + notify("exit"));
    CHECK(s.response(2).is_null());
    REQUIRE(s.anonymousErrors().size() == 2);
    for (const json& e : s.anonymousErrors()) {
      CHECK(errorCode(e) == -32700);
      CHECK(e["error"]["message"].get<std::string>().find("limit of 64 levels") != std::string::npos);
    }
    CHECK(s.response(3).contains("result"));
    CHECK(s.exitCode == 0);
  }
  SUBCASE("64 levels are read, 65 are not") {
    Session s = runSession(initialize() + deepRequest(1, 62) + deepRequest(2, 63) + shutdownExit());
    CHECK(errorCode(s.response(1)) == -32601); // parsed: an unknown method
    CHECK(s.response(2).is_null());
    REQUIRE(s.anonymousErrors().size() == 1);
    CHECK(errorCode(s.anonymousErrors()[0]) == -32700);
  }
  SUBCASE("brackets inside strings are text") {
    Session s =
        runSession(initialize() + request(1, "workspace/frobnicate", {{"x", std::string(1000, '[')}}) + shutdownExit());
    CHECK(errorCode(s.response(1)) == -32601);
    CHECK(s.anonymousErrors().empty());
  }
}

TEST_CASE("lsp: the limits of open documents are those documented") {
  const lsp::Limits l;
  CHECK(l.maxMessageBytes == lsp::kMaxMessageBytes);
  CHECK(l.maxMessageBytes == size_t{64} << 20);
  CHECK(l.maxDocumentBytes == size_t{64} << 20);
  CHECK(l.maxTotalBytes == size_t{256} << 20);
  CHECK(l.maxDocuments == 1000);
}

namespace {
lsp::Limits smallLimits() {
  lsp::Limits l;
  l.maxMessageBytes = 1 << 20;
  l.maxDocumentBytes = 100;
  l.maxTotalBytes = 400;
  l.maxDocuments = 3;
  return l;
}
std::string program(size_t bytes) { // a valid program of `bytes` bytes
  std::string s = "G0 X1\n";
  s += std::string(bytes - s.size() - 4, ' ');
  return s + "M30\n";
}
std::string hoverAt(int id, const std::string& uri) { return at(id, "textDocument/hover", uri, 0, 0); }
} // namespace

TEST_CASE("lsp: a document over its limit is not kept, and the server says which and why") {
  TempDir dir;
  const std::string big = uriIn(dir, "big.mpf"), ok = uriIn(dir, "ok.mpf");
  Session s = runSession(initialize() + didOpen(big, program(101)) + hoverAt(1, big) + didOpen(ok, program(100)) +
                             hoverAt(2, ok) + shutdownExit(),
                         {}, smallLimits());
  REQUIRE(s.shown().size() == 1);
  const json m = s.shown()[0];
  CHECK(m["type"] == 1);
  const std::string text = m["message"].get<std::string>();
  CHECK(text.find(big) != std::string::npos);
  CHECK(text.find("not checked") != std::string::npos);
  CHECK(text.find("101 bytes is over the limit of 100 bytes for one document") != std::string::npos);
  CHECK(s.published(big).empty());
  CHECK(s.response(1)["result"].is_null());
  CHECK(s.published(ok).size() == 1);
  CHECK(s.response(2)["result"].is_object()); // G0 has a hover
  CHECK(s.exitCode == 0);
}

TEST_CASE("lsp: the count and the total size of open documents are bounded") {
  TempDir dir;
  auto uri = [&](int i) { return uriIn(dir, "p" + std::to_string(i) + ".mpf"); };
  SUBCASE("count") {
    lsp::Limits l = smallLimits();
    l.maxTotalBytes = 1 << 20;
    Session s = runSession(initialize() + didOpen(uri(1), program(20)) + didOpen(uri(2), program(20)) +
                               didOpen(uri(3), program(20)) + didOpen(uri(4), program(20)) +
                               notify("textDocument/didClose", {{"textDocument", {{"uri", uri(1)}}}}) +
                               didOpen(uri(5), program(20)) + shutdownExit(),
                           {}, l);
    REQUIRE(s.shown().size() == 1);
    CHECK(s.shown()[0]["message"].get<std::string>().find(uri(4)) != std::string::npos);
    CHECK(s.shown()[0]["message"].get<std::string>().find("limit of 3 open documents") != std::string::npos);
    CHECK(s.published(uri(4)).empty());
    CHECK(!s.published(uri(5)).empty()); // a closed document makes room
    CHECK(s.exitCode == 0);
  }
  SUBCASE("total: texts and URIs") {
    lsp::Limits l = smallLimits();
    l.maxDocuments = 100;
    const size_t each = uri(1).size() + 90;
    l.maxTotalBytes = 2 * each + uri(4).size() + 10; // a third of 90 bytes does not fit, one of 10 does
    Session s = runSession(initialize() + didOpen(uri(1), program(90)) + didOpen(uri(2), program(90)) +
                               didOpen(uri(3), program(90)) + didOpen(uri(4), program(10)) + shutdownExit(),
                           {}, l);
    REQUIRE(s.shown().size() == 1);
    CHECK(s.shown()[0]["message"].get<std::string>().find(uri(3)) != std::string::npos);
    CHECK(s.shown()[0]["message"].get<std::string>().find("in all") != std::string::npos);
    CHECK(s.published(uri(3)).empty());
    CHECK(!s.published(uri(4)).empty());
  }
}

TEST_CASE("lsp: an edit that takes a document over its limit closes it") {
  TempDir dir;
  const std::string uri = uriIn(dir, "a.mpf");
  auto change = [&](json c, int version) {
    return notify("textDocument/didChange",
                  {{"textDocument", {{"uri", uri}, {"version", version}}}, {"contentChanges", json::array({c})}});
  };
  SUBCASE("incremental") {
    Session s =
        runSession(initialize() + didOpen(uri, program(60)) + hoverAt(1, uri) +
                       change({{"range", range(0, 0, 0, 0)}, {"text", std::string(40, ' ')}}, 2) +
                       change({{"range", range(0, 0, 0, 0)}, {"text", " "}}, 3) + hoverAt(2, uri) + shutdownExit(),
                   {}, smallLimits());
    REQUIRE(s.shown().size() == 1);
    const std::string text = s.shown()[0]["message"].get<std::string>();
    CHECK(text.find("closed and no longer checked") != std::string::npos);
    CHECK(text.find("101 bytes") != std::string::npos);
    CHECK(s.response(1)["result"].is_object());
    CHECK(s.response(2)["result"].is_null());
    // its diagnostics are cleared
    REQUIRE(!s.published(uri).empty());
    CHECK(s.published(uri).back()["diagnostics"].empty());
    CHECK(s.exitCode == 0);
  }
  SUBCASE("full text") {
    Session s = runSession(initialize() + didOpen(uri, program(60)) + change({{"text", program(101)}}, 2) +
                               hoverAt(2, uri) + shutdownExit(),
                           {}, smallLimits());
    REQUIRE(s.shown().size() == 1);
    CHECK(s.response(2)["result"].is_null());
  }
  SUBCASE("opened again over the limit: the old text goes too") {
    Session s = runSession(initialize() + didOpen(uri, program(60)) + didOpen(uri, program(101), 2) + hoverAt(2, uri) +
                               shutdownExit(),
                           {}, smallLimits());
    REQUIRE(s.shown().size() == 1);
    CHECK(s.response(2)["result"].is_null());
  }
}

TEST_CASE("lsp: a message over the message limit is refused unread") {
  lsp::Limits l = smallLimits();
  l.maxMessageBytes = 200;
  TempDir dir;
  const std::string uri = uriIn(dir, "a.mpf");
  Session s = runSession(initialize() + didOpen(uri, program(100) + std::string(200, ' ')) + request(3, "shutdown") +
                             notify("exit"),
                         {}, l);
  REQUIRE(s.anonymousErrors().size() == 1);
  CHECK(s.anonymousErrors()[0]["error"]["message"].get<std::string>().find("over the limit of 200 bytes") !=
        std::string::npos);
  CHECK(s.response(3).contains("result"));
  CHECK(s.exitCode == 0);
}
