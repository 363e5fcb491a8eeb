//! @file FuzzLsp.cpp
//! @brief Fuzz target: a byte stream of JSON-RPC frames -> the language server (lsp::Server on
//!        in-memory streams, the built-in machine). Whatever the input, the server must end
//!        (exit code 0 or 1) without a crash or an exception, and everything it writes must be
//!        well-formed: `Content-Length: N\r\n\r\n` and N bytes, repeated to the end; each body a
//!        JSON-RPC 2.0 object that is a response (an id and a result or an error with an integer
//!        code and a string message) or one of the notifications it sends (publishDiagnostics,
//!        window/showMessage, isotools/dryRun) or requests (workspace/codeLens/refresh,
//!        workspace/inlayHint/refresh).
//!
//! Input format: the bytes the editor would write on the server's standard input (frames,
//! headers, garbage), at most 1 MiB. The server runs with small limits (messages of 64 KiB,
//! documents of 16 KiB, 64 KiB and 8 documents in all) so that the inputs reach them; a
//! `file:` URI makes the server read the .mpf/.spf files of that folder, as in an editor.
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "Support.h"
#include "lsp/Server.h"
#include "machine/Machine.h"

namespace {

using nlohmann::json;
constexpr const char* kTarget = "FuzzLsp";

void checkMessage(const json& m, const std::string& body) {
  if (!m.is_object() || m.value("jsonrpc", "") != "2.0") iso::fuzz::fail(kTarget, "not a JSON-RPC 2.0 object: ", body);
  if (m.contains("method")) {
    const std::string method = m["method"].is_string() ? m["method"].get<std::string>() : "";
    // the requests it sends: the client refreshes its lenses and hints after a dry run
    if (method == "workspace/codeLens/refresh" || method == "workspace/inlayHint/refresh") {
      if (!m.contains("id")) iso::fuzz::fail(kTarget, "a refresh request without an id: ", body);
      return;
    }
    if (m.contains("id") || !m.contains("params") || !m["params"].is_object())
      iso::fuzz::fail(kTarget, "a notification with an id or without params: ", body);
    if (method == "textDocument/publishDiagnostics") {
      if (!m["params"].contains("uri") || !m["params"].value("diagnostics", json()).is_array())
        iso::fuzz::fail(kTarget, "publishDiagnostics without uri or diagnostics: ", body);
    } else if (method == "isotools/dryRun") {
      const json& p = m["params"];
      if (!p.value("uri", json()).is_string() || !p.value("state", json()).is_string() ||
          !p.value("title", json()).is_string())
        iso::fuzz::fail(kTarget, "isotools/dryRun without uri, state or title: ", body);
    } else if (method == "window/showMessage") {
      if (!m["params"].value("type", json()).is_number_integer() || !m["params"].value("message", json()).is_string())
        iso::fuzz::fail(kTarget, "showMessage without type or message: ", body);
    } else {
      iso::fuzz::fail(kTarget, "an unexpected notification: ", body);
    }
    return;
  }
  if (!m.contains("id") || m.contains("result") == m.contains("error"))
    iso::fuzz::fail(kTarget, "a response needs an id and one of result and error: ", body);
  if (m.contains("error")) {
    const json& e = m["error"];
    if (!e.is_object() || !e.value("code", json()).is_number_integer() || !e.value("message", json()).is_string())
      iso::fuzz::fail(kTarget, "an error without an integer code and a string message: ", body);
  }
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const iso::machine::Machine machine = iso::machine::builtinMachine();
  if (size > (1u << 20)) return 0;
  iso::lsp::Limits limits;
  limits.maxMessageBytes = 64 << 10;
  limits.maxDocumentBytes = 16 << 10;
  limits.maxTotalBytes = 64 << 10;
  limits.maxDocuments = 8;
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  std::ostringstream out;
  int code = -1;
  try {
    iso::lsp::Server server(in, out, {&machine, {}, false, limits});
    code = server.run();
  } catch (const std::exception& e) {
    iso::fuzz::fail(kTarget, "the server threw: ", e.what());
  }
  if (code != 0 && code != 1) iso::fuzz::fail(kTarget, "exit code not 0 or 1: ", std::to_string(code));
  iso::fuzz::forEachFrame(kTarget, out.str(), checkMessage);
  return 0;
}
