//! @file Render.h
//! @brief Renders diagnostics as text (gcc/clang shape), JSON (SPEC §8) or SARIF 2.1.0.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "diag/Diagnostic.h"
#include "diag/SourceManager.h"

namespace iso::diag {

struct Counts {
  size_t errors = 0, warnings = 0, infos = 0;
};
Counts countOf(const std::vector<Diagnostic>& diags);

/// `file:line:col: error: message [E205 case-backward-jump]`, the source line, a caret,
/// indented notes. ANSI colours when `color`.
std::string renderText(const std::vector<Diagnostic>& diags, const SourceManager& sm, bool color);
/// The closing count line: "3 files checked: 1 error, 2 warnings, 0 infos".
std::string renderCountLine(const Counts& c, size_t files);

/// The JSON object of SPEC §8 (keys in the documented order).
nlohmann::ordered_json renderJson(const std::vector<Diagnostic>& diags, const SourceManager& sm, size_t files);

/// A SARIF 2.1.0 log with one run; rules are the whole §7 table.
/// The 1-based UTF-16 column of the 1-based byte column `byteCol` of a source line (SARIF's
/// columnKind utf16CodeUnits); bytes that are not UTF-8 count as one unit each.
uint32_t utf16Column(std::string_view line, uint32_t byteCol);

nlohmann::ordered_json renderSarif(const std::vector<Diagnostic>& diags, const SourceManager& sm,
                                   const std::string& toolName, const std::string& version);

} // namespace iso::diag
