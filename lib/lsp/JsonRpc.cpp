//! @file JsonRpc.cpp
//! @brief LSP base protocol framing by hand.
#include "lsp/JsonRpc.h"
#include "support/CaseFold.h"

#include <algorithm>
#include <charconv>
#include <istream>
#include <limits>
#include <ostream>

namespace iso::lsp {

namespace {
size_t findNoCase(std::string_view s, std::string_view needle) {
  for (size_t i = 0; i + needle.size() <= s.size(); ++i)
    if (support::istartsWith(s.substr(i), needle)) return i;
  return std::string_view::npos;
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t'))
    s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t'))
    s.remove_suffix(1);
  return s;
}
} // namespace

MessageReader::Line MessageReader::readLine(std::string& line) {
  line.clear();
  for (;;) {
    int c = in_.get();
    if (c == std::char_traits<char>::eof()) return Line::Eof;
    if (c == '\n') break;
    if (line.size() >= kMaxHeaderLine) {
      // Drop the rest of an overlong line, so that the next read starts on a fresh line.
      in_.ignore(std::numeric_limits<std::streamsize>::max(), '\n');
      return in_.eof() ? Line::Eof : Line::TooLong;
    }
    line.push_back(static_cast<char>(c));
  }
  if (!line.empty() && line.back() == '\r') line.pop_back();
  return Line::Ok;
}

MessageReader::Status MessageReader::read(std::string& body, std::string& error) {
  body.clear();
  error.clear();
  while (skip_ > 0) {
    auto step = static_cast<std::streamsize>(std::min<unsigned long long>(skip_, 1u << 20));
    in_.ignore(step);
    if (in_.gcount() < step) {
      skip_ = 0;
      return Status::Eof;
    }
    skip_ -= static_cast<unsigned long long>(step);
  }
  constexpr std::string_view kLength = "Content-Length:";
  bool haveLength = false, sawHeader = false;
  unsigned long long length = 0;
  std::string line;
  for (;;) {
    Line r = readLine(line);
    if (r == Line::Eof) return Status::Eof;
    if (r == Line::TooLong) {
      if (error.empty()) error = "header line longer than 4096 bytes";
      sawHeader = true;
      continue;
    }
    if (line.empty()) {
      if (!sawHeader) continue; // blank lines between messages
      break;
    }
    sawHeader = true;
    std::string_view l = line;
    // Resynchronise after garbage (say, a body that was longer than its Content-Length): a
    // header may follow junk on the same line.
    if (size_t at = findNoCase(l, kLength); at != std::string_view::npos && at > 0) {
      if (error.empty()) error = "unexpected bytes before a Content-Length header";
      l.remove_prefix(at);
    }
    size_t colon = l.find(':');
    if (colon == std::string_view::npos) {
      if (error.empty()) error = "malformed header line (no ':')";
      continue;
    }
    if (support::istartsWith(l, kLength)) {
      std::string_view v = trim(l.substr(kLength.size()));
      unsigned long long n = 0;
      auto [end, ec] = std::from_chars(v.data(), v.data() + v.size(), n);
      if (v.empty() || ec != std::errc() || end != v.data() + v.size()) {
        error = "Content-Length is not a number: '" + std::string(v.substr(0, 40)) + "'";
        haveLength = false;
        continue;
      }
      length = n;
      haveLength = true;
    }
    // Content-Type and unknown headers are ignored.
  }
  if (!haveLength) {
    if (error.empty()) error = "message without a Content-Length header";
    return Status::Bad;
  }
  if (length > maxBytes_) {
    // Answered now; its body is skipped unread by the next read, in bounded steps, so memory
    // never depends on the claimed size.
    error = "message of " + std::to_string(length) + " bytes is over the limit of " + std::to_string(maxBytes_) +
            " bytes; skipped";
    skip_ = length;
    return Status::Bad;
  }
  body.resize(static_cast<size_t>(length));
  in_.read(body.data(), static_cast<std::streamsize>(length));
  if (static_cast<unsigned long long>(in_.gcount()) < length) return Status::Eof;
  error.clear(); // junk before a good message does not matter
  return Status::Message;
}

bool MessageReader::idle() const {
  auto* buf = in_.rdbuf();
  return buf == nullptr || buf->in_avail() <= 0;
}

void writeMessage(std::ostream& out, const nlohmann::json& message) {
  std::string body = message.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  out << "Content-Length: " << body.size() << "\r\n\r\n" << body;
  out.flush();
}

nlohmann::json errorResponse(const nlohmann::json& id, ErrorCode code, const std::string& message) {
  return {{"jsonrpc", "2.0"}, {"id", id}, {"error", {{"code", static_cast<int>(code)}, {"message", message}}}};
}

} // namespace iso::lsp
