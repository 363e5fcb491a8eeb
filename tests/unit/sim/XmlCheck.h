//! @file XmlCheck.h
//! @brief A small well-formedness check for the XML the plot writes (tests only): one root
//!        element, nested tags that match, quoted attributes, the predefined entities, no
//!        control characters. Comments, CDATA, declarations and DOCTYPE are refused as well:
//!        the plot writes none.
#pragma once

#include <cctype>
#include <string>
#include <vector>

namespace iso::test {

/// "" when `doc` is well-formed in that sense, else what is wrong and where.
inline std::string xmlProblem(const std::string& doc) {
  auto at = [](size_t i) { return " at offset " + std::to_string(i); };
  auto isNameChar = [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '-' || c == '_' || c == ':' || c == '.';
  };
  // Character data (text or an attribute value) in [from, to).
  auto badText = [&](size_t from, size_t to) -> std::string {
    for (size_t k = from; k < to; ++k) {
      auto c = static_cast<unsigned char>(doc[k]);
      if (c < 0x20 && c != '\n' && c != '\t' && c != '\r') return "control character" + at(k);
      if (c == '<') return "'<' in character data" + at(k);
      if (c == '&') {
        size_t semi = doc.find(';', k);
        std::string ent = semi == std::string::npos || semi >= to ? "" : doc.substr(k, semi - k + 1);
        if (ent != "&amp;" && ent != "&lt;" && ent != "&gt;" && ent != "&quot;" && ent != "&apos;")
          return "unknown or unterminated entity" + at(k);
      }
    }
    return "";
  };
  std::vector<std::string> open;
  int roots = 0;
  size_t i = 0;
  for (;;) {
    size_t lt = doc.find('<', i);
    size_t textEnd = lt == std::string::npos ? doc.size() : lt;
    if (open.empty()) {
      for (size_t k = i; k < textEnd; ++k)
        if (!std::isspace(static_cast<unsigned char>(doc[k]))) return "text outside the root element" + at(k);
    } else if (std::string why = badText(i, textEnd); !why.empty()) {
      return why;
    }
    if (lt == std::string::npos) break;
    size_t p = lt + 1;
    bool closing = p < doc.size() && doc[p] == '/';
    if (closing) ++p;
    size_t nameStart = p;
    while (p < doc.size() && isNameChar(doc[p]))
      ++p;
    if (p == nameStart) return "a tag without a name" + at(lt);
    std::string name = doc.substr(nameStart, p - nameStart);
    if (closing) {
      while (p < doc.size() && std::isspace(static_cast<unsigned char>(doc[p])))
        ++p;
      if (p >= doc.size() || doc[p] != '>') return "unterminated end tag" + at(lt);
      if (open.empty() || open.back() != name) return "end tag </" + name + "> does not match" + at(lt);
      open.pop_back();
      i = p + 1;
      continue;
    }
    if (open.empty() && ++roots > 1) return "a second root element" + at(lt);
    std::vector<std::string> attrs;
    for (;;) {
      size_t ws = p;
      while (p < doc.size() && std::isspace(static_cast<unsigned char>(doc[p])))
        ++p;
      if (p >= doc.size()) return "unterminated tag <" + name + ">" + at(lt);
      if (doc[p] == '>' || (doc[p] == '/' && p + 1 < doc.size() && doc[p + 1] == '>')) break;
      if (p == ws) return "no space before an attribute" + at(p);
      size_t an = p;
      while (p < doc.size() && isNameChar(doc[p]))
        ++p;
      if (p == an || p + 1 >= doc.size() || doc[p] != '=' || doc[p + 1] != '"') return "malformed attribute" + at(an);
      std::string attr = doc.substr(an, p - an);
      for (const auto& a : attrs)
        if (a == attr) return "attribute " + attr + " twice" + at(an);
      attrs.push_back(attr);
      size_t close = doc.find('"', p + 2);
      if (close == std::string::npos) return "unterminated attribute value" + at(an);
      if (std::string why = badText(p + 2, close); !why.empty()) return why;
      p = close + 1;
    }
    if (doc[p] == '/') {
      i = p + 2;
    } else {
      open.push_back(name);
      i = p + 1;
    }
  }
  if (!open.empty()) return "<" + open.back() + "> is not closed";
  if (roots != 1) return "no root element";
  return "";
}

} // namespace iso::test
