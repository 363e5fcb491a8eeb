//! @file BadImages.h
//! @brief One small image per verifier rule, each valid but for that rule, with the reason the
//!        verifier must give. Used by VerifierTests.cpp; the golden fixtures
//!        tests/golden/images/bad-*.hex were generated from this table (see VerifierTests.cpp,
//!        ISO_WRITE_BAD_IMAGES) and then commented.
#pragma once

#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "ImageTestUtil.h"

namespace iso::test {

struct BadImage {
  const char* name; ///< fixture name: bad-<name>.hex
  const char* rule; ///< the rule, as in isoimage(5) VERIFIER RULES
  std::function<image::Image()> make;
  const char* expect; ///< a substring of the verifier's message
};

/// A main program "m" from m.mpf with the given code (and a line per stmt), axes X Y Z, the
/// constant pool {2.5}.
inline image::Image mainOnly(const Asm& code, bool lines = true) {
  Builder b;
  b.img.constants = {2.5};
  b.proc(image::UnitKind::Main, "m", "m.mpf", code, lines);
  return b.img;
}

/// The same plus a subprogram "S" from s.spf (procedure 1): stmt, ret.
inline image::Image withSub(const Asm& code, const Asm& sub = Asm().stmt().op(Op::Ret)) {
  Builder b;
  b.img.constants = {2.5};
  b.proc(image::UnitKind::Main, "m", "m.mpf", code);
  b.proc(image::UnitKind::Sub, "S", "s.spf", sub);
  return b.img;
}

inline Asm endProg() { return Asm().stmt().op(Op::End); }

inline std::vector<BadImage> badImages() {
  using UK = image::UnitKind;
  std::vector<BadImage> v;
  auto add = [&](const char* n, const char* r, std::function<image::Image()> f, const char* e) {
    v.push_back({n, r, std::move(f), e});
  };
  // ---- tables
  add(
      "string-duplicate", "the string table holds each string once",
      [] {
        auto i = mainOnly(endProg());
        i.strings.push_back("m");
        return i;
      },
      "string 2 is a duplicate");
  add(
      "constant-not-finite", "constants are finite numbers",
      [] {
        auto i = mainOnly(endProg());
        i.constants.push_back(std::numeric_limits<double>::infinity());
        return i;
      },
      "constant 1 is not a finite number");
  add(
      "constant-duplicate", "the constant pool holds each value (bit pattern) once",
      [] {
        auto i = mainOnly(endProg());
        i.constants.push_back(2.5);
        return i;
      },
      "constant 1 (2.5) is a duplicate");
  add(
      "axes-too-many", "at most 16 axes",
      [] {
        auto i = mainOnly(endProg());
        i.axes = {'A', 'B', 'C', 'D', 'E', 'H', 'L', 'O', 'P', 'Q', 'S', 'T', 'U', 'V', 'W', 'X', 'Y'};
        return i;
      },
      "17 axes; at most 16");
  add(
      "axis-letter", "axis names are letters A-Z other than G M N F R I J K",
      [] {
        auto i = mainOnly(endProg());
        i.axes[1] = 'F';
        return i;
      },
      "axis 1 (byte 0x46) is not an axis letter");
  add(
      "axis-duplicate", "each axis is listed once",
      [] {
        auto i = mainOnly(endProg());
        i.axes[2] = 'X';
        return i;
      },
      "axis 2 'X' is listed twice");
  add(
      "procs-none", "there is at least one procedure",
      [] {
        auto i = mainOnly(endProg(), false);
        i.procs.clear();
        i.code.clear();
        return i;
      },
      "no procedures");
  add(
      "proc-name-range", "procedure name and file are string indices in range",
      [] {
        auto i = mainOnly(endProg());
        i.procs[0].name = 9;
        return i;
      },
      "procedure 0: name string 9 out of range");
  add(
      "proc-file-range", "procedure name and file are string indices in range",
      [] {
        auto i = mainOnly(endProg());
        i.procs[0].file = 2;
        return i;
      },
      "procedure 0: file string 2 out of range");
  add(
      "proc-empty", "procedures are not empty",
      [] {
        auto i = withSub(endProg());
        i.procs[1].size = 0;
        i.code.resize(i.procs[1].entry);
        return i;
      },
      "procedure 1 (S) is empty");
  add(
      "proc-gap", "procedures are sorted, do not overlap and cover the code",
      [] {
        auto i = withSub(endProg());
        i.code.insert(i.code.begin() + i.procs[1].entry, 0x48);
        ++i.procs[1].entry;
        for (auto& l : i.lines) {
          if (l.offset >= i.procs[1].entry - 1) ++l.offset;
        }
        return i;
      },
      "leaves code 0x0002..0x0003 outside every procedure");
  add(
      "proc-overlap", "procedures are sorted, do not overlap and cover the code",
      [] {
        auto i = withSub(endProg());
        i.procs[0].size += 1;
        return i;
      },
      "procedure 1 (S) at 0x0002 overlaps the previous one");
  add(
      "proc-past-end", "procedures lie inside the code",
      [] {
        auto i = mainOnly(endProg());
        i.procs[0].size = 3;
        return i;
      },
      "ends past the end of the code");
  add(
      "code-outside-procs", "procedures are sorted, do not overlap and cover the code",
      [] {
        auto i = mainOnly(endProg());
        i.code.push_back(0x48);
        return i;
      },
      "code 0x0002..0x0003 is outside every procedure");
  add(
      "entries-none", "there is an entry point for the main program",
      [] {
        auto i = mainOnly(endProg());
        i.entries.clear();
        return i;
      },
      "no entry points");
  add(
      "entry-first-not-main", "entry 0 is the main program",
      [] {
        auto i = mainOnly(endProg());
        i.entries[0].kind = UK::Semi;
        i.procs[0].kind = UK::Semi;
        return i;
      },
      "entry 0 is a semi program; the first entry must be the main program");
  add(
      "entry-second-main", "entries after the first are semi-automatic programs",
      [] {
        Builder b;
        b.proc(UK::Main, "m", "m.mpf", endProg());
        b.proc(UK::Main, "n", "n.mpf", endProg());
        return b.img;
      },
      "entry 1 is a main program; entries after the first must be semi-automatic");
  add(
      "entry-name-range", "entry names are string indices in range",
      [] {
        auto i = mainOnly(endProg());
        i.entries[0].name = 5;
        return i;
      },
      "entry 0: name string 5 out of range");
  add(
      "entry-proc-range", "entries name existing procedures",
      [] {
        auto i = mainOnly(endProg());
        i.entries[0].proc = 1;
        return i;
      },
      "entry 0: procedure 1 out of range");
  add(
      "entry-kind-mismatch", "an entry's kind is its procedure's kind",
      [] {
        auto i = withSub(endProg());
        i.entries[0].proc = 1;
        return i;
      },
      "entry 0 (main) names procedure 1 (S), a sub procedure");
  add(
      "entry-same-proc", "each entry names a different procedure",
      [] {
        Builder b;
        b.proc(UK::Main, "m", "m.mpf", endProg());
        b.proc(UK::Semi, "s", "s.mpf", Asm().stmt().op(Op::EndImplicit));
        b.img.entries.push_back(b.img.entries[1]);
        return b.img;
      },
      "entry 2 names procedure 1 (s) a second time");
  // ---- decoding
  add(
      "opcode-unknown", "every byte of a procedure decodes as an instruction",
      [] { return mainOnly(Asm().stmt().byte(0xEE).op(Op::End)); }, "unknown opcode 0xEE at code 0x0001");
  add(
      "instr-crosses-proc-end", "instructions tile each procedure exactly",
      [] {
        auto i = withSub(Asm().stmt().op(Op::End).op(Op::PushD0));
        return i;
      },
      "instruction at code 0x0002 runs past the end of procedure 0 (m)");
  add(
      "operand-truncated", "instructions tile each procedure exactly",
      [] { return mainOnly(Asm().stmt().op(Op::End).op(Op::Jump).byte(0).byte(0)); },
      "truncated u32 address operand at code 0x0002");
  add(
      "leb-non-minimal", "LEB128 operands are minimal",
      [] { return mainOnly(Asm().stmt().op(Op::LoadR).byte(0x81).byte(0x00).op(Op::StoreR).uleb(2).op(Op::End)); },
      "load.r at code 0x0001: non-minimal LEB128 operand");
  // ---- operands
  add(
      "const-index", "constant indices are in range",
      [] { return mainOnly(Asm().stmt().pushConst(1).storeR(1).op(Op::End)); },
      "push.const at code 0x0001: constant 1 out of range (1 constants)");
  add(
      "r-index-zero", "R indices are 1..2880", [] { return mainOnly(Asm().stmt().push(1).storeR(0).op(Op::End)); },
      "store.r at code 0x0003: R0 outside R1..R2880");
  add(
      "r-index-high", "R indices are 1..2880", [] { return mainOnly(Asm().stmt().loadR(2881).storeR(1).op(Op::End)); },
      "load.r at code 0x0001: R2881 outside R1..R2880");
  add(
      "axvar-sysvar", "system variable numbers fit the opcode",
      [] { return mainOnly(Asm().stmt().op(Op::LoadAxVar).byte(5).byte(0).storeR(1).op(Op::End)); },
      "system variable 5 ($aa_in) is not an axis variable (0..4)");
  add(
      "axvar-axis", "axis indices are in range",
      [] { return mainOnly(Asm().stmt().op(Op::LoadAxVar).byte(3).byte(3).storeR(1).op(Op::End)); },
      "axis 3 out of range (3 axes)");
  add(
      "loadio-sysvar", "system variable numbers fit the opcode",
      [] { return mainOnly(Asm().stmt().push(1).op(Op::LoadIo).byte(4).storeR(1).op(Op::End)); },
      "system variable 4 ($aa_fw) is not an I/O variable (5..7)");
  add(
      "storeio-sysvar", "system variable numbers fit the opcode",
      [] { return mainOnly(Asm().stmt().push(1).push(1).op(Op::StoreIo).byte(5).op(Op::End)); },
      "system variable 5 ($aa_in) is not writable (6..7)");
  add(
      "call-range", "call targets exist", [] { return mainOnly(Asm().stmt().call(1).stmt().op(Op::End)); },
      "call at code 0x0001: procedure 1 out of range (1 procedures)");
  add(
      "call-not-sub", "call targets are subprograms", [] { return mainOnly(Asm().stmt().call(0).stmt().op(Op::End)); },
      "calls procedure 0 (m), a main program");
  add(
      "m-too-large", "M numbers fit in 32 bits",
      [] { return mainOnly(Asm().stmt().op(Op::M).uleb(0x100000000ull).op(Op::End)); },
      "M number 4294967296 does not fit in 32 bits");
  add(
      "zword-address", "z-word address codes are 0..6",
      [] { return mainOnly(Asm().stmt().push(1).op(Op::ZWord).byte(7).op(Op::End)); },
      "address code 7 out of range (0..6)");
  add(
      "move-kind", "move descriptor kinds are 0..6",
      [] { return mainOnly(Asm().stmt().push(1).move({0x70}).op(Op::End)); },
      "descriptor 0 (0x70): kind 7 out of range (0..6)");
  add(
      "move-axis", "axis indices are in range", [] { return mainOnly(Asm().stmt().push(1).move({0x03}).op(Op::End)); },
      "descriptor 0 (0x03): axis 3 out of range (3 axes)");
  add(
      "move-arc-nibble", "arc words (I J K CR) have axis nibble 0",
      [] {
        return mainOnly(Asm().stmt().push(1).push(1).move({0x00, 0x31}).op(Op::End));
      },
      "descriptor 1 (0x31): arc word I with axis nibble 1 (must be 0)");
  add(
      "move-axis-twice", "an axis moves at most once per move",
      [] {
        return mainOnly(Asm().stmt().push(1).push(1).move({0x00, 0x10}).op(Op::End));
      },
      "descriptor 1: axis X moves twice");
  add(
      "move-fa-twice", "an axis has at most one feed per move",
      [] {
        return mainOnly(Asm().stmt().push(1).push(1).push(1).move({0x00, 0x20, 0x20}).op(Op::End));
      },
      "descriptor 2: a second feed for axis X");
  add(
      "move-fa-without-target", "a feed Fa names an axis that moves in the same move",
      [] {
        return mainOnly(Asm().stmt().push(1).push(1).move({0x00, 0x21}).op(Op::End));
      },
      "feed for axis Y, which does not move in this block");
  add(
      "move-arc-twice", "each arc word appears at most once per move",
      [] {
        return mainOnly(Asm().stmt().push(1).push(1).move({0x60, 0x60}).op(Op::End));
      },
      "descriptor 1: arc word CR twice");
  add(
      "case-const", "constant indices are in range",
      [] {
        return mainOnly(Asm()
                            .stmt()
                            .push(1)
                            .op(Op::Case)
                            .uleb(1)
                            .uleb(4)
                            .ref("a")
                            .u32(image::kNoTarget)
                            .label("a")
                            .stmt()
                            .op(Op::End));
      },
      "case at code 0x0003: arm 0: constant 4 out of range (1 constants)");
  add(
      "case-target", "jump targets are instruction boundaries",
      [] {
        return mainOnly(
            Asm().stmt().push(1).op(Op::Case).uleb(1).uleb(0).ref("@2").u32(image::kNoTarget).stmt().op(Op::End));
      },
      "case at code 0x0003: arm target 0x0002 is not an instruction boundary");
  add(
      "jump-outside-proc", "jump targets lie inside the same procedure",
      [] { return withSub(Asm().stmt().jump(Op::Jump, "@8")); },
      "jump at code 0x0001: target 0x0008 is outside procedure 0 (m)");
  add(
      "jump-not-boundary", "jump targets are instruction boundaries",
      [] { return mainOnly(Asm().stmt().jump(Op::Jump, "@2").stmt().op(Op::End)); },
      "jump at code 0x0001: target 0x0002 is not an instruction boundary");
  add(
      "stmt-skip-target", "jump targets lie inside the same procedure",
      [] { return mainOnly(Asm().op(Op::StmtSkip).ref("@99").op(Op::End)); },
      "stmt.skip at code 0x0000: target 0x0063 is outside procedure 0 (m)");
  add(
      "when-target", "WHEN condition and body lie inside the same procedure",
      [] {
        return mainOnly(Asm().stmt().op(Op::When).ref("@3").ref("b").op(Op::End).label("b").stmt().op(Op::BodyEnd));
      },
      "when at code 0x0001: condition 0x0003 is not an instruction boundary");
  // ---- line table
  add(
      "line-file-range", "line entries name a file string in range",
      [] {
        auto i = mainOnly(endProg());
        i.lines[0].file = 7;
        return i;
      },
      "line entry 0: file string 7 out of range");
  add(
      "line-zero", "line numbers count from 1",
      [] {
        auto i = mainOnly(endProg());
        i.lines[0].line = 0;
        return i;
      },
      "line entry 0: line 0");
  add(
      "line-same-offset", "line entries are sorted by strictly increasing code offset",
      [] {
        auto i = mainOnly(endProg());
        i.lines.push_back(i.lines[0]);
        i.lines[1].line = 2;
        return i;
      },
      "line entry 1 (code 0x0000) does not follow entry 0 (code 0x0000)");
  add(
      "line-past-code", "line entries point into the code",
      [] {
        auto i = mainOnly(endProg());
        i.lines.push_back({2, 1, 2, false, 0});
        return i;
      },
      "line entry 1: code 0x0002 is past the end of the code");
  add(
      "line-not-boundary", "line entries point at instruction boundaries",
      [] {
        auto i = mainOnly(Asm().stmt().push(300).storeR(1).op(Op::End));
        i.lines.push_back({2, 1, 2, false, 0});
        return i;
      },
      "line entry 1: code 0x0002 is not an instruction boundary");
  add(
      "line-not-stmt", "line entries point at stmt or stmt.skip instructions",
      [] {
        auto i = mainOnly(endProg());
        i.lines.push_back({1, 1, 2, false, 0});
        return i;
      },
      "line entry 1: code 0x0001 is a end instruction, not stmt or stmt.skip");
  // ---- flow
  add(
      "region-jump-into-body", "control stays in its region (procedure, WHEN condition, WHEN body)",
      [] {
        return mainOnly(Asm()
                            .stmt()
                            .op(Op::When)
                            .ref("c")
                            .ref("b")
                            .jump(Op::Jump, "b")
                            .label("c")
                            .loadR(1)
                            .op(Op::CondEnd)
                            .label("b")
                            .stmt()
                            .op(Op::BodyEnd));
      },
      "reached from a WHEN body at 0x0012 and from the procedure");
  add(
      "region-fall-into-cond", "control stays in its region (procedure, WHEN condition, WHEN body)",
      [] {
        return mainOnly(Asm()
                            .stmt()
                            .op(Op::When)
                            .ref("c")
                            .ref("b")
                            .label("c")
                            .loadR(1)
                            .op(Op::CondEnd)
                            .label("b")
                            .stmt()
                            .op(Op::BodyEnd));
      },
      "reached from a WHEN condition at 0x000A and from the procedure");
  add(
      "stack-depth-mismatch", "the stack depth at an instruction is the same on every path",
      [] {
        return mainOnly(
            Asm().stmt().push(1).jump(Op::JumpFalse, "l").push(2).label("l").push(3).op(Op::Add).storeR(1).op(Op::End));
      },
      "stack depth 1 on one path and 0 on another");
  add(
      "stack-not-empty-at-stmt", "the stack is empty at stmt and stmt.skip",
      [] { return mainOnly(Asm().stmt().push(1).stmt().storeR(1).op(Op::End)); },
      "stmt at code 0x0003: needs an empty stack, has 1 value(s)");
  add(
      "stack-underflow", "the stack never underflows",
      [] { return mainOnly(Asm().stmt().push(1).op(Op::Add).storeR(1).op(Op::End)); },
      "add at code 0x0003: stack underflow: pops 2 value(s), the stack has 1");
  add(
      "stack-overflow", "the stack holds at most 256 values",
      [] {
        Asm a;
        a.stmt();
        for (int k = 0; k < 257; ++k)
          a.push(0);
        for (int k = 0; k < 256; ++k)
          a.op(Op::Add);
        a.storeR(1).op(Op::End);
        return mainOnly(a);
      },
      "stack depth 257 exceeds the limit of 256");
  add(
      "cond-end-two-values", "a WHEN condition leaves exactly one value at cond.end",
      [] {
        return mainOnly(Asm()
                            .stmt()
                            .op(Op::When)
                            .ref("c")
                            .ref("b")
                            .op(Op::End)
                            .label("c")
                            .loadR(1)
                            .loadR(2)
                            .op(Op::CondEnd)
                            .label("b")
                            .stmt()
                            .op(Op::BodyEnd));
      },
      "needs exactly one value (the condition) on the stack, has 2");
  add(
      "cond-has-stmt", "a WHEN condition holds only expressions and cond.end",
      [] {
        return mainOnly(Asm()
                            .stmt()
                            .op(Op::When)
                            .ref("c")
                            .ref("b")
                            .op(Op::End)
                            .label("c")
                            .stmt()
                            .loadR(1)
                            .op(Op::CondEnd)
                            .label("b")
                            .stmt()
                            .op(Op::BodyEnd));
      },
      "stmt at code 0x000B: not allowed in a WHEN condition");
  add(
      "body-has-call", "a WHEN body does not call, return, end, arm a WHEN or end a condition",
      [] {
        return withSub(Asm()
                           .stmt()
                           .op(Op::When)
                           .ref("c")
                           .ref("b")
                           .op(Op::End)
                           .label("c")
                           .loadR(1)
                           .op(Op::CondEnd)
                           .label("b")
                           .stmt()
                           .call(1)
                           .op(Op::BodyEnd));
      },
      "call at code 0x000F: not allowed in a WHEN body");
  add(
      "body-end-in-proc", "cond.end and body.end end WHEN regions only",
      [] { return mainOnly(Asm().stmt().op(Op::BodyEnd)); },
      "body.end at code 0x0001: reached from the procedure's own code");
  add(
      "ret-in-main", "only subprograms return", [] { return mainOnly(Asm().stmt().op(Op::Ret)); },
      "ret at code 0x0001: in procedure 0 (m), a main program");
  add(
      "end-implicit-in-sub", "subprograms do not end with end.implicit",
      [] { return withSub(endProg(), Asm().stmt().op(Op::EndImplicit)); },
      "end.implicit at code 0x0003: in procedure 1 (S), a subprogram");
  add(
      "falls-off-end", "no instruction falls through past the end of its procedure",
      [] { return withSub(Asm().stmt().push(1).storeR(1), Asm().stmt().op(Op::Ret)); },
      "store.r at code 0x0003: execution falls off the end of procedure 0 (m)");
  add(
      "body-falls-off-end", "a WHEN body ends with body.end",
      [] {
        return mainOnly(Asm()
                            .stmt()
                            .op(Op::When)
                            .ref("c")
                            .ref("b")
                            .op(Op::End)
                            .label("c")
                            .loadR(1)
                            .op(Op::CondEnd)
                            .label("b")
                            .stmt()
                            .push(1)
                            .storeR(1));
      },
      "store.r at code 0x0011: execution falls off the end of procedure 0 (m)");
  add(
      "jump-with-values", "the stack is empty at jump targets",
      [] { return mainOnly(Asm().stmt().push(1).push(1).jump(Op::JumpFalse, "l").label("l").storeR(1).op(Op::End)); },
      "jump.false at code 0x0005: jumps with 1 value(s) on the stack");
  add(
      "call-with-values", "the stack is empty at calls",
      [] { return withSub(Asm().stmt().push(1).call(1).storeR(1).op(Op::End)); },
      "call at code 0x0003: needs an empty stack, has 1 value(s)");
  add(
      "end-with-values", "the stack is empty at terminators", [] { return mainOnly(Asm().stmt().push(1).op(Op::End)); },
      "end at code 0x0003: needs an empty stack, has 1 value(s)");
  return v;
}

} // namespace iso::test
