//! @file Z32GCodes.h
//! @brief The G functions that only dialect z32 has (SPEC §4.7): G26, G28, G29, and the valid
//!        Z32 codes whose effect isotools does not model (W420), each with what it is. Header-only.
#pragma once

#include <string_view>

namespace iso::lang {

/// G26: return from subprogram (z32), like M17.
constexpr int kG26Return = 26;

struct Z32GCode {
  int code;
  bool modelled;        ///< false: W420, a no-op in zero time
  std::string_view doc; ///< what it is (messages, hover and completion)
};

inline constexpr Z32GCode kZ32GCodes[] = {
    {25, false, "a Z32 function written with a descriptive tail after its number"},
    {26, true, "return from subprogram, like M17, as the last step of its line"},
    {27, false, "a Z32 function written with a descriptive tail after its number"},
    {28, true, "take the axes written after it under control (G28XY; no letters: every axis)"},
    {29, true, "release the axes written after it from control (G29AB; no letters: every axis)"},
    {36, false, "a Z32 function executed first on its line"},
    {61, false, "a Z32 special motion, run with the axis motion of its line"},
    {62, false, "a Z32 special motion, run with the axis motion of its line"},
    {80, false, "a Z32 function executed first on its line"},
    {84, false, "a Z32 function executed first on its line"},
    {100, false, "a Z32 function executed first on its line"},
    {101, false, "a Z32 function executed first on its line"},
    {110, false, "the Z32 pocketing macro (it numbers the lines it generates itself)"},
};

/// The z32-only G code `code`, or nullptr.
constexpr const Z32GCode* findZ32G(int code) {
  for (const Z32GCode& g : kZ32GCodes)
    if (g.code == code) return &g;
  return nullptr;
}

} // namespace iso::lang
