//! @file LanguageDocsTests.cpp
//! @brief The hover and completion texts come from the lang tables: one completion entry per
//!        row, the same text as the hover, and each item name a real item of the language.
#include <map>
#include <set>
#include <string>

#include <doctest/doctest.h>

#include "lang/Addresses.h"
#include "lang/GCodes.h"
#include "lang/Keywords.h"
#include "lang/MFunctions.h"
#include "lang/SysVars.h"
#include "lsp/LanguageDocs.h"

using namespace iso;
using lsp::EntryKind;

TEST_CASE("lsp docs: one completion entry per lang row, each with its hover text") {
  std::map<EntryKind, size_t> count;
  std::set<std::string> labels;
  for (const lsp::LanguageEntry& e : lsp::languageEntries()) {
    CAPTURE(e.label);
    ++count[e.kind];
    CHECK(labels.insert(e.label).second);
    CHECK_FALSE(e.detail.empty());
    switch (e.kind) {
    case EntryKind::Keyword:
    case EntryKind::Item: CHECK(lsp::hoverWord(e.label) == e.doc); break;
    case EntryKind::GCode: CHECK(lsp::hoverG(std::stoi(e.label.substr(1))) == e.doc); break;
    case EntryKind::MCode: CHECK(lsp::hoverM(std::stoi(e.label.substr(1))) == e.doc); break;
    case EntryKind::SysVar: CHECK(lsp::hoverSysVar(e.label) == e.doc); break;
    }
  }
  size_t reserved = 0;
  for (const lang::KeywordInfo& k : lang::kKeywords)
    reserved += k.reserved ? 1 : 0;
  CHECK(count[EntryKind::Keyword] == reserved);
  CHECK(count[EntryKind::Item] == lang::kKeywordCount - reserved + 1); // and the address CR
  CHECK(count[EntryKind::GCode] == lang::kGCodeCount);
  CHECK(count[EntryKind::MCode] == std::size(lang::kMFunctionDocs));
  CHECK(count[EntryKind::SysVar] == lang::kSysVarCount);
}

TEST_CASE("lsp docs: every item name is an item of the language") {
  for (const lsp::LanguageEntry& e : lsp::languageEntries()) {
    CAPTURE(e.label);
    if (e.kind == EntryKind::Keyword) CHECK(lang::isReservedKeyword(e.label));
    if (e.kind != EntryKind::Item) continue;
    if (auto k = lang::findKeyword(e.label)) {
      CHECK_FALSE(lang::keywordInfo(*k).reserved);
      CHECK(lang::keywordInfo(*k).spelling == e.label);
    } else {
      // not a keyword: a two-letter address of both dialects
      REQUIRE(e.label.size() == 2);
      for (auto d : {lang::Dialect::Sidac, lang::Dialect::Z32})
        CHECK(lang::isTwoLetterAddress(e.label[0], e.label[1], d));
    }
  }
}
