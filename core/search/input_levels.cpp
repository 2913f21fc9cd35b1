#include "core/search/input_levels.hpp"

#include <cmath>

namespace hyfal {

namespace {

void append_fractions(std::size_t inputs, std::size_t dim, int remaining, std::vector<double>& prefix,
                      std::vector<double>& out) {
  if (dim == inputs) {
    if (remaining == 0) out.insert(out.end(), prefix.begin(), prefix.end());
    return;
  }
  for (double corner : {0.0, 1.0}) {  // cost 0
    prefix[dim] = corner;
    append_fractions(inputs, dim + 1, remaining, prefix, out);
  }
  for (int k = 1; k <= remaining; ++k) {  // n / 2^k, n odd: cost k
    const double d = std::ldexp(1.0, k);
    for (int n = 1; n < (1 << k); n += 2) {
      prefix[dim] = n / d;
      append_fractions(inputs, dim + 1, remaining - k, prefix, out);
    }
  }
}

}  // namespace

std::vector<double> dyadic_level_fractions(std::size_t inputs, int level) {
  std::vector<double> out, prefix(inputs);
  if (inputs > 0 && level >= 0) append_fractions(inputs, 0, level, prefix, out);
  return out;
}

std::vector<double> dyadic_refinement_sequence(std::size_t inputs, std::size_t at_least) {
  std::vector<double> out;
  if (inputs == 0) return out;
  for (int level = 0; out.size() / inputs < at_least && level < 30; ++level) {
    const std::vector<double> f = dyadic_level_fractions(inputs, level);
    out.insert(out.end(), f.begin(), f.end());
  }
  return out;
}

}  // namespace hyfal
