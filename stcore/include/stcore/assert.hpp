#pragma once
// Invariant checks with a replaceable handler (Box2D's b2SetAssertFcn, Jolt's JPH_ASSERT and
// AssertFailed): STCORE_ASSERT(cond) calls the handler when cond is false, so a test can catch a
// broken invariant and an application can log it its own way. The default handler prints
// "FILE:LINE: stcore assertion failed: COND" to stderr and aborts; it is the one place stcore
// writes anything, as it is about to stop the program.
//
// Checked unless NDEBUG is defined, as assert() is. CI's sanitizer build compiles without NDEBUG
// so the checks run there (.ci/run); under NDEBUG the condition is not evaluated.
namespace st {

// Called with the condition's text, the file and the line. A handler that returns lets the
// caller go on past the broken invariant: a test handler should throw or record and stop.
using AssertHandler = void (*)(const char* condition, const char* file, int line);

// Installs `handler` (nullptr: the default) and returns the one it replaces.
AssertHandler setAssertHandler(AssertHandler handler);

// Calls the installed handler; STCORE_ASSERT's failure path.
void assertFailed(const char* condition, const char* file, int line);

}  // namespace st

#ifdef NDEBUG
// sizeof: the condition is not evaluated, yet its variables count as used (no warnings)
#define STCORE_ASSERT(cond) static_cast<void>(sizeof(!(cond)))
#else
#define STCORE_ASSERT(cond) ((cond) ? static_cast<void>(0) : ::st::assertFailed(#cond, __FILE__, __LINE__))
#endif
