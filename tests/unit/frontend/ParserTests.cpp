//! @file ParserTests.cpp
//! @brief SPEC §3–§4 and §10: the shape of the syntax tree (strict left-to-right arithmetic,
//!        comparison and logic tiers, statements, prefixes and labels) and error recovery.
#include <string>

#include <doctest/doctest.h>

#include "TestUtil.h"

using namespace iso;
using namespace iso::frontend;
using test::count;
using test::dump;
using test::evalConst;
using test::hasCode;
using test::lintText;
using test::loadText;

namespace {

/// The parsed file of a one-file set.
const File& fileOf(const std::unique_ptr<ProgramSet>& set) { return set->files.at(0); }

/// The value expression of the single assignment on statement `i`.
ExprId assignedValue(const File& f, size_t i = 0) {
  const Stmt& s = f.stmts.at(i);
  REQUIRE(s.kind == StmtKind::Block);
  REQUIRE(s.itemCount == 1);
  return f.items[s.firstItem].value;
}

bool isR(const File& f, ExprId e, int index) { return f.expr(e).kind == ExprKind::RParam && f.expr(e).rIndex == index; }

bool isBin(const File& f, ExprId e, BinOp op) {
  return f.expr(e).kind == ExprKind::Binary && static_cast<BinOp>(f.expr(e).op) == op;
}

bool isLogic(const File& f, ExprId e, LogicOp op) {
  return f.expr(e).kind == ExprKind::Logic && static_cast<LogicOp>(f.expr(e).op) == op;
}

bool isCompare(const File& f, ExprId e, CmpOp op) {
  return f.expr(e).kind == ExprKind::Compare && static_cast<CmpOp>(f.expr(e).op) == op;
}

} // namespace

// ---- arithmetic: strictly left to right ------------------------------------------------------------

TEST_CASE("parser: 2 + 3 * 4 folds to 20 (no precedence)") {
  CHECK(*evalConst("2 + 3 * 4") == 20);
  CHECK(*evalConst("10 - 2 - 3") == 5);
  CHECK(*evalConst("8 / 2 / 2") == 2);
  CHECK(*evalConst("1 + 2 * 3 - 4 / 5") == doctest::Approx(1.0));
  CHECK(*evalConst("2 * (3 + 4)") == 14);
  CHECK(*evalConst("((2))") == 2);
  CHECK(*evalConst("-2 * 3") == -6);
  CHECK(*evalConst("-(2 + 3) * 2") == -10);
  CHECK(*evalConst("2 * -3") == -6);
  CHECK(*evalConst("+4 - -1") == 5);
  CHECK_FALSE(evalConst("R2 + 1").has_value());
  CHECK_FALSE(evalConst("1 / 0").has_value());
}

TEST_CASE("parser: R34 + R56 / R45 is (R34 + R56) / R45") {
  auto set = loadText("R1 = R34 + R56 / R45\nM30\n");
  const File& f = fileOf(set);
  ExprId e = assignedValue(f);
  REQUIRE(isBin(f, e, BinOp::Div));
  ExprId sum = f.expr(e).a;
  REQUIRE(isBin(f, sum, BinOp::Add));
  CHECK(isR(f, f.expr(sum).a, 34));
  CHECK(isR(f, f.expr(sum).b, 56));
  CHECK(isR(f, f.expr(e).b, 45));
}

TEST_CASE("parser: parentheses group, indirect R takes an expression") {
  auto set = loadText("R1 = R34 + (R56 / R45)\nR[170 + R45] = 1\nM30\n");
  const File& f = fileOf(set);
  ExprId e = assignedValue(f);
  REQUIRE(isBin(f, e, BinOp::Add));
  CHECK(isBin(f, f.expr(e).b, BinOp::Div));
  const Stmt& s = f.stmts.at(1);
  const Item& it = f.items[s.firstItem];
  REQUIRE(it.kind == ItemKind::AssignR);
  REQUIRE(f.expr(it.target).kind == ExprKind::RIndirect);
  CHECK(isBin(f, f.expr(it.target).a, BinOp::Add));
  CHECK(set->diags.size() == 0);
}

