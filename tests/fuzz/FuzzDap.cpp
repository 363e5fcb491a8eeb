//! @file FuzzDap.cpp
//! @brief Fuzz target: a byte stream of Debug Adapter Protocol frames -> isosim's debug adapter
//!        (dap::runDebugAdapter on in-memory streams). Whatever the input, the adapter must end
//!        (exit code 0 or 1) without a crash or an exception, and everything it writes must be
//!        well-formed: `Content-Length: N\r\n\r\n` and N bytes, repeated to the end; each body a
//!        JSON object with an integer `seq` that is a response (request_seq, success, command;
//!        a message when it failed) or an event (a string `event` and an object `body`).
//!
//! Input format: the bytes an editor would write on the adapter's standard input, at most
//! 1 MiB. Relative paths start from the project's samples folder, so that a seed launches a
//! sample by a relative path (drilling_when/foratura_piastra.mpf) wherever the project is.
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "Support.h"
#include "dap/DebugAdapter.h"

namespace {

using nlohmann::json;
constexpr const char* kTarget = "FuzzDap";

void checkMessage(const json& m, const std::string& body) {
  if (!m.is_object() || !m.value("seq", json()).is_number_integer())
    iso::fuzz::fail(kTarget, "not an object with an integer seq: ", body);
  const std::string type = m.value("type", "");
  if (type == "response") {
    if (!m.value("request_seq", json()).is_number_integer() || !m.value("success", json()).is_boolean() ||
        !m.value("command", json()).is_string())
      iso::fuzz::fail(kTarget, "a response without request_seq, success or command: ", body);
    if (!m["success"].get<bool>() && !m.value("message", json()).is_string())
      iso::fuzz::fail(kTarget, "a failed response without a message: ", body);
  } else if (type == "event") {
    if (!m.value("event", json()).is_string() || !m.value("body", json()).is_object())
      iso::fuzz::fail(kTarget, "an event without a name or a body: ", body);
  } else {
    iso::fuzz::fail(kTarget, "neither a response nor an event: ", body);
  }
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size > (1u << 20)) return 0;
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  std::ostringstream out;
  int code = -1;
  try {
    code = iso::dap::runDebugAdapter(in, out, {.pollFd = -1, .baseDir = ISO_SAMPLES_DIR});
  } catch (const std::exception& e) {
    iso::fuzz::fail(kTarget, "the adapter threw: ", e.what());
  }
  if (code != 0 && code != 1) iso::fuzz::fail(kTarget, "exit code not 0 or 1: ", std::to_string(code));
  iso::fuzz::forEachFrame(kTarget, out.str(), checkMessage);
  return 0;
}
