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
  for (int e = 0; e < 2000; ++e) {
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
    REQUIRE(doc.text() == text);
    const lsp::TextDocument fresh(text, 1);
    REQUIRE(doc.lineCount() == fresh.lineCount());
    for (uint32_t l = 0; l < fresh.lineCount(); ++l)
      REQUIRE(doc.line(l) == fresh.line(l));
  }
}
