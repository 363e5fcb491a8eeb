//! @file ShellCompletion.cpp
//! @brief Shell completion scripts generated from the CLI11 definition of a tool.
#include "driver/ShellCompletion.h"

#include "driver/Common.h"
#include "support/CaseFold.h"

#include <algorithm>
#include <cctype>
#include <ostream>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

namespace iso::driver {

std::optional<Shell> parseShell(std::string_view name) {
  if (name == "bash") return Shell::Bash;
  if (name == "zsh") return Shell::Zsh;
  if (name == "fish") return Shell::Fish;
  return std::nullopt;
}

namespace {

using Kind = CompletionValue::Kind;

std::vector<std::string> split(std::string_view s, char sep) {
  std::vector<std::string> parts;
  size_t b = 0;
  for (size_t e; (e = s.find(sep, b)) != std::string_view::npos; b = e + 1)
    parts.emplace_back(s.substr(b, e - b));
  parts.emplace_back(s.substr(b));
  return parts;
}

/// A literal word of a type name: "text", "z32", "sarif" (metavariables are upper case).
bool isLiteralWord(std::string_view w) {
  if (w.empty() || !(std::islower(static_cast<unsigned char>(w[0])) || std::isdigit(static_cast<unsigned char>(w[0]))))
    return false;
  return std::all_of(w.begin(), w.end(), [](char c) {
    auto u = static_cast<unsigned char>(c);
    return std::islower(u) || std::isdigit(u) || c == '-' || c == '_';
  });
}

bool isAlnumWord(std::string_view w) {
  return !w.empty() &&
         std::all_of(w.begin(), w.end(), [](char c) { return std::isalnum(static_cast<unsigned char>(c)); });
}

/// Extensions listed in a description as "(.mpf/.spf)": {"mpf", "spf"}.
std::vector<std::string> extensionsIn(std::string_view description) {
  for (size_t open = description.find("(."); open != std::string_view::npos; open = description.find("(.", open + 1)) {
    size_t close = description.find(')', open);
    if (close == std::string_view::npos) break;
    std::vector<std::string> exts;
    bool ok = true;
    for (const auto& part : split(description.substr(open + 1, close - open - 1), '/')) {
      ok = part.size() > 1 && part[0] == '.' && isAlnumWord(std::string_view(part).substr(1));
      if (!ok) break;
      exts.push_back(support::lowerCopy(part.substr(1)));
    }
    if (ok) return exts;
  }
  return {};
}

CompletionValue classify(const std::string& valueName, const std::string& description, bool positional) {
  CompletionValue v;
  std::string base = valueName;
  if (base.size() > 3 && base.compare(base.size() - 3, 3, "...") == 0) base.resize(base.size() - 3);
  auto alternatives = split(base, '|');
  if (std::all_of(alternatives.begin(), alternatives.end(), isLiteralWord)) {
    v.kind = Kind::Choices;
    v.choices = std::move(alternatives);
    return v;
  }
  if (base == "DIR") {
    v.kind = Kind::Dirs;
    return v;
  }
  size_t dot = base.rfind('.');
  if (dot != std::string::npos && dot > 0 && isAlnumWord(std::string_view(base).substr(dot + 1))) {
    v.kind = Kind::Files; // OUT.isob
    v.extensions.push_back(support::lowerCopy(base.substr(dot + 1)));
    return v;
  }
  if (base == "FILE" || base == "PATH" || base == "IMAGE" || base == "PROGRAM" || positional) {
    v.kind = Kind::Files;
    v.extensions = extensionsIn(description);
    return v;
  }
  v.kind = Kind::Free;
  return v;
}

bool sameValue(const CompletionValue& a, const CompletionValue& b) {
  return a.kind == b.kind && a.choices == b.choices && a.extensions == b.extensions;
}

/// A shell function name made from the tool name.
std::string identifier(const std::string& tool) {
  std::string id = tool;
  for (char& c : id)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return id;
}

std::string joined(const std::vector<std::string>& words, std::string_view sep) {
  std::string s;
  for (const auto& w : words) {
    if (!s.empty()) s += sep;
    s += w;
  }
  return s;
}

/// Text inside single quotes for bash and zsh: ' becomes '\''.
std::string shQuoted(std::string_view s) {
  std::string q = "'";
  for (char c : s) {
    if (c == '\'')
      q += "'\\''";
    else
      q += c;
  }
  q += '\'';
  return q;
}

// --- bash -------------------------------------------------------------------------------------

std::string bashAction(const CompletionValue& v, const std::string& id) {
  switch (v.kind) {
  case Kind::Choices: return fmt::format("COMPREPLY=($(compgen -W '{}' -- \"$cur\"))", joined(v.choices, " "));
  case Kind::Files: return fmt::format("_{}_files '{}' \"$cur\" -f", id, joined(v.extensions, " "));
  case Kind::Dirs: return fmt::format("_{}_files '' \"$cur\" -d", id);
  case Kind::None:
  case Kind::Free: break;
  }
  return ":";
}

std::string bashScript(const CompletionModel& m, const std::string& tool) {
  const std::string id = identifier(tool);
  std::vector<std::string> all, valued;
  for (const auto& o : m.options) {
    all.insert(all.end(), o.names.begin(), o.names.end());
    if (o.value.kind != Kind::None) valued.insert(valued.end(), o.names.begin(), o.names.end());
  }
  std::string s = fmt::format(R"(# bash completion for {0}; generated by `{0} --completion bash` from its options.

# _{1}_files EXTS WORD -f|-d: the files (-f) whose extension, in any case, is one of EXTS ("" is
# any), and the directories, that start with WORD; -d: the directories only.
_{1}_files() {{
    local f ext
    compopt -o filenames 2>/dev/null
    while IFS= read -r f; do
        ext=${{f##*.}}
        if [[ -d $f || ( $3 == -f && ( -z $1 || ( $f == *.* && " $1 " == *" ${{ext,,}} "* ) ) ) ]]; then
            COMPREPLY+=("$f")
        fi
    done < <(compgen "$3" -- "$2")
}}

_{1}() {{
    local cur=${{COMP_WORDS[COMP_CWORD]}} prev= pre=
    (( COMP_CWORD > 0 )) && prev=${{COMP_WORDS[COMP_CWORD-1]}}
    COMPREPLY=()
    # --option=value is one word, or three (--option = value) when = breaks words.
    if [[ $cur == --*=* ]]; then
        prev=${{cur%%=*}} pre=${{cur%%=*}}= cur=${{cur#*=}}
    elif [[ $cur == = && $prev == --* ]]; then
        cur=
    elif [[ $prev == = ]] && (( COMP_CWORD > 1 )); then
        prev=${{COMP_WORDS[COMP_CWORD-2]}}
    fi
    case $prev in
)",
                              tool, id);
  for (const auto& o : m.options) {
    if (o.value.kind == Kind::None) continue;
    s += fmt::format("        {})\n            {} ;;\n", joined(o.names, "|"), bashAction(o.value, id));
  }
  s += "        *)\n";
  s += fmt::format("            if [[ $cur == -* ]]; then\n"
                   "                COMPREPLY=($(compgen -W '{}' -- \"$cur\"))\n",
                   joined(all, " "));
  bool oneKind = std::all_of(m.positionals.begin(), m.positionals.end(),
                             [&](const CompletionItem& p) { return sameValue(p.value, m.positionals[0].value); });
  if (m.positionals.empty()) {
    s += "            fi ;;\n";
  } else if (oneKind) {
    s += fmt::format("            else\n                {}\n            fi ;;\n",
                     bashAction(m.positionals[0].value, id));
  } else {
    // Which positional argument: count the words before, skipping options and their values.
    s += "            else\n"
         "                local i n=0\n"
         "                for (( i = 1; i < COMP_CWORD; i++ )); do\n"
         "                    case ${COMP_WORDS[i]} in\n";
    if (!valued.empty())
      s += fmt::format("                        {}) [[ ${{COMP_WORDS[i+1]}} == = ]] && (( i++ )); (( i++ )) ;;\n",
                       joined(valued, "|"));
    s += "                        -*) ;;\n"
         "                        *) (( n++ )) ;;\n"
         "                    esac\n"
         "                done\n"
         "                case $n in\n";
    for (size_t i = 0; i < m.positionals.size(); ++i) {
      bool last = i + 1 == m.positionals.size();
      bool rest = last || m.positionals[i].repeatable; // a repeatable one takes the rest
      s += fmt::format("                    {}) {} ;;\n", rest ? std::string("*") : std::to_string(i),
                       bashAction(m.positionals[i].value, id));
      if (rest) break;
    }
    s += "                esac\n"
         "            fi ;;\n";
  }
  s += "    esac\n"
       "    if [[ -n $pre ]]; then COMPREPLY=(\"${COMPREPLY[@]/#/$pre}\"); fi\n"
       "    return 0\n"
       "}\n";
  s += fmt::format("complete -F _{} {}\n", id, tool);
  return s;
}

// --- zsh --------------------------------------------------------------------------------------

/// Text for an _arguments description or message: \ [ ] : are escaped for _arguments.
std::string zshText(std::string_view s) {
  std::string e;
  for (char c : s) {
    if (c == '\\' || c == '[' || c == ']' || c == ':') e += '\\';
    e += c;
  }
  return e;
}

std::string zshAction(const CompletionValue& v) {
  switch (v.kind) {
  case Kind::Choices: return fmt::format("({})", joined(v.choices, " "));
  case Kind::Files: {
    if (v.extensions.empty()) return "_files";
    std::vector<std::string> both;
    for (const auto& e : v.extensions) {
      both.push_back(e);
      const std::string up = support::upperCopy(e);
      if (up != e) both.push_back(up);
    }
    return fmt::format("_files -g \"*.({})\"", joined(both, "|"));
  }
  case Kind::Dirs: return "_files -/";
  case Kind::None:
  case Kind::Free: break;
  }
  return " ";
}

std::string zshScript(const CompletionModel& m, const std::string& tool) {
  const std::string id = identifier(tool);
  std::string s = fmt::format("#compdef {0}\n"
                              "# zsh completion for {0}; generated by `{0} --completion zsh` from its options.\n"
                              "\n"
                              "_{1}() {{\n"
                              "  _arguments -S",
                              tool, id);
  for (const auto& o : m.options) {
    bool valued = o.value.kind != Kind::None;
    std::vector<std::string> forms;
    for (const auto& n : o.names)
      forms.push_back(valued ? n + (n.size() == 2 ? "+" : "=") : n);
    std::string spec;
    if (o.repeatable)
      spec = "'*'";
    else if (o.names.size() > 1)
      spec = fmt::format("'({})'", joined(o.names, " "));
    spec += forms.size() > 1 ? fmt::format("{{{}}}", joined(forms, ",")) : forms[0];
    std::string rest = fmt::format("[{}]", zshText(o.description));
    if (valued) rest += fmt::format(":{}:{}", zshText(o.valueName), zshAction(o.value));
    spec += shQuoted(rest);
    s += fmt::format(" \\\n    {}", spec);
  }
  for (const auto& p : m.positionals) {
    s += fmt::format(" \\\n    {}", shQuoted(fmt::format("{}:{}:{}", p.repeatable ? "*" : "", zshText(p.valueName),
                                                         zshAction(p.value))));
    if (p.repeatable) break;
  }
  s += fmt::format("\n}}\n\n"
                   "if [[ $funcstack[1] == _{0} ]]; then\n"
                   "  _{0} \"$@\"\n"
                   "else\n"
                   "  compdef _{0} {1}\n"
                   "fi\n",
                   id, tool);
  return s;
}

// --- fish -------------------------------------------------------------------------------------

std::string fishQuoted(std::string_view s) {
  std::string q = "'";
  for (char c : s) {
    if (c == '\\' || c == '\'') q += '\\';
    q += c;
  }
  q += '\'';
  return q;
}

std::string fishScript(const CompletionModel& m, const std::string& tool) {
  std::string s =
      fmt::format("# fish completion for {0}; generated by `{0} --completion fish` from its options.\n", tool);
  // Positional arguments: fish completes file names unless told not to.
  bool filesForArguments = std::any_of(m.positionals.begin(), m.positionals.end(), [](const CompletionItem& p) {
    return p.value.kind == Kind::Files || p.value.kind == Kind::Dirs;
  });
  if (!filesForArguments) s += fmt::format("complete -c {} -f\n", tool);
  for (const auto& p : m.positionals)
    if (p.value.kind == Kind::Choices)
      s += fmt::format("complete -c {} -a {}\n", tool, fishQuoted(joined(p.value.choices, " ")));
  for (const auto& o : m.options) {
    std::string line = fmt::format("complete -c {}", tool);
    for (const auto& n : o.names) {
      if (n.size() == 2)
        line += fmt::format(" -s {}", n.substr(1));
      else if (n.size() > 2)
        line += fmt::format(" -l {}", n.substr(2));
    }
    switch (o.value.kind) {
    case Kind::None: break;
    case Kind::Free: line += " -x"; break;
    case Kind::Choices: line += fmt::format(" -x -a {}", fishQuoted(joined(o.value.choices, " "))); break;
    case Kind::Files: line += " -r"; break;
    case Kind::Dirs: line += " -x -a '(__fish_complete_directories)'"; break;
    }
    if (!o.description.empty()) line += fmt::format(" -d {}", fishQuoted(o.description));
    s += line;
    s += '\n';
  }
  return s;
}

} // namespace

CompletionModel completionModel(const CLI::App& app) {
  CompletionModel m;
  for (const CLI::Option* opt : app.get_options()) {
    if (opt->get_group().empty()) continue; // hidden
    CompletionItem item;
    for (const auto& n : opt->get_snames())
      item.names.push_back(fmt::format("-{}", n));
    for (const auto& n : opt->get_lnames())
      item.names.push_back(fmt::format("--{}", n));
    const std::string& d = opt->get_description();
    item.description = d.substr(0, d.find('\n'));
    bool positional = !opt->nonpositional();
    if (positional || opt->get_expected_max() > 0) { // flags expect no value
      std::string t = opt->get_type_name();          // "N:validator description" -> "N"
      item.valueName = t.substr(0, t.find(':'));
      item.value = classify(item.valueName, item.description, positional);
      item.repeatable = opt->get_expected_max() > 1;
    }
    (positional ? m.positionals : m.options).push_back(std::move(item));
  }
  return m;
}

std::string completionScript(const CLI::App& app, const std::string& tool, Shell shell) {
  CompletionModel m = completionModel(app);
  switch (shell) {
  case Shell::Bash: return bashScript(m, tool);
  case Shell::Zsh: return zshScript(m, tool);
  case Shell::Fish: return fishScript(m, tool);
  }
  return {};
}

void addCompletionOption(CLI::App& app) {
  // CLI11 2.1 ends --help with an extra blank line when the hidden group "" is the last group
  // of options; it is not when the hidden option comes first. So the help flag is taken away,
  // the hidden option added and the help flag added again, with its names and description.
  const CLI::Option* help = app.get_help_ptr();
  std::string helpNames = help != nullptr ? help->get_name(false, true) : std::string();
  std::string helpDescription = help != nullptr ? help->get_description() : std::string();
  if (help != nullptr) app.set_help_flag();
  // CLI11 leaves the names of hidden options out of its error messages, so the shell is checked
  // by handleCompletionOption, and a missing one too (the value is optional here).
  app.add_option("--completion")
      ->description("Print the shell completion script for bash, zsh or fish and exit")
      ->type_name("bash|zsh|fish")
      ->expected(0, 1)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast)
      ->group("");
  if (!helpNames.empty()) app.set_help_flag(helpNames, helpDescription);
}

int handleCompletionOption(const CLI::App& app, const char* tool, Io& io) {
  const CLI::Option* opt = app.get_option_no_throw("--completion");
  if (opt == nullptr || opt->count() == 0) return -1;
  const CLI::results_t& values = opt->results();
  std::string name = values.empty() ? std::string() : values.back();
  if (name.empty()) return usageError(io, tool, "--completion needs a shell: bash, zsh or fish");
  auto shell = parseShell(name);
  if (!shell) return usageError(io, tool, fmt::format("--completion: {} is not bash, zsh or fish", name));
  io.out << completionScript(app, tool, *shell);
  return kExitOk;
}

} // namespace iso::driver
