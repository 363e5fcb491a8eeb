//! @file FuzzSource.cpp
//! @brief Fuzz target: source text -> lexer, parser, semantic checks, text diagnostics,
//!        compiler -> image bytes -> reader + verifier. Any input must give diagnostics or an
//!        image, never a crash or a hang, and an image the compiler writes must load. isolint's
//!        one pass (compact trees) must give the same diagnostics as the full load, split
//!        between two threads too, and the lexer's fast path the tokens of its general path.
//!
//! Input format: the first byte picks the variant (bit 0: dialect sidac/z32; bit 1: the file
//! name fuzz.mpf/fuzz.spf, i.e. the unit kind; bit 2: strip the line table; bit 3: colours in
//! the text diagnostics); the rest is the file's text. The seeds start with a digit 0-7. One
//! variant per input keeps the target fast (JSON and SARIF are FuzzRender's).
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

#include "Support.h"
#include "diag/Render.h"
#include "frontend/ProgramSet.h"
#include "machine/Machine.h"

namespace {
constexpr size_t kTextDiagnostics = 12;
} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const iso::machine::Machine machine = iso::machine::builtinMachine();
  if (size == 0) return 0;
  const uint8_t variant = data[0];
  const bool z32 = (variant & 1) != 0;
  const char* path = (variant & 2) != 0 ? "fuzz.spf" : "fuzz.mpf";
  iso::frontend::LoadOptions lo;
  lo.machine = &machine;
  lo.dialect = z32 ? iso::machine::Dialect::Z32 : iso::machine::Dialect::Sidac;
  iso::frontend::ProgramSet set;
  const std::string source(reinterpret_cast<const char*>(data) + 1, size - 1);
  iso::frontend::loadSingleSource(path, source, lo, set);
  iso::fuzz::checkCompactLoad(set, path, source, lo, "FuzzSource"); // isolint's one pass
  iso::fuzz::checkLexerPaths(source, lo.dialect, "FuzzSource");     // the lexer's fast path
  {
    // as isolint's text format does, with a per-file limit: a dozen diagnostics exercise the
    // source windows; rendering hundreds of them would cost more than the frontend (every
    // diagnostic of every input is rendered by FuzzRender)
    std::ostringstream os;
    iso::diag::TextRenderer text(os, set.sources, (variant & 8) != 0, kTextDiagnostics);
    for (const auto& d : set.diags.items())
      text.add(d);
    text.finish();
  }
  if (iso::fuzz::hasErrors(set)) return 0;
  iso::compiler::CompileOptions co;
  co.dialect = lo.dialect;
  co.strip = (variant & 4) != 0;
  std::optional<iso::image::VerifiedImage> img;
  (void)iso::fuzz::compileAndLoad(set, co, img, "FuzzSource"); // false e.g. for a lone .spf
  return 0;
}
