//! @file Sema.cpp
//! @brief Per-file checks (labels, jumps, IF/WHEN structure, control flow, blocks, values)
//!        and set-level checks (subprogram names, calls, nesting).
#include "frontend/Sema.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <functional>
#include <map>
#include <thread>
#include <unordered_map>

#include <fmt/format.h>

#include "frontend/Lexer.h"
#include "frontend/Parser.h"
#include "lang/GCodes.h"
#include "lang/Limits.h"
#include "lang/MFunctions.h"
#include "lang/Unsupported.h"
#include "support/CaseFold.h"
#include "support/Memory.h"
#include "support/Text.h"

namespace iso::frontend {

using diag::Msg;

static std::string_view extensionOf(std::string_view path) {
  size_t slash = path.find_last_of('/');
  size_t dot = path.find_last_of('.');
  if (dot == std::string_view::npos || (slash != std::string_view::npos && dot < slash)) return {};
  return path.substr(dot + 1);
}

UnitKind classifyUnit(const File& f) {
  std::string_view ext = extensionOf(f.path);
  const Stmt* first = nullptr;
  for (const Stmt& s : f.stmts)
    if (s.kind != StmtKind::Empty) {
      first = &s;
      break;
    }
  if (support::iequals(ext, "spf")) return UnitKind::Sub;
  if (first && first->kind == StmtKind::Semi) return UnitKind::Semi;
  if (support::iequals(ext, "mpf")) return UnitKind::Main;
  if (first && first->kind == StmtKind::Proc) return UnitKind::Sub;
  return UnitKind::Main;
}

std::optional<double> constValue(const File& f, ExprId e) {
  if (e == kNoExpr) return std::nullopt;
  const Expr& x = f.expr(e);
  switch (x.kind) {
  case ExprKind::Number: return x.value;
  case ExprKind::Neg: {
    auto a = constValue(f, x.a);
    if (!a) return std::nullopt;
    return -*a;
  }
  case ExprKind::Binary: {
    auto a = constValue(f, x.a);
    auto b = constValue(f, x.b);
    if (!a || !b) return std::nullopt;
    switch (static_cast<BinOp>(x.op)) {
    case BinOp::Add: return *a + *b;
    case BinOp::Sub: return *a - *b;
    case BinOp::Mul: return *a * *b;
    case BinOp::Div:
      if (*b == 0) return std::nullopt;
      return *a / *b;
    }
    return std::nullopt;
  }
  default: return std::nullopt;
  }
}

namespace {

/// A target within this distance (mm or deg) of a soft limit counts as on it (SPEC §4.3).
constexpr double kLimitTolerance = 1e-9;

bool hasM(const File& f, const Stmt& s, int code) {
  if (s.kind != StmtKind::Block) return false;
  const Item* it = f.itemsOf(s);
  for (uint32_t k = 0; k < s.itemCount; ++k)
    if (it[k].kind == ItemKind::M && !it[k].nb && it[k].code == code) return true;
  return false;
}

/// The statement's kind, or for a line that failed to parse the structural role its keyword
/// announced (IF/ELSE/ENDIF/WHEN/CANCEL), so that one bad line gives no follow-on errors.
bool isKind(const Stmt& s, StmtKind k) { return s.kind == k || (s.kind == StmtKind::Invalid && s.recoverAs == k); }

/// A file's labels by name, in any case (E203, jumps): open addressing over the indices of
/// File::labels, sized once for all of them. (A CAM program has a label every few lines: a
/// node per label and a pointer chase per lookup cost more than the checks that use them.)
class LabelIndex {
public:
  explicit LabelIndex(const std::vector<StmtLabel>& labels) : labels_(labels) {}
  /// Empties it, with room for every label of the file (at most half full: short probes).
  void clear() {
    size_t capacity = 16;
    while (capacity < 2 * labels_.size())
      capacity *= 2;
    slots_.assign(capacity, Slot{0, kNoIndex});
  }
  /// Adds label `j` (an index in File::labels), unless a label of its name is there already:
  /// then that one's index, else kNoIndex.
  uint32_t add(uint32_t j) {
    const std::string_view name = labels_[j].text;
    const uint64_t h = hash(name);
    size_t i = static_cast<size_t>(h) & (slots_.size() - 1);
    for (; slots_[i].label != kNoIndex; i = (i + 1) & (slots_.size() - 1))
      if (slots_[i].hash == h && support::iequals(labels_[slots_[i].label].text, name)) return slots_[i].label;
    slots_[i] = Slot{h, j};
    return kNoIndex;
  }
  /// The index in File::labels of the label `name`, or kNoIndex.
  uint32_t find(std::string_view name) const {
    if (slots_.empty()) return kNoIndex;
    const uint64_t h = hash(name);
    for (size_t i = static_cast<size_t>(h) & (slots_.size() - 1); slots_[i].label != kNoIndex;
         i = (i + 1) & (slots_.size() - 1))
      if (slots_[i].hash == h && support::iequals(labels_[slots_[i].label].text, name)) return slots_[i].label;
    return kNoIndex;
  }

private:
  struct Slot {
    uint64_t hash;  ///< all of it: names are compared only when the whole hash agrees
    uint32_t label; ///< kNoIndex: empty
  };
  static uint64_t hash(std::string_view s) {
    uint64_t h = 1469598103934665603ull; // FNV-1a
    for (char c : s)
      h = (h ^ static_cast<unsigned char>(support::upperAscii(c))) * 1099511628211ull;
    return h ^ (h >> 29); // the low bits pick the slot: fold the high ones in
  }
  const std::vector<StmtLabel>& labels_;
  std::vector<Slot> slots_;
};

class FileChecker {
public:
  FileChecker(File& f, const SemaOptions& o, diag::DiagnosticList& d) : FileChecker(f, o, d, nullptr) {}

  /// `blocksChecked`: the values of every statement were checked as the file was parsed
  /// (startBlocks, blockStmt), so only the checks of the file as a whole remain. `twoThreads`:
  /// the passes that do not depend on each other run two at a time (the same diagnostics; they
  /// are sorted by place before anyone sees them).
  FileFlow run(bool blocksChecked = false, bool twoThreads = false) {
    n_ = static_cast<int32_t>(f_.stmts.size());
    flow_.match.assign(f_.stmts.size(), -1);
    if (twoThreads) {
      runInTwo();
    } else {
      checkHeaders();
      collectLabels();
      matchIfsAndResolveJumps();
      checkWhens();
      checkJumpsIntoBlocks();
      computeReachability();
      checkLineNumbers();
    }
    if (!blocksChecked) checkBlocks();
    return std::move(flow_);
  }

private:
  /// A checker of the same file that shares `flow` (parallel passes write different entries).
  FileChecker(File& f, const SemaOptions& o, diag::DiagnosticList& d, FileFlow* flow)
      : f_(f), opts_(o), diags_(d), flow_(flow ? *flow : ownFlow_) {
    if (opts_.machine)
      for (int a = 0; a < 26; ++a) {
        const int k = opts_.machine->axisIndex(static_cast<char>('A' + a));
        axisByLetter_[a] = k < 0 ? nullptr : &opts_.machine->axes[static_cast<size_t>(k)];
      }
  }

  /// run's passes on two threads: a second checker of the file (its own diagnostics, the same
  /// flow) runs the headers, the WHENs and the N numbers beside the labels, IFs and jumps,
  /// then the jumps into blocks beside the flow. Each pass reads only what the passes before
  /// its pair wrote; the two of a pair write different entries of FileFlow::match, and only
  /// the first resolves jump targets (the WHEN checks never read them).
  void runInTwo() {
    diag::DiagnosticList helperDiags;
    FileChecker helper(f_, opts_, helperDiags, &flow_);
    helper.n_ = n_;
    besideHelper(
        [&] {
          helper.checkHeaders();
          helper.checkWhens();
          helper.checkLineNumbers();
        },
        [&] {
          collectLabels();
          matchIfsAndResolveJumps();
        });
    helper.endifOf_ = endifOf_;
    besideHelper([&] { helper.checkJumpsIntoBlocks(); }, [&] { computeReachability(); });
    diags_.append(std::move(helperDiags));
  }

  /// Runs `help` on a thread of its own while `work` runs here; any exception comes out here.
  template <class Help, class Work> static void besideHelper(Help help, Work work) {
    std::exception_ptr helpError;
    {
      std::thread t([&] {
        try {
          help();
        } catch (...) {
          helpError = std::current_exception();
        }
      });
      struct Join {
        std::thread& t;
        ~Join() { t.join(); }
      } join{t};
      work();
    }
    if (helpError) std::rethrow_exception(helpError);
  }

