//! @file FuzzSettings.cpp
//! @brief Fuzz target: bytes -> the settings reader (`isotools.toml`: the UTF-8 check, the
//!        nesting pre-scan, the TOML parser, the key checks). Any input must give settings or
//!        one clean error naming the file ("fuzz.toml: error: ..." or "fuzz.toml:LINE...");
//!        never a crash, a throw or a stack overflow (toml++ recurses once per level, so the
//!        pre-scan must stop every input nested deeper than 64 levels). Settings that load are
//!        also applied: rules per path and exclusions (glob patterns) on a few paths.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "Support.h"
#include "driver/Settings.h"

namespace {
constexpr const char* kTarget = "settings";
constexpr const char* kPath = "fuzz.toml";
} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  iso::driver::Settings s;
  std::string error;
  if (!iso::driver::parseSettings(text, kPath, s, error)) {
    if (error.rfind(std::string(kPath) + ":", 0) != 0 || error.find(" error: ") == std::string::npos)
      iso::fuzz::fail(kTarget, "an error that does not name the file: ", error);
    return 0;
  }
  if (!error.empty()) iso::fuzz::fail(kTarget, "settings read with an error: ", error);
  if (s.dialect != "" && s.dialect != "sidac" && s.dialect != "z32") iso::fuzz::fail(kTarget, "dialect ", s.dialect);
  if (s.maxDiagnostics && *s.maxDiagnostics < 0) iso::fuzz::fail(kTarget, "max-diagnostics below 0");
  for (const char* file : {"p.mpf", "legacy/a/b.spf", "old/x.mpf"}) {
    const std::string path = s.dir + "/" + file;
    (void)s.excludes(path);
    for (size_t c = 0; c < iso::diag::codeCount(); c += 7)
      (void)s.disabledFor(path, static_cast<iso::diag::Code>(c));
  }
  return 0;
}
