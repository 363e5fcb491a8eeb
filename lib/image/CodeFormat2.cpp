//! @file CodeFormat2.cpp
//! @brief Format-2 code: the recent-statement list shared by the encoder and the decoder (both
//!        drive it with the same events, so they always agree), the expansion of a recalled
//!        statement, the decoder and the encoder.
#include "image/CodeFormat2.h"

#include <algorithm>
#include <array>
#include <cstring>

#include <fmt/format.h>

#include "image/Opcode.h"
#include "support/Bytes.h"
#include "support/Memory.h"

namespace iso::image {

using namespace code2;
using support::ByteCursor;
using support::LebError;

namespace {

// A plain unit is an opcode byte: every opcode must stay below the recall codes (and is not 0,
// the raw unit).
constexpr bool opcodesFitPlainUnits() {
  for (unsigned b = 0; b < 256; ++b)
    if (detail::kOpTable[b].valid && (b == kRaw || b >= kRecall)) return false;
  return true;
}
static_assert(opcodesFitPlainUnits(), "format 2: opcodes must be 0x01..0x7F (Opcodes.def)");

uint64_t zigzag(int64_t v) { return (static_cast<uint64_t>(v) << 1) ^ static_cast<uint64_t>(v >> 63); }
int64_t unzigzag(uint64_t u) { return static_cast<int64_t>(u >> 1) ^ -static_cast<int64_t>(u & 1); }

/// The scale of a field that is not a decimal number (an integer, a jump distance).
constexpr uint8_t kNotNumber = 0xFF;

bool isStatementStart(Op op) { return op == Op::Stmt || op == Op::StmtSkip; }

/// A statement as the recent list keeps it: its shape (the instructions without their field
/// values; every push.d<k> as push.d0) and its fields.
struct Statement {
  std::vector<uint8_t> shape;
  std::vector<int64_t> value; ///< a number's mantissa at `scale` places; an integer; a jump distance
  std::vector<uint8_t> scale; ///< decimal places of a number, kNotNumber for the others
  uint32_t bytes = 0;         ///< decoded bytes
  bool recallable = true;     ///< within kMaxFields and kMaxStatementBytes, every instruction coded

  /// The shape compiled for expand(): the decoded bytes that do not depend on a field (`fixed`),
  /// cut into runs, each followed by one field (or by nothing, the last).
  enum class Emit : uint8_t { End, Number, Uleb, CaseConst, Target };
  struct Run {
    uint16_t fixedEnd;   ///< the run is fixed[previous fixedEnd, fixedEnd)
    Emit emit;           ///< then this field is written
    uint8_t instruction; ///< the field's instruction starts this many bytes into the run
                         ///< (kSameInstruction: in an earlier run)
  };
  static constexpr uint8_t kSameInstruction = 0xFF;
  static constexpr size_t kPad = 16;
  std::vector<uint8_t> fixed;
  std::vector<Run> runs;

  void compile() {
    fixed.clear();
    runs.clear();
    size_t runStart = 0;
    uint8_t instruction = kSameInstruction;
    auto field = [&](Emit e) {
      runs.push_back({static_cast<uint16_t>(fixed.size()), e, instruction});
      runStart = fixed.size();
      instruction = kSameInstruction;
    };
    for (size_t k = 0; k < shape.size();) {
      instruction = static_cast<uint8_t>(fixed.size() - runStart);
      const uint8_t op = shape[k++];
      switch (opInfo(op).shape) {
      case Shape::None: fixed.push_back(op); break;
      case Shape::Dec: field(Emit::Number); break; // the number writes its push.d<k>
      case Shape::Uleb:
        fixed.push_back(op);
        field(Emit::Uleb);
        break;
      case Shape::U8:
      case Shape::U8U8: {
        const size_t n = opInfo(op).shape == Shape::U8 ? 1 : 2;
        fixed.push_back(op);
        fixed.insert(fixed.end(), shape.begin() + static_cast<std::ptrdiff_t>(k),
                     shape.begin() + static_cast<std::ptrdiff_t>(k + n));
        k += n;
        break;
      }
      case Shape::Addr:
        fixed.push_back(op);
        field(Emit::Target);
        break;
      case Shape::When:
      case Shape::Range:
        fixed.push_back(op);
        field(Emit::Target);
        field(Emit::Target);
        break;
      case Shape::Case: {
        const uint8_t arms = shape[k++];
        const bool hasDefault = shape[k++] != 0;
        fixed.push_back(op);
        support::ByteWriter(fixed).uleb(arms);
        for (unsigned a = 0; a < arms; ++a) {
          field(Emit::CaseConst);
          field(Emit::Target);
        }
        if (hasDefault)
          field(Emit::Target);
        else
          support::ByteWriter(fixed).u32(kNoTarget);
        break;
      }
      case Shape::Move: {
        const uint8_t n = shape[k];
        fixed.push_back(op);
        fixed.insert(fixed.end(), shape.begin() + static_cast<std::ptrdiff_t>(k),
                     shape.begin() + static_cast<std::ptrdiff_t>(k + 1 + n));
        k += 1 + n;
        break;
      }
      }
    }
    instruction = kSameInstruction;
    field(Emit::End);
    fixed.resize(fixed.size() + kPad); // expand() copies runs of up to kPad bytes at once
  }

