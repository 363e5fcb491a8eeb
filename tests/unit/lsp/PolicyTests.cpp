//! @file PolicyTests.cpp
//! @brief The language server lints each folder under the policy isolint applies to it: the
//!        settings file found for the folder (or --config), its machine file and dialect, its
//!        disable/enable and per-path rules, max-diagnostics. The editor's diagnostics of a
//!        document equal the command line's JSON for that file.
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include "LspTestUtil.h"
#include "driver/Lint.h"

using namespace iso;
using namespace iso::test;

namespace {

/// One diagnostic as both front ends can state it: code, 1-based line and column, severity,
/// message.
std::vector<std::string> cliDiagnostics(const std::string& path, const driver::CommonOptions& common,
                                        std::vector<std::string> disable = {}) {
  driver::LintOptions o;
  o.common = common;
  o.paths = {path};
  o.format = "json";
  o.disable = std::move(disable);
  std::ostringstream out, err;
  driver::Io io{out, err, false, false};
  driver::runLint(o, io);
  INFO(err.str());
  std::vector<std::string> rows;
  const json report = json::parse(out.str());
  for (const auto& d : report["diagnostics"])
    rows.push_back(fmt::format("{} {}:{} {} {}", d["code"].get<std::string>(), d["line"].get<int>(),
                               d["column"].get<int>(), d["severity"].get<std::string>(),
                               d["message"].get<std::string>()));
  return rows;
}

std::vector<std::string> editorDiagnostics(const json& published) {
  static const char* kSeverity[] = {"", "error", "warning", "info", "hint"};
  std::vector<std::string> rows;
  for (const auto& d : published["diagnostics"])
    rows.push_back(fmt::format("{} {}:{} {} {}", d["code"].get<std::string>(),
                               d["range"]["start"]["line"].get<int>() + 1,
                               d["range"]["start"]["character"].get<int>() + 1, kSeverity[d["severity"].get<int>()],
                               d["message"].get<std::string>()));
  return rows;
}

/// The diagnostics the server publishes last for `path`, opened as it is on disk.
std::vector<std::string> editorOf(const std::string& path, const driver::CommonOptions* policy,
                                  std::vector<diag::Code> disabled = {}) {
  const std::string uri = lsp::pathToUri(path);
  Session s = runSession(initialize() + didOpen(uri, test::readFileBytes(path)) + shutdownExit(), std::move(disabled),
                         {}, policy);
  auto pub = s.published(uri);
  REQUIRE(!pub.empty());
  return editorDiagnostics(pub.back());
}

} // namespace

TEST_CASE("lsp policy: the z32 sample shows in the editor what isolint shows, through its isotools.toml") {
  const std::string path = std::string(ISO_SOURCE_DIR) + "/samples/z32_toolchange/fresatura_flangia.mpf";
  driver::CommonOptions common;
  const auto cli = cliDiagnostics(path, common);
  CHECK(editorOf(path, &common) == cli);
  // without the policy the folder's machine file (dialect z32, special M6) is not read
  CHECK(editorOf(path, nullptr) != cli);
}
