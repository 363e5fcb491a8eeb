//! @file SetChecks.cpp
//! @brief The checks of a whole program set: subprogram names (E209), calls (E210, and E110
//!        for other dialects' words), the call graph's depth (E211) and recursion (W409).
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "frontend/Parser.h" // unsupportedNameMessage
#include "frontend/Sema.h"
#include "lang/Unsupported.h"
#include "support/CaseFold.h"

namespace iso::frontend {

using diag::Msg;

namespace {

/// How a call site runs its callee, and the nesting levels it adds.
enum class Via : uint8_t {
  Call,    ///< a call line or z32 GOP: one level
  Special, ///< z32: a special M: one level
  Kg,      ///< z32: KG replaces the running frame: no level
  Range,   ///< z32: a GO range runs lines of its own file: one level
};

/// A call (or z32 special M, KG, GO range) of a node of the call graph: the callee's node
/// (a file, or a GO range) and where it is made.
struct CallSite {
  size_t callee;
  Loc loc;
  int64_t m = -1; ///< z32: the special M that makes the call
  Via via = Via::Call;
  int levels() const { return via == Via::Kg ? 0 : 1; }
};

/// The nodes of the call graph: every file (nodes 0..files-1), then every resolved z32 GO range.
struct Node {
  size_t file;
  std::string name; ///< the subprogram's name, or the range as written (GON10-N20)
};

struct CallGraph {
  std::vector<Node> nodes;
  std::vector<std::vector<CallSite>> calls; ///< per node
};
using ProcIndex = std::unordered_map<std::string, size_t>;

/// E209: unique subprogram names; returns the upper-case name -> file index.
ProcIndex indexProcs(const std::vector<File>& files, const SetOrder& by, diag::DiagnosticList& diags) {
  // E209: unique subprogram names. The definition reported as the first is one of a file whose
  // diagnostics are not shown, if there is one (so that the file shown gets the error), else
  // the first in the order of a full load.
  std::vector<size_t> order(files.size());
  for (size_t k = 0; k < order.size(); ++k)
    order[k] = k;
  auto key = [&](size_t i) {
    const bool shown = by.reported && i < by.reported->size() && (*by.reported)[i];
    const size_t r = by.rank && i < by.rank->size() ? (*by.rank)[i] : i;
    return std::pair{shown, r};
  };
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return key(a) < key(b); });
  ProcIndex procs;
  for (const size_t i : order) {
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

/// z32: a node for each resolved GO range of file `i`, called from the range's GO line, and
/// calling what the lines it runs (those of its first through its last line) call.
void addGoRanges(const File& f, size_t i, CallGraph& g) {
  const size_t first = g.calls.size();
  std::vector<std::pair<uint32_t, uint32_t>> lines; // per new node: [first line, line after the last)
  for (const GoJump& go : f.gos) {
    if (!go.range || go.target < 0 || go.rangeEnd < 0) continue;
    const auto end = static_cast<size_t>(go.rangeEnd) + 1;
    lines.push_back({f.stmts[static_cast<size_t>(go.target)].line,
                     end < f.stmts.size() ? f.stmts[end].line : std::numeric_limits<uint32_t>::max()});
    g.nodes.push_back({i, fmt::format("GO{}-{}", go.from, go.to)});
    Loc at = go.fromLoc;
    at.col = at.col > 2 ? at.col - 2 : 1; // the GO
    g.calls[i].push_back({g.calls.size(), at, -1, Via::Range});
    g.calls.emplace_back();
  }
  for (size_t r = first; r < g.calls.size(); ++r)
    for (const CallSite& cs : g.calls[i])
      if (cs.loc.line >= lines[r - first].first && cs.loc.line < lines[r - first].second) g.calls[r].push_back(cs);
}

/// The calls of each file (E210 for unknown names, E110 for other dialects' words), and the
/// z32 GO ranges as nodes of their own.
CallGraph buildCallGraph(std::vector<File>& files, const ProcIndex& procs, const SemaOptions& opts,
                         diag::DiagnosticList& diags) {
  CallGraph g;
  g.calls.resize(files.size());
  for (size_t i = 0; i < files.size(); ++i)
    g.nodes.push_back({i, std::string(files[i].procName)});
  for (size_t i = 0; i < files.size(); ++i) {
    File& f = files[i];
    auto& calls = g.calls;
    auto onSpecial = [&](const Item& x, const std::string& name) {
      auto p = procs.find(support::upperCopy(name));
      if (p == procs.end()) {
        diags.report(Msg::SpecialMUnknownProc, x.loc, x.len, x.code, opts.machine->name, name);
        return;
      }
      calls[i].push_back({p->second, x.loc, x.code, Via::Special});
    };
    auto onKg = [&](const Item& x, std::string_view) {
      const StmtName& name = f.names.at(static_cast<size_t>(x.code));
      auto it = procs.find(support::upperCopy(name.text));
      if (it == procs.end()) {
        diags.report(Msg::ProcUnknown, name.loc, name.len, name.text);
        return;
      }
      calls[i].push_back({it->second, name.loc, -1, Via::Kg});
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
    forEachCall(f, opts.specialMap(), onCall, onSpecial, onKg);
    addGoRanges(f, i, g);
  }
  return g;
}

/// The longest chain of nesting levels below each node of the call graph (memoised DFS), and
/// W409 at a call that closes a cycle.
struct Depths {
  std::vector<int> depth;   ///< nesting levels below this node along the longest chain
  std::vector<int> nextHop; ///< index into calls[node] of the longest chain's first call
};

Depths longestChains(const std::vector<File>& files, const CallGraph& g, diag::DiagnosticList& diags) {
  const size_t n = g.calls.size();
  std::vector<int> state(n, 0); // 0 new, 1 on stack, 2 done
  Depths d{std::vector<int>(n, 0), std::vector<int>(n, -1)};
  std::vector<uint8_t> recursionReported(n, 0);
  auto fold = [&](size_t u, size_t k, size_t v) {
    const int via = d.depth[v] + g.calls[u][k].levels();
    if (via > d.depth[u] || d.nextHop[u] < 0) {
      d.depth[u] = std::max(d.depth[u], via);
      if (via == d.depth[u]) d.nextHop[u] = static_cast<int>(k);
    }
  };
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
      if (fr.next == g.calls[u].size()) {
        state[u] = 2;
        stack.pop_back();
        if (!stack.empty()) fold(stack.back().unit, stack.back().next - 1, u); // the call that led here
        continue;
      }
      size_t k = fr.next++;
      size_t v = g.calls[u][k].callee;
      if (state[v] == 1) {
        if (!recursionReported[u]) {
          recursionReported[u] = 1;
          diags.report(Msg::Recursion, g.calls[u][k].loc, 1, g.nodes[v].name);
        }
        continue;
      }
      if (state[v] == 0) {
        state[v] = 1;
        stack.push_back({v, 0}); // invalidates fr
        continue;
      }
      fold(u, k, v);
    }
  };
  // Main and semi-automatic programs first, so that a cycle is reported at the call that
  // leads back up the chain as seen from the program that runs it.
  for (size_t i = 0; i < files.size(); ++i)
    if (state[i] == 0 && files[i].kind != UnitKind::Sub) dfs(i);
  for (size_t i = 0; i < n; ++i)
    if (state[i] == 0) dfs(i);
  return d;
}

/// W409 recursion and E211 depth below each main and semi-automatic program; the notes show
/// the chain (calls, special M, GO ranges and KG).
void checkDepth(const std::vector<File>& files, const CallGraph& g, const SemaOptions& opts,
                diag::DiagnosticList& diags) {
  const Depths d = longestChains(files, g, diags);
  int limit = opts.maxNesting();
  for (size_t i = 0; i < files.size(); ++i) {
    if (files[i].kind == UnitKind::Sub) continue; // chains are counted below main and semi programs
    if (d.depth[i] <= limit) continue;
    const CallSite& first = g.calls[i][static_cast<size_t>(d.nextHop[i])];
    auto& e = diags.report(Msg::NestingTooDeep, first.loc, 1, d.depth[i], limit);
    size_t u = i;
    int level = 0;
    for (int hops = 0; d.nextHop[u] >= 0 && hops < 64; ++hops) {
      const CallSite& cs = g.calls[u][static_cast<size_t>(d.nextHop[u])];
      level += cs.levels();
      const std::string& name = g.nodes[cs.callee].name;
      switch (cs.via) {
      case Via::Call: e.note(Msg::NestingLevelNote, cs.loc, level, name); break;
      case Via::Special: e.note(Msg::NestingLevelSpecialNote, cs.loc, level, cs.m, name); break;
      case Via::Kg: e.note(Msg::NestingKgNote, cs.loc, level, name); break;
      case Via::Range: e.note(Msg::NestingRangeNote, cs.loc, level, name); break;
      }
      u = cs.callee;
    }
  }
}

} // namespace

void checkSet(std::vector<File>& files, const SemaOptions& opts, diag::DiagnosticList& diags, const SetOrder& order) {
  const ProcIndex procs = indexProcs(files, order, diags);
  const CallGraph calls = buildCallGraph(files, procs, opts, diags);
  checkDepth(files, calls, opts, diags);
}

} // namespace iso::frontend
