//! @file TextDocumentEditTests.cpp
//! @brief lsp::TextDocument::edit keeps its line index as a fresh index of the new text would.
#include <random>
#include <string>

#include <doctest/doctest.h>

#include "lsp/TextDocument.h"

using namespace iso;

TEST_CASE("text document: random edits keep the line index of the new text") {
  std::mt19937 rng(7);
  std::string text = "G0 X1\nG1 Y2 F100\r\n\nM30\n";
  lsp::TextDocument doc(text, 1);
  static const std::string kBytes = "ab\n\r X1;";
  for (int e = 0; e < 4000; ++e) {
    const auto line = static_cast<uint32_t>(rng() % (doc.lineCount() + 1));
    const lsp::Position a{line, static_cast<uint32_t>(rng() % 8)};
    const lsp::Position b{line + static_cast<uint32_t>(rng() % 3), static_cast<uint32_t>(rng() % 8)};
    std::string ins;
    for (unsigned k = rng() % 4; k > 0; --k)
      ins += kBytes[rng() % kBytes.size()];
    const size_t from = doc.offset(a), to = doc.offset(b);
    const lsp::TextDocument::Change c = doc.edit({a, b}, ins);
    const size_t lo = std::min(from, to), hi = std::max(from, to);
    CHECK(c.at == lo);
    CHECK(c.removed == hi - lo);
    CHECK(c.inserted == ins.size());
    const std::string removed = text.substr(lo, hi - lo);
    CHECK(c.sameLines ==
          (std::count(removed.begin(), removed.end(), '\n') == std::count(ins.begin(), ins.end(), '\n')));
    text.replace(lo, hi - lo, ins);
    REQUIRE(doc.size() == text.size());
    const lsp::TextDocument fresh(text, 1);
    REQUIRE(doc.lineCount() == fresh.lineCount());
    for (uint32_t l = 0; l < fresh.lineCount(); ++l)
      REQUIRE(doc.line(l) == fresh.line(l));
    const size_t off = rng() % (text.size() + 1);
    REQUIRE(doc.position(off) == fresh.position(off));
    REQUIRE(doc.offset(fresh.position(off)) == fresh.offset(fresh.position(off)));
    const std::string_view pre = doc.prefix(off);
    REQUIRE(pre.size() >= off);
    REQUIRE(pre == std::string_view(text).substr(0, pre.size()));
    REQUIRE((pre.empty() || pre.size() == text.size() || text[pre.size() - 1] == '\n'));
    if (e % 7 == 0) REQUIRE(doc.text() == text); // closes the gap
  }
}

TEST_CASE("text document: edits across blocks of line starts") {
  std::mt19937 rng(11);
  std::string text;
  for (int k = 0; k < 5000; ++k)
    text += "G1 X" + std::to_string(k) + "\n";
  lsp::TextDocument doc(text, 1);
  for (int e = 0; e < 600; ++e) {
    const auto line = static_cast<uint32_t>(rng() % doc.lineCount());
    const lsp::Position a{line, static_cast<uint32_t>(rng() % 6)};
    const lsp::Position b{line, a.character + static_cast<uint32_t>(rng() % 2)};
    const std::string ins = e % 50 == 49 ? "\n" : std::string(rng() % 3, 'Y');
    const size_t from = doc.offset(a), to = doc.offset(b);
    doc.edit({a, b}, ins);
    text.replace(from, to - from, ins);
    const lsp::TextDocument fresh(text, 1);
    REQUIRE(doc.lineCount() == fresh.lineCount());
    for (uint32_t l : {0u, line > 0 ? line - 1 : 0u, line, line + 1, 1023u, 1024u, 2047u, 2048u, doc.lineCount() - 1})
      REQUIRE(doc.line(l) == fresh.line(l));
    const size_t off = rng() % (text.size() + 1);
    REQUIRE(doc.position(off) == fresh.position(off));
  }
  CHECK(doc.text() == text);
}
