// The replaceable assert hook: a test catches a broken invariant, the default stops the program
// naming where.
#include <gtest/gtest.h>

#include <string>

#include <stcore/assert.hpp>

namespace st {
namespace {

struct Caught {
  int calls = 0;
  std::string condition, file;
  int line = 0;
};
Caught caught;

void record(const char* condition, const char* file, int line) {
  ++caught.calls;
  caught.condition = condition;
  caught.file = file;
  caught.line = line;
}

// installs `record` for one test, the previous handler back after it
class AssertHook : public ::testing::Test {
 protected:
  void SetUp() override {
    caught = Caught{};
    previous_ = setAssertHandler(&record);
  }
  void TearDown() override { setAssertHandler(previous_); }

 private:
  AssertHandler previous_ = nullptr;
};

TEST_F(AssertHook, TheInstalledHandlerIsCalledWithConditionFileAndLine) {
  assertFailed("a < b", "grid.cpp", 12);
  EXPECT_EQ(caught.calls, 1);
  EXPECT_EQ(caught.condition, "a < b");
  EXPECT_EQ(caught.file, "grid.cpp");
  EXPECT_EQ(caught.line, 12);
}

TEST_F(AssertHook, AViolatedAssertionCallsItWhereAssertionsAreOn) {
  int evaluated = 0;
  auto holds = [&] { return ++evaluated == 0; };  // false, counting its evaluations
  [[maybe_unused]] const int line = __LINE__ + 1;
  STCORE_ASSERT(holds());
  STCORE_ASSERT(evaluated >= 0);  // holds: not reported
#ifdef NDEBUG
  // off: the condition is not even evaluated
  EXPECT_EQ(evaluated, 0);
  EXPECT_EQ(caught.calls, 0);
#else
  EXPECT_EQ(evaluated, 1);
  ASSERT_EQ(caught.calls, 1);
  EXPECT_EQ(caught.condition, "holds()");
  EXPECT_NE(caught.file.find("assert_test.cpp"), std::string::npos);
  EXPECT_EQ(caught.line, line);
#endif
}

TEST(AssertDefault, AbortsNamingFileAndLine) {
  setAssertHandler(nullptr);  // the default, whatever ran before
  EXPECT_DEATH(assertFailed("count == size", "region_tree.cpp", 418),
               "region_tree.cpp:418: stcore assertion failed: count == size");
}

}  // namespace
}  // namespace st
