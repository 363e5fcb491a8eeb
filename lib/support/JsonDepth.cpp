//! @file JsonDepth.cpp
//! @brief The nesting depth of JSON text by one scan.
#include "support/JsonDepth.h"

namespace iso::support {

bool jsonNestingWithin(std::string_view text, unsigned maxDepth) {
  unsigned depth = 0;
  bool inString = false;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (inString) {
      if (c == '\\')
        ++i; // the escaped character, whatever it is, cannot end the string
      else if (c == '"')
        inString = false;
      continue;
    }
    switch (c) {
    case '"': inString = true; break;
    case '[':
    case '{':
      if (++depth > maxDepth) return false;
      break;
    case ']':
    case '}':
      if (depth > 0) --depth;
      break;
    default: break;
    }
  }
  return true;
}

} // namespace iso::support
