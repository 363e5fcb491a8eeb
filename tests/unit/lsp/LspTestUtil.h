//! @file LspTestUtil.h
//! @brief Drives the language server in memory: frames messages, runs a session, parses what
//!        the server wrote.
#pragma once

#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "TestUtil.h"
#include "lsp/JsonRpc.h"
#include "lsp/Server.h"
#include "lsp/Uri.h"

namespace iso::test {

using nlohmann::json;

/// One framed message.
inline std::string frame(const json& message) {
  std::ostringstream os;
  lsp::writeMessage(os, message);
  return os.str();
}
/// A framed body given as raw text (for malformed JSON).
inline std::string frameRaw(const std::string& body) {
  return "Content-Length: " + std::to_string(body.size()) + "\r\n\r\n" + body;
}
inline std::string request(int id, const std::string& method, json params = json::object()) {
  return frame({{"jsonrpc", "2.0"}, {"id", id}, {"method", method}, {"params", std::move(params)}});
}
inline std::string notify(const std::string& method, json params = json::object()) {
  return frame({{"jsonrpc", "2.0"}, {"method", method}, {"params", std::move(params)}});
}
inline std::string initialize() {
  return request(0, "initialize", {{"capabilities", json::object()}}) + notify("initialized");
}
inline std::string shutdownExit() { return request(999, "shutdown") + notify("exit"); }

inline std::string didOpen(const std::string& uri, const std::string& text, int version = 1) {
  return notify("textDocument/didOpen",
                {{"textDocument", {{"uri", uri}, {"languageId", "iso"}, {"version", version}, {"text", text}}}});
}
inline json position(uint32_t line, uint32_t character) { return {{"line", line}, {"character", character}}; }
inline json range(uint32_t l0, uint32_t c0, uint32_t l1, uint32_t c1) {
  return {{"start", position(l0, c0)}, {"end", position(l1, c1)}};
}
inline std::string at(int id, const std::string& method, const std::string& uri, uint32_t line, uint32_t character,
                      json extra = json::object()) {
  json params = {{"textDocument", {{"uri", uri}}}, {"position", position(line, character)}};
  params.update(extra);
  return request(id, method, std::move(params));
}

/// What a session produced: the messages the server wrote (in order) and its exit code.
struct Session {
  std::vector<json> messages;
  int exitCode = -1;
  std::string raw;

  /// The response to request `id` (null if none).
  json response(int id) const {
    for (const auto& m : messages)
      if (m.contains("id") && m["id"] == id && !m.contains("method")) return m;
    return nullptr;
  }
  /// Every publishDiagnostics for `uri`, in order.
  std::vector<json> published(const std::string& uri) const {
    std::vector<json> out;
    for (const auto& m : messages)
      if (m.value("method", "") == "textDocument/publishDiagnostics" && m["params"]["uri"] == uri)
        out.push_back(m["params"]);
    return out;
  }
  /// The `window/showMessage` notifications, in order.
  std::vector<json> shown() const {
    std::vector<json> out;
    for (const auto& m : messages)
      if (m.value("method", "") == "window/showMessage") out.push_back(m["params"]);
    return out;
  }
  /// Error responses with a null id (framing and parse errors).
  std::vector<json> anonymousErrors() const {
    std::vector<json> out;
    for (const auto& m : messages)
      if (m.contains("error") && m["id"].is_null()) out.push_back(m);
    return out;
  }
};

/// Runs the server on `input` with the built-in machine (and `limits`); with `policy` (the
/// options of isolint --lsp) each folder gets its settings file and machine as isolint's.
inline Session runSession(const std::string& input, std::vector<diag::Code> disabled = {},
                          const lsp::Limits& limits = {}, const driver::CommonOptions* policy = nullptr) {
  std::istringstream in(input);
  std::ostringstream out;
  lsp::Server server(in, out, {&builtin(), std::move(disabled), false, limits, policy});
  Session s;
  s.exitCode = server.run();
  s.raw = out.str();
  // Parse the frames back (the server writes well-formed ones).
  std::istringstream back(s.raw);
  lsp::MessageReader reader(back);
  std::string body, error;
  while (reader.read(body, error) == lsp::MessageReader::Status::Message)
    s.messages.push_back(json::parse(body));
  return s;
}

/// A file URI in a temporary directory.
inline std::string uriIn(const TempDir& dir, const std::string& name) {
  return lsp::pathToUri(dir.path() + "/" + name);
}

} // namespace iso::test
