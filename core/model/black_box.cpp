#include "core/model/black_box.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <set>
#include <stdexcept>

#include <fmt/format.h>
#include <fmt/ranges.h>

namespace hyfal {

namespace {

class BlackBoxSystem final : public System {
 public:
  BlackBoxSystem(SystemInfo info, Box box, std::shared_ptr<const stl::SignalModel> model)
      : info_(std::move(info)), model_(std::move(model)) {
    inputs_.box = std::move(box);
  }
  const SystemInfo& info() const override { return info_; }
  bool valid_mode(Mode q) const override { return q == 0; }
  const InputSet& inputs(Mode) const override { return inputs_; }
  std::string mode_name(Mode q) const override { return q == 0 ? "model" : std::to_string(q) + " (not a mode)"; }
  void derivative(Mode, std::span<const double>, std::span<const double>, std::span<const double>,
                  std::span<double>) const override {}
  int guard_count(Mode) const override { return 0; }
  double guard(Mode, int, std::span<const double>, std::span<const double>) const override { return -1.0; }
  Mode jump(Mode q, int, std::span<double>, std::span<const double>) const override { return q; }
  bool invariant(Mode, std::span<const double>, std::span<const double>) const override { return true; }
  // No unsafe set: the requirement alone decides (the `safety` signal is 1 throughout).
  double spec(Mode, std::span<const double>, std::span<const double>) const override { return 1.0; }
  std::unique_ptr<Propagator> make_propagator(const IntegratorSettings&) const override {
    throw std::invalid_argument(
        fmt::format("'{}' is a model known only by its simulations: it has no state to propagate",
                    info_.instance.value("name", std::string("model"))));
  }
  const stl::SignalModel* signal_model() const override { return model_.get(); }

 private:
  SystemInfo info_;
  InputSet inputs_;
  std::shared_ptr<const stl::SignalModel> model_;
};

void check_names(const std::vector<std::string>& names, const char* what, std::set<std::string>& seen) {
  if (names.empty()) throw std::invalid_argument(fmt::format("a black box needs at least one {}", what));
  for (const std::string& n : names) {
    const bool identifier =
        !n.empty() && (std::isalpha(static_cast<unsigned char>(n[0])) || n[0] == '_') &&
        std::all_of(n.begin(), n.end(), [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; });
    if (!identifier)
      throw std::invalid_argument(
          fmt::format("{} '{}' is not a name STL formulas can read (letters, digits, '_')", what, n));
    if (n == "safety" || !seen.insert(n).second)
      throw std::invalid_argument(fmt::format("{} '{}' is named twice (or is the reserved 'safety')", what, n));
  }
}

}  // namespace

std::shared_ptr<const System> make_black_box(const BlackBoxSpec& spec, std::shared_ptr<const stl::SignalModel> model) {
  if (!model) throw std::invalid_argument("a black box needs a model");
  std::set<std::string> seen;
  check_names(spec.input_names, "input", seen);
  check_names(spec.output_names, "signal", seen);
  if (spec.input_box.lo.size() != spec.input_names.size() || spec.input_box.hi.size() != spec.input_names.size())
    throw std::invalid_argument("a black box needs one range per input");
  for (std::size_t i = 0; i < spec.input_names.size(); ++i)
    if (!(std::isfinite(spec.input_box.lo[i]) && std::isfinite(spec.input_box.hi[i]) &&
          spec.input_box.lo[i] <= spec.input_box.hi[i]))
      throw std::invalid_argument(fmt::format("input '{}': the range [{}, {}] is not finite with lo <= hi",
                                              spec.input_names[i], spec.input_box.lo[i], spec.input_box.hi[i]));
  if (!(std::isfinite(spec.horizon) && spec.horizon > 0.0))
    throw std::invalid_argument(fmt::format("horizon = {}: must be a positive number of seconds", spec.horizon));
  if (!(std::isfinite(spec.step) && spec.step > 0.0))
    throw std::invalid_argument(fmt::format("step = {}: must be a positive number of seconds", spec.step));
  if (spec.step > spec.horizon)
    throw std::invalid_argument(
        fmt::format("step = {} is longer than the horizon {}: the input signal holds pieces of "
                    "step seconds within the horizon",
                    spec.step, spec.horizon));
  SystemInfo info;
  info.suite = "black-box";
  Json ranges = Json::object();
  for (std::size_t i = 0; i < spec.input_names.size(); ++i)
    ranges[spec.input_names[i]] = {spec.input_box.lo[i], spec.input_box.hi[i]};
  info.instance = {{"name", spec.name},
                   {"inputs", ranges},
                   {"signals", spec.output_names},
                   {"horizon", spec.horizon},
                   {"step", spec.step}};
  info.input_names = spec.input_names;
  for (const std::string& n : spec.output_names) info.outputs.push_back({n, "", "the model's signal"});
  info.initial_mode = 0;
  info.step_duration = spec.step;
  info.held_inputs = true;
  info.interpolated_inputs = true;
  info.integrator.max_step = spec.step / 10.0;  // a linear signal's pieces
  info.integrator.step = spec.step / 10.0;
  return std::make_shared<BlackBoxSystem>(std::move(info), spec.input_box, std::move(model));
}

}  // namespace hyfal
