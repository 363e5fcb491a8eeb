//! @file Ast.h
//! @brief The syntax tree of one source file: statements per logical line, pooled items and
//!        expressions (indices, not pointers, so a file's tree is a few flat vectors).
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <forward_list>
#include <functional>
#include <new>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "diag/Diagnostic.h"
#include "lang/SysVars.h"
#include "lang/UnitKind.h"

namespace iso::frontend {

using diag::Loc;

using UnitKind = lang::UnitKind;
const char* unitKindName(UnitKind k);

/// System variables of SPEC §3.3 (lang/SysVars.def).
using lang::SysVar;
/// The canonical spelling ("$aa_iw").
const char* sysVarName(SysVar v);
inline bool sysVarTakesAxis(SysVar v) { return lang::sysVarInfo(v).takesAxis; }
/// $MAX_VELO and $POS_LIMIT_*: machine data, legal only as the whole right side of R = .
inline bool sysVarIsMachineData(SysVar v) { return lang::sysVarInfo(v).machineData; }
inline bool sysVarIsRealTime(SysVar v) { return lang::sysVarInfo(v).realTime; }

using ExprId = int32_t;
constexpr ExprId kNoExpr = -1;

enum class ExprKind : uint8_t {
  Number,    ///< value
  RParam,    ///< rIndex (constant index)
  RIndirect, ///< R[a]
  SysAxis,   ///< sysvar[axis]
  SysIndex,  ///< sysvar[a]
  Neg,       ///< -a
  Binary,    ///< a op b, op in + - * /  (strictly left to right)
  Compare,   ///< a op b, op in > < == >= <= <>
  Logic,     ///< a op b, op in AND OR
  Not,       ///< NOT a
  Par,       ///< z32: PAR[a] (index 0..999)
  Pal,       ///< z32: PAL[a] (index 0..255), shared with the PLC
  UserParam, ///< z32: a user parameter address (HA): rIndex = its index in machine->parameters
  Error,     ///< placeholder after a syntax error
};

enum class BinOp : uint8_t { Add, Sub, Mul, Div };
enum class CmpOp : uint8_t { Gt, Lt, Eq, Ge, Le, Ne };
enum class LogicOp : uint8_t { And, Or };
const char* cmpOpText(CmpOp op);

/// An underline length as an expression stores it. A parsed line has at most 240 characters
/// (longer ones are E102 and not parsed), so this only guards the type: longer spans would
/// underline their first 65,535 bytes.
constexpr uint16_t clampLen(uint32_t len) {
  return len > UINT16_MAX ? uint16_t{UINT16_MAX} : static_cast<uint16_t>(len);
}

// 40 bytes: a CAM program has several expressions per line, most of them constants. (Packing
// it to 36 would leave `value` misaligned.)
struct Expr {
  ExprKind kind = ExprKind::Error;
  uint8_t op = 0; ///< BinOp / CmpOp / LogicOp
  SysVar sysvar = SysVar::AaIw;
  bool paren = false;  ///< written inside ( ) (the group itself)
  bool isBool = false; ///< Compare, Logic, Not (or a group of one)
  char axis = 0;       ///< SysAxis: upper-case letter
  uint16_t len = 1;    ///< clampLen
  ExprId a = kNoExpr;
  ExprId b = kNoExpr;
  union {
    double value = 0; ///< Number
    int32_t rIndex;   ///< RParam
  };
  Loc loc;
};

enum class ItemKind : uint8_t {
  G,        ///< code
  Move,     ///< axis, mode, value
  Feed,     ///< F: value
  AxisFeed, ///< Fa[axis]: value
  ArcI,
  ArcJ,
  ArcK,
  ArcCR,       ///< value
  M,           ///< code, nb
  AssignR,     ///< target (RParam/RIndirect expr) = value
  AssignIo,    ///< sysvar (AaOut/AaMarker), target = index expr, value
  ZWord,       ///< dialect z32: S T TA TB MA MB MC O words (zaddr; value)
  Kg,          ///< z32: KG<name>: code = its name's index in File::names
  AxisControl, ///< z32: G28 (code 28) / G29 (code 29); target = bit mask of the named axes (bit k = 'A'+k; 0 = all)
  AssignP,     ///< z32: target (a Par, Pal or UserParam expr) = value
};

enum class MoveMode : uint8_t { Word, Assign, Pos, Posa };

struct Item {
  ItemKind kind = ItemKind::G;
  MoveMode mode = MoveMode::Word;
  SysVar sysvar = SysVar::AaOut;
  bool nb = false; ///< M=NB(n)
  char axis = 0;   ///< Move/AxisFeed: upper-case letter
  char zaddr[3] = {0, 0, 0};
  int32_t code = 0; ///< G/M number
  ExprId target = kNoExpr;
  ExprId value = kNoExpr;
  Loc loc;
  uint32_t len = 1;
};

/// Calls `f(letter)` for each axis letter a G28/G29 item names, A to Z (none for "every axis").
template <class F> void forEachControlledAxis(const Item& x, F&& f) {
  const auto mask = static_cast<uint32_t>(x.target);
  for (int b = 0; b < 26; ++b)
    if ((mask >> b) & 1u) f(static_cast<char>('A' + b));
}

enum class StmtKind : uint8_t {
  Empty, ///< blank, comment-only or label-only line
  Block, ///< items
  If,    ///< cond; form: block IF, THEN simple (inner), or jump
  Else,
  EndIf,
  Jump, ///< jump
  Case, ///< cond = selector expr; arms
  When, ///< cond; inner >= 0 for the short form
  Cancel,
  Call,    ///< name (z32: also GOP<name>)
  Go,      ///< z32: GO<target> or GO<a>-<b> alone on its line: File::gos
  Proc,    ///< name, save
  Semi,    ///< name (display string)
  Invalid, ///< a line with a syntax error (already reported)
};

enum class JumpKind : uint8_t { Gotof, Gotob, Goto };
const char* jumpKindName(JumpKind k);

struct Jump {
  JumpKind kind = JumpKind::Gotof;
  std::string_view label; ///< as written
  Loc loc;                ///< of the label name
  uint32_t len = 1;
  Loc kwLoc;           ///< of the GOTO keyword
  int32_t target = -1; ///< statement index, resolved by Sema
};

/// A z32 GO jump or GO range (File::gos, File::goOf).
struct GoJump {
  bool range = false;        ///< GO<a>-<b>
  std::string_view from, to; ///< the target texts as written ("N12", "%N1"); `to` for a range
  Loc fromLoc, toLoc;        ///< of each target text
  uint32_t fromLen = 1, toLen = 1;
  int32_t target = -1;   ///< statement index of the line found for `from`, resolved by Sema
  int32_t rangeEnd = -1; ///< a range: statement index of the line found for `to`
};

struct CaseArm {
  double value = 0;
  bool isDefault = false;
  Loc valueLoc;
  Jump jump;
};

/// The N number of a statement, as written (File::numbers, File::numberOf).
struct LineNumber {
  uint32_t stmt = 0;     ///< index of its statement in File::stmts
  std::string_view text; ///< W411 compares these (N132,5 is not N132.5)
  Loc loc;
  uint32_t len = 1;
  double value = 0;
};

/// The label of a statement ("L4:"): File::labels, File::labelOf.
struct StmtLabel {
  uint32_t stmt = 0;     ///< index of its statement in File::stmts
  std::string_view text; ///< as written
  Loc loc;
};

/// The name of a Call, Proc or Semi statement (File::names, File::nameOf).
struct StmtName {
  std::string_view text;
  Loc loc;
  uint32_t len = 1;
  bool joined = false; ///< the name crosses a `$` continuation join
};

constexpr uint32_t kNoIndex = UINT32_MAX;

/// Which side table Stmt::partIdx points into: a statement has at most one of these parts.
enum class StmtPart : uint8_t {
  None,
  Jump, ///< File::jumps: a Jump, or an If with a jump
  Name, ///< File::names: Call, Proc, Semi
  Arms, ///< File::armRanges: Case
  Go,   ///< File::gos: z32 GO jumps and ranges
};

/// The arms of one CASE statement in File::arms.
struct ArmRange {
  uint32_t first = 0, count = 0;
};

/// One logical line. The parts few lines have (N number, label, jump, name) live in the File's
/// side tables and are reached with File::numberOf / labelOf / jumpOf / nameOf / armsOf: a CAM
/// program of millions of lines keeps a 52-byte record per line.
struct Stmt {
  StmtKind kind = StmtKind::Empty;
  /// Invalid only: the structural role the line's keyword announced (If for a block IF, When
  /// for a long-form WHEN, Else, EndIf, Cancel), so that Sema matches IF/ENDIF and WHEN/CANCEL
  /// without follow-on errors; Invalid when there is none.
  StmtKind recoverAs = StmtKind::Invalid;
  StmtPart part = StmtPart::None; ///< what partIdx points to
  bool skippable : 1 = false;     ///< "/" prefix
  bool procSave : 1 = false;
  bool isInner : 1 = false; ///< the simple statement of IF..THEN / WHEN..DO
  /// Block only: the line had an error (reported); its items are the valid ones, kept so that
  /// their modal effects (G, F) are not lost, but the block as a whole is not checked.
  bool partial : 1 = false;
  /// The line was not analysed to its end (E102, CR-only line ends): it may hold anything.
  bool truncated : 1 = false;
  bool numbered : 1 = false;             ///< an N number (File::numberOf; top-level statements only)
  bool labelled : 1 = false;             ///< a label (File::labelOf; top-level statements only)
  uint32_t line = 0;                     ///< first physical line
  uint32_t lastLine = 0;                 ///< last physical line ($ continuation)
  Loc loc;                               ///< where the statement proper starts
  uint32_t firstItem = 0, itemCount = 0; ///< Block
  ExprId cond = kNoExpr;                 ///< If, When (condition); Case (selector)
  int32_t inner = -1;                    ///< If THEN / When DO short form: index into File::inner
  uint32_t partIdx = kNoIndex;           ///< File::jumps, names or armRanges (`part`)
  /// Block: bit `a` set when the line moves axis 'A' + a by a word, `=`, POS (movedAxes) or by
  /// POSA (posaAxes). Later checks (WHEN triggers) read these, not the items: isolint keeps only
  /// the M items of a line it has checked (SemaOptions, parseAndCheckFile).
  uint32_t movedAxes = 0, posaAxes = 0;

