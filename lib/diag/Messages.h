//! @file Messages.h
//! @brief The message table (`Messages.def`): every text a diagnostic, its notes or its fix-its
//!        show, one entry per variant, grouped by code. Call sites name a `Msg` and pass the
//!        format arguments; the code comes from the table, and the arguments are checked
//!        against the format string at compile time (count and types).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <type_traits>
#include <utility>

#include <fmt/format.h>

#include "diag/Code.h"

namespace iso::diag {

/// Every message variant of Messages.def, in table order.
enum class Msg : uint16_t {
#define MSG(e, code, format) e,
#include "diag/Messages.def"
  Count_
};

struct MsgInfo {
  Code code;          ///< the diagnostic code this text belongs to
  const char* name;   ///< "LabelTwice" (the enumerator, for tests)
  const char* format; ///< an fmt format string
};

inline constexpr MsgInfo kMessages[] = {
#define MSG(e, code, format) {Code::code, #e, format},
#include "diag/Messages.def"
};
static_assert(sizeof(kMessages) / sizeof(kMessages[0]) == static_cast<size_t>(Msg::Count_));

constexpr size_t msgCount() { return static_cast<size_t>(Msg::Count_); }
constexpr const MsgInfo& info(Msg m) { return kMessages[static_cast<size_t>(m)]; }
constexpr Code codeOf(Msg m) { return info(m).code; }

/// The number of replacement fields ({} or {:spec}) of a format string; "{{" and "}}" are
/// literal braces.
constexpr size_t placeholderCount(const char* s) {
  size_t n = 0;
  for (; *s != '\0'; ++s) {
    if (*s == '{') {
      if (s[1] == '{') {
        ++s;
        continue;
      }
      ++n;
    } else if (*s == '}' && s[1] == '}') {
      ++s;
    }
  }
  return n;
}

/// A `Msg` whose format string takes exactly the arguments `A...`: constructed only at compile
/// time, where fmt checks the format string against the argument types and this checks that
/// every argument has a place.
template <class... A> struct MsgRef {
  Msg msg;
  consteval MsgRef(Msg m) : msg(m) { // NOLINT(google-explicit-constructor): call sites name a Msg
#if !defined(__clang__)
    // GCC checks the types here; clang 14 (the fuzz build) rejects fmt's consteval check
    // inside another consteval function, so with clang only the count below is checked.
    [[maybe_unused]] fmt::format_string<A...> checked(info(m).format);
#endif
    if (placeholderCount(info(m).format) != sizeof...(A)) throw "message arguments do not match its format string";
  }
  constexpr Code code() const { return codeOf(msg); }
  constexpr const char* format() const { return info(msg).format; }
};

/// The text of `m` with its arguments.
template <class... A> std::string message(MsgRef<std::type_identity_t<A>...> m, A&&... args) {
  return fmt::format(fmt::runtime(m.format()), std::forward<A>(args)...);
}

} // namespace iso::diag