  Loc L(uint32_t line, uint32_t col = 1) const { return Loc{f_.id, line, col}; }

  // ---- headers (E208) ------------------------------------------------------------------
  void checkHeaders() {
    const Stmt* first = nullptr;
    for (const Stmt& s : f_.stmts)
      if (s.kind != StmtKind::Empty) {
        first = &s;
        break;
      }
    if (f_.kind == UnitKind::Sub) {
      if (!first || (first->kind != StmtKind::Proc && first->kind != StmtKind::Invalid && !first->partial)) {
        diags_.report(Msg::ProcNotFirst, first ? first->loc : L(1), 1);
      } else if (first->kind == StmtKind::Proc) {
        f_.procName = f_.nameOf(*first).text;
      }
    }
    if (f_.kind == UnitKind::Semi && first) f_.semiName = std::string(f_.nameOf(*first).text);
    for (const Stmt& s : f_.stmts) {
      if (&s == first) continue;
      if (s.kind == StmtKind::Proc) diags_.report(Msg::ProcLater, s.loc, 1);
      if (s.kind == StmtKind::Semi) diags_.report(Msg::SemiLater, s.loc, 1);
    }
    if (first && first->kind == StmtKind::Proc && f_.kind != UnitKind::Sub)
      diags_.report(Msg::ProcInMain, first->loc, 1);
    if (first && first->kind == StmtKind::Semi && f_.kind == UnitKind::Sub)
      diags_.report(Msg::SemiInSub, first->loc, 1);
  }

  // ---- labels (E203) -------------------------------------------------------------------
  void collectLabels() {
    // File::labels is in statement order: one entry per labelled statement
    labels_.clear();
    for (uint32_t j = 0; j < f_.labels.size(); ++j) {
      const StmtLabel& label = f_.labels[j];
      const uint32_t first = labels_.add(j);
      if (first != kNoIndex) {
        auto& d = diags_.report(Msg::LabelTwice, label.loc, static_cast<uint32_t>(label.text.size()), label.text);
        d.note(Msg::LabelTwiceNote, f_.labels[first].loc);
      }
    }
  }

  // ---- IF / ELSE / ENDIF (E201) ----------------------------------------------------------
  /// The block IFs open at a statement, and the ELSE of each (-1: none yet).
  struct OpenIfs {
    std::vector<int32_t> stack; // If indices
    std::vector<int32_t> elseOf;
  };

  void matchIf(OpenIfs& open, int32_t i, const Stmt& s) {
    std::vector<int32_t>& stack = open.stack;
    std::vector<int32_t>& elseOf = open.elseOf;
    if (isKind(s, StmtKind::If) && s.inner < 0 && !s.hasJump()) {
      stack.push_back(i);
      elseOf.push_back(-1);
    } else if (isKind(s, StmtKind::Else)) {
      if (stack.empty()) {
        diags_.report(Msg::IfElseWithoutIf, s.loc, 4);
      } else if (elseOf.back() >= 0) {
        auto& d = diags_.report(Msg::IfSecondElse, s.loc, 4);
        d.note(Msg::IfFirstElseNote, f_.stmts[static_cast<size_t>(elseOf.back())].loc);
      } else {
        elseOf.back() = i;
        flow_.match[static_cast<size_t>(stack.back())] = i;
      }
    } else if (isKind(s, StmtKind::EndIf)) {
      if (stack.empty()) {
        diags_.report(Msg::IfEndifWithoutIf, s.loc, 5);
      } else {
        int32_t ifIdx = stack.back();
        if (elseOf.back() >= 0) {
          flow_.match[static_cast<size_t>(elseOf.back())] = i;
        } else {
          flow_.match[static_cast<size_t>(ifIdx)] = i;
        }
        endifOf_.push_back({ifIdx, i});
        stack.pop_back();
        elseOf.pop_back();
      }
    }
  }

  void finishIfs(const OpenIfs& open) {
    for (int32_t idx : open.stack) {
      const Stmt& s = f_.stmts[static_cast<size_t>(idx)];
      diags_.report(Msg::IfWithoutEndif, s.loc, 2);
      flow_.match[static_cast<size_t>(idx)] = -1;
    }
    std::sort(endifOf_.begin(), endifOf_.end()); // inner IFs close first
  }

  /// E201 and the jumps in one walk over the statements (the labels are collected): each step
  /// reads only what it keeps itself.
  void matchIfsAndResolveJumps() {
    OpenIfs open;
    for (int32_t i = 0; i < n_; ++i) {
      Stmt& s = f_.stmts[static_cast<size_t>(i)];
      matchIf(open, i, s);
      resolveJumpsOf(i, s);
    }
    finishIfs(open);
  }

  // ---- jumps (E202, E204, E205, W408, W413) -------------------------------------------------
  int32_t findLabel(std::string_view name) const {
    const uint32_t j = labels_.find(name);
    return j == kNoIndex ? -1 : static_cast<int32_t>(f_.labels[j].stmt);
  }

  void resolveJump(Jump& j, int32_t from, bool isCase) {
    int32_t t = findLabel(j.label);
    if (t < 0) {
      diags_.report(Msg::LabelUnknown, j.loc, j.len, j.label);
      return;
    }
    const Stmt& target = f_.stmts[static_cast<size_t>(t)];
    if (isCase) {
      if (j.kind != JumpKind::Gotof || t <= from) {
        auto& d = j.kind != JumpKind::Gotof ? diags_.report(Msg::CaseNotGotof, j.kwLoc, 5, jumpKindName(j.kind))
                                            : diags_.report(Msg::CaseLabelBefore, j.loc, j.len, j.label);
        d.note(Msg::CaseLabelNote, f_.labelOf(target).loc);
        if (j.kind == JumpKind::Gotof) return;
      }
      j.target = t;
      return;
    }
    switch (j.kind) {
    case JumpKind::Gotof:
      if (t <= from) {
        auto& d = t == from ? diags_.report(Msg::GotofSameLine, j.kwLoc, 5, j.label)
                            : diags_.report(Msg::GotofBackward, j.kwLoc, 5, j.label);
        d.note(Msg::JumpDirectionLabelNote, f_.labelOf(target).loc);
        return;
      }
      break;
    case JumpKind::Gotob:
      if (t > from) {
        auto& d = diags_.report(Msg::GotobForward, j.kwLoc, 5, j.label);
        d.note(Msg::JumpDirectionLabelNote, f_.labelOf(target).loc);
        return;
      }
      break;
    case JumpKind::Goto:
      diags_.report(Msg::GotoDirection, j.kwLoc, 4, jumpKindName(t > from ? JumpKind::Gotof : JumpKind::Gotob),
                    j.label);
      break;
    }
    j.target = t;
  }

  /// The jumps of statement `i` (its own, its THEN's, its CASE arms').
  void resolveJumpsOf(int32_t i, Stmt& s) {
    if ((s.kind == StmtKind::Jump || s.kind == StmtKind::If) && s.hasJump()) resolveJump(f_.jumpOf(s), i, false);
    if (s.inner >= 0) {
      Stmt& in = f_.inner[static_cast<size_t>(s.inner)];
      if (in.kind == StmtKind::Jump) resolveJump(f_.jumpOf(in), i, false);
    }
    if (s.kind == StmtKind::Case) {
      std::unordered_map<double, const CaseArm*> seen; // value (0 for -0) -> first arm
      for (CaseArm& arm : f_.armsOf(s)) {
        resolveJump(arm.jump, i, true);
        if (arm.isDefault) continue;
        auto [prev, inserted] = seen.emplace(arm.value == 0 ? 0.0 : arm.value, &arm);
        if (!inserted) {
          auto& d = diags_.report(Msg::CaseDuplicate, arm.valueLoc, 1, arm.value);
          d.note(Msg::CaseDuplicateNote, prev->second->valueLoc);
        }
      }
    }
  }

  const Stmt& st(int32_t i) const { return f_.stmts[static_cast<size_t>(i)]; }

  // ---- WHEN (E212, E213) ---------------------------------------------------------------------
  /// What a WHEN body may not hold (E212): a label, a jump, a CASE, a call, another WHEN, an
  /// M that ends the unit (`m`), a special M.
  enum class Forbidden : uint8_t { None, Label, Jump, Case, Call, When, EndM, SpecialM };
  struct BodyCheck {
    Forbidden what = Forbidden::None;
    int32_t m = 0; ///< EndM: the M number
  };

