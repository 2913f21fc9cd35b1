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
constexpr std::int64_t trial_seed(std::uint64_t master, std::string_view suite, std::string_view instance,
                                  std::string_view method, std::int64_t trial_index) {
  std::uint64_t h = splitmix64(master);
  h = splitmix64(h ^ fnv1a(suite));
  h = splitmix64(h ^ fnv1a(instance));
  h = splitmix64(h ^ fnv1a(method));
  h = splitmix64(h ^ static_cast<std::uint64_t>(trial_index));
  return static_cast<std::int64_t>(h >> 1);
}

// A SplitMix64 stream for instance generators (mazes, random scenarios): platform-independent,
// unlike the std distributions over Rng, so an instance seed means the same instance on every
// machine; one stream per purpose, so adding draws for one purpose leaves the others unchanged.
class InstanceStream {
 public:
  InstanceStream(std::uint64_t seed, std::string_view purpose) : s_(splitmix64(seed ^ fnv1a(purpose))) {}
  std::uint64_t next() {
    s_ += 0x9e3779b97f4a7c15ULL;
    std::uint64_t z = s_;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
  // Uniform in [0, range), unbiased (Lemire 2019).
  std::uint64_t below(std::uint64_t range) {
    unsigned __int128 m = static_cast<unsigned __int128>(next()) * range;
    auto low = static_cast<std::uint64_t>(m);
    if (low < range) {
      const std::uint64_t t = (0 - range) % range;
      while (low < t) {
        m = static_cast<unsigned __int128>(next()) * range;
        low = static_cast<std::uint64_t>(m);
      }
    }
    return static_cast<std::uint64_t>(m >> 64);
  }
  double uniform01() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform01(); }

 private:
  std::uint64_t s_;
};

}  // namespace hyfal
