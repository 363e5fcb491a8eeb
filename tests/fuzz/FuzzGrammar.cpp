//! @file FuzzGrammar.cpp
//! @brief Fuzz target: bytes -> a syntactically plausible program set (a generator driven by
//!        the bytes) -> frontend -> text diagnostics -> compiler -> image bytes -> reader +
//!        verifier -> interpreter with small budgets. Byte mutation rarely gets past the parser
//!        into the checks, the compiler and the interpreter; this target starts there.
//!
//! Each byte is a choice: which statement comes next, which G code, which axis, how a number
//! is written, where a `$` continuation splits a line, ... Choices are made in written order
//! (never two of them as arguments of one call, whose order GCC and clang evaluate
//! differently), so an input means the same program in the fuzzer and in any build's replay.
//! An exhausted input chooses 0, the simplest option, so every input ends (open IFs are
//! closed, the program gets its M30/M17). Now and then a choice injects noise instead (a
//! keyword, a code or a token out of place) so that the error paths are reached from deep
//! inside plausible programs too.
//!
//! Vocabulary: G codes, M functions, system variables and keywords come from the language
//! tables of lib/lang, diagnostic codes (for `isolint: disable=` comments)
//! from lib/diag/Diagnostics.def, axis letters from the built-in machine. The few lists that
//! have no table in lib/ yet are grammarOnly below (and nowhere else).
//!
//! The first byte picks the dialect (bit 0) and the number of subprograms (bits 1-2) and
//! whether a semi-automatic program joins the set (bit 3). Set the environment variable
//! ISO_FUZZ_PRINT=1 to print the generated files to stderr (to read what an input means).
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include <fmt/format.h>

#include "Support.h"
#include "diag/Render.h"
#include "format/Formatter.h"
#include "format/Renumber.h"
#include "frontend/ProgramSet.h"
#include "image/ImageWriter.h"
#include "lang/GCodes.h"
#include "lang/Keywords.h"
#include "lang/MFunctions.h"
#include "lang/SysVars.h"
#include "machine/Machine.h"
#include "sim/Run.h"

namespace {

// ---- vocabulary from the tables of lib/

struct Named {
  const char* text;
  int number;
};

namespace lang = iso::lang;

/// The system variables (number: 1 for those indexed by an axis), those a program reads while
/// it runs first, then machine data.
constexpr auto kSysVars = [] {
  std::array<Named, lang::kSysVarCount> a{};
  size_t n = 0;
  for (bool machineData : {false, true})
    for (const lang::SysVarInfo& v : lang::kSysVars)
      if (v.machineData == machineData) a[n++] = {v.name.data(), v.takesAxis ? 1 : 0};
  return a;
}();
/// The reserved keywords (the spellings are NUL-terminated string literals).
constexpr size_t kReservedCount = [] {
  size_t n = 0;
  for (const lang::KeywordInfo& k : lang::kKeywords)
    n += k.reserved ? 1 : 0;
  return n;
}();
constexpr auto kKeywords = [] {
  std::array<Named, kReservedCount> a{};
  size_t n = 0;
  for (const lang::KeywordInfo& k : lang::kKeywords)
    if (k.reserved) a[n++] = {k.spelling.data(), 0};
  return a;
}();

// NOLINTBEGIN(cppcoreguidelines-macro-usage)
#define DIAG(Enum, code, name, severity, description) {code, 0}, {name, 1},
constexpr Named kDiagNames[] = {
#include "diag/Diagnostics.def"
};
#undef DIAG
// NOLINTEND(cppcoreguidelines-macro-usage)

// ---- the lists that have no table in lib/ yet (SPEC §3.2, §4.5-§4.6)
namespace grammarOnly {
constexpr const char* kRelOps[] = {"==", "<>", "<", ">", "<=", ">="};
constexpr const char* kArithOps[] = {"+", "-", "*", "/"};
constexpr const char* kLogicOps[] = {"AND", "OR"};
constexpr const char* kArcWords[] = {"I", "J", "K", "CR"};
/// z32 M functions (SPEC §4.6): managed and final; plain PLC sequences are any other number
constexpr int kZ32M[] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 19};
/// z32 addresses beside the axes (SPEC §4.6)
constexpr const char* kZ32Words[] = {"S", "T", "MA", "MB", "MC"};
/// arc planes (SPEC §4.2): the G code, the two axes, the centre word of the first axis
constexpr const char* kPlanes[][4] = {{"G17", "X", "Y", "I"}, {"G18", "Z", "X", "K"}, {"G19", "Y", "Z", "J"}};
/// tokens for noise: what the grammar does not expect in a place (and some it never accepts)
constexpr const char* kNoise[] = {"=",   "(",     ")",  "[", "]", ":", "%", "#",   "\"",  "$",   "$aa_bogus[1]",
                                  "R0",  "R2881", "X",  "F", "G", "M", "N", "1e5", "..5", "DEF", "WHILE",
                                  "RET", "M98",   "G54"};
} // namespace grammarOnly

