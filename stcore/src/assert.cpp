#include <stcore/assert.hpp>

#include <atomic>
#include <cstdio>
#include <cstdlib>

namespace st {

namespace {

void defaultHandler(const char* condition, const char* file, int line) {
  std::fprintf(stderr, "%s:%d: stcore assertion failed: %s\n", file, line, condition);
  std::abort();
}

// atomic: a handler set by one thread is seen by the tree another thread updates
std::atomic<AssertHandler> handler{&defaultHandler};

}  // namespace

AssertHandler setAssertHandler(AssertHandler h) { return handler.exchange(h != nullptr ? h : &defaultHandler); }

void assertFailed(const char* condition, const char* file, int line) { handler.load()(condition, file, line); }

}  // namespace st
