//! @file Renumber.cpp
//! @brief N numbers and the GO targets that name them, rewritten together (Renumber.h).
#include "format/Renumber.h"

#include <algorithm>
#include <deque>
#include <map>

#include <fmt/format.h>

#include "format/Formatter.h"
#include "format/LineText.h"
#include "frontend/GoTarget.h"
#include "lang/Limits.h"

namespace iso::format {

using frontend::Tok;
using frontend::Token;

namespace {

struct Refusal {
  uint32_t line = 0;
  std::string message;
};

struct Edit {
  size_t at = 0;
  size_t len = 0;
  std::string text;
};

/// One GO target of the file: `GO<a>` or the `<b>` of `GO<a>-<b>`.
struct GoRef {
  std::string_view target; ///< as written: "N12", "%N1"
  size_t offset = 0;       ///< of the target text in the file
  uint32_t line = 0;       ///< of the GO
  int from = -1;           ///< a range end: the index of its start in the list
  uint32_t found = 0;      ///< the line the target finds
  std::string renamed;     ///< the target after renumbering
};

class Renumberer {
public:
  Renumberer(std::string_view text, const RenumberOptions& opts) : text_(text), opts_(opts) {}

  std::string run() {
    if (const uint32_t bad = firstSyntaxErrorLine(text_, opts_.lex); bad != 0)
      throw Refusal{bad, "the file has syntax errors (isolint shows them): not renumbered"};
    phys_ = splitLines(text_);
    lexAll();
    for (const auto& l : lines_)
      numberLine(l);
    for (auto& g : gos_)
      resolve(g);
    keepCommentColumns();
    std::string out = apply();
    verify(out);
    return out;
  }

private:
  size_t offsetOf(const Token& t) const { return phys_[t.line - 1].begin + t.col - 1; }
  size_t textOffset(std::string_view s) const { return static_cast<size_t>(s.data() - text_.data()); }

  void lexAll() {
    diag::DiagnosticList diags;
    std::vector<frontend::Suppression> suppressions;
    frontend::Lexer lexer(text_, 0, opts_.lex, diags, suppressions, owned_);
    for (;;) {
      frontend::LogicalLine l;
      if (!lexer.next(l)) break;
      l.tokens.pop_back();
      if (!l.tokens.empty() && l.firstLine == l.lastLine)
        tokensEnd_[l.firstLine - 1] = offsetOf(l.tokens.back()) + l.tokens.back().len;
      for (size_t k = 0; k < l.tokens.size(); ++k) {
        const Token& t = l.tokens[k];
        if (t.kind != Tok::GoTarget) continue;
        GoRef g{t.text, textOffset(t.text), t.line, -1, 0, {}};
        const bool rangeEnd = t.len == t.text.size(); // the token does not span `GO`
        if (rangeEnd && !gos_.empty()) g.from = static_cast<int>(gos_.size() - 1);
        gos_.push_back(g);
      }
      lines_.push_back(std::move(l));
    }
  }

  std::string nextNumber(uint32_t line) {
    if (opts_.start > kMaxLineNumber || (count_ > 0 && opts_.step > (kMaxLineNumber - opts_.start) / count_))
      throw Refusal{
          line, fmt::format("the N numbers would pass {} (9 digits): choose a smaller start or step", kMaxLineNumber)};
    const uint64_t n = opts_.start + count_ * opts_.step;
    ++count_;
    return std::to_string(n);
  }

  void numberLine(const frontend::LogicalLine& l) {
    const auto& toks = l.tokens;
    const size_t p = prefixCount(toks);
    const bool hasN = p > 0 && toks[p - 1].kind == Tok::Word && toks[p - 1].addr[0] == 'N';
    if (hasN) {
      const Token& t = toks[p - 1];
      if (t.joined) throw Refusal{t.line, "an N number split by a $ continuation"};
      std::string n = nextNumber(t.line);
      checkLength(l, n.size(), t.text.size());
      written_[std::string(t.text)].push_back(t.line);
      newNumber_[t.line] = n;
      edits_.push_back({textOffset(t.text), t.text.size(), std::move(n)});
      return;
    }
    if (!opts_.allLines || toks.size() <= p) return;
    const size_t s = statementStart(toks);
    if (s < toks.size() && (toks[s].kind == Tok::KwProc || toks[s].kind == Tok::KwSemi)) return;
    const size_t at = p == 0 ? phys_[l.firstLine - 1].begin : offsetOf(toks[p - 1]) + toks[p - 1].len;
    std::string ins = fmt::format("N{} ", nextNumber(l.firstLine));
    checkLength(l, ins.size(), 0);
    edits_.push_back({at, 0, std::move(ins)});
  }

  static void checkLength(const frontend::LogicalLine& l, size_t added, size_t removed) {
    if (l.length + added > lang::kMaxLineLength + removed)
      throw Refusal{l.firstLine,
                    fmt::format("renumbered, the line would be longer than {} characters", lang::kMaxLineLength)};
  }

