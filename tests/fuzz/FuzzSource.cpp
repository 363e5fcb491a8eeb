//! @file FuzzSource.cpp
//! @brief Fuzz target: source text -> lexer, parser, semantic checks, renderers, compiler.
//!        Any input must give diagnostics or an image, never a crash or a hang.
#include <cstddef>
#include <cstdint>
#include <string>

#include "compiler/Compiler.h"
#include "diag/Render.h"
#include "frontend/ProgramSet.h"
#include "machine/Machine.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const iso::machine::Machine machine = iso::machine::builtinMachine();
  std::string text(reinterpret_cast<const char*>(data), size);
  for (int dialect = 0; dialect < 2; ++dialect) {
    iso::frontend::LoadOptions lo;
    lo.machine = &machine;
    lo.dialect = dialect ? iso::machine::Dialect::Z32 : iso::machine::Dialect::Sidac;
    for (const char* path : {"fuzz.mpf", "fuzz.spf"}) {
      iso::frontend::ProgramSet set;
      iso::frontend::loadSingleSource(path, text, lo, set);
      (void)iso::diag::renderText(set.diags.items(), set.sources, false);
      (void)iso::diag::renderSarif(set.diags.items(), set.sources, "isolint", "fuzz").dump();
      iso::image::Image img;
      iso::compiler::CompileError err;
      (void)iso::compiler::compileProgramSet(set, {}, img, err);
    }
  }
  return 0;
}
