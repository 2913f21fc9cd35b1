#include "core/simulate/input_signal.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <stdexcept>

namespace hyfal::stl {

std::vector<InputPiece> linear_signal_pieces(std::span<const double> times, std::span<const std::vector<double>> values,
                                             double step, std::vector<ControlWeights>* weights) {
  if (weights) weights->clear();
  if (times.size() != values.size()) throw std::invalid_argument("linear_signal_pieces: one value per control point");
  if (!(step > 0.0)) throw std::invalid_argument("linear_signal_pieces: the step must be > 0");
  std::vector<InputPiece> pieces;
  for (std::size_t k = 0; k + 1 < times.size(); ++k) {
    const double length = times[k + 1] - times[k];
    if (!(length > 0.0)) throw std::invalid_argument("linear_signal_pieces: times must increase");
    const auto n = static_cast<std::size_t>(std::max(1.0, std::ceil(length / step - 1e-9)));
    const double h = length / static_cast<double>(n);
    for (std::size_t j = 0; j < n; ++j) {
      const double w = (static_cast<double>(j) + 0.5) / static_cast<double>(n);  // the midpoint's weight on the end
      InputPiece p{h, std::vector<double>(values[k].size())};
      for (std::size_t i = 0; i < p.u.size(); ++i) p.u[i] = linear_value(values[k][i], values[k + 1][i], w);
      if (weights) weights->push_back({k, 1.0 - w, w});
      pieces.push_back(std::move(p));
    }
  }
  return pieces;
}

std::optional<SampledSignalProblem> sampled_signal_problem(std::span<const double> times,
                                                           std::span<const std::vector<double>> values,
                                                           const Box& box) {
  using Kind = SampledSignalProblem::Kind;
  for (std::size_t k = 0; k < times.size(); ++k) {
    if (k == 0 && times[0] != 0.0) return SampledSignalProblem{Kind::first_time, 0, 0, times[0]};
    if (k > 0 && !(times[k] > times[k - 1])) return SampledSignalProblem{Kind::not_increasing, k, 0, times[k]};
    for (std::size_t i = 0; i < box.dim() && i < values[k].size(); ++i)
      if (values[k][i] < box.lo[i] - 1e-9 || values[k][i] > box.hi[i] + 1e-9)
        return SampledSignalProblem{Kind::outside, k, i, values[k][i]};
  }
  if (times.size() < 2) return SampledSignalProblem{Kind::too_few, times.size(), 0, 0.0};
  return std::nullopt;
}

std::vector<InputPiece> sampled_signal_pieces(std::span<const double> times, std::vector<std::vector<double>> values,
                                              const Box& box, double linear_step,
                                              std::vector<ControlWeights>* weights) {
  for (auto& u : values)
    for (std::size_t i = 0; i < box.dim() && i < u.size(); ++i) u[i] = std::clamp(u[i], box.lo[i], box.hi[i]);
  if (linear_step > 0.0) return linear_signal_pieces(times, values, linear_step, weights);
  std::vector<InputPiece> pieces;
  if (weights) weights->clear();
  for (std::size_t k = 0; k + 1 < times.size(); ++k) {
    pieces.push_back({times[k + 1] - times[k], std::move(values[k])});
    if (weights) weights->push_back({k, 1.0, 0.0});
  }
  return pieces;
}

double linear_piece_step(const SystemInfo& info) { return std::min(info.integrator.max_step, info.integrator.step); }

std::size_t input_named(const SystemInfo& info, std::string_view name) {
  const auto same = [&](std::string_view a) {
    return a.size() == name.size() && std::equal(a.begin(), a.end(), name.begin(), [](char x, char y) {
             return std::tolower(static_cast<unsigned char>(x)) == std::tolower(static_cast<unsigned char>(y));
           });
  };
  for (std::size_t i = 0; i < info.input_names.size(); ++i) {
    if (same(info.input_names[i])) return i;
    if (i < info.input_aliases.size())
      for (const auto& alias : info.input_aliases[i])
        if (same(alias)) return i;
  }
  return info.input_names.size();
}

}  // namespace hyfal::stl
