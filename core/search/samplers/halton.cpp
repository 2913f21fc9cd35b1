#include "core/search/samplers/halton.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

namespace hyfal {

namespace {

constexpr std::array<unsigned, 64> kPrimes = {
    2,   3,   5,   7,   11,  13,  17,  19,  23,  29,  31,  37,  41,  43,  47,  53,  59,  61,  67,  71,  73,  79,
    83,  89,  97,  101, 103, 107, 109, 113, 127, 131, 137, 139, 149, 151, 157, 163, 167, 173, 179, 181, 191, 193,
    197, 199, 211, 223, 227, 229, 233, 239, 241, 251, 257, 263, 269, 271, 277, 281, 283, 293, 307, 311};

}  // namespace

double radical_inverse(std::uint64_t index, unsigned base) {
  if (base < 2) throw std::invalid_argument("radical_inverse: base must be >= 2");
  const double inv = 1.0 / static_cast<double>(base);
  double scale = inv, r = 0.0;
  while (index > 0) {
    r += static_cast<double>(index % base) * scale;
    index /= base;
    scale *= inv;
  }
  return r;
}

unsigned halton_base(std::size_t k) {
  if (k >= kPrimes.size()) throw std::invalid_argument(fmt::format("halton: at most {} dimensions", kPrimes.size()));
  return kPrimes[k];
}

HaltonSequence::HaltonSequence(Box box, std::vector<double> shift) : box_(std::move(box)), shift_(std::move(shift)) {
  if (box_.hi.size() != box_.lo.size()) throw std::invalid_argument("halton: malformed box");
  if (box_.dim() > kPrimes.size())
    throw std::invalid_argument(fmt::format("halton: at most {} dimensions", kPrimes.size()));
  for (std::size_t k = 0; k < box_.dim(); ++k)
    if (!(box_.hi[k] >= box_.lo[k])) throw std::invalid_argument("halton: empty box");
  if (!shift_.empty() && shift_.size() != box_.dim()) throw std::invalid_argument("halton: one shift per dimension");
  for (double s : shift_)
    if (!(s >= 0.0 && s < 1.0)) throw std::invalid_argument("halton: shifts must lie in [0, 1)");
}

std::vector<double> HaltonSequence::point(std::uint64_t i) const {
  std::vector<double> x(box_.dim());
  for (std::size_t k = 0; k < x.size(); ++k) {
    double u = radical_inverse(i, kPrimes[k]);
    if (!shift_.empty()) {
      u += shift_[k];
      if (u >= 1.0) u -= 1.0;
    }
    x[k] = box_.lo[k] + u * (box_.hi[k] - box_.lo[k]);
  }
  return x;
}

double dispersion(const std::vector<std::vector<double>>& points, const Box& box, std::size_t grid_budget) {
  std::vector<std::size_t> axes;  // axes of non-zero width
  for (std::size_t k = 0; k < box.dim(); ++k)
    if (box.hi[k] > box.lo[k]) axes.push_back(k);
  const std::size_t d = axes.size();
  if (d == 0) return 0.0;
  if (d > kPrimes.size()) throw std::invalid_argument(fmt::format("dispersion: at most {} dimensions", kPrimes.size()));
  if (points.empty()) return 1.0;
  // Normalized coordinates, clamped to the box.
  std::vector<double> z;
  z.reserve(points.size() * d);
  for (const auto& p : points) {
    if (p.size() != box.dim()) throw std::invalid_argument("dispersion: a point has the wrong dimension");
    for (std::size_t k : axes) z.push_back(std::clamp((p[k] - box.lo[k]) / (box.hi[k] - box.lo[k]), 0.0, 1.0));
  }
  const std::size_t n = points.size();
  if (d == 1) {  // exact: the largest end gap, or half the largest inner gap
    std::sort(z.begin(), z.end());
    double mu = std::max(z.front(), 1.0 - z.back());
    for (std::size_t i = 1; i < n; ++i) mu = std::max(mu, 0.5 * (z[i] - z[i - 1]));
    return mu;
  }
  auto farthest_from = [&](const double* probe) {  // min over the points of the distance to probe
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < n; ++i) {
      double s = 0.0;
      for (std::size_t k = 0; k < d; ++k) {
        const double diff = z[i * d + k] - probe[k];
        s += diff * diff;
      }
      best = std::min(best, s);
    }
    return best;
  };
  double mu2 = 0.0;
  std::vector<double> probe(d);
  // r: the largest odd count per axis with r^d <= budget (at least 3).
  std::size_t r = 3;
  auto fits = [&](std::size_t c) {
    double total = 1.0;
    for (std::size_t k = 0; k < d; ++k) total *= static_cast<double>(c);
    return total <= static_cast<double>(std::max<std::size_t>(grid_budget, 1));
  };
  if (fits(3)) {
    while (fits(r + 2)) r += 2;
    std::vector<std::size_t> idx(d, 0);
    while (true) {
      for (std::size_t k = 0; k < d; ++k) probe[k] = static_cast<double>(idx[k]) / static_cast<double>(r - 1);
      mu2 = std::max(mu2, farthest_from(probe.data()));
      std::size_t k = 0;  // odometer
      for (; k < d; ++k) {
        if (++idx[k] < r) break;
        idx[k] = 0;
      }
      if (k == d) break;
    }
  } else {  // too many dimensions for a grid: Halton probes (far from the seeds' own indices)
    const std::uint64_t offset = std::uint64_t{1} << 40;
    for (std::uint64_t i = 0; i < std::max<std::size_t>(grid_budget, 1); ++i) {
      for (std::size_t k = 0; k < d; ++k) probe[k] = radical_inverse(offset + i, kPrimes[k]);
      mu2 = std::max(mu2, farthest_from(probe.data()));
    }
  }
  return std::sqrt(mu2) / std::sqrt(static_cast<double>(d));
}

}  // namespace hyfal
