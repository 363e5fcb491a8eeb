//! @file Blocks.cpp
//! @brief The values of each statement in the modal state they run in: G groups, moves, feeds,
//!        arc words, M functions, assignments, dwell, soft limits (the E3xx and W4xx of a block).
#include "frontend/checks/FileChecker.h"

#include <bit>
#include <cmath>
#include <optional>
#include <string>

#include <fmt/format.h>

#include "lang/Limits.h"

namespace iso::frontend::checks {

// The members marked inline run for every item of every line and only this file calls them:
// inline keeps them inlined, as they were when the class was defined in one piece.

using diag::Msg;

namespace {

/// A target within this distance (mm or deg) of a soft limit counts as on it (SPEC §4.3).
constexpr double kLimitTolerance = 1e-9;

} // namespace

inline void FileChecker::checkExpr(ExprId e, bool wholeRAssignRhs) {
  if (e == kNoExpr) return;
  const Expr& x = f_.expr(e);
  switch (x.kind) {
  case ExprKind::Binary:
    if (static_cast<BinOp>(x.op) == BinOp::Div) {
      auto b = constValue(f_, x.b);
      if (b && *b == 0) {
        const Expr& bx = f_.expr(x.b);
        diags_.report(Msg::DivZero, bx.loc, bx.len);
      }
    }
    break;
  case ExprKind::SysAxis:
    if (!axisOf(x.axis)) diags_.report(Msg::MachineNoAxis, x.loc, x.len, x.axis);
    if (sysVarIsMachineData(x.sysvar) && !wholeRAssignRhs)
      diags_.report(Msg::SysvarContext, x.loc, x.len, sysVarName(x.sysvar), sysVarName(x.sysvar), x.axis);
    break;
  case ExprKind::SysIndex: checkIoIndex(x.sysvar, x.a); break;
  case ExprKind::RIndirect: {
    auto v = constValue(f_, x.a);
    if (v && (*v != std::floor(*v) || !lang::isRIndex(*v)))
      diags_.report(Msg::RConstOutside, x.loc, x.len, *v, lang::kMinRIndex, lang::kMaxRIndex);
    break;
  }
  default: break;
  }
  checkExpr(x.a, false);
  checkExpr(x.b, false);
}

inline void FileChecker::checkIoIndex(SysVar v, ExprId idx) {
  auto c = constValue(f_, idx);
  if (!c) return;
  int hi = v == SysVar::AaMarker ? lang::kMaxMarker
           : v == SysVar::AaIn   ? (opts_.machine ? opts_.machine->numInputs : lang::kDefaultIoCount) - 1
                                 : (opts_.machine ? opts_.machine->numOutputs : lang::kDefaultIoCount) - 1;
  if (*c != std::floor(*c) || *c < 0 || *c > hi) {
    const Expr& x = f_.expr(idx);
    if (v == SysVar::AaMarker)
      diags_.report(Msg::IoIndexMarker, x.loc, x.len, *c, hi);
    else if (v == SysVar::AaIn)
      diags_.report(Msg::IoIndexInput, x.loc, x.len, *c, hi);
    else
      diags_.report(Msg::IoIndexOutput, x.loc, x.len, *c, hi);
  }
}

/// The modal effect of G`g` (SPEC §4.2); the path group (G60/G64) is not tracked here.
inline void FileChecker::applyG(lang::GCode g) {
  switch (lang::gGroup(g)) {
  case lang::GGroup::Motion: modal_.motion = lang::gModal(g); break;
  case lang::GGroup::Distance: modal_.incremental = lang::gModal(g) != 0; break;
  case lang::GGroup::Plane: modal_.plane = lang::gModal(g); break;
  case lang::GGroup::Path:
  case lang::GGroup::None: break;
  }
}

/// A block line with an error keeps its valid items: only their modal effects count (no
/// checks of the block as a whole, which would be follow-ups of the error).
inline void FileChecker::applyPartialBlock(const Stmt& s) {
  const Item* it = f_.itemsOf(s);
  bool dwell = hasG4(s);
  for (uint32_t k = 0; k < s.itemCount; ++k) {
    const Item& x = it[k];
    if (x.kind == ItemKind::G) {
      if (auto g = lang::findG(x.code)) applyG(*g);
    } else if (x.kind == ItemKind::Feed && !dwell) {
      modal_.feedSet = true;
      auto fv = constValue(f_, x.value);
      modal_.feedNotPositive = fv && *fv <= 0;
    }
  }
  invalidatePositions();
}

inline void FileChecker::blockG(BlockFacts& b, const Item& x) {
  const auto g = lang::findG(x.code);
  if (!g) return; // unknown: E310 already
  applyG(*g);
  if (*g == lang::kDwell) b.dwell = true;
  const auto group = static_cast<size_t>(lang::gGroup(*g));
  if (group >= lang::kModalGroupCount) return;
  if (b.gByGroup[group]) diags_.report(Msg::GConflict, x.loc, x.len, b.gByGroup[group]->code, x.code, x.code);
  b.gByGroup[group] = &x;
}

inline void FileChecker::blockMove(BlockFacts& b, const Item& x) {
  int a = x.axis - 'A';
  if (a < 0 || a >= 26) return;
  if (!b.firstMove) b.firstMove = &x;
  if (!axisOf(x.axis)) {
    diags_.report(Msg::MachineNoAxis, x.loc, x.len, x.axis);
  }
  if (b.move(a)) {
    auto& d = diags_.report(Msg::AxisTwice, x.loc, x.len, x.axis);
    d.note(Msg::AxisTwiceNote, b.moves[a]->loc);
  } else {
    b.moves[a] = &x;
    b.moveMask |= uint32_t{1} << a;
    ++b.moveCount;
  }
  (x.mode == MoveMode::Posa ? b.anyPosa : b.anyBlocking) = true;
  checkExpr(x.value, false);
}

inline void FileChecker::blockFeed(BlockFacts& b, const Stmt& s, const Item& x) {
  if (b.dwell || hasG4(s)) { // in a G04 line F is only the dwell time (SPEC §4.2)
    b.dwellF = &x;
  } else {
    modal_.feedSet = true;
    auto fv = constValue(f_, x.value);
    modal_.feedNotPositive = fv && *fv <= 0;
    const machine::Axis* fastest = fastestAxis();
    modal_.highFeed = fv && fastest && *fv > fastest->maxVelocity ? *fv : 0;
    const Expr& vx = f_.expr(x.value); // F=1000: the word up to the end of its value
    modal_.highFeedLoc = x.loc;
    modal_.highFeedLen = vx.loc.line == x.loc.line && vx.loc.col >= x.loc.col ? vx.loc.col + vx.len - x.loc.col : x.len;
  }
  checkExpr(x.value, false);
}

inline void FileChecker::blockAxisFeed(BlockFacts& b, const Item& x) {
  b.anyFa = true;
  if (!b.firstFa) b.firstFa = &x;
  if (x.axis >= 'A' && x.axis <= 'Z') {
    const int a = x.axis - 'A';
    if (b.axisFeedMask >> a & 1u) {
      auto& d = diags_.report(Msg::FaTwice, x.loc, x.len, x.axis);
      d.note(Msg::FaTwiceNote, b.axisFeeds[a]->loc);
    } else {
      b.axisFeeds[a] = &x;
      b.axisFeedMask |= uint32_t{1} << a;
    }
  }
  if (!axisOf(x.axis)) diags_.report(Msg::MachineNoAxis, x.loc, x.len, x.axis);
  checkExpr(x.value, false);
}

inline void FileChecker::blockArcWord(BlockFacts& b, const Item& x) {
  const int w = x.kind == ItemKind::ArcI ? 0 : x.kind == ItemKind::ArcJ ? 1 : x.kind == ItemKind::ArcK ? 2 : 3;
  const Item*& slot = w < 3 ? b.arcCentre[w] : b.cr;
  if (slot) {
    auto& d = diags_.report(Msg::ArcWordTwice, x.loc, x.len, w < 3 ? std::string(1, "IJK"[w]) : "CR");
    d.note(Msg::ArcWordTwiceNote, slot->loc);
  } else {
    slot = &x;
  }
  checkExpr(x.value, false);
}

inline void FileChecker::blockM(BlockFacts& b, const Item& x) {
  const lang::MRole role = lang::mRole(x.code, opts_.dialect);
  bool isEnd = !x.nb && lang::isFinal(role);
  // I501 is about M functions that run before the motion; M0/M17/M30 run after it (§4.5),
  // and in z32 M19 M5 M6 too, while a special M ends the line (W415 instead).
  bool runsFirst = !isEnd && (!isZ32() || x.nb ||
                              (lang::z32Step(x.code, opts_.specialM(x.code) != nullptr) == lang::Z32Step::Other) ||
                              lang::z32Step(x.code, false) == lang::Z32Step::Spindle);
  if (!b.firstM && runsFirst) b.firstM = &x;
  if (!isEnd) return;
  if (b.endM) diags_.report(Msg::TwoEndFunctions, x.loc, x.len, b.endM->code, x.code);
  b.endM = &x;
}

inline void FileChecker::blockAssign(const Item& x) {
  if (x.kind == ItemKind::AssignR) {
    const Expr& t = f_.expr(x.target);
    if (t.kind == ExprKind::RIndirect) checkExpr(x.target, false);
    const Expr& v = f_.expr(x.value);
    bool whole = v.kind == ExprKind::SysAxis && sysVarIsMachineData(v.sysvar) && !v.paren;
    checkExpr(x.value, whole);
    return;
  }
  checkIoIndex(x.sysvar, x.target);
  checkExpr(x.target, false);
  checkExpr(x.value, false);
  auto v = constValue(f_, x.value);
  if (v && *v != 0 && *v != 1) {
    const Expr& vx = f_.expr(x.value);
    diags_.report(Msg::IoValue, vx.loc, vx.len, sysVarName(x.sysvar), *v);
  }
}

/// E304: Fa of an axis that does not move; E309: the dwell line.
inline void FileChecker::blockFaAndDwell(const BlockFacts& b, const Stmt& s) {
  const Item* it = f_.itemsOf(s);
  for (uint32_t k = 0; k < s.itemCount; ++k) {
    const Item& x = it[k];
    if (x.kind != ItemKind::AxisFeed) continue;
    int a = x.axis - 'A';
    if (a < 0 || a >= 26 || !b.move(a)) diags_.report(Msg::FaWithoutMove, x.loc, x.len, x.axis, x.axis);
  }
  if (!b.dwell) return;
  if (!b.dwellF) {
    const Item* g4 = nullptr;
    for (uint32_t k = 0; k < s.itemCount; ++k)
      if (it[k].kind == ItemKind::G && lang::isDwell(it[k].code)) g4 = &it[k];
    const int g = lang::gNumber(lang::kDwell);
    diags_.report(Msg::DwellWithoutTime, g4 ? g4->loc : s.loc, 3, g, g, g);
  } else {
    auto v = constValue(f_, b.dwellF->value);
    if (v && *v < 0) diags_.report(Msg::DwellNegative, b.dwellF->loc, b.dwellF->len);
  }
  if (b.moveCount > 0)
    diags_.report(Msg::DwellWithMotion, b.firstMove->loc, b.firstMove->len, lang::gNumber(lang::kDwell));
}

/// The machine's axis with the highest max_velocity (the first of equals); nullptr without a machine.
inline const machine::Axis* FileChecker::fastestAxis() const {
  if (!opts_.machine) return nullptr;
  const machine::Axis* best = nullptr;
  for (const auto& ax : opts_.machine->axes)
    if (!best || ax.maxVelocity > best->maxVelocity) best = &ax;
  return best;
}

/// W422 at the F word of modal_.highFeed, once: the first feed move (`move`) that runs at it.
inline void FileChecker::reportHighFeed(const Item& move) {
  const machine::Axis* fastest = fastestAxis();
  const double f = modal_.highFeed;
  modal_.highFeed = 0;
  if (!fastest) return;
  const double perSecond = std::round(f / 60 * 1000) / 1000;
  auto& d = diags_.report(Msg::FeedAboveMaxVelocity, modal_.highFeedLoc, modal_.highFeedLen, f, fastest->maxVelocity,
                          fastest->letter, f, perSecond);
  if (move.loc.line != modal_.highFeedLoc.line) d.note(Msg::FeedAboveMaxVelocityNote, move.loc);
}

/// W402 feed unset or <= 0, W403 Pos/Posa mixed, W414 Fa on G00 (a feed move of the block).
inline void FileChecker::blockFeedMove(const BlockFacts& b, const Stmt& s) {
  const Item* it = f_.itemsOf(s);
  if (!b.dwell && modal_.motion != lang::kMotionRapid) {
    bool allFa = true;
    for (uint32_t m = b.moveMask; m != 0 && allFa; m &= m - 1) {
      const int a = std::countr_zero(m);
      bool has = false;
      for (uint32_t k = 0; k < s.itemCount && !has; ++k)
        has = it[k].kind == ItemKind::AxisFeed && it[k].axis == 'A' + a;
      allFa = has;
    }
    const bool ownFeeds = modal_.motion == lang::kMotionLinear && allFa && b.moveCount > 0;
    const Item* first = b.firstMove;
    if (!ownFeeds && !modal_.feedSet) {
      diags_.report(Msg::FeedUnset, first ? first->loc : s.loc, first ? first->len : 1);
    } else if (!ownFeeds && modal_.feedNotPositive) {
      diags_.report(Msg::FeedNotPositive, first ? first->loc : s.loc, first ? first->len : 1);
    }
    if (!ownFeeds && first && modal_.highFeed > 0) reportHighFeed(*first);
    if (modal_.motion == lang::kMotionLinear && b.moveCount <= 3 && !b.anyFa && b.anyPosa && b.anyBlocking) {
      diags_.report(Msg::MixedBlocking, s.loc, 1);
    }
  }
  if (modal_.motion == lang::kMotionRapid && b.anyFa && !b.dwell)
    diags_.report(Msg::FaOnRapid, b.firstFa->loc, b.firstFa->len, lang::gNumber(lang::GCode::G0));
}

/// W410 soft limits of constant absolute targets, and the positions later lines start from.
inline void FileChecker::blockTargets(const BlockFacts& b, bool arcMotion) {
  for (uint32_t m = b.moveMask; m != 0; m &= m - 1) {
    const int a = std::countr_zero(m);
    auto v = constValue(f_, b.moves[a]->value);
    const machine::Axis* ax = axisOf(static_cast<char>('A' + a));
    std::optional<double> target;
    if (v && !modal_.incremental)
      target = v;
    else if (v && modal_.pos[static_cast<size_t>(a)])
      target = *modal_.pos[static_cast<size_t>(a)] + *v;
    if (v && !modal_.incremental && ax &&
        (*v < ax->limitMinus - kLimitTolerance || *v > ax->limitPlus + kLimitTolerance)) {
      const Item& x = *b.moves[a];
      diags_.report(Msg::SoftLimit, x.loc, x.len, x.axis, *v, ax->limitMinus, ax->limitPlus, x.axis);
    }
    if (!arcMotion || b.dwell) modal_.pos[static_cast<size_t>(a)] = target;
  }
  if (!modal_.incremental && b.moveMask != 0) blockZones(b);
}

/// W423: every axis of a forbidden zone programmed on the line with a constant absolute target,
/// the end point inside the zone.
inline void FileChecker::blockZones(const BlockFacts& b) {
  if (!opts_.machine) return;
  for (const machine::Zone& zone : opts_.machine->zones) {
    if (!zone.forbidden) continue;
    bool inside = true;
    std::string where;
    const Item* first = nullptr;
    for (const machine::ZoneAxis& za : zone.axes) {
      const int a = support::upperAscii(za.letter) - 'A';
      const Item* x = a >= 0 && a < 26 ? b.move(a) : nullptr;
      const auto v = x ? constValue(f_, x->value) : std::nullopt;
      if (!v || *v < za.min || *v > za.max) {
        inside = false;
        break;
      }
      if (!first) first = x;
      where += fmt::format("{}{}={}", where.empty() ? "" : " ", za.letter, *v);
    }
    if (inside && first) diags_.report(Msg::ZoneTarget, first->loc, first->len, where, zone.name);
  }
}

inline void FileChecker::checkBlock(const Stmt& s) {
  if (s.partial) return applyPartialBlock(s);
  const Item* it = f_.itemsOf(s);
  BlockFacts b;
  for (uint32_t k = 0; k < s.itemCount; ++k) {
    const Item& x = it[k];
    switch (x.kind) {
    case ItemKind::G: blockG(b, x); break;
    case ItemKind::Move: blockMove(b, x); break;
    case ItemKind::Feed: blockFeed(b, s, x); break;
    case ItemKind::AxisFeed: blockAxisFeed(b, x); break;
    case ItemKind::ArcI:
    case ItemKind::ArcJ:
    case ItemKind::ArcK:
    case ItemKind::ArcCR: blockArcWord(b, x); break;
    case ItemKind::M: blockM(b, x); break;
    case ItemKind::AssignR:
    case ItemKind::AssignIo: blockAssign(x); break;
    case ItemKind::ZWord: checkExpr(x.value, false); break;
    case ItemKind::AssignP:
      checkExpr(x.target, false);
      checkExpr(x.value, false);
      break;
    case ItemKind::Kg:
    case ItemKind::AxisControl: break;
    }
    if (isZ32()) blockZ32Item(x);
  }
  if (isZ32()) checkZ32Line(s);
  blockFaAndDwell(b, s);
  const Item* special = specialOn(s);
  if (special && lang::z32Step(special->code, true) == lang::Z32Step::Special) b.firstM = nullptr; // W415 instead
  if (b.firstM && b.moveCount > 0) diags_.report(Msg::MBeforeMotion, b.firstM->loc, b.firstM->len);
  bool arcMotion = lang::isArc(modal_.motion);
  bool centreGiven = b.arcCentre[0] || b.arcCentre[1] || b.arcCentre[2] || b.cr;
  if (b.moveCount == 0 && !(arcMotion && centreGiven)) return;
  if (arcMotion && !b.dwell) {
    checkArc(s, b);
  } else if (centreGiven) {
    const Item* c = b.cr ? b.cr : b.arcCentre[0] ? b.arcCentre[0] : b.arcCentre[1] ? b.arcCentre[1] : b.arcCentre[2];
    diags_.report(Msg::ArcWordsWithoutArc, c->loc, c->len, lang::gNumber(lang::GCode::G2),
                  lang::gNumber(lang::GCode::G3));
  }
  blockFeedMove(b, s);
  blockTargets(b, arcMotion);
}

void FileChecker::blockZ32Item(const Item& x) {
  if (x.kind == ItemKind::G) {
    const lang::Z32GCode* g = lang::findZ32G(x.code);
    if (!g || g->modelled) return;
    if (std::find(notModelledSeen_.begin(), notModelledSeen_.end(), x.code) != notModelledSeen_.end()) return;
    notModelledSeen_.push_back(x.code);
    diags_.report(Msg::Z32NotModelled, x.loc, x.len, x.code, g->doc);
  } else if (x.kind == ItemKind::AxisControl) {
    forEachControlledAxis(x, [&](char letter) {
      if (!axisOf(letter)) diags_.report(Msg::MachineNoAxis, x.loc, x.len, letter);
    });
  } else if (x.kind == ItemKind::ZWord && x.zaddr[0] == 'O' && x.zaddr[1] == 0 && opts_.machine &&
             !opts_.machine->builtin) {
    auto v = constValue(f_, x.value);
    if (!v || *v == 0 || opts_.machine->origins.count(static_cast<int>(*v))) return;
    std::string have;
    for (const auto& [n, offsets] : opts_.machine->origins)
      have += (have.empty() ? "O" : ", O") + std::to_string(n);
    diags_.report(Msg::OriginUnknown, x.loc, x.len, static_cast<int>(*v), have.empty() ? "none" : have);
  }
}

inline bool FileChecker::hasG4(const Stmt& s) const {
  const Item* it = f_.itemsOf(s);
  for (uint32_t k = 0; k < s.itemCount; ++k)
    if (it[k].kind == ItemKind::G && lang::isDwell(it[k].code)) return true;
  return false;
}

inline void FileChecker::checkStmtValues(const Stmt& s) {
  switch (s.kind) {
  case StmtKind::Block: checkBlock(s); break;
  case StmtKind::If:
  case StmtKind::When:
  case StmtKind::Case:
    checkExpr(s.cond, false);
    if (s.inner >= 0) {
      const Stmt& in = f_.inner[static_cast<size_t>(s.inner)];
      if (in.kind == StmtKind::Block) {
        // The inner block may or may not run: its modal effects are uncertain, except that
        // an F written there is "an F earlier in the file" for W402.
        Modal saved = modal_;
        checkBlock(in);
        bool feed = saved.feedSet || modal_.feedSet;
        bool notPositive = saved.feedNotPositive && modal_.feedNotPositive;
        modal_ = saved;
        modal_.feedSet = feed;
        modal_.feedNotPositive = notPositive;
        invalidatePositions();
      }
    }
    break;
  default: break;
  }
}

void FileChecker::checkBlocks() {
  startBlocks();
  for (int32_t i = 0; i < n_; ++i)
    blockStmt(st(i));
}

/// The values of the statements, in order (the modal state runs through them): startBlocks
/// once f_.kind is known, then blockStmt for each statement.
void FileChecker::startBlocks() {
  if (f_.kind != UnitKind::Sub && opts_.machine) {
    for (const auto& ax : opts_.machine->axes)
      modal_.pos[static_cast<size_t>(ax.letter - 'A')] = ax.start;
  }
}

void FileChecker::blockStmt(const Stmt& s) {
  if (s.hasLabel() || s.kind == StmtKind::Call || s.kind == StmtKind::Else || s.kind == StmtKind::EndIf ||
      s.kind == StmtKind::When || s.kind == StmtKind::Cancel)
    invalidatePositions();
  checkStmtValues(s);
  if (s.kind == StmtKind::If && s.inner < 0 && !s.hasJump()) invalidatePositions();
}

} // namespace iso::frontend::checks
