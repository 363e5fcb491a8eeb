//! @file RuleDocs.h
//! @brief The documentation of each rule, from its one source: the RULES section of
//!        man/isolint.1 (embedded at build time). Used by isolint --explain and the SARIF rules.
#pragma once

#include <string>

#include "diag/Diagnostic.h"

namespace iso::diag {

struct RuleDoc {
  std::string text;     ///< what the rule reports, as plain text (one paragraph)
  std::string markdown; ///< the same in Markdown (code in backticks)
  std::string example;  ///< a program that triggers it (lines), or ""
};

/// The documentation of `code` (empty fields when the man page lacks its entry).
const RuleDoc& ruleDoc(Code code);

/// `isolint --explain CODE`: the code, name, severity, the text, the example and how to
/// silence it, as plain text.
std::string explainRule(Code code);

/// The Markdown help of SARIF rules: the text, the example as a code block, how to silence it.
std::string ruleHelpMarkdown(Code code);

} // namespace iso::diag
