// See star_discrepancy.hpp for the estimate and the draw.
#include "core/search/samplers/star_discrepancy.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

namespace hyfal {

StarDiscrepancyGrid::StarDiscrepancyGrid(const Box& box, std::vector<int> dims, int boxes, double floor_frac)
    : box_(box), dims_(std::move(dims)), bx_(boxes), by_(1), floor_frac_(floor_frac) {
  if (boxes < 1) throw std::invalid_argument("star discrepancy: boxes must be >= 1");
  if (dims_.empty() || dims_.size() > 2) throw std::invalid_argument("star discrepancy: 1 or 2 projected dimensions");
  for (int d : dims_)
    if (d < 0 || static_cast<std::size_t>(d) >= box_.dim())
      throw std::invalid_argument("star discrepancy: projected dimension outside the state");
  if (!(floor_frac_ > 0.0)) throw std::invalid_argument("star discrepancy: the floor must be > 0");
  if (dims_.size() == 2) by_ = boxes;
  const std::size_t n = static_cast<std::size_t>(bx_) * static_cast<std::size_t>(by_);
  counts_.assign(n, 0);
  deficit_.assign(n, 0.0);
  corner_.assign(n, 0.0);
  weight_.assign(n, 0.0);
  cumulative_.assign(n, 0.0);
  refresh();
}

namespace {
// Index of x along one axis of [lo, hi] cut into k cells; -1 when outside.
int axis_cell(double x, double lo, double hi, int k) {
  if (!(x >= lo && x <= hi)) return -1;
  if (!(hi > lo)) return 0;
  const int i = static_cast<int>(std::floor((x - lo) / (hi - lo) * k));
  return std::clamp(i, 0, k - 1);
}
}  // namespace

std::optional<std::size_t> StarDiscrepancyGrid::cell_of(std::span<const double> x) const {
  const int ix = axis_cell(x[dims_[0]], box_.lo[dims_[0]], box_.hi[dims_[0]], bx_);
  if (ix < 0) return std::nullopt;
  int iy = 0;
  if (dims_.size() == 2) {
    iy = axis_cell(x[dims_[1]], box_.lo[dims_[1]], box_.hi[dims_[1]], by_);
    if (iy < 0) return std::nullopt;
  }
  return static_cast<std::size_t>(ix) + static_cast<std::size_t>(bx_) * static_cast<std::size_t>(iy);
}

bool StarDiscrepancyGrid::add(std::span<const double> x) {
  const auto c = cell_of(x);
  if (!c) return false;
  ++counts_[*c];
  ++total_;
  return true;
}

void StarDiscrepancyGrid::refresh() {
  const std::size_t W = static_cast<std::size_t>(bx_) + 1;
  // S[i + W j] = A([0, (i, j))): nodes in the cells ix < i, iy < j.
  std::vector<std::int64_t> S(W * (static_cast<std::size_t>(by_) + 1), 0);
  for (int j = 1; j <= by_; ++j)
    for (int i = 1; i <= bx_; ++i)
      S[i + W * j] = counts_[(i - 1) + static_cast<std::size_t>(bx_) * (j - 1)] + S[(i - 1) + W * j] +
                     S[i + W * (j - 1)] - S[(i - 1) + W * (j - 1)];
  const double N = static_cast<double>(total_);
  const double v = 1.0 / (static_cast<double>(bx_) * by_);
  auto vol = [&](int i, int j) { return (static_cast<double>(i) / bx_) * (static_cast<double>(j) / by_); };
  auto frac = [&](int i, int j) { return N > 0 ? static_cast<double>(S[i + W * j]) / N : 0.0; };

  upper_ = 0.0;
  lower_ = 0.0;
  for (int j = 0; j <= by_; ++j)
    for (int i = 0; i <= bx_; ++i) lower_ = std::max(lower_, std::abs(vol(i, j) - frac(i, j)));
  if (N == 0) lower_ = upper_ = 1.0;  // no point: D* = 1 by convention
  double acc = 0.0;
  for (int iy = 0; iy < by_; ++iy)
    for (int ix = 0; ix < bx_; ++ix) {
      const std::size_t b = static_cast<std::size_t>(ix) + static_cast<std::size_t>(bx_) * iy;
      const double p = N > 0 ? static_cast<double>(counts_[b]) / N : 0.0;
      deficit_[b] = std::max(v - p, 0.0);
      corner_[b] = std::max(vol(ix + 1, iy + 1) - frac(ix + 1, iy + 1), 0.0);
      if (N > 0) upper_ = std::max({upper_, frac(ix + 1, iy + 1) - vol(ix, iy), vol(ix + 1, iy + 1) - frac(ix, iy)});
      weight_[b] = deficit_[b] + corner_[b] + floor_frac_ * v;
      acc += weight_[b];
      cumulative_[b] = acc;
    }
}

std::optional<std::size_t> StarDiscrepancyGrid::sample(Rng& rng, double uniform_mix, std::span<double> x) const {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (std::size_t i = 0; i < box_.dim(); ++i) x[i] = box_.lo[i] + (box_.hi[i] - box_.lo[i]) * unit(rng);
  if (unit(rng) < uniform_mix) return std::nullopt;
  const double r = unit(rng) * cumulative_.back();
  const std::size_t b = std::min<std::size_t>(
      static_cast<std::size_t>(std::upper_bound(cumulative_.begin(), cumulative_.end(), r) - cumulative_.begin()),
      cumulative_.size() - 1);
  const int cell[2] = {static_cast<int>(b % static_cast<std::size_t>(bx_)),
                       static_cast<int>(b / static_cast<std::size_t>(bx_))};
  const int k[2] = {bx_, by_};
  for (std::size_t a = 0; a < dims_.size(); ++a) {
    const int d = dims_[a];
    const double w = (box_.hi[d] - box_.lo[d]) / k[a];
    x[d] = box_.lo[d] + w * (cell[a] + unit(rng));
  }
  return b;
}

}  // namespace hyfal
