//! @file Compiler.cpp
//! @brief AST -> image code. The strict left-to-right rule is baked in by emitting operands in
//!        written order; the order of execution inside a line (SPEC §4.5) by emitting
//!        assignments/G/F/values, then M functions, then the move, then dwell, then M0/M17/M30.
#include "compiler/Compiler.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>
#include <set>
#include <unordered_map>

#include <fmt/format.h>

#include "frontend/Lexer.h"
#include "frontend/Parser.h"
#include "image/Opcode.h"
#include "lang/Axes.h"
#include "lang/GCodes.h"
#include "lang/MFunctions.h"
#include "lang/Z32GCodes.h"
#include "support/CaseFold.h"
#include "support/Memory.h"
#include "support/SourceText.h"

namespace iso::compiler {

using namespace iso::frontend;
using image::Op;
namespace fs = std::filesystem;

namespace {

class Linker {
public:
  explicit Linker(image::Image& img) : img_(img) {}

  uint32_t str(const std::string& s) {
    auto [it, ins] = strings_.emplace(s, static_cast<uint32_t>(img_.strings.size()));
    if (ins) img_.strings.push_back(s);
    return it->second;
  }

  uint32_t constant(double v) {
    uint64_t bits;
    std::memcpy(&bits, &v, sizeof bits);
    auto [it, ins] = consts_.emplace(bits, static_cast<uint32_t>(img_.constants.size()));
    if (ins) img_.constants.push_back(v);
    return it->second;
  }

  uint8_t axis(char letter) {
    for (size_t i = 0; i < img_.axes.size(); ++i)
      if (img_.axes[i] == letter) return static_cast<uint8_t>(i);
    return 0xFF; // collected beforehand; never reached for checked programs
  }

  image::Image& img_;
  std::map<std::string, uint32_t> strings_;
  std::unordered_map<uint64_t, uint32_t> consts_;
  std::map<std::string, uint32_t> procIndex; ///< upper-case PROC name -> index
};

bool accessesRealTime(const File& f, ExprId e) {
  if (e == kNoExpr) return false;
  const Expr& x = f.expr(e);
  if ((x.kind == ExprKind::SysAxis || x.kind == ExprKind::SysIndex) && sysVarIsRealTime(x.sysvar)) return true;
  return accessesRealTime(f, x.a) || accessesRealTime(f, x.b);
}

bool stmtAccessesRealTime(const File& f, const Stmt& s) {
  switch (s.kind) {
  case StmtKind::Block: {
    const Item* it = f.itemsOf(s);
    for (uint32_t k = 0; k < s.itemCount; ++k) {
      if (it[k].kind == ItemKind::AxisControl) continue; // its target is an axis mask
      if (it[k].kind == ItemKind::AssignIo) return true;
      if (it[k].kind == ItemKind::AssignP && f.expr(it[k].target).kind == ExprKind::Pal) return true;
      if (accessesRealTime(f, it[k].target) || accessesRealTime(f, it[k].value)) return true;
    }
    return false;
  }
  case StmtKind::If:
  case StmtKind::Case:
    if (accessesRealTime(f, s.cond)) return true;
    if (s.inner >= 0) return stmtAccessesRealTime(f, f.inner[static_cast<size_t>(s.inner)]);
    return false;
  default: return false;
  }
}

class ProcCompiler {
public:
  /// `f` gives the statements, their jumps (resolved), names, N numbers and CASE arms; their
  /// items and expressions are in `content` (statement() says which), which is `f` itself
  /// unless `f` is in the compact form.
  ProcCompiler(const File& f, const FileFlow& flow, Linker& lk, uint32_t fileStr, bool strip,
               const File* content = nullptr)
      : f_(f), c_(content ? content : &f), flow_(flow), lk_(lk), code_(lk.img_.code), fileStr_(fileStr), strip_(strip) {
  }

  void compile(UnitKind kind) {
    begin();
    for (size_t i = 0; i < f_.stmts.size(); ++i)
      statement(i, f_.stmts[i]);
    finish(kind);
  }

  void begin() {
    stmtOffset_.assign(f_.stmts.size() + 1, kUnbound);
    for (const GoJump& g : f_.gos)
      if (g.range && g.rangeEnd >= 0) rangeEnds_.insert(static_cast<size_t>(g.rangeEnd));
  }

  /// Statement i, every one once and in order; `content` (in the content file) has its items
  /// and expressions.
  void statement(size_t i, const Stmt& content) {
    if (i == bodyEnd_) endWhen(); // the CANCEL of a long WHEN: its body ends before it
    compileStmt(i, bodyEnd_ != SIZE_MAX, content);
  }

  /// The N numbers of f_ the statements compiled so far have passed (File::numbers).
  size_t numbersPassed() const { return number_; }

  void finish(UnitKind kind) {
    if (bodyEnd_ != SIZE_MAX) endWhen(); // (a checked long WHEN always has its CANCEL)
    const size_t n = f_.stmts.size();
    stmtOffset_[n] = here();
    emit(kind == UnitKind::Sub ? Op::Ret : Op::EndImplicit);
    for (const auto& [at, target] : fixups_) {
      uint32_t off = stmtOffset_[target];
      // Empty statements bind to the code of the next statement.
      size_t t = target;
      while (off == kUnbound && t + 1 < stmtOffset_.size())
        off = stmtOffset_[++t];
      image::patchU32(code_, at, off);
    }
  }

private:
  static constexpr uint32_t kUnbound = 0xFFFFFFFFu;
  uint32_t here() const { return static_cast<uint32_t>(code_.size()); }
  void emit(Op op) { code_.push_back(static_cast<uint8_t>(op)); }
  void emitUleb(Op op, uint64_t v) {
    emit(op);
    image::writeUleb(code_, v);
  }
  /// Emits a u32 that will hold the code offset of statement `target`.
  void addrToStmt(size_t target) {
    fixups_.emplace_back(code_.size(), target);
    image::writeU32(code_, 0);
  }
  size_t addrPlaceholder() {
    size_t at = code_.size();
    image::writeU32(code_, 0);
    return at;
  }
  void bindHere(size_t at) { image::patchU32(code_, at, here()); }

