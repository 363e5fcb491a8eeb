//! @file Z32FlowTests.cpp
//! @brief Dialect z32 program flow and the rest of the line (SPEC §4.7): the trees of GO, GOP,
//!        KG, G26, G28/G29, O, TA/TB, PAR/PAL and user parameters, and the rules E215, E313,
//!        W420, E207/E206 for G26, E301 for PAR/PAL, E312 for three-digit M numbers.
#include <string>

#include <doctest/doctest.h>

#include "TestUtil.h"

using namespace iso;
using test::dump;
using test::hasCode;
using test::lintText;
using test::lintZ32;

namespace {
machine::Machine z32Machine() {
  machine::Machine m = machine::builtinMachine();
  m.dialect = machine::Dialect::Z32;
  m.parameters = {"HA", "Q"};
  m.origins = {{1, {{'X', 100.0}}}, {2, {{'Z', -20.0}}}};
  m.builtin = false; // as read from a machine file
  return m;
}
const frontend::File& mainFile(const frontend::ProgramSet& set) { return set.files.at(0); }
size_t count(const test::Diags& d, const std::string& code) {
  size_t n = 0;
  for (const auto& x : d)
    n += diag::info(x.code).code == code;
  return n;
}
} // namespace

TEST_CASE("z32 GO: jumps and ranges, with or without '!', resolve to their lines") {
  auto set =
      test::loadText("G0 X0\nN12 G1 X1 F100\n!GON12!\nGO%N1\n%N1 X2\nGON12-N20\nN20 X3\nM30\n", "t.mpf", z32Machine());
  INFO(dump(set->diags.items()));
  const auto& f = mainFile(*set);
  REQUIRE(f.gos.size() == 3);
  CHECK(f.stmts[2].kind == frontend::StmtKind::Go);
  CHECK(f.gos[0].from == "N12");
  CHECK(!f.gos[0].range);
  CHECK(f.gos[0].target == 1);
  CHECK(f.gos[0].fromLoc.line == 3);
  CHECK(f.gos[0].fromLoc.col == 4); // after "!GO"
  CHECK(f.gos[1].from == "%N1");
  CHECK(f.gos[1].target == 4);
  CHECK(f.gos[2].range);
  CHECK(f.gos[2].from == "N12");
  CHECK(f.gos[2].to == "N20");
  CHECK(f.gos[2].target == 1);
  CHECK(f.gos[2].rangeEnd == 6);
  CHECK(!hasCode(set->diags.items(), "E215"));
  CHECK(!hasCode(set->diags.items(), "E100"));
}

TEST_CASE("z32 GO: E215 when no line begins with the target, notes for blanks and duplicates") {
  auto d = lintZ32("G0 X0\n  N10 X1\nGON10\nGON1\nN12 X2\nM30\n");
  INFO(dump(d));
  CHECK(hasCode(d, "E215", 3, 3));
  CHECK(hasCode(d, "E215", 4, 3)); // GON1 does not find N12
  const auto* e = test::find(d, "E215");
  REQUIRE(e);
  REQUIRE(e->notes.size() == 1);
  CHECK(e->notes[0].loc.line == 2);
  CHECK(e->notes[0].message.find("blanks") != std::string::npos);
  // near miss: the line at the very start is found
  auto ok = lintZ32("G0 X0\nN10 X1\nGON10\nM30\n");
  INFO(dump(ok));
  CHECK(!hasCode(ok, "E215"));
  // a range end found only before the start of the range; the later duplicate is never found
  auto r = lintZ32("N5 X0\nN7 X1\nN5 X2\nGON7-N5\nM30\n");
  INFO(dump(r));
  REQUIRE(hasCode(r, "E215", 4, 6));
  const auto* re = test::find(r, "E215");
  REQUIRE(re->notes.size() == 2);
  CHECK(re->notes[0].loc.line == 1);
  CHECK(re->notes[1].loc.line == 3);
  CHECK(re->notes[1].message.find("never found") != std::string::npos);
  CHECK(hasCode(r, "W411", 3));
  const auto* w = test::find(r, "W411");
  REQUIRE(w->notes.size() == 2);
  CHECK(w->notes[1].message.find("GO N5") != std::string::npos);
}