  BodyCheck bodyForbidden(const File& f, const Stmt& s) const {
    if (s.hasLabel()) return {Forbidden::Label};
    switch (s.kind) {
    case StmtKind::Jump: return {Forbidden::Jump};
    case StmtKind::Case: return {Forbidden::Case};
    case StmtKind::Call: return {Forbidden::Call};
    case StmtKind::When: return {Forbidden::When};
    case StmtKind::If: return {s.hasJump() ? Forbidden::Jump : Forbidden::None};
    case StmtKind::Block:
      if (hasM(f, s, lang::kMReturn)) return {Forbidden::EndM, lang::kMReturn};
      if (hasM(f, s, lang::kMEnd)) return {Forbidden::EndM, lang::kMEnd};
      if (isZ32() && hasM(f, s, lang::kMEndZ32)) return {Forbidden::EndM, lang::kMEndZ32}; // z32: M2 ends like M30
      if (specialOn(s)) return {Forbidden::SpecialM};
      return {};
    default: return {};
    }
  }

  void reportForbidden(const Loc& at, BodyCheck c) {
    switch (c.what) {
    case Forbidden::None: break;
    case Forbidden::Label: diags_.report(Msg::WhenBodyLabel, at, 1); break;
    case Forbidden::Jump: diags_.report(Msg::WhenBodyJump, at, 1); break;
    case Forbidden::Case: diags_.report(Msg::WhenBodyCase, at, 1); break;
    case Forbidden::Call: diags_.report(Msg::WhenBodyCall, at, 1); break;
    case Forbidden::When: diags_.report(Msg::WhenBodyWhen, at, 1); break;
    case Forbidden::EndM: diags_.report(Msg::WhenBodyEndM, at, 1, c.m); break;
    case Forbidden::SpecialM: diags_.report(Msg::WhenBodySpecialM, at, 1); break;
    }
  }

  void checkTriggerAxis(int32_t whenIdx, const Stmt& trigger) {
    const Stmt& when = st(whenIdx);
    const std::string_view axes = f_.whenAxesOf(static_cast<uint32_t>(whenIdx));
    if (axes.empty()) {
      diags_.report(Msg::WhenReadsNoAxis, when.loc, 4, sysVarName(SysVar::AaIw));
      return;
    }
    for (char a : axes) {
      const uint32_t bit = a >= 'A' && a <= 'Z' ? uint32_t{1} << (a - 'A') : 0;
      const bool moved = (trigger.movedAxes & bit) != 0, posa = (trigger.posaAxes & bit) != 0;
      if (!moved) {
        auto& d = posa ? diags_.report(Msg::TriggerPosa, when.loc, 4, a, a, a)
                       : diags_.report(Msg::TriggerNoMove, when.loc, 4, a, sysVarName(SysVar::AaIw));
        d.note(Msg::TriggerNote, trigger.loc);
      }
    }
  }

  void checkWhens() {
    int32_t i = 0;
    while (i < n_) {
      const Stmt& s = st(i);
      if (isKind(s, StmtKind::Cancel)) {
        diags_.report(Msg::CancelWithoutWhen, s.loc, 6);
        ++i;
        continue;
      }
      if (s.kind == StmtKind::Invalid && s.recoverAs == StmtKind::When) {
        // A long-form WHEN whose line failed to parse: skip its body and CANCEL.
        int32_t k = i + 1;
        while (k < n_ && !isKind(st(k), StmtKind::Cancel) && !isKind(st(k), StmtKind::When))
          ++k;
        i = k < n_ && isKind(st(k), StmtKind::Cancel) ? k + 1 : i + 1;
        continue;
      }
      if (s.kind != StmtKind::When) {
        ++i;
        continue;
      }
      // A chain: WHEN [body CANCEL] { WHEN ... } trigger
      std::vector<int32_t> chain;
      std::vector<const Stmt*> bodies; // the single path instruction of each inner body, or null
      int32_t j = i;
      bool broken = false;
      while (j < n_ && st(j).kind == StmtKind::When) {
        const Stmt& w = st(j);
        if (!chain.empty() && w.hasLabel()) diags_.report(Msg::WhenChainLabel, f_.labelOf(w).loc, 1);
        chain.push_back(j);
        const Stmt* single = nullptr;
        int bodyCount = 0;
        int32_t next;
        if (w.inner >= 0) {
          const Stmt& in = f_.inner[static_cast<size_t>(w.inner)];
          reportForbidden(in.loc, bodyForbidden(f_, in));
          single = &in;
          bodyCount = 1;
          next = j + 1;
        } else {
          int32_t k = j + 1;
          while (k < n_ && !isKind(st(k), StmtKind::Cancel) && st(k).kind != StmtKind::When)
            ++k;
          if (k < n_ && st(k).kind == StmtKind::When) {
            diags_.report(Msg::WhenInWhenBody, st(k).loc, 4);
            broken = true;
            j = j + 1;
            break;
          }
          if (k >= n_) {
            // Body checks would only repeat this error: the body's end is unknown.
            diags_.report(Msg::WhenWithoutCancel, w.loc, 4);
            broken = true;
            j = j + 1;
            break;
          }
          for (int32_t b = j + 1; b < k; ++b) {
            const Stmt& bs = st(b);
            if (bs.kind == StmtKind::Empty && !bs.hasLabel()) continue;
            const BodyCheck c = bodyForbidden(f_, bs);
            reportForbidden(c.what == Forbidden::Label ? f_.labelOf(bs).loc : bs.loc, c);
            ++bodyCount;
            single = &bs;
          }
          flow_.match[static_cast<size_t>(j)] = k;
          next = k + 1;
        }
        bodies.push_back(bodyCount == 1 ? single : nullptr);
        (void)bodyCount;
        // skip blank and comment lines
        while (next < n_ && st(next).kind == StmtKind::Empty && !st(next).hasLabel())
          ++next;
        j = next;
      }
      if (broken) {
        i = j;
        continue;
      }
      i = checkWhenChain(chain, bodies, j);
    }
  }

  /// A parsed WHEN chain (`chain`: its WHEN lines, `bodies`: each inner body's one statement)
  /// before the statement `j`: the chain length, the inner bodies, the trigger. Returns where
  /// the next WHEN may start.
  int32_t checkWhenChain(const std::vector<int32_t>& chain, std::vector<const Stmt*>& bodies, int32_t j) {
    if (chain.size() > static_cast<size_t>(lang::kMaxWhenChain)) {
      auto& d = diags_.report(Msg::WhenChainTooLong, st(chain[lang::kMaxWhenChain]).loc, 4, lang::kMaxWhenChain,
                              chain.size());
      d.note(Msg::WhenChainStartNote, st(chain[0]).loc);
    }
    // inner bodies (every WHEN but the first written) must be exactly one path instruction
    for (size_t c = 1; c < chain.size(); ++c) {
      const Stmt* b = bodies[c];
      if (!b || !b->hasMotion()) {
        diags_.report(Msg::WhenChainBody, st(chain[c]).loc, 4);
        bodies[c] = nullptr;
      }
    }
    // the trigger
    if (j >= n_ || st(j).kind != StmtKind::Block || !st(j).hasMotion()) {
      const Stmt& last = st(chain.back());
      diags_.report(Msg::WhenWithoutTrigger, j < n_ ? st(j).loc : last.loc, 4);
      return j;
    }
    const Stmt& trigger = st(j);
    if (trigger.hasLabel()) diags_.report(Msg::WhenTriggerLabel, f_.labelOf(trigger).loc, 1);
    checkTriggerAxis(chain.back(), trigger);
    for (size_t c = 0; c + 1 < chain.size(); ++c)
      if (bodies[c + 1]) checkTriggerAxis(chain[c], *bodies[c + 1]);
    for (int32_t c : chain) {
      int32_t cancel = flow_.match[static_cast<size_t>(c)];
      if (cancel > c) whenBodies_.push_back({c + 1, cancel - 1});
    }
    return j + 1;
  }

