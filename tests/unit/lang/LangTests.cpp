//! @file LangTests.cpp
//! @brief The tables of lib/lang: each is consistent in itself and with its readers (lexer,
//!        image, machine), the limits agree with SPEC.md, and no fact of the tables is written
//!        a second time in lib/.
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include <doctest/doctest.h>
#include <fmt/format.h>

#include "TestUtil.h"
#include "frontend/Ast.h"
#include "frontend/Lexer.h"
#include "image/Image.h"
#include "image/ImageVerifier.h"
#include "image/Opcode.h"
#include "lang/Addresses.h"
#include "lang/Axes.h"
#include "lang/GCodes.h"
#include "lang/Keywords.h"
#include "lang/Limits.h"
#include "lang/MFunctions.h"
#include "lang/SysVars.h"
#include "lang/UnitKind.h"
#include "lang/Unsupported.h"
#include "machine/Machine.h"
#include "support/CaseFold.h"

using namespace iso;
using frontend::Tok;

namespace {} // namespace

// ---- G codes ----------------------------------------------------------------------------------

TEST_CASE("lang: every G code is listed once, has a group and an opcode that maps back to it") {
  std::set<int> codes;
  for (size_t i = 0; i < lang::kGCodeCount; ++i) {
    const lang::GInfo& g = lang::kGCodes[i];
    CAPTURE(g.code);
    CHECK(codes.insert(g.code).second);
    CHECK(static_cast<size_t>(g.id) == i); // rows in enum order: gInfo indexes by id
    CHECK(lang::findG(g.code) == g.id);
    CHECK(lang::findUnsupportedG(g.code) == nullptr); // a G code is ours or another dialect's
    if (g.id == lang::kDwell) {
      CHECK(g.group == lang::GGroup::None);
      CHECK_FALSE(image::modalOp(g.id).has_value()); // the dwell is Op::Dwell after the motion
      continue;
    }
    CHECK(static_cast<size_t>(g.group) < lang::kModalGroupCount);
    auto op = image::modalOp(g.id);
    REQUIRE(op.has_value());
    CHECK(image::opInfo(static_cast<uint8_t>(*op)).valid);
    CHECK(image::gCodeOf(*op) == g.id);
  }
  CHECK_FALSE(lang::findG(5).has_value());
  CHECK_FALSE(image::gCodeOf(image::Op::Dwell).has_value());
}

TEST_CASE("lang: each modal group has one initial code, as SPEC §4.2 says (G00 G90 G60 G17)") {
  for (size_t grp = 0; grp < lang::kModalGroupCount; ++grp) {
    int initials = 0;
    for (const lang::GInfo& g : lang::kGCodes)
      if (static_cast<size_t>(g.group) == grp && g.initial) ++initials;
    CHECK(initials == 1);
  }
  CHECK(lang::gNumber(lang::initialG(lang::GGroup::Motion)) == 0);
  CHECK(lang::gNumber(lang::initialG(lang::GGroup::Distance)) == 90);
  CHECK(lang::gNumber(lang::initialG(lang::GGroup::Path)) == 60);
  CHECK(lang::gNumber(lang::initialG(lang::GGroup::Plane)) == 17);
  CHECK_FALSE(lang::kInitialIncremental);
  CHECK_FALSE(lang::kInitialContinuous);
  CHECK(lang::isDwell(4));
}

TEST_CASE("lang: every unsupported G and M code is listed once") {
  std::set<int> g, m;
  for (const auto& u : lang::kUnsupportedG)
    CHECK(g.insert(u.code).second);
  for (const auto& u : lang::kUnsupportedM)
    CHECK(m.insert(u.code).second);
  for (const auto& u : lang::kUnsupportedM)
    CHECK(lang::mRole(u.code, lang::Dialect::Z32) == lang::MRole::Plain);
}

// ---- system variables -------------------------------------------------------------------------

