//! @file Server.cpp
//! @brief The LSP lifecycle and the dispatch of requests and notifications.
#include "lsp/Server.h"

#include <iostream>
#include <istream>
#include <ostream>
#include <utility>

#include "driver/Format.h"
#include "driver/Lint.h"
#include "frontend/Lexer.h"
#include "lsp/Features.h"
#include "support/JsonDepth.h"
#include "support/Memory.h"
#include "support/Version.h"

namespace iso::lsp {

using nlohmann::json;

namespace {
/// A request whose params do not have the expected shape.
struct BadParams {
  std::string message;
};
/// A request the server cannot carry out as asked (LSP RequestFailed).
struct Failed {
  std::string message;
};

const json& member(const json& j, const char* key) {
  if (!j.is_object() || !j.contains(key)) throw BadParams{std::string("missing '") + key + "'"};
  return j[key];
}
std::string uriOf(const json& params) {
  const json& uri = member(member(params, "textDocument"), "uri");
  if (!uri.is_string()) throw BadParams{"textDocument.uri is not a string"};
  return uri.get<std::string>();
}
uint32_t natural(const json& j, const char* what) {
  if (!j.is_number_integer() && !j.is_number_unsigned()) throw BadParams{std::string(what) + " is not an integer"};
  auto v = j.get<int64_t>();
  if (v < 0) throw BadParams{std::string(what) + " is negative"};
  return static_cast<uint32_t>(std::min<int64_t>(v, UINT32_MAX));
}
Position positionOf(const json& p) {
  return {natural(member(p, "line"), "line"), natural(member(p, "character"), "character")};
}
Range rangeOf(const json& r) { return {positionOf(member(r, "start")), positionOf(member(r, "end"))}; }
json& member(json& j, const char* key) { return const_cast<json&>(member(std::as_const(j), key)); }
/// A URI as a message shows it: at most 200 bytes.
std::string displayUri(const std::string& uri) { return uri.size() <= 200 ? uri : uri.substr(0, 200) + "..."; }
} // namespace

Server::Server(std::istream& in, std::ostream& out, WorkspaceOptions opts)
    : reader_(in, opts.limits.maxMessageBytes), out_(out), workspace_(std::move(opts)), policy_(opts.policy) {
  // (asked from the check's threads too: the main thread waits for them meanwhile)
  workspace_.setCancel([this] { return cancellable_ && inputWaiting(); });
}

void Server::send(const json& message) { writeMessage(out_, message); }

void Server::showError(const std::string& message) {
  send({{"jsonrpc", "2.0"},
        {"method", "window/showMessage"},
        {"params", {{"type", 1}, {"message", "isolint: " + message}}}});
}

int Server::run() {
  std::string body, error;
  while (!exited_) {
    MessageReader::Status st = reader_.read(body, error);
    if (st == MessageReader::Status::Eof) break;
    if (st == MessageReader::Status::Bad)
      send(errorResponse(nullptr, ErrorCode::ParseError, error));
    else
      handle(body);
    if (body.capacity() > (size_t{64} << 10)) { // a large message's buffer is not kept, nor what it was parsed to
      std::string().swap(body);
      support::returnFreedMemory();
    }
    if (!exited_ && reader_.idle()) {
      // a check the editor's next message would make stale is given up for it (a request
      // checks what it needs first, to the end)
      cancellable_ = true;
      publishPending();
      cancellable_ = false;
    }
    if (!exited_ && !inputWaiting()) runDryRuns();
  }
  return state_ == State::ShutDown ? 0 : 1;
}

void Server::handle(const std::string& body) {
  // nlohmann::json's parser recurses per level: deep input must not reach it.
  if (!support::jsonNestingWithin(body))
    return send(errorResponse(nullptr, ErrorCode::ParseError,
                              "the message nests arrays and objects deeper than the limit of " +
                                  std::to_string(support::kMaxNesting) + " levels"));
  json msg = json::parse(body, nullptr, false);
  if (msg.is_discarded()) return send(errorResponse(nullptr, ErrorCode::ParseError, "the message is not valid JSON"));
  if (!msg.is_object())
    return send(errorResponse(nullptr, ErrorCode::InvalidRequest, "a message must be a JSON object"));
  const bool hasId = msg.contains("id");
  json id = hasId ? msg["id"] : json(nullptr);
  if (msg.contains("method") && msg["method"] == "exit") {
    // exit always ends the process, whatever else the message holds.
    exited_ = true;
    return;
  }
  if (hasId && !id.is_string() && !id.is_number_integer() && !id.is_number_unsigned())
    return send(errorResponse(nullptr, ErrorCode::InvalidRequest, "the id must be an integer or a string"));
  if (!msg.contains("method")) {
    if (hasId && (msg.contains("result") || msg.contains("error"))) return; // a response: we send no requests
    return send(errorResponse(id, ErrorCode::InvalidRequest, "a request needs a 'method'"));
  }
  if (!msg["method"].is_string())
    return send(errorResponse(id, ErrorCode::InvalidRequest, "'method' must be a string"));
  if (!msg.contains("jsonrpc") || msg["jsonrpc"] != "2.0") {
    if (hasId) send(errorResponse(id, ErrorCode::InvalidRequest, "'jsonrpc' must be \"2.0\""));
    return;
  }
  const std::string method = msg["method"].get<std::string>();
  // Absent and null params are the same: no parameters (a method that needs some says which).
  json params = msg.contains("params") && !msg["params"].is_null() ? std::move(msg["params"]) : json::object();
  if (!params.is_object() && !params.is_array()) {
    if (hasId) send(errorResponse(id, ErrorCode::InvalidParams, "'params' must be an object or an array"));
    return;
  }
  if (hasId)
    request(id, method, params);
  else
    notification(method, params);
}

void Server::request(const json& id, const std::string& method, const json& params) {
  auto fail = [&](ErrorCode code, const std::string& message) { send(errorResponse(id, code, message)); };
  if (state_ == State::Uninitialized && method != "initialize")
    return fail(ErrorCode::ServerNotInitialized, "the server is not initialized: send 'initialize' first");
  if (state_ == State::ShutDown) return fail(ErrorCode::InvalidRequest, "the server is shut down: send 'exit'");
  publishPending();
  json result;
  try {
    if (method == "initialize") {
      if (state_ != State::Uninitialized) return fail(ErrorCode::InvalidRequest, "the server is already initialized");
      result = initialize(params);
      state_ = State::Running;
    } else if (method == "shutdown") {
      state_ = State::ShutDown;
      result = nullptr;
    } else if (method == "workspace/symbol") {
      result = workspaceSymbol(params);
    } else if (method.rfind("textDocument/", 0) == 0) {
      result = feature(method, params);
      if (result.is_discarded()) return fail(ErrorCode::MethodNotFound, "unknown method '" + method + "'");
    } else {
      return fail(ErrorCode::MethodNotFound, "unknown method '" + method + "'");
    }
  } catch (const BadParams& e) {
    return fail(ErrorCode::InvalidParams, method + ": " + e.message);
  } catch (const Failed& e) {
    return fail(ErrorCode::RequestFailed, method + ": " + e.message);
  } catch (const json::exception& e) {
    return fail(ErrorCode::InvalidParams, method + ": " + e.what());
  } catch (const std::exception& e) {
    return fail(ErrorCode::InternalError, method + ": internal error: " + e.what());
  }
  send({{"jsonrpc", "2.0"}, {"id", id}, {"result", std::move(result)}});
}

json Server::initialize(const json& params) {
  if (params.is_object() && params.contains("capabilities")) {
    json formats = params["capabilities"].value("/textDocument/hover/contentFormat"_json_pointer, json::array());
    if (formats.is_array() && !formats.empty())
      markdownHover_ = std::find(formats.begin(), formats.end(), "markdown") != formats.end();
    const json& caps = params["capabilities"];
    editCaps_.documentChanges = caps.value("/workspace/workspaceEdit/documentChanges"_json_pointer, json()) == true;
    // A client that renames files takes them in documentChanges, the only place they can be
    // (Neovim 0.7 says the one and not the other).
    json ops = caps.value("/workspace/workspaceEdit/resourceOperations"_json_pointer, json::array());
    editCaps_.renameFiles = ops.is_array() && std::find(ops.begin(), ops.end(), "rename") != ops.end();
  }
  readCycleTimeOptions(params);
  json capabilities = {
      {"positionEncoding", "utf-16"},
      {"textDocumentSync", {{"openClose", true}, {"change", 2}, {"save", {{"includeText", false}}}}},
      {"hoverProvider", true},
      {"definitionProvider", true},
      {"referencesProvider", true},
      {"renameProvider", {{"prepareProvider", true}}},
      {"documentSymbolProvider", true},
      {"foldingRangeProvider", true},
      {"workspaceSymbolProvider", true},
      {"semanticTokensProvider",
       {{"legend", {{"tokenTypes", semanticTokenTypes()}, {"tokenModifiers", json::array()}}},
        {"full", {{"delta", true}}}}},
      {"completionProvider", {{"triggerCharacters", {"$"}}, {"resolveProvider", false}}},
      {"codeActionProvider", {{"codeActionKinds", {"quickfix"}}}},
      {"documentFormattingProvider", true},
      {"documentRangeFormattingProvider", true},
      {"codeLensProvider", {{"resolveProvider", false}}},
      {"inlayHintProvider", true},
  };
  return {{"capabilities", std::move(capabilities)}, {"serverInfo", {{"name", "isolint"}, {"version", kVersion}}}};
}

json Server::workspaceSymbol(const json& params) {
  const json& q = member(params, "query");
  if (!q.is_string()) throw BadParams{"query must be a string"};
  std::vector<const Analysis*> analyses;
  for (const auto& folder : workspace_.folders())
    if (const Analysis* a = workspace_.analyseFolder(folder)) analyses.push_back(a);
  constexpr size_t kMaxSymbols = 1000; // bounded whatever the folder holds
  return workspaceSymbols(analyses, q.get<std::string>(), kMaxSymbols);
}

json Server::formatting(const std::string& method, const json& params) {
  const std::string uri = uriOf(params);
  driver::LineSpan lines; // all
  if (method == "textDocument/rangeFormatting") {
    Range r = rangeOf(member(params, "range"));
    if (r.end.line < r.start.line || (r.end.line == r.start.line && r.end.character < r.start.character))
      std::swap(r.start, r.end);
    // Whole lines: those the range touches; a range that ends at the start of a line leaves it out.
    uint32_t last = r.end.line;
    if (r.end.character == 0 && last > r.start.line) --last;
    auto oneBased = [](uint32_t l) { return l == UINT32_MAX ? l : l + 1; };
    lines = {oneBased(r.start.line), oneBased(last)};
  }
  // `options` (tabSize, insertSpaces) is not read: the layout is isofmt's for the file.
  auto edits = workspace_.format(uri, lines);
  if (!edits) throw Failed{edits.error().message + "; the document is not formatted"};
  const TextDocument* doc = workspace_.document(uri);
  return doc ? textEdits(*doc, *edits) : json::array();
}

json Server::feature(const std::string& method, const json& params) {
  if (method == "textDocument/formatting" || method == "textDocument/rangeFormatting")
    return formatting(method, params);
  if (method == "textDocument/codeLens") return codeLenses(uriOf(params));
  if (method == "textDocument/inlayHint") return inlayHints(uriOf(params), params);
  static const char* const kMethods[] = {"textDocument/hover",
                                         "textDocument/definition",
                                         "textDocument/references",
                                         "textDocument/documentSymbol",
                                         "textDocument/completion",
                                         "textDocument/codeAction",
                                         "textDocument/foldingRange",
                                         "textDocument/semanticTokens/full",
                                         "textDocument/semanticTokens/full/delta",
                                         "textDocument/prepareRename",
                                         "textDocument/rename"};
  if (std::find(std::begin(kMethods), std::end(kMethods), method) == std::end(kMethods))
    return json::value_t::discarded;
  const std::string uri = uriOf(params);
  const bool tokens = method.rfind("textDocument/semanticTokens/", 0) == 0;
  const bool listResult = method != "textDocument/hover" && method != "textDocument/prepareRename" &&
                          method != "textDocument/rename" && !tokens;
  const Analysis* a = workspace_.analysis(uri);
  std::optional<uint32_t> file = a ? a->fileOf(uri) : std::nullopt;
  if (!file) return listResult ? json::array() : json(nullptr); // not an open document
  if (method == "textDocument/documentSymbol") return documentSymbols(*a, *file);
  if (tokens) return semanticTokensOf(uri, *a, *file, params, method == "textDocument/semanticTokens/full/delta");
  if (method == "textDocument/foldingRange") return foldingRanges(*a, *file, *workspace_.document(uri));
  if (method == "textDocument/codeAction") return codeActions(*a, *file, rangeOf(member(params, "range")));
  Position p = positionOf(member(params, "position"));
  if (method == "textDocument/hover") return withLineTime(hover(*a, *file, p, markdownHover_), uri, p.line);
  if (method == "textDocument/definition") return definition(*a, *file, p);
  if (method == "textDocument/prepareRename" || method == "textDocument/rename")
    return renameOf(method, *a, *file, p, params);
  if (method == "textDocument/references") {
    bool decl = params.value("/context/includeDeclaration"_json_pointer, false);
    return references(*a, *file, p, decl);
  }
  return completion(*a, *file, *workspace_.document(uri), p);
}

json Server::renameOf(const std::string& method, const Analysis& a, uint32_t file, Position p, const json& params) {
  support::Expected<json> r = json(nullptr);
  if (method == "textDocument/prepareRename") {
    r = prepareRename(a, file, p);
  } else {
    const json& name = member(params, "newName");
    if (!name.is_string()) throw BadParams{"newName is not a string"};
    auto versionOf = [&](const std::string& uri) -> std::optional<int64_t> {
      const TextDocument* doc = workspace_.document(uri);
      return doc ? std::optional<int64_t>(doc->version()) : std::nullopt;
    };
    r = rename(a, file, p, name.get<std::string>(), editCaps_, versionOf);
  }
  if (!r) throw Failed{r.error().message};
  return std::move(*r);
}

json Server::semanticTokensOf(const std::string& uri, const Analysis& a, uint32_t file, const json& params,
                              bool delta) {
  const auto data = semanticTokens(a, file)["data"].get<std::vector<uint32_t>>();
  const std::string id = std::to_string(nextTokensId_++);
  auto it = tokensSent_.find(uri);
  json result;
  std::string wanted;
  if (delta) {
    const json& p = member(params, "previousResultId");
    if (!p.is_string()) throw BadParams{"previousResultId must be a string"};
    wanted = p.get<std::string>();
  }
  if (delta && it != tokensSent_.end() && it->second.resultId == wanted) {
    // One edit: the differing middle between the common prefix and the common suffix.
    const std::vector<uint32_t>& old = it->second.data;
    size_t pre = 0;
    while (pre < old.size() && pre < data.size() && old[pre] == data[pre])
      ++pre;
    size_t suf = 0;
    while (suf < old.size() - pre && suf < data.size() - pre &&
           old[old.size() - 1 - suf] == data[data.size() - 1 - suf])
      ++suf;
    json edits = json::array();
    if (pre != old.size() || old.size() != data.size()) {
      std::vector<uint32_t> inserted(data.begin() + static_cast<std::ptrdiff_t>(pre),
                                     data.end() - static_cast<std::ptrdiff_t>(suf));
      edits.push_back({{"start", pre}, {"deleteCount", old.size() - pre - suf}, {"data", std::move(inserted)}});
    }
    result = {{"resultId", id}, {"edits", std::move(edits)}};
  } else {
    result = {{"resultId", id}, {"data", data}}; // a full result: no or an unknown previous one
  }
  tokensSent_[uri] = {id, data};
  return result;
}

void Server::notification(const std::string& method, json& params) {
  if (state_ != State::Running) return; // before initialize and after shutdown, notifications are dropped
  try {
    if (method == "textDocument/didOpen") {
      didOpen(params);
      queueDryRun(uriOf(params));
    } else if (method == "textDocument/didChange") {
      didChange(params);
    } else if (method == "textDocument/didSave") {
      workspace_.touch(uriOf(params));
      queueDryRun(uriOf(params));
    } else if (method == "textDocument/didClose") {
      const std::string uri = uriOf(params);
      workspace_.close(uri);
      tokensSent_.erase(uri);
      dryRunQueue_.erase(uri);
    }
    // initialized, $/cancelRequest, $/setTrace, workspace/* and unknown notifications: nothing
    // to do (JSON-RPC: a notification is never answered).
  } catch (const BadParams&) {
  } catch (const json::exception&) {
  }
}

void Server::didOpen(json& params) {
  const std::string uri = uriOf(params);
  json& td = params["textDocument"];
  json& text = member(td, "text");
  if (!text.is_string()) throw BadParams{"text is not a string"};
  const int64_t version = td.value("version", int64_t{0});
  // The text is moved out of the message: a large document is not held twice.
  if (auto refused = workspace_.open(uri, std::move(text.get_ref<std::string&>()), version))
    showError(displayUri(uri) + " is not checked: " + *refused);
}

void Server::didChange(json& params) {
  const std::string uri = uriOf(params);
  TextDocument* doc = workspace_.document(uri);
  if (!doc) return;
  json& changes = member(params, "contentChanges");
  if (!changes.is_array()) throw BadParams{"contentChanges is not an array"};
  for (json& c : changes) {
    json& text = member(c, "text");
    if (!text.is_string()) throw BadParams{"text is not a string"};
    const bool ranged = c.contains("range");
    const Range r = ranged ? rangeOf(c["range"]) : Range{};
    const std::string& t = text.get_ref<const std::string&>();
    if (auto refused = workspace_.admitsSize(uri, ranged ? doc->sizeAfterEdit(r, t.size()) : t.size())) {
      workspace_.close(uri);
      return showError(displayUri(uri) + " is closed and no longer checked: " + *refused);
    }
    if (ranged) {
      workspace_.edited(uri, doc->edit(r, t));
    } else {
      doc->replace(std::move(text.get_ref<std::string&>()));
      workspace_.touch(uri);
    }
  }
  const json& td = member(params, "textDocument");
  if (td.contains("version") && td["version"].is_number_integer()) doc->setVersion(td["version"].get<int64_t>());
}

void Server::publishPending() {
  for (const auto& uri : workspace_.takeClosed())
    send({{"jsonrpc", "2.0"},
          {"method", "textDocument/publishDiagnostics"},
          {"params", {{"uri", uri}, {"diagnostics", json::array()}}}});
  const std::vector<std::string> stale = workspace_.takeStaleFolders();
  for (size_t k = 0; k < stale.size(); ++k) {
    const std::string& folder = stale[k];
    for (const auto& uri : workspace_.documentsIn(folder)) {
      const FolderLint* lint = nullptr;
      std::vector<diag::Diagnostic> diags;
      try {
        diags = workspace_.diagnostics(uri, lint);
      } catch (const frontend::Cancelled&) {
        // More came from the editor during the check: it is read first, and this folder and
        // those after it are checked once it has been handled (their diagnostics would be stale).
        for (size_t j = k; j < stale.size(); ++j)
          workspace_.checkLater(stale[j]);
        return;
      }
      if (!lint) continue;
      // a broken settings or machine file is shown once, until it changes or is mended
      std::string& shown = policyErrors_[folder];
      if (lint->policyError != shown && !lint->policyError.empty())
        showError(lint->policyError.substr(0, lint->policyError.find_last_not_of('\n') + 1) +
                  " (the folder is checked without it)");
      shown = lint->policyError;
      send({{"jsonrpc", "2.0"},
            {"method", "textDocument/publishDiagnostics"},
            {"params",
             {{"uri", uri},
              {"version", workspace_.document(uri)->version()},
              {"diagnostics", diagnosticsJson(diags, workspace_.lineText(*lint), lint->uris)}}}});
    }
  }
}

int runLspServer(const driver::LintOptions& opts, std::istream& in, driver::Io& io) {
  if (!opts.paths.empty()) return driver::usageError(io, "isolint", "--lsp takes no PATH (the editor sends the files)");
  std::vector<diag::Code> disabled;
  if (!driver::resolveCodes(opts.disable, disabled, io, "isolint")) return driver::kExitUsage;
  auto m = driver::loadMachine(opts.common, io);
  if (!m) return driver::kExitUsage;
  Server server(in, io.out, {&*m, std::move(disabled), opts.werror, {}, &opts.common});
  if (&in == &std::cin) server.setInputFd(0);
  return server.run();
}

} // namespace iso::lsp