  // ---- W412 / jumps into WHEN bodies ------------------------------------------------------------
  void checkJumpsIntoBlocks() {
    // Innermost IF body (then or else range) of every label and the WHEN body of a statement:
    // one linear pass, then each jump is checked in O(log n) (jump targets are labels).
    // Nothing here is per statement: a CAM program of millions of lines has few labels.
    struct Range {
      int32_t lo, hi;
    };
    std::vector<Range> ranges;
    std::vector<int32_t> innerOfLabel(f_.labels.size(), -1);
    std::vector<int32_t> open;
    std::vector<int32_t> matchedEnds;
    matchedEnds.reserve(endifOf_.size());
    for (const auto& [ifIdx, endIdx] : endifOf_)
      matchedEnds.push_back(endIdx);
    std::sort(matchedEnds.begin(), matchedEnds.end());
    // matchedEnds, endifOf_ and File::labels are in statement order: read as `i` goes
    size_t nextEnd = 0, nextIf = 0, nextLabel = 0;
    auto isMatchedEnd = [&](int32_t i) {
      while (nextEnd < matchedEnds.size() && matchedEnds[nextEnd] < i)
        ++nextEnd;
      return nextEnd < matchedEnds.size() && matchedEnds[nextEnd] == i;
    };
    auto hasEndif = [&](int32_t i) {
      while (nextIf < endifOf_.size() && endifOf_[nextIf].first < i)
        ++nextIf;
      return nextIf < endifOf_.size() && endifOf_[nextIf].first == i;
    };
    auto labelIndex = [&](int32_t i) {
      while (nextLabel < f_.labels.size() && f_.labels[nextLabel].stmt < static_cast<uint32_t>(i))
        ++nextLabel;
      return nextLabel;
    };
    for (int32_t i = 0; i < n_; ++i) {
      const Stmt& s = st(i);
      bool closes = (s.kind == StmtKind::Else && flow_.match[static_cast<size_t>(i)] >= 0) ||
                    (s.kind == StmtKind::EndIf && isMatchedEnd(i));
      if (closes) {
        if (!open.empty()) {
          ranges[static_cast<size_t>(open.back())].hi = i - 1;
          open.pop_back();
        }
      }
      if (s.hasLabel()) innerOfLabel[labelIndex(i)] = open.empty() ? -1 : open.back();
      bool opens = (s.kind == StmtKind::If && s.inner < 0 && !s.hasJump() && hasEndif(i)) ||
                   (s.kind == StmtKind::Else && flow_.match[static_cast<size_t>(i)] >= 0);
      if (opens) {
        ranges.push_back({i + 1, n_ - 1});
        open.push_back(static_cast<int32_t>(ranges.size() - 1));
      }
    }
    // WHEN bodies are disjoint and found in file order (checkWhens)
    auto whenOf = [&](int32_t k) -> int32_t {
      auto it = std::upper_bound(whenBodies_.begin(), whenBodies_.end(), k,
                                 [](int32_t v, const std::pair<int32_t, int32_t>& b) { return v < b.first; });
      if (it == whenBodies_.begin()) return -1;
      --it;
      return k <= it->second ? static_cast<int32_t>(it - whenBodies_.begin()) : -1;
    };
    auto check = [&](const Jump& j, int32_t from) {
      if (j.target < 0) return;
      int32_t wt = whenOf(j.target);
      if (wt >= 0 && whenOf(from) != wt) diags_.report(Msg::JumpIntoWhen, j.loc, j.len);
      const Stmt& target = st(j.target);
      int32_t r = target.hasLabel() ? innerOfLabel[f_.labelIndexOf(static_cast<uint32_t>(j.target))] : -1;
      if (r < 0) return;
      const Range& best = ranges[static_cast<size_t>(r)];
      if (!(from >= best.lo && from <= best.hi)) {
        auto& d = diags_.report(Msg::JumpIntoBlock, j.loc, j.len, j.label);
        d.note(Msg::JumpIntoBlockNote, f_.labelOf(target).loc);
      }
    };
    for (int32_t i = 0; i < n_; ++i) {
      const Stmt& s = st(i);
      if (s.hasJump()) check(f_.jumpOf(s), i);
      if (s.inner >= 0 && f_.inner[static_cast<size_t>(s.inner)].kind == StmtKind::Jump)
        check(f_.jumpOf(f_.inner[static_cast<size_t>(s.inner)]), i);
      if (s.kind == StmtKind::Case)
        for (const CaseArm& arm : f_.armsOf(s))
          check(arm.jump, i);
    }
  }

  // ---- control flow (W404, W405, E206, E207) ------------------------------------------------------
  /// The line ends the program or subprogram. In z32 a special M on the line ends it first
  /// (the final M never runs, W415).
  bool terminal(const Stmt& s) const {
    return (hasM(f_, s, lang::kMEnd) || hasM(f_, s, lang::kMReturn) || (isZ32() && hasM(f_, s, lang::kMEndZ32))) &&
           !specialOn(s);
  }
  /// z32: the first special M of a block (blocking), or nullptr.
  const Item* specialOn(const Stmt& s) const {
    if (!isZ32() || s.kind != StmtKind::Block) return nullptr;
    const Item* it = f_.itemsOf(s);
    for (uint32_t k = 0; k < s.itemCount; ++k)
      if (it[k].kind == ItemKind::M && !it[k].nb && opts_.specialM(it[k].code)) return &it[k];
    return nullptr;
  }
  bool isZ32() const { return opts_.dialect == machine::Dialect::Z32; }

  void computeReachability() {
    flow_.reachable.assign(f_.stmts.size(), 0);
    std::vector<int32_t> work;
    auto push = [&](int32_t t) {
      if (t == n_) {
        flow_.endReachable = true;
        return;
      }
      if (t < 0 || t > n_) return;
      if (!flow_.reachable[static_cast<size_t>(t)]) {
        flow_.reachable[static_cast<size_t>(t)] = 1;
        work.push_back(t);
      }
    };
    push(0);
    if (n_ == 0) flow_.endReachable = true;
    while (!work.empty()) {
      int32_t i = work.back();
      work.pop_back();
      // A run of lines that only fall through to the next is walked here, not through the
      // work list (the same lines become reachable: a fall-through line pushes only i + 1,
      // which the list would pop next).
      while (fallsThroughOnly(st(i)) && i + 1 < n_ && !flow_.reachable[static_cast<size_t>(i + 1)]) {
        ++i;
        flow_.reachable[static_cast<size_t>(i)] = 1;
      }
      const Stmt& s = st(i);
      switch (s.kind) {
      case StmtKind::Jump:
        // An unresolved jump (E202/E204 already reported) falls through: no follow-on W404.
        push(f_.jumpOf(s).target >= 0 ? f_.jumpOf(s).target : i + 1);
        break;
      case StmtKind::If:
        push(i + 1);
        if (s.hasJump()) {
          if (f_.jumpOf(s).target >= 0) push(f_.jumpOf(s).target);
        } else if (s.inner >= 0) {
          const Stmt& in = f_.inner[static_cast<size_t>(s.inner)];
          if (in.kind == StmtKind::Jump && f_.jumpOf(in).target >= 0) push(f_.jumpOf(in).target);
        } else {
          int32_t m = flow_.match[static_cast<size_t>(i)];
          if (m >= 0)
            push(m + 1);
          else if (int32_t e = endifOf(i); e >= 0)
            push(e + 1);
        }
        break;
      case StmtKind::Else: {
        int32_t m = flow_.match[static_cast<size_t>(i)];
        push(m >= 0 ? m : i + 1);
        break;
      }
      case StmtKind::Case: {
        bool hasDefault = false;
        for (const CaseArm& arm : f_.armsOf(s)) {
          if (arm.isDefault && arm.jump.target >= 0) hasDefault = true;
          if (arm.jump.target >= 0) push(arm.jump.target);
        }
        if (!hasDefault) push(i + 1);
        break;
      }
      case StmtKind::Block:
        if (!terminal(s)) push(i + 1);
        break;
      case StmtKind::Invalid:
        push(i + 1);
        if (s.recoverAs == StmtKind::If) { // a bad block IF may still skip to its ELSE/ENDIF
          int32_t m = flow_.match[static_cast<size_t>(i)];
          if (m >= 0) push(m + 1);
        }
        break;
      default: push(i + 1); break;
      }
      // A '/' line is skipped when isosim runs with block skip on (SPEC §2): the next line is
      // reachable whatever the line does (`/M17` can leave the end reachable without M17, E206).
      if (s.skippable) push(i + 1);
    }
    reportUnreachable();
    checkUnitEnd();
  }

  /// The line's only successor is the next line (computeReachability's `default` and
  /// non-terminal blocks).
  bool fallsThroughOnly(const Stmt& s) const {
    switch (s.kind) {
    case StmtKind::Empty:
    case StmtKind::EndIf:
    case StmtKind::Call:
    case StmtKind::Proc:
    case StmtKind::Semi:
    case StmtKind::When:
    case StmtKind::Cancel: return true;
    case StmtKind::Block: return !terminal(s);
    default: return false;
    }
  }

