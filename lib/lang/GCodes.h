//! @file GCodes.h
//! @brief The G functions (SPEC §4.2) from GCodes.def: number, modal group, the value each
//!        gives its modal field, the initial state, the text editors show. Header-only, no
//!        dependencies.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string_view>

#include "lang/Axes.h"

namespace iso::lang {

/// Modal groups; the first four index per-line conflict tables (W401).
enum class GGroup : uint8_t { Motion, Distance, Path, Plane, None };
constexpr size_t kModalGroupCount = 4;

enum class GCode : uint8_t {
#define ISO_G(code, Name, Group, modal, initial, doc) Name,
#include "lang/GCodes.def"
};

struct GInfo {
  int code;
  GCode id;
  GGroup group;
  int modal;
  bool initial;
  std::string_view doc; ///< what the code does, for editors (Markdown)
};

constexpr GInfo kGCodes[] = {
#define ISO_G(code, Name, Group, modal, initial, doc) {code, GCode::Name, GGroup::Group, modal, initial != 0, doc},
#include "lang/GCodes.def"
};
constexpr size_t kGCodeCount = sizeof(kGCodes) / sizeof(kGCodes[0]);

constexpr const GInfo& gInfo(GCode g) { return kGCodes[static_cast<size_t>(g)]; }
constexpr int gNumber(GCode g) { return gInfo(g).code; }
constexpr GGroup gGroup(GCode g) { return gInfo(g).group; }
/// The value G`g` gives its group's modal field (motion 0..3, incremental, continuous, plane).
constexpr int gModal(GCode g) { return gInfo(g).modal; }

/// A group's name as editors show it; the one code of GGroup::None is the dwell.
constexpr std::string_view gGroupName(GGroup group) {
  switch (group) {
  case GGroup::Motion: return "motion";
  case GGroup::Distance: return "distance";
  case GGroup::Path: return "path";
  case GGroup::Plane: return "plane";
  case GGroup::None: break;
  }
  return "dwell";
}

/// The G function numbered `code`, if the language has it.
constexpr std::optional<GCode> findG(int64_t code) {
  for (const GInfo& g : kGCodes)
    if (g.code == code) return g.id;
  return std::nullopt;
}
/// The code of `group` in force at program start.
constexpr GCode initialG(GGroup group) {
  for (const GInfo& g : kGCodes)
    if (g.group == group && g.initial) return g.id;
  return GCode::G0;
}

/// The dwell G04: non-modal, F is the time.
constexpr GCode kDwell = GCode::G4;
constexpr bool isDwell(int64_t code) { return code == gNumber(kDwell); }

/// The modal state the G groups describe, in the form the checker and the simulator keep.
constexpr int kInitialMotion = gModal(initialG(GGroup::Motion));
constexpr int kInitialPlane = gModal(initialG(GGroup::Plane));
constexpr bool kInitialIncremental = gModal(initialG(GGroup::Distance)) != 0;
constexpr bool kInitialContinuous = gModal(initialG(GGroup::Path)) != 0;
/// Planes by their G number's modal value.
constexpr int kPlaneXY = gModal(GCode::G17);
constexpr int kPlaneZX = gModal(GCode::G18);
constexpr int kPlaneYZ = gModal(GCode::G19);
/// Motion modes by modal value.
constexpr int kMotionRapid = gModal(GCode::G0);
constexpr int kMotionLinear = gModal(GCode::G1);
constexpr int kMotionArcCw = gModal(GCode::G2);
constexpr int kMotionArcCcw = gModal(GCode::G3);

/// True for the circular motions G02/G03.
constexpr bool isArc(int motion) { return motion == kMotionArcCw || motion == kMotionArcCcw; }

/// The two axes of a plane and the arc-centre words that go with them (SPEC §5.2):
/// G17 X Y (I J), G18 Z X (K I), G19 Y Z (J K). Words by index: 0 I, 1 J, 2 K.
struct PlaneAxes {
  char p, q;        ///< first and second axis of the plane
  int pWord, qWord; ///< the centre word of each (0 I, 1 J, 2 K)
};
constexpr PlaneAxes planeAxes(int plane) {
  if (plane == kPlaneZX) return {kDefaultAxisLetters[2], kDefaultAxisLetters[0], 2, 0};
  if (plane == kPlaneYZ) return {kDefaultAxisLetters[1], kDefaultAxisLetters[2], 1, 2};
  return {kDefaultAxisLetters[0], kDefaultAxisLetters[1], 0, 1};
}

} // namespace iso::lang
