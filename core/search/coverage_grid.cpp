#include "core/search/coverage_grid.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace hyfal {

CoverageGrid::CoverageGrid(const CoverageSpec& spec, std::size_t state_dim, std::size_t max_points)
    : spacing_(spec.spacing) {
  if (!(spec.spacing > 0.0)) throw std::invalid_argument("coverage grid: spacing must be > 0");
  if (spec.dims.empty())
    for (std::size_t i = 0; i < state_dim; ++i) dims_.push_back(static_cast<int>(i));
  else
    dims_ = spec.dims;
  if (spec.box.dim() != dims_.size())
    throw std::invalid_argument("coverage grid: the box does not match the coverage dimensions");
  std::int64_t total = 1;
  for (std::size_t k = 0; k < dims_.size(); ++k) {
    const double width = spec.box.hi[k] - spec.box.lo[k];
    if (!(width >= 0.0)) throw std::invalid_argument("coverage grid: empty box");
    const auto n = static_cast<std::int64_t>(std::floor(width / spacing_ + 1e-9)) + 1;
    lo_.push_back(spec.box.lo[k]);
    count_.push_back(n);
    stride_.push_back(total);
    total *= n;
    if (static_cast<std::size_t>(total) > max_points)
      throw std::invalid_argument(fmt::format("coverage grid: more than {} points", max_points));
  }
  distance_.assign(static_cast<std::size_t>(total), static_cast<float>(spacing_));
  sum_ = static_cast<double>(total) * spacing_;
  lo_idx_.resize(dims_.size());
  hi_idx_.resize(dims_.size());
  idx_.resize(dims_.size());
}

void CoverageGrid::add(std::span<const double> x) {
  const std::size_t d = dims_.size();
  // Grid points within δ of x lie in the index box [ceil((x-δ-lo)/δ), floor((x+δ-lo)/δ)].
  bool empty = false;
  for (std::size_t k = 0; k < d; ++k) {
    const double t = (x[dims_[k]] - lo_[k]) / spacing_;
    lo_idx_[k] = std::max<std::int64_t>(0, static_cast<std::int64_t>(std::ceil(t - 1.0)));
    hi_idx_[k] = std::min<std::int64_t>(count_[k] - 1, static_cast<std::int64_t>(std::floor(t + 1.0)));
    if (lo_idx_[k] > hi_idx_[k]) empty = true;
  }
  if (!empty) {
    idx_ = lo_idx_;
    while (true) {
      std::int64_t flat = 0;
      double d2 = 0.0;
      for (std::size_t k = 0; k < d; ++k) {
        flat += idx_[k] * stride_[k];
        const double diff = lo_[k] + static_cast<double>(idx_[k]) * spacing_ - x[dims_[k]];
        d2 += diff * diff;
      }
      const double dist = std::sqrt(d2);
      float& cell = distance_[static_cast<std::size_t>(flat)];
      if (dist < cell) {
        sum_ += dist - cell;
        cell = static_cast<float>(dist);
      }
      std::size_t k = 0;  // odometer over the index box
      for (; k < d; ++k) {
        if (++idx_[k] <= hi_idx_[k]) break;
        idx_[k] = lo_idx_[k];
      }
      if (k == d) break;
    }
  }
  history_.push_back(coverage());
}

double CoverageGrid::coverage() const { return 1.0 - sum_ / (static_cast<double>(distance_.size()) * spacing_); }

double CoverageGrid::growth(std::size_t window) const {
  if (history_.empty() || window == 0) return 0.0;
  const std::size_t w = std::min(window, history_.size() - 1);
  if (w == 0) return history_.back();
  return (history_.back() - history_[history_.size() - 1 - w]) / static_cast<double>(w);
}

double CoverageGrid::coverage_of(const CoverageSpec& spec, std::size_t state_dim,
                                 const std::vector<std::vector<double>>& nodes) {
  CoverageGrid g(spec, state_dim);
  const std::size_t d = g.dims_.size();
  double sum = 0.0;
  std::vector<std::int64_t> idx(d, 0);
  for (std::size_t flat = 0; flat < g.distance_.size(); ++flat) {
    double best = spec.spacing;
    for (const auto& x : nodes) {
      double d2 = 0.0;
      for (std::size_t k = 0; k < d; ++k) {
        const double diff = g.lo_[k] + static_cast<double>(idx[k]) * spec.spacing - x[g.dims_[k]];
        d2 += diff * diff;
      }
      best = std::min(best, std::sqrt(d2));
    }
    sum += best;
    for (std::size_t k = 0; k < d; ++k) {
      if (++idx[k] < g.count_[k]) break;
      idx[k] = 0;
    }
  }
  return 1.0 - sum / (static_cast<double>(g.distance_.size()) * spec.spacing);
}

}  // namespace hyfal