  void clear() {
    shape.clear();
    value.clear();
    scale.clear();
    bytes = 0;
    recallable = true;
  }
  void field(int64_t v, uint8_t s) {
    value.push_back(v);
    scale.push_back(s);
    if (value.size() > kMaxFields) recallable = false;
  }
  /// Appends instruction `in` (decoded at offset in.offset).
  void add(const Instr& in) {
    bytes += in.length;
    if (bytes > kMaxStatementBytes) recallable = false;
    const auto op = static_cast<uint8_t>(in.op);
    const auto rel = [&](uint32_t target) { return static_cast<int64_t>(target) - static_cast<int64_t>(in.offset); };
    switch (opInfo(op).shape) {
    case Shape::None: shape.push_back(op); break;
    case Shape::Dec:
      shape.push_back(static_cast<uint8_t>(Op::PushD0));
      field(in.s, static_cast<uint8_t>(op - static_cast<uint8_t>(Op::PushD0)));
      break;
    case Shape::Uleb:
      shape.push_back(op);
      field(static_cast<int64_t>(in.u), kNotNumber);
      break;
    case Shape::U8:
      shape.push_back(op);
      shape.push_back(static_cast<uint8_t>(in.u));
      break;
    case Shape::U8U8:
      shape.push_back(op);
      shape.push_back(static_cast<uint8_t>(in.u));
      shape.push_back(in.u2);
      break;
    case Shape::Addr:
      shape.push_back(op);
      field(rel(in.addr), kNotNumber);
      break;
    case Shape::When:
    case Shape::Range:
      shape.push_back(op);
      field(rel(in.addr), kNotNumber);
      field(rel(in.addr2), kNotNumber);
      break;
    case Shape::Case:
      shape.push_back(op);
      shape.push_back(static_cast<uint8_t>(in.arms.size()));
      shape.push_back(in.caseDefault != kNoTarget ? 1 : 0);
      for (const auto& [c, t] : in.arms) {
        field(c, kNotNumber);
        field(rel(t), kNotNumber);
      }
      if (in.caseDefault != kNoTarget) field(rel(in.caseDefault), kNotNumber);
      break;
    case Shape::Move:
      shape.push_back(op);
      shape.push_back(static_cast<uint8_t>(in.moves.size()));
      shape.insert(shape.end(), in.moves.begin(), in.moves.end());
      break;
    }
    if (!in.minimal) recallable = false; // a recall writes minimal LEB128 only
  }
};

/// The statements of the current procedure seen most recently, and the one being read
/// instruction by instruction. The encoder and the decoder make the same calls in the same
/// order, so their lists are always equal.
class RecentList {
public:
  void reset() {
    count_ = 0;
    building_ = false;
  }
  unsigned size() const { return count_; }
  Statement& at(unsigned j) { return slots_[order_[j]]; }

