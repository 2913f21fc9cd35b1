// Ū at a state: the discretized inputs a tree extension tries from (x, q).
//
// For a system whose admissible inputs do not depend on the state this is Ū_q itself (no
// copy). For a state-dependent one (a driver model, seed 002 Sect. 4.1.2: the driver picks u
// from an interval that depends on the speed) Ū_q is mapped affinely from U_q's box onto
// System::input_bounds(q, x), so that the grid keeps its shape (the same number of levels,
// endpoints included) and every input tried is admissible at x. One InputGrid per thread;
// no allocation after the first use of the largest Ū.
//
// The suite's input policy (SystemInfo::continuous_random_inputs) is every method's: when it is
// set (navigation's drivers draw u "pseudo-uniformly at random" from an interval, seed 002
// Sect. 4.1.2), draw() replaces the grid by SystemInfo::random_inputs_per_extension fresh uniform
// draws from the admissible box, so a method that tries every input of Ū (rrt, rrt-dstar, rrft,
// enhanced-rrt) tries that many random inputs, drawn the same way as HyDICE draws its one.
#pragma once
#include <algorithm>
#include <span>
#include <vector>

#include "core/model/system.hpp"
#include "core/search/input_levels.hpp"
#include "core/util/rng.hpp"

namespace hyfal {

// u uniform on the box [lo, hi] (one unit draw per dimension, in order), clamped at hi where
// lo + t (hi - lo) rounds past it.
template <class Urbg>
inline void draw_uniform_input(Urbg& rng, std::span<const double> lo, std::span<const double> hi, std::span<double> u) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (std::size_t i = 0; i < u.size(); ++i) u[i] = std::min(hi[i], lo[i] + unit(rng) * (hi[i] - lo[i]));
}

class InputGrid {
 public:
  explicit InputGrid(const System& system) : system_(system), dependent_(system.state_dependent_inputs()) {}

  // Selects Ū at (q, x); the spans from input() stay valid until the next call.
  void at(Mode q, std::span<const double> x) {
    set_ = &system_.inputs(q);
    drawn_ = 0;
    if (!dependent_) return;
    const std::size_t m = set_->dim(), k = set_->count();
    lo_.resize(m);
    hi_.resize(m);
    system_.input_bounds(q, x, lo_, hi_);
    mapped_.resize(m * k);
    const Box& box = set_->box;
    for (std::size_t j = 0; j < k; ++j)
      for (std::size_t i = 0; i < m; ++i)
        mapped_[j * m + i] = map_onto(set_->values[j * m + i], box.lo[i], box.hi[i], lo_[i], hi_[i]);
  }
  // The affine image of v in [from_lo, from_hi] on [lo, hi]: lo + t (hi - lo) with t the position
  // of v in its interval (the middle when that interval is a point), exact at both ends so that
  // the endpoints stay admissible. Also how the OMPL methods map a control (core/planners/ompl).
  static double map_onto(double v, double from_lo, double from_hi, double lo, double hi) {
    const double width = from_hi - from_lo;
    const double t = width > 0.0 ? (v - from_lo) / width : 0.5;
    return t >= 1.0 ? hi : t <= 0.0 ? lo : std::min(hi, lo + t * (hi - lo));
  }
  // Ū at (q, x) under the suite's input policy: at(q, x), or, for continuous random inputs,
  // count() fresh uniform draws from the admissible box at x (from `rng`).
  void draw(Mode q, std::span<const double> x, Rng& rng) {
    if (!system_.info().continuous_random_inputs) return at(q, x);
    set_ = &system_.inputs(q);
    const std::size_t m = set_->dim(), k = static_cast<std::size_t>(system_.info().random_inputs_per_extension);
    lo_.resize(m);
    hi_.resize(m);
    system_.input_bounds(q, x, lo_, hi_);
    mapped_.resize(m * k);
    for (std::size_t j = 0; j < k; ++j) draw_uniform_input(rng, lo_, hi_, std::span<double>(mapped_.data() + j * m, m));
    drawn_ = k;
  }
  // Input refinement (the trees' option input_refinement): instead of Ū, `values` inputs of the
  // dyadic refinement sequence (core/search/input_levels.hpp: the corners, then the midpoints, then the
  // quarter points, ...) mapped onto the admissible box at (q, x), its `chunk`-th run of `values`
  // (wrapping around at the sequence's end), after `held` (the input the node was reached with;
  // left out when empty or not admissible at x), so that a refined value can be held on.
  void refine(Mode q, std::span<const double> x, std::size_t chunk, std::size_t values, std::span<const double> held) {
    set_ = &system_.inputs(q);
    const std::size_t m = set_->dim();
    if (sequence_.empty()) sequence_ = dyadic_refinement_sequence(m, 4096);
    lo_.resize(m);
    hi_.resize(m);
    if (dependent_) {
      system_.input_bounds(q, x, lo_, hi_);
    } else {
      std::copy(set_->box.lo.begin(), set_->box.lo.end(), lo_.begin());
      std::copy(set_->box.hi.begin(), set_->box.hi.end(), hi_.begin());
    }
    mapped_.clear();
    bool admissible = held.size() == m;
    for (std::size_t i = 0; admissible && i < m; ++i) admissible = held[i] >= lo_[i] && held[i] <= hi_[i];
    if (admissible) mapped_.insert(mapped_.end(), held.begin(), held.end());
    const std::size_t total = sequence_.size() / m;
    for (std::size_t k = 0; k < values; ++k) {
      const double* f = sequence_.data() + ((chunk * values + k) % total) * m;
      for (std::size_t i = 0; i < m; ++i)
        mapped_.push_back(f[i] >= 1.0   ? hi_[i]
                          : f[i] <= 0.0 ? lo_[i]
                                        : std::min(hi_[i], lo_[i] + f[i] * (hi_[i] - lo_[i])));
    }
    drawn_ = mapped_.size() / m;
  }
  std::size_t count() const { return drawn_ > 0 ? drawn_ : set_->count(); }
  std::span<const double> input(std::size_t j) const {
    if (!dependent_ && drawn_ == 0) return set_->input(j);
    const std::size_t m = set_->dim();
    return {mapped_.data() + j * m, m};
  }

 private:
  const System& system_;
  bool dependent_;
  std::size_t drawn_ = 0;  // inputs drawn by the last call (draw() with continuous random inputs), else 0
  const InputSet* set_ = nullptr;
  std::vector<double> lo_, hi_, mapped_;
  std::vector<double> sequence_;  // the dyadic refinement sequence, fractions (refine())
};

}  // namespace hyfal
