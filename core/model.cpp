#include "core/model.hpp"

#include <stdexcept>

namespace hyfal {

InputSet InputSet::grid(Box box, int levels) {
  if (levels < 1) throw std::invalid_argument("input discretization needs at least 1 level");
  InputSet s;
  s.box = std::move(box);
  const std::size_t m = s.box.dim();
  std::size_t count = 1;
  for (std::size_t i = 0; i < m; ++i) count *= static_cast<std::size_t>(levels);
  s.values.reserve(count * m);
  std::vector<int> idx(m, 0);
  for (std::size_t j = 0; j < count; ++j) {
    for (std::size_t i = 0; i < m; ++i) {
      const double a = s.box.lo[i], b = s.box.hi[i];
      s.values.push_back(levels == 1 ? 0.5 * (a + b) : a + (b - a) * idx[i] / (levels - 1));
    }
    for (std::size_t i = 0; i < m; ++i) {  // odometer increment
      if (++idx[i] < levels) break;
      idx[i] = 0;
    }
  }
  return s;
}

}  // namespace hyfal
