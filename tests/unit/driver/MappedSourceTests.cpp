//! @file MappedSourceTests.cpp
//! @brief A mapped source whose file shrinks while a tool reads it: a clear error and exit 2
//!        (driver::installInterruptHandler), never a crash.
#include <csignal>
#include <string>

#include <doctest/doctest.h>

#include "TestUtil.h"
#include "driver/Common.h"
#include "support/SourceText.h"

#include <sys/wait.h>
#include <unistd.h>

namespace {

struct ChildResult {
  int status = 0;
  std::string err; ///< what it wrote to standard error
};

/// Runs `body` in a child process with its standard error captured.
template <class Body> ChildResult inChild(Body&& body) {
  int fds[2];
  REQUIRE(::pipe(fds) == 0);
  const pid_t pid = ::fork();
  REQUIRE(pid >= 0);
  if (pid == 0) {
    ::close(fds[0]);
    ::dup2(fds[1], 2);
    body();
    ::_exit(0);
  }
  ::close(fds[1]);
  ChildResult r;
  char buf[512];
  for (ssize_t n; (n = ::read(fds[0], buf, sizeof buf)) > 0;)
    r.err.append(buf, static_cast<size_t>(n));
  ::close(fds[0]);
  ::waitpid(pid, &r.status, 0);
  return r;
}

} // namespace

TEST_CASE("mapped source: a file that shrinks while it is read is an error naming it, exit 2") {
  iso::test::TempDir dir;
  const std::string path = dir.write("big.mpf", std::string(iso::support::kMapSourcesFrom + 100, 'X') + "\nM30\n");
  ChildResult r = inChild([&] {
    iso::driver::installInterruptHandler("isolint");
    auto text = iso::support::readSource(path);
    if (!text || !text->isMapped()) ::_exit(10);
    if (::truncate(path.c_str(), 0) != 0) ::_exit(11);
    volatile char last = text->data()[text->size() - 1]; // SIGBUS: the byte is gone
    (void)last;
    ::_exit(12);
  });
  REQUIRE(WIFEXITED(r.status));
  CHECK(WEXITSTATUS(r.status) == 2);
  CHECK(r.err == "isolint: error: " + path + ": the file shrank while it was read; no output file was changed\n");
}

TEST_CASE("mapped source: another SIGBUS still ends the process as SIGBUS") {
  ChildResult r = inChild([] {
    iso::driver::installInterruptHandler("isolint");
    ::raise(SIGBUS);
    ::_exit(12);
  });
  REQUIRE(WIFSIGNALED(r.status));
  CHECK(WTERMSIG(r.status) == SIGBUS);
  CHECK(r.err.empty());
}
