//! @file Policy.cpp
//! @brief One lint policy for isolint and the language server: settings, machine, rules.
#include "driver/Policy.h"

#include <filesystem>

namespace iso::driver {

const Settings* LintPolicies::settingsFor(const std::string& input) {
  std::string file = common_.config;
  if (file.empty()) {
    std::error_code ec;
    const std::string dir =
        std::filesystem::is_directory(input, ec) ? input : std::filesystem::path(input).parent_path().string();
    auto [it, inserted] = settingsFileByDir_.emplace(dir, std::string());
    if (inserted) it->second = findSettings(input);
    file = it->second;
  }
  auto [it, inserted] = settingsByFile_.emplace(file, nullptr);
  if (inserted) { // an invalid file stays nullptr: its error is printed once
    auto st = std::make_unique<Settings>();
    CommonOptions c = common_;
    c.config = file;
    if (file.empty() || applySettings(c, input, *st, io_)) it->second = std::move(st);
  }
  return it->second.get();
}

const machine::Machine* LintPolicies::machineFor(const Settings& st) {
  CommonOptions c = common_;
  if (c.machinePath.empty()) c.machinePath = st.machine;
  if (c.dialect.empty()) c.dialect = st.dialect;
  auto& m = machines_[{c.machinePath, c.dialect}];
  if (!m) {
    auto loaded = loadMachine(c, io_);
    if (!loaded) return nullptr;
    m = std::make_unique<machine::Machine>(std::move(*loaded));
  }
  return m.get();
}

DiagnosticFilter LintPolicies::filterFor(const frontend::ProgramSet& set, const Settings& st) const {
  DiagnosticFilter filter{disabled_, werror_, false, nullptr, selected_};
  if (!st.path.empty())
    filter.disabledFor = [&set, &st](uint32_t file, diag::Code code) {
      return st.disabledFor(set.sources.path(file), code);
    };
  return filter;
}

} // namespace iso::driver
