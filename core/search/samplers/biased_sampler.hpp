// Sampling distributions for x_rand.
//
// BiasedSampler is B(x; µ, β) of seed 000 eq. (III.6), per dimension on [a, b]: the Gaussian
// N(x; µ, σ) plus its truncated mass C_t spread uniformly, drawn exactly as the paper suggests —
// a normal draw, replaced by a uniform draw on [a, b] when it falls outside. Its width is
// σ(β) = (1 - β)(σ_max - σ_min) + σ_min (III.7), in units of the box width b - a. A NaN
// component of µ leaves that dimension uniform. AdaptiveBias keeps the β statistics of (III.5).
#pragma once
#include <cmath>
#include <random>
#include <span>
#include <vector>

#include "core/model/system.hpp"
#include "core/util/rng.hpp"

namespace hyfal {

class BiasedSampler {
 public:
  BiasedSampler(const Box& box, std::vector<double> mu, double sigma_min, double sigma_max)
      : box_(box), mu_(std::move(mu)), sigma_min_(sigma_min), sigma_max_(sigma_max) {}

  // σ(β) of (III.7), as a fraction of the box width.
  double sigma(double beta) const { return (1.0 - beta) * (sigma_max_ - sigma_min_) + sigma_min_; }

  void sample(Rng& rng, double beta, std::span<double> x) const {
    const double s = sigma(beta);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (std::size_t i = 0; i < box_.dim(); ++i) {
      const double a = box_.lo[i], b = box_.hi[i];
      if (!std::isnan(mu_[i])) {
        std::normal_distribution<double> normal(mu_[i], s * (b - a));
        const double z = normal(rng);
        if (z >= a && z <= b) {
          x[i] = z;
          continue;
        }
      }
      x[i] = a + (b - a) * unit(rng);  // the truncated mass C_t, spread uniformly
    }
  }

 private:
  Box box_;
  std::vector<double> mu_;
  double sigma_min_, sigma_max_;
};

// β = n_s / n_β of (III.5), recomputed every N_s iterations: n_β counts the iterations whose
// sample fell inside S and n_s, among them, the successful ones (the tree grew toward x_rand,
// rho(x_new, x_rand) < rho(x_near, x_rand)). Starts at β = 1 (heaviest bias), as Alg. 3.
// Seed 000 says when β is recomputed but not that the counts restart, so by default they run
// over the whole search (Counts::run): β is the success rate of every sample drawn in S so far.
// Counts::window restarts them every N_s iterations (a window with no sample in S keeps β); it
// locks β at 0 once a window's few samples in S all fail, because at β = 0 (σ = σ_max) almost
// no sample lands in a small S again (hovercraft: β = 0 in ~94 % of the updates).
class AdaptiveBias {
 public:
  enum class Counts { run, window };
  explicit AdaptiveBias(int n_s, Counts counts = Counts::run) : window_(n_s < 1 ? 1 : n_s), counts_(counts) {}
  double beta() const { return beta_; }
  // Records one iteration; returns true when β was recomputed.
  bool record(bool sample_in_spec, bool successful) {
    if (sample_in_spec) {
      ++n_beta_;
      n_s_ += successful;
    }
    if (++iterations_ % window_ != 0) return false;
    if (n_beta_ > 0) beta_ = static_cast<double>(n_s_) / static_cast<double>(n_beta_);
    if (counts_ == Counts::window) n_s_ = n_beta_ = 0;
    return true;
  }

 private:
  long window_;
  Counts counts_;
  long iterations_ = 0;
  long n_s_ = 0, n_beta_ = 0;
  double beta_ = 1.0;
};

}  // namespace hyfal
