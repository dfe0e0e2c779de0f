// The hashes against their published test vectors: FNV-1a 64 (Fowler, Noll, Vo reference values,
// from the published basis)
// and splitmix64 from state 0 (the first outputs of Vigna's reference generator).
#include <gtest/gtest.h>

#include <stcore/hash.hpp>

namespace st {
namespace {

TEST(Hash, Fnv1aReferenceVectors) {
  EXPECT_EQ(fnv1a("", kFnvOffsetBasis), 0xcbf29ce484222325ull);
  EXPECT_EQ(fnv1a("a", kFnvOffsetBasis), 0xaf63dc4c8601ec8cull);
  EXPECT_EQ(fnv1a("foobar", kFnvOffsetBasis), 0x85944171f73967e8ull);
  // stsim's own basis, which earlier results depend on
  EXPECT_EQ(fnv1a(""), 1469598103934665603ull);
}

TEST(Hash, SplitmixReferenceSequence) {
  std::uint64_t state = 0;
  EXPECT_EQ(splitmixMix(state += kSplitmixGamma), 0xe220a8397b1dcdafull);
  EXPECT_EQ(splitmixMix(state += kSplitmixGamma), 0x6e789e6aa1b965f4ull);
  EXPECT_EQ(splitmixMix(state += kSplitmixGamma), 0x06c45d188009454full);
}

TEST(Hash, UnitIntervalSpansZeroToBelowOne) {
  EXPECT_EQ(unitInterval(0), 0.0);
  EXPECT_LT(unitInterval(~0ull), 1.0);
  EXPECT_EQ(unitInterval(~0ull), 1.0 - 0x1.0p-53);
}

}  // namespace
}  // namespace st