// ---- the byte stream of choices

class Choices {
public:
  Choices(const uint8_t* d, size_t n) : d_(d), n_(n) {}
  bool exhausted() const { return i_ >= n_; }
  unsigned byte() { return i_ < n_ ? d_[i_++] : 0; }
  size_t pick(size_t n) { return n <= 1 ? 0 : byte() % n; }
  /// true with probability k/256 (never once exhausted)
  bool chance(unsigned k) { return !exhausted() && byte() < k; }
  template <class T, size_t N> const T& from(const T (&a)[N]) { return a[pick(N)]; }
  template <class T, size_t N> const T& from(const std::array<T, N>& a) { return a[pick(N)]; }

private:
  const uint8_t* d_;
  size_t n_;
  size_t i_ = 0;
};

// ---- the generator

struct SetShape {
  bool z32 = false;
  size_t subs = 0;
  bool semi = false;
};

class Generator {
public:
  Generator(const SetShape& shape, std::string axes) : shape_(shape), axes_(std::move(axes)) {}

  /// One file from the choices `c`: a main program (kind 0), a subprogram (1) or a
  /// semi-automatic program (2).
  std::string file(Choices& c, int kind, size_t index) {
    c_ = &c;
    out_.clear();
    kind_ = kind;
    backward_.clear();
    labels_ = 0;
    forward_.clear();
    ifDepth_ = 0;
    if (kind == 1) line(fmt::format("PROC {} SAVE", subName(index)));
    if (kind == 2) line(fmt::format("SEMI \"semi {}{}\"", index, c_->chance(20) ? " $ caf\xC3\xA8" : ""));
    const size_t maxLines = 12 + c_->pick(60);
    for (size_t n = 0; n < maxLines && !c_->exhausted(); ++n)
      statement(kind, 0);
    // close what is open: forward labels, IFs, then the end
    for (size_t i = 0; i < forward_.size(); ++i)
      line(fmt::format("{}:", forward_[i]));
    forward_.clear();
    while (ifDepth_ > 0) {
      line("ENDIF");
      --ifDepth_;
    }
    if (!c_->chance(8)) line(kind == 1 ? "M17" : "M30");
    return out_;
  }

  static std::string subName(size_t i) { return fmt::format("Sub_{}", i); }

private:
  // -- lines, prefixes, comments, continuations

  void line(std::string text) {
    std::string prefix;
    if (c_->chance(10)) prefix += "% ";
    if (c_->chance(14)) prefix += "/";
    if (c_->chance(40))
      prefix += fmt::format("N{}{} ", ++nNumber_, c_->chance(40) ? (c_->chance(128) ? ".5" : ",25") : "");
    text = prefix + text;
    if (c_->chance(30)) text += comment();
    if (c_->chance(24) && text.size() > 2) {
      // split with `$` continuations (SPEC §2), never inside a `;` comment
      const size_t semi = text.find(';');
      const size_t limit = semi == std::string::npos ? text.size() : semi;
      if (limit > 1) {
        const size_t at = 1 + c_->pick(limit - 1);
        const size_t open = text.rfind('(', at - 1), close = text.rfind(')', at - 1);
        const bool inComment = open != std::string::npos && (close == std::string::npos || close < open);
        // a `$` in a ( ) comment is E103; a `$` before a letter would start a system variable
        if (!inComment && text[at - 1] != '$' && text[at] != '(') {
          std::string joined = text.substr(0, at);
          joined += c_->chance(128) ? "$" : "$ ignored tail";
          joined += '\n';
          joined += text.substr(at);
          text = std::move(joined);
        }
      }
    }
    out_ += text;
    out_ += c_->chance(8) ? "\r\n" : "\n";
    if (c_->chance(12)) out_ += c_->chance(128) ? "\n" : "; a comment line\n";
    if (c_->chance(6)) out_ += "( whole-line comment )\n";
  }