  /// W404: runs of unreachable statements. ELSE and ENDIF only mark where a body ends: a
  /// body that ends with M30 or a jump (IF c / GOTOF L / ENDIF) leaves them unreached, which
  /// is no dead code, so a run never starts at them.
  void reportUnreachable() {
    int32_t i = 0;
    while (i < n_) {
      if (flow_.reachable[static_cast<size_t>(i)] || st(i).kind == StmtKind::Empty || st(i).kind == StmtKind::Invalid ||
          st(i).kind == StmtKind::Else || st(i).kind == StmtKind::EndIf) {
        ++i;
        continue;
      }
      int32_t j = i;
      int32_t last = i;
      while (j < n_ && !flow_.reachable[static_cast<size_t>(j)]) {
        if (st(j).kind != StmtKind::Empty) last = j;
        ++j;
      }
      const Stmt& a = st(i);
      const Stmt& b = st(last);
      const Loc at{f_.id, a.line,
                   a.hasN() ? f_.numberOf(a).loc.col : (a.hasLabel() ? f_.labelOf(a).loc.col : a.loc.col)};
      if (last == i)
        diags_.report(Msg::UnreachableLine, at, 1);
      else
        diags_.report(Msg::UnreachableLines, at, 1, a.line, b.lastLine);
      i = j;
    }
  }

  /// E207 M17 in a main program; E206 / W405: the end of the unit reachable without M17 / M30.
  void checkUnitEnd() {
    bool anyM17 = false;
    for (int32_t k = 0; k < n_; ++k) {
      const Stmt& s = st(k);
      bool m17 = hasM(f_, s, lang::kMReturn) ||
                 (s.inner >= 0 && hasM(f_, f_.inner[static_cast<size_t>(s.inner)], lang::kMReturn));
      if (m17) {
        anyM17 = true;
        if (f_.kind != UnitKind::Sub) {
          const Item* it = f_.itemsOf(s.inner >= 0 ? f_.inner[static_cast<size_t>(s.inner)] : s);
          const Stmt& ss = s.inner >= 0 ? f_.inner[static_cast<size_t>(s.inner)] : s;
          Loc at = ss.loc;
          for (uint32_t q = 0; q < ss.itemCount; ++q)
            if (it[q].kind == ItemKind::M && it[q].code == lang::kMReturn) at = it[q].loc;
          diags_.report(Msg::M17InMain, at, 3, lang::kMReturn, unitKindName(f_.kind), lang::kMEnd);
        }
      }
    }
    uint32_t lastLine = n_ > 0 ? st(n_ - 1).lastLine : 1;
    if (n_ > 0 && st(n_ - 1).truncated) return; // the unchecked rest of the last line may end the unit
    if (f_.kind == UnitKind::Sub) {
      if (!anyM17)
        diags_.report(Msg::SubWithoutM17, L(lastLine), 1, lang::kMReturn, lang::kMReturn);
      else if (flow_.endReachable)
        diags_.report(Msg::SubEndWithoutM17, L(lastLine), 1, lang::kMReturn);
    } else if (flow_.endReachable) {
      diags_.report(Msg::MainWithoutEnd, L(lastLine), 1, unitKindName(f_.kind), lang::kMEnd);
    }
  }

  // ---- W411 ---------------------------------------------------------------------------------
  void checkLineNumbers() {
    // SPEC §2: compared as written, so N132,5 and N132.5 (or N10 and N010) are different numbers.
    // File::numbers holds them in statement order. Equal texts have equal values: numbers that
    // strictly increase, as CAM output's do, hold no two alike.
    const auto& nums = f_.numbers;
    if (std::adjacent_find(nums.begin(), nums.end(),
                           [](const LineNumber& a, const LineNumber& b) { return !(a.value < b.value); }) == nums.end())
      return;
    std::unordered_map<std::string_view, uint32_t> seen;
    seen.reserve(nums.size());
    for (uint32_t k = 0; k < nums.size(); ++k) {
      const LineNumber& n = nums[k];
      auto [it, ins] = seen.emplace(n.text, k);
      if (!ins) {
        auto& d = diags_.report(Msg::LineNumberTwice, n.loc, n.len, n.text);
        d.note(Msg::LineNumberTwiceNote, nums[it->second].loc);
      }
    }
  }

  // ---- blocks and values ------------------------------------------------------------------------
  const machine::Axis* axisOf(char a) const {
    const char u = support::upperAscii(a);
    if (u >= 'A' && u <= 'Z') return axisByLetter_[u - 'A'];
    int k = opts_.machine ? opts_.machine->axisIndex(a) : -1;
    return k < 0 ? nullptr : &opts_.machine->axes[static_cast<size_t>(k)];
  }

