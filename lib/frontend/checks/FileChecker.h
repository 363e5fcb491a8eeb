//! @file FileChecker.h
//! @brief The per-file checker, private to the frontend: one class whose passes live in one
//!        file per section of this folder (the section comments below name the file and the
//!        diagnostics it reports). checkFile (Sema.cpp) and parseAndCheckFile (FilePipeline.cpp)
//!        are its only users; it never parses.
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <climits>
#include <cstdint>
#include <optional>
#include <string_view>
#include <utility>
#include <vector>

#include "diag/Diagnostic.h"
#include "frontend/Ast.h"
#include "frontend/Sema.h"
#include "frontend/checks/LabelIndex.h"
#include "lang/GCodes.h"
#include "lang/MFunctions.h"
#include "lang/Z32GCodes.h"
#include "machine/Machine.h"
#include "support/CaseFold.h"

namespace iso::frontend::checks {

/// Block `s` has M`code` (not M=NB).
inline bool hasM(const File& f, const Stmt& s, int code) {
  if (s.kind != StmtKind::Block) return false;
  const Item* it = f.itemsOf(s);
  for (uint32_t k = 0; k < s.itemCount; ++k)
    if (it[k].kind == ItemKind::M && !it[k].nb && it[k].code == code) return true;
  return false;
}

/// The statement's kind, or for a line that failed to parse the structural role its keyword
/// announced (IF/ELSE/ENDIF/WHEN/CANCEL), so that one bad line gives no follow-on errors.
inline bool isKind(const Stmt& s, StmtKind k) {
  return s.kind == k || (s.kind == StmtKind::Invalid && s.recoverAs == k);
}

class FileChecker {
  /// The modal state the values of a statement are checked in. (A field added here is
  /// compared in BlockState::sameAs too: the split of parseAndCheckFile relies on it.)
  struct Modal {
    int motion = lang::kInitialMotion; // the modal value of G0..G3
    bool incremental = lang::kInitialIncremental;
    int plane = lang::kInitialPlane; // the modal value of G17..G19
    bool feedSet = false;
    bool feedNotPositive = false; // the last F set is a constant <= 0
    double highFeed = 0;          // W422: the last F set, a constant above every max_velocity, not yet
                                  // reported at a feed move (0: none)
    Loc highFeedLoc{};            // W422: that F word
    uint32_t highFeedLen = 0;
    std::array<std::optional<double>, 26> pos{};
  };

public:
  FileChecker(File& f, const SemaOptions& o, diag::DiagnosticList& d) : FileChecker(f, o, d, nullptr) {}

  /// Every check of the file (FileChecker.cpp). `blocksChecked`: the values of every statement
  /// were checked as the file was parsed (startBlocks, blockStmt), so only the checks of the
  /// file as a whole remain. `twoThreads`: the passes that do not depend on each other run two
  /// at a time (the same diagnostics; they are sorted by place before anyone sees them).
  FileFlow run(bool blocksChecked = false, bool twoThreads = false);

  /// What runs from one statement to the next through blockStmt: the modal state and W417/W418's
  /// facts. Two equal states give the same diagnostics on the same statements.
  struct BlockState {
    Modal modal;
    bool sSet = false, tSet = false;
    std::vector<int> notModelledSeen; ///< z32: the codes W420 has named (once per code and file)
    /// Equal to the bit (-0 is not 0, for it may be printed): the checks run the same from both.
    bool sameAs(const BlockState& o) const {
      const Modal& a = modal;
      const Modal& b = o.modal;
      if (a.motion != b.motion || a.incremental != b.incremental || a.plane != b.plane || a.feedSet != b.feedSet ||
          a.feedNotPositive != b.feedNotPositive || a.highFeed != b.highFeed ||
          a.highFeedLoc.line != b.highFeedLoc.line || a.highFeedLoc.col != b.highFeedLoc.col ||
          a.highFeedLen != b.highFeedLen || sSet != o.sSet || tSet != o.tSet || notModelledSeen != o.notModelledSeen)
        return false;
      for (size_t k = 0; k < a.pos.size(); ++k) {
        if (a.pos[k].has_value() != b.pos[k].has_value()) return false;
        if (a.pos[k] && std::bit_cast<uint64_t>(*a.pos[k]) != std::bit_cast<uint64_t>(*b.pos[k])) return false;
      }
      return true;
    }
  };
  BlockState blockState() const { return {modal_, sSet_, tSet_, notModelledSeen_}; }
  void setBlockState(const BlockState& s) {
    modal_ = s.modal;
    sSet_ = s.sSet;
    tSet_ = s.tSet;
    notModelledSeen_ = s.notModelledSeen;
  }

  /// The values of the statements, in order (the modal state runs through them): startBlocks
  /// once f_.kind is known, then blockStmt for each statement (Blocks.cpp).
  void startBlocks();
  void blockStmt(const Stmt& s);

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

  // ---- the passes on two threads (FileChecker.cpp) ---------------------------------------------
  void runInTwo();
  template <class Help, class Work> static void besideHelper(Help help, Work work);

  // ---- headers: E208 (Headers.cpp) -------------------------------------------------------------
  void checkHeaders();

  // ---- labels: E203 (Labels.cpp) ---------------------------------------------------------------
  void collectLabels();
  int32_t findLabel(std::string_view name) const;

  // ---- IF / ELSE / ENDIF: E201 (IfBlocks.cpp) --------------------------------------------------
  /// The block IFs open at a statement, and the ELSE of each (-1: none yet).
  struct OpenIfs {
    std::vector<int32_t> stack; // If indices
    std::vector<int32_t> elseOf;
  };
  void matchIf(OpenIfs& open, int32_t i, const Stmt& s);
  void finishIfs(const OpenIfs& open);
  void matchIfsAndResolveJumps();

