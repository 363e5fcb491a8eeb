//! @file CompletionTests.cpp
//! @brief driver/Completion: the completion model of a small CLI11 app, the bash, zsh and fish
//!        scripts made from it, and the hidden --completion option of the tools.
#include <doctest/doctest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "driver/Common.h"
#include "driver/ShellCompletion.h"

using namespace iso::driver;
using Kind = CompletionValue::Kind;

namespace {

struct DemoApp {
  CLI::App app{"demo - a small app for the completion generator", "demo"};
  std::string format, machine, out, dir, secret, entry;
  std::vector<std::string> tags, paths;
  bool verbose = false;
  DemoApp() {
    app.add_option("--format", format, "Output format")->type_name("text|json");
    app.add_option("-m,--machine", machine, "Machine file [JSON]: it's optional")->type_name("FILE");
    app.add_option("-o,--output", out, "Write the image")->type_name("OUT.isob");
    app.add_option("--tag", tags, "Tags, repeatable\nsecond line")->type_name("CODE|NAME");
    app.add_option("--into", dir, "A directory")->type_name("DIR");
    app.add_option("--entry", entry, "Entry name")->type_name("NAME");
    app.add_flag("-v,--verbose", verbose, "Talk more");
    app.add_option("--secret", secret, "Hidden")->group("");
    app.add_option("paths", paths, "Program files (.mpf/.SPF) or directories")->type_name("PATH");
  }
};

const CompletionItem* find(const std::vector<CompletionItem>& items, const std::string& name) {
  for (const auto& i : items)
    for (const auto& n : i.names)
      if (n == name) return &i;
  return nullptr;
}

/// Runs `bash -n` on a script: 0 when it parses.
int bashSyntaxCheck(const std::string& script) {
  static int count = 0; // one file per call and process: the test cases run in parallel
  auto path = std::filesystem::temp_directory_path() / fmt::format("iso-completion-{}-{}.bash", ::getpid(), count++);
  std::ofstream(path) << script;
  int rc = std::system(fmt::format("bash -n {}", path.string()).c_str());
  std::filesystem::remove(path);
  return rc;
}

} // namespace

TEST_CASE("completion: the model of an app follows its options") {
  DemoApp d;
  CompletionModel m = completionModel(d.app);

  const CompletionItem* help = find(m.options, "--help");
  REQUIRE(help != nullptr);
  CHECK(help->names == std::vector<std::string>{"-h", "--help"});
  CHECK(help->value.kind == Kind::None);

  const CompletionItem* format = find(m.options, "--format");
  REQUIRE(format != nullptr);
  CHECK(format->value.kind == Kind::Choices);
  CHECK(format->value.choices == std::vector<std::string>{"text", "json"});
  CHECK_FALSE(format->repeatable);

  const CompletionItem* machine = find(m.options, "--machine");
  REQUIRE(machine != nullptr);
  CHECK(machine->names == std::vector<std::string>{"-m", "--machine"});
  CHECK(machine->value.kind == Kind::Files);
  CHECK(machine->value.extensions.empty());

  const CompletionItem* out = find(m.options, "-o");
  REQUIRE(out != nullptr);
  CHECK(out->value.kind == Kind::Files);
  CHECK(out->value.extensions == std::vector<std::string>{"isob"});

  const CompletionItem* tag = find(m.options, "--tag");
  REQUIRE(tag != nullptr);
  CHECK(tag->value.kind == Kind::Free); // CODE|NAME are metavariables, not choices
  CHECK(tag->repeatable);
  CHECK(tag->description == "Tags, repeatable");

  CHECK(find(m.options, "--into")->value.kind == Kind::Dirs);
  CHECK(find(m.options, "--entry")->value.kind == Kind::Free);
  CHECK(find(m.options, "--verbose")->value.kind == Kind::None);
  CHECK(find(m.options, "--secret") == nullptr); // hidden: group ""

  REQUIRE(m.positionals.size() == 1);
  CHECK(m.positionals[0].names.empty());
  CHECK(m.positionals[0].valueName == "PATH");
  CHECK(m.positionals[0].value.kind == Kind::Files);
  CHECK(m.positionals[0].value.extensions == std::vector<std::string>{"mpf", "spf"});
  CHECK(m.positionals[0].repeatable);
}

TEST_CASE("completion: a type name with a validator's description keeps only the name") {
  CLI::App app{"x", "x"};
  int n = 0;
  app.add_option("--jobs", n, "Threads")->type_name("N")->check(CLI::Range(1, 8));
  CompletionModel m = completionModel(app);
  REQUIRE(find(m.options, "--jobs") != nullptr);
  CHECK(find(m.options, "--jobs")->valueName == "N");
  CHECK(find(m.options, "--jobs")->value.kind == Kind::Free);
}

TEST_CASE("completion: bash script") {
  DemoApp d;
  std::string s = completionScript(d.app, "demo", Shell::Bash);
  CHECK(s.find("complete -F _demo demo\n") != std::string::npos);
  CHECK(s.find("        --format)\n            COMPREPLY=($(compgen -W 'text json' -- \"$cur\")) ;;") !=
        std::string::npos);
  CHECK(s.find("        -m|--machine)\n            _demo_files '' \"$cur\" -f ;;") != std::string::npos);
  CHECK(s.find("        -o|--output)\n            _demo_files 'isob' \"$cur\" -f ;;") != std::string::npos);
  CHECK(s.find("        --into)\n            _demo_files '' \"$cur\" -d ;;") != std::string::npos);
  CHECK(s.find("        --tag)\n            : ;;") != std::string::npos);
  CHECK(s.find("compgen -W '-h --help --format -m --machine -o --output --tag --into --entry -v --verbose'") !=
        std::string::npos);
  CHECK(s.find("_demo_files 'mpf spf' \"$cur\" -f") != std::string::npos);
  CHECK(s.find("secret") == std::string::npos);
  CHECK(bashSyntaxCheck(s) == 0);
}

