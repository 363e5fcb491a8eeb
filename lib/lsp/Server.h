//! @file Server.h
//! @brief `isolint --lsp`: a Language Server Protocol 3.17 server. It reads JSON-RPC messages
//!        from an std::istream and writes to an std::ostream, so tests drive it in memory.
//!        Single-threaded: each message is handled to completion before the next is read.
#pragma once

#include <iosfwd>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "lsp/Features.h"
#include "lsp/JsonRpc.h"
#include "lsp/Workspace.h"

namespace iso::driver {
struct Io;
struct LintOptions;
} // namespace iso::driver

namespace iso::lsp {

class Server {
public:
  /// `opts.machine` must outlive the server.
  Server(std::istream& in, std::ostream& out, WorkspaceOptions opts);

  /// Serves until the `exit` notification or the end of the input. Returns the process exit
  /// code: 0 when `shutdown` came first, else 1 (LSP 3.17, "exit").
  int run();

private:
  enum class State { Uninitialized, Running, ShutDown };
  void handle(const std::string& body);
  void request(const nlohmann::json& id, const std::string& method, const nlohmann::json& params);
  void notification(const std::string& method, nlohmann::json& params);
  nlohmann::json initialize(const nlohmann::json& params);
  nlohmann::json feature(const std::string& method, const nlohmann::json& params);
  /// textDocument/formatting and rangeFormatting: TextEdit[] that lay the document out as
  /// isofmt lays out its file.
  nlohmann::json formatting(const std::string& method, const nlohmann::json& params);
  /// textDocument/prepareRename and rename (RequestFailed when the name cannot be renamed).
  nlohmann::json renameOf(const std::string& method, const Analysis& a, uint32_t file, Position p,
                          const nlohmann::json& params);
  /// workspace/symbol: the symbols of the open documents' program sets matching the query.
  nlohmann::json workspaceSymbol(const nlohmann::json& params);
  void didOpen(nlohmann::json& params);
  /// Applies the edits in order; one that would take the document over a limit closes it.
  void didChange(nlohmann::json& params);
  /// A `window/showMessage` of type Error.
  void showError(const std::string& message);
  /// Lints the folders changed since the last call and publishes their open documents'
  /// diagnostics; clears those of closed documents. Called when the input is idle and before
  /// every request, so that a burst of edits is linted once (the debounce), deterministically.
  void publishPending();
  void send(const nlohmann::json& message);

  MessageReader reader_;
  std::ostream& out_;
  Workspace workspace_;
  State state_ = State::Uninitialized;
  bool exited_ = false;
  bool markdownHover_ = true;
  EditCapabilities editCaps_ = {};                  ///< what the client's WorkspaceEdits may hold
  std::map<std::string, std::string> policyErrors_; ///< per folder: the last error shown
  /// The last semantic tokens sent per open document (dropped when it closes), for
  /// semanticTokens/full/delta: their resultId and data.
  struct TokensSent {
    std::string resultId;
    std::vector<uint32_t> data; ///< 4 bytes a number, not a JSON value each
  };
  std::map<std::string, TokensSent> tokensSent_;
  uint64_t nextTokensId_ = 1;
  /// semanticTokens/full and /full/delta: the tokens, or the edit from the previous result.
  nlohmann::json semanticTokensOf(const std::string& uri, const Analysis& a, uint32_t file,
                                  const nlohmann::json& params, bool delta);
};

/// isolint --lsp: applies --machine, --dialect, --disable and --werror (a usage error is
/// printed to io.err and returned as exit 2), then serves on `in` and io.out. Each folder is
/// linted under the policy isolint applies to it: the settings file found for it (or
/// --config), its machine file, dialect and rules.
int runLspServer(const driver::LintOptions& opts, std::istream& in, driver::Io& io);

} // namespace iso::lsp