  /// A statement coded instruction by instruction: each of its instructions.
  void instruction(const Instr& in) {
    if (isStatementStart(in.op)) {
      commit();
      pending_.clear();
      building_ = true;
    }
    if (building_) pending_.add(in);
  }
  /// Before a recalled statement: the statement being read ends.
  void commit() {
    if (building_) enter();
  }
  /// Raw bytes: the statement being read is not kept.
  void drop() { building_ = false; }
  /// Statement j was recalled with `values`: it becomes the most recent.
  void recalled(unsigned j, const int64_t* values) {
    Statement& s = at(j);
    if (values != s.value.data()) std::copy(values, values + s.value.size(), s.value.begin());
    const uint8_t slot = order_[j];
    for (unsigned k = j; k > 0; --k) // j is small: a loop, not a call
      order_[k] = order_[k - 1];
    order_[0] = slot;
  }

private:
  [[gnu::noinline]] void enter() {
    if (pending_.recallable) {
      const unsigned slot = count_ < kRecent ? count_++ : order_[kRecent - 1];
      std::move_backward(order_.begin(), order_.begin() + count_ - 1, order_.begin() + count_);
      order_[0] = static_cast<uint8_t>(slot);
      pending_.compile();
      std::swap(slots_[slot], pending_);
    }
    building_ = false;
  }

