//! @file Axes.h
//! @brief The axes of the built-in machine (SPEC §5.1): their letters, in machine order (which
//!        is also the order of the image's axis table and of the CSV trace columns).
#pragma once

#include <string_view>

namespace iso::lang {

/// The default machine's axes, in order: X Y Z A B C U V W.
constexpr std::string_view kDefaultAxisLetters = "XYZABCUVW";

/// The linear axes that span the planes G17/G18/G19, in the order of the arc-centre words I J K.
constexpr std::string_view kPlaneAxisLetters = kDefaultAxisLetters.substr(0, 3);

/// True when `c` (upper-case) is an axis of the default machine.
constexpr bool isDefaultAxis(char c) { return c != 0 && kDefaultAxisLetters.find(c) != std::string_view::npos; }

} // namespace iso::lang
