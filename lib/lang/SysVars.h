//! @file SysVars.h
//! @brief The system variables (SPEC §3.3) from SysVars.def: spelling, aliases, whether they
//!        take an axis, are real-time, writable or machine data, their image number, and the
//!        texts editors show. Header-only, no dependencies.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string_view>

#include "support/CaseFold.h"

namespace iso::lang {

/// A system variable; the value is its number in the image.
enum class SysVar : uint8_t {
#define ISO_SYSVAR(Name, spelling, id, axis, realtime, writable, machinedata, doc, access) Name = id,
#include "lang/SysVars.def"
};

struct SysVarInfo {
  SysVar id;
  std::string_view name; ///< canonical spelling with '$'
  bool takesAxis;
  bool realTime;
  bool writable;
  bool machineData;
  std::string_view doc;    ///< what it holds, for editors (Markdown)
  std::string_view access; ///< how a program may use it, for editors
};

constexpr SysVarInfo kSysVars[] = {
#define ISO_SYSVAR(Name, spelling, id, axis, realtime, writable, machinedata, doc, access)                             \
  {SysVar::Name, spelling, axis != 0, realtime != 0, writable != 0, machinedata != 0, doc, access},
#include "lang/SysVars.def"
};
constexpr size_t kSysVarCount = sizeof(kSysVars) / sizeof(kSysVars[0]);

struct SysVarAlias {
  std::string_view name; ///< with '$'
  SysVar id;
};
constexpr SysVarAlias kSysVarAliases[] = {
#define ISO_SYSVAR_ALIAS(spelling, Name) {spelling, SysVar::Name},
#include "lang/SysVars.def"
};

/// The row of `v`; the rows are in image-number order (checked by a static_assert below).
constexpr const SysVarInfo& sysVarInfo(SysVar v) { return kSysVars[static_cast<size_t>(v)]; }
constexpr bool isSysVarId(uint64_t id) { return id < kSysVarCount; }

constexpr bool sysVarRowsInIdOrder() {
  for (size_t i = 0; i < kSysVarCount; ++i)
    if (static_cast<size_t>(kSysVars[i].id) != i) return false;
  return true;
}
static_assert(sysVarRowsInIdOrder(), "SysVars.def: the image numbers must be 0, 1, 2, ... in row order");

/// The variable spelled `name` ('$' included, any case); `alias` tells a W407 spelling.
struct SysVarLookup {
  SysVar id;
  bool alias;
};
constexpr std::optional<SysVarLookup> findSysVar(std::string_view name) {
  for (const SysVarInfo& v : kSysVars)
    if (support::iequals(name, v.name)) return SysVarLookup{v.id, false};
  for (const SysVarAlias& a : kSysVarAliases)
    if (support::iequals(name, a.name)) return SysVarLookup{a.id, true};
  return std::nullopt;
}

} // namespace iso::lang
