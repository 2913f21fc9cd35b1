#include "core/model/system.hpp"

#include <algorithm>
#include <stdexcept>

#include <fmt/format.h>

namespace hyfal {

InputSet InputSet::grid(Box box, int levels) {
  if (levels < 1) throw std::invalid_argument("input discretization needs at least 1 level");
  InputSet s;
  s.box = std::move(box);
  const std::size_t m = s.box.dim();
  // Every method tries each element of Ū per extension: a grid beyond this is a setting error,
  // not a search (and its size must not overflow or exhaust memory).
  constexpr std::size_t kMaxInputs = 1'000'000;
  std::size_t count = 1;
  for (std::size_t i = 0; i < m; ++i) {
    count *= static_cast<std::size_t>(levels);
    if (count > kMaxInputs)
      throw std::invalid_argument(
          fmt::format("input grid: {} levels in {} dimensions exceed {} inputs", levels, m, kMaxInputs));
  }
  s.values.reserve(count * m);
  std::vector<int> idx(m, 0);
  for (std::size_t j = 0; j < count; ++j) {
    for (std::size_t i = 0; i < m; ++i) {
      const double a = s.box.lo[i], b = s.box.hi[i];
      // Clamped: a + (b - a) * k / (levels - 1) may round past b, and U_q is closed.
      s.values.push_back(levels == 1 ? 0.5 * (a + b) : std::clamp(a + (b - a) * idx[i] / (levels - 1), a, b));
    }
    for (std::size_t i = 0; i < m; ++i) {  // odometer increment
      if (++idx[i] < levels) break;
      idx[i] = 0;
    }
  }
  return s;
}

}  // namespace hyfal
