#pragma once
// A check that could hang before its fix, run bounded: in a child process with an alarm, so a read
// that never ends fails the test in seconds instead of blocking it (or filling the memory).
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <exception>
#include <functional>
#include <string>

// AddressSanitizer reserves terabytes of address space for its shadow memory: under it an
// address-space limit stops the sanitizer, not the read (it failed to mmap and every check said
// "hung"), so there the alarm alone bounds the check.
#if defined(__SANITIZE_ADDRESS__)
#define STSIM_BOUNDED_NO_AS_LIMIT 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define STSIM_BOUNDED_NO_AS_LIMIT 1
#endif
#endif

namespace st::test {

// What `f` threw (its what()), "" if it returned, "hung" if it ran past `seconds` or past 1 GiB
// (the memory bound: not under AddressSanitizer).
inline std::string errorWithin(const std::function<void()>& f, unsigned seconds = 10) {
  int fds[2];
  if (::pipe(fds) != 0) return "pipe failed";
  const pid_t pid = ::fork();
  if (pid < 0) return "fork failed";
  if (pid == 0) {
    ::close(fds[0]);
    ::alarm(seconds);
#ifndef STSIM_BOUNDED_NO_AS_LIMIT
    const rlimit mem{rlim_t{1} << 30, rlim_t{1} << 30};
    ::setrlimit(RLIMIT_AS, &mem);
#endif
    std::string what;
    try {
      f();
    } catch (const std::bad_alloc&) {
      ::_exit(3);
    } catch (const std::exception& e) {
      what = e.what();
    }
    std::size_t off = 0;
    while (off < what.size()) {
      const ssize_t n = ::write(fds[1], what.data() + off, what.size() - off);
      if (n <= 0) break;
      off += static_cast<std::size_t>(n);
    }
    ::_exit(0);
  }
  ::close(fds[1]);
  std::string what;
  char buf[4096];
  ssize_t n;
  while ((n = ::read(fds[0], buf, sizeof buf)) > 0) what.append(buf, static_cast<std::size_t>(n));
  ::close(fds[0]);
  int status = 0;
  ::waitpid(pid, &status, 0);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) return "hung";
  return what;
}

}  // namespace st::test