TEST_CASE("z32 GO: shape, standing alone, and dialect sidac") {
  CHECK(hasCode(lintZ32("GON12 X1\nN12\nM30\n"), "E100", 1));
  CHECK(hasCode(lintZ32("!GON12\nN12\nM30\n"), "E100", 1));
  CHECK(hasCode(lintZ32("IF (R1>0) THEN GON12\nN12\nM30\n"), "E100", 1));
  auto sidac = lintText("GON12\nN12\nM30\n");
  CHECK(!hasCode(sidac, "E215"));
  CHECK(test::errorCount(sidac) > 0); // a call of an unknown subprogram, or unsupported
}

TEST_CASE("z32 GO: reachability follows the jump") {
  auto d = lintZ32("GON20\nG0 X1\nN20 G0 X2\nM30\n");
  INFO(dump(d));
  CHECK(hasCode(d, "W404", 2));
  CHECK(!hasCode(d, "W404", 3));
  auto range = lintZ32("GON20-N20\nG0 X1\nM30\nN20 G0 X2\nM17\n");
  INFO(dump(range));
  CHECK(!hasCode(range, "W404", 2)); // a range returns to the next line
}

TEST_CASE("z32 GOP, KG and G26") {
  auto set = test::loadText("GOPPALLET\nG0 X1 KGCAMBIO\n", "t.mpf", z32Machine());
  const auto& f = mainFile(*set);
  REQUIRE(f.stmts.size() >= 2);
  CHECK(f.stmts[0].kind == frontend::StmtKind::Call);
  CHECK(f.nameOf(f.stmts[0]).text == "PALLET");
  CHECK(f.nameOf(f.stmts[0]).loc.col == 4);
  // KG ends the line's flow: no W405 for a main program that ends with KG
  auto d = lintZ32("G0 X1 KGCAMBIO\n");
  INFO(dump(d));
  CHECK(!hasCode(d, "W405"));
  CHECK(!hasCode(d, "E100"));
  // G26 returns like M17: it satisfies E206, and is E207 in a main program
  auto sub = lintZ32("PROC P SAVE\nG0 X1 G26\n", "p.spf");
  INFO(dump(sub));
  CHECK(!hasCode(sub, "E206"));
  CHECK(!hasCode(sub, "W420"));
  auto main = lintZ32("G0 X1\nG26\nM30\n");
  INFO(dump(main));
  CHECK(hasCode(main, "E207", 2, 1));
  CHECK(hasCode(main, "W404", 3));
  auto subNo = lintZ32("PROC P SAVE\nG0 X1\n", "p.spf");
  CHECK(hasCode(subNo, "E206"));
}

TEST_CASE("z32 G28/G29 take the axis letters written after the number") {
  auto set = test::loadText("G29AB\nN2G28XY X10\nG28\nM30\n", "t.mpf", z32Machine());
  INFO(dump(set->diags.items()));
  const auto& f = mainFile(*set);
  CHECK(!hasCode(set->diags.items(), "E100"));
  CHECK(!hasCode(set->diags.items(), "E110"));
  std::vector<std::pair<int, uint32_t>> ctl;
  for (const auto& it : f.items)
    if (it.kind == frontend::ItemKind::AxisControl) ctl.push_back({it.code, static_cast<uint32_t>(it.target)});
  REQUIRE(ctl.size() == 3);
  CHECK(ctl[0] == std::pair<int, uint32_t>{29, 0b11u});
  CHECK(ctl[1] == std::pair<int, uint32_t>{28, (1u << ('X' - 'A')) | (1u << ('Y' - 'A'))});
  CHECK(ctl[2] == std::pair<int, uint32_t>{28, 0u});
  // a letter that is no axis of the machine: E302
  auto d = test::lintText("G29AQ\nM30\n", "t.mpf", machine::builtinMachine(), machine::Dialect::Z32);
  CHECK(hasCode(d, "E302", 1));
  // sidac: still unsupported with its own message
  auto s = lintText("G28\nM30\n");
  CHECK(hasCode(s, "E110", 1));
  // z32: no other controller's meaning in any message
  auto z = lintZ32("G30\nG63\nM30\n");
  INFO(dump(z));
  CHECK(dump(z).find("reference point") == std::string::npos);
  CHECK(dump(z).find("Fanuc") == std::string::npos);
  CHECK(hasCode(z, "E310", 1));
}

