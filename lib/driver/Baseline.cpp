//! @file Baseline.cpp
//! @brief isolint --baseline: reading, writing and applying the file of known findings.
#include "driver/Baseline.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "diag/Render.h"
#include "support/File.h"
#include "support/Text.h"

namespace iso::driver {

namespace {
constexpr int kBaselineVersion = 1;
} // namespace

support::Expected<Baseline> readBaseline(const std::string& path) {
  auto text = support::readFile(path);
  if (!text) return text.error();
  nlohmann::json doc;
  try {
    doc = nlohmann::json::parse(*text);
  } catch (const nlohmann::json::parse_error& e) {
    return support::Error{fmt::format("{}:byte {}", path, e.byte), "not a baseline file: it is not JSON"};
  }
  auto bad = [&](const std::string& why) { return support::Error{path, "not an isolint baseline: " + why}; };
  if (!doc.is_object() || !doc.contains("isolint_baseline") || !doc["isolint_baseline"].is_number_integer())
    return bad("no \"isolint_baseline\" version (write one with --baseline NEW_FILE)");
  if (doc["isolint_baseline"].get<long long>() != kBaselineVersion)
    return bad(
        fmt::format("version {} (this isolint reads version {})", doc["isolint_baseline"].dump(), kBaselineVersion));
  if (!doc.contains("findings") || !doc["findings"].is_array()) return bad("no \"findings\" list");
  Baseline b;
  size_t i = 0;
  for (const auto& f : doc["findings"]) {
    auto str = [&](const char* key) -> const std::string* {
      return f.is_object() && f.contains(key) && f[key].is_string() ? f[key].get_ptr<const std::string*>() : nullptr;
    };
    const std::string *file = str("file"), *code = str("code"), *fp = str("fingerprint");
    if (!file || !code || !fp) return bad(fmt::format("finding {} lacks a \"file\", \"code\" or \"fingerprint\"", i));
    b.known.emplace(*file, *code, *fp);
    ++i;
  }
  return b;
}

std::string baselineText(const std::vector<diag::Diagnostic>& diags, const diag::SourceManager& sm) {
  const auto fps = diag::findingFingerprints(diags, sm);
  nlohmann::ordered_json doc;
  doc["isolint_baseline"] = kBaselineVersion;
  auto findings = nlohmann::ordered_json::array();
  for (size_t i = 0; i < diags.size(); ++i) {
    const auto& d = diags[i];
    nlohmann::ordered_json f;
    f["file"] = sm.path(d.loc.file);
    f["line"] = d.loc.line;
    f["code"] = diag::info(d.code).code;
    f["message"] = support::toValidUtf8(d.message);
    f["fingerprint"] = fps[i];
    findings.push_back(std::move(f));
  }
  doc["findings"] = std::move(findings);
  return doc.dump(2) + "\n";
}

size_t applyBaseline(std::vector<diag::Diagnostic>& diags, const diag::SourceManager& sm, const Baseline& baseline) {
  const auto fps = diag::findingFingerprints(diags, sm);
  size_t out = 0;
  for (size_t i = 0; i < diags.size(); ++i) {
    if (baseline.known.count({sm.path(diags[i].loc.file), std::string(diag::info(diags[i].code).code), fps[i]}))
      continue;
    if (out != i) diags[out] = std::move(diags[i]);
    ++out;
  }
  const size_t dropped = diags.size() - out;
  diags.resize(out);
  return dropped;
}

} // namespace iso::driver