TEST_CASE("parser: an unbalanced parenthesis is E100 (seed 000 §6.2 typo)") {
  auto d = lintText("R1 = R[45 + R5]) * R32\nM30\n");
  INFO(dump(d));
  CHECK(hasCode(d, "E100", 1, 16));
  CHECK(d.size() == 1);
}

// ---- comparisons and logic -----------------------------------------------------------------------------

TEST_CASE("parser: a comparison binds looser than arithmetic") {
  auto set = loadText("IF R1 + 2 > R3 * 4 GOTOF E\nE:\nM30\n");
  const File& f = fileOf(set);
  const Stmt& s = f.stmts.at(0);
  REQUIRE(s.kind == StmtKind::If);
  REQUIRE(isCompare(f, s.cond, CmpOp::Gt));
  CHECK(isBin(f, f.expr(s.cond).a, BinOp::Add));
  CHECK(isBin(f, f.expr(s.cond).b, BinOp::Mul));
  CHECK(set->diags.size() == 0);
}

TEST_CASE("parser: all six comparison operators") {
  const std::pair<const char*, CmpOp> ops[] = {{">", CmpOp::Gt},  {"<", CmpOp::Lt},  {"==", CmpOp::Eq},
                                               {">=", CmpOp::Ge}, {"<=", CmpOp::Le}, {"<>", CmpOp::Ne}};
  for (const auto& entry : ops) {
    const char* text = entry.first; // not a structured binding: clang 14 cannot capture those
    const CmpOp op = entry.second;
    CAPTURE(text);
    auto set = loadText(std::string("IF R1 ") + text + " 2 GOTOF E\nE:\nM30\n");
    CHECK(set->diags.size() == 0);
    CHECK(isCompare(fileOf(set), fileOf(set).stmts.at(0).cond, op));
  }
}

TEST_CASE("parser: (A) OR (B) AND (C) is ((A) OR (B)) AND (C)") {
  auto set = loadText("IF (R1 > 1) OR (R2 > 2) AND (R3 > 3) GOTOF E\nE:\nM30\n");
  INFO(dump(set->diags.items()));
  REQUIRE(set->diags.size() == 0);
  const File& f = fileOf(set);
  ExprId c = f.stmts.at(0).cond;
  REQUIRE(isLogic(f, c, LogicOp::And));
  ExprId left = f.expr(c).a;
  REQUIRE(isLogic(f, left, LogicOp::Or));
  CHECK(isCompare(f, f.expr(left).a, CmpOp::Gt));
  CHECK(isR(f, f.expr(f.expr(left).a).a, 1));
  CHECK(isR(f, f.expr(f.expr(left).b).a, 2));
  CHECK(isR(f, f.expr(f.expr(c).b).a, 3));
}

TEST_CASE("parser: (A) AND (B) OR (C) AND (D) groups strictly left to right") {
  auto set = loadText("IF (R1 > 1) AND (R2 > 2) OR (R3 > 3) AND (R4 > 4) GOTOF E\nE:\nM30\n");
  REQUIRE(set->diags.size() == 0);
  const File& f = fileOf(set);
  ExprId c = f.stmts.at(0).cond;
  REQUIRE(isLogic(f, c, LogicOp::And));
  REQUIRE(isLogic(f, f.expr(c).a, LogicOp::Or));
  CHECK(isLogic(f, f.expr(f.expr(c).a).a, LogicOp::And));
}

TEST_CASE("parser: NOT applies to the group that follows") {
  auto set = loadText("IF NOT (R1 > 1) AND (R2 > 2) GOTOF E\nIF (R1 > 1) AND NOT (R2 > 2) GOTOF E\n"
                      "IF NOT ((R1 > 1) OR (R2 > 2)) GOTOF E\nE:\nM30\n");
  INFO(dump(set->diags.items()));
  REQUIRE(set->diags.size() == 0);
  const File& f = fileOf(set);
  ExprId a = f.stmts.at(0).cond;
  REQUIRE(isLogic(f, a, LogicOp::And));
  CHECK(f.expr(f.expr(a).a).kind == ExprKind::Not);
  ExprId b = f.stmts.at(1).cond;
  REQUIRE(isLogic(f, b, LogicOp::And));
  CHECK(f.expr(f.expr(b).b).kind == ExprKind::Not);
  ExprId c = f.stmts.at(2).cond;
  REQUIRE(f.expr(c).kind == ExprKind::Not);
  CHECK(isLogic(f, f.expr(c).a, LogicOp::Or));
}