  std::array<Statement, kRecent> slots_;
  std::array<uint8_t, kRecent> order_{};
  unsigned count_ = 0;
  Statement pending_;
  bool building_ = false;
};

/// Writes at a pointer into a buffer known to be large enough (LEB128 minimal).
struct Sink {
  uint8_t* p;
  void u8(uint8_t v) { *p++ = v; }
  void u32(uint32_t v) {
    for (int i = 0; i < 4; ++i)
      *p++ = static_cast<uint8_t>(v >> (8 * i));
  }
  void uleb(uint64_t v) {
    while (v >= 0x80) {
      *p++ = static_cast<uint8_t>(v | 0x80);
      v >>= 7;
    }
    *p++ = static_cast<uint8_t>(v);
  }
  void sleb(int64_t v) {
    if (v >= -64 && v < 64) {
      *p++ = static_cast<uint8_t>(v & 0x7F);
      return;
    }
    if (v >= -8192 && v < 8192) {
      *p++ = static_cast<uint8_t>((v & 0x7F) | 0x80);
      *p++ = static_cast<uint8_t>((v >> 7) & 0x7F);
      return;
    }
    for (;;) {
      const auto b = static_cast<uint8_t>(v & 0x7F);
      v >>= 7;
      if ((v == 0 && !(b & 0x40)) || (v == -1 && (b & 0x40))) {
        *p++ = b;
        return;
      }
      *p++ = b | 0x80;
    }
  }
};

/// The most bytes a recalled statement decodes to: its shape (at most kMaxStatementBytes) and
/// at most 5 bytes more per field (a 5-byte LEB128 or a u32 where the shape has none), and
/// what expand() may write past its end (a padded run).
constexpr size_t kMaxRecallBytes = kMaxStatementBytes + kMaxFields * 5 + Statement::kPad;

/// Writes the decoded code of statement `s` (compiled) with field values `v` at `dst` (room
/// for kMaxRecallBytes), the first instruction at decoded offset `base`; returns the end, or
/// nullptr with `why` when a value does not fit its instruction.
uint8_t* expand(const Statement& s, const int64_t* v, uint32_t base, uint8_t* dst, std::string& why) {
  using Emit = Statement::Emit;
  Sink w{dst};
  const uint8_t* fixed = s.fixed.data();
  const uint8_t* instruction = dst;
  size_t from = 0, f = 0;
  for (const Statement::Run& r : s.runs) {
    uint8_t* run = w.p;
    const size_t n = r.fixedEnd - from;
    if (n <= Statement::kPad) // fixed is padded: one fixed-size copy
      std::memcpy(w.p, fixed + from, Statement::kPad);
    else
      std::memcpy(w.p, fixed + from, n);
    w.p += n;
    from = r.fixedEnd;
    if (r.instruction != Statement::kSameInstruction) instruction = run + r.instruction;
    if (r.emit == Emit::End) return w.p;
    const int64_t x = v[f];
    switch (r.emit) {
    case Emit::End: return w.p;
    case Emit::Number: {
      if (x > kMaxMantissa || x < -kMaxMantissa) {
        why = fmt::format("field {}: mantissa {} outside -2^33..2^33", f, x);
        return nullptr;
      }
      int64_t m = x;
      int places = s.scale[f];
      while (places > 0 && m % 10 == 0) {
        m /= 10;
        --places;
      }
      w.u8(static_cast<uint8_t>(static_cast<int>(Op::PushD0) + places));
      w.sleb(m);
      break;
    }
    case Emit::Uleb:
    case Emit::CaseConst: {
      const uint64_t limit = r.emit == Emit::Uleb ? (uint64_t{1} << 35) - 1 : 0xFFFFFFFFu;
      if (x < 0 || static_cast<uint64_t>(x) > limit) {
        why = fmt::format("field {}: value {} outside 0..{}", f, x, limit);
        return nullptr;
      }
      w.uleb(static_cast<uint64_t>(x));
      break;
    }
    case Emit::Target: {
      // (x is bounded before it is added: a field reaches INT64_MAX)
      const int64_t t =
          x < -0x100000000LL || x > 0x100000000LL ? -1 : static_cast<int64_t>(base) + (instruction - dst) + x;
      if (t < 0 || t > 0xFFFFFFFFLL) {
        why = fmt::format("field {}: jump distance {} leads outside 0..0xFFFFFFFF", f, x);
        return nullptr;
      }
      w.u32(static_cast<uint32_t>(t));
      break;
    }
    }
    ++f;
  }
  return w.p;
}

/// The boundaries after `from` (an index into the sorted list) are passed one by one.
struct Boundaries {
  const std::vector<uint32_t>& at;
  size_t next = 0;
  /// True when `offset` is a boundary not yet passed (the state resets there).
  bool reached(uint32_t offset) {
    bool hit = false;
    while (next < at.size() && at[next] <= offset) {
      hit = hit || at[next] == offset;
      ++next;
    }
    return hit;
  }
  /// The first boundary after the offset last passed to reached(), or UINT64_MAX.
  uint64_t after() const { return next < at.size() ? at[next] : UINT64_MAX; }
};

/// An unsigned LEB128 field of at most 10 bytes, minimal; the two-byte case inline.
inline LebError fieldVarint(ByteCursor& c, uint64_t& v) {
  if (c.left() >= 2) {
    const uint8_t* p = c.data() + c.pos();
    if (p[0] < 0x80) {
      v = p[0];
      c.skip(1);
      return LebError::None;
    }
    if (p[1] < 0x80) {
      v = (p[0] & 0x7Fu) | uint64_t{p[1]} << 7;
      c.skip(2);
      return p[1] == 0 ? LebError::NonMinimal : LebError::None;
    }
  }
  return c.uleb(v, 10);
}

class Decoder {
public:
  Decoder(const uint8_t* data, size_t size, const std::vector<uint32_t>& bounds, std::vector<uint8_t>& out,
          std::vector<CodeUnit>* units)
      : d_(data), size_(size), bounds_{bounds}, out_(out), units_(units) {}

