// Input signals as the simulators take them: pieces of constant input, made from control points
// joined by lines (linear_signal_pieces) or from samples held or interpolated (sampled_signal_pieces,
// what `hyfal simulate` reads from a CSV and the Python module from arrays).
#pragma once
#include <cstddef>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "core/model/signal_model.hpp"
#include "core/model/system.hpp"

namespace hyfal::stl {

// The signal through control points (times[k], values[k]), linear between consecutive ones (S-TaLiRo's
// and Breach's default interpolation; the Simulink trace's inputs), as pieces of constant input:
// each interval cut into ceil(length / step) equal pieces holding the line's value at their
// midpoints (the integral of the input over each piece is exact; a model affine in u sees the
// exact input mean over every integration step when step is its integrator's). Times increase;
// values.size() == times.size(). The signal ends at the last control point.
// The line from a to b at weight w in [0, 1], kept between a and b (a rounding of the line must
// not step outside an input box whose bound is a or b).
inline double linear_value(double a, double b, double w) {
  const double v = (1.0 - w) * a + w * b;
  return a <= b ? (v < a ? a : v > b ? b : v) : (v < b ? b : v > a ? a : v);
}

// weights, when given, receives each piece's ControlWeights (signal_model.hpp).
std::vector<InputPiece> linear_signal_pieces(std::span<const double> times, std::span<const std::vector<double>> values,
                                             double step, std::vector<ControlWeights>* weights = nullptr);

// An input signal given at samples, as `hyfal simulate` reads it from a CSV and the Python module
// from arrays: values[k] (one per input) at times[k]; held from times[k] to times[k + 1] (zoh), or,
// with linear_step > 0, the line through the samples cut into pieces of at most linear_step
// (linear_signal_pieces). What either accepts: at least two samples, times from 0 and increasing,
// each value inside `box` up to 1e-9 (then clamped into it). The first sample that breaks it, in
// sample order and, within a sample, time first, then the inputs in order.
struct SampledSignalProblem {
  enum class Kind { too_few, first_time, not_increasing, outside } kind;
  std::size_t sample = 0, input = 0;  // input: for `outside`
  double value = 0.0;                 // the time (first_time, not_increasing) or the value (outside)
};
std::optional<SampledSignalProblem> sampled_signal_problem(std::span<const double> times,
                                                           std::span<const std::vector<double>> values, const Box& box);
// The pieces of a signal sampled_signal_problem accepts (values clamped into `box`).
std::vector<InputPiece> sampled_signal_pieces(std::span<const double> times, std::vector<std::vector<double>> values,
                                              const Box& box, double linear_step,
                                              std::vector<ControlWeights>* weights = nullptr);
// The pieces a linear signal is cut into for `info`'s system: its integrator's (largest) step.
double linear_piece_step(const SystemInfo& info);
// The input `name` names: an input's name or an alias the suite declares (SystemInfo::input_aliases,
// e.g. ARCH-COMP's `throttle`), case-insensitively; info.input_names.size() when none.
std::size_t input_named(const SystemInfo& info, std::string_view name);

}  // namespace hyfal::stl
