//! @file MessagesTests.cpp
//! @brief The message table (diag/Messages.def): every entry belongs to a code, every code has
//!        a message, the entries are grouped by code, no code repeats a text, the format strings
//!        are well formed, and language facts come in as arguments.
#include <set>
#include <string>
#include <string_view>
#include <utility>

#include <doctest/doctest.h>

#include "diag/Diagnostic.h"

using namespace iso::diag;

namespace {
Msg msgAt(size_t i) { return static_cast<Msg>(i); }

/// Counts the replacement fields of `f`; false when a brace is unbalanced or a field names an argument.
bool wellFormed(std::string_view f, size_t& fields) {
  fields = 0;
  for (size_t i = 0; i < f.size(); ++i) {
    if (f[i] == '{') {
      if (i + 1 < f.size() && f[i + 1] == '{') {
        ++i;
        continue;
      }
      size_t close = f.find('}', i);
      if (close == std::string_view::npos) return false;
      std::string_view field = f.substr(i + 1, close - i - 1);
      if (!field.empty() && field[0] != ':') return false; // automatic indexing only
      if (field.find('{') != std::string_view::npos) return false;
      ++fields;
      i = close;
    } else if (f[i] == '}') {
      if (i + 1 < f.size() && f[i + 1] == '}') {
        ++i;
        continue;
      }
      return false;
    }
  }
  return true;
}
} // namespace

TEST_CASE("messages: every entry has a valid code, and the entries are grouped by code") {
  REQUIRE(msgCount() > 0);
  for (size_t i = 0; i < msgCount(); ++i) {
    const MsgInfo& m = info(msgAt(i));
    INFO(m.name);
    CHECK(static_cast<size_t>(m.code) < codeCount());
    CHECK(std::string_view(m.format).size() > 0);
    if (i > 0) CHECK(info(msgAt(i - 1)).code <= m.code); // in the order of Diagnostics.def
  }
}

TEST_CASE("messages: every code of Diagnostics.def has at least one message") {
  std::set<Code> with;
  for (size_t i = 0; i < msgCount(); ++i)
    with.insert(codeOf(msgAt(i)));
  for (size_t c = 0; c < codeCount(); ++c) {
    INFO(info(static_cast<Code>(c)).code);
    CHECK(with.count(static_cast<Code>(c)) == 1);
  }
}

TEST_CASE("messages: no two entries of one code have the same text") {
  std::set<std::pair<Code, std::string>> seen;
  for (size_t i = 0; i < msgCount(); ++i) {
    const MsgInfo& m = info(msgAt(i));
    INFO(m.name);
    CHECK(seen.insert({m.code, m.format}).second);
  }
}

TEST_CASE("messages: format strings are well formed and their fields are counted") {
  for (size_t i = 0; i < msgCount(); ++i) {
    const MsgInfo& m = info(msgAt(i));
    INFO(m.name << ": " << m.format);
    size_t fields = 0;
    CHECK(wellFormed(m.format, fields));
    // The count MsgRef checks call sites against (at compile time) is the count here.
    CHECK(placeholderCount(m.format) == fields);
  }
  static_assert(placeholderCount("a {} b {:02} c {{}} d") == 2);
  static_assert(placeholderCount("no fields") == 0);
}

TEST_CASE("messages: language facts are arguments, not text") {
  // Limits, M functions, G codes and system variables come from lib/lang at the call site.
  for (const char* fact :
       {"M17", "M30", "M2 ", "G00", "G02", "G03", "G04", "2880", "240", "$aa_", "$AA_", "8000", "0.01"})
    for (size_t i = 0; i < msgCount(); ++i) {
      const MsgInfo& m = info(msgAt(i));
      INFO(m.name << " holds " << fact);
      CHECK(std::string_view(m.format).find(fact) == std::string_view::npos);
    }
}

TEST_CASE("messages: report takes the code from the table and formats the arguments") {
  DiagnosticList list;
  Diagnostic& d = list.report(Msg::LabelTwice, Loc{0, 3, 1}, 4, std::string_view("LOOP"));
  d.note(Msg::LabelTwiceNote, Loc{0, 1, 1});
  CHECK(d.code == Code::LabelDuplicate);
  CHECK(d.severity == Severity::Error);
  CHECK(d.message == "label 'LOOP' is defined twice in this file");
  CHECK(d.endCol == 5);
  REQUIRE(d.notes.size() == 1);
  CHECK(d.notes[0].message == "first defined here");
  CHECK(message(Msg::GConflict, 1, 0, 0) == "G01 and G00 are of one group on one line; the last (G00) wins");
  CHECK(codeOf(Msg::GConflict) == Code::GConflict);
  CHECK(
      message(Msg::ArcEndOffCircle, 1.0, 1.5, 0.5, 0.01) ==
      "end point is not on the circle: start radius 1.0000 mm, end radius 1.5000 mm (difference 0.5000 mm > 0.01 mm)");
  CHECK(message(Msg::AuxClamped, "MA", "12345", 9999, size_t{4}, 8000) ==
        "MA12345 is sent to the PLC as 9999 (only 4 integer digits are significant; a sign adds 8000)");
}