  bool run(uint32_t& errAt, std::string& why) {
    out_.clear();
    // the decoded size the procedures claim (at most kMaxExpansion times the section), to grow
    // by half if the code decodes to more
    const uint64_t claimed = bounds_.at.empty() ? 0 : bounds_.at.back();
    const size_t room = static_cast<size_t>(std::min<uint64_t>(claimed, uint64_t{kMaxExpansion} * size_)) + kRoom;
    support::reserveHuge(out_, room);
    out_.resize(room);
    uint64_t limit = 0; // the next procedure boundary

    recent_.reset();
    ByteCursor c(d_, 0, size_);
    while (c.left() > 0) {
      const auto unitAt = static_cast<uint32_t>(c.pos());
      const auto from = static_cast<uint32_t>(len_);
      if (from >= limit) {
        if (bounds_.reached(from)) recent_.reset();
        limit = bounds_.after();
      }
      if (len_ + kRoom > out_.size()) out_.resize(out_.size() + out_.size() / 2 + kRoom);
      const uint8_t b = d_[c.pos()];
      bool ok;
      if (b == kRaw)
        ok = raw(c, why);
      else if (b < kRecall)
        ok = plain(c, from, why);
      else if (b < kRecallEnd)
        ok = recall(c, from, why);
      else
        ok = fail(why, fmt::format("unit code 0x{:02X} is not used (0xC0..0xFF)", b));
      if (ok && len_ > limit)
        ok = fail(why, fmt::format("the unit's code (decoded 0x{:04X}..0x{:04X}) crosses the procedure boundary "
                                   "at 0x{:04X}",
                                   from, len_, limit));
      if (ok && len_ > 0xFFFFFFFFu) ok = fail(why, "the decoded code exceeds 4 GiB");
      if (!ok) {
        errAt = unitAt;
        why = fmt::format("format 2 code unit at 0x{:04X}: {}", unitAt, why);
        out_.resize(len_);
        return false;
      }
      if (units_) units_->push_back({from, unitAt});
    }
    out_.resize(len_);
    return true;
  }

private:
  /// Room made before each unit: the most any unit but a raw one decodes to (a case of 255
  /// arms: 1 + 2 + 255 x 9 + 4 bytes), and more than a recall's kMaxRecallBytes.
  static constexpr size_t kRoom = 4096;
  const uint8_t* d_;
  size_t size_;
  Boundaries bounds_;
  std::vector<uint8_t>& out_;
  size_t len_ = 0; ///< bytes of out_ decoded so far (out_ is larger: room to write into)
  std::vector<CodeUnit>* units_;
  RecentList recent_;
  Instr in_;

  static bool fail(std::string& why, std::string msg) {
    why = std::move(msg);
    return false;
  }
  static bool leb(LebError e, std::string& why, const char* what) {
    switch (e) {
    case LebError::None: return true;
    case LebError::Truncated: return fail(why, fmt::format("truncated varint ({})", what));
    case LebError::NonMinimal: return fail(why, fmt::format("non-minimal varint ({})", what));
    default: return fail(why, fmt::format("varint too large ({})", what));
    }
  }

  bool raw(ByteCursor& c, std::string& why) {
    c.skip(1);
    uint64_t n;
    if (!leb(c.uleb(n, 5), why, "raw length")) return false;
    if (n == 0 || n > c.left())
      return fail(why, fmt::format("raw length {} (1..{}, the bytes left in the section)", n, c.left()));
    if (len_ + n + kRoom > out_.size()) out_.resize(out_.size() + out_.size() / 2 + static_cast<size_t>(n) + kRoom);
    std::memcpy(out_.data() + len_, d_ + c.pos(), static_cast<size_t>(n));
    len_ += static_cast<size_t>(n);
    c.skip(static_cast<size_t>(n));
    recent_.drop();
    return true;
  }

  /// A jump distance: sleb, the target = from + distance, inside 0..2^32-1.
  bool distance(ByteCursor& c, uint32_t from, uint32_t& target, std::string& why) {
    int64_t rel;
    if (!leb(c.sleb(rel, 10), why, "jump distance")) return false;
    // (the distance is bounded before it is added: a sleb of 10 bytes reaches INT64_MAX)
    if (rel < -0x100000000LL || rel > 0x100000000LL)
      return fail(why, fmt::format("jump distance {} leads outside 0..0xFFFFFFFF", rel));
    const int64_t t = static_cast<int64_t>(from) + rel;
    if (t < 0 || t > 0xFFFFFFFFLL) return fail(why, fmt::format("jump distance {} leads outside 0..0xFFFFFFFF", rel));
    target = static_cast<uint32_t>(t);
    return true;
  }