TEST_CASE("z32 W420: the not-modelled codes, once per code and file") {
  auto d = lintZ32("G84 X10\nG84 X20\nG110\nG61 X1\nG0 X0\nM30\n");
  INFO(dump(d));
  CHECK(count(d, "W420") == 3);
  CHECK(hasCode(d, "W420", 1, 1));
  CHECK(!hasCode(d, "W420", 2));
  CHECK(hasCode(d, "W420", 3));
  CHECK(test::find(d, "W420")->message.find("G84") != std::string::npos);
  CHECK(test::find(d, "W420")->message.find("does not model") != std::string::npos);
  CHECK(!hasCode(d, "E310"));
  for (int g : {25, 27, 36, 62, 80, 100, 101})
    CHECK(hasCode(lintZ32(fmt::format("G{}\nM30\n", g)), "W420", 1));
  CHECK(!hasCode(lintZ32("G0 X1\nM30\n"), "W420"));
}

TEST_CASE("z32 origins: O<n>, E313 against the machine file, letters are E100") {
  auto ok = lintText("O1\nO0\nG0 X1\nM30\n", "t.mpf", z32Machine());
  INFO(dump(ok));
  CHECK(!hasCode(ok, "E313"));
  CHECK(test::errorCount(ok) == 0);
  auto bad = lintText("O5\nM30\n", "t.mpf", z32Machine());
  INFO(dump(bad));
  CHECK(hasCode(bad, "E313", 1, 1));
  CHECK(test::find(bad, "E313")->message.find("O1, O2") != std::string::npos);
  auto letters = lintZ32("G0 X1 OAB\nM30\n");
  CHECK(hasCode(letters, "E100", 1, 7));
  CHECK(test::find(letters, "E100")->message.find("only numbered origins are supported") != std::string::npos);
  CHECK(hasCode(lintZ32("O100\nM30\n"), "E100", 1));
  CHECK(hasCode(lintText("O1\nM30\n"), "E110", 1)); // sidac: as before
  // without a machine file (the built-in machine) an unknown origin is left to the run
  machine::Machine builtin = machine::builtinMachine();
  builtin.dialect = machine::Dialect::Z32;
  auto noFile = lintText("O5\nM30\n", "t.mpf", builtin);
  INFO(dump(noFile));
  CHECK(!hasCode(noFile, "E313"));
  CHECK(test::errorCount(noFile) == 0);
}

TEST_CASE("z32 TA, TB, PAR, PAL and user parameters") {
  auto set =
      test::loadText("TA5 TB6\nPAR[3]=2\nPAL[R1]=PAR[3]+1\nHA=PAL[2]*2\nQ12.5\nR1=HA+Q\nM30\n", "t.mpf", z32Machine());
  INFO(dump(set->diags.items()));
  CHECK(test::errorCount(set->diags.items()) == 0);
  const auto& f = mainFile(*set);
  std::string words;
  int assigns = 0;
  for (const auto& it : f.items) {
    if (it.kind == frontend::ItemKind::ZWord) words += std::string(it.zaddr) + " ";
    if (it.kind == frontend::ItemKind::AssignP) ++assigns;
  }
  CHECK(words == "TA TB ");
  CHECK(assigns == 4); // PAR, PAL, HA=, Q12.5 (R1= is an R assignment)
  bool par = false, pal = false, ha = false, q = false;
  for (const auto& e : f.exprs) {
    par |= e.kind == frontend::ExprKind::Par;
    pal |= e.kind == frontend::ExprKind::Pal;
    ha |= e.kind == frontend::ExprKind::UserParam && e.rIndex == 0;
    q |= e.kind == frontend::ExprKind::UserParam && e.rIndex == 1;
  }
  CHECK((par && pal && ha && q));
  // constant indices out of range: E301
  CHECK(hasCode(lintZ32("PAR[1000]=1\nM30\n"), "E301", 1));
  CHECK(hasCode(lintZ32("R1=PAL[256]\nM30\n"), "E301", 1));
  CHECK(!hasCode(lintZ32("PAR[999]=1\nR1=PAL[255]\nM30\n"), "E301"));
  // without the machine's parameters, HA is nothing
  CHECK(test::errorCount(lintZ32("HA=1\nM30\n")) > 0);
}