TEST_CASE("lang: every system variable's image number round-trips through the image and the lexer") {
  std::set<std::string> names;
  for (const lang::SysVarInfo& v : lang::kSysVars) {
    CAPTURE(v.name);
    CHECK(names.insert(support::upperCopy(v.name)).second);
    const auto id = static_cast<uint8_t>(v.id);
    CHECK(lang::isSysVarId(id));
    CHECK(std::string(image::sysVarIdName(id)) == v.name);
    CHECK(std::string(frontend::sysVarName(v.id)) == v.name);
    auto found = lang::findSysVar(support::upperCopy(v.name));
    REQUIRE(found.has_value());
    CHECK(found->id == v.id);
    CHECK_FALSE(found->alias);
    // LoadAxVar takes the axis variables, LoadIo/StoreIo the others (Opcodes.def)
    CHECK(v.takesAxis == (id <= static_cast<uint8_t>(image::SysVarId::AaFw)));
    if (v.writable) CHECK_FALSE(v.takesAxis);
    if (v.machineData) CHECK_FALSE(v.realTime);
    // the lexer reads it, whatever the case
    auto r = test::lexText(std::string(v.name) + "\n");
    auto toks = r->tokens(0);
    REQUIRE(toks.size() == 1);
    CHECK(toks[0].kind == Tok::SysVar);
    CHECK(toks[0].sysvar == v.id);
  }
  CHECK(std::string(image::sysVarIdName(image::kSysVarCount)) == "?");
  for (const lang::SysVarAlias& a : lang::kSysVarAliases) {
    CAPTURE(a.name);
    CHECK(names.insert(support::upperCopy(a.name)).second);
    auto found = lang::findSysVar(a.name);
    REQUIRE(found.has_value());
    CHECK(found->alias);
    auto r = test::lexText(std::string(a.name) + "[X]\n");
    CHECK(test::hasCode(r->diags.items(), "W407"));
  }
  CHECK_FALSE(lang::findSysVar("$aa_iwx").has_value());
}

// ---- keywords ---------------------------------------------------------------------------------

TEST_CASE("lang: every keyword is its own token kind, in any case - an identifier is never one") {
  std::set<std::string> spellings;
  for (const lang::KeywordInfo& k : lang::kKeywords) {
    CAPTURE(k.spelling);
    CHECK(spellings.insert(support::upperCopy(k.spelling)).second);
    CHECK(frontend::keywordOf(frontend::keywordTok(k.id)) == k.id);
    CHECK(frontend::isReservedTok(frontend::keywordTok(k.id)) == k.reserved);
    CHECK(frontend::isKeyword(k.spelling) == k.reserved);
    CHECK(lang::findUnsupportedName(k.spelling) == nullptr);
    std::string lower;
    for (char c : k.spelling)
      lower.push_back(static_cast<char>(c >= 'A' && c <= 'Z' ? c + 32 : c));
    for (const std::string& text : {std::string(k.spelling), lower, support::upperCopy(k.spelling)}) {
      auto r = test::lexText("Lbl: " + text + "\n");
      auto toks = r->tokens(0);
      REQUIRE(toks.size() == 3);
      CHECK(toks[2].kind == frontend::keywordTok(k.id));
      CHECK(toks[2].text == text);
    }
    for (const std::string& text : {std::string(k.spelling) + "_1", std::string(k.spelling) + "X", "_" + lower}) {
      CAPTURE(text);
      auto r = test::lexText("Lbl: " + text + "\n");
      auto toks = r->tokens(0);
      REQUIRE(toks.size() == 3);
      CHECK(toks[2].kind == Tok::Ident);
    }
  }
  // the token kinds after the keywords' own are not keywords
  CHECK_FALSE(frontend::isKeywordTok(Tok::Error));
  CHECK_FALSE(frontend::isKeywordTok(Tok::Ident));
}

TEST_CASE("lang: a reserved keyword cannot be a label, an item name can") {
  CHECK(test::hasCode(test::lintText("IF: G0 X1\nM30\n"), "E100"));
  CHECK_FALSE(test::hasCode(test::lintText("Posa: G0 X1\nM30\n"), "E100"));
}

// ---- unsupported constructs -------------------------------------------------------------------

TEST_CASE("lang: every unsupported name is listed once and says what it is") {
  std::set<std::string> names;
  for (const lang::UnsupportedInfo& u : lang::kUnsupportedNames) {
    CAPTURE(u.name);
    CHECK(names.insert(support::upperCopy(u.name)).second);
    CHECK_FALSE(u.construct.empty());
    CHECK(lang::findUnsupportedName(u.name) == &u);
    if (!u.replacement.empty()) CHECK(u.replacement == fmt::format("M{}", lang::kMReturn));
  }
  for (const lang::UnsupportedInfo& u : lang::kUnsupportedPrefixes)
    CHECK(lang::findUnsupportedPrefix(u.name) == &u);
  std::set<char> letters;
  for (const auto& a : lang::kUnsupportedAddresses) {
    CHECK(letters.insert(a.letter).second);
    CHECK_FALSE(lang::isFixedAddress(a.letter)); // S and T are addresses in z32 only
  }
  CHECK(lang::findUnsupportedName("ret")->text() == "RET; end a subprogram with M17");
}

