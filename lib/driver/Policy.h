//! @file Policy.h
//! @brief The lint policy of a program set, one for every front end: the settings file found
//!        for it (or --config), its machine file and dialect, the rules it disables (per path
//!        too) and its diagnostic limit. isolint and the language server both resolve it here,
//!        so the editor shows a document exactly the diagnostics the command line shows.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "driver/Common.h"
#include "driver/Lint.h"
#include "driver/Settings.h"
#include "machine/Machine.h"

namespace iso::driver {

/// The settings, machines and rules of one run (isolint) or one analysis (the language
/// server). Settings files and machine files are read once per run. The failing calls print
/// the reason to the Io's err stream (as "FILE:LINE: error: ...") and return nullptr.
class LintPolicies {
public:
  /// `common`: --config, --machine, --dialect as given; `disabled`: --disable; `werror`.
  LintPolicies(CommonOptions common, std::vector<diag::Code> disabled, bool werror, Io& io)
      : common_(std::move(common)), disabled_(std::move(disabled)), werror_(werror), io_(io) {}

  /// The settings for `input` (a file or a folder): --config, else the isotools.toml found
  /// from its folder upwards (empty Settings when there is none); nullptr when it is invalid.
  const Settings* settingsFor(const std::string& input);
  /// The machine of a program set under `st`: --machine, else the settings' machine file,
  /// else the built-in machine, with --dialect (else the settings' dialect) applied.
  const machine::Machine* machineFor(const Settings& st);
  /// The filter isolint applies to a set loaded under `st`: --disable, --select, --werror,
  /// inline suppressions, and the settings' disable/enable and per-path rules.
  DiagnosticFilter filterFor(const frontend::ProgramSet& set, const Settings& st) const;
  /// --select: only these rules are shown (none: every rule).
  void select(std::vector<diag::Code> codes) { selected_ = std::move(codes); }
  /// The per-file limit of diagnostics in a format that is not text: --max-diagnostics, else
  /// the settings' max-diagnostics; 0 or less: all.
  long long maxDiagnostics(long long cli, const Settings& st) const {
    return cli >= 0 ? cli : st.maxDiagnostics.value_or(-1);
  }

private:
  CommonOptions common_;
  std::vector<diag::Code> disabled_;
  std::vector<diag::Code> selected_;
  bool werror_ = false;
  Io& io_;
  std::map<std::string, std::unique_ptr<Settings>> settingsByFile_;
  std::map<std::string, std::string> settingsFileByDir_; ///< findSettings once per folder
  std::map<std::pair<std::string, std::string>, std::unique_ptr<machine::Machine>> machines_;
};

} // namespace iso::driver
