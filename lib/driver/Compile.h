//! @file Compile.h
//! @brief isocc: compile a program set into an image, or disassemble / verify / dump an image
//!        (SPEC §8, man/isocc.1).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "driver/Common.h"
#include "driver/ImageFile.h"
#include "frontend/ProgramSet.h"

namespace iso::driver {

struct CompileOptions {
  CommonOptions common;
  std::vector<std::string> paths; ///< program files or directories (compile mode)
  std::string output;             ///< -o OUT.isob
  bool strip = false;             ///< --strip: no line table
  std::string disasm;             ///< --disasm IMAGE
  std::string verify;             ///< --verify IMAGE
  std::string dump;               ///< --dump=hex: with PATH... the compiled image, else the IMAGE given
};

/// Runs isocc; returns the exit code of SPEC §8. Writes the image only when the program set
/// has no errors and the encoded image passes the reader and the verifier.
int runCompile(const CompileOptions& opts, Io& io);

/// Every file of a loaded program set, the machine file and the settings file: what no output
/// may overwrite.
std::vector<std::string> inputPaths(const frontend::ProgramSet& set, const CommonOptions& common);

} // namespace iso::driver
