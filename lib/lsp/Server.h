//! @file Server.h
//! @brief `isolint --lsp`: a Language Server Protocol 3.17 server. It reads JSON-RPC messages
//!        from an std::istream and writes to an std::ostream, so tests drive it in memory.
//!        Single-threaded: each message is handled to completion before the next is read.
#pragma once

#include <atomic>
#include <iosfwd>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "lsp/DryRun.h"
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
  /// While a dry run runs, the server looks at this descriptor (and the stream's buffer) for
  /// the editor's next message, and stops the run when one comes (-1: the buffer only).
  void setInputFd(int fd) { inputFd_ = fd; }

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
  // ---- the cycle time beside the code (CycleTime.cpp)
  /// initializationOptions.cycleTime and the client's refresh capabilities.
  void readCycleTimeOptions(const nlohmann::json& params);
  /// After didOpen and didSave: the document's program runs when the input is idle.
  void queueDryRun(const std::string& uri);
  /// Runs the queued dry runs while no message waits; one that a message interrupts stays queued.
  void runDryRuns();
  bool inputWaiting() const;
  /// The programs whose dry run shows in `uri`: itself (a main or semi-automatic program), or
  /// the main programs of its folder (a subprogram); empty when none.
  std::vector<std::string> programsFor(const std::string& uri);
  /// The runs that show in the document at `path`, with the time each spent on its lines.
  std::vector<const DryRun*> runsShownIn(const std::string& path) const;
  /// The isotools/dryRun notification of a document: its state and the title of its lens.
  void notifyDryRun(const std::string& uri, const char* state, const std::string& title);
  std::string lensTitle(const std::string& path) const;
  nlohmann::json codeLenses(const std::string& uri);
  nlohmann::json inlayHints(const std::string& uri, const nlohmann::json& params);
  /// The hover with the line's dry-run time, share and limiting factor added.
  nlohmann::json withLineTime(nlohmann::json hover, const std::string& uri, uint32_t line);
  DryRunOptions dryRunOpts_;
  const driver::CommonOptions* policy_ = nullptr;
  int inputFd_ = -1;
  std::atomic<bool> cancellable_{false}; ///< the check running may be given up for new input
  bool lensRefresh_ = false;             ///< the client takes workspace/codeLens/refresh
  bool hintRefresh_ = false;             ///< ... and workspace/inlayHint/refresh
  uint64_t nextRequestId_ = 1;
  std::set<std::string> dryRunQueue_;     ///< document URIs
  std::map<std::string, DryRun> dryRuns_; ///< by program path

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
