//! @file Settings.h
//! @brief Project settings: `isotools.toml`, found by walking up from an input's folder (or
//!        given with --config FILE), read by all three tools. Command-line options win.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "diag/Diagnostic.h"

namespace iso::driver {

/// The file name looked for in each folder from an input up to the root.
inline constexpr const char* kSettingsFileName = "isotools.toml";

struct Settings {
  std::string path;    ///< the file read ("" = no settings)
  std::string dir;     ///< its folder: relative paths and patterns start there
  std::string machine; ///< machine file, made relative to the working directory
  std::string dialect; ///< sidac | z32 | ""
  std::optional<long long> maxDiagnostics;
  std::vector<diag::Code> disable;  ///< rules off everywhere
  std::vector<diag::Code> enable;   ///< rules back on (after disable)
  std::vector<std::string> exclude; ///< patterns of files that folder walks skip
  struct Override {
    std::vector<std::string> paths; ///< patterns (relative to dir)
    std::vector<diag::Code> disable;
    std::vector<diag::Code> enable;
  };
  std::vector<Override> overrides;

  /// True when `code` is disabled for the file `path` (as named on the command line).
  bool disabledFor(const std::string& file, diag::Code code) const;
  /// True when `path` matches an `exclude` pattern.
  bool excludes(const std::string& file) const;
};

/// Reads and checks a settings file. Unknown keys, wrong types and unknown rule codes are
/// errors: false with `error` = "FILE:LINE: error: ..." naming the key.
bool loadSettings(const std::string& path, Settings& out, std::string& error);

/// The settings file for `input` (a file or folder): `isotools.toml` in its folder or the
/// nearest one above; "" when there is none.
std::string findSettings(const std::string& input);

/// Glob matching of a path against a pattern: `*` and `?` within one path component, `**`
/// across components (`legacy/**`, `**/*.bak.mpf`).
bool globMatch(std::string_view pattern, std::string_view path);

} // namespace iso::driver
