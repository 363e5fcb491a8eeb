//! @file TokenNames.cpp
//! @brief What messages call tokens (tokName), source bytes as a message quotes them
//!        (printableBytes), the reserved keywords (isKeyword); see LexerInternal.h.
#include <string>
#include <string_view>

#include <fmt/format.h>

#include "frontend/LexerInternal.h"

namespace iso::frontend {

using diag::Msg;
using namespace lexer_detail;

std::string printableBytes(std::string_view text) {
  std::string r;
  r.reserve(text.size());
  for (char ch : text) {
    auto b = static_cast<unsigned char>(ch);
    if (b >= 0x80 || isControl(b) || b == '\t')
      r += fmt::format("\\x{:02X}", b);
    else
      r.push_back(ch);
  }
  return r;
}

bool isKeyword(std::string_view s) { return lang::isReservedKeyword(s); }

const char* tokName(Tok t) {
  switch (t) {
  case Tok::End: return "end of line";
  case Tok::Word: return "word";
  case Tok::Ident: return "name";
  case Tok::Number: return "number";
  case Tok::SysVar: return "system variable";
  case Tok::String: return "string";
  case Tok::GoTarget: return "GO target";
  case Tok::Plus: return "'+'";
  case Tok::Minus: return "'-'";
  case Tok::Star: return "'*'";
  case Tok::Slash: return "'/'";
  case Tok::Assign: return "'='";
  case Tok::Eq: return "'=='";
  case Tok::Ne: return "'<>'";
  case Tok::Lt: return "'<'";
  case Tok::Gt: return "'>'";
  case Tok::Le: return "'<='";
  case Tok::Ge: return "'>='";
  case Tok::LParen: return "'('";
  case Tok::RParen: return "')'";
  case Tok::LBracket: return "'['";
  case Tok::RBracket: return "']'";
  case Tok::Colon: return "':'";
  case Tok::Percent: return "'%'";
  case Tok::Hash: return "'#'";
  case Tok::Other: return "character";
  case Tok::Error: return "error";
#define ISO_KEYWORD(Name, spelling, reserved) case Tok::Kw##Name:
#include "lang/Keywords.def"
    return "keyword";
  }
  return "token";
}

} // namespace iso::frontend
