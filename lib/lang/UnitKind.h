//! @file UnitKind.h
//! @brief The kinds of program unit (SPEC §1). The values are also the image's encoding.
#pragma once

#include <cstdint>

namespace iso::lang {

enum class UnitKind : uint8_t {
  Main = 0, ///< NAME.mpf, ends with M30
  Semi = 1, ///< NAME.mpf starting with SEMI "display name"
  Sub = 2,  ///< NAME.spf starting with PROC name SAVE, ends with M17
};

} // namespace iso::lang