  void pushNumber(double v) {
    for (int k = 0; k <= 9; ++k) {
      static const double pow10[] = {1, 10, 100, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9};
      double scaled = v * pow10[k];
      if (!(std::abs(scaled) < 9.0e15)) break;
      double m = std::nearbyint(scaled);
      auto mi = static_cast<int64_t>(m);
      // The sleb must fit the decoder's 5 bytes (35 bits).
      if (mi > (int64_t{1} << 33) || mi < -(int64_t{1} << 33)) break;
      Op op = static_cast<Op>(static_cast<int>(Op::PushD0) + k);
      if (image::decValue(op, mi) == v && !(v == 0 && std::signbit(v))) {
        emit(op);
        image::writeSleb(code_, mi);
        return;
      }
    }
    emitUleb(Op::PushConst, lk_.constant(v));
  }

  void expr(ExprId e) {
    const Expr& x = c_->expr(e);
    switch (x.kind) {
    case ExprKind::Number: pushNumber(x.value); break;
    case ExprKind::RParam: emitUleb(Op::LoadR, static_cast<uint64_t>(x.rIndex)); break;
    case ExprKind::RIndirect:
      expr(x.a);
      emit(Op::LoadRInd);
      break;
    case ExprKind::SysAxis:
      emit(Op::LoadAxVar);
      code_.push_back(static_cast<uint8_t>(x.sysvar));
      code_.push_back(lk_.axis(x.axis));
      break;
    case ExprKind::SysIndex:
      expr(x.a);
      emit(Op::LoadIo);
      code_.push_back(static_cast<uint8_t>(x.sysvar));
      break;
    case ExprKind::Neg:
      expr(x.a);
      emit(Op::Neg);
      break;
    case ExprKind::Binary:
      expr(x.a);
      expr(x.b);
      emit(static_cast<Op>(static_cast<int>(Op::Add) + x.op));
      break;
    case ExprKind::Compare:
      expr(x.a);
      expr(x.b);
      emit(static_cast<Op>(static_cast<int>(Op::CmpGt) + x.op));
      break;
    case ExprKind::Logic:
      expr(x.a);
      expr(x.b);
      emit(static_cast<LogicOp>(x.op) == LogicOp::And ? Op::And : Op::Or);
      break;
    case ExprKind::Not:
      expr(x.a);
      emit(Op::Not);
      break;
    case ExprKind::Par:
      expr(x.a);
      emit(Op::LoadPar);
      break;
    case ExprKind::Pal:
      expr(x.a);
      emit(Op::LoadPal);
      break;
    case ExprKind::UserParam: emitUleb(Op::LoadUser, userParam(x.rIndex)); break;
    case ExprKind::Error: pushNumber(0); break;
    }
  }

  /// The string index of user parameter `index` of the machine's `parameters`.
  uint32_t userParam(int32_t index) {
    const bool known = parameters_ && index >= 0 && static_cast<size_t>(index) < parameters_->size();
    return lk_.str(known ? (*parameters_)[static_cast<size_t>(index)] : std::string("?"));
  }

  /// True when no statement with code follows statement i inside the WHEN body being compiled.
  bool lastInBody(size_t i) const {
    for (size_t k = i + 1; k < bodyEnd_ && k < f_.stmts.size(); ++k) {
      StmtKind kk = f_.stmts[k].kind;
      if (kk != StmtKind::Empty && kk != StmtKind::Proc && kk != StmtKind::Semi && kk != StmtKind::Invalid)
        return false;
    }
    return true;
  }

  /// File::numberOf(s).value of a top-level statement: they come in order, so a cursor finds it.
  double numberValue(const Stmt& s) {
    if (!s.hasN()) return 0;
    const auto i = static_cast<uint32_t>(&s - f_.stmts.data());
    while (number_ < f_.numbers.size() && f_.numbers[number_].stmt < i)
      ++number_;
    if (number_ < f_.numbers.size() && f_.numbers[number_].stmt == i) return f_.numbers[number_].value;
    return f_.numberOf(s).value;
  }

  void stmtHeader(const Stmt& s, size_t nextStmt, bool sync, bool skipToBodyEnd = false, bool noSkip = false) {
    uint32_t at = here();
    if (s.skippable && !noSkip) {
      emit(Op::StmtSkip);
      // the last statement of a WHEN body skips to the body's end, never out of the body
      if (skipToBodyEnd)
        bodyEndFixups_.push_back(addrPlaceholder());
      else
        addrToStmt(nextStmt);
    } else {
      emit(Op::Stmt);
    }
    if (!strip_) lk_.img_.lines.push_back({at, fileStr_, s.line, s.hasN(), numberValue(s)});
    if (sync) emit(Op::Sync);
  }