  std::string comment() {
    switch (c_->pick(4)) {
    case 0: return " ; note";
    case 1: return " (inline)";
    case 2: {
      const Named& d = c_->from(kDiagNames);
      return fmt::format(" ; isolint: disable={}", d.text);
    }
    default: return " ; commento \xC3\xA8 $ not a continuation";
    }
  }

  // -- numbers and expressions

  std::string number(bool allowSign) {
    std::string s;
    if (allowSign && c_->chance(50)) s += c_->chance(128) ? "-" : "+";
    const unsigned shape = static_cast<unsigned>(c_->pick(8));
    const unsigned v = c_->byte();
    switch (shape) {
    case 0: s += std::to_string(v); break;
    case 1: s += fmt::format("{}.{}", v, c_->pick(100)); break;
    case 2: s += fmt::format("{},{}", v, c_->pick(1000)); break;
    case 3: s += fmt::format(".{}", v); break;
    case 4: s += fmt::format("{}.", v); break;
    case 5: s += fmt::format("00{}", v); break;
    case 6: s += fmt::format("{}{}", v, c_->chance(8) ? "0000000000" : "000"); break; // rarely E101
    default: s += fmt::format(",{}", v); break;
    }
    return s;
  }

  char axis() { return axes_[c_->pick(axes_.size())]; }

  std::string sysvar(bool readOnlyOk) {
    const Named& v = c_->from(kSysVars);
    const std::string_view name = v.text;
    if (!readOnlyOk && (name.substr(0, 4) == "$MAX" || name.substr(0, 4) == "$POS")) return "$aa_iw[X]";
    if (v.number == 1) return fmt::format("{}[{}]", v.text, axis());
    return fmt::format("{}[{}]", v.text, c_->pick(8));
  }

  std::string rref() {
    if (c_->chance(24)) {
      const size_t base = c_->pick(10);
      return fmt::format("R[{} + R{}]", base, 1 + c_->pick(20));
    }
    return fmt::format("R{}", 1 + c_->pick(40));
  }

  std::string term(int depth) {
    switch (depth > 3 ? 0 : c_->pick(6)) {
    case 0: return number(false);
    case 1: return rref();
    case 2: return fmt::format("({})", expr(depth + 1));
    case 3: return fmt::format("-{}", term(depth + 1));
    case 4: return sysvar(false);
    default: return number(true);
    }
  }

  std::string expr(int depth) {
    std::string s = term(depth);
    const size_t n = depth > 3 ? 0 : c_->pick(4);
    for (size_t i = 0; i < n; ++i) {
      s += ' ';
      s += c_->from(grammarOnly::kArithOps);
      s += ' ';
      s += term(depth + 1);
    }
    return s;
  }

  std::string comparison(int depth) {
    const std::string left = expr(depth);
    const char* op = c_->from(grammarOnly::kRelOps);
    return fmt::format("{} {} {}", left, op, expr(depth));
  }

  std::string cond(int depth) {
    if (depth > 2 || c_->pick(3) != 0) return comparison(depth + 1);
    const char* negate = c_->chance(60) ? "NOT " : "";
    std::string s = fmt::format("{}({})", negate, cond(depth + 1));
    const size_t n = c_->pick(3);
    for (size_t i = 0; i < n; ++i) {
      const char* op = c_->from(grammarOnly::kLogicOps);
      negate = c_->chance(40) ? "NOT " : "";
      s += fmt::format(" {} {}({})", op, negate, cond(depth + 1));
    }
    return s;
  }

  // -- statements

  std::string label() { return fmt::format("L{}", labels_++); }

  /// A label to jump forward to: defined later in this file.
  std::string forwardLabel() {
    std::string l = label();
    forward_.push_back(l);
    return l;
  }

  /// A label defined earlier (or a fresh one defined now on its own line, for GOTOB).
  std::string backwardLabel() {
    if (!backward_.empty() && c_->chance(200)) return backward_[c_->pick(backward_.size())];
    std::string l = label();
    line(fmt::format("{}:", l));
    backward_.push_back(l);
    return l;
  }

