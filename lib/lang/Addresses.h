//! @file Addresses.h
//! @brief The addresses of each dialect (SPEC §2, §4.6): the letters a word may start with
//!        besides the machine's axis names. Header-only, no dependencies.
#pragma once

#include <string>
#include <string_view>

#include "lang/MFunctions.h"
#include "support/CaseFold.h"

namespace iso::lang {

/// Fixed single-letter addresses of both dialects, never axis names: G M N F R I J K.
constexpr std::string_view kFixedAddresses = "GMNFRIJK";
/// Single-letter addresses that dialect z32 adds: S (spindle speed), T (tool).
constexpr std::string_view kZ32Addresses = "ST";
/// Dialect z32's origin address O (O<n>: a number, no expression).
constexpr char kOriginAddress = 'O';
/// The arc radius CR (both dialects).
constexpr std::string_view kRadiusAddress = "CR";
/// Dialect z32's auxiliary functions MA MB MC: M followed by one of these letters.
constexpr std::string_view kAuxLetters = "ABC";
/// Dialect z32's actual and next tool TA TB: T followed by one of these letters.
constexpr std::string_view kToolLetters = "AB";

constexpr bool contains(std::string_view set, char c) { return c != 0 && set.find(c) != std::string_view::npos; }

/// A fixed address of both dialects (upper-case letter).
constexpr bool isFixedAddress(char c) { return contains(kFixedAddresses, c); }
/// A fixed address of dialect `d`: never an axis name there.
constexpr bool isFixedAddress(char c, Dialect d) {
  return isFixedAddress(c) || (d == Dialect::Z32 && (contains(kZ32Addresses, c) || c == kOriginAddress));
}
/// `a b` (upper-case) is a two-letter address of dialect `d`: CR, and z32's MA MB MC TA TB.
constexpr bool isTwoLetterAddress(char a, char b, Dialect d) {
  if (a == kRadiusAddress[0] && b == kRadiusAddress[1]) return true;
  return d == Dialect::Z32 && ((a == 'M' && contains(kAuxLetters, b)) || (a == 'T' && contains(kToolLetters, b)));
}
/// `a` (upper-case) is the first letter of a two-letter address of dialect `d`.
constexpr bool startsTwoLetterAddress(char a, Dialect d) {
  return a == kRadiusAddress[0] || (d == Dialect::Z32 && (a == 'M' || a == 'T'));
}
/// `name` (any case) spells a z32 word address that takes `=expr`: S T MA MB MC TA TB (not O:
/// an origin is a number).
constexpr bool isZ32WordName(std::string_view name) {
  if (name.size() == 1)
    return name[0] != 'O' && name[0] != 'o' && contains(kZ32Addresses, support::upperAscii(name[0]));
  return name.size() == 2 &&
         isTwoLetterAddress(support::upperAscii(name[0]), support::upperAscii(name[1]), Dialect::Z32) &&
         support::upperAscii(name[0]) != 'C';
}

/// Dialect z32's two-letter program-flow words: GO (GO jumps, GOP calls) and KG.
constexpr std::string_view kZ32FlowWords[] = {"GO", "KG"};

/// `name` (upper case, one or two letters) is an address or a flow word of dialect z32, so no
/// user parameter may be named after it: G M N F R I J K S T O, CR MA MB MC TA TB, GO KG.
constexpr bool isZ32AddressName(std::string_view name) {
  if (name.size() == 1) return isFixedAddress(name[0], Dialect::Z32);
  if (name.size() != 2) return false;
  if (isTwoLetterAddress(name[0], name[1], Dialect::Z32)) return true;
  for (std::string_view w : kZ32FlowWords)
    if (name == w) return true;
  return false;
}

/// The letters of `set` separated by spaces ("G M N F R I J K"), for messages.
inline std::string spacedLetters(std::string_view set) {
  std::string s;
  for (char c : set) {
    if (!s.empty()) s.push_back(' ');
    s.push_back(c);
  }
  return s;
}

} // namespace iso::lang