  void checkExpr(ExprId e, bool wholeRAssignRhs) {
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

  void checkIoIndex(SysVar v, ExprId idx) {
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

  /// (A field added here is compared in BlockState::sameAs too: the split of parseAndCheckFile
  /// relies on it.)
  struct Modal {
    int motion = lang::kInitialMotion; // the modal value of G0..G3
    bool incremental = lang::kInitialIncremental;
    int plane = lang::kInitialPlane; // the modal value of G17..G19
    bool feedSet = false;
    bool feedNotPositive = false; // the last F set is a constant <= 0
    std::array<std::optional<double>, 26> pos{};
  };

public:
  /// What runs from one statement to the next through blockStmt: the modal state and W417/W418's
  /// facts. Two equal states give the same diagnostics on the same statements.
  struct BlockState {
    Modal modal;
    bool sSet = false, tSet = false;
    /// Equal to the bit (-0 is not 0, for it may be printed): the checks run the same from both.
    bool sameAs(const BlockState& o) const {
      const Modal& a = modal;
      const Modal& b = o.modal;
      if (a.motion != b.motion || a.incremental != b.incremental || a.plane != b.plane || a.feedSet != b.feedSet ||
          a.feedNotPositive != b.feedNotPositive || sSet != o.sSet || tSet != o.tSet)
        return false;
      for (size_t k = 0; k < a.pos.size(); ++k) {
        if (a.pos[k].has_value() != b.pos[k].has_value()) return false;
        if (a.pos[k] && std::bit_cast<uint64_t>(*a.pos[k]) != std::bit_cast<uint64_t>(*b.pos[k])) return false;
      }
      return true;
    }
  };
  BlockState blockState() const { return {modal_, sSet_, tSet_}; }
  void setBlockState(const BlockState& s) {
    modal_ = s.modal;
    sSet_ = s.sSet;
    tSet_ = s.tSet;
  }

private:
  void invalidatePositions() { modal_.pos.fill(std::nullopt); }

  /// The modal effect of G`g` (SPEC §4.2); the path group (G60/G64) is not tracked here.
  void applyG(lang::GCode g) {
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
  void applyPartialBlock(const Stmt& s) {
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

  static bool isZWord(const Item& x, const char* addr) {
    return x.kind == ItemKind::ZWord && std::strncmp(x.zaddr, addr, 3) == 0;
  }

  /// z32 (SPEC §4.6): the per-line limits (E312), a special M ending the line (W415), MA/MB/MC
  /// clamped (W416), M3/M4 without S (W417), M6 without T (W418).
  void checkZ32Line(const Stmt& s) {
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
      auto& d =
          diags_.report(Msg::SpindleBothWays, spindle[1]->loc, spindle[1]->len, spindle[0]->code, spindle[1]->code);
      d.note(Msg::SpindleBothWaysNote, spindle[0]->loc, spindle[0]->code);
    }
    if (special) reportSpecialRest(s, *special, specialStep);
  }

  void checkAuxClamp(const Item& x) {
    auto v = constValue(f_, x.value);
    if (!v) return;
    bool clamped = false;
    const int sent = lang::auxSent(*v, &clamped);
    if (clamped)
      diags_.report(Msg::AuxClamped, x.loc, x.len, x.zaddr, formatConstant(*v), sent,
                    fmt::formatted_size("{}", lang::kAuxMax), lang::kAuxSignOffset);
  }

  static std::string formatConstant(double v) { return fmt::format("{}", v); }

  /// W415: what the line order puts after a special M never runs.
  void reportSpecialRest(const Stmt& s, const Item& special, lang::Z32Step step) {
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
        if (x.zaddr[0] != 'M') continue;
        xs = lang::Z32Step::Other;
        name = x.zaddr;
        break;
      case ItemKind::Move:
        xs = lang::Z32Step::Motion;
        name = diag::message(Msg::SpecialMRestMove, x.axis);
        break;
      case ItemKind::G:
        if (!lang::isDwell(x.code)) continue;
        xs = lang::Z32Step::Dwell;
        name = diag::message(Msg::SpecialMRestDwell, x.code);
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
      diags_.report(Msg::SpecialMRestPlural, special.loc, special.len, special.code, *opts_.specialM(special.code),
                    list);
  }

  /// What the items of one block line say, collected in written order (checkBlock).
  struct BlockFacts {
    const Item* gByGroup[lang::kModalGroupCount] = {};
    bool dwell = false;
    const Item* dwellF = nullptr;
    const Item* firstM = nullptr;
    const Item* endM = nullptr;
    // moves and axisFeeds are read only where their mask has the bit: nothing per line to clear
    const Item* moves[26];
    uint32_t moveMask = 0; ///< bit a: moves[a] is set
    int moveCount = 0;
    bool anyPosa = false, anyBlocking = false, anyFa = false;
    const Item* arcCentre[3] = {nullptr, nullptr, nullptr};
    const Item* axisFeeds[26];
    uint32_t axisFeedMask = 0; ///< bit a: axisFeeds[a] is set
    const Item* move(int a) const { return moveMask >> a & 1u ? moves[a] : nullptr; }
    const Item* cr = nullptr;
    const Item* firstFa = nullptr;
    const Item* firstMove = nullptr;
  };

  void blockG(BlockFacts& b, const Item& x) {
    const auto g = lang::findG(x.code);
    if (!g) return; // unknown: E310 already
    applyG(*g);
    if (*g == lang::kDwell) b.dwell = true;
    const auto group = static_cast<size_t>(lang::gGroup(*g));
    if (group >= lang::kModalGroupCount) return;
    if (b.gByGroup[group]) diags_.report(Msg::GConflict, x.loc, x.len, b.gByGroup[group]->code, x.code, x.code);
    b.gByGroup[group] = &x;
  }

  void blockMove(BlockFacts& b, const Item& x) {
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

  void blockFeed(BlockFacts& b, const Stmt& s, const Item& x) {
    if (b.dwell || hasG4(s)) { // in a G04 line F is only the dwell time (SPEC §4.2)
      b.dwellF = &x;
    } else {
      modal_.feedSet = true;
      auto fv = constValue(f_, x.value);
      modal_.feedNotPositive = fv && *fv <= 0;
    }
    checkExpr(x.value, false);
  }

  void blockAxisFeed(BlockFacts& b, const Item& x) {
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

  void blockArcWord(BlockFacts& b, const Item& x) {
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

  void blockM(BlockFacts& b, const Item& x) {
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

  void blockAssign(const Item& x) {
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
  void blockFaAndDwell(const BlockFacts& b, const Stmt& s) {
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

  /// W402 feed unset or <= 0, W403 Pos/Posa mixed, W414 Fa on G00 (a feed move of the block).
  void blockFeedMove(const BlockFacts& b, const Stmt& s) {
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
      if (modal_.motion == lang::kMotionLinear && b.moveCount <= 3 && !b.anyFa && b.anyPosa && b.anyBlocking) {
        diags_.report(Msg::MixedBlocking, s.loc, 1);
      }
    }
    if (modal_.motion == lang::kMotionRapid && b.anyFa && !b.dwell)
      diags_.report(Msg::FaOnRapid, b.firstFa->loc, b.firstFa->len, lang::gNumber(lang::GCode::G0));
  }

  /// W410 soft limits of constant absolute targets, and the positions later lines start from.
  void blockTargets(const BlockFacts& b, bool arcMotion) {
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
  }

  void checkBlock(const Stmt& s) {
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
      }
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

  bool hasG4(const Stmt& s) const {
    const Item* it = f_.itemsOf(s);
    for (uint32_t k = 0; k < s.itemCount; ++k)
      if (it[k].kind == ItemKind::G && lang::isDwell(it[k].code)) return true;
    return false;
  }

  void checkArc(const Stmt& s, const BlockFacts& b) {
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

  void checkStmtValues(const Stmt& s) {
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

  void checkBlocks() {
    startBlocks();
    for (int32_t i = 0; i < n_; ++i)
      blockStmt(st(i));
  }

public:
  /// The values of the statements, in order (the modal state runs through them): startBlocks
  /// once f_.kind is known, then blockStmt for each statement.
  void startBlocks() {
    if (f_.kind != UnitKind::Sub && opts_.machine) {
      for (const auto& ax : opts_.machine->axes)
        modal_.pos[static_cast<size_t>(ax.letter - 'A')] = ax.start;
    }
  }
  void blockStmt(const Stmt& s) {
    if (s.hasLabel() || s.kind == StmtKind::Call || s.kind == StmtKind::Else || s.kind == StmtKind::EndIf ||
        s.kind == StmtKind::When || s.kind == StmtKind::Cancel)
      invalidatePositions();
    checkStmtValues(s);
    if (s.kind == StmtKind::If && s.inner < 0 && !s.hasJump()) invalidatePositions();
  }

private:
  File& f_;
  const SemaOptions& opts_;
  bool sSet_ = false; ///< z32: an S word earlier in the file (W417)
  bool tSet_ = false; ///< z32: a T word earlier in the file (W418)
  diag::DiagnosticList& diags_;
  int32_t n_ = 0;
  FileFlow ownFlow_;
  FileFlow& flow_;
  const machine::Axis* axisByLetter_[26] = {}; ///< the machine's axis of each letter (axisOf)
  /// The labels by name, in any case (collectLabels fills it when every label is known). Their
  /// texts point into the source or File::ownedText, which outlive the checker.
  LabelIndex labels_{f_.labels};
  std::vector<std::pair<int32_t, int32_t>> endifOf_; ///< (block IF, its ENDIF), sorted by IF (matchIfs)
  /// The ENDIF of block IF `i`, or -1.
  int32_t endifOf(int32_t i) const {
    auto it = std::lower_bound(endifOf_.begin(), endifOf_.end(), std::pair<int32_t, int32_t>{i, INT32_MIN});
    return it != endifOf_.end() && it->first == i ? it->second : -1;
  }
  std::vector<std::pair<int32_t, int32_t>> whenBodies_;
  Modal modal_;
};

} // namespace

FileFlow checkFile(File& f, const SemaOptions& opts, diag::DiagnosticList& diags) {
  FileChecker c(f, opts, diags);
  return c.run();
}

namespace {

/// parseAndCheckFile's pass: each statement's values are checked once its line is parsed (in
/// order, as checkFile would: the unit kind is known at the first statement that is not
/// empty), then a top-level block keeps only its M items and gives back its expressions.
class LineChecker {
public:
  LineChecker(File& f, const SemaOptions& o, diag::DiagnosticList& d) : f_(f), blocks_(f, o, d) {}

  void finish() {
    if (!started_) start();
  }

  /// Checks the line just parsed (the file's last statement).
  void line() {
    Stmt& s = f_.stmts.back();
    if (started_) {
      blocks_.blockStmt(s);
      ++checked_;
    } else if (s.kind != StmtKind::Empty) {
      start();
    }
    if (started_) forget(s);
    itemMark_ = f_.items.size();
    exprMark_ = f_.exprs.size();
  }

  /// The unit kind is known (f_.kind), and the next statement starts from `state`: a later part
  /// of a file (parseAndCheckFile's second thread).
  void startWith(const FileChecker::BlockState& state) {
    started_ = true;
    blocks_.setBlockState(state);
  }
  bool started() const { return started_; }
  FileChecker::BlockState state() const { return blocks_.blockState(); }

private:
  void start() {
    f_.kind = classifyUnit(f_);
    blocks_.startBlocks();
    started_ = true;
    for (; checked_ < f_.stmts.size(); ++checked_)
      blocks_.blockStmt(f_.stmts[checked_]);
  }

  /// What later checks read of a checked line: the M items of its blocks (M30/M17 end the
  /// unit, special M call subprograms) and the axes they move (Stmt::movedAxes); a WHEN's
  /// axes are in File::whenAxes. The rest of its items and its expressions are given back.
  void forget(Stmt& s) {
    if (s.kind == StmtKind::Block) keepMItems(s);
    if (s.inner >= 0 && f_.inner[static_cast<size_t>(s.inner)].kind == StmtKind::Block)
      keepMItems(f_.inner[static_cast<size_t>(s.inner)]);
    if (s.kind == StmtKind::Invalid && s.inner < 0) f_.items.resize(itemMark_);
    f_.exprs.resize(exprMark_);
    s.cond = kNoExpr;
  }

  /// Moves the M items of block `b`, the last items of the file, to its front.
  void keepMItems(Stmt& b) {
    Item* first = f_.items.data() + b.firstItem;
    uint32_t kept = 0;
    for (uint32_t k = 0; k < b.itemCount; ++k)
      if (first[k].kind == ItemKind::M) {
        first[kept] = first[k];
        first[kept++].value = kNoExpr;
      }
    b.itemCount = kept;
    f_.items.resize(b.firstItem + kept);
  }

  File& f_;
  FileChecker blocks_;
  bool started_ = false;
  size_t checked_ = 0;  ///< statements whose values are checked
  size_t itemMark_ = 0; ///< items before the current line
  size_t exprMark_ = 0; ///< expressions before the current line
};

// A large file is checked in parts by two threads when two threads are allowed (SplitOptions).
// The parts end at split points, line starts that no logical line crosses. The first thread
// checks the first part; once it has checked SplitOptions::guessAfter statements, the second
// thread starts on the next part, from the modal state the first has then: a guess of the state
// at the part's start. Each thread then takes the next part nobody took, from the same guess,
// until none is left (a slower thread takes fewer). At the join, part after part, the first
// thread checks the part again from the true state at its start (the state at the end of the
// part before) until the state equals the guess's at one of the checkpoints the part recorded:
// from there on both give the same diagnostics, so the part's are kept. The statements come out
// as a single pass would make them (the parser keeps nothing from line to line), and so do the
// diagnostics. If no checkpoint agrees, the part is checked again whole, as one thread would.
constexpr size_t kCheckEvery = 8;     ///< statements between two checkpoints
constexpr size_t kCheckpoints = 512;  ///< checkpoints of a part (its first ~4k statements)
constexpr size_t kSplitSearch = 4096; ///< lines tried after a target offset for a split point

/// `at` can split `text` (Lexer::isSplitPoint): not in a file of lone CRs (lexed whole), so
/// there is another LF before, and the BOM lies behind.
bool canSplitAt(std::string_view text, uint32_t at) {
  return at >= 2 && text.find('\n') < at - 1 && Lexer::isSplitPoint(text, at);
}

/// The first line start from offset `from` on where `text` can be split (0: none near).
uint32_t splitPointFrom(std::string_view text, size_t from) {
  for (size_t tries = 0; tries < kSplitSearch; ++tries) {
    const size_t nl = text.find('\n', from);
    if (nl == std::string_view::npos || nl + 1 >= text.size()) return 0;
    const auto at = static_cast<uint32_t>(nl + 1);
    if (canSplitAt(text, at)) return at;
    from = nl + 1;
  }
  return 0;
}

/// Where the parts of `text` start, after the first (none: one thread checks it all).
std::vector<uint32_t> splitPoints(std::string_view text, const SplitOptions& o) {
  std::vector<uint32_t> out;
  if (o.at != 0) {
    if (canSplitAt(text, o.at)) out.push_back(o.at);
    return out;
  }
  const size_t parts = o.parts ? o.parts : 2;
  for (size_t k = 1; k < parts; ++k) {
    const uint32_t at = splitPointFrom(text, text.size() * k / parts);
    if (at != 0 && (out.empty() || at > out.back())) out.push_back(at);
  }
  return out;
}

/// The state before a statement of a part, as the thread that checked the part had it.
struct Checkpoint {
  size_t stmt = 0; ///< the statement's index in the part
  size_t diag = 0; ///< diagnostics of the part before it
  FileChecker::BlockState state;
};

/// A part of a split file after the first, as a thread parsed and checked it.
struct Part {
  uint32_t begin = 0, end = 0; ///< offsets: [begin, end)
  uint32_t firstLine = 1;
  File file;
  diag::DiagnosticList diags;
  std::vector<Checkpoint> checkpoints;
  FileChecker::BlockState last; ///< the state after its last statement
  std::exception_ptr error;
};

/// A file to hold a part of `f`'s lines.
File partOf(const File& f) {
  File part;
  part.id = f.id;
  part.path = f.path;
  part.kind = f.kind;
  return part;
}

void checkPart(Part& out, std::string_view text, const LexOptions& lex, const SemaOptions& opts,
               const FileChecker::BlockState& guess) {
  try {
    File& g = out.file;
    LineParser lines(g, text, lex, out.diags, /*reserve=*/false);
    lines.setRange(out.begin, out.firstLine, out.end);
    LineChecker check(g, opts, out.diags);
    check.startWith(guess);
    out.checkpoints.reserve(kCheckpoints);
    auto mark = [&] {
      if (out.checkpoints.size() < kCheckpoints && g.stmts.size() % kCheckEvery == 0)
        out.checkpoints.push_back({g.stmts.size(), out.diags.size(), check.state()});
    };
    mark();
    while (lines.parseLine()) {
      check.line();
      mark();
    }
    out.last = check.state();
  } catch (...) {
    out.error = std::current_exception();
  }
}

/// Appends `part` to `f` and its diagnostics to `diags`, checked again from `state` (the true
/// state at its start) until a checkpoint agrees; returns the true state at its end.
FileChecker::BlockState joinPart(File& f, std::string_view text, const LexOptions& lex, const SemaOptions& opts,
                                 diag::DiagnosticList& diags, const FileChecker::BlockState& state, Part& part) {
  File again = partOf(f);
  diag::DiagnosticList againDiags;
  LineParser lines(again, text, lex, againDiags, /*reserve=*/false);
  lines.setRange(part.begin, part.firstLine, part.end);
  LineChecker check(again, opts, againDiags);
  check.startWith(state);
  const std::vector<Checkpoint>& points = part.checkpoints;
  size_t c = 0;
  for (;;) {
    const size_t n = again.stmts.size();
    while (c < points.size() && points[c].stmt < n)
      ++c;
    if (c < points.size() && points[c].stmt == n && check.state().sameAs(points[c].state)) {
      // The rest is as the part's thread checked it; the lines before, as checked again.
      appendPart(f, std::move(part.file), /*twoThreads=*/true);
      diags.append(std::move(againDiags));
      auto& tail = part.diags.items();
      for (size_t k = points[c].diag; k < tail.size(); ++k)
        diags.items().push_back(std::move(tail[k]));
      return part.last;
    }
    if (c == points.size() && !part.file.stmts.empty()) {
      part.file = File{}; // no checkpoint agreed: the part is checked again, whole
      part.diags = {};
    }
    if (!lines.parseLine()) break;
    check.line();
  }
  appendPart(f, std::move(again));
  diags.append(std::move(againDiags));
  return check.state();
}

} // namespace

FileFlow parseAndCheckFile(File& f, std::string_view text, const LexOptions& lex, const SemaOptions& opts,
                           diag::DiagnosticList& diags, unsigned threads, const SplitOptions& splitting) {
  std::vector<uint32_t> starts;
  if (threads >= 2 && text.size() >= splitting.minBytes && text.size() < UINT32_MAX)
    starts = splitPoints(text, splitting);
  const uint32_t split = starts.empty() ? 0 : starts.front(); // where the first part ends
  {
    LineParser lines(f, text, lex, diags);
    LineChecker check(f, opts, diags);
    std::vector<Part> parts(starts.size());
    std::atomic<size_t> nextPart{0};
    std::thread worker;
    struct Joiner {
      std::thread& t;
      ~Joiner() {
        if (t.joinable()) t.join();
      }
    } joiner{worker};
    FileChecker::BlockState guess;
    auto takeParts = [&] {
      for (size_t k = nextPart++; k < parts.size(); k = nextPart++)
        checkPart(parts[k], text, lex, opts, guess);
    };
    bool atSplit = false;
    while (lines.parseLine()) {
      check.line();
      if (split == 0) continue;
      // Started: the unit kind is known. Not past the split: a file whose first statement lies
      // beyond it is checked whole.
      const uint32_t at = lines.nextOffset();
      if (!worker.joinable() && check.started() && at <= split &&
          (f.stmts.size() >= splitting.guessAfter || at == split)) {
        // Each part's statements go right after the room the parts before can take: one per
        // physical line at most (those joined by `$` leave a gap, closed by appendPart).
        size_t before = support::countByte(text.substr(0, split), '\n');
        for (size_t k = 0; k < parts.size(); ++k) {
          Part& p = parts[k];
          p.begin = starts[k];
          p.end = k + 1 < parts.size() ? starts[k + 1] : static_cast<uint32_t>(text.size());
          p.firstLine = static_cast<uint32_t>(before + 1);
          p.file = partOf(f);
          before += support::countByte(text.substr(p.begin, p.end - p.begin), '\n');
        }
        const size_t total = before + 1;
        if (f.stmts.capacity() < total) {
          f.stmts.reserve(total);
          support::adviseHugePages(f.stmts.data(), f.stmts.capacity() * sizeof(Stmt));
        }
        f.numbers.reserve(total); // at most one per statement: the same rooms
        for (size_t k = 0; k < parts.size(); ++k) {
          const size_t base = parts[k].firstLine - 1;
          const size_t room = (k + 1 < parts.size() ? parts[k + 1].firstLine - 1 : total) - base;
          parts[k].file.stmts = StmtArray::inside(f.stmts.data() + base, room);
          parts[k].file.numbers = InPlaceArray<LineNumber>::inside(f.numbers.data() + base, room);
        }
        guess = check.state();
        worker = std::thread(takeParts);
      }
      if (worker.joinable() && at == split) {
        atSplit = true;
        break;
      }
    }
    if (worker.joinable()) {
      // (A first part that read past the split, which a split point rules out, read the whole
      // file: the other parts are dropped.)
      if (atSplit) takeParts();
      worker.join();
      if (atSplit) {
        FileChecker::BlockState state = check.state();
        for (Part& p : parts) {
          if (p.error) std::rethrow_exception(p.error);
          state = joinPart(f, text, lex, opts, diags, state, p);
        }
        f.splitAt = split;
      }
    }
    check.finish(); // f.kind is set (LineChecker::start)
  }
  FileChecker c(f, opts, diags);
  return c.run(/*blocksChecked=*/true, /*twoThreads=*/split != 0);
}

// ---- set level ---------------------------------------------------------------------------------

namespace {

/// A call (or z32 special M) of a subprogram: the callee's file index and where it is made.
struct CallSite {
  size_t callee;
  Loc loc;
  int64_t m = -1; ///< z32: the special M that makes the call
};

using CallGraph = std::vector<std::vector<CallSite>>;
using ProcIndex = std::unordered_map<std::string, size_t>;

/// E209: unique subprogram names; returns the upper-case name -> file index.
ProcIndex indexProcs(const std::vector<File>& files, diag::DiagnosticList& diags) {
  // E209: unique subprogram names
  ProcIndex procs;
  for (size_t i = 0; i < files.size(); ++i) {
    const File& f = files[i];
    if (f.kind != UnitKind::Sub || f.procName.empty()) continue;
    auto [it, ins] = procs.emplace(support::upperCopy(f.procName), i);
    if (!ins) {
      const Stmt* h = nullptr;
      for (const Stmt& s : f.stmts)
        if (s.kind == StmtKind::Proc) {
          h = &s;
          break;
        }
      const File& first = files[it->second];
      const Stmt* h0 = nullptr;
      for (const Stmt& s : first.stmts)
        if (s.kind == StmtKind::Proc) {
          h0 = &s;
          break;
        }
      auto& d =
          diags.report(Msg::ProcTwice, h ? f.nameOf(*h).loc : Loc{f.id, 1, 1}, h ? f.nameOf(*h).len : 1, f.procName);
      if (h0) d.note(Msg::ProcTwiceNote, first.nameOf(*h0).loc);
    }
  }
  return procs;
}

/// The calls of each file (E210 for unknown names, E110 for other dialects' words).
CallGraph buildCallGraph(std::vector<File>& files, const ProcIndex& procs, const SemaOptions& opts,
                         diag::DiagnosticList& diags) {
  std::vector<std::vector<CallSite>> calls(files.size());
  for (size_t i = 0; i < files.size(); ++i) {
    File& f = files[i];
    auto onSpecial = [&](const Item& x, const std::string& name) {
      auto p = procs.find(support::upperCopy(name));
      if (p == procs.end()) {
        diags.report(Msg::SpecialMUnknownProc, x.loc, x.len, x.code, opts.machine->name, name);
        return;
      }
      calls[i].push_back({p->second, x.loc, x.code});
    };
    auto onCall = [&](const Stmt& s) {
      const StmtName& name = f.nameOf(s);
      auto it = procs.find(support::upperCopy(name.text));
      if (it == procs.end()) {
        if (auto msg = unsupportedNameMessage(name.text, opts.dialect)) {
          auto& d = diags.report(diag::codeOf(Msg::UnsupportedName), name.loc, name.len, std::move(*msg));
          // RET and ENDPROC end a subprogram: the SIDAC way is M17, one for one. Elsewhere
          // (a main program, after THEN) M17 would be an error of its own: no fix.
          const auto* u = lang::findUnsupportedName(name.text);
          if (f.kind == UnitKind::Sub && !s.isInner && !name.joined && u && !u->replacement.empty())
            d.fixes.push_back({diag::message(Msg::UnsupportedReplaceFix, name.text, u->replacement),
                               {{name.loc, name.loc.line, name.loc.col + name.len, std::string(u->replacement)}}});
          return;
        }
        diags.report(Msg::ProcUnknown, name.loc, name.len, name.text);
        return;
      }
      calls[i].push_back({it->second, name.loc});
    };
    forEachCall(f, opts.specialMap(), onCall, onSpecial);
  }
  return calls;
}

/// W409 recursion and E211 depth below each main and semi-automatic program.
void checkDepth(const std::vector<File>& files, const CallGraph& calls, const SemaOptions& opts,
                diag::DiagnosticList& diags) {
  // longest chain of calls below each unit (memoised DFS)
  const size_t n = files.size();
  std::vector<int> state(n, 0);    // 0 new, 1 on stack, 2 done
  std::vector<int> depth(n, 0);    // nested calls below this unit along the longest chain
  std::vector<int> nextHop(n, -1); // index into calls[i] of the longest chain's first call
  std::vector<uint8_t> recursionReported(n, 0);
  // Iterative: a chain of thousands of subprograms must not exhaust the stack.
  struct Frame {
    size_t unit;
    size_t next; ///< index into calls[unit] of the next call to follow
  };
  std::vector<Frame> stack;
  auto dfs = [&](size_t root) {
    state[root] = 1;
    stack.push_back({root, 0});
    while (!stack.empty()) {
      Frame& fr = stack.back();
      size_t u = fr.unit;
      if (fr.next == calls[u].size()) {
        state[u] = 2;
        stack.pop_back();
        if (!stack.empty()) { // the caller's call that led here is done: fold its depth
          Frame& caller = stack.back();
          size_t k = caller.next - 1;
          if (depth[u] + 1 > depth[caller.unit]) {
            depth[caller.unit] = depth[u] + 1;
            nextHop[caller.unit] = static_cast<int>(k);
          }
        }
        continue;
      }
      size_t k = fr.next++;
      size_t v = calls[u][k].callee;
      if (state[v] == 1) {
        if (!recursionReported[u]) {
          recursionReported[u] = 1;
          diags.report(Msg::Recursion, calls[u][k].loc, 1, files[v].procName);
        }
        continue;
      }
      if (state[v] == 0) {
        state[v] = 1;
        stack.push_back({v, 0}); // invalidates fr
        continue;
      }
      if (depth[v] + 1 > depth[u]) {
        depth[u] = depth[v] + 1;
        nextHop[u] = static_cast<int>(k);
      }
    }
  };
  // Main and semi-automatic programs first, so that a cycle is reported at the call that
  // leads back up the chain as seen from the program that runs it.
  for (size_t i = 0; i < n; ++i)
    if (state[i] == 0 && files[i].kind != UnitKind::Sub) dfs(i);
  for (size_t i = 0; i < n; ++i)
    if (state[i] == 0) dfs(i);
  int limit = opts.maxNesting();
  for (size_t i = 0; i < n; ++i) {
    if (files[i].kind == UnitKind::Sub) continue; // chains are counted below main and semi programs
    if (depth[i] <= limit) continue;
    const CallSite& first = calls[i][static_cast<size_t>(nextHop[i])];
    auto& d = diags.report(Msg::NestingTooDeep, first.loc, 1, depth[i], limit);
    size_t u = i;
    int level = 0;
    while (nextHop[u] >= 0 && level < 64) {
      const CallSite& cs = calls[u][static_cast<size_t>(nextHop[u])];
      ++level;
      if (cs.m >= 0)
        d.note(Msg::NestingLevelSpecialNote, cs.loc, level, cs.m, files[cs.callee].procName);
      else
        d.note(Msg::NestingLevelNote, cs.loc, level, files[cs.callee].procName);
      u = cs.callee;
    }
  }
}

} // namespace

void checkSet(std::vector<File>& files, const SemaOptions& opts, diag::DiagnosticList& diags) {
  const ProcIndex procs = indexProcs(files, diags);
  const CallGraph calls = buildCallGraph(files, procs, opts, diags);
  checkDepth(files, calls, opts, diags);
}

} // namespace iso::frontend
