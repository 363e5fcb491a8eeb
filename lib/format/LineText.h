//! @file LineText.h
//! @brief One logical line on one physical line, written again from its tokens (private to the
//!        format area): the prefixes and label, the statement's words with the style's case and
//!        blanks, the comments as written.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "format/Formatter.h"

namespace iso::format {

/// The index of the first token after the prefixes (`%`, `/`, the N number) and the label.
size_t statementStart(const std::vector<frontend::Token>& toks);
/// The number of prefix tokens (`%`, `/`, the N number) at the start of `toks`.
size_t prefixCount(const std::vector<frontend::Token>& toks);

/// True when `a` and `b` are the same tokens for the parser: kinds, addresses, values, names
/// in any case; strings, GO targets and (unless `numbersMayDiffer`) number spellings exactly.
bool sameTokens(const std::vector<frontend::Token>& a, const std::vector<frontend::Token>& b, bool numbersMayDiffer);

/// The first line with a syntax error (a lexical or parse error), 0 when the file has none.
uint32_t firstSyntaxErrorLine(std::string_view text, const frontend::LexOptions& lex);

/// A number as the Normalised style spells it: a leading 0 before a leading separator, `.` as
/// the separator. The value is the same.
std::string normaliseNumber(std::string_view digits);

/// A line written again: its text, or (ok false) the reason it stays as written ("" when
/// that is no news: a line that cannot be read as tokens on its own).
struct WrittenLine {
  bool ok = false; ///< false: the line stays as written
  std::string text;
  std::string why;
};

class LineWriter {
public:
  explicit LineWriter(const FormatOptions& opts) : opts_(opts) {}
  /// The new text of the physical line `raw` (no line end) holding the logical line `toks`
  /// (without Tok::End), its statement at IF/WHEN depth `depth`.
  WrittenLine write(std::string_view raw, const std::vector<frontend::Token>& toks, uint32_t depth) const;

private:
  std::string tokenText(const std::vector<frontend::Token>& toks, size_t i, std::string_view raw) const;
  std::string separator(const std::vector<frontend::Token>& toks, size_t i, std::string_view raw) const;
  std::string cased(std::string_view s) const;
  /// `head`: the text of the prefixes and, after them, of the statement.
  bool writeHead(std::string_view raw, const std::vector<frontend::Token>& toks, uint32_t depth, std::string& out,
                 size_t& next) const;
  void writeTail(std::string_view raw, const std::vector<frontend::Token>& toks, std::string& out,
                 size_t& commentAt) const;
  bool relexes(std::string_view line, const std::vector<frontend::Token>& toks) const;

  const FormatOptions& opts_;
};

} // namespace iso::format
