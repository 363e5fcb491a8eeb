//! @file Compiler.h
//! @brief Compiles a checked program set (no error diagnostics) into an image.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "frontend/ProgramSet.h"
#include "image/Image.h"

namespace iso::compiler {

struct CompileOptions {
  bool strip = false;                                 ///< drop the line table
  machine::Dialect dialect = machine::Dialect::Sidac; ///< z32: the line order and M functions of SPEC §4.6
  /// z32: the machine's special_m (M number -> subprogram name); a special M compiles to a call.
  const std::map<int, std::string>* specialM = nullptr;
  /// z32: the machine's user parameter addresses (ExprKind::UserParam indexes them).
  const std::vector<std::string>* parameters = nullptr;
  /// The set was loaded in the compact form (LoadOptions::compactTrees) with these options:
  /// each unit's text is parsed again, a line at a time, and each line compiled as soon as it
  /// is parsed (no unit's tree is held whole). Null: the set holds the full trees.
  const frontend::LexOptions* reparse = nullptr;
  /// With `reparse`: the set is not used once compiled (isocc), and the pages of each unit's
  /// statements and N numbers leave memory as the compiler passes them (their bytes are gone).
  bool releaseSet = false;
  /// With `reparse`: a mapped text's pages behind the compiler leave memory (they are read
  /// again from the file if needed), and with releaseSet the statements', every so many bytes.
  size_t releaseEvery = size_t{4} << 20;
};

struct CompileError {
  std::string message; ///< e.g. "several main programs and none named: a.mpf, b.mpf"
};

/// The units an image of `set` links, in link order: the main program (the first named .mpf
/// that is a main program, else the only one), every semi-automatic program, then every
/// subprogram reachable from them by calls (and, in z32, by special M functions). Empty, with
/// `err` saying why, when the set has no main program or several and none named. Every unit
/// must pass the checks before it is compiled: the drivers report the diagnostics of each.
std::vector<size_t> linkedUnits(const frontend::ProgramSet& set, const CompileOptions& opts, CompileError& err);

/// Links one main program (the first named .mpf that is a main program, else the only main
/// program of the set), every semi-automatic program and every subprogram reachable from them
/// into `out`. The set must have no error-severity diagnostics. Deterministic: the same set
/// gives the same image whatever the order of the paths.
bool compileProgramSet(const frontend::ProgramSet& set, const CompileOptions& opts, image::Image& out,
                       CompileError& err);

} // namespace iso::compiler
