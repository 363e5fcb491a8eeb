//! @file Sema.h
//! @brief Semantic checks of SPEC §7 on parsed files and on a whole program set, plus the
//!        control-flow facts (jump targets, IF matching, reachability) the compiler reuses.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "diag/Diagnostic.h"
#include "frontend/Ast.h"
#include "machine/Machine.h"

namespace iso::frontend {

struct SemaOptions {
  const machine::Machine* machine = nullptr; ///< axes, soft limits, I/O ranges
  machine::Dialect dialect = machine::Dialect::Sidac;
  int maxNesting() const { return lang::maxNesting(dialect); }
  /// z32: the subprogram the machine's special_m maps M`m` to, or nullptr (sidac: always).
  const std::string* specialM(int64_t m) const {
    if (dialect != machine::Dialect::Z32 || !machine) return nullptr;
    auto it = machine->specialM.find(static_cast<int>(m));
    return it == machine->specialM.end() ? nullptr : &it->second;
  }
};

/// Per-file facts computed by checkFile and used by the compiler.
struct FileFlow {
  std::vector<int32_t> match;     ///< If(block)->Else or EndIf; Else->EndIf; When(long)->Cancel; else -1
  std::vector<uint8_t> reachable; ///< per statement
  bool endReachable = false;      ///< control can fall off the end of the file
};

/// Decides the unit kind from the file name and the first statement (SPEC §1).
UnitKind classifyUnit(const File& f);

/// Runs every per-file check; resolves jump targets in the AST. Appends to `diags`.
FileFlow checkFile(File& f, const SemaOptions& opts, diag::DiagnosticList& diags);

/// Constant value of an expression if it folds (numbers and arithmetic on them).
std::optional<double> constValue(const File& f, ExprId e);

/// Set-level checks: E209 duplicate PROC names, E210 unknown calls, E211 nesting depth,
/// W409 recursion. `files` are all files of the set.
void checkSet(std::vector<File>& files, const SemaOptions& opts, diag::DiagnosticList& diags);

/// Upper-cases ASCII letters.
std::string upperCopy(std::string_view s);

} // namespace iso::frontend
