//! @file LexerInternal.h
//! @brief What the lexer's source files share (not part of the library's interface).
//!
//! The members of Lexer are defined in four files, cut along what they read: Lexer.cpp owns
//! the lexer proper (physical lines, the `$` continuation, next(), and every token: the fast
//! path for the words of a plain line, number scanning, names, system variables, strings,
//! operators); LexComments.cpp owns `( ... )` and `;` comments and the `isolint:` directives
//! they carry; LexNumbers.cpp finishes the numbers the scans do not (those of more than 9
//! digits, or on a line a `$` continues): the value past 15 digits, E101 and its fix-it;
//! TokenNames.cpp owns the texts of tokens and bytes that messages quote. The hot paths stay
//! in Lexer.cpp with their callers, and what several files need on them (the character
//! classes below, Lexer::peek, joinedOffset) is inline here or in Lexer.h: no call that was
//! inlined before the split became an out-of-line one.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "frontend/Lexer.h"
#include "lang/Limits.h"

namespace iso::frontend::lexer_detail {

// One table lookup per character class test (the lexer asks several per byte).
enum CharClass : uint8_t { kAlpha = 1, kDigit = 2, kUnderscore = 4, kSep = 8, kBlank = 16, kControl = 32 };
inline constexpr std::array<uint8_t, 256> kCharClass = [] {
  std::array<uint8_t, 256> t{};
  for (int c = 'A'; c <= 'Z'; ++c)
    t[static_cast<size_t>(c)] = t[static_cast<size_t>(c + 32)] = kAlpha;
  for (int c = '0'; c <= '9'; ++c)
    t[static_cast<size_t>(c)] = kDigit;
  t['_'] = kUnderscore;
  t['.'] = t[','] = kSep;
  t[' '] = t['\t'] = kBlank;
  for (int c = 0; c < 0x20; ++c)
    if (c != '\t') t[static_cast<size_t>(c)] = kControl;
  t[0x7F] = kControl;
  return t;
}();
inline bool is(char c, unsigned mask) { return (kCharClass[static_cast<unsigned char>(c)] & mask) != 0; }
inline bool isAlpha(char c) { return is(c, kAlpha); }
inline bool isDigit(char c) { return is(c, kDigit); }
inline bool isIdentStart(char c) { return is(c, kAlpha | kUnderscore); }
inline bool isIdentChar(char c) { return is(c, kAlpha | kDigit | kUnderscore); }
inline bool isSep(char c) { return is(c, kSep); }
inline bool isBlank(char c) { return is(c, kBlank); }
inline bool isControl(unsigned char c) { return (kCharClass[c] & kControl) != 0; }
inline constexpr auto kDigits = static_cast<size_t>(lang::kMaxSignificantDigits);
/// Numbers of up to this many digits are exact integers in a double (< 2^53), as is 10^15.
inline constexpr size_t kExactDigits = 15;

// Up to kExactDigits digits (so at most as many decimals), a mantissa and 10^fraction are exact doubles and one
// division rounds correctly: the same double as from_chars (Clinger's fast path).
inline constexpr double kPow10[kExactDigits + 1] = {1e0, 1e1, 1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                                    1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15};

} // namespace iso::frontend::lexer_detail

namespace iso::frontend {

// Defined here, inline as before the split, for next() and lexComment (LexComments.cpp).
inline uint32_t Lexer::joinedOffset(const Cursor& c) const {
  return joinedBefore_[c.line - firstLine_] + (c.p - c.lineStart);
}

/// What a number's scan found (Lexer::lexNumber).
struct Lexer::NumberScan {
  bool sep = false;
  size_t digits = 0;     // integer and fraction digits together, for the 9-digit rule
  size_t leadZeros = 0;  // of those, the zeros before the first other digit
  uint64_t mantissa = 0; // the first kExactDigits digits as an integer
  uint32_t fraction = 0; // digits after the separator
  void digit(char ch) {
    if (digits == leadZeros && ch == '0') ++leadZeros;
    if (digits < lexer_detail::kExactDigits) mantissa = mantissa * 10 + static_cast<uint64_t>(ch - '0');
    ++digits;
    if (sep) ++fraction;
  }
};

} // namespace iso::frontend
