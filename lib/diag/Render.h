//! @file Render.h
//! @brief Renders diagnostics as text (gcc/clang shape), JSON (SPEC §8) or SARIF 2.1.0.
//!        Every renderer streams: it writes one diagnostic at a time to an std::ostream, so the
//!        output's size never has to fit in memory. Bytes from sources and file names are
//!        escaped for terminals (text) and made valid UTF-8 (JSON, SARIF): see support/Text.h.
#pragma once

#include <iosfwd>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "diag/Diagnostic.h"
#include "diag/DiagnosticEngine.h"
#include "diag/SourceManager.h"

namespace iso::diag {

/// Text output in the gcc/clang shape: `file:line:col: error: message [E205 case-backward-jump]`,
/// a window of the source line (at most kWindowColumns columns around the caret, `…` where
/// it is cut), the caret, indented notes; ANSI colours when `color`. At most `maxPerFile`
/// diagnostics per file (0 = all), then a line `N more diagnostics in FILE`.
class TextRenderer {
public:
  static constexpr size_t kWindowColumns = 100;
  TextRenderer(std::ostream& os, const SourceManager& sm, bool color, size_t maxPerFile = 0)
      : os_(os), sm_(sm), color_(color), maxPerFile_(maxPerFile) {}
  void add(const Diagnostic& d);
  /// Writes the pending `N more diagnostics` line (call once, after the last add).
  void finish();

private:
  void flushHidden();
  std::ostream& os_;
  const SourceManager& sm_;
  bool color_;
  size_t maxPerFile_;
  uint32_t file_ = UINT32_MAX;
  size_t shownInFile_ = 0;
  size_t hiddenInFile_ = 0;
  std::string buf_;
};

/// All of `diags` as text (no per-file limit): tests and fuzzing.
std::string renderText(const std::vector<Diagnostic>& diags, const SourceManager& sm, bool color);
/// The closing count line: "3 files checked: 1 error, 2 warnings, 0 infos".
std::string renderCountLine(const Counts& c, size_t files);

/// The source line window of the text format: `line` cut to about `width` columns around
/// byte column `col` (1-based), escaped for a terminal, with `…` at each cut end. `caretCol`
/// receives the display column (0-based) of `col` in the result and `underline` the display
/// width of `len` bytes from there (at least 1).
std::string sourceWindow(std::string_view line, uint32_t col, uint32_t len, size_t width, size_t& caretCol,
                         size_t& underline);

/// The version of isolint's JSON (schemas/isolint.schema.json): raised when a key changes
/// meaning or goes away.
inline constexpr int kLintJsonFormatVersion = 1;

/// The JSON object of SPEC §8 (keys in the documented order), written to `os` (indent 2).
/// `input_errors` is present only when some input could not be read. The counts are those of
/// `diags` unless `counts` gives them (a list cut by --max-diagnostics still counts all).
void writeJson(std::ostream& os, const std::vector<Diagnostic>& diags, const SourceManager& sm, size_t files,
               const std::vector<InputError>& inputErrors = {}, const Counts* counts = nullptr);
nlohmann::ordered_json renderJson(const std::vector<Diagnostic>& diags, const SourceManager& sm, size_t files);

/// The 1-based UTF-16 column of the 1-based byte column `byteCol` of a source line (SARIF's
/// columnKind utf16CodeUnits); bytes that are not UTF-8 count as one unit each.
uint32_t utf16Column(std::string_view line, uint32_t byteCol);

/// A SARIF 2.1.0 log with one run; rules are the whole §7 table. Inputs that could not be read
/// are toolExecutionNotifications of the run's invocation (then executionSuccessful is false).
/// Each result has partialFingerprints["isolint/v1"] (sarifFingerprint), stable across edits
/// elsewhere in its file. With `srcRoot` (the directory relative paths start from), relative
/// URIs carry uriBaseId SRCROOT, defined in originalUriBaseIds. `ruleTable` false leaves out
/// tool.driver.rules (the same in every log: the fuzz target checks it once, then the results).
void writeSarif(std::ostream& os, const std::vector<Diagnostic>& diags, const SourceManager& sm,
                const std::string& toolName, const std::string& version,
                const std::vector<InputError>& inputErrors = {}, const std::string& srcRoot = {},
                bool ruleTable = true);

/// The fingerprint of a finding: its rule, file and line text (blanks folded), and how many
/// identical ones come before it in the file: "<16 hex digits>:<occurrence>".
std::string sarifFingerprint(std::string_view ruleId, std::string_view path, std::string_view lineText,
                             size_t occurrence);
/// The fingerprint of each of `diags`, in order (the occurrences counted in that order), as
/// SARIF's partialFingerprints and isolint's baseline file carry them.
std::vector<std::string> findingFingerprints(const std::vector<Diagnostic>& diags, const SourceManager& sm);

/// GitHub's escaping of workflow command data (`%`, CR, LF) and, for properties (file=,
/// title=), also `:` and `,`.
std::string githubEscape(std::string_view s, bool property);

/// GitHub Actions workflow commands, one a diagnostic:
/// `::error file=F,line=L,col=C,endLine=L2,endColumn=C2,title=E205 case-backward-jump::message`
/// (infos are `::notice`), so that findings show as annotations on the pull request.
void writeGithub(std::ostream& os, const std::vector<Diagnostic>& diags, const SourceManager& sm);
nlohmann::ordered_json renderSarif(const std::vector<Diagnostic>& diags, const SourceManager& sm,
                                   const std::string& toolName, const std::string& version);

} // namespace iso::diag