  std::string gword() {
    const int g = c_->from(lang::kGCodes).code;
    if (c_->chance(4)) return fmt::format("G{}", c_->pick(100)); // maybe unknown or another dialect's
    if (g == 4 && !c_->chance(16)) return "G01";                 // G04 needs a line of its own
    if ((g == 2 || g == 3) && !c_->chance(16)) return "G00";     // arcs: see arc()
    return c_->chance(128) ? fmt::format("G{}", g) : fmt::format("G{:02}", g);
  }

  std::string mword() {
    if (shape_.z32 && c_->chance(100)) return fmt::format("M{}", c_->from(grammarOnly::kZ32M));
    if (c_->chance(80)) {
      const int m = c_->from(lang::kMFunctionDocs).number;
      if (m == 17 && kind_ != 1 && !c_->chance(16)) return "M0"; // M17 ends subprograms only
      return fmt::format("M{}", m);
    }
    if (c_->chance(60)) return fmt::format("M=NB({})", 10 + c_->pick(40));
    return fmt::format("M{}", 10 + c_->pick(90));
  }

  std::string axisItem(char a) {
    switch (c_->pick(5)) {
    case 0: return fmt::format("{}{}", a, number(true));
    case 1: return fmt::format("{}={}", a, expr(1));
    case 2: return fmt::format("Pos[{}]={}", a, expr(1));
    case 3: return fmt::format("Posa[{}]={}", a, expr(2));
    default: return fmt::format("{} {}", a, number(true));
    }
  }

  std::string block() {
    std::string s;
    const size_t items = 1 + c_->pick(5);
    std::string used;
    for (size_t i = 0; i < items; ++i) {
      if (!s.empty()) s += c_->chance(30) ? "" : " ";
      switch (c_->pick(10)) {
      case 0:
      case 1: s += gword(); break;
      case 2:
      case 3:
      case 4: {
        char a = axis();
        if (used.find(a) != std::string::npos && c_->pick(4) != 0) a = axes_[(axes_.find(a) + 1) % axes_.size()];
        used.push_back(a);
        s += axisItem(a);
        break;
      }
      case 5: s += c_->chance(128) ? fmt::format("F{}", number(false)) : fmt::format("F={}", expr(2)); break;
      case 6:
        if (!used.empty())
          s += fmt::format("Fa[{}]={}", used.back(), expr(2));
        else
          s += fmt::format("F{}", number(false));
        break;
      case 7:
        if (c_->chance(10)) { // E311 but on an arc
          s += c_->from(grammarOnly::kArcWords);
          s += fmt::format("={}", expr(2));
        } else {
          s += gword();
        }
        break;
      case 8: s += assignment(1); break;
      default:
        if (shape_.z32 && c_->chance(128)) {
          s += c_->from(grammarOnly::kZ32Words);
          s += number(true);
        } else {
          s += mword();
        }
        break;
      }
    }
    return s;
  }

  /// A statement that fits after THEN or a short DO.
  std::string simple(bool inWhen) {
    switch (c_->pick(inWhen ? 3 : 5)) {
    case 0: return block();
    case 1: {
      const std::string target = c_->chance(128) ? fmt::format("$aa_out[{}]", c_->pick(8)) : rref();
      return fmt::format("{} = {}", target, c_->chance(200) ? std::to_string(c_->pick(2)) : expr(1));
    }
    case 2: {
      const size_t marker = c_->pick(201);
      return fmt::format("$aa_marker[{}] = {}", marker, c_->pick(2));
    }
    case 3: return fmt::format("GOTOF {}", forwardLabel());
    default: return shape_.subs > 0 ? subName(c_->pick(shape_.subs)) : block();
    }
  }