  /// One instruction of format 1; jump targets as distances from the instruction.
  bool plain(ByteCursor& c, uint32_t from, std::string& why) {
    const uint8_t op = d_[c.pos()];
    const OpInfo& info = opInfo(op);
    if (!info.valid) return fail(why, fmt::format("0x{:02X} is no opcode", op));
    Instr& in = in_;
    Sink w{out_.data() + len_};
    switch (info.shape) {
    case Shape::Addr:
    case Shape::When:
    case Shape::Range:
    case Shape::Case: {
      in.op = static_cast<Op>(op);
      in.offset = from;
      in.minimal = true;
      in.arms.clear();
      in.caseDefault = kNoTarget;
      c.skip(1);
      w.u8(op);
      if (info.shape == Shape::Case) {
        uint64_t n;
        if (!leb(c.uleb(n, 5), why, "case arm count")) return false;
        if (n == 0 || n > kMaxCaseArms) return fail(why, fmt::format("case with {} arms (1..{})", n, kMaxCaseArms));
        w.uleb(n);
        for (uint64_t a = 0; a < n; ++a) {
          uint64_t k;
          uint32_t t;
          if (!leb(c.uleb(k, 5), why, "case constant")) return false;
          if (k > 0xFFFFFFFFu) return fail(why, "case constant index too large");
          if (!distance(c, from, t, why)) return false;
          w.uleb(k);
          w.u32(t);
          in.arms.emplace_back(static_cast<uint32_t>(k), t);
        }
        uint8_t hasDefault;
        if (!c.u8(hasDefault)) return fail(why, "truncated case default");
        if (hasDefault > 1) return fail(why, fmt::format("case default flag {} (0 or 1)", hasDefault));
        if (hasDefault && !distance(c, from, in.caseDefault, why)) return false;
        w.u32(in.caseDefault);
      } else {
        if (!distance(c, from, in.addr, why)) return false;
        w.u32(in.addr);
        if (info.shape == Shape::When || info.shape == Shape::Range) {
          if (!distance(c, from, in.addr2, why)) return false;
          w.u32(in.addr2);
        }
      }
      in.length = static_cast<uint32_t>(w.p - (out_.data() + len_));
      break;
    }
    default: {
      if (const DecodeStatus st = decode(d_, size_, static_cast<uint32_t>(c.pos()), in); !st)
        return fail(why, st.message());
      std::memcpy(w.p, d_ + c.pos(), in.length);
      c.skip(in.length);
      in.offset = from;
      break;
    }
    }
    len_ += in.length;
    recent_.instruction(in);
    return true;
  }

  bool recall(ByteCursor& c, uint32_t from, std::string& why) {
    const uint8_t b = d_[c.pos()];
    c.skip(1);
    const bool masked = b >= kRecallMasked;
    const unsigned j = b & 0x1Fu;
    recent_.commit();
    if (j >= recent_.size())
      return fail(why,
                  fmt::format("recalls statement {}; the procedure has {} recent statement(s)", j, recent_.size()));
    Statement& s = recent_.at(j);
    const size_t n = s.value.size();
    int64_t* v = s.value.data(); // the new values replace the old ones (on failure nothing is kept)
    uint64_t mask = n == 0 ? 0 : (uint64_t{1} << n) - 1;
    if (masked) {
      if (!leb(c.uleb(mask, 5), why, "field mask")) return false;
      if (mask >> n)
        return fail(why, fmt::format("field mask 0x{:X} names a field beyond the statement's {}", mask, n));
    }
    for (size_t i = 0; i < n; ++i) {
      if (!(mask >> i & 1)) continue;
      uint64_t t;
      if (!leb(fieldVarint(c, t), why, "field")) return false;
      const int64_t x = unzigzag(t >> 1);
      const int64_t old = v[i];
      if (t & 1)
        v[i] = x;
      else if (__builtin_add_overflow(old, x, &v[i]))
        return fail(why, fmt::format("field {}: {} + {} overflows", i, old, x));
    }
    uint8_t* end = expand(s, v, from, out_.data() + len_, why);
    if (!end) return false;
    len_ = static_cast<size_t>(end - out_.data());
    recent_.recalled(j, v);
    return true;
  }
};

/// The bytes of a field's varint: the change from `old` (low bit 0) or the value (low bit 1),
/// whichever is shorter (the change when equal).
uint64_t fieldCode(int64_t old, int64_t value) {
  int64_t delta = 0;
  const bool fits = !__builtin_sub_overflow(value, old, &delta);
  const uint64_t byDelta = zigzag(delta) << 1;
  const uint64_t byValue = zigzag(value) << 1 | 1;
  if (fits && (zigzag(delta) >> 63) == 0 && support::ulebLength(byDelta) <= support::ulebLength(byValue))
    return byDelta;
  return byValue;
}

class Encoder {
public:
  Encoder(const std::vector<uint8_t>& code, const std::vector<uint32_t>& bounds, std::vector<CodeUnit>* units)
      : code_(code), bounds_(bounds), units_(units) {}