TEST_CASE("parser: a parenthesised comparison is a condition") {
  CHECK(lintText("IF (R1 > 2) GOTOF E\nIF ((R1 > 2)) GOTOF E\nE:\nM30\n").empty());
}

TEST_CASE("parser: logic operands must be groups, comparisons cannot chain") {
  auto d = lintText("IF R1 > 2 AND R2 < 3 GOTOF E\n"  // 1 E108 at the comparison
                    "IF (R1 > 2) OR R2 < 3 GOTOF E\n" // 2 E108 at the second operand
                    "IF NOT R1 > 2 GOTOF E\n"         // 3 E108 at R1
                    "IF R1 GOTOF E\n"                 // 4 E108 bare value
                    "IF (R1) AND (R2 > 1) GOTOF E\n"  // 5 E108 a group that is no condition
                    "IF R1 < R2 < R3 GOTOF E\n"       // 6 E109
                    "R1 = R2 > 3\n"                   // 7 E109
                    "IF (R1 > 2) + 1 > 0 GOTOF E\n"   // 8 E109 comparison inside arithmetic
                    "IF R1 = 2 GOTOF E\n"             // 9 E107
                    "E:\nM30\n");
  INFO(dump(d));
  CHECK(hasCode(d, "E108", 1, 4));
  CHECK(hasCode(d, "E108", 2, 16));
  CHECK(hasCode(d, "E108", 3, 8));
  CHECK(hasCode(d, "E108", 4, 4));
  CHECK(hasCode(d, "E108", 5, 5)); // a group points at its content
  CHECK(hasCode(d, "E109", 6, 12));
  CHECK(hasCode(d, "E109", 7, 9));
  CHECK(hasCode(d, "E109", 8, 5));
  CHECK(hasCode(d, "E107", 9, 7));
  CHECK(d.size() == 9); // one diagnostic per bad line
}

// ---- statements ------------------------------------------------------------------------------------------

TEST_CASE("parser: single-line IF forms") {
  auto set = loadText("IF R1 == 1 THEN R2 = 3\n"
                      "IF R1 == 1 THEN G1 X10 F100\n"
                      "IF R1 == 1 THEN GOTOF A\n"
                      "IF R1 == 1 GOTOF A\n"
                      "IF R1 == 1 THEN Sub\n"
                      "A:\nIF R1 == 1 GOTOB A\n"
                      "IF R1 == 1\nENDIF\nM30\n"); // Sub is unknown here (E210): only the shapes matter
  const File& f = fileOf(set);
  const Stmt& s0 = f.stmts.at(0);
  REQUIRE(s0.kind == StmtKind::If);
  REQUIRE(s0.inner >= 0);
  CHECK(f.inner[static_cast<size_t>(s0.inner)].kind == StmtKind::Block);
  CHECK(f.inner[static_cast<size_t>(s0.inner)].isInner);
  const Stmt& s1 = f.stmts.at(1);
  REQUIRE(s1.inner >= 0);
  CHECK(f.inner[static_cast<size_t>(s1.inner)].itemCount == 3);
  const Stmt& s2 = f.stmts.at(2);
  REQUIRE(s2.inner >= 0);
  const Stmt& j = f.inner[static_cast<size_t>(s2.inner)];
  CHECK(j.kind == StmtKind::Jump);
  CHECK(f.jumpOf(j).kind == JumpKind::Gotof);
  CHECK(f.jumpOf(j).target == 5);
  const Stmt& s3 = f.stmts.at(3);
  CHECK(s3.inner < 0);
  CHECK(s3.hasJump());
  CHECK(f.jumpOf(s3).label == "A");
  CHECK(f.jumpOf(s3).target == 5);
  const Stmt& s4 = f.stmts.at(4);
  REQUIRE(s4.inner >= 0);
  CHECK(f.inner[static_cast<size_t>(s4.inner)].kind == StmtKind::Call);
  CHECK(f.nameOf(f.inner[static_cast<size_t>(s4.inner)]).text == "Sub");
  const Stmt& s6 = f.stmts.at(6);
  CHECK(s6.hasJump());
  CHECK(f.jumpOf(s6).kind == JumpKind::Gotob);
  CHECK(f.jumpOf(s6).target == 5);
  const Stmt& s7 = f.stmts.at(7);
  CHECK(s7.kind == StmtKind::If);
  CHECK(s7.inner < 0);
  CHECK_FALSE(s7.hasJump());
  CHECK(f.stmts.at(8).kind == StmtKind::EndIf);
}

