//! @file RuleDocs.cpp
#include "diag/RuleDocs.h"

#include <array>
#include <string_view>
#include <vector>

#include <fmt/format.h>

namespace iso::diag {

namespace {

constexpr std::string_view kRulesRoff =
#include "diag/RuleDocs.inc"
    ;

/// Appends the UTF-8 encoding of code point `cp`.
void appendUtf8(std::string& out, unsigned cp) {
  if (cp < 0x80) {
    out.push_back(static_cast<char>(cp));
  } else if (cp < 0x800) {
    out.push_back(static_cast<char>(0xC0 | (cp >> 6)));
    out.push_back(static_cast<char>(0x80 | (cp & 0x3F)));
  } else {
    out.push_back(static_cast<char>(0xE0 | (cp >> 12)));
    out.push_back(static_cast<char>(0x80 | ((cp >> 6) & 0x3F)));
    out.push_back(static_cast<char>(0x80 | (cp & 0x3F)));
  }
}

/// One line of roff text to plain text (`markdown` false) or Markdown: font changes become
/// backticks (bold) and asterisks (italic), escapes their characters.
std::string fromRoff(std::string_view in, bool markdown) {
  std::string out;
  char font = 'R';
  auto setFont = [&](char f) {
    if (f == 'P') f = 'R';
    if (markdown && f != font) {
      if (font == 'B') out += '`';
      if (font == 'I') out += '*';
      if (f == 'B') out += '`';
      if (f == 'I') out += '*';
    }
    font = f;
  };
  for (size_t i = 0; i < in.size(); ++i) {
    char c = in[i];
    if (c != '\\' || i + 1 >= in.size()) {
      out.push_back(c);
      continue;
    }
    char e = in[++i];
    if (e == 'f' && i + 1 < in.size()) {
      setFont(in[++i]);
    } else if (e == '-' || e == 'e') {
      out.push_back(e == '-' ? '-' : '\\');
    } else if (e == '&') {
    } else if (e == '(' && i + 2 < in.size()) {
      std::string_view n = in.substr(i + 1, 2);
      i += 2;
      if (n == "aq")
        out += '\'';
      else if (n == "dq")
        out += '"';
      else if (n == "rs")
        out += '\\';
      else if (n == "en")
        out += "\xE2\x80\x93";
      else if (n == "em")
        out += "\xE2\x80\x94";
      else if (n == "->")
        out += "\xE2\x86\x92";
      else
        out += n;
    } else if (e == '[') {
      size_t close = in.find(']', i);
      if (close == std::string_view::npos) break;
      std::string_view n = in.substr(i + 1, close - i - 1);
      if (n.size() > 1 && n[0] == 'u')
        appendUtf8(out, static_cast<unsigned>(std::stoul(std::string(n.substr(1)), nullptr, 16)));
      i = close;
    } else {
      out.push_back(e);
    }
  }
  setFont('R');
  return out;
}

std::array<RuleDoc, codeCount()> parse() {
  std::array<RuleDoc, codeCount()> docs{};
  std::vector<std::string_view> lines;
  for (size_t b = 0; b < kRulesRoff.size();) {
    size_t e = kRulesRoff.find('\n', b);
    if (e == std::string_view::npos) e = kRulesRoff.size();
    lines.push_back(kRulesRoff.substr(b, e - b));
    b = e + 1;
  }
  for (size_t i = 0; i + 1 < lines.size(); ++i) {
    if (lines[i] != ".TP") continue;
    std::string heading = fromRoff(lines[i + 1], false); // "E100 syntax"
    auto code = findCode(heading.substr(0, heading.find(' ')));
    if (!code) continue;
    RuleDoc& d = docs[static_cast<size_t>(*code)];
    size_t k = i + 2;
    for (; k < lines.size() && (lines[k].empty() || lines[k][0] != '.' || lines[k].rfind(".BR ", 0) == 0); ++k) {
      std::string_view l = lines[k];
      std::string plain, md;
      if (l.rfind(".BR ", 0) == 0) { // ".BR isosim (1)": the words joined
        std::string_view rest = l.substr(4);
        size_t sp = rest.find(' ');
        std::string word(rest.substr(0, sp)), tail(sp == std::string_view::npos ? "" : rest.substr(sp + 1));
        plain = fromRoff(word, false) + fromRoff(tail, false);
        md = fmt::format("`{}`{}", fromRoff(word, false), fromRoff(tail, false));
      } else {
        plain = fromRoff(l, false);
        md = fromRoff(l, true);
      }
      if (!d.text.empty()) {
        const bool glue = plain.size() > 0 && (plain[0] == ')' || plain[0] == ',' || plain[0] == '.');
        if (!glue) d.text += ' ', d.markdown += ' ';
      }
      d.text += plain;
      d.markdown += md;
    }
    if (k + 1 < lines.size() && lines[k] == ".IP" && lines[k + 1] == ".EX")
      for (size_t j = k + 2; j < lines.size() && lines[j] != ".EE"; ++j) {
        d.example += fromRoff(lines[j], false);
        d.example += '\n';
      }
  }
  return docs;
}

} // namespace

const RuleDoc& ruleDoc(Code code) {
  static const std::array<RuleDoc, codeCount()> docs = parse();
  return docs[static_cast<size_t>(code)];
}

std::string explainRule(Code code) {
  const CodeInfo& ci = info(code);
  const RuleDoc& d = ruleDoc(code);
  std::string out = fmt::format("{} {} ({})\n\n{}\n", ci.code, ci.name, severityName(ci.severity),
                                d.text.empty() ? ci.description : d.text);
  if (!d.example.empty()) {
    out += "\nExample:\n";
    for (size_t b = 0; b < d.example.size();) {
      size_t e = d.example.find('\n', b);
      out += fmt::format("    {}\n", std::string_view(d.example).substr(b, e - b));
      b = e + 1;
    }
  }
  out += fmt::format("\nSilence it with --disable {} (or {}), on one line with '; isolint: disable={}', in a "
                     "file with '; isolint: disable-file={}'. See isolint(1).\n",
                     ci.code, ci.name, ci.code, ci.code);
  return out;
}

std::string ruleHelpMarkdown(Code code) {
  const CodeInfo& ci = info(code);
  const RuleDoc& d = ruleDoc(code);
  std::string out = fmt::format("**{} {}**: {}\n", ci.code, ci.name, d.markdown.empty() ? ci.description : d.markdown);
  if (!d.example.empty()) out += fmt::format("\nExample:\n\n```\n{}```\n", d.example);
  out += fmt::format("\nSilence it on one line with `; isolint: disable={}`, or everywhere with `--disable {}`.\n",
                     ci.code, ci.code);
  return out;
}

} // namespace iso::diag
