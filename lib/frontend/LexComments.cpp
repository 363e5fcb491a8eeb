//! @file LexComments.cpp
//! @brief `( ... )` comments (nested on a comment line, never continued) and `;` comments with
//!        their `isolint: disable=` / `disable-file=` directives (see LexerInternal.h).
#include <string_view>

#include "frontend/LexerInternal.h"

namespace iso::frontend {

using diag::Msg;
using namespace lexer_detail;

void Lexer::lexComment(bool wholeLine) {
  // cur_ is at '('. Comments never continue: raw bytes of this physical line.
  Loc open = loc(cur_);
  uint32_t p = cur_.p + 1;
  int depth = 1;
  bool closed = false;
  // Only the first 240 characters of the logical line are analysed (E102 stops the rest).
  uint32_t used = joinedOffset(cur_) - (cur_.p - cur_.lineStart);
  uint32_t limit = used >= kMaxLineLength ? cur_.lineStart : cur_.lineStart + (kMaxLineLength - used);
  for (; p < cur_.lineEnd; ++p) {
    if (p >= limit) {
      cur_.p = p; // the line is too long: next() reports E102 here and skips the rest
      return;
    }
    char ch = src_[p];
    if (ch == '\r') {
      reportControlByte(cur_.line, p - cur_.lineStart + 1, '\r');
    } else if (ch == '$') {
      diags_.report(Msg::DollarInComment, Loc{fileId_, cur_.line, p - cur_.lineStart + 1}, 1);
      errorOnLine_ = true;
    } else if (ch == '(' && wholeLine) {
      ++depth;
    } else if (ch == ')') {
      if (!wholeLine || --depth == 0) {
        closed = true;
        ++p;
        break;
      }
    }
  }
  if (!closed) {
    if (wholeLine)
      diags_.report(Msg::CommentLineUnclosed, open, 1);
    else
      diags_.report(Msg::CommentUnclosed, open, 1);
    errorOnLine_ = true;
    p = cur_.lineEnd;
    lineEnded_ = true;
  } else if (wholeLine) {
    // A comment line must end with ')' (Z32): code after it would be part of the comment on
    // the control. Another comment or a ';' comment may follow.
    uint32_t q = p;
    while (q < cur_.lineEnd && (isBlank(src_[q]) || src_[q] == '\r'))
      ++q; // a lone CR: lexToken reports it
    if (q < cur_.lineEnd && src_[q] != ';' && src_[q] != '(') {
      diags_.report(Msg::CodeAfterCommentLine, Loc{fileId_, cur_.line, q - cur_.lineStart + 1}, 1);
      errorOnLine_ = true;
      p = cur_.lineEnd;
      lineEnded_ = true;
    }
  }
  cur_.p = p;
}

void Lexer::lexSemicolonComment() {
  semicolonAt_ = cur_.p;
  std::string_view text = src_.substr(cur_.p + 1, cur_.lineEnd - cur_.p - 1);
  if (size_t cr = text.find('\r'); cr != std::string_view::npos) // one per comment: its length is not bounded
    reportControlByte(cur_.line, static_cast<uint32_t>(cur_.p + 2 + cr - cur_.lineStart), '\r');
  cur_.p = cur_.lineEnd;
  lineEnded_ = true;
  size_t k = text.find("isolint:");
  if (k == std::string_view::npos) return;
  std::string_view rest = text.substr(k + 8);
  while (!rest.empty() && isBlank(rest.front()))
    rest.remove_prefix(1);
  uint32_t line = 0;
  if (rest.substr(0, 13) == "disable-file=") {
    rest.remove_prefix(13);
  } else if (rest.substr(0, 8) == "disable=") {
    rest.remove_prefix(8);
    line = cur_.line;
  } else {
    return;
  }
  while (!rest.empty()) {
    size_t e = 0;
    while (e < rest.size() && (isIdentChar(rest[e]) || rest[e] == '-'))
      ++e;
    if (e == 0) break;
    const auto col = static_cast<uint32_t>(rest.data() - src_.data()) - cur_.lineStart + 1;
    if (auto code = diag::findCode(rest.substr(0, e))) {
      suppressions_.push_back({line, *code, line, cur_.line, col, static_cast<uint32_t>(e)});
    } else {
      diags_.report(Msg::SuppressionUnknown, Loc{fileId_, cur_.line, col}, static_cast<uint32_t>(e), rest.substr(0, e));
    }
    rest.remove_prefix(e);
    if (rest.empty() || rest.front() != ',') break;
    rest.remove_prefix(1);
  }
}

} // namespace iso::frontend
