// --shard i/K: the i-th of K disjoint shares of a job list, for schedulers that start K
// independent processes (Slurm job arrays), each with its own database, merged afterwards.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace hyfal {

constexpr std::int64_t kMaxShards = 100'000;

// A share of a job list: the jobs at positions p with p % count == index. The position is taken
// in the full deterministic job list (before stored trials are dropped), so that a resumed shard
// keeps the same share, and the K shares together are exactly the single-process list.
struct Shard {
  std::int64_t index = 0, count = 1;

  bool whole() const { return count == 1; }
  bool keeps(std::int64_t position) const { return position % count == index; }
  // How many of the positions first, first+1, ..., first+n-1 this shard keeps.
  std::int64_t count_in(std::int64_t first, std::int64_t n) const {
    const auto upto = [&](std::int64_t end) {  // positions 0..end-1 kept
      return end <= index ? 0 : (end - index + count - 1) / count;
    };
    return upto(first + n) - upto(first);
  }
  std::string text() const { return std::to_string(index) + "/" + std::to_string(count); }
};

// "i/K" with decimal digits only, 0 <= i < K <= kMaxShards; nullopt for anything else.
inline std::optional<Shard> parse_shard(std::string_view text) {
  const auto slash = text.find('/');
  if (slash == std::string_view::npos) return std::nullopt;
  const auto number = [](std::string_view digits) -> std::optional<std::int64_t> {
    if (digits.empty() || digits.size() > 6) return std::nullopt;
    std::int64_t v = 0;
    for (const char c : digits) {
      if (c < '0' || c > '9') return std::nullopt;
      v = v * 10 + (c - '0');
    }
    return v;
  };
  const auto i = number(text.substr(0, slash)), k = number(text.substr(slash + 1));
  if (!i || !k || *k < 1 || *k > kMaxShards || *i >= *k) return std::nullopt;
  return Shard{*i, *k};
}

}  // namespace hyfal