TEST_CASE("completion: bash counts positional arguments when they complete differently") {
  CLI::App app{"two", "tool-2"};
  std::string kind, file;
  int level = 0;
  app.add_option("--level", level, "Level")->type_name("N");
  app.add_option("kind", kind, "Kind")->type_name("alpha|beta");
  app.add_option("file", file, "The file (.txt)")->type_name("FILE");
  std::string s = completionScript(app, "tool-2", Shell::Bash);
  CHECK(s.find("_tool_2()") != std::string::npos);
  CHECK(s.find("complete -F _tool_2 tool-2\n") != std::string::npos);
  CHECK(s.find("--level) [[ ${COMP_WORDS[i+1]} == = ]] && (( i++ )); (( i++ )) ;;") != std::string::npos);
  CHECK(s.find("0) COMPREPLY=($(compgen -W 'alpha beta' -- \"$cur\")) ;;") != std::string::npos);
  CHECK(s.find("*) _tool_2_files 'txt' \"$cur\" -f ;;") != std::string::npos);
  CHECK(bashSyntaxCheck(s) == 0);
}

TEST_CASE("completion: zsh script") {
  DemoApp d;
  std::string s = completionScript(d.app, "demo", Shell::Zsh);
  CHECK(s.rfind("#compdef demo\n", 0) == 0);
  CHECK(s.find("--format='[Output format]:text|json:(text json)'") != std::string::npos);
  // [ ] : are escaped for _arguments, ' for the shell.
  CHECK(s.find("'(-m --machine)'{-m+,--machine=}'[Machine file \\[JSON\\]\\: it'\\''s optional]:FILE:_files'") !=
        std::string::npos);
  CHECK(s.find("'*'--tag='[Tags, repeatable]:CODE|NAME: '") != std::string::npos);
  CHECK(s.find("--into='[A directory]:DIR:_files -/'") != std::string::npos);
  CHECK(s.find("'(-v --verbose)'{-v,--verbose}'[Talk more]'") != std::string::npos);
  CHECK(s.find("'*:PATH:_files -g \"*.(mpf|MPF|spf|SPF)\"'") != std::string::npos);
  CHECK(s.find("compdef _demo demo") != std::string::npos);
  CHECK(s.find("secret") == std::string::npos);
}

TEST_CASE("completion: fish script") {
  DemoApp d;
  std::string s = completionScript(d.app, "demo", Shell::Fish);
  CHECK(s.find("complete -c demo -l format -x -a 'text json' -d 'Output format'\n") != std::string::npos);
  CHECK(s.find("complete -c demo -s m -l machine -r -d 'Machine file [JSON]: it\\'s optional'\n") != std::string::npos);
  CHECK(s.find("complete -c demo -l tag -x -d 'Tags, repeatable'\n") != std::string::npos);
  CHECK(s.find("complete -c demo -l into -x -a '(__fish_complete_directories)'") != std::string::npos);
  CHECK(s.find("complete -c demo -s v -l verbose -d 'Talk more'\n") != std::string::npos);
  CHECK(s.find("complete -c demo -f\n") == std::string::npos); // positional files: fish's default
  CHECK(s.find("secret") == std::string::npos);
}

TEST_CASE("completion: the hidden --completion option of the tools") {
  CHECK(parseShell("bash") == Shell::Bash);
  CHECK(parseShell("zsh") == Shell::Zsh);
  CHECK(parseShell("fish") == Shell::Fish);
  CHECK_FALSE(parseShell("tcsh").has_value());

  auto run = [](std::vector<std::string> args, std::string& out, std::string& err) {
    CLI::App app{"tool", "tool"};
    CommonOptions opts;
    addCommonOptions(app, opts, "tool");
    std::vector<char*> argv;
    for (auto& a : args)
      argv.push_back(a.data());
    std::ostringstream o, e;
    Io io{o, e};
    int rc = parseCommandLine(app, static_cast<int>(argv.size()), argv.data(), io, "tool");
    out = o.str();
    err = e.str();
    return rc;
  };
  std::string out, err;
  CHECK(run({"tool", "--completion", "fish"}, out, err) == 0);
  CHECK(out.find("complete -c tool -l dialect -x -a 'sidac z32'") != std::string::npos);
  CHECK(out.find("completion") != std::string::npos); // only in the header comment
  CHECK(out.find("-l completion") == std::string::npos);
  CHECK(run({"tool", "--completion", "tcsh"}, out, err) == kExitUsage);
  CHECK(err == "tool: error: --completion: tcsh is not bash, zsh or fish (run 'tool --help')\n");
  CHECK(run({"tool", "--completion"}, out, err) == kExitUsage);
  CHECK(err == "tool: error: --completion needs a shell: bash, zsh or fish (run 'tool --help')\n");
  CHECK(run({"tool", "--completion", "zsh", "--completion=bash"}, out, err) == 0);
  CHECK(out.find("complete -F _tool tool") != std::string::npos);
  CHECK(run({"tool", "--help"}, out, err) == 0);
  CHECK(out.find("--completion") == std::string::npos);
  CHECK(run({"tool", "--color", "never"}, out, err) == -1);
}