TEST_CASE("parser: the statement after THEN and DO is an inner one of its line") {
  auto set = loadText("/IF R1 == 1 THEN G1 X10 $\n"
                      "  F100\n"
                      "/WHEN $aa_iw[X] > 10 DO $aa_out[4] = 1\n"
                      "IF R1 == 2 THEN  GOTOF A\n"
                      "A: M30\n");
  const File& f = fileOf(set);
  REQUIRE(f.inner.size() == 3);
  const Stmt& s0 = f.stmts.at(0);
  REQUIRE(s0.inner == 0);
  const Stmt& in0 = f.inner[0];
  CHECK(in0.isInner);
  CHECK(in0.kind == StmtKind::Block);
  CHECK(in0.line == 1);
  CHECK(in0.lastLine == 2); // the line's continuation belongs to it too
  CHECK(in0.loc.line == 1);
  CHECK(in0.loc.col == 18); // at G1
  CHECK(in0.itemCount == 3);
  CHECK(f.items[in0.firstItem].kind == ItemKind::G);
  CHECK(in0.skippable); // an IF's inner statement takes the line's '/'
  const Stmt& s1 = f.stmts.at(1);
  REQUIRE(s1.kind == StmtKind::When);
  REQUIRE(s1.inner == 1);
  const Stmt& in1 = f.inner[1];
  CHECK(in1.isInner);
  CHECK(in1.line == 3);
  CHECK(in1.lastLine == 3);
  CHECK(in1.loc.col == 25); // at $aa_out
  CHECK(f.items[in1.firstItem].kind == ItemKind::AssignIo);
  CHECK(s1.skippable);
  CHECK_FALSE(in1.skippable); // a WHEN's body is covered by the WHEN line's own skip
  REQUIRE(f.stmts.at(2).inner == 2);
  const Stmt& in2 = f.inner[2];
  CHECK(in2.kind == StmtKind::Jump);
  CHECK(in2.loc.col == 18);
  CHECK_FALSE(in2.skippable);
}

TEST_CASE("parser: IF without THEN, jump or end of line is E100") {
  auto d = lintText("IF R1 == 1 R2 = 3\nM30\n");
  INFO(dump(d));
  CHECK(hasCode(d, "E100", 1, 12));
  CHECK(d.size() == 1);
}

TEST_CASE("parser: CASE with signed values and DEFAULT") {
  auto set = loadText("CASE R1 OF 1 GOTOF A -2 GOTOF B 3.5 GOTOF C DEFAULT GOTOF D\nA:\nB:\nC:\nD:\nM30\n");
  INFO(dump(set->diags.items()));
  CHECK(set->diags.size() == 0);
  const File& f = fileOf(set);
  const Stmt& s = f.stmts.at(0);
  REQUIRE(s.kind == StmtKind::Case);
  CHECK(isR(f, s.cond, 1));
  REQUIRE(f.armsOf(s).size() == 4);
  const CaseArm* a = f.armsOf(s).data();
  CHECK(a[0].value == 1);
  CHECK(a[0].jump.label == "A");
  CHECK(a[0].jump.target == 1);
  CHECK(a[1].value == -2);
  CHECK(a[1].jump.target == 2);
  CHECK(a[2].value == 3.5);
  CHECK(a[3].isDefault);
  CHECK(a[3].jump.label == "D");
  CHECK(a[3].jump.target == 4);
}

