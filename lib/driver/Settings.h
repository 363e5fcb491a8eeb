//! @file Settings.h
//! @brief Project settings: `isotools.toml`, found by walking up from an input's folder (or
//!        given with --config FILE), read by all three tools. Command-line options win.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
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
  /// isofmt's `[format]` table: each key the file gives (the command line wins).
  struct Format {
    std::optional<std::string> wordCase;      ///< "case": upper | lower | keep
    std::optional<bool> spaceBetweenWords;    ///< "spaces"
    std::optional<bool> spaceAroundOperators; ///< "operator-spaces"
    std::optional<long long> indent;          ///< "indent": blanks per level, 0..8
    std::optional<std::string> numbers;       ///< "numbers": as-written | normalised
    std::optional<long long> blankLines;      ///< "blank-lines": the longest run kept, 0..9
    std::optional<std::string> renumber;      ///< "renumber": "START[,STEP]"
    std::optional<bool> renumberAll;          ///< "renumber-all"
  };
  Format format;

  /// True when `code` is disabled for the file `path` (as named on the command line).
  bool disabledFor(const std::string& file, diag::Code code) const;
  /// True when `path` matches an `exclude` pattern.
  bool excludes(const std::string& file) const;
};

/// The largest settings file read (16 MiB): a larger one is an error.
inline constexpr size_t kMaxSettingsBytes = size_t{16} << 20;

/// Reads and checks a settings file. Unknown keys, wrong types and unknown rule codes are
/// errors: false with `error` = "FILE:LINE: error: ..." naming the key (with "did you mean"
/// when a known one is near). A file that cannot be read, one over kMaxSettingsBytes, one
/// that is not UTF-8 text (or holds a NUL byte) and one nested deeper than 64 levels are
/// errors too ("FILE: error: ...", "FILE:LINE:COL: error: ..."); such a file is read only up
/// to the cap (so a device like /dev/zero ends at once).
bool loadSettings(const std::string& path, Settings& out, std::string& error);

/// The same checks of settings text read from `path` (which names it in errors and is where
/// relative paths start).
bool parseSettings(std::string_view text, const std::string& path, Settings& out, std::string& error);

/// "did you mean" for a rule code or name that is not one: the code (or name) nearest to
/// `name` when it is near enough to be a typo of it, else "".
std::string suggestCode(std::string_view name);

/// The settings file for `input` (a file or folder): `isotools.toml` in its folder or the
/// nearest one above; "" when there is none.
std::string findSettings(const std::string& input);

/// Glob matching of a path against a pattern: `*` and `?` within one path component, `**`
/// across components (`legacy/**`, `**/*.bak.mpf`).
bool globMatch(std::string_view pattern, std::string_view path);

} // namespace iso::driver
