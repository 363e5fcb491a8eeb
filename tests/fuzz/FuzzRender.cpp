//! @file FuzzRender.cpp
//! @brief Fuzz target: source text -> frontend -> every diagnostic rendered as text, JSON and
//!        SARIF (isolint --format text|json|sarif). Each output must be valid UTF-8; the text
//!        must hold no control byte but LF and TAB (ESC too when coloured); JSON and SARIF must
//!        parse back (nlohmann) with one entry per diagnostic and the right counts.
//!
//! Input format: as FuzzSource (its corpus is a good seed): the first byte picks the variant
//! (bit 0: dialect sidac/z32; bit 1: .mpf/.spf; bits 2-3: the file name, plain, with a space
//! and a `%`, with a Latin-1 byte (not UTF-8) or with a UTF-8 letter; bits 4-5: the output,
//! 0 text, 1 JSON, 2 SARIF, 3 all three; bit 6: colours in the text); the rest is the file's
//! text. One output per input (most of the time) keeps the target fast. SARIF is validated with nlohmann's accept (no
//! tree), the results counted by text; its rule table (76 KB, the same for every input) only with the first input. The
//! first 8 diagnostics of an input are rendered (FuzzSource's text output stops at 12): every renderer treats each
//! alike.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "Support.h"
#include "diag/Render.h"
#include "frontend/ProgramSet.h"
#include "machine/Machine.h"
#include "support/Text.h"

namespace {

[[noreturn]] void fail(const char* what, const std::string& detail = {}) {
  iso::fuzz::fail("FuzzRender", what, detail);
}

constexpr size_t kMaxDiagnostics = 8;

constexpr const char* kStems[] = {"fuzz", "dir with space/50% off", "caf\xE8", "pi\303\250ce"};

void checkText(std::string_view text, bool color) {
  if (!iso::support::isValidUtf8(text)) fail("text output is not valid UTF-8");
  for (unsigned char c : text)
    if ((c < 0x20 && c != '\n' && c != '\t' && !(color && c == 0x1B)) || c == 0x7F)
      fail("text output holds a control byte");
}

nlohmann::json parseBack(const std::string& s, const char* format) {
  if (!iso::support::isValidUtf8(s)) fail("output is not valid UTF-8: ", format);
  nlohmann::json j = nlohmann::json::parse(s, nullptr, false);
  if (j.is_discarded() || !j.is_object()) fail("output does not parse as a JSON object: ", format);
  return j;
}

void renderTextOutputs(const std::vector<iso::diag::Diagnostic>& diags, const iso::frontend::ProgramSet& set,
                       bool color) {
  checkText(iso::diag::renderText(diags, set.sources, color), color);
  {
    std::ostringstream os;
    iso::diag::TextRenderer limited(os, set.sources, false, 3); // the "N more diagnostics" line
    for (const auto& d : diags)
      limited.add(d);
    limited.finish();
    checkText(os.str(), false);
  }
}

void renderJsonOutput(const std::vector<iso::diag::Diagnostic>& diags, const iso::frontend::ProgramSet& set,
                      const iso::diag::Counts& counts) {
  std::ostringstream js;
  iso::diag::writeJson(js, diags, set.sources, 1);
  const nlohmann::json j = parseBack(js.str(), "JSON");
  if (!j.contains("diagnostics") || !j["diagnostics"].is_array() || j["diagnostics"].size() != diags.size())
    fail("JSON: diagnostics array missing or of the wrong size");
  if (j.value("errors", SIZE_MAX) != counts.errors || j.value("warnings", SIZE_MAX) != counts.warnings ||
      j.value("files", SIZE_MAX) != 1)
    fail("JSON: counts differ");
}

void renderSarifOutput(const std::vector<iso::diag::Diagnostic>& diags, const iso::frontend::ProgramSet& set) {

  // SARIF is validated as JSON without building a tree, and its results are counted by their "ruleId" members (one per
  // result: a string inside the log cannot hold an unescaped quote, so the text occurs nowhere else). The rule table
  // (the same in every log) is checked with the first input, then left out.
  static bool firstSarif = true;
  std::ostringstream ss;
  iso::diag::writeSarif(ss, diags, set.sources, "isolint", "fuzz", {}, {}, firstSarif);
  firstSarif = false;
  const std::string sarif = ss.str();
  if (!iso::support::isValidUtf8(sarif)) fail("output is not valid UTF-8: ", "SARIF");
  if (!nlohmann::json::accept(sarif)) fail("output does not parse as JSON: ", "SARIF");
  if (sarif.find("\n  \"version\": \"2.1.0\",\n") == std::string::npos) fail("SARIF: not version 2.1.0");
  size_t results = 0;
  for (size_t at = sarif.find("\"ruleId\": "); at != std::string::npos; at = sarif.find("\"ruleId\": ", at + 1))
    ++results;
  if (results != diags.size()) fail("SARIF: results missing or of the wrong size");
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const iso::machine::Machine machine = iso::machine::builtinMachine();
  if (size == 0) return 0;
  const uint8_t variant = data[0];
  const bool color = (variant & 64) != 0;
  std::string path = kStems[(variant >> 2) & 3];
  path += (variant & 2) != 0 ? ".spf" : ".mpf";
  iso::frontend::LoadOptions lo;
  lo.machine = &machine;
  lo.dialect = (variant & 1) != 0 ? iso::machine::Dialect::Z32 : iso::machine::Dialect::Sidac;
  iso::frontend::ProgramSet set;
  iso::frontend::loadSingleSource(path, std::string(reinterpret_cast<const char*>(data) + 1, size - 1), lo, set);
  // The first kMaxDiagnostics only: every renderer treats each diagnostic alike, and an input with hundreds of them
  // would cost hundreds of times the code it covers (the writers run under coverage tracing).
  const auto& all = set.diags.items();
  const std::vector<iso::diag::Diagnostic> diags(all.begin(), all.begin() + std::min(all.size(), kMaxDiagnostics));
  const iso::diag::Counts counts = iso::diag::countOf(diags);

  const unsigned outputs = (variant >> 4) & 3;
  if (outputs == 0 || outputs == 3) renderTextOutputs(diags, set, color);
  if (outputs == 1 || outputs == 3) renderJsonOutput(diags, set, counts);
  if (outputs == 2 || outputs == 3) renderSarifOutput(diags, set);
  return 0;
}
