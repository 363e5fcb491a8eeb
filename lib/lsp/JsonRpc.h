//! @file JsonRpc.h
//! @brief JSON-RPC 2.0 over the LSP base protocol: `Content-Length` framed messages on
//!        streams. Untrusted input: headers are bounded, bodies are bounded, nothing throws.
#pragma once

#include <cstddef>
#include <iosfwd>
#include <string>

#include <nlohmann/json.hpp>

namespace iso::lsp {

/// JSON-RPC and LSP error codes.
enum class ErrorCode : int {
  ParseError = -32700,
  InvalidRequest = -32600,
  MethodNotFound = -32601,
  InvalidParams = -32602,
  InternalError = -32603,
  ServerNotInitialized = -32002,
  RequestFailed = -32803,
};

/// The largest message body accepted (64 MiB); a larger one is answered and skipped unread.
inline constexpr size_t kMaxMessageBytes = size_t{64} << 20;
/// The longest header line accepted.
inline constexpr size_t kMaxHeaderLine = 4096;

/// Reads framed messages from a stream. One reader per stream; not thread-safe.
class MessageReader {
public:
  enum class Status {
    Message, ///< `body` holds one message body
    Eof,     ///< the input ended (also inside a header or a body)
    Bad,     ///< a framing error: `error` says what; the reader has resynchronised
  };
  explicit MessageReader(std::istream& in, size_t maxBytes = kMaxMessageBytes) : in_(in), maxBytes_(maxBytes) {}

  Status read(std::string& body, std::string& error);
  /// True when no further input is buffered (the peer is probably waiting for us).
  bool idle() const;

private:
  enum class Line { Ok, Eof, TooLong };
  Line readLine(std::string& line);
  std::istream& in_;
  size_t maxBytes_;
  unsigned long long skip_ = 0; ///< bytes of a refused message still to discard
};

/// Writes one message (`Content-Length` header and compact JSON; bytes that are not UTF-8
/// are replaced) and flushes.
void writeMessage(std::ostream& out, const nlohmann::json& message);

/// `{"jsonrpc": "2.0", "id": id, "error": {"code", "message"}}`.
nlohmann::json errorResponse(const nlohmann::json& id, ErrorCode code, const std::string& message);

} // namespace iso::lsp
