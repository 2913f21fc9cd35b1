// ModelSystem<M>: the System interface over one concrete HybridModel (type erasure at the
// granularity of a propagation, not of an RK stage).
#pragma once
#include <algorithm>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>

#include "core/model/system.hpp"
#include "core/simulate/model_propagator.hpp"
#include "core/simulate/tangent_model.hpp"

namespace hyfal {

template <class M>
concept ModelWithInputs = HybridModel<M> && requires(const M m, Mode q) {
  { m.inputs(q) } -> std::convertible_to<const InputSet&>;
};

template <ModelWithInputs M>
class ModelSystem final : public System {
 public:
  ModelSystem(M model, SystemInfo info) : model_(std::move(model)), info_(std::move(info)) {}

  const M& model() const { return model_; }
  const SystemInfo& info() const override { return info_; }
  bool valid_mode(Mode q) const override { return model_.valid_mode(q); }
  const InputSet& inputs(Mode q) const override { return model_.inputs(q); }
  std::string mode_name(Mode q) const override {
    // A model's mode_name may index tables with q: never hand it an invalid one.
    if (!model_.valid_mode(q)) return std::to_string(q) + " (not a mode)";
    if constexpr (requires { model_.mode_name(q); })
      return model_.mode_name(q);
    else
      return std::to_string(q);
  }
  void derivative(Mode q, std::span<const double> x, std::span<const double> u, std::span<const double> p,
                  std::span<double> dx) const override {
    model_.flow(q, x.data(), u.data(), p.data(), dx.data());
    if constexpr (requires { M::flowing_dim; })  // the flow need not write its frozen tail (model.hpp)
      std::fill(dx.begin() + M::flowing_dim, dx.end(), 0.0);
  }
  bool input_affine(Mode) const override {
    if constexpr (requires { M::input_affine; })
      return M::input_affine;
    else
      return false;
  }
  bool state_dependent_inputs() const override {
    if constexpr (requires { model_.state_dependent_inputs(); })
      return model_.state_dependent_inputs();
    else
      return false;
  }
  void input_bounds(Mode q, std::span<const double> x, std::span<double> lo, std::span<double> hi) const override {
    if constexpr (requires { model_.input_bounds(q, x.data(), lo.data(), hi.data()); })
      model_.input_bounds(q, x.data(), lo.data(), hi.data());
    else
      System::input_bounds(q, x, lo, hi);
  }
  int guard_count(Mode q) const override { return model_.guard_count(q); }
  double guard(Mode q, int k, std::span<const double> x, std::span<const double> p) const override {
    if constexpr (StateGuards<M>)
      return model_.guard(q, k, x.data(), p.data());
    else
      throw std::logic_error("the guards of this model read the input: call guard_with_input");
  }
  double guard_with_input(Mode q, int k, std::span<const double> x, std::span<const double> u,
                          std::span<const double> p) const override {
    if constexpr (StateGuards<M>)
      return model_.guard(q, k, x.data(), p.data());
    else
      return model_.guard(q, k, x.data(), u.data(), p.data());
  }
  Mode jump(Mode q, int k, std::span<double> x, std::span<const double> p) const override {
    return model_.jump(q, k, x.data(), p.data());
  }
  bool invariant(Mode q, std::span<const double> x, std::span<const double> p) const override {
    return model_.invariant(q, x.data(), p.data());
  }
  double spec(Mode q, std::span<const double> x, std::span<const double> p) const override {
    return model_.spec(q, x.data(), p.data());
  }
  void outputs(Mode q, std::span<const double> x, std::span<const double> u, std::span<const double> p,
               std::span<double> y) const override {
    if constexpr (requires { model_.outputs(q, x.data(), u.data(), p.data(), y.data()); })
      model_.outputs(q, x.data(), u.data(), p.data(), y.data());
  }
  std::unique_ptr<Propagator> make_propagator(const IntegratorSettings& s) const override {
    return std::make_unique<ModelPropagator<M>>(model_, s);
  }
  using System::make_propagator;
  std::unique_ptr<TangentPropagator> make_tangent_propagator(std::size_t variables,
                                                             const IntegratorSettings& s) const override {
    if (s.kind != IntegratorKind::rk4) return nullptr;  // tangent_model.hpp: RK4 only
    return std::make_unique<ModelTangentPropagator<M>>(model_, info_.input_names.size(), variables, s);
  }
  using System::make_tangent_propagator;
  const Decomposition* decomposition() const override {
    if constexpr (requires {
                    { model_.decomposition() } -> std::convertible_to<const Decomposition*>;
                  })
      return model_.decomposition();
    else
      return nullptr;
  }

 private:
  M model_;
  SystemInfo info_;
};

}  // namespace hyfal