// ---- addresses, axes, limits ------------------------------------------------------------------

TEST_CASE("lang: the default axes are not addresses of either dialect and fit a machine and an image") {
  for (char c : lang::kDefaultAxisLetters) {
    CAPTURE(c);
    CHECK_FALSE(lang::isFixedAddress(c, lang::Dialect::Sidac));
    CHECK_FALSE(lang::isFixedAddress(c, lang::Dialect::Z32));
    CHECK(lang::isDefaultAxis(c));
  }
  CHECK(lang::kDefaultAxisLetters.size() == static_cast<size_t>(lang::kMaxMachineAxes));
  CHECK(static_cast<unsigned>(lang::kMaxMachineAxes) <= lang::kMaxImageAxes);
  CHECK(lang::kMaxImageAxes == 16); // a Move descriptor's axis is a nibble
  CHECK(image::kMaxAxes == lang::kMaxImageAxes);
  const machine::Machine m = machine::builtinMachine();
  std::string letters;
  for (const auto& a : m.axes)
    letters.push_back(a.letter);
  CHECK(letters == lang::kDefaultAxisLetters);
  for (char c : lang::kZ32Addresses) {
    CHECK(lang::isFixedAddress(c, lang::Dialect::Z32));
    CHECK_FALSE(lang::isFixedAddress(c, lang::Dialect::Sidac));
  }
  CHECK(lang::isTwoLetterAddress('C', 'R', lang::Dialect::Sidac));
  CHECK_FALSE(lang::isTwoLetterAddress('M', 'A', lang::Dialect::Sidac));
  CHECK(lang::isTwoLetterAddress('M', 'C', lang::Dialect::Z32));
  CHECK(lang::isZ32WordName("ma"));
  CHECK_FALSE(lang::isZ32WordName("MD"));
  CHECK(lang::spacedLetters(lang::kFixedAddresses) == "G M N F R I J K");
}

TEST_CASE("lang: one UnitKind for the frontend and the image") {
  static_assert(std::is_same_v<frontend::UnitKind, lang::UnitKind>);
  static_assert(std::is_same_v<image::UnitKind, lang::UnitKind>);
  static_assert(std::is_same_v<frontend::SysVar, image::SysVarId>);
  CHECK(static_cast<int>(lang::UnitKind::Sub) == 2); // the image encoding
}

TEST_CASE("lang: the limits are those of SPEC.md") {
  const std::filesystem::path spec = std::filesystem::path(ISO_SHARED_DIR) / "SPEC.md";
  std::ifstream in(spec);
  if (!in) {
    MESSAGE("SPEC.md not found at ", spec.string(), "; the limits are checked against their values only");
  }
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string text = ss.str();
  auto says = [&](const std::string& phrase) {
    CAPTURE(phrase);
    if (!text.empty()) CHECK(text.find(phrase) != std::string::npos);
  };
  says(fmt::format("`R{}`..`R{}`", lang::kMinRIndex, lang::kMaxRIndex));
  says(fmt::format("n in 0..{}", lang::kMaxMarker));
  says(fmt::format("at most **{}** characters", lang::kMaxLineLength));
  says(fmt::format("At most **{} significant digits**", lang::kMaxSignificantDigits));
  says(fmt::format("Up to **{}** chained WHENs", lang::kMaxWhenChain));
  says(fmt::format("at most **{}** nested calls below the main program (dialect `z32`: {})", lang::kMaxNestingSidac,
                   lang::kMaxNestingZ32));
  says(fmt::format("Built-in default: {} axes `{}`", lang::kMaxMachineAxes,
                   lang::spacedLetters(lang::kDefaultAxisLetters)));
  says(fmt::format("Addresses in dialect sidac: `{}`", lang::spacedLetters(lang::kFixedAddresses)));
  says(fmt::format("z32 adds `{} MA MB MC`", lang::spacedLetters(lang::kZ32Addresses)));
  says(fmt::format("at most {} entries", lang::kMaxSpecialM));
  // and the values themselves, should SPEC.md be absent
  CHECK(lang::kMaxRIndex == 2880);
  CHECK(lang::kMaxMarker == 200);
  CHECK(lang::kMaxLineLength == 240);
  CHECK(lang::kMaxSignificantDigits == 9);
  CHECK(lang::kMaxWhenChain == 3);
  CHECK(image::kMaxRIndex == static_cast<uint32_t>(lang::kMaxRIndex));
  CHECK(frontend::Lexer::kMaxLineLength == lang::kMaxLineLength);
}

