//! @file Arcs.cpp
//! @brief G2/G3 blocks: axes and centre words of the plane, CR, and the constant geometry.
#include "frontend/checks/FileChecker.h"

#include <bit>
#include <cmath>
#include <optional>

#include "lang/Limits.h"

namespace iso::frontend::checks {

using diag::Msg;

void FileChecker::checkArc(const Stmt& s, const BlockFacts& b) {
  const Item* const* centre = b.arcCentre;
  const Item* cr = b.cr;
  // plane axes: G17 X Y (I J), G18 Z X (K I), G19 Y Z (J K)
  const lang::PlaneAxes pa = lang::planeAxes(modal_.plane);
  const char p = pa.p, q = pa.q;
  const int ci = pa.pWord, cj = pa.qWord;
  bool reported = false;
  for (uint32_t m = b.moveMask; m != 0; m &= m - 1) {
    const int a = std::countr_zero(m);
    const Item& x = *b.moves[a];
    char name = static_cast<char>('A' + a);
    if (name != p && name != q) {
      diags_.report(Msg::ArcAxisOutsidePlane, x.loc, x.len, name, modal_.plane, p, q);
      reported = true;
    }
    if (x.mode == MoveMode::Posa) {
      diags_.report(Msg::ArcPosa, x.loc, x.len);
      reported = true;
    }
  }
  if (b.firstFa) {
    diags_.report(Msg::ArcFa, b.firstFa->loc, b.firstFa->len);
    reported = true;
  }
  for (int c = 0; c < 3; ++c) {
    if (centre[c] && c != ci && c != cj) {
      diags_.report(Msg::ArcCentreWordPlane, centre[c]->loc, centre[c]->len, "IJK"[c], modal_.plane);
      reported = true;
    }
  }
  bool ijk = centre[ci] || centre[cj];
  if (!ijk && !cr) {
    diags_.report(Msg::ArcWithoutCentre, s.loc, 1, modal_.motion);
    reported = true;
  }
  if (ijk && cr) {
    diags_.report(Msg::ArcCentreAndRadius, cr->loc, cr->len);
    reported = true;
  }
  // constant geometry check
  auto startP = modal_.pos[static_cast<size_t>(p - 'A')];
  auto startQ = modal_.pos[static_cast<size_t>(q - 'A')];
  auto endOf = [&](char axis, std::optional<double> start) -> std::optional<double> {
    const Item* m = b.move(axis - 'A');
    if (!m) return start;
    auto v = constValue(f_, m->value);
    if (!v) return std::nullopt;
    if (!modal_.incremental) return v;
    if (!start) return std::nullopt;
    return *start + *v;
  };
  auto endP = endOf(p, startP);
  auto endQ = endOf(q, startQ);
  if (!reported && startP && startQ && endP && endQ) {
    if (cr) {
      auto r = constValue(f_, cr->value);
      if (r && std::abs(*endP - *startP) < 1e-9 && std::abs(*endQ - *startQ) < 1e-9)
        diags_.report(Msg::ArcFullCircleCr, cr->loc, cr->len);
      else if (r) {
        double chord = std::hypot(*endP - *startP, *endQ - *startQ);
        if (chord > 2 * std::abs(*r) + lang::kArcTolerance)
          diags_.report(Msg::ArcRadiusTooSmall, cr->loc, cr->len, std::abs(*r), chord);
      }
    } else {
      auto ip = centre[ci] ? constValue(f_, centre[ci]->value) : std::optional<double>(0.0);
      auto iq = centre[cj] ? constValue(f_, centre[cj]->value) : std::optional<double>(0.0);
      if (ip && iq) {
        double cp = *startP + *ip, cq = *startQ + *iq;
        double r0 = std::hypot(*startP - cp, *startQ - cq);
        double r1 = std::hypot(*endP - cp, *endQ - cq);
        if (std::abs(r1 - r0) > lang::kArcTolerance) {
          const Item* c = centre[ci] ? centre[ci] : centre[cj];
          diags_.report(Msg::ArcEndOffCircle, c->loc, c->len, r0, r1, std::abs(r1 - r0), lang::kArcTolerance);
        }
      }
    }
  }
  modal_.pos[static_cast<size_t>(p - 'A')] = endP;
  modal_.pos[static_cast<size_t>(q - 'A')] = endQ;
  if (reported) // a malformed arc: where its axes end is unknown; no follow-on geometry errors
    for (int a = 0; a < 26; ++a)
      if (b.move(a) || a == p - 'A' || a == q - 'A') modal_.pos[static_cast<size_t>(a)] = std::nullopt;
}

} // namespace iso::frontend::checks