  bool hasN() const { return numbered; }
  bool hasLabel() const { return labelled; }
  bool hasJump() const { return part == StmtPart::Jump; } ///< If with a jump, or Jump
  bool hasMotion() const { return kind == StmtKind::Block && (movedAxes | posaAxes) != 0; }
};

/// File::stmts and File::numbers: an array like std::vector<T> of trivially copyable records.
/// It can also start inside the storage of another file's array (inside): parseAndCheckFile's
/// threads write the records of the later parts of a file where they will stay, after the room
/// the parts before can take, so that joining the parts copies nothing. Such an array does not
/// own its storage; if it outgrows its room, it moves to storage of its own.
template <class T> class InPlaceArray {
  static_assert(std::is_trivially_copyable_v<T>, "InPlaceArray moves its records as bytes");

public:
  using value_type = T;
  InPlaceArray() = default;
  ~InPlaceArray() { release(); }
  InPlaceArray(const InPlaceArray& o) { *this = o; }
  InPlaceArray& operator=(const InPlaceArray& o) {
    if (this == &o) return *this;
    size_ = 0;
    reserve(o.size_);
    if (o.size_) std::memcpy(static_cast<void*>(data_), o.data_, o.size_ * sizeof(T));
    size_ = o.size_;
    return *this;
  }
  InPlaceArray(InPlaceArray&& o) noexcept { *this = std::move(o); }
  InPlaceArray& operator=(InPlaceArray&& o) noexcept {
    if (this == &o) return *this;
    release();
    data_ = std::exchange(o.data_, nullptr);
    size_ = std::exchange(o.size_, 0);
    cap_ = std::exchange(o.cap_, 0);
    owned_ = std::exchange(o.owned_, true);
    return *this;
  }

  /// An empty array that fills [at, at + room) of storage that outlives it and stays put.
  static InPlaceArray inside(T* at, size_t room) {
    InPlaceArray a;
    a.data_ = at;
    a.cap_ = room;
    a.owned_ = false;
    return a;
  }
  bool ownsStorage() const { return owned_; }

  size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  size_t capacity() const { return cap_; }
  T* data() { return data_; }
  const T* data() const { return data_; }
  T* begin() { return data_; }
  T* end() { return data_ + size_; }
  const T* begin() const { return data_; }
  const T* end() const { return data_ + size_; }
  T& operator[](size_t i) { return data_[i]; }
  const T& operator[](size_t i) const { return data_[i]; }
  const T& at(size_t i) const {
    if (i >= size_) throw std::out_of_range("InPlaceArray::at");
    return data_[i];
  }
  T& front() { return data_[0]; }
  const T& front() const { return data_[0]; }
  T& back() { return data_[size_ - 1]; }
  const T& back() const { return data_[size_ - 1]; }

  /// A new record at the end, as T{} makes it.
  T& emplace_back() {
    if (size_ == cap_) grow(size_ + 1);
    return *new (data_ + size_++) T();
  }
  void push_back(const T& x) {
    const T copy = x; // `x` may be one of ours, and growing moves them
    emplace_back() = copy;
  }
  void reserve(size_t n) {
    if (n > cap_) grow(n);
  }
  void clear() { size_ = 0; }
  /// The first `n` records stay (n <= size()), or the caller wrote records up to `n` into the
  /// storage (n <= capacity()).
  void setSize(size_t n) {
    if (n > cap_) throw std::length_error("InPlaceArray::setSize");
    size_ = n;
  }

private:
  /// Storage of its own for at least `need`.
  void grow(size_t need) {
    const size_t cap = std::max<size_t>({need, cap_ * 2, 16});
    if (cap > SIZE_MAX / sizeof(T)) throw std::bad_alloc();
    auto* p = static_cast<T*>(std::malloc(cap * sizeof(T)));
    if (!p) throw std::bad_alloc();
    if (size_) std::memcpy(static_cast<void*>(p), data_, size_ * sizeof(T));
    if (owned_) std::free(data_);
    data_ = p;
    cap_ = cap;
    owned_ = true;
  }
  void release() {
    if (owned_) std::free(data_);
    data_ = nullptr;
    size_ = cap_ = 0;
    owned_ = true;
  }
  T* data_ = nullptr;
  size_t size_ = 0;
  size_t cap_ = 0;
  bool owned_ = true;
};

using StmtArray = InPlaceArray<Stmt>;

/// The axes whose $AA_IW a WHEN condition reads, in the order written (File::whenAxes).
struct WhenAxes {
  uint32_t stmt = 0;  ///< index of the WHEN in File::stmts
  uint32_t first = 0; ///< its letters in File::whenAxisLetters: upper-case, repeated as often as read
  uint32_t count = 0;
};

/// Inline suppressions from "; isolint: disable=CODE[,CODE]" (line) and "disable-file=".
struct Suppression {
  uint32_t line = 0; ///< first physical line of the logical line; 0 = whole file
  diag::Code code = diag::Code::Syntax;
  uint32_t lastLine = 0;    ///< last physical line of the logical line ($ continuation)
  uint32_t commentLine = 0; ///< where the code is written (W421): its physical line, column, length
  uint32_t col = 0;
  uint32_t length = 0;
};

struct File {
  uint32_t id = 0; ///< SourceManager id
  std::string path;
  UnitKind kind = UnitKind::Main;
  std::string_view procName; ///< Sub: the PROC name ("" if the header is bad)
  std::string semiName;      ///< Semi: display name
  StmtArray stmts;           ///< one per logical line, in order
  std::vector<Stmt> inner;   ///< simple statements after THEN / DO
  std::vector<Item> items;
  std::vector<Expr> exprs;
  std::vector<CaseArm> arms;
  std::vector<ArmRange> armRanges;  ///< one per Case statement
  InPlaceArray<LineNumber> numbers; ///< in statement order
  std::vector<StmtLabel> labels;
  std::vector<Jump> jumps;
  std::vector<StmtName> names;
  std::vector<GoJump> gos;        ///< z32: one per Go statement
  std::vector<WhenAxes> whenAxes; ///< one per WHEN statement, in statement order
  std::string whenAxisLetters;    ///< the letters of every WhenAxes
  std::vector<Suppression> suppressions;
  std::deque<std::string> ownedText;                     ///< names split by $ continuation (views point here)
  std::forward_list<std::deque<std::string>> ownedParts; ///< the ownedText of appended parts (appendPart)
  uint64_t bytes = 0;
  /// The whole source text the file was parsed from (the z32 GO rule searches it); it belongs
  /// to the caller, who keeps it alive while the file is checked.
  std::string_view source;
  bool binary = false; ///< a binary file (one E100, not parsed)
  /// isolint: the offset where the file was split between two threads (parseAndCheckFile), 0
  /// when one thread checked it all.
  uint32_t splitAt = 0;
  /// The compact form (parseAndCheckFile): the axis letters its items and expressions name
  /// (bit k: 'A' + k), collected before they are given back; the compiler's axis table.
  uint32_t usedAxes = 0;