// ---- one place per fact -----------------------------------------------------------------------

TEST_CASE("lang: the facts of lib/lang are written nowhere else in lib/") {
  // Spellings that would mean a table of lib/lang has been copied. Rule summaries
  // (diag/Diagnostics.def) quote SPEC §7: prose. The texts editors show are columns of the
  // lang tables.
  const char* needles[] = {
      "XYZABCUVW",   "GMNFRIJK",    "G M N F R I J K", "2880",           "'X', 'Y', 'Z'", "\"STDHOPQE\"",
      "\"GOTOF\"",   "\"ENDIF\"",   "\"Posa\"",        "\"$aa_marker\"", "\"$MAX_VELO\"", "\"MAX_LIMIT_PLUS\"",
      "\"WHILE\"",   "\"STOPRE\"",  "\"ENDPROC\"",     "\"$aa_in\"",     "\"$aa_out\"",   "\"XYZ\"",
      "plane == 18", "plane == 19", "motion == 2",     "motion == 3",
  };
  const std::set<std::string> prose = {"diag/Diagnostics.def"};
  const std::filesystem::path lib = std::filesystem::path(ISO_SOURCE_DIR) / "lib";
  REQUIRE(std::filesystem::is_directory(lib));
  std::vector<std::string> found;
  std::set<std::string> inLang; // the scan sees the facts where they belong
  size_t files = 0;
  for (const auto& e : std::filesystem::recursive_directory_iterator(lib)) {
    if (!e.is_regular_file()) continue;
    const std::string rel = std::filesystem::relative(e.path(), lib).generic_string();
    const std::string ext = e.path().extension().string();
    if (prose.count(rel) || (ext != ".cpp" && ext != ".h" && ext != ".def")) continue;
    const bool lang = rel.rfind("lang/", 0) == 0;
    files += lang ? 0 : 1;
    std::ifstream f(e.path());
    std::string line;
    for (int n = 1; std::getline(f, line); ++n)
      for (const char* needle : needles)
        if (line.find(needle) == std::string::npos)
          continue;
        else if (lang)
          inLang.insert(needle);
        else
          found.push_back(fmt::format("lib/{}:{}: {}", rel, n, needle));
  }
  CHECK(files > 50);
  for (const char* needle : {"XYZABCUVW", "GMNFRIJK", "2880", "\"GOTOF\"", "\"$aa_marker\"", "\"WHILE\""})
    CHECK(inLang.count(needle) == 1);
  for (const auto& f : found)
    FAIL_CHECK(f);
  CHECK(found.empty());
}

TEST_CASE("lang: startsTwoLetterAddress names the first letter of every two-letter address") {
  for (auto d : {lang::Dialect::Sidac, lang::Dialect::Z32})
    for (char a = 'A'; a <= 'Z'; ++a) {
      bool any = false;
      for (char b = 'A'; b <= 'Z'; ++b)
        any = any || lang::isTwoLetterAddress(a, b, d);
      CAPTURE(a);
      CHECK(lang::startsTwoLetterAddress(a, d) == any);
    }
}

TEST_CASE("findKeyword: every keyword in any case, nothing else") {
  for (const lang::KeywordInfo& k : lang::kKeywords) {
    const std::string upper = support::upperCopy(k.spelling), lower = support::lowerCopy(k.spelling);
    CHECK(lang::findKeyword(k.spelling) == k.id);
    CHECK(lang::findKeyword(upper) == k.id);
    CHECK(lang::findKeyword(lower) == k.id);
    CHECK_FALSE(lang::findKeyword(upper + "X").has_value());
    CHECK_FALSE(lang::findKeyword("_" + upper).has_value());
    if (upper.size() > 1) CHECK_FALSE(lang::findKeyword(upper.substr(0, upper.size() - 1) + "Q").has_value());
  }
  for (const char* name : {"", "I", "X", "POSAX", "ENDI", "GOTOC", "1IF", "$IF", "\xc3\x84", "L4"})
    CHECK_FALSE(lang::findKeyword(name).has_value());
  CHECK(lang::findKeyword("posa") == lang::Keyword::Posa); // Pos and Posa share their first letter
  CHECK(lang::findKeyword("pos") == lang::Keyword::Pos);
  CHECK(lang::findKeyword("gOtO") == lang::Keyword::Goto);
}
