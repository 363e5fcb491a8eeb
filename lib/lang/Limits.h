//! @file Limits.h
//! @brief The numeric limits of the language and of its machine model (SPEC §1–§5), each
//!        written once. Header-only, no dependencies.
#pragma once

#include <cstdint>

namespace iso::lang {

/// R parameters R1..R2880 (SPEC §3.1); R0 is reserved for the system.
constexpr int kMinRIndex = 1;
constexpr int kMaxRIndex = 2880;
constexpr bool isRIndex(double v) { return v >= kMinRIndex && v <= kMaxRIndex; }

/// z32 (SPEC §4.7): PAR[0..999], PAL[0..255], origins O0..O99 (O0: none), M numbers of two digits.
constexpr int kMaxParIndex = 999;
constexpr int kMaxPalIndex = 255;
constexpr int kMaxOrigin = 99;
constexpr int kMaxMNumberZ32 = 99;

/// PLC markers $aa_marker[0..200] (SPEC §3.3).
constexpr int kMaxMarker = 200;

/// Digital inputs and outputs assumed by isolint when no machine file is given (indices 0..255).
constexpr int kDefaultIoCount = 256;

/// A machine has 1..9 axes (SPEC §5.1).
constexpr int kMaxMachineAxes = 9;

/// An image's axis table holds at most 16 axes: a Move descriptor's axis is a nibble.
constexpr unsigned kMaxImageAxes = 16;

/// A logical line holds at most 240 characters after `$` joins (SPEC §2, E102).
constexpr uint32_t kMaxLineLength = 240;

/// A number holds at most 9 significant digits (SPEC §2, E101).
constexpr int kMaxSignificantDigits = 9;

/// Up to 3 chained WHENs (SPEC §4.4, E212).
constexpr int kMaxWhenChain = 3;

/// The largest G number a program may write (G<n>); larger ones are read as not whole.
constexpr int32_t kMaxGNumber = 999'999;

/// An arc's end may miss its circle (or a CR chord its diameter) by this much, in mm (SPEC §5.2,
/// E311 at lint time, a run-time error in the simulator).
constexpr double kArcTolerance = 0.01;

} // namespace iso::lang