  // ---- jumps: E202, E204, E205, W408, W413, W412 and jumps into WHEN bodies (Jumps.cpp) --------
  void resolveJump(Jump& j, int32_t from, bool isCase);
  void resolveJumpsOf(int32_t i, Stmt& s);
  void checkJumpsIntoBlocks();
  // GoJumps.cpp: z32 GO jumps and ranges (E215)
  void resolveGos();
  int32_t resolveGoTarget(std::string_view text, const Loc& loc, uint32_t len, int32_t rangeStart);
  int32_t stmtAtLine(uint32_t line) const;

  // ---- WHEN: E212, E213 (When.cpp) -------------------------------------------------------------
  /// What a WHEN body may not hold (E212): a label, a jump, a CASE, a call, another WHEN, an
  /// M that ends the unit (`m`), a special M.
  enum class Forbidden : uint8_t { None, Label, Jump, Case, Call, When, EndM, SpecialM, Kg, Return };
  struct BodyCheck {
    Forbidden what = Forbidden::None;
    int32_t m = 0; ///< EndM: the M number
  };
  BodyCheck bodyForbidden(const File& f, const Stmt& s) const;
  void reportForbidden(const Loc& at, BodyCheck c);
  void checkTriggerAxis(int32_t whenIdx, const Stmt& trigger);
  void checkWhens();
  int32_t checkWhenChain(const std::vector<int32_t>& chain, std::vector<const Stmt*>& bodies, int32_t j);

  // ---- control flow: W404, W405, E206, E207 (ControlFlow.cpp) ----------------------------------
  bool terminal(const Stmt& s) const;
  const Item* z32Return(const Stmt& s) const; ///< z32: the line's G26, or nullptr
  bool hasKg(const Stmt& s) const;            ///< z32: the line ends with KG<name>
  void computeReachability();
  bool fallsThroughOnly(const Stmt& s) const;
  void reportUnreachable();
  void checkUnitEnd();

  // ---- N numbers: W411 (LineNumbers.cpp) -------------------------------------------------------
  void checkLineNumbers();

  // ---- blocks and values (Blocks.cpp; z32 lines in Z32Lines.cpp, arcs in Arcs.cpp) -------------
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
  void checkExpr(ExprId e, bool wholeRAssignRhs);
  void checkIoIndex(SysVar v, ExprId idx);
  void invalidatePositions() { modal_.pos.fill(std::nullopt); }
  void applyG(lang::GCode g);
  void applyPartialBlock(const Stmt& s);
  void blockG(BlockFacts& b, const Item& x);
  void blockMove(BlockFacts& b, const Item& x);
  void blockFeed(BlockFacts& b, const Stmt& s, const Item& x);
  void blockAxisFeed(BlockFacts& b, const Item& x);
  void blockArcWord(BlockFacts& b, const Item& x);
  void blockM(BlockFacts& b, const Item& x);
  void blockAssign(const Item& x);
  void blockFaAndDwell(const BlockFacts& b, const Stmt& s);
  void blockFeedMove(const BlockFacts& b, const Stmt& s);
  void blockTargets(const BlockFacts& b, bool arcMotion);
  void blockZones(const BlockFacts& b);
  void checkBlock(const Stmt& s);
  bool hasG4(const Stmt& s) const;
  void checkStmtValues(const Stmt& s);
  void checkBlocks();
  void checkZ32Line(const Stmt& s);
  void checkAuxClamp(const Item& x);
  void reportSpecialRest(const Stmt& s, const Item& special, lang::Z32Step step);
  void checkArc(const Stmt& s, const BlockFacts& b);

  // ---- shared by the sections ------------------------------------------------------------------
  Loc L(uint32_t line, uint32_t col = 1) const { return Loc{f_.id, line, col}; }
  const Stmt& st(int32_t i) const { return f_.stmts[static_cast<size_t>(i)]; }
  bool isZ32() const { return opts_.dialect == machine::Dialect::Z32; }
  /// z32: the first special M of a block (blocking), or nullptr.
  const Item* specialOn(const Stmt& s) const {
    if (!isZ32() || s.kind != StmtKind::Block) return nullptr;
    const Item* it = f_.itemsOf(s);
    for (uint32_t k = 0; k < s.itemCount; ++k)
      if (it[k].kind == ItemKind::M && !it[k].nb && opts_.specialM(it[k].code)) return &it[k];
    return nullptr;
  }
  const machine::Axis* fastestAxis() const;
  void reportHighFeed(const Item& move);
  const machine::Axis* axisOf(char a) const {
    const char u = support::upperAscii(a);
    if (u >= 'A' && u <= 'Z') return axisByLetter_[u - 'A'];
    int k = opts_.machine ? opts_.machine->axisIndex(a) : -1;
    return k < 0 ? nullptr : &opts_.machine->axes[static_cast<size_t>(k)];
  }
  /// The ENDIF of block IF `i`, or -1.
  int32_t endifOf(int32_t i) const {
    auto it = std::lower_bound(endifOf_.begin(), endifOf_.end(), std::pair<int32_t, int32_t>{i, INT32_MIN});
    return it != endifOf_.end() && it->first == i ? it->second : -1;
  }

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
  std::vector<std::pair<int32_t, int32_t>> whenBodies_;
  Modal modal_;
  std::vector<int> notModelledSeen_; ///< z32: the codes W420 has named in this file
  void blockZ32Item(const Item& x);  ///< z32: W420, E313, the axes of G28/G29
};

} // namespace iso::frontend::checks
