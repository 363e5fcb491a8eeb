//! @file Z32Lines.cpp
//! @brief The per-line rules of dialect z32: S, T and MA/MB/MC words (E312, W416), M3/M4 and M6
//!        (W417, W418), one plain M a line, M=NB, and what a special M leaves unrun (W415).
#include "frontend/checks/FileChecker.h"

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "lang/Z32GCodes.h"

namespace iso::frontend::checks {

using diag::Msg;

namespace {

bool isZWord(const Item& x, const char* addr) {
  return x.kind == ItemKind::ZWord && std::strncmp(x.zaddr, addr, 3) == 0;
}

std::string formatConstant(double v) { return fmt::format("{}", v); }

} // namespace

/// z32 (SPEC §4.6): the per-line limits (E312), a special M ending the line (W415), MA/MB/MC
/// clamped (W416), M3/M4 without S (W417), M6 without T (W418).
void FileChecker::checkZ32Line(const Stmt& s) {
  const Item* it = f_.itemsOf(s);
  const Item* other = nullptr;
  const Item* spindle[2] = {nullptr, nullptr}; // M3, M4
  const Item* special = nullptr;
  lang::Z32Step specialStep = lang::Z32Step::Final;
  for (uint32_t k = 0; k < s.itemCount; ++k) {
    const Item& x = it[k];
    if (isZWord(x, "S") || isZWord(x, "T")) {
      (x.zaddr[0] == 'S' ? sSet_ : tSet_) = true;
      auto v = constValue(f_, x.value);
      if (v && x.zaddr[0] == 'S' && *v < 0) diags_.report(Msg::SpindleSpeedNegative, x.loc, x.len);
      if (v && x.zaddr[0] == 'T' && (*v < 0 || *v != std::floor(*v) || *v > lang::kMaxToolNumber))
        diags_.report(Msg::ToolNumberInvalid, x.loc, x.len);
    }
    if (x.kind == ItemKind::ZWord && x.zaddr[0] == 'M') checkAuxClamp(x);
  }
  for (uint32_t k = 0; k < s.itemCount; ++k) {
    const Item& x = it[k];
    if (x.kind != ItemKind::M) continue;
    const lang::MRole role = lang::mRole(x.code, lang::Dialect::Z32);
    const std::string* proc = opts_.specialM(x.code);
    if (x.nb && (lang::isManaged(role) || lang::isFinal(role) || proc)) {
      if (proc)
        diags_.report(Msg::NbZ32Special, x.loc, x.len, x.code, x.code, *proc);
      else if (lang::isManaged(role))
        diags_.report(Msg::NbZ32Managed, x.loc, x.len, x.code, x.code);
      else
        diags_.report(Msg::NbZ32Final, x.loc, x.len, x.code, x.code);
      continue;
    }
    // M=NB(n) of a plain sequence is an "other M" too (SPEC §4.6: at most one per line)
    if (role == lang::MRole::Plain) {
      if (other) {
        auto& d = diags_.report(Msg::Z32TwoPlainM, x.loc, x.len, other->code, x.code);
        d.note(Msg::Z32TwoPlainMNote, other->loc);
      } else {
        other = &x;
      }
    }
    if (x.nb) continue;
    if (role == lang::MRole::SpindleCw || role == lang::MRole::SpindleCcw) {
      spindle[role == lang::MRole::SpindleCw ? 0 : 1] = &x;
      if (!sSet_) diags_.report(Msg::SpindleSpeedUnset, x.loc, x.len, x.code);
    }
    if (role == lang::MRole::ToolChange && !tSet_) diags_.report(Msg::ToolUnset, x.loc, x.len, x.code);
    if (proc) {
      const lang::Z32Step step = lang::z32Step(x.code, true);
      if (!special || step < specialStep) {
        special = &x;
        specialStep = step;
      }
    }
  }
  if (spindle[0] && spindle[1]) {
    auto& d = diags_.report(Msg::SpindleBothWays, spindle[1]->loc, spindle[1]->len, spindle[0]->code, spindle[1]->code);
    d.note(Msg::SpindleBothWaysNote, spindle[0]->loc, spindle[0]->code);
  }
  if (special) reportSpecialRest(s, *special, specialStep);
}

void FileChecker::checkAuxClamp(const Item& x) {
  auto v = constValue(f_, x.value);
  if (!v) return;
  bool clamped = false;
  const int sent = lang::auxSent(*v, &clamped);
  if (clamped)
    diags_.report(Msg::AuxClamped, x.loc, x.len, x.zaddr, formatConstant(*v), sent,
                  fmt::formatted_size("{}", lang::kAuxMax), lang::kAuxSignOffset);
}

/// W415: what the line order puts after a special M never runs.
void FileChecker::reportSpecialRest(const Stmt& s, const Item& special, lang::Z32Step step) {
  const Item* it = f_.itemsOf(s);
  std::vector<std::string> lost;
  for (uint32_t k = 0; k < s.itemCount && lost.size() < 8; ++k) {
    const Item& x = it[k];
    if (&x == &special) continue;
    lang::Z32Step xs = lang::Z32Step::Words;
    std::string name;
    switch (x.kind) {
    case ItemKind::M:
      xs = x.nb ? lang::Z32Step::Other : lang::z32Step(x.code, opts_.specialM(x.code) != nullptr);
      name = fmt::format("M{}", x.code);
      break;
    case ItemKind::ZWord:
      if (x.zaddr[0] == 'S') continue;                                       // step 1
      xs = x.zaddr[0] == 'O' ? lang::Z32Step::Origin : lang::Z32Step::Other; // T TA TB MA MB MC: step 4
      name = x.zaddr;
      break;
    case ItemKind::Move:
      xs = lang::Z32Step::Motion;
      name = diag::message(Msg::SpecialMRestMove, x.axis);
      break;
    case ItemKind::G:
      if (lang::isDwell(x.code)) {
        xs = lang::Z32Step::Dwell;
        name = diag::message(Msg::SpecialMRestDwell, x.code);
      } else if (x.code == lang::kG26Return || x.code == 61 || x.code == 62) {
        xs = x.code == lang::kG26Return ? lang::Z32Step::Return : lang::Z32Step::Motion;
        name = fmt::format("G{}", x.code);
      } else {
        continue;
      }
      break;
    case ItemKind::AxisControl:
      if (x.code != 29) continue; // G28: step 1
      xs = lang::Z32Step::Release;
      name = "G29";
      break;
    case ItemKind::Kg:
      xs = lang::Z32Step::Continue;
      name = fmt::format("KG{}", f_.names.at(static_cast<size_t>(x.code)).text);
      break;
    default: continue;
    }
    if (xs > step || (xs == step && step == lang::Z32Step::Special)) lost.push_back(name);
  }
  if (lost.empty()) return;
  std::string list;
  for (size_t k = 0; k < lost.size(); ++k)
    list += (k == 0 ? "" : k + 1 == lost.size() ? " and " : ", ") + lost[k];
  if (lost.size() == 1)
    diags_.report(Msg::SpecialMRest, special.loc, special.len, special.code, *opts_.specialM(special.code), list);
  else
    diags_.report(Msg::SpecialMRestPlural, special.loc, special.len, special.code, *opts_.specialM(special.code), list);
}

} // namespace iso::frontend::checks