  /// An arc in one of the planes, incremental: a full circle (centre) or a half circle (radius).
  void arc(const std::string& lab) {
    const auto& p = c_->from(grammarOnly::kPlanes);
    const unsigned r = 1 + c_->pick(50);
    const char* dir = c_->chance(128) ? "G02" : "G03";
    if (c_->chance(128))
      line(lab + fmt::format("{} G91 {} {}0 {}0 {}={} F{}", p[0], dir, p[1], p[2], p[3], r, 10 + c_->pick(200)));
    else {
      const char* sign = c_->chance(40) ? "-" : "";
      line(lab +
           fmt::format("{} G91 {} {}{} {}0 CR={}{} F{}", p[0], dir, p[1], 2 * r, p[2], sign, r, 10 + c_->pick(200)));
    }
    line(c_->chance(200) ? "G90 G01" : "G90 G00 G64");
  }

  std::string assignment(int depth) {
    const std::string target = rref();
    return fmt::format("{} = {}", target, expr(depth));
  }

  std::string noise() {
    if (c_->chance(128)) return c_->from(grammarOnly::kNoise);
    return c_->from(kKeywords).text;
  }

  void statement(int kind, int depth) {
    std::string lab;
    if (c_->chance(20)) {
      lab = label() + ": ";
      backward_.push_back(lab.substr(0, lab.size() - 2));
    }
    const size_t what = c_->pick(depth > 2 ? 6 : 16);
    switch (what) {
    case 0: // motion, the common case
    case 1: line(lab + block()); break;
    case 2: line(lab + assignment(0)); break;
    case 3:
      line(lab + (c_->chance(128) ? fmt::format("G04 F{}", number(false)) : fmt::format("G04 F={}", expr(1))));
      break;
    case 4: line(lab + mword()); break;
    case 5: {
      const size_t r = 1 + c_->pick(30);
      line(lab + fmt::format("R{} = {}", r, sysvar(true)));
      break;
    }
    case 6: { // block IF
      line(lab + fmt::format("IF {}", cond(0)));
      ++ifDepth_;
      const size_t n = c_->pick(4);
      for (size_t i = 0; i < n; ++i)
        statement(kind, depth + 1);
      if (c_->chance(100)) {
        line("ELSE");
        const size_t m = c_->pick(3);
        for (size_t i = 0; i < m; ++i)
          statement(kind, depth + 1);
      }
      if (!c_->chance(6)) {
        line("ENDIF");
        --ifDepth_;
      }
      break;
    }
    case 7: {
      const std::string c = cond(0);
      line(lab + fmt::format("IF {} THEN {}", c, simple(false)));
      break;
    }
    case 8: { // conditional jumps: a backward one is a loop, bounded by the step budget
      const unsigned j = c_->byte();
      if (j < 120)
        line(lab + fmt::format("IF {} GOTOF {}", cond(0), forwardLabel()));
      else if (j < 220) {
        const std::string l = backwardLabel();
        line(fmt::format("R{0} = R{0} + 1", 40 + c_->pick(5)));
        const size_t r = 40 + c_->pick(5);
        line(lab + fmt::format("IF R{} < {} GOTOB {}", r, c_->pick(20), l));
      } else
        line(lab + fmt::format("GOTO {}", c_->chance(128) ? forwardLabel() : backwardLabel()));
      break;
    }
    case 9: line(lab + fmt::format("GOTOF {}", forwardLabel())); break;
    case 10: { // CASE
      std::string s = fmt::format("CASE {} OF", expr(1));
      const size_t arms = 1 + c_->pick(5);
      for (size_t i = 0; i < arms; ++i)
        s += fmt::format(" {} GOTOF {}", number(true), forwardLabel());
      if (c_->chance(128)) s += fmt::format(" DEFAULT GOTOF {}", forwardLabel());
      line(lab + s);
      break;
    }
    case 11: { // WHEN: short or long form, chains of up to three, then the trigger
      // written in reverse order (SPEC §4.4): the body of each later WHEN is one path
      // instruction, the trigger of the WHEN above it; the last trigger follows the chain
      char a = axis();
      const size_t chain = 1 + (c_->chance(30) ? c_->pick(3) : 0);
      for (size_t i = 0; i < chain; ++i) {
        const char b = i == 0 ? a : axis();
        const char* op = c_->from(grammarOnly::kRelOps);
        const std::string cnd = fmt::format("$aa_iw[{}] {} {}", b, op, number(true));
        if (i > 0) {
          const std::string to = number(true);
          line(fmt::format("WHEN {} DO G01 {}{} F{}", cnd, a, to, 1 + c_->pick(500)));
        } else if (c_->chance(128)) {
          line(fmt::format("WHEN {} DO {}", cnd, simple(true)));
        } else {
          line(fmt::format("WHEN {} DO", cnd));
          const size_t n = 1 + c_->pick(3);
          for (size_t k = 0; k < n; ++k)
            line(simple(true));
          line("CANCEL");
        }
        a = b;
      }
      // the trigger: moves, blocking, the axis the last condition reads (else E213)
      const unsigned t = c_->byte();
      const std::string move = t < 120   ? fmt::format("{}{}", a, number(true))
                               : t < 240 ? fmt::format("Pos[{}]={}", a, expr(2))
                                         : fmt::format("Posa[{}]={}", a, number(true));
      line(fmt::format("G01 {} F{}", move, 1 + c_->pick(500)));
      break;
    }
    case 12: // a call
      if (shape_.subs > 0)
        line(lab + subName(c_->pick(shape_.subs + (c_->chance(10) ? 1 : 0))));
      else
        line(lab + block());
      break;
    case 13: { // an output or a marker
      const std::string target =
          c_->chance(128) ? fmt::format("$aa_out[{}]", c_->pick(10)) : fmt::format("$aa_marker[{}]", c_->pick(210));
      line(lab + fmt::format("{} = {}", target, c_->chance(220) ? std::to_string(c_->pick(2)) : expr(1)));
      break;
    }
    case 14: { // noise in a plausible line, rarely
      std::string s = block();
      if (c_->chance(48)) {
        const size_t at = c_->pick(s.size() + 1);
        s.insert(at, fmt::format(" {} ", noise()));
      }
      line(lab + s);
      break;
    }
    default: { // an arc, an end function in the middle (unreachable code after it), a block
      const unsigned k = c_->byte();
      if (k < 40)
        line(lab + (kind == 1 ? "M17" : "M30"));
      else if (k < 160)
        arc(lab);
      else
        line(lab + block());
      break;
    }
    }
  }

