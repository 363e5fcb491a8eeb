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
