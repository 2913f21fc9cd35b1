// Ū at a state: the discretized inputs a tree extension tries from (x, q).
//
// For a system whose admissible inputs do not depend on the state this is Ū_q itself (no
// copy). For a state-dependent one (a driver model, seed 002 Sect. 4.1.2: the driver picks u
// from an interval that depends on the speed) Ū_q is mapped affinely from U_q's box onto
// System::input_bounds(q, x), so that the grid keeps its shape (the same number of levels,
// endpoints included) and every input tried is admissible at x. One InputGrid per thread;
// no allocation after the first use of the largest Ū.
#pragma once
#include <algorithm>
#include <span>
#include <vector>

#include "core/model.hpp"

namespace hyfal {

class InputGrid {
 public:
  explicit InputGrid(const System& system)
      : system_(system), dependent_(system.state_dependent_inputs()) {}

  // Selects Ū at (q, x); the spans from input() stay valid until the next call.
  void at(Mode q, std::span<const double> x) {
    set_ = &system_.inputs(q);
    if (!dependent_) return;
    const std::size_t m = set_->dim(), k = set_->count();
    lo_.resize(m);
    hi_.resize(m);
    system_.input_bounds(q, x, lo_, hi_);
    mapped_.resize(m * k);
    const Box& box = set_->box;
    for (std::size_t j = 0; j < k; ++j)
      for (std::size_t i = 0; i < m; ++i) {
        const double width = box.hi[i] - box.lo[i];
        const double t = width > 0.0 ? (set_->values[j * m + i] - box.lo[i]) / width : 0.5;
        // lo + t (hi - lo), exact at both ends so that the endpoints stay admissible.
        mapped_[j * m + i] = t >= 1.0 ? hi_[i] : t <= 0.0 ? lo_[i] : std::min(hi_[i], lo_[i] + t * (hi_[i] - lo_[i]));
      }
  }
  std::size_t count() const { return set_->count(); }
  std::span<const double> input(std::size_t j) const {
    if (!dependent_) return set_->input(j);
    const std::size_t m = set_->dim();
    return {mapped_.data() + j * m, m};
  }

 private:
  const System& system_;
  bool dependent_;
  const InputSet* set_ = nullptr;
  std::vector<double> lo_, hi_, mapped_;
};

}  // namespace hyfal
