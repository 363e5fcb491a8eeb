//! @file Unsupported.h
//! @brief Lookups in Unsupported.def: the constructs of other dialects that E110 names, and
//!        the SIDAC way. Header-only, no dependencies.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "support/CaseFold.h"

namespace iso::lang {

struct UnsupportedInfo {
  std::string_view name;        ///< the name, prefix or "" (G/M codes, addresses)
  std::string_view construct;   ///< what it is ("WHILE loops")
  std::string_view way;         ///< the SIDAC way, or ""
  std::string_view replacement; ///< the statement that replaces it one for one, or ""

  /// "construct; way", or the construct alone.
  std::string text() const {
    std::string s(construct);
    if (!way.empty()) {
      s += "; ";
      s += way;
    }
    return s;
  }
};

constexpr UnsupportedInfo kUnsupportedNames[] = {
#define ISO_UNSUPPORTED(name, construct, way, replacement) {name, construct, way, replacement},
#include "lang/Unsupported.def"
};
constexpr UnsupportedInfo kUnsupportedPrefixes[] = {
#define ISO_UNSUPPORTED_PREFIX(prefix, construct) {prefix, construct, "", ""},
#include "lang/Unsupported.def"
};
struct UnsupportedCode {
  int code;
  UnsupportedInfo info;
};
constexpr UnsupportedCode kUnsupportedG[] = {
#define ISO_UNSUPPORTED_G(code, construct, way) {code, {"", construct, way, ""}},
#include "lang/Unsupported.def"
};
constexpr UnsupportedCode kUnsupportedM[] = {
#define ISO_UNSUPPORTED_M(code, construct, way) {code, {"", construct, way, ""}},
#include "lang/Unsupported.def"
};
struct UnsupportedAddress {
  char letter;
  UnsupportedInfo info;
};
constexpr UnsupportedAddress kUnsupportedAddresses[] = {
#define ISO_UNSUPPORTED_ADDRESS(letter, construct, way) {letter, {"", construct, way, ""}},
#include "lang/Unsupported.def"
};
constexpr std::string_view kUnsupportedProcAttributes[] = {
#define ISO_UNSUPPORTED_PROC_ATTRIBUTE(name) name,
#include "lang/Unsupported.def"
};

/// The construct a whole name spells (RET, STOPRE, SIN), any case.
constexpr const UnsupportedInfo* findUnsupportedName(std::string_view name) {
  for (const UnsupportedInfo& u : kUnsupportedNames)
    if (support::iequals(name, u.name)) return &u;
  return nullptr;
}
/// The construct a name starts with (CYCLE81, POCKET3), any case.
constexpr const UnsupportedInfo* findUnsupportedPrefix(std::string_view name) {
  for (const UnsupportedInfo& u : kUnsupportedPrefixes)
    if (name.size() >= u.name.size() && support::iequals(name.substr(0, u.name.size()), u.name)) return &u;
  return nullptr;
}
/// A G code of another dialect (G54, G81).
constexpr const UnsupportedInfo* findUnsupportedG(int64_t code) {
  for (const UnsupportedCode& u : kUnsupportedG)
    if (u.code == code) return &u.info;
  return nullptr;
}
/// An M function of another dialect (M98, M99).
constexpr const UnsupportedInfo* findUnsupportedM(int64_t code) {
  for (const UnsupportedCode& u : kUnsupportedM)
    if (u.code == code) return &u.info;
  return nullptr;
}
/// An address letter of another dialect (upper-case).
constexpr const UnsupportedInfo* findUnsupportedAddress(char letter) {
  for (const UnsupportedAddress& u : kUnsupportedAddresses)
    if (u.letter == letter) return &u.info;
  return nullptr;
}
/// A Sinumerik attribute after PROC name SAVE (DISPLOF), any case.
constexpr bool isUnsupportedProcAttribute(std::string_view name) {
  for (std::string_view a : kUnsupportedProcAttributes)
    if (support::iequals(name, a)) return true;
  return false;
}

} // namespace iso::lang