  void block(const Stmt& s) {
    if (dialect_ == machine::Dialect::Z32) return blockZ32(s);
    const Item* it = c_->itemsOf(s);
    bool dwell = false;
    for (uint32_t k = 0; k < s.itemCount; ++k)
      if (it[k].kind == ItemKind::G && lang::isDwell(it[k].code)) dwell = true;
    const Item* lastFeed = nullptr;
    for (uint32_t k = 0; k < s.itemCount; ++k)
      if (it[k].kind == ItemKind::Feed) lastFeed = &it[k];
    std::vector<uint8_t> desc;
    std::vector<const Item*> ms;
    const Item* endM = nullptr;
    for (uint32_t k = 0; k < s.itemCount; ++k) {
      const Item& x = it[k];
      if (isMoveWord(x.kind)) {
        moveWord(x, desc);
        continue;
      }
      switch (x.kind) {
      case ItemKind::G: gCode(x.code); break;
      case ItemKind::Feed: feed(x, dwell, lastFeed); break;
      case ItemKind::AssignR:
      case ItemKind::AssignIo:
      case ItemKind::AssignP: assign(x); break;
      case ItemKind::M:
        if (!x.nb && lang::isFinal(lang::mRole(x.code, lang::Dialect::Sidac)))
          endM = &x;
        else
          ms.push_back(&x);
        break;
      case ItemKind::ZWord: break; // z32 only (blockZ32)
      default: break;              // move words: above; z32 words: blockZ32
      }
    }
    for (const Item* m : ms)
      emitUleb(m->nb ? Op::MNb : Op::M, static_cast<uint64_t>(m->code));
    if (!desc.empty()) {
      emit(Op::Move);
      code_.push_back(static_cast<uint8_t>(desc.size()));
      code_.insert(code_.end(), desc.begin(), desc.end());
    }
    if (dwell) emit(Op::Dwell);
    if (endM) {
      if (endM->code == lang::kMStop)
        emit(Op::M0);
      else if (endM->code == lang::kMReturn)
        emit(Op::Ret);
      else
        emit(Op::End);
    }
  }

  /// The subprogram index M`code` calls in z32, or -1 when it is not special.
  int64_t specialProc(const Item& x) const {
    if (x.kind != ItemKind::M || x.nb || !specialM_) return -1;
    auto it = specialM_->find(x.code);
    if (it == specialM_->end()) return -1;
    auto p = lk_.procIndex.find(support::upperCopy(it->second));
    return p == lk_.procIndex.end() ? -1 : static_cast<int64_t>(p->second);
  }

  /// Items and values of one z32 line (SPEC §4.6, §4.7): what the line order needs to know.
  struct Z32Line {
    const Item* special = nullptr; ///< the special M that ends the line (step 3, or M6 at step 9)
    bool specialFirst = false;     ///< it runs at step 3: nothing after the words is evaluated
    bool dwell = false;
    std::vector<uint8_t> desc;      ///< move descriptors, in written order
    std::vector<const Item*> stack; ///< the items whose values are on the stack, bottom first
  };

  void emitSpecial(const Item& m) {
    emitUleb(Op::MSpecial, static_cast<uint64_t>(m.code));
    emitUleb(Op::Call, static_cast<uint64_t>(specialProc(m)));
  }

  /// Where a G code that isotools does not model runs in a z32 line (SPEC §4.7): G36 G80 G84
  /// G100 G101 first (step 0), G61 G62 with the motion (step 5), the others in written order.
  enum class NmStep : uint8_t { None, First, Words, Motion };
  static NmStep notModelledStep(const Item& x) {
    if (x.kind != ItemKind::G || !image::isNotModelledG(static_cast<uint64_t>(x.code))) return NmStep::None;
    switch (x.code) {
    case 36:
    case 80:
    case 84:
    case 100:
    case 101: return NmStep::First;
    case 61:
    case 62: return NmStep::Motion;
    default: return NmStep::Words;
    }
  }
  void emitNotModelled(const Stmt& s, NmStep step) {
    const Item* it = c_->itemsOf(s);
    for (uint32_t k = 0; k < s.itemCount; ++k)
      if (notModelledStep(it[k]) == step) emitUleb(Op::Nm, static_cast<uint64_t>(it[k].code));
  }

  /// G28 (on) or G29 (off) of `x`: its axis letters as a mask of image axes (0: every axis).
  void axisControl(const Item& x) {
    uint32_t mask = 0;
    forEachControlledAxis(x, [&](char letter) {
      const uint8_t ax = lk_.axis(letter);
      if (ax < 32) mask |= 1u << ax;
    });
    emitUleb(Op::AxisCtl, image::axisCtlOperand(mask, x.code == 28));
  }
  void emitAxisRelease(const Stmt& s) {
    const Item* it = c_->itemsOf(s);
    for (uint32_t k = 0; k < s.itemCount; ++k)
      if (it[k].kind == ItemKind::AxisControl && it[k].code == 29) axisControl(it[k]);
  }

  static bool isZWord(const Item& x, char a, char b = '\0') {
    return x.kind == ItemKind::ZWord && x.zaddr[0] == a && x.zaddr[1] == b;
  }
  static bool isToolWord(const Item& x) { return x.kind == ItemKind::ZWord && x.zaddr[0] == 'T'; }