TEST_CASE("parser: CASE labels that look like words") {
  auto set = loadText("CASE R1 + 1 OF 1 GOTOF X 2 GOTOF Y10\nX:\nY10:\nM30\n");
  INFO(dump(set->diags.items()));
  CHECK(set->diags.size() == 0);
  const File& f = fileOf(set);
  const Stmt& s = f.stmts.at(0);
  REQUIRE(f.armsOf(s).size() == 2);
  CHECK(f.armsOf(s)[0].jump.label == "X");
  CHECK(f.armsOf(s)[1].value == 2);
  CHECK(f.armsOf(s)[1].jump.label == "Y10");
}

TEST_CASE("parser: CASE errors: DEFAULT not last, no arm, colon after the label") {
  auto d = lintText("CASE R1 OF DEFAULT GOTOF A 1 GOTOF A\n"
                    "CASE R1 OF\n"
                    "CASE R1 OF 1 GOTOF Fine:\n"
                    "A:\nFine:\nM30\n");
  INFO(dump(d));
  CHECK(hasCode(d, "E100", 1, 28));
  CHECK(hasCode(d, "E100", 2));
  REQUIRE(hasCode(d, "E100", 3, 24));
  CHECK(count(d, "E100") == 3);
}

TEST_CASE("parser: GOTOF Fine: gets a hint to drop the colon") {
  auto d = lintText("GOTOF Fine:\nFine:\nM30\n");
  REQUIRE(hasCode(d, "E100", 1, 11));
  CHECK(test::find(d, "E100")->message.find("without the colon") != std::string::npos);
}

TEST_CASE("parser: WHEN long and short forms") {
  auto set = loadText("F100\n"
                      "WHEN $aa_iw[X] > 50 DO\n"
                      "$aa_out[3] = 1\n"
                      "CANCEL\n"
                      "G1 X100\n"
                      "WHEN $aa_iw[X] > 10 DO $aa_out[4] = 1\n"
                      "G1 X0\n"
                      "M30\n");
  INFO(dump(set->diags.items()));
  CHECK(set->diags.size() == 0);
  const File& f = fileOf(set);
  const Stmt& w = f.stmts.at(1);
  REQUIRE(w.kind == StmtKind::When);
  CHECK(w.inner < 0);
  CHECK(isCompare(f, w.cond, CmpOp::Gt));
  CHECK(f.expr(f.expr(w.cond).a).kind == ExprKind::SysAxis);
  CHECK(f.expr(f.expr(w.cond).a).axis == 'X');
  CHECK(f.stmts.at(3).kind == StmtKind::Cancel);
  CHECK(set->flows.at(0).match.at(1) == 3);
  const Stmt& s = f.stmts.at(5);
  REQUIRE(s.kind == StmtKind::When);
  REQUIRE(s.inner >= 0);
  const Stmt& body = f.inner[static_cast<size_t>(s.inner)];
  REQUIRE(body.kind == StmtKind::Block);
  CHECK(f.items[body.firstItem].kind == ItemKind::AssignIo);
}

TEST_CASE("parser: M=NB(34) is a non-blocking M") {
  auto set = loadText("M=NB(34)\nm=nb(35)\nM23 M24\nM00\nM30\n");
  INFO(dump(set->diags.items()));
  CHECK(set->diags.size() == 0);
  const File& f = fileOf(set);
  const Item& m = f.items[f.stmts.at(0).firstItem];
  CHECK(m.kind == ItemKind::M);
  CHECK(m.nb);
  CHECK(m.code == 34);
  CHECK(f.items[f.stmts.at(1).firstItem].code == 35);
  CHECK(f.stmts.at(2).itemCount == 2);
  const Item& m0 = f.items[f.stmts.at(3).firstItem];
  CHECK(m0.code == 0);
  CHECK_FALSE(m0.nb);
}

