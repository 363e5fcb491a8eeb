//! @file Sema.h
//! @brief Semantic checks of SPEC §7 on parsed files (checkFile: checks/) and on a whole program
//!        set (checkSet: SetChecks.cpp), plus the control-flow facts (jump targets, IF matching,
//!        reachability) the compiler reuses. isolint's parse-and-check pass: FilePipeline.h.
#pragma once

#include <map>
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
  /// z32: the machine's special_m map (M number -> subprogram name); nullptr in dialect sidac.
  const std::map<int, std::string>* specialMap() const {
    return dialect == machine::Dialect::Z32 && machine ? &machine->specialM : nullptr;
  }
  /// z32: the subprogram the machine's special_m maps M`m` to, or nullptr (sidac: always).
  const std::string* specialM(int64_t m) const {
    const auto* map = specialMap();
    if (!map) return nullptr;
    auto it = map->find(static_cast<int>(m));
    return it == map->end() ? nullptr : &it->second;
  }
};

/// Per-file facts computed by checkFile (and parseAndCheckFile) and used by the compiler.
struct FileFlow {
  std::vector<int32_t> match;     ///< If(block)->Else or EndIf; Else->EndIf; When(long)->Cancel; else -1
  std::vector<uint8_t> reachable; ///< per statement
  bool endReachable = false;      ///< control can fall off the end of the file
};

/// Visits every call that `f` makes, in statement order (each statement, then the statement
/// after its THEN/DO): `onCall(stmt)` for a call statement (z32: also GOP<name>);
/// `onSpecial(item, name)` for an M that `specialM` (the z32 machine's special_m, or nullptr)
/// maps to subprogram `name`; `onKg(item, name)` for a z32 `KG<name>` item (it continues in
/// `name` without return: no nesting level).
template <class OnCall, class OnSpecial, class OnKg>
void forEachCall(const File& f, const std::map<int, std::string>* specialM, OnCall&& onCall, OnSpecial&& onSpecial,
                 OnKg&& onKg) {
  auto visit = [&](const Stmt& s) {
    if (s.kind == StmtKind::Call) onCall(s);
    if (s.kind != StmtKind::Block) return;
    const Item* it = f.itemsOf(s);
    for (uint32_t k = 0; k < s.itemCount; ++k) {
      if (it[k].kind == ItemKind::Kg) {
        onKg(it[k], f.names.at(static_cast<size_t>(it[k].code)).text);
        continue;
      }
      if (!specialM || it[k].kind != ItemKind::M || it[k].nb) continue;
      auto sp = specialM->find(it[k].code);
      if (sp != specialM->end()) onSpecial(it[k], sp->second);
    }
  };
  for (const Stmt& s : f.stmts) {
    visit(s);
    if (s.inner >= 0) visit(f.inner[static_cast<size_t>(s.inner)]);
  }
}

/// The same for callers that only need the names a file runs: a z32 `KG<name>` item comes to
/// `onSpecial(item, name)` too (the program set loads and links `name` either way).
template <class OnCall, class OnSpecial>
void forEachCall(const File& f, const std::map<int, std::string>* specialM, OnCall&& onCall, OnSpecial&& onSpecial) {
  forEachCall(f, specialM, onCall, onSpecial,
              [&](const Item& x, std::string_view name) { onSpecial(x, std::string(name)); });
}

/// Decides the unit kind from the file name and the first statement (SPEC §1).
UnitKind classifyUnit(const File& f);

/// Runs every per-file check; resolves jump targets in the AST. Appends to `diags`.
FileFlow checkFile(File& f, const SemaOptions& opts, diag::DiagnosticList& diags);

/// Constant value of an expression if it folds (numbers and arithmetic on them).
std::optional<double> constValue(const File& f, ExprId e);

/// Set-level checks: E209 duplicate PROC names, E210 unknown calls, E211 nesting depth,
/// W409 recursion. `files` are all files of the set.
/// Which of two subprograms of one name is the first (E209 is reported on the other): one of
/// a file whose diagnostics are not shown (`reported`, per file), else the first by `rank`
/// (per file: its place in a full load of its folders; a lazy load reads them in another
/// order), else by index.
struct SetOrder {
  const std::vector<uint8_t>* reported = nullptr;
  const std::vector<size_t>* rank = nullptr;
};
void checkSet(std::vector<File>& files, const SemaOptions& opts, diag::DiagnosticList& diags,
              const SetOrder& order = {});

} // namespace iso::frontend
