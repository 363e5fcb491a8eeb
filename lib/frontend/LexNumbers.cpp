//! @file LexNumbers.cpp
//! @brief A scanned number finished when it is long or on a line a `$` continues: its value past 15
//!        digits (from_chars), E101 for more than 9 significant digits with its rounding fix-it,
//!        and that rounding (see LexerInternal.h).
#include <charconv>
#include <optional>
#include <string>
#include <string_view>

#include "frontend/LexerInternal.h"

namespace iso::frontend {

using diag::Msg;
using namespace lexer_detail;

std::optional<std::string> roundToNineDigits(std::string_view number) {
  // The digits as one string, and where the separator stood in it (npos: none).
  std::string digits;
  size_t sepAt = std::string_view::npos;
  char sep = 0;
  for (char c : number) {
    if (isDigit(c)) {
      digits.push_back(c);
    } else if (isSep(c) && sep == 0) {
      sep = c;
      sepAt = digits.size();
    } else {
      return std::nullopt; // not a number as the lexer reads them
    }
  }
  size_t intLen = sepAt == std::string_view::npos ? digits.size() : sepAt;
  auto significant = [&] {
    size_t z = digits.find_first_not_of('0');
    return z == std::string::npos ? size_t{0} : digits.size() - z;
  };
  if (significant() <= kDigits) return std::nullopt;
  size_t z = digits.find_first_not_of('0');
  const size_t keep = z + kDigits;
  if (keep < intLen) return std::nullopt; // 1000000000 and above: no 9-digit spelling
  const bool up = digits[keep] >= '5';
  digits.resize(keep);
  if (up) {
    size_t k = digits.size();
    while (k > 0 && digits[k - 1] == '9')
      digits[--k] = '0';
    if (k == 0) {
      digits.insert(digits.begin(), '1');
      ++intLen;
    } else {
      ++digits[k - 1];
    }
    // a carry into a new leading digit leaves ten: the last one is a fraction 0, or none is left
    if (significant() > kDigits) {
      if (digits.size() <= intLen) return std::nullopt;
      digits.pop_back();
    }
  }
  // trailing zeros of the fraction say nothing: drop them (the separator stays)
  while (digits.size() > intLen && digits.back() == '0')
    digits.pop_back();
  std::string out = digits.substr(0, intLen);
  if (sep != 0) {
    out.push_back(sep);
    out += digits.substr(intLen);
  }
  if (significant() > kDigits || out.find_first_of("0123456789") == std::string::npos) return std::nullopt;
  return out;
}

void Lexer::finishNumber(const NumberScan& n, uint32_t line, uint32_t col, bool oneLine, Token& t) {
  t.hasSep = n.sep;
  const size_t significant = n.digits - n.leadZeros;
  if (significant > kDigits) {
    auto& d = diags_.report(Msg::TooManyDigits, Loc{fileId_, line, col}, static_cast<uint32_t>(t.text.size()),
                            printableBytes(t.text), significant, kDigits);
    if (oneLine) // a number split by a `$` join is left to the programmer
      if (auto rounded = roundToNineDigits(t.text)) {
        diag::Loc at{fileId_, line, col};
        d.fixes.push_back({diag::message(Msg::RoundNumberFix, kDigits, *rounded),
                           {{at, at.line, at.col + static_cast<uint32_t>(t.text.size()), *rounded}}});
      }
    t.tooManyDigits = true;
    errorOnLine_ = true;
  }
  if (n.digits <= kExactDigits) { // exact (kPow10)
    t.value = static_cast<double>(n.mantissa) / kPow10[n.fraction];
    return;
  }
  // The text as from_chars reads it: the separator as '.', its first 63 characters.
  char buf[64];
  size_t len = 0;
  for (char ch : t.text) {
    if (len == sizeof(buf) - 1) break;
    buf[len++] = isSep(ch) ? '.' : ch;
  }
  double v = 0;
  std::from_chars(buf, buf + len, v);
  t.value = v;
}

} // namespace iso::frontend