  std::vector<uint8_t> run() {
    support::reserveHuge(out_, code_.size() / 2 + 64); // (it codes to less than half: grows if not)
    std::vector<uint32_t> cuts{0};
    for (uint32_t b : bounds_)
      if (b > 0 && b < code_.size()) cuts.push_back(b);
    cuts.push_back(static_cast<uint32_t>(code_.size()));
    for (size_t i = 0; i + 1 < cuts.size(); ++i)
      if (cuts[i] < cuts[i + 1]) range(cuts[i], cuts[i + 1]);
    return std::move(out_);
  }

private:
  const std::vector<uint8_t>& code_;
  const std::vector<uint32_t>& bounds_;
  std::vector<CodeUnit>* units_;
  std::vector<uint8_t> out_;
  RecentList recent_;
  std::vector<Instr> stmt_; ///< the instructions of the statement being coded
  Statement shape_;         ///< its shape and fields
  std::vector<uint8_t> check_ = std::vector<uint8_t>(kMaxRecallBytes);

  void unit(uint32_t decoded) {
    if (units_) units_->push_back({decoded, static_cast<uint32_t>(out_.size())});
  }

  void range(uint32_t begin, uint32_t end) {
    recent_.reset();
    for (uint32_t off = begin; off < end;) {
      // a statement: from a stmt or stmt.skip to the next one (code before the first one of a
      // procedure is coded instruction by instruction)
      stmt_.clear();
      Instr in;
      bool bad = !decode(code_.data(), end, off, in);
      if (!bad) {
        stmt_.push_back(in);
        off += in.length;
      }
      while (!bad && off < end && isStatementStart(stmt_.front().op)) {
        if (!decode(code_.data(), end, off, in)) {
          bad = true;
          break;
        }
        if (isStatementStart(in.op)) break;
        stmt_.push_back(in);
        off += in.length;
      }
      if (bad || stmt_.empty() || !isStatementStart(stmt_.front().op) || !recallOne())
        for (const Instr& i : stmt_)
          plain(i);
      if (bad) { // bytes that are no instruction: raw to the end of the procedure
        raw(off, end - off);
        off = end;
      }
    }
  }

  void raw(uint32_t off, uint32_t n) {
    unit(off);
    out_.push_back(kRaw);
    support::ByteWriter(out_).uleb(n);
    out_.insert(out_.end(), code_.begin() + off, code_.begin() + off + n);
    recent_.drop();
  }

  void plain(const Instr& in) {
    if (in.op == Op::Case && !in.minimal) { // a crafted case with a non-minimal uleb: raw keeps its bytes
      raw(in.offset, in.length);
      return;
    }
    unit(in.offset);
    support::ByteWriter w(out_);
    const auto rel = [&](uint32_t t) { return static_cast<int64_t>(t) - static_cast<int64_t>(in.offset); };
    switch (opInfo(static_cast<uint8_t>(in.op)).shape) {
    case Shape::Addr:
      w.u8(static_cast<uint8_t>(in.op));
      w.sleb(rel(in.addr));
      break;
    case Shape::When:
    case Shape::Range:
      w.u8(static_cast<uint8_t>(in.op));
      w.sleb(rel(in.addr));
      w.sleb(rel(in.addr2));
      break;
    case Shape::Case:
      w.u8(static_cast<uint8_t>(in.op));
      w.uleb(in.arms.size());
      for (const auto& [k, t] : in.arms) {
        w.uleb(k);
        w.sleb(rel(t));
      }
      w.u8(in.caseDefault != kNoTarget ? 1 : 0);
      if (in.caseDefault != kNoTarget) w.sleb(rel(in.caseDefault));
      break;
    default: w.bytes(code_.data() + in.offset, in.length); break;
    }
    recent_.instruction(in);
  }