TEST_CASE("parser: motion items in all their forms") {
  auto set = loadText("G1 Pos[X]=10 Posa[Y]=R1 Z=2*3 A-.5 F=100 Fa[Z]=50\nG2 X10 Y0 I5 J=0\nG3 X0 Y0 CR=-5\n"
                      "M30\n");
  const File& f = fileOf(set);
  const Stmt& s = f.stmts.at(0);
  REQUIRE(s.itemCount == 7);
  const Item* it = f.itemsOf(s);
  CHECK(it[0].kind == ItemKind::G);
  CHECK(it[0].code == 1);
  CHECK(it[1].mode == MoveMode::Pos);
  CHECK(it[1].axis == 'X');
  CHECK(it[2].mode == MoveMode::Posa);
  CHECK(it[2].axis == 'Y');
  CHECK(it[3].mode == MoveMode::Assign);
  CHECK(it[3].axis == 'Z');
  CHECK(it[4].mode == MoveMode::Word);
  CHECK(it[4].axis == 'A');
  CHECK(it[5].kind == ItemKind::Feed);
  CHECK(it[6].kind == ItemKind::AxisFeed);
  CHECK(it[6].axis == 'Z');
  const Item* arc = f.itemsOf(f.stmts.at(1));
  CHECK(arc[3].kind == ItemKind::ArcI);
  CHECK(arc[4].kind == ItemKind::ArcJ);
  const Item* cr = f.itemsOf(f.stmts.at(2));
  CHECK(cr[3].kind == ItemKind::ArcCR);
  CHECK(*constValue(f, cr[3].value) == -5);
}

TEST_CASE("parser: PROC and SEMI headers") {
  auto sub = loadText("PROC Alza_carrello SAVE\nG0 Z100\nM17\n", "alza.spf");
  INFO(dump(sub->diags.items()));
  CHECK(sub->diags.size() == 0);
  const File& f = fileOf(sub);
  CHECK(f.kind == UnitKind::Sub);
  CHECK(f.procName == "Alza_carrello");
  CHECK(f.stmts.at(0).kind == StmtKind::Proc);
  CHECK(f.stmts.at(0).procSave);

  auto semi = loadText("; programma semiautomatico\nSEMI \"Cambio utensile (manuale)\"\nG0 Z0\nM30\n", "c.mpf");
  CHECK(semi->diags.size() == 0);
  CHECK(fileOf(semi).kind == UnitKind::Semi);
  CHECK(fileOf(semi).semiName == "Cambio utensile (manuale)");

  auto main = loadText("G0 X0\nM30\n", "p.MPF");
  CHECK(fileOf(main).kind == UnitKind::Main);
}

TEST_CASE("parser: a file with another extension is a subprogram if it starts with PROC") {
  CHECK(fileOf(loadText("PROC Uno SAVE\nM17\n", "uno.nc")).kind == UnitKind::Sub);
  CHECK(fileOf(loadText("G0 X0\nM30\n", "main.iso")).kind == UnitKind::Main);
  CHECK(fileOf(loadText("PROC Uno SAVE\nM17\n", "UNO.SPF")).kind == UnitKind::Sub);
}

TEST_CASE("parser: G04 F=R1 is a dwell, G04 FR1 is E100") {
  auto set = loadText("R1 = 2\nG04 F=R1\nG4 F.5\nM30\n");
  INFO(dump(set->diags.items()));
  CHECK(set->diags.size() == 0);
  const File& f = fileOf(set);
  const Item* it = f.itemsOf(f.stmts.at(1));
  CHECK(it[0].kind == ItemKind::G);
  CHECK(it[0].code == 4);
  CHECK(it[1].kind == ItemKind::Feed);
  CHECK(isR(f, it[1].value, 1));
  auto d = lintText("G04 FR1\nM30\n");
  INFO(dump(d));
  REQUIRE(hasCode(d, "E100", 1, 5));
  CHECK(test::find(d, "E100")->message.find("F=R1") != std::string::npos);
}

