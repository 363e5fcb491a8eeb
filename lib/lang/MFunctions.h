//! @file MFunctions.h
//! @brief The M functions of both dialects (SPEC §4.5, §4.6): what each number means, where it
//!        runs in the order of a line in dialect z32, and the per-line limits. Header-only,
//!        no dependencies: read by the parser, sema, compiler and simulator.
#pragma once

#include <cstdint>
#include <string_view>

namespace iso::lang {

enum class Dialect : uint8_t { Sidac, Z32 };

/// Call nesting below the main program (SPEC §1; z32 §4.6: each call and special M counts).
constexpr int kMaxNestingSidac = 30;
constexpr int kMaxNestingZ32 = 10;
constexpr int maxNesting(Dialect d) { return d == Dialect::Z32 ? kMaxNestingZ32 : kMaxNestingSidac; }

/// The largest M number a program may write (M<n>, M=NB(n)).
constexpr int32_t kMaxMNumber = 999'999'999; ///< 9 digits, as any number (SPEC §2)
/// z32: the largest tool number T that M6 mounts (9 digits too; SPEC §2, §4.6).
constexpr int32_t kMaxToolNumber = 999'999'999;

/// The M functions of both dialects that are more than a PLC sequence (SPEC §4.5).
constexpr int32_t kMStop = 0;    ///< M0
constexpr int32_t kMReturn = 17; ///< M17
constexpr int32_t kMEnd = 30;    ///< M30
constexpr int32_t kMEndZ32 = 2;  ///< z32 M2

/// The M functions that are more than a PLC sequence in both dialects (z32 adds more: mRole),
/// one row each, with the text editors show (Markdown).
struct MFunctionDoc {
  int32_t number;
  std::string_view doc;
};
constexpr MFunctionDoc kMFunctionDocs[] = {
    {kMStop, "stop until the operator presses start (the machine file gives the wait); runs last on its line"},
    {kMReturn,
     "end of subprogram: return to the caller, restoring the modal G state and F (SAVE); mandatory in a .spf"},
    {kMEnd, "end of program: waits for the machine to be idle; ends the whole program from anywhere"},
};

/// What an M function does beyond its PLC sequence.
enum class MRole : uint8_t {
  Plain,        ///< a PLC sequence only ("other M")
  Stop,         ///< M0: stop until start (m0_wait_s); z32: spindle and coolants off first
  OptionalStop, ///< z32 M1: acts as M0 when the machine's optional_stop is true
  End,          ///< M30 (both dialects), M2 (z32): end of program
  Return,       ///< M17: end of subprogram
  SpindleCw,    ///< z32 M3
  SpindleCcw,   ///< z32 M4
  SpindleStop,  ///< z32 M5 (coolants off too)
  ToolChange,   ///< z32 M6 (may be special)
  Coolant1,     ///< z32 M7
  Coolant2,     ///< z32 M8
  CoolantOff,   ///< z32 M9
  SpindleOrient ///< z32 M19 (spindle stopped, coolants off)
};

/// The role of M`n` in dialect `d` (SPEC §4.5; z32 §4.6).
constexpr MRole mRole(int64_t n, Dialect d) {
  switch (n) {
  case kMStop: return MRole::Stop;
  case kMReturn: return MRole::Return;
  case kMEnd: return MRole::End;
  default: break;
  }
  if (d != Dialect::Z32) return MRole::Plain;
  switch (n) {
  case 1: return MRole::OptionalStop;
  case kMEndZ32: return MRole::End;
  case 3: return MRole::SpindleCw;
  case 4: return MRole::SpindleCcw;
  case 5: return MRole::SpindleStop;
  case 6: return MRole::ToolChange;
  case 7: return MRole::Coolant1;
  case 8: return MRole::Coolant2;
  case 9: return MRole::CoolantOff;
  case 19: return MRole::SpindleOrient;
  default: return MRole::Plain;
  }
}

/// Final M: at most one per line; they end the line's work (M0 M1 M2 M17 M30).
constexpr bool isFinal(MRole r) {
  return r == MRole::Stop || r == MRole::OptionalStop || r == MRole::End || r == MRole::Return;
}
/// Z32-managed M (M3 M4 M5 M6 M7 M8 M9 M19): any number per line.
constexpr bool isManaged(MRole r) { return r >= MRole::SpindleCw; }

/// M numbers that cannot be special in z32 (SPEC §4.6: 0 1 2 3 4 5 7 8 9 17 19 30; M6 can).
constexpr bool mayBeSpecial(int64_t n) {
  switch (n) {
  case 0:
  case 1:
  case 2:
  case 3:
  case 4:
  case 5:
  case 7:
  case 8:
  case 9:
  case 17:
  case 19:
  case 30: return false;
  default: return n >= 0 && n <= kMaxMNumber;
  }
}
/// The most entries the machine key special_m may hold (seed 004: up to 48).
constexpr int kMaxSpecialM = 48;

/// The place of a function in the order of one z32 line (SPEC §4.6, (1)..(10)).
enum class Z32Step : uint8_t {
  Words = 10,      ///< assignments, G (G28 too), F, S in written order
  Spindle = 20,    ///< M3 / M4
  Special = 30,    ///< the special M (then the line ends)
  Other = 40,      ///< T, TA, TB, the other M, M7 M8 M9, MA MB MC in written order
  Origin = 45,     ///< O (step 4b)
  Motion = 50,     ///< axis motion (and G61/G62)
  Dwell = 60,      ///< G04
  Release = 65,    ///< G29 (step 6b)
  Orient = 70,     ///< M19
  SpindleOff = 80, ///< M5
  Tool = 90,       ///< M6 (special or not)
  Final = 100,     ///< M0 M1 M2 M17 M30
  Continue = 110,  ///< KG (step 11)
  Return = 120,    ///< G26 (step 12)
};

/// Where M`n` runs in a z32 line; `special` tells whether the machine maps it to a subprogram.
constexpr Z32Step z32Step(int64_t n, bool special) {
  switch (mRole(n, Dialect::Z32)) {
  case MRole::SpindleCw:
  case MRole::SpindleCcw: return Z32Step::Spindle;
  case MRole::SpindleOrient: return Z32Step::Orient;
  case MRole::SpindleStop: return Z32Step::SpindleOff;
  case MRole::ToolChange: return Z32Step::Tool;
  case MRole::Coolant1:
  case MRole::Coolant2:
  case MRole::CoolantOff: return Z32Step::Other;
  case MRole::Plain: return special ? Z32Step::Special : Z32Step::Other;
  default: return Z32Step::Final;
  }
}

/// MA/MB/MC (seed 004, SPEC §4.6): the integer sent to the PLC. Decimals are dropped, a
/// negative sign adds 8000 to the magnitude (-0 stays 0), and the result is clamped to 9999.
constexpr int kAuxSignOffset = 8000;
constexpr int kAuxMax = 9999;
inline int auxSent(double programmed, bool* clamped = nullptr) {
  const bool negative = programmed < 0;
  const double mag = negative ? -programmed : programmed;
  // truncate toward zero without overflowing an int (values have at most 9 digits anyway)
  const double whole = !(mag < 1e9) ? 1e9 : static_cast<double>(static_cast<int64_t>(mag)); // NaN: clamped
  double sent = whole == 0 ? 0 : (negative ? whole + kAuxSignOffset : whole);
  const bool over = sent > kAuxMax;
  if (clamped) *clamped = over;
  return over ? kAuxMax : static_cast<int>(sent);
}

} // namespace iso::lang
