//! @file Code.h
//! @brief The diagnostic codes of SPEC §7 (generated from Diagnostics.def) and their table.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string_view>

namespace iso::diag {

enum class Severity : uint8_t { Info, Warning, Error };

/// Every diagnostic code of SPEC §7, in table order.
enum class Code : uint16_t {
#define DIAG(e, code, name, sev, desc) e,
#include "diag/Diagnostics.def"
  Count_
};

struct CodeInfo {
  const char* code;        ///< "E205"
  const char* name;        ///< "case-backward-jump"
  Severity severity;       ///< default severity
  const char* description; ///< one line, for rule tables (SARIF, man page)
};

const CodeInfo& info(Code code);
/// Finds a code by its code ("E205", case-insensitive) or its name ("case-backward-jump").
std::optional<Code> findCode(std::string_view codeOrName);
constexpr size_t codeCount() { return static_cast<size_t>(Code::Count_); }
const char* severityName(Severity s);

} // namespace iso::diag