  /// Step (1): assignments, G, F, G28 and S in written order; move and MA/MB/MC values are
  /// pushed in written order too (the expressions of a line run left to right) unless a special
  /// M at step 3 abandons the rest of the line.
  void z32Words(const Stmt& s, Z32Line& z) {
    const Item* it = c_->itemsOf(s);
    const Item* lastFeed = nullptr;
    for (uint32_t k = 0; k < s.itemCount; ++k) {
      if (it[k].kind == ItemKind::Feed) lastFeed = &it[k];
      if (it[k].kind == ItemKind::G && lang::isDwell(it[k].code)) z.dwell = true;
      if (specialProc(it[k]) < 0) continue;
      const bool first = it[k].code != 6;
      if (!z.special || (first && !z.specialFirst)) {
        z.special = &it[k];
        z.specialFirst = first;
      }
    }
    for (uint32_t k = 0; k < s.itemCount; ++k) {
      const Item& x = it[k];
      if (isMoveWord(x.kind)) {
        if (!z.specialFirst) {
          moveWord(x, z.desc);
          z.stack.push_back(&x);
        }
        continue;
      }
      switch (x.kind) {
      case ItemKind::G:
        if (notModelledStep(x) == NmStep::Words)
          emitUleb(Op::Nm, static_cast<uint64_t>(x.code));
        else if (notModelledStep(x) == NmStep::None && x.code != lang::kG26Return)
          gCode(x.code);
        break;
      case ItemKind::AxisControl:
        if (x.code == 28) axisControl(x);
        break;
      case ItemKind::Feed:
        if (!(z.dwell && z.specialFirst) && feed(x, z.dwell, lastFeed)) z.stack.push_back(&x);
        break;
      case ItemKind::AssignR:
      case ItemKind::AssignIo:
      case ItemKind::AssignP: assign(x); break;
      case ItemKind::ZWord:
        if (isZWord(x, 'S')) {
          expr(x.value);
          emit(Op::ZWord);
          code_.push_back(static_cast<uint8_t>(image::ZAddr::S));
        } else if (x.zaddr[0] == 'M' && !z.specialFirst) {
          expr(x.value);
          z.stack.push_back(&x);
        }
        break;        // T TA TB: step 4; O: step 4b
      default: break; // move words: above; M, KG: later steps
      }
    }
  }

  /// T, TA or TB at step (4): the value, then the word.
  void toolWord(const Item& x) {
    expr(x.value);
    emit(Op::ZWord);
    const image::ZAddr a = x.zaddr[1] == 'A'   ? image::ZAddr::TA
                           : x.zaddr[1] == 'B' ? image::ZAddr::TB
                                               : image::ZAddr::T;
    code_.push_back(static_cast<uint8_t>(a));
  }

  /// Emits the M functions of `s` that run at `step`, in written order (T TA TB and MA/MB/MC
  /// at step 4).
  void z32Step(const Stmt& s, Z32Line& z, lang::Z32Step step) {
    const Item* it = c_->itemsOf(s);
    for (uint32_t k = 0; k < s.itemCount; ++k) {
      const Item& x = it[k];
      if (step == lang::Z32Step::Other && isToolWord(x)) {
        toolWord(x);
        continue;
      }
      if (x.kind == ItemKind::ZWord && x.zaddr[0] == 'M' && step == lang::Z32Step::Other) {
        auto at = std::find(z.stack.begin(), z.stack.end(), &x);
        const auto depth = static_cast<uint8_t>(z.stack.end() - at - 1);
        z.stack.erase(at);
        emit(Op::Aux);
        code_.push_back(static_cast<uint8_t>(x.zaddr[1] - 'A')); // 0 MA, 1 MB, 2 MC
        code_.push_back(depth);
        continue;
      }
      if (x.kind != ItemKind::M || &x == z.special) continue;
      const bool special = specialProc(x) >= 0;
      const lang::Z32Step xs = x.nb ? lang::Z32Step::Other : lang::z32Step(x.code, special);
      if (xs != step) continue;
      if (step == lang::Z32Step::Final) return z32Final(x);
      emitUleb(x.nb ? Op::MNb : Op::M, static_cast<uint64_t>(x.code));
    }
  }

  /// Step (4b): the origin O<n> (the last one written counts).
  void z32Origin(const Stmt& s) {
    const Item* it = c_->itemsOf(s);
    for (uint32_t k = 0; k < s.itemCount; ++k) {
      if (!isZWord(it[k], 'O')) continue;
      const auto v = constValue(*c_, it[k].value);
      emitUleb(Op::Origin, v && *v >= 0 && *v <= lang::kMaxOrigin ? static_cast<uint64_t>(*v) : 0);
    }
  }

  /// Steps (11) and (12): KG, then G26.
  void z32Leave(const Stmt& s) {
    const Item* it = c_->itemsOf(s);
    bool ret = false;
    for (uint32_t k = 0; k < s.itemCount; ++k) {
      if (it[k].kind == ItemKind::Kg) emitUleb(Op::Kg, procOf(c_->names.at(static_cast<size_t>(it[k].code)).text));
      if (it[k].kind == ItemKind::G && it[k].code == lang::kG26Return) ret = true;
    }
    if (ret) emit(Op::Ret);
  }

  /// Step (10): M0 and M1 run their PLC sequence, then stop; M2 runs its sequence, then ends
  /// like M30; M30 ends and M17 returns as in dialect sidac.
  void z32Final(const Item& x) {
    switch (lang::mRole(x.code, lang::Dialect::Z32)) {
    case lang::MRole::Stop:
      emitUleb(Op::M, 0);
      emit(Op::M0);
      break;
    case lang::MRole::OptionalStop:
      emitUleb(Op::M, 1);
      emit(Op::M1);
      break;
    case lang::MRole::Return: emit(Op::Ret); break;
    default:
      if (x.code == lang::kMEndZ32) emitUleb(Op::M, static_cast<uint64_t>(lang::kMEndZ32));
      emit(Op::End);
      break;
    }
  }

