//! @file LangDocsTests.cpp
//! @brief The documentation columns of the lang tables (the texts editors show): every row has
//!        them, and what they say agrees with the row's other columns.
#include <cstdint>
#include <string>
#include <string_view>

#include <doctest/doctest.h>
#include <fmt/format.h>

#include "lang/Addresses.h"
#include "lang/GCodes.h"
#include "lang/Keywords.h"
#include "lang/Limits.h"
#include "lang/MFunctions.h"
#include "lang/SysVars.h"

using namespace iso;

namespace {
bool has(std::string_view text, std::string_view part) { return text.find(part) != std::string_view::npos; }
} // namespace

TEST_CASE("lang docs: every G code is documented, and the texts agree with its group") {
  for (const lang::GInfo& g : lang::kGCodes) {
    CAPTURE(g.code);
    CHECK_FALSE(g.doc.empty());
    CHECK_FALSE(lang::gGroupName(g.group).empty());
    if (g.group == lang::GGroup::None) CHECK(g.id == lang::kDwell); // "dwell" names the group
    if (g.group == lang::GGroup::Plane) {
      const lang::PlaneAxes axes = lang::planeAxes(g.modal);
      CHECK(g.doc == fmt::format("arc plane {}{}", axes.p, axes.q));
    }
    if (g.group == lang::GGroup::Motion && lang::isArc(g.modal)) CHECK(has(g.doc, lang::kRadiusAddress));
  }
  CHECK(lang::gGroupName(lang::GGroup::Motion) == "motion");
  CHECK(lang::gGroupName(lang::GGroup::None) == "dwell");
}

TEST_CASE("lang docs: every keyword is documented with a syntax that spells it") {
  for (const lang::KeywordInfo& k : lang::kKeywords) {
    CAPTURE(k.spelling);
    CHECK_FALSE(k.doc.empty());
    CHECK(has(k.syntax, k.spelling));
    CHECK_FALSE(has(k.syntax, "\n"));
  }
}

TEST_CASE("lang docs: every system variable is documented, and its access agrees with its flags") {
  for (const lang::SysVarInfo& v : lang::kSysVars) {
    CAPTURE(v.name);
    CHECK_FALSE(v.doc.empty());
    CHECK(has(v.access, "read"));
    CHECK(has(v.access, "write") == v.writable);
    CHECK(has(v.access, "only as the whole right side of an R assignment") == v.machineData);
  }
  CHECK(has(lang::sysVarInfo(lang::SysVar::AaMarker).doc, fmt::format("0..{}", lang::kMaxMarker)));
}

TEST_CASE("lang docs: one row for each M function that is more than a PLC sequence in both dialects") {
  for (int64_t n = 0; n <= 1000; ++n) {
    CAPTURE(n);
    int rows = 0;
    for (const lang::MFunctionDoc& m : lang::kMFunctionDocs)
      if (m.number == n) {
        ++rows;
        CHECK_FALSE(m.doc.empty());
      }
    CHECK(rows == (lang::mRole(n, lang::Dialect::Sidac) != lang::MRole::Plain ? 1 : 0));
    if (rows != 0) CHECK(lang::mRole(n, lang::Dialect::Z32) == lang::mRole(n, lang::Dialect::Sidac));
  }
}
