#pragma once
// Deterministic hashing for reproducible runs: which vehicles are equipped, a rack's jitter and an
// experiment's run ids must not depend on the platform's std::hash or on the order of a run.
#include <cstdint>
#include <string_view>

namespace st {

// FNV-1a's published 64-bit offset basis, and the basis stsim hashes from: the same digits less
// the last one (a slip made early on). Any odd basis hashes as well; it stays so that a seed
// equips the same vehicles and a sweep names its runs as in every earlier result.
inline constexpr std::uint64_t kFnvOffsetBasis = 14695981039346656037ull;
inline constexpr std::uint64_t kHashBasis = 1469598103934665603ull;

// FNV-1a (64-bit) of the bytes of s, starting from basis.
constexpr std::uint64_t fnv1a(std::string_view s, std::uint64_t basis = kHashBasis) {
  std::uint64_t h = basis;
  for (unsigned char c : s) {
    h ^= c;
    h *= 1099511628211ull;
  }
  return h;
}

// splitmix64 (Steele, Lea, Flood 2014): the state advances by this odd constant...
inline constexpr std::uint64_t kSplitmixGamma = 0x9e3779b97f4a7c15ull;

// ...and each state is mixed into an output whose bits all depend on all of the state's.
constexpr std::uint64_t splitmixMix(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

// A double in [0, 1) from the top 53 bits of x.
constexpr double unitInterval(std::uint64_t x) { return static_cast<double>(x >> 11) * 0x1.0p-53; }

}  // namespace st