  /// A block in dialect z32: the order of SPEC §4.7 (0)..(12), whatever the written order.
  void blockZ32(const Stmt& s) {
    Z32Line z;
    emitNotModelled(s, NmStep::First);
    z32Words(s, z);
    z32Step(s, z, lang::Z32Step::Spindle);
    if (z.special && z.specialFirst) return emitSpecial(*z.special); // the line ends here
    z32Step(s, z, lang::Z32Step::Other);
    z32Origin(s);
    if (!z.desc.empty()) {
      emit(Op::Move);
      code_.push_back(static_cast<uint8_t>(z.desc.size()));
      code_.insert(code_.end(), z.desc.begin(), z.desc.end());
    }
    emitNotModelled(s, NmStep::Motion);
    if (z.dwell) emit(Op::Dwell);
    emitAxisRelease(s);
    z32Step(s, z, lang::Z32Step::Orient);
    z32Step(s, z, lang::Z32Step::SpindleOff);
    z32Step(s, z, lang::Z32Step::Tool);
    if (z.special) return emitSpecial(*z.special); // M6 special: the line ends here
    z32Step(s, z, lang::Z32Step::Final);
    z32Leave(s);
  }

  /// F: the modal feed, or in a G04 line the dwell time (with several F the last one counts).
  /// Returns true when it pushed the dwell time.
  bool feed(const Item& x, bool dwell, const Item* lastFeed) {
    if (dwell) {
      if (&x != lastFeed) return false;
      expr(x.value);
      return true;
    }
    expr(x.value);
    emit(Op::SetF);
    return false;
  }

  void gCode(int32_t code) {
    // G04 is the dwell (no modal opcode); unknown codes were errors
    if (auto g = lang::findG(code))
      if (auto op = image::modalOp(*g)) emit(*op);
  }

  void assign(const Item& x) {
    if (x.kind == ItemKind::AssignP) return assignP(x);
    if (x.kind == ItemKind::AssignIo) {
      expr(x.target);
      expr(x.value);
      emit(Op::StoreIo);
      code_.push_back(static_cast<uint8_t>(x.sysvar));
      return;
    }
    const Expr& t = c_->expr(x.target);
    if (t.kind == ExprKind::RIndirect) {
      expr(t.a);
      expr(x.value);
      emit(Op::StoreRInd);
    } else {
      expr(x.value);
      emitUleb(Op::StoreR, static_cast<uint64_t>(t.rIndex));
    }
  }

  /// z32: PAR[i] = , PAL[i] = , or a user parameter = (the index first, then the value).
  void assignP(const Item& x) {
    const Expr& t = c_->expr(x.target);
    if (t.kind == ExprKind::UserParam) {
      expr(x.value);
      emitUleb(Op::StoreUser, userParam(t.rIndex));
      return;
    }
    expr(t.a);
    expr(x.value);
    emit(t.kind == ExprKind::Pal ? Op::StorePal : Op::StorePar);
  }

  /// A word of the line's Move: an axis target, an axis feed, an arc centre or radius.
  static bool isMoveWord(ItemKind k) {
    switch (k) {
    case ItemKind::Move:
    case ItemKind::AxisFeed:
    case ItemKind::ArcI:
    case ItemKind::ArcJ:
    case ItemKind::ArcK:
    case ItemKind::ArcCR: return true;
    default: return false;
    }
  }

  /// Evaluates a move word's value and adds its descriptor to the line's Move.
  void moveWord(const Item& x, std::vector<uint8_t>& desc) {
    expr(x.value);
    desc.push_back(moveDescriptor(x));
  }

  uint8_t moveDescriptor(const Item& x) {
    switch (x.kind) {
    case ItemKind::Move:
      return static_cast<uint8_t>(
          (static_cast<uint8_t>(x.mode == MoveMode::Posa ? image::MoveKind::TargetNb : image::MoveKind::Target) << 4) |
          lk_.axis(x.axis));
    case ItemKind::AxisFeed:
      return static_cast<uint8_t>((static_cast<uint8_t>(image::MoveKind::Fa) << 4) | lk_.axis(x.axis));
    case ItemKind::ArcI: return static_cast<uint8_t>(static_cast<uint8_t>(image::MoveKind::I) << 4);
    case ItemKind::ArcJ: return static_cast<uint8_t>(static_cast<uint8_t>(image::MoveKind::J) << 4);
    case ItemKind::ArcK: return static_cast<uint8_t>(static_cast<uint8_t>(image::MoveKind::K) << 4);
    default: return static_cast<uint8_t>(static_cast<uint8_t>(image::MoveKind::CR) << 4);
    }
  }

  void jumpTo(Op op, const Jump& j) {
    emit(op);
    addrToStmt(static_cast<size_t>(j.target < 0 ? 0 : j.target));
  }

  /// The simple statement after THEN or DO: `in` in f_.inner, `content` in the content file's.
  void simple(const Stmt& in, const Stmt& content) {
    switch (in.kind) {
    case StmtKind::Block: block(content); break;
    case StmtKind::Jump: jumpTo(Op::Jump, f_.jumpOf(in)); break;
    case StmtKind::Call: call(in); break;
    case StmtKind::Go: go(in); break;
    default: break;
    }
  }

  uint32_t procOf(std::string_view name) const {
    auto it = lk_.procIndex.find(support::upperCopy(name));
    return it == lk_.procIndex.end() ? 0 : it->second;
  }
  void call(const Stmt& s) { emitUleb(Op::Call, procOf(f_.nameOf(s).text)); }

  /// z32 GO<target> (a jump) or GO<a>-<b> (a range with return).
  void go(const Stmt& s) {
    const GoJump& g = f_.goOf(s);
    if (!g.range) {
      emit(Op::Jump);
      addrToStmt(static_cast<size_t>(g.target < 0 ? 0 : g.target));
      return;
    }
    emit(Op::GoRange);
    addrToStmt(static_cast<size_t>(g.target < 0 ? 0 : g.target));
    addrToStmt(static_cast<size_t>(g.rangeEnd < 0 ? 0 : g.rangeEnd));
  }