TEST_CASE("z32 M numbers have at most two digits") {
  CHECK(hasCode(lintZ32("M123\nM30\n"), "E312", 1));
  CHECK(!hasCode(lintZ32("S100 M03\nM19\nM30\n"), "E312"));
  CHECK(!hasCode(lintText("M123\nM30\n"), "E312")); // sidac: any number
}

namespace {
/// z32 with special M6 -> CAMBIO and M40 -> PALLET, origin 1, and both subprograms.
test::SetResult lintSpecialLine(const std::string& file, const std::string& text) {
  machine::Machine m = z32Machine();
  m.specialM = {{6, "CAMBIO"}, {40, "PALLET"}};
  return test::lintFiles(
      {{"cambio.spf", "PROC CAMBIO SAVE\nM17\n"}, {"pallet.spf", "PROC PALLET SAVE\nM17\n"}, {file, text}}, m);
}
std::string w415(const test::SetResult& r, uint32_t line) {
  for (const auto& d : r.diags)
    if (diag::info(d.code).code == std::string("W415") && d.loc.line == line) return d.message;
  return "";
}
} // namespace

TEST_CASE("z32 W415: T, TA, TB, O, G29, KG and G26 after a special M never run") {
  auto r = lintSpecialLine("main.mpf", "G0 X0\nS100 M40 T5 TA3 TB4 O1 G29X G28Y\nG0 X1 M6 KGPALLET\nM30\n");
  REQUIRE(r.loaded);
  INFO(dump(r.diags));
  CHECK(w415(r, 2) == "M40 is a special M (it calls 'PALLET'): the line ends when it runs, so T, TA, TB, O and G29 "
                      "never run");
  // a special M6 (step 9) abandons the final M, KG and G26 (steps 10 to 12), not the move
  CHECK(w415(r, 3) == "M6 is a special M (it calls 'CAMBIO'): the line ends when it runs, so KGPALLET never runs");
  auto sub = lintSpecialLine("p.spf", "PROC P SAVE\nG0 X1 M40 G26\nM17\n");
  REQUIRE(sub.loaded);
  INFO(dump(sub.diags));
  CHECK(w415(sub, 2) == "M40 is a special M (it calls 'PALLET'): the line ends when it runs, so the move of X and G26 "
                        "never run");
  // near miss: what runs before the special M (S, G28, T before a special M6) is not named
  auto ok = lintSpecialLine("main.mpf", "S100 G28X M40\nT5 M6\nM30\n");
  INFO(dump(ok.diags));
  CHECK(!hasCode(ok.diags, "W415"));
}

