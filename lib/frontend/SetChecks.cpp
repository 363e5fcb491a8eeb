//! @file SetChecks.cpp
//! @brief The checks of a whole program set: subprogram names (E209), calls (E210, and E110
//!        for other dialects' words), the call graph's depth (E211) and recursion (W409).
#include <cstddef>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "frontend/Parser.h" // unsupportedNameMessage
#include "frontend/Sema.h"
#include "lang/Unsupported.h"
#include "support/CaseFold.h"

namespace iso::frontend {

using diag::Msg;

namespace {

/// A call (or z32 special M) of a subprogram: the callee's file index and where it is made.
struct CallSite {
  size_t callee;
  Loc loc;
  int64_t m = -1; ///< z32: the special M that makes the call
};

using CallGraph = std::vector<std::vector<CallSite>>;
using ProcIndex = std::unordered_map<std::string, size_t>;

/// E209: unique subprogram names; returns the upper-case name -> file index.
ProcIndex indexProcs(const std::vector<File>& files, diag::DiagnosticList& diags) {
  // E209: unique subprogram names
  ProcIndex procs;
  for (size_t i = 0; i < files.size(); ++i) {
    const File& f = files[i];
    if (f.kind != UnitKind::Sub || f.procName.empty()) continue;
    auto [it, ins] = procs.emplace(support::upperCopy(f.procName), i);
    if (!ins) {
      const Stmt* h = nullptr;
      for (const Stmt& s : f.stmts)
        if (s.kind == StmtKind::Proc) {
          h = &s;
          break;
        }
      const File& first = files[it->second];
      const Stmt* h0 = nullptr;
      for (const Stmt& s : first.stmts)
        if (s.kind == StmtKind::Proc) {
          h0 = &s;
          break;
        }
      auto& d =
          diags.report(Msg::ProcTwice, h ? f.nameOf(*h).loc : Loc{f.id, 1, 1}, h ? f.nameOf(*h).len : 1, f.procName);
      if (h0) d.note(Msg::ProcTwiceNote, first.nameOf(*h0).loc);
    }
  }
  return procs;
}

/// The calls of each file (E210 for unknown names, E110 for other dialects' words).
CallGraph buildCallGraph(std::vector<File>& files, const ProcIndex& procs, const SemaOptions& opts,
                         diag::DiagnosticList& diags) {
  std::vector<std::vector<CallSite>> calls(files.size());
  for (size_t i = 0; i < files.size(); ++i) {
    File& f = files[i];
    auto onSpecial = [&](const Item& x, const std::string& name) {
      auto p = procs.find(support::upperCopy(name));
      if (p == procs.end()) {
        diags.report(Msg::SpecialMUnknownProc, x.loc, x.len, x.code, opts.machine->name, name);
        return;
      }
      calls[i].push_back({p->second, x.loc, x.code});
    };
    auto onCall = [&](const Stmt& s) {
      const StmtName& name = f.nameOf(s);
      auto it = procs.find(support::upperCopy(name.text));
      if (it == procs.end()) {
        if (auto msg = unsupportedNameMessage(name.text, opts.dialect)) {
          auto& d = diags.report(diag::codeOf(Msg::UnsupportedName), name.loc, name.len, std::move(*msg));
          // RET and ENDPROC end a subprogram: the SIDAC way is M17, one for one. Elsewhere
          // (a main program, after THEN) M17 would be an error of its own: no fix.
          const auto* u = lang::findUnsupportedName(name.text);
          if (f.kind == UnitKind::Sub && !s.isInner && !name.joined && u && !u->replacement.empty())
            d.fixes.push_back({diag::message(Msg::UnsupportedReplaceFix, name.text, u->replacement),
                               {{name.loc, name.loc.line, name.loc.col + name.len, std::string(u->replacement)}}});
          return;
        }
        diags.report(Msg::ProcUnknown, name.loc, name.len, name.text);
        return;
      }
      calls[i].push_back({it->second, name.loc});
    };
    forEachCall(f, opts.specialMap(), onCall, onSpecial);
  }
  return calls;
}

/// W409 recursion and E211 depth below each main and semi-automatic program.
void checkDepth(const std::vector<File>& files, const CallGraph& calls, const SemaOptions& opts,
                diag::DiagnosticList& diags) {
  // longest chain of calls below each unit (memoised DFS)
  const size_t n = files.size();
  std::vector<int> state(n, 0);    // 0 new, 1 on stack, 2 done
  std::vector<int> depth(n, 0);    // nested calls below this unit along the longest chain
  std::vector<int> nextHop(n, -1); // index into calls[i] of the longest chain's first call
  std::vector<uint8_t> recursionReported(n, 0);
  // Iterative: a chain of thousands of subprograms must not exhaust the stack.
  struct Frame {
    size_t unit;
    size_t next; ///< index into calls[unit] of the next call to follow
  };
  std::vector<Frame> stack;
  auto dfs = [&](size_t root) {
    state[root] = 1;
    stack.push_back({root, 0});
    while (!stack.empty()) {
      Frame& fr = stack.back();
      size_t u = fr.unit;
      if (fr.next == calls[u].size()) {
        state[u] = 2;
        stack.pop_back();
        if (!stack.empty()) { // the caller's call that led here is done: fold its depth
          Frame& caller = stack.back();
          size_t k = caller.next - 1;
          if (depth[u] + 1 > depth[caller.unit]) {
            depth[caller.unit] = depth[u] + 1;
            nextHop[caller.unit] = static_cast<int>(k);
          }
        }
        continue;
      }
      size_t k = fr.next++;
      size_t v = calls[u][k].callee;
      if (state[v] == 1) {
        if (!recursionReported[u]) {
          recursionReported[u] = 1;
          diags.report(Msg::Recursion, calls[u][k].loc, 1, files[v].procName);
        }
        continue;
      }
      if (state[v] == 0) {
        state[v] = 1;
        stack.push_back({v, 0}); // invalidates fr
        continue;
      }
      if (depth[v] + 1 > depth[u]) {
        depth[u] = depth[v] + 1;
        nextHop[u] = static_cast<int>(k);
      }
    }
  };
  // Main and semi-automatic programs first, so that a cycle is reported at the call that
  // leads back up the chain as seen from the program that runs it.
  for (size_t i = 0; i < n; ++i)
    if (state[i] == 0 && files[i].kind != UnitKind::Sub) dfs(i);
  for (size_t i = 0; i < n; ++i)
    if (state[i] == 0) dfs(i);
  int limit = opts.maxNesting();
  for (size_t i = 0; i < n; ++i) {
    if (files[i].kind == UnitKind::Sub) continue; // chains are counted below main and semi programs
    if (depth[i] <= limit) continue;
    const CallSite& first = calls[i][static_cast<size_t>(nextHop[i])];
    auto& d = diags.report(Msg::NestingTooDeep, first.loc, 1, depth[i], limit);
    size_t u = i;
    int level = 0;
    while (nextHop[u] >= 0 && level < 64) {
      const CallSite& cs = calls[u][static_cast<size_t>(nextHop[u])];
      ++level;
      if (cs.m >= 0)
        d.note(Msg::NestingLevelSpecialNote, cs.loc, level, cs.m, files[cs.callee].procName);
      else
        d.note(Msg::NestingLevelNote, cs.loc, level, files[cs.callee].procName);
      u = cs.callee;
    }
  }
}

} // namespace

void checkSet(std::vector<File>& files, const SemaOptions& opts, diag::DiagnosticList& diags) {
  const ProcIndex procs = indexProcs(files, diags);
  const CallGraph calls = buildCallGraph(files, procs, opts, diags);
  checkDepth(files, calls, opts, diags);
}

} // namespace iso::frontend