  void resolve(GoRef& g) {
    const std::string shown = fmt::format("GO target {}", g.target);
    frontend::GoLineMatch m;
    if (g.from < 0) {
      m = frontend::findGoLine(text_, g.target);
    } else {
      m.line = frontend::findGoLineFrom(text_, g.target, gos_[static_cast<size_t>(g.from)].found);
    }
    if (m.line == 0) throw Refusal{g.line, fmt::format("the {} finds no line", shown)};
    if (m.blankCandidate != 0)
      throw Refusal{g.line, fmt::format("line {} holds {} after blanks (never a GO target): renumbering could "
                                        "change which line the {} finds",
                                        m.blankCandidate, g.target, shown)};
    const size_t n = g.target.find_first_of("Nn");
    const std::string_view digits = g.target.substr(n + 1);
    auto it = newNumber_.find(m.line);
    auto w = written_.find(std::string(digits));
    if (it == newNumber_.end() || w == written_.end())
      throw Refusal{g.line,
                    fmt::format("the {} finds line {}, which does not start with that N number", shown, m.line)};
    if (w->second.size() > 1)
      throw Refusal{g.line, fmt::format("the {} names N{}, written on lines {} and {}: a repeated N number is no "
                                        "GO target",
                                        shown, digits, w->second[0], w->second[1])};
    g.found = m.line;
    g.renamed = std::string(g.target.substr(0, n + 1)) + it->second;
    edits_.push_back({g.offset + n + 1, digits.size(), it->second});
  }

  /// A line whose numbers grow or shrink keeps its `;` comment in its column where the blanks
  /// before the comment allow it.
  void keepCommentColumns() {
    std::map<uint32_t, long long> delta; // physical line (0-based) -> bytes added
    for (const auto& e : edits_) {
      auto it = std::upper_bound(phys_.begin(), phys_.end(), e.at,
                                 [](size_t at, const PhysicalLine& l) { return at < l.begin; });
      const auto line = static_cast<uint32_t>(it - phys_.begin() - 1);
      delta[line] += static_cast<long long>(e.text.size()) - static_cast<long long>(e.len);
    }
    for (const auto& [line, d] : delta) {
      auto end = tokensEnd_.find(line);
      if (d == 0 || end == tokensEnd_.end()) continue;
      const PhysicalLine& l = phys_[line];
      const std::string_view rest = text_.substr(end->second, l.end - end->second);
      const size_t semi = rest.find_first_not_of(" \t");
      if (semi == std::string_view::npos || rest[semi] != ';') continue;
      const size_t at = end->second + semi;
      if (d < 0) {
        edits_.push_back({at, 0, std::string(static_cast<size_t>(-d), ' ')});
      } else if (semi > static_cast<size_t>(d)) {
        edits_.push_back({at - static_cast<size_t>(d), static_cast<size_t>(d), ""});
      }
    }
  }

  std::string apply() {
    std::sort(edits_.begin(), edits_.end(), [](const Edit& a, const Edit& b) { return a.at < b.at; });
    std::string out;
    size_t copied = 0;
    for (const auto& e : edits_) {
      out.append(text_.substr(copied, e.at - copied));
      out.append(e.text);
      copied = e.at + e.len;
    }
    out.append(text_.substr(copied));
    return out;
  }

  /// Every GO of the renumbered text finds the line it found before.
  void verify(std::string_view out) const {
    for (const auto& g : gos_) {
      uint32_t line = 0;
      if (g.from < 0) {
        const auto m = frontend::findGoLine(out, g.renamed);
        line = m.blankCandidate == 0 ? m.line : 0;
      } else {
        line = frontend::findGoLineFrom(out, g.renamed, gos_[static_cast<size_t>(g.from)].found);
      }
      if (line != g.found)
        throw Refusal{g.line, fmt::format("renumbered, the GO target {} would find line {} instead of line {}",
                                          g.renamed, line, g.found)};
    }
  }

  std::string_view text_;
  const RenumberOptions& opts_;
  std::vector<PhysicalLine> phys_;
  std::deque<std::string> owned_;
  std::vector<frontend::LogicalLine> lines_;
  std::vector<GoRef> gos_;
  std::vector<Edit> edits_;
  std::map<uint32_t, std::string> newNumber_;            ///< physical line -> its new N number
  std::map<std::string, std::vector<uint32_t>> written_; ///< an N number as written -> its lines
  std::map<uint32_t, size_t> tokensEnd_;                 ///< physical line (0-based) -> the end of its last token
  uint64_t count_ = 0;
};

} // namespace

support::Expected<std::string> renumber(std::string_view text, const RenumberOptions& opts) {
  try {
    return Renumberer(text, opts).run();
  } catch (const Refusal& r) {
    return support::Error{r.line == 0 ? "" : std::to_string(r.line), r.message};
  }
}

} // namespace iso::format