  /// Codes stmt_ as a recall of the recent statement that takes the fewest bytes; false if
  /// none has its shape or can give back its exact bytes.
  bool recallOne() {
    shape_.clear();
    for (const Instr& i : stmt_)
      shape_.add(i);
    if (!shape_.recallable) return false;
    recent_.commit(); // as the decoder does before a recall
    const uint32_t at = stmt_.front().offset;
    const uint32_t length = stmt_.back().offset + stmt_.back().length - at;
    const size_t n = shape_.value.size();
    std::array<int64_t, kMaxFields> v{};
    size_t bestBytes = SIZE_MAX;
    unsigned best = 0;
    bool bestMasked = false;
    std::array<int64_t, kMaxFields> bestV{};
    for (unsigned j = 0; j < recent_.size(); ++j) {
      const Statement& r = recent_.at(j);
      if (r.shape != shape_.shape) continue;
      bool fits = true;
      for (size_t i = 0; i < n && fits; ++i) {
        v[i] = shape_.value[i];
        if (r.scale[i] == kNotNumber) continue;
        // a number: its mantissa at the recent statement's places
        for (int p = shape_.scale[i]; p < r.scale[i] && fits; ++p)
          fits = !__builtin_mul_overflow(v[i], 10, &v[i]);
        fits = fits && shape_.scale[i] <= r.scale[i];
      }
      if (!fits) continue;
      std::string why;
      const uint8_t* end = expand(r, v.data(), at, check_.data(), why);
      if (!end || static_cast<size_t>(end - check_.data()) != length ||
          !std::equal(static_cast<const uint8_t*>(check_.data()), end, code_.data() + at))
        continue;
      size_t all = 1, masked = 1;
      uint64_t mask = 0;
      for (size_t i = 0; i < n; ++i) {
        const size_t b = support::ulebLength(fieldCode(r.value[i], v[i]));
        all += b;
        if (v[i] != r.value[i]) {
          masked += b;
          mask |= uint64_t{1} << i;
        }
      }
      masked += support::ulebLength(mask);
      const size_t bytes = std::min(all, masked);
      if (bytes < bestBytes) {
        bestBytes = bytes;
        best = j;
        bestMasked = masked < all;
        bestV = v;
      }
    }
    if (bestBytes == SIZE_MAX) return false;
    const Statement& r = recent_.at(best);
    unit(at);
    support::ByteWriter w(out_);
    w.u8(static_cast<uint8_t>((bestMasked ? kRecallMasked : kRecall) + best));
    uint64_t mask = 0;
    for (size_t i = 0; i < n; ++i)
      if (bestV[i] != r.value[i]) mask |= uint64_t{1} << i;
    if (bestMasked) w.uleb(mask);
    for (size_t i = 0; i < n; ++i)
      if (!bestMasked || (mask >> i & 1)) w.uleb(fieldCode(r.value[i], bestV[i]));
    recent_.recalled(best, bestV.data());
    return true;
  }
};

} // namespace

std::vector<uint32_t> codeBoundaries(const std::vector<Proc>& procs) {
  std::vector<uint32_t> b;
  b.reserve(procs.size() * 2);
  for (const Proc& p : procs) {
    b.push_back(p.entry);
    const uint64_t end = uint64_t{p.entry} + p.size;
    if (end <= 0xFFFFFFFFu) b.push_back(static_cast<uint32_t>(end));
  }
  std::sort(b.begin(), b.end());
  b.erase(std::unique(b.begin(), b.end()), b.end());
  return b;
}

std::vector<uint8_t> encodeCode2(const std::vector<uint8_t>& code, const std::vector<uint32_t>& boundaries,
                                 std::vector<CodeUnit>* units) {
  return Encoder(code, boundaries, units).run();
}

std::optional<Code2Error> decodeCode2(const uint8_t* data, size_t size, const std::vector<uint32_t>& boundaries,
                                      std::vector<uint8_t>& out, std::vector<CodeUnit>* units) {
  Code2Error e;
  if (Decoder(data, size, boundaries, out, units).run(e.at, e.message)) return std::nullopt;
  return e;
}

} // namespace iso::image