TEST_CASE("parser: prefixes % / N and labels") {
  auto set = loadText("%\n/N10 Lab: G0 X0\nN20\nA1:\nUno: G0 X1\n/Salto:\nM30\n");
  INFO(dump(set->diags.items()));
  CHECK(set->diags.size() == 0);
  const File& f = fileOf(set);
  CHECK(f.stmts.at(0).kind == StmtKind::Empty);
  const Stmt& s = f.stmts.at(1);
  CHECK(s.skippable);
  CHECK(s.hasN());
  CHECK(f.numberOf(s).value == 10);
  CHECK(s.hasLabel());
  CHECK(f.labelOf(s).text == "Lab");
  CHECK(s.kind == StmtKind::Block);
  CHECK(s.loc.col == 11);
  CHECK(f.stmts.at(2).kind == StmtKind::Empty);
  CHECK(f.stmts.at(2).hasN());
  CHECK(f.stmts.at(3).hasLabel());
  CHECK(f.labelOf(f.stmts.at(3)).text == "A1");
  CHECK(f.labelOf(f.stmts.at(4)).text == "Uno");
  CHECK(f.stmts.at(4).kind == StmtKind::Block);
  CHECK(f.stmts.at(5).skippable);
}

TEST_CASE("parser: N numbers may have decimals (Z32)") {
  auto set = loadText("N10.5 G0 X0\nN10,6 G0 X1\nM30\n");
  CHECK(set->diags.size() == 0);
  CHECK(fileOf(set).numberOf(fileOf(set).stmts.at(0)).value == 10.5);
}

TEST_CASE("parser: GOTOB W jumps to the label W") {
  auto set = loadText("W:\nR1 = R1 + 1\nIF R1 < 3 GOTOB W\nM30\n");
  INFO(dump(set->diags.items()));
  CHECK(set->diags.size() == 0);
  CHECK(fileOf(set).jumpOf(fileOf(set).stmts.at(2)).target == 0);
}

TEST_CASE("parser: a label on a skipped (/) line is still a jump target") {
  auto set = loadText("GOTOF Salto\nR1 = 1\n/Salto: R1 = 2\nM30\n");
  CHECK(fileOf(set).jumpOf(fileOf(set).stmts.at(0)).target == 2);
  CHECK(count(set->diags.items(), "E202") == 0);
}

TEST_CASE("parser: labels and calls are case-insensitive") {
  auto set = loadText("loop:\nR1 = R1 + 1\nif r1 < 3 gotob LOOP\nm30\n");
  CHECK(set->diags.size() == 0);
  CHECK(fileOf(set).jumpOf(fileOf(set).stmts.at(2)).target == 0);
}

TEST_CASE("parser: a keyword cannot be a label") {
  auto d = lintText("IF:\nM30\n");
  CHECK(hasCode(d, "E100", 1, 1));
}

TEST_CASE("parser: a name alone on its line is a call") {
  auto set = loadText("Alza_carrello\n  alza_carrello  ; commento\nM30\n");
  const File& f = fileOf(set);
  CHECK(f.stmts.at(0).kind == StmtKind::Call);
  CHECK(f.nameOf(f.stmts.at(0)).text == "Alza_carrello");
  CHECK(f.stmts.at(1).kind == StmtKind::Call);
  CHECK(f.nameOf(f.stmts.at(1)).loc.col == 3);
}

TEST_CASE("parser: z32 S T MA words are recorded") {
  auto set = loadText("S1000 T1 M6\nMA-100\nM2\n", "t.mpf", test::builtin(), machine::Dialect::Z32);
  INFO(dump(set->diags.items()));
  CHECK(set->diags.size() == 0);
  const File& f = fileOf(set);
  CHECK(f.items[f.stmts.at(0).firstItem].kind == ItemKind::ZWord);
}

// ---- error recovery ----------------------------------------------------------------------------------------

TEST_CASE("parser: a bad line does not hide the next line's error") {
  auto d = lintText("G1 X=(1+\nR0 = 1\nG1 X1 X2 F100\nM30\n");
  INFO(dump(d));
  CHECK(hasCode(d, "E100", 1, 9));
  CHECK(hasCode(d, "E301", 2, 1));
  CHECK(hasCode(d, "E303", 3, 7));
  CHECK(d.size() == 3);
}

