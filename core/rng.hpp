// Per-trial random streams. A trial's seed depends only on (master seed, suite, instance key,
// method, trial index) — never on the thread that runs it — so results are identical at any
// thread count.
#pragma once
#include <cstdint>
#include <random>
#include <string_view>

namespace hyfal {

using Rng = std::mt19937_64;

// FNV-1a over bytes, then SplitMix64 finalization: a stable, platform-independent hash.
constexpr std::uint64_t fnv1a(std::string_view s, std::uint64_t h = 0xcbf29ce484222325ULL) {
  for (unsigned char c : s) {
    h ^= c;
    h *= 0x100000001b3ULL;
  }
  return h;
}

constexpr std::uint64_t splitmix64(std::uint64_t z) {
  z += 0x9e3779b97f4a7c15ULL;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

// 63-bit so that it is stored unchanged in SQLite's signed INTEGER.
constexpr std::int64_t trial_seed(std::uint64_t master, std::string_view suite,
                                  std::string_view instance, std::string_view method,
                                  std::int64_t trial_index) {
  std::uint64_t h = splitmix64(master);
  h = splitmix64(h ^ fnv1a(suite));
  h = splitmix64(h ^ fnv1a(instance));
  h = splitmix64(h ^ fnv1a(method));
  h = splitmix64(h ^ static_cast<std::uint64_t>(trial_index));
  return static_cast<std::int64_t>(h >> 1);
}

}  // namespace hyfal
