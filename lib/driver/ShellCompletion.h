//! @file ShellCompletion.h
//! @brief Shell completion scripts (bash, zsh, fish) generated from a tool's CLI11 definition, so
//! that the completions cannot drift from the options they complete.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace CLI {
class App;
} // namespace CLI

namespace iso::driver {

struct Io;

enum class Shell { Bash, Zsh, Fish };

/// "bash", "zsh", "fish" -> Shell; anything else -> nullopt.
std::optional<Shell> parseShell(std::string_view name);

/// What the value of an option (or a positional argument) completes to.
struct CompletionValue {
  enum class Kind {
    None,    ///< a flag: no value
    Free,    ///< a value that cannot be completed (N, S, CODE|NAME)
    Choices, ///< one of `choices` (type name "a|b|c" of lowercase words)
    Files,   ///< file names (and directories to get there); only `extensions` when not empty
    Dirs,    ///< directory names
  };
  Kind kind = Kind::None;
  std::vector<std::string> choices;    ///< Kind::Choices
  std::vector<std::string> extensions; ///< Kind::Files: without the dot, lower case ("mpf")
};

/// One option or positional argument as the completions see it.
struct CompletionItem {
  std::vector<std::string> names; ///< "-j", "--jobs"; empty for a positional argument
  std::string description;        ///< first line of the option's description
  std::string valueName;          ///< "FILE", "text|json|sarif", "PATH"; "" for a flag
  CompletionValue value;
  bool repeatable = false; ///< may be given more than once (a vector option)
};

/// The completion model of an app: its visible options (those in a help group; the hidden ones,
/// group "", are left out) and its positional arguments, in the order they were added.
/// Value kinds come from the type names: a type name of lowercase alternatives ("text|json|sarif",
/// "hex") lists the choices; FILE, PATH, IMAGE, PROGRAM and NAME.ext name files (PATH and PROGRAM
/// also directories), DIR directories; positional arguments without such a name complete files.
/// File extensions come from a parenthesised list in the description: "Program files (.mpf/.spf)".
struct CompletionModel {
  std::vector<CompletionItem> options;
  std::vector<CompletionItem> positionals;
};
CompletionModel completionModel(const CLI::App& app);

/// The completion script of `tool` for `shell`: bash (a function _TOOL registered with
/// `complete -F`), zsh (an #compdef _arguments function), fish (`complete -c` lines).
std::string completionScript(const CLI::App& app, const std::string& tool, Shell shell);

/// Adds the hidden option `--completion bash|zsh|fish` (group "": not in --help). After a
/// successful parse, parseCommandLine prints the script and the tool exits 0. Call it before
/// adding other options (addCommonOptions does): then --help looks as it did without it.
void addCompletionOption(CLI::App& app);

/// After parsing: if `--completion SHELL` was given, writes the script of `tool` to io.out and
/// returns kExitOk, or for a missing or unknown SHELL prints a usage error and returns
/// kExitUsage; else returns -1.
int handleCompletionOption(const CLI::App& app, const char* tool, Io& io);

} // namespace iso::driver
