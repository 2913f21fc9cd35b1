// History-based weighting, seed 000 eq. (III.3):
//
//   H(x_j, x_rand; rho) = (rho_j - rho_min) / (rho_max - rho_min) + (n_j - n_min) / (n_max - n_min)
//
// over the candidate set (the whole tree in the paper; the k nearest in the cheap variant),
// where n_j counts the failed extensions of node j. A zero range makes its term 0; an infinite
// distance (t2go with no closing input) takes the worst normalized value 1. Returns the index
// of the candidate with the smallest H (the first on ties), or npos when the set is empty.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>

namespace hyfal {

inline constexpr std::size_t kNoCandidate = static_cast<std::size_t>(-1);

inline std::size_t argmin_history_weight(std::span<const double> rho, std::span<const std::uint32_t> n) {
  if (rho.empty()) return kNoCandidate;
  double rmin = std::numeric_limits<double>::infinity(), rmax = -rmin;
  std::uint32_t nmin = std::numeric_limits<std::uint32_t>::max(), nmax = 0;
  for (std::size_t i = 0; i < rho.size(); ++i) {
    if (std::isfinite(rho[i])) {
      rmin = std::min(rmin, rho[i]);
      rmax = std::max(rmax, rho[i]);
    }
    nmin = std::min(nmin, n[i]);
    nmax = std::max(nmax, n[i]);
  }
  const double rrange = rmax - rmin, nrange = static_cast<double>(nmax - nmin);
  std::size_t best = kNoCandidate;
  double best_h = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < rho.size(); ++i) {
    const double hr = !std::isfinite(rho[i]) ? 1.0 : (rrange > 0.0 ? (rho[i] - rmin) / rrange : 0.0);
    const double hn = nrange > 0.0 ? static_cast<double>(n[i] - nmin) / nrange : 0.0;
    const double h = hr + hn;
    if (h < best_h) {
      best_h = h;
      best = i;
    }
  }
  return best;
}

}  // namespace hyfal