  /// Compiles statement i (a long WHEN: its start; its body follows, then endWhen).
  void compileStmt(size_t i, bool inBody, const Stmt& cs) {
    const Stmt& s = f_.stmts[i];
    stmtOffset_[i] = here();
    switch (s.kind) {
    case StmtKind::Empty:
      if (rangeEnds_.count(i) != 0) { // a GO range returns after this line: it needs a header
        stmtHeader(s, i + 1, false);
        return;
      }
      stmtOffset_[i] = kUnbound;
      return;
    case StmtKind::Proc:
    case StmtKind::Semi:
    case StmtKind::Invalid: stmtOffset_[i] = kUnbound; return;
    default: break;
    }
    if (s.kind == StmtKind::When) return when(i, cs);
    bool sync = !inBody && stmtAccessesRealTime(*c_, cs);
    stmtHeader(s, i + 1, sync, inBody && lastInBody(i));
    switch (s.kind) {
    case StmtKind::Block: block(cs); break;
    case StmtKind::If:
      expr(cs.cond);
      if (s.hasJump()) {
        jumpTo(Op::JumpTrue, f_.jumpOf(s));
      } else if (s.inner >= 0) {
        emit(Op::JumpFalse);
        size_t at = addrPlaceholder();
        simple(f_.inner[static_cast<size_t>(s.inner)], c_->inner[static_cast<size_t>(cs.inner)]);
        bindHere(at);
      } else {
        int32_t m = flow_.match[i];
        emit(Op::JumpFalse);
        // false: to the first statement of the ELSE body, or to the ENDIF line
        size_t target = m < 0 ? f_.stmts.size()
                              : (f_.stmts[static_cast<size_t>(m)].kind == StmtKind::Else ? static_cast<size_t>(m) + 1
                                                                                         : static_cast<size_t>(m));
        addrToStmt(target);
      }
      break;
    case StmtKind::Else: {
      int32_t m = flow_.match[i];
      emit(Op::Jump);
      addrToStmt(m < 0 ? i + 1 : static_cast<size_t>(m));
      break;
    }
    case StmtKind::Jump: jumpTo(Op::Jump, f_.jumpOf(s)); break;
    case StmtKind::Case: {
      expr(cs.cond);
      emit(Op::Case);
      uint32_t nArms = 0;
      const CaseArm* def = nullptr;
      for (const CaseArm& arm : f_.armsOf(s)) {
        if (arm.isDefault)
          def = &arm;
        else
          ++nArms;
      }
      image::writeUleb(code_, nArms);
      for (const CaseArm& a : f_.armsOf(s)) {
        if (a.isDefault) continue;
        image::writeUleb(code_, lk_.constant(a.value));
        addrToStmt(static_cast<size_t>(a.jump.target < 0 ? 0 : a.jump.target));
      }
      if (def)
        addrToStmt(static_cast<size_t>(def->jump.target < 0 ? 0 : def->jump.target));
      else
        image::writeU32(code_, image::kNoTarget);
      break;
    }
    case StmtKind::Call: call(s); break;
    case StmtKind::Go: go(s); break;
    default: break; // EndIf, Cancel: the statement header is all
    }
  }

  /// A WHEN: its condition, then the short form's statement, or (the long form) the start of
  /// its body, which the statements up to its CANCEL fill (bodyEnd_).
  void when(size_t i, const Stmt& cs) {
    const Stmt& s = f_.stmts[i];
    int32_t cancel = flow_.match[i];
    size_t next = s.inner >= 0 ? i + 1 : (cancel > 0 ? static_cast<size_t>(cancel) : i + 1);
    uint32_t at = here();
    if (s.skippable) {
      emit(Op::StmtSkip);
      whenSkip_ = addrPlaceholder();
    } else {
      emit(Op::Stmt);
      whenSkip_ = SIZE_MAX;
    }
    if (!strip_) lk_.img_.lines.push_back({at, fileStr_, s.line, s.hasN(), numberValue(s)});
    emit(Op::When);
    size_t condAt = addrPlaceholder();
    size_t bodyAt = addrPlaceholder();
    emit(Op::Jump);
    whenAfter_ = addrPlaceholder();
    bindHere(condAt);
    expr(cs.cond);
    emit(Op::CondEnd);
    bindHere(bodyAt);
    bodyEndFixups_.clear();
    if (s.inner >= 0) {
      stmtHeader(s, i + 1, false, false, /*noSkip=*/true); // the WHEN line's own skip covers it
      simple(f_.inner[static_cast<size_t>(s.inner)], c_->inner[static_cast<size_t>(cs.inner)]);
      endWhen();
    } else if (next == i + 1) {
      endWhen();
    } else {
      bodyEnd_ = next;
    }
  }