TEST_CASE("WHEN cond statement CANCEL on one line is the short form, in both dialects") {
  const std::string oneLine = "G1 F100 X0\nWHEN $aa_iw[X] > 5 $aa_out[1] = 1 CANCEL\nG1 X10\nM30\n";
  const std::string doForm = "G1 F100 X0\nWHEN $aa_iw[X] > 5 DO $aa_out[1] = 1\nG1 X10\nM30\n";
  for (auto dialect : {machine::Dialect::Sidac, machine::Dialect::Z32}) {
    machine::Machine m = z32Machine();
    m.dialect = dialect;
    auto d = test::lintText(oneLine, "t.mpf", m);
    INFO(dump(d));
    CHECK(d.empty());
    auto a = test::loadText(oneLine, "t.mpf", m);
    auto b = test::loadText(doForm, "t.mpf", m);
    const auto& fa = mainFile(*a);
    const auto& fb = mainFile(*b);
    REQUIRE(fa.stmts.size() == fb.stmts.size());
    for (size_t k = 0; k < fa.stmts.size(); ++k) {
      CHECK(fa.stmts[k].kind == fb.stmts[k].kind);
      CHECK(fa.stmts[k].inner == fb.stmts[k].inner);
    }
    REQUIRE(fa.inner.size() == 1);
    REQUIRE(fb.inner.size() == 1);
    CHECK(fa.inner[0].kind == fb.inner[0].kind);
    CHECK(fa.inner[0].itemCount == fb.inner[0].itemCount);
    CHECK(fa.items.size() == fb.items.size());
    CHECK(fa.stmts[1].kind == frontend::StmtKind::When);
  }
  // a one-line form with a motion body also triggers on the next line; CANCEL alone is still E212
  CHECK(test::errorCount(test::lintText("G1 F100 X0\nWHEN $aa_iw[X] > 5 M5 CANCEL\nG1 X10\nM30\n")) == 0);
  CHECK(hasCode(test::lintText("CANCEL\nM30\n"), "E212", 1));
}

TEST_CASE("z32 E212: a WHEN body may not hold GO, GOP, KG or G26") {
  auto body = [](const std::string& lines) {
    return lintZ32("G1 F100 X0\nWHEN $aa_iw[X] > 5 DO\n" + lines + "CANCEL\nN10 G1 X10\nM30\n", "t.mpf");
  };
  auto go = body("GON10\n");
  INFO(dump(go));
  CHECK(hasCode(go, "E212", 3, 1));
  CHECK(test::find(go, "E212")->message == "a WHEN body may not hold a jump");
  CHECK(hasCode(body("GOPLIFT\n"), "E212", 3, 1));
  auto kg = body("X1 KGLIFT\n");
  INFO(dump(kg));
  CHECK(test::find(kg, "E212")->message == "a WHEN body may not hold KG (it continues in a subprogram)");
  auto g26 = lintZ32("PROC P SAVE\nG1 F100 X0\nWHEN $aa_iw[X] > 5 DO G26\nG1 X10\nM17\n", "p.spf");
  INFO(dump(g26));
  REQUIRE(hasCode(g26, "E212", 3, 23));
  CHECK(test::find(g26, "E212")->message == "a WHEN body may not hold G26 (a return from subprogram)");
  // near miss: the same body without them is clean
  CHECK(test::errorCount(body("$aa_out[1] = 1\n")) == 0);
}

TEST_CASE("z32 W412: a GO into an IF or ELSE body from outside it") {
  // line 4 is inside the IF body, line 6 inside the ELSE body
  const std::string body = "IF R1 > 0\nN10 X1\nELSE\nN20 X2\nENDIF\n";
  SUBCASE("into the IF body, into the ELSE body, and a range starting inside") {
    auto d = lintZ32("R1 = 1\nG0 X0 F100\nGON10\n" + body + "GON20\nGON10-N20\nM30\n");
    INFO(dump(d));
    CHECK(count(d, "W412") == 3);
    CHECK(hasCode(d, "W412", 3, 3));
    CHECK(hasCode(d, "W412", 9, 3));
    CHECK(hasCode(d, "W412", 10, 3));
  }
  SUBCASE("near misses: a GO inside the same body, to the IF line itself, past ENDIF") {
    auto d = lintZ32("R1 = 1\nG0 X0 F100\nN5 IF R1 > 0\nN10 X1\nGON10\nELSE\nN20 X2\nGON20\nENDIF\nN30 X3\n"
                     "GON5\nGON30\nM30\n");
    INFO(dump(d));
    CHECK(!hasCode(d, "W412"));
  }
}
