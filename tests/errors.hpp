#pragma once
// What a call throws, for the tests of readers that throw their caller's exception type.
#include <functional>
#include <string>

namespace st::test {

// The message of the E that f throws; "(no error)" when it throws none (any other exception
// propagates, so a wrong type fails the test).
template <class E>
std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const E& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace st::test
