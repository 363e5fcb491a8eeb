//! @file FileChecker.cpp
//! @brief The checker's run: every pass of a file, in order or two at a time.
#include "frontend/checks/FileChecker.h"

#include <exception>
#include <thread>
#include <utility>

namespace iso::frontend::checks {

FileFlow FileChecker::run(bool blocksChecked, bool twoThreads) {
  n_ = static_cast<int32_t>(f_.stmts.size());
  flow_.match.assign(f_.stmts.size(), -1);
  if (twoThreads) {
    runInTwo();
  } else {
    checkHeaders();
    collectLabels();
    matchIfsAndResolveJumps();
    resolveGos();
    checkWhens();
    checkJumpsIntoBlocks();
    computeReachability();
    checkLineNumbers();
  }
  if (!blocksChecked) checkBlocks();
  return std::move(flow_);
}

/// Runs `help` on a thread of its own while `work` runs here; any exception comes out here.
template <class Help, class Work> void FileChecker::besideHelper(Help help, Work work) {
  std::exception_ptr helpError;
  {
    std::thread t([&] {
      try {
        help();
      } catch (...) {
        helpError = std::current_exception();
      }
    });
    struct Join {
      std::thread& t;
      ~Join() { t.join(); }
    } join{t};
    work();
  }
  if (helpError) std::rethrow_exception(helpError);
}

/// run's passes on two threads: a second checker of the file (its own diagnostics, the same
/// flow) runs the headers, the WHENs and the N numbers beside the labels, IFs and jumps,
/// then the jumps into blocks beside the flow. Each pass reads only what the passes before
/// its pair wrote; the two of a pair write different entries of FileFlow::match, and only
/// the first resolves jump targets (the WHEN checks never read them).
void FileChecker::runInTwo() {
  diag::DiagnosticList helperDiags;
  FileChecker helper(f_, opts_, helperDiags, &flow_);
  helper.n_ = n_;
  besideHelper(
      [&] {
        helper.checkHeaders();
        helper.checkWhens();
        helper.checkLineNumbers();
      },
      [&] {
        collectLabels();
        matchIfsAndResolveJumps();
        resolveGos();
      });
  helper.endifOf_ = endifOf_;
  besideHelper([&] { helper.checkJumpsIntoBlocks(); }, [&] { computeReachability(); });
  diags_.append(std::move(helperDiags));
}

} // namespace iso::frontend::checks