  Choices* c_ = nullptr;
  SetShape shape_;
  std::string axes_;
  std::string out_;
  int kind_ = 0;
  size_t labels_ = 0;
  size_t ifDepth_ = 0;
  unsigned nNumber_ = 0;
  std::vector<std::string> forward_, backward_;
};

// ---- isofmt's promise on every generated set that compiles

/// The stripped image of `texts` (everything but the line table), empty when the set does not
/// load without errors or does not compile.
std::vector<uint8_t> strippedImage(std::vector<iso::frontend::ProgramText> texts,
                                   const iso::frontend::LoadOptions& lo) {
  iso::frontend::ProgramSet set;
  iso::frontend::loadProgramTexts(std::move(texts), lo, set);
  if (iso::fuzz::hasErrors(set)) return {};
  iso::compiler::CompileOptions co;
  co.dialect = lo.dialect;
  co.strip = true;
  iso::image::Image img;
  iso::compiler::CompileError err;
  if (!iso::compiler::compileProgramSet(set, co, img, err)) return {};
  return iso::image::writeImage(img);
}

/// A style from the choice byte `b`: the defaults (0) or a mix of the other options.
iso::format::Style styleOf(unsigned b) {
  iso::format::Style s;
  if (b == 0) return s;
  s.wordCase = (b & 3) == 1 ? iso::format::WordCase::Lower
                            : ((b & 3) == 2 ? iso::format::WordCase::Keep : iso::format::WordCase::Upper);
  s.spaceBetweenWords = (b & 4) == 0;
  s.spaceAroundOperators = (b & 8) == 0;
  s.indent = (b >> 4) & 3;
  s.numbers = (b & 64) != 0 ? iso::format::NumberStyle::Normalised : iso::format::NumberStyle::AsWritten;
  s.maxBlankLines = (b >> 7) & 1;
  return s;
}