  const Expr& expr(ExprId e) const { return exprs[static_cast<size_t>(e)]; }
  const Item* itemsOf(const Stmt& s) const { return items.data() + s.firstItem; }
  // A statement's side parts; an empty record when it has none.
  const LineNumber& numberOf(const Stmt& s) const {
    return s.hasN() ? byStmt(numbers, s) : sidePart(numbers, kNoIndex);
  }
  const StmtLabel& labelOf(const Stmt& s) const {
    return s.hasLabel() ? byStmt(labels, s) : sidePart(labels, kNoIndex);
  }
  /// The index in `labels` of the label of statement `stmt` (kNoIndex when it has none).
  uint32_t labelIndexOf(uint32_t stmt) const { return byStmtIndex(labels, stmt); }
  const Jump& jumpOf(const Stmt& s) const { return sidePart(jumps, s, StmtPart::Jump); }
  Jump& jumpOf(const Stmt& s) { return jumps.at(s.part == StmtPart::Jump ? s.partIdx : kNoIndex); } ///< s.hasJump()
  const StmtName& nameOf(const Stmt& s) const { return sidePart(names, s, StmtPart::Name); }
  const GoJump& goOf(const Stmt& s) const { return sidePart(gos, s, StmtPart::Go); }
  GoJump& goOf(const Stmt& s) { return gos.at(s.part == StmtPart::Go ? s.partIdx : kNoIndex); } ///< s.kind == Go
  /// The arms of a Case statement (none for others).
  std::span<const CaseArm> armsOf(const Stmt& s) const {
    const ArmRange& r = sidePart(armRanges, s, StmtPart::Arms);
    return {arms.data() + r.first, r.count};
  }
  std::span<CaseArm> armsOf(const Stmt& s) {
    const ArmRange& r = sidePart(armRanges, s, StmtPart::Arms);
    return {arms.data() + r.first, r.count};
  }
  /// The $AA_IW axes of the condition of WHEN statement `stmt` ("" for other statements).
  std::string_view whenAxesOf(uint32_t stmt) const;

private:
  template <class V> static const typename V::value_type& sidePart(const V& v, uint32_t i) {
    static const typename V::value_type none{};
    return i < v.size() ? v[i] : none;
  }
  // numbers, labels and whenAxes are in statement order: found by the index of their statement
  template <class V> static uint32_t byStmtIndex(const V& v, uint32_t stmt) {
    auto it = std::lower_bound(v.begin(), v.end(), stmt, [](const auto& x, uint32_t i) { return x.stmt < i; });
    return it != v.end() && it->stmt == stmt ? static_cast<uint32_t>(it - v.begin()) : kNoIndex;
  }
  template <class V> const typename V::value_type& byStmt(const V& v, const Stmt& s) const {
    const std::less<const Stmt*> before;
    if (stmts.empty() || before(&s, stmts.data()) || !before(&s, stmts.data() + stmts.size()))
      return sidePart(v, kNoIndex); // not a top-level statement of this file
    return sidePart(v, byStmtIndex(v, static_cast<uint32_t>(&s - stmts.data())));
  }
  template <class T> static const T& sidePart(const std::vector<T>& v, const Stmt& s, StmtPart part) {
    return sidePart(v, s.part == part ? s.partIdx : kNoIndex);
  }
};

/// Appends `part`, the statements that follow `f`'s in the same source (a later range of its
/// lines, parsed on its own), to `f`: every index it holds is moved past `f`'s records, and the
/// texts it owns stay where they are. The pages of `part`'s large arrays are given back as they
/// are copied, so that the two are not both resident. Jump targets must not be resolved yet.
/// `twoThreads`: statements already in place are renumbered by two threads.
void appendPart(File& f, File&& part, bool twoThreads = false);

/// Replaces the statements [from, to) of `f`, a checked file in the compact form (no
/// expressions; no z32 GO jumps), by `part`: the statements parsed again from the same lines of
/// an edited text, numbered in its lines. The lines of the statements after move by
/// `lineShift`; every index is moved to match; jump targets are cleared (the whole-file passes
/// resolve them again). The texts `part` views must outlive `f` (ownTexts). False, `f`
/// unchanged, when `f` or `part` is not in the compact form.
bool spliceStatements(File& f, uint32_t from, uint32_t to, File&& part, int32_t lineShift);

/// Copies every text the records of `f` view (N numbers, labels, jump labels, names, the PROC
/// name) into storage `f` owns, so that the text it was parsed from may change or go; the
/// z32 GO rule's view of the whole source is dropped.
void ownTexts(File& f);

} // namespace iso::frontend