TEST_CASE("parser: a bad block IF gives no follow-on IF/ENDIF errors") {
  auto d = lintText("IF R1 = 1\nR2 = 1\nELSE\nR2 = 2\nENDIF\nM30\n");
  INFO(dump(d));
  CHECK(hasCode(d, "E107", 1, 7));
  CHECK(d.size() == 1);
}

TEST_CASE("parser: 'IF cond THEN' with nothing after THEN is E100, its ENDIF matches it") {
  auto d = lintText("IF R1 == 1 THEN\nR2 = 1\nENDIF\nM30\n");
  INFO(dump(d));
  CHECK(hasCode(d, "E100", 1, 16));
  CHECK(d.size() == 1);
}

TEST_CASE("parser: a bad ENDIF still closes its IF") {
  auto d = lintText("IF R1 == 1\nR2 = 1\nENDIF R3\nM30\n");
  INFO(dump(d));
  CHECK(hasCode(d, "E100", 3, 7));
  CHECK(d.size() == 1);
}

TEST_CASE("parser: a bad long-form WHEN gives no follow-on CANCEL error") {
  auto d = lintText("F100\nWHEN $aa_iw[X] = 3 DO\n$aa_out[1] = 1\nCANCEL\nG1 X10\nM30\n");
  INFO(dump(d));
  CHECK(hasCode(d, "E107", 2, 16));
  CHECK(d.size() == 1);
}

TEST_CASE("parser: an unresolved jump gives no follow-on unreachable or missing-M30 warning") {
  auto d = lintText("GOTOF Nowhere\nR1 = 1\nM30\n");
  INFO(dump(d));
  CHECK(hasCode(d, "E202", 1, 7));
  CHECK(d.size() == 1);
  auto back = lintText("GOTOF Start\nStart:\nGOTOF Start\nR1 = 1\nM30\n");
  INFO(dump(back));
  CHECK(hasCode(back, "E204", 3, 1));
  CHECK(back.size() == 1);
}

TEST_CASE("parser: E110 resumes parsing at the next line") {
  auto d = lintText("WHILE R1 < 3\nENDWHILE\nR0 = 1\nM30\n");
  INFO(dump(d));
  CHECK(hasCode(d, "E110", 1, 1));
  CHECK(hasCode(d, "E110", 2, 1));
  CHECK(hasCode(d, "E301", 3, 1));
  CHECK(d.size() == 3);
}

TEST_CASE("parser: a control statement after block items is E100 with a hint") {
  auto d = lintText("G0 X0 GOTOF Fine\nFine:\nM30\n");
  INFO(dump(d));
  REQUIRE(hasCode(d, "E100", 1, 7));
  CHECK(test::find(d, "E100")->message.find("stand alone") != std::string::npos);
  CHECK(d.size() == 1);
}

TEST_CASE("parser: messages show a word's sign") {
  auto d = lintText("M-1\nM30\n");
  REQUIRE(hasCode(d, "E312", 1, 1));
  CHECK(test::find(d, "E312")->message.find("'M-1'") != std::string::npos);
}

TEST_CASE("parser: a negative R index is one error") {
  auto d = lintText("R-5 = 1\nR1 = R-5\nM30\n");
  INFO(dump(d));
  CHECK(hasCode(d, "E301", 1, 1));
  CHECK(hasCode(d, "E100", 2, 6));
  CHECK(d.size() == 2);
}

TEST_CASE("parser: an expression's underline length saturates at 65535 (its 16-bit field)") {
  CHECK(clampLen(1) == 1);
  CHECK(clampLen(240) == 240);
  CHECK(clampLen(65535) == 65535);
  CHECK(clampLen(65536) == 65535);
  CHECK(clampLen(UINT32_MAX) == 65535);
  auto set = loadText("R1 = R3 * R2\nM30\n");
  CHECK(fileOf(set).expr(assignedValue(fileOf(set))).len == 7); // "R3 * R2"
}