  /// The end of the WHEN being compiled: its body's skips land here, then the BodyEnd.
  void endWhen() {
    bodyEnd_ = SIZE_MAX;
    for (size_t at2 : bodyEndFixups_)
      bindHere(at2);
    bodyEndFixups_.clear();
    emit(Op::BodyEnd);
    bindHere(whenAfter_);
    if (whenSkip_ != SIZE_MAX) bindHere(whenSkip_);
  }

public:
  machine::Dialect dialect_ = machine::Dialect::Sidac;
  const std::map<int, std::string>* specialM_ = nullptr;
  const std::vector<std::string>* parameters_ = nullptr; ///< z32: the machine's user parameters

private:
  const File& f_;
  const File* c_; ///< the items and expressions of f_'s statements (f_ unless it is compact)
  const FileFlow& flow_;
  Linker& lk_;
  std::vector<uint8_t>& code_;
  uint32_t fileStr_;
  bool strip_;
  std::vector<uint32_t> stmtOffset_;
  std::set<size_t> rangeEnds_; ///< z32: statements that end a GO range
  std::vector<std::pair<size_t, size_t>> fixups_;
  size_t number_ = 0;                 ///< numberValue's cursor in f_.numbers
  size_t whenSkip_ = SIZE_MAX;        ///< the skip of the WHEN being compiled (SIZE_MAX: none)
  size_t whenAfter_ = 0;              ///< its jump past the WHEN
  size_t bodyEnd_ = SIZE_MAX;         ///< statement index of the CANCEL while compiling a body
  std::vector<size_t> bodyEndFixups_; ///< skip targets to bind to the BodyEnd
};

std::string stemOf(const std::string& path) { return fs::path(path).stem().string(); }

void collectAxes(const File& f, std::set<char>& axes) {
  for (const Item& it : f.items) {
    if (it.kind == ItemKind::Move || it.kind == ItemKind::AxisFeed) axes.insert(it.axis);
    if (it.kind == ItemKind::AxisControl) forEachControlledAxis(it, [&](char letter) { axes.insert(letter); });
  }
  for (const Expr& e : f.exprs)
    if (e.kind == ExprKind::SysAxis) axes.insert(e.axis);
  for (int k = 0; k < 26; ++k) // the compact form: collected as it was parsed
    if ((f.usedAxes >> k) & 1u) axes.insert(static_cast<char>('A' + k));
}

/// Gives back what the parser put in `g` for its last line.
void clearLine(File& g) {
  g.stmts.clear();
  g.inner.clear();
  g.items.clear();
  g.exprs.clear();
  g.arms.clear();
  g.armRanges.clear();
  g.numbers.clear();
  g.labels.clear();
  g.jumps.clear();
  g.names.clear();
  g.gos.clear();
  g.whenAxes.clear();
  g.whenAxisLetters.clear();
  g.suppressions.clear();
  g.ownedText.clear();
}

/// Compiles `f`, a unit in the compact form, from its text parsed again a line at a time into
/// `g` (pc's content file): each statement is compiled as soon as it is parsed, then given back.
bool compileReparsed(const File& f, const support::SourceText& text, const CompileOptions& opts, File& g,
                     ProcCompiler& pc, CompileError& err) {
  g.id = f.id;
  diag::DiagnosticList diags; // the load reported them
  LineParser lines(g, text, *opts.reparse, diags, /*reserve=*/false);
  pc.begin();
  size_t i = 0;
  size_t dropped = 0; // a mapped text's pages leave behind the reader
  for (; lines.parseLine(); ++i) {
    if (i >= f.stmts.size() || g.stmts.size() != 1 || g.stmts[0].kind != f.stmts[i].kind) break;
    pc.statement(i, g.stmts[0]);
    clearLine(g);
    diags.items().clear();
    if (lines.nextOffset() >= dropped + opts.releaseEvery) {
      // (a statement's views point into its own line: the lines behind are not read again)
      text.dropPages(dropped > 4096 ? dropped - 4096 : 0, lines.nextOffset());
      dropped = lines.nextOffset();
      if (opts.releaseSet) { // CompileOptions::releaseSet: the compiler reads no statement behind it
        auto& passed = const_cast<File&>(f);
        support::releasePages(passed.stmts.data(), i * sizeof(Stmt));
        support::releasePages(passed.numbers.data(), pc.numbersPassed() * sizeof(LineNumber));
      }
    }
  }
  if (text.changedOnDisk(f.path)) {
    err.message = fmt::format("{} was written while it was compiled: compile it again", f.path);
    return false;
  }
  if (i != f.stmts.size() || !g.stmts.empty()) {
    err.message = fmt::format("internal error: {} read again differs at line {} (please report this bug)", f.path,
                              g.stmts.empty() ? 0 : g.stmts.back().line);
    return false;
  }
  pc.finish(f.kind);
  return true;
}

} // namespace

namespace {
/// The main program: the first named main program, else the only one (-1 and `err` if none).
int findMainProgram(const ProgramSet& set, CompileError& err) {
  for (size_t id : set.namedOrder)
    if (set.files[id].kind == UnitKind::Main) return static_cast<int>(id);
  std::vector<std::string> mains;
  int mainIdx = -1;
  for (size_t i = 0; i < set.files.size(); ++i)
    if (set.files[i].kind == UnitKind::Main) {
      mains.push_back(set.files[i].path);
      mainIdx = static_cast<int>(i);
    }
  std::sort(mains.begin(), mains.end());
  if (mains.size() > 1) {
    err.message = fmt::format("several main programs and none named: {}", fmt::join(mains, ", "));
    return -1;
  }
  if (mains.empty()) {
    err.message = "the program set has no main program (.mpf without SEMI)";
    return -1;
  }
  return mainIdx;
}

/// File names are recorded relative to the main program's folder: independent of the working
/// directory.
fs::path mainFolder(const ProgramSet& set, size_t mainIdx) {
  std::error_code ec;
  return fs::absolute(fs::path(set.files[mainIdx].path), ec).lexically_normal().parent_path();
}

std::string recordedPath(const fs::path& base, const std::string& p) {
  std::error_code ec;
  fs::path abs = fs::absolute(fs::path(p), ec).lexically_normal();
  fs::path rel = abs.lexically_relative(base);
  return rel.empty() ? fs::path(p).filename().string() : rel.generic_string();
}
} // namespace

std::vector<size_t> linkedUnits(const ProgramSet& set, const CompileOptions& opts, CompileError& err) {
  const int mainIdx = findMainProgram(set, err);
  if (mainIdx < 0) return {};
  // procedures by name
  std::map<std::string, size_t> subs;
  for (size_t i = 0; i < set.files.size(); ++i)
    if (set.files[i].kind == UnitKind::Sub && !set.files[i].procName.empty())
      subs.emplace(support::upperCopy(set.files[i].procName), i);
  // units: main, semis (by path), reachable subs (by name)
  const fs::path base = mainFolder(set, static_cast<size_t>(mainIdx));
  std::vector<size_t> semis;
  for (size_t i = 0; i < set.files.size(); ++i)
    if (set.files[i].kind == UnitKind::Semi) semis.push_back(i);
  std::sort(semis.begin(), semis.end(), [&](size_t a, size_t b) {
    return recordedPath(base, set.files[a].path) < recordedPath(base, set.files[b].path);
  });
  const std::map<int, std::string>* specialM = opts.dialect == machine::Dialect::Z32 ? opts.specialM : nullptr;
  std::set<std::string> reachable;
  std::vector<size_t> work{static_cast<size_t>(mainIdx)};
  work.insert(work.end(), semis.begin(), semis.end());
  while (!work.empty()) {
    size_t u = work.back();
    work.pop_back();
    const File& f = set.files[u];
    auto reach = [&](std::string key) {
      auto it = subs.find(key);
      if (it != subs.end() && reachable.insert(key).second) work.push_back(it->second);
    };
    forEachCall(
        f, specialM, [&](const Stmt& s) { reach(support::upperCopy(f.nameOf(s).text)); },
        [&](const Item&, const std::string& name) { reach(support::upperCopy(name)); }); // z32: a special M calls it
    for (const Item& it : f.items) // z32: KG continues in a subprogram
      if (it.kind == ItemKind::Kg && it.code >= 0 && static_cast<size_t>(it.code) < f.names.size())
        reach(support::upperCopy(f.names[static_cast<size_t>(it.code)].text));
  }
  std::vector<size_t> units{static_cast<size_t>(mainIdx)};
  units.insert(units.end(), semis.begin(), semis.end());
  for (const auto& name : reachable)
    units.push_back(subs.at(name));
  return units;
}

bool compileProgramSet(const ProgramSet& set, const CompileOptions& opts, image::Image& out, CompileError& err) {
  out = image::Image{};
  const std::vector<size_t> units = linkedUnits(set, opts, err);
  if (units.empty()) return false;
  const fs::path base = mainFolder(set, units.front());
  const std::map<int, std::string>* specialM = opts.dialect == machine::Dialect::Z32 ? opts.specialM : nullptr;
  for (const auto& d : set.diags.items()) {
    if (d.severity != diag::Severity::Error) continue;
    for (size_t u : units)
      if (set.files[u].id == d.loc.file) {
        err.message = fmt::format("{} has errors; nothing was compiled", set.files[u].path);
        return false;
      }
  }
  Linker lk(out);
  // Room for the code and the line table at once (a line entry per statement at most, and one
  // more for a WHEN's DO; rarely more code than source bytes): nothing is copied as they grow,
  // and room never used is never touched.
  size_t stmts = 0, bytes = 0;
  for (size_t u : units) {
    stmts += set.files[u].stmts.size() + set.files[u].whenAxes.size();
    bytes += set.files[u].bytes;
  }
  support::reserveHuge(out.code, bytes + 64);
  if (!opts.strip) support::reserveHuge(out.lines, stmts);
  // axes used, in the default machine order, then others alphabetically
  std::set<char> axes;
  for (size_t u : units)
    collectAxes(set.files[u], axes);
  for (char c : lang::kDefaultAxisLetters)
    if (axes.erase(c)) out.axes.push_back(c);
  for (char c : axes)
    out.axes.push_back(c);
  for (size_t k = 0; k < units.size(); ++k) {
    const File& f = set.files[units[k]];
    if (f.kind == UnitKind::Sub) lk.procIndex.emplace(support::upperCopy(f.procName), static_cast<uint32_t>(k));
  }
  for (size_t k = 0; k < units.size(); ++k) {
    size_t u = units[k];
    const File& f = set.files[u];
    image::Proc p;
    p.kind = f.kind;
    p.name = lk.str(f.kind == UnitKind::Sub ? std::string(f.procName) : stemOf(f.path));
    p.file = lk.str(recordedPath(base, f.path));
    p.entry = static_cast<uint32_t>(out.code.size());
    File line; // the compact form: the line being compiled
    ProcCompiler pc(f, set.flows[u], lk, p.file, opts.strip, opts.reparse ? &line : nullptr);
    pc.dialect_ = opts.dialect;
    pc.specialM_ = specialM;
    pc.parameters_ = opts.parameters;
    if (!opts.reparse)
      pc.compile(f.kind);
    else if (!compileReparsed(f, set.sources.file(f.id).text, opts, line, pc, err))
      return false;
    p.size = static_cast<uint32_t>(out.code.size()) - p.entry;
    out.procs.push_back(p);
    if (f.kind != UnitKind::Sub) {
      image::EntryPoint e;
      e.kind = p.kind;
      e.name = f.kind == UnitKind::Semi ? lk.str(f.semiName) : p.name;
      e.proc = static_cast<uint32_t>(k);
      out.entries.push_back(e);
    }
  }
  if (opts.strip) out.flags |= image::Image::kFlagStripped;
  if (opts.dialect == machine::Dialect::Z32) out.flags |= image::Image::kFlagZ32;
  return true;
}

} // namespace iso::compiler
