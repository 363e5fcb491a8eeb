//! @file Formatter.cpp
//! @brief isofmt's layout (Formatter.h): the tokens of each logical line written again with
//!        the style's case and blanks, checked by lexing the new text.
#include "format/Formatter.h"

#include <deque>
#include <exception>
#include <optional>

#include <fmt/format.h>

#include "format/LineText.h"

namespace iso::format {

using frontend::Tok;
using frontend::Token;

std::vector<PhysicalLine> splitLines(std::string_view text) {
  std::vector<PhysicalLine> out;
  size_t p = text.substr(0, 3) == "\xEF\xBB\xBF" ? 3 : 0;
  while (p < text.size()) {
    PhysicalLine l;
    l.begin = p;
    const size_t nl = text.find('\n', p);
    l.next = nl == std::string_view::npos ? text.size() : nl + 1;
    l.end = nl == std::string_view::npos ? text.size() : nl;
    if (l.end > l.begin && text[l.end - 1] == '\r' && nl != std::string_view::npos) --l.end;
    out.push_back(l);
    p = l.next;
  }
  return out;
}

Assembled assemble(std::string_view base, const std::vector<LineOutput>& lines) {
  Assembled a;
  const auto phys = splitLines(base);
  size_t copied = 0;
  for (size_t i = 0; i < phys.size() && i < lines.size(); ++i) {
    const PhysicalLine& l = phys[i];
    const std::string_view old = base.substr(l.begin, l.end - l.begin);
    if (lines[i].removed) {
      a.edits.push_back({l.begin, l.next, ""});
    } else if (lines[i].content != old) {
      a.edits.push_back({l.begin, l.end, lines[i].content});
    }
  }
  for (const auto& e : a.edits) {
    a.text.append(base.substr(copied, e.begin - copied));
    a.text.append(e.replacement);
    copied = e.end;
  }
  a.text.append(base.substr(copied));
  return a;
}

namespace {

/// The IF and WHEN structure of a logical line.
enum class Shape : uint8_t { Other, BlockIf, Else, EndIf, LongWhen, Cancel };

Shape shapeOf(const std::vector<Token>& toks) {
  const size_t s = statementStart(toks);
  if (s >= toks.size()) return Shape::Other;
  const bool alone = s + 1 == toks.size();
  switch (toks[s].kind) {
  case Tok::KwIf:
    for (size_t k = s + 1; k < toks.size(); ++k)
      if (toks[k].kind == Tok::KwThen || frontend::isJumpTok(toks[k].kind) || toks[k].kind == Tok::GoTarget)
        return Shape::Other;
    return Shape::BlockIf;
  case Tok::KwElse: return alone ? Shape::Else : Shape::Other;
  case Tok::KwEndIf: return alone ? Shape::EndIf : Shape::Other;
  case Tok::KwWhen: return toks.back().kind == Tok::KwDo ? Shape::LongWhen : Shape::Other;
  case Tok::KwCancel: return alone ? Shape::Cancel : Shape::Other;
  default: return Shape::Other;
  }
}

/// The open IF and WHEN bodies: the depth a line is printed at.
class Nesting {
public:
  uint32_t depthFor(Shape s) {
    switch (s) {
    case Shape::BlockIf: open_.push_back('I'); return depth() - 1;
    case Shape::LongWhen: open_.push_back('W'); return depth() - 1;
    case Shape::Else: return top('I') ? depth() - 1 : depth();
    case Shape::EndIf:
      if (top('I')) open_.pop_back();
      return depth();
    case Shape::Cancel:
      if (top('W')) open_.pop_back();
      return depth();
    case Shape::Other: break;
    }
    return depth();
  }

private:
  uint32_t depth() const { return static_cast<uint32_t>(open_.size()); }
  bool top(char c) const { return !open_.empty() && open_.back() == c; }
  std::vector<char> open_;
};

struct Lexed {
  std::deque<std::string> owned;
  std::vector<frontend::LogicalLine> lines;
};

void lexAll(std::string_view text, const FormatOptions& opts, Lexed& out) {
  diag::DiagnosticList diags;
  std::vector<frontend::Suppression> suppressions;
  frontend::Lexer lexer(text, 0, opts.lex, diags, suppressions, out.owned);
  for (;;) {
    frontend::LogicalLine l;
    if (!lexer.next(l)) break;
    l.tokens.pop_back(); // Tok::End
    out.lines.push_back(std::move(l));
  }
}

/// Drops blank lines beyond the style's run length and those at the end of the file. Only a
/// blank line that is a logical line of its own is dropped (a `$` may join the next line to it).
void collapseBlankLines(std::vector<LineOutput>& lines, const std::vector<bool>& standalone, uint32_t maxRun) {
  uint32_t run = 0;
  for (size_t i = 0; i < lines.size(); ++i) {
    if (!standalone[i] || !lines[i].content.empty()) {
      run = 0;
      continue;
    }
    if (++run > maxRun) lines[i].removed = true;
  }
  for (size_t i = lines.size(); i-- > 0;) {
    if (!standalone[i] || !lines[i].content.empty()) break;
    lines[i].removed = true;
  }
}

void formatAll(std::string_view text, const FormatOptions& opts, const std::vector<PhysicalLine>& phys,
               FormatResult& r) {
  Lexed lexed;
  lexAll(text, opts, lexed);
  std::vector<bool> standalone(phys.size(), false);
  Nesting nesting;
  const LineWriter writer(opts);
  for (const auto& ll : lexed.lines) {
    if (ll.firstLine == 0 || ll.firstLine > phys.size()) continue;
    const uint32_t depth = nesting.depthFor(shapeOf(ll.tokens));
    const size_t i = ll.firstLine - 1;
    if (ll.lastLine != ll.firstLine) continue; // a `$` continuation stays as written
    standalone[i] = true;
    const std::string_view raw = text.substr(phys[i].begin, phys[i].end - phys[i].begin);
    auto line = writer.write(raw, ll.tokens, depth);
    if (line.ok) {
      r.lines[i].content = std::move(line.text);
    } else {
      r.lines[i].content = std::string(raw);
      if (!line.why.empty()) r.notes.push_back({ll.firstLine, std::move(line.why)});
    }
  }
  collapseBlankLines(r.lines, standalone, opts.style.maxBlankLines);
}

} // namespace

FormatResult formatLines(std::string_view text, const FormatOptions& opts) {
  FormatResult r;
  const auto phys = splitLines(text);
  r.lines.resize(phys.size());
  for (size_t i = 0; i < phys.size(); ++i)
    r.lines[i].content = std::string(text.substr(phys[i].begin, phys[i].end - phys[i].begin));
  const std::vector<LineOutput> asWritten = r.lines;
  try {
    if (const uint32_t bad = firstSyntaxErrorLine(text, opts.lex); bad != 0) {
      r.keptAsWritten = true;
      r.notes.push_back({bad, "the file has syntax errors (isolint shows them): it is left as written"});
      return r;
    }
    formatAll(text, opts, phys, r);
  } catch (const std::exception& e) {
    r.lines = asWritten;
    r.keptAsWritten = true;
    r.notes.clear();
    r.notes.push_back({0, fmt::format("left as written: {}", e.what())});
  }
  return r;
}

} // namespace iso::format