/// Formats every file of a set that compiles (with the style `styleByte` picks) and renumbers
/// it: formatting twice changes nothing, and the formatted and the renumbered set compile to
/// the stripped image of the set as generated. A difference is a crash.
void checkFormatting(const std::vector<iso::frontend::ProgramText>& texts, const iso::frontend::LoadOptions& lo,
                     unsigned styleByte) {
  const std::vector<uint8_t> original = strippedImage(texts, lo);
  if (original.empty()) return;
  iso::format::FormatOptions fo;
  fo.style = styleOf(styleByte);
  fo.lex = iso::frontend::lexOptionsFor(lo);
  std::vector<iso::frontend::ProgramText> formatted = texts, renumbered = texts;
  bool allRenumbered = true;
  for (size_t i = 0; i < texts.size(); ++i) {
    const auto once = iso::format::formatLines(texts[i].text, fo);
    formatted[i].text = iso::format::assemble(texts[i].text, once.lines).text;
    const auto twice = iso::format::formatLines(formatted[i].text, fo);
    if (iso::format::assemble(formatted[i].text, twice.lines).text != formatted[i].text)
      iso::fuzz::fail("FuzzGrammar", "formatting twice changes ", texts[i].path);
    const auto r = iso::format::renumber(texts[i].text, {10, 10, (styleByte & 1) != 0, fo.lex});
    if (r) renumbered[i].text = *r;
    allRenumbered = allRenumbered && r.ok();
  }
  if (strippedImage(formatted, lo) != original)
    iso::fuzz::fail("FuzzGrammar", "formatted, the set compiles to another image");
  if (allRenumbered && strippedImage(renumbered, lo) != original)
    iso::fuzz::fail("FuzzGrammar", "renumbered, the set compiles to another image");
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const iso::machine::Machine machine = iso::machine::builtinMachine();
  static const bool print = std::getenv("ISO_FUZZ_PRINT") != nullptr;
  if (size == 0 || size > 16 * 1024) return 0;
  SetShape shape;
  shape.z32 = (data[0] & 1) != 0;
  shape.subs = (data[0] >> 1) & 3;
  shape.semi = (data[0] & 8) != 0;
  std::string axes;
  for (const auto& a : machine.axes)
    axes.push_back(a.letter);
  Generator gen(shape, axes);
  // each file makes its choices from its own slice of the input: the main program gets half
  const size_t n = size - 1, others = shape.subs + (shape.semi ? 1 : 0);
  const size_t mainPart = others == 0 ? n : n / 2, part = others == 0 ? 0 : (n - mainPart) / others;
  const uint8_t* at = data + 1;
  auto next = [&](size_t len, int kind, size_t index) {
    Choices c(at, len);
    at += len;
    return gen.file(c, kind, index);
  };
  std::vector<iso::frontend::ProgramText> texts;
  texts.push_back({"main.mpf", next(mainPart, 0, 0), true});
  for (size_t i = 0; i < shape.subs; ++i)
    texts.push_back({fmt::format("{}.spf", Generator::subName(i)), next(part, 1, i), true});
  if (shape.semi) texts.push_back({"semi.mpf", next(part, 2, 0), true});
  if (print)
    for (const auto& t : texts)
      std::fprintf(stderr, "==== %s\n%s", t.path.c_str(), t.text.c_str());

  iso::frontend::LoadOptions lo;
  lo.machine = &machine;
  lo.dialect = shape.z32 ? iso::machine::Dialect::Z32 : iso::machine::Dialect::Sidac;
  iso::frontend::ProgramSet set;
  const std::vector<iso::frontend::ProgramText> generated = texts;
  iso::frontend::loadProgramTexts(std::move(texts), lo, set);
  {
    std::ostringstream os;
    iso::diag::TextRenderer text(os, set.sources, false, 12);
    for (const auto& d : set.diags.items())
      text.add(d);
    text.finish();
    if (print) std::fprintf(stderr, "%s", os.str().c_str());
  }
  if (iso::fuzz::hasErrors(set)) return 0;

  iso::compiler::CompileOptions co;
  co.dialect = lo.dialect;
  std::optional<iso::image::VerifiedImage> img;
  if (!iso::fuzz::compileAndLoad(set, co, img, "FuzzGrammar")) return 0;
  checkFormatting(generated, lo, data[size - 1]);
  const iso::sim::SimResult r = iso::fuzz::runBounded(*img, machine, "", false, {}, "FuzzGrammar");
  if (print)
    std::fprintf(stderr, "sim: %s %g s, %llu blocks %s\n", iso::sim::statusName(r.summary.status), r.summary.cycleTimeS,
                 static_cast<unsigned long long>(r.summary.blocks), r.summary.message.c_str());
  return 0;
}
