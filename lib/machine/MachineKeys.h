//! @file MachineKeys.h
//! @brief The machine-file keys of MachineKeys.def as typed rows: the helpers the table's
//!        columns are written with, and forEachKey, which the reader, the printer, the built-in
//!        machine and the tests walk the table with.
#pragma once

#include <map>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "lang/Axes.h"
#include "lang/Limits.h"
#include "lang/MFunctions.h"
#include "machine/Machine.h"

namespace iso::machine::keys {

/// The JSON type of a key's value (the schema's "type"; Enum: the schema lists the values).
enum class JsonType { String, Enum, Array, Number, Integer, Boolean, Object };

/// When the printer writes a key (IfSet: only when it is not at its default).
enum class Print { Always, IfZ32, IfSet };

/// When the reader reads a key: Late ones after every Early one of the same object.
enum class Read { Early, Late };

/// A bound of a value, or of the element or entry count of an array or object.
struct Bound {
  enum Kind { None, Above, AtLeast, AtMost };
  Kind kind = None;
  int value = 0;
};
inline constexpr Bound Any{};
constexpr Bound Above(int n) { return {Bound::Above, n}; }
constexpr Bound AtLeast(int n) { return {Bound::AtLeast, n}; }
constexpr Bound AtMost(int n) { return {Bound::AtMost, n}; }

/// The defaults (see MachineKeys.def).
template <class T> struct Given { T value; };
template <class T> struct Needed { T value; };
struct NoEntries {};
struct OtherKey {
  std::string_view key;
};
template <class T> constexpr Given<T> Is(T value) { return {value}; }
template <class T> constexpr Needed<T> Required(T value) { return {value}; }
inline constexpr NoEntries None{};
constexpr OtherKey FromKey(std::string_view key) { return {key}; }

template <class D> inline constexpr bool kIsRequired = false;
template <class T> inline constexpr bool kIsRequired<Needed<T>> = true;

// The bounds the table names.
inline constexpr int kMaxAxes = lang::kMaxMachineAxes;
inline constexpr int kMaxCount = 1'000'000; ///< counts (inputs, outputs, look-ahead): keeps allocations sane
inline constexpr int kMaxSpecial = lang::kMaxSpecialM;
inline constexpr std::string_view kBuiltinAxisLetters = lang::kDefaultAxisLetters;

/// One row of the table: the key of object O that fills the member `field` of type T.
template <class O, class T, class D> struct Key {
  const char* name;
  JsonType type;
  Bound min;
  Bound max;
  D def;
  T O::*field;
  Print print;
  Read read;
};

template <class O, class T, class D>
constexpr Key<O, T, D> makeKey(const char* name, JsonType type, Bound min, Bound max, D def, T O::*field, Print print,
                               Read read) {
  return {name, type, min, max, def, field, print, read};
}

/// The JSON type that a member of C++ type T holds.
template <class T> constexpr JsonType jsonTypeOf() {
  if constexpr (std::is_same_v<T, bool>) {
    return JsonType::Boolean;
  } else if constexpr (std::is_same_v<T, int>) {
    return JsonType::Integer;
  } else if constexpr (std::is_same_v<T, double>) {
    return JsonType::Number;
  } else if constexpr (std::is_same_v<T, std::string> || std::is_same_v<T, char>) {
    return JsonType::String;
  } else if constexpr (std::is_same_v<T, Dialect>) {
    return JsonType::Enum;
  } else if constexpr (std::is_same_v<T, std::vector<Axis>> || std::is_same_v<T, std::vector<std::string>> ||
                       std::is_same_v<T, std::vector<Zone>>) {
    return JsonType::Array;
  } else {
    return JsonType::Object; // the tables by number or index
  }
}

#define MACHINE_KEY(Object, key, Type, Min, Max, Default, Field, PrintWhen, ReadWhen)                                  \
  static_assert(jsonTypeOf<decltype(Object::Field)>() == JsonType::Type,                                               \
                "MachineKeys.def: the type of " #key " does not fit " #Object "::" #Field);
#include "machine/MachineKeys.def"
#undef MACHINE_KEY

/// Calls visit(key) for every row of object O (Machine, Axis, MSequence), in table order.
template <class O, class F> void forEachKey(F&& visit) {
#define MACHINE_KEY(Object, key, Type, Min, Max, Default, Field, PrintWhen, ReadWhen)                                  \
  if constexpr (std::is_same_v<O, Object>) {                                                                           \
    visit(makeKey(#key, JsonType::Type, Min, Max, Default, &Object::Field, Print::PrintWhen, Read::ReadWhen));         \
  }
#include "machine/MachineKeys.def"
#undef MACHINE_KEY
}

/// The keys of object O, in table order.
template <class O> const std::vector<std::string_view>& keyNames() {
  static const std::vector<std::string_view> names = [] {
    std::vector<std::string_view> out;
    forEachKey<O>([&](const auto& key) { out.push_back(key.name); });
    return out;
  }();
  return names;
}

} // namespace iso::machine::keys
