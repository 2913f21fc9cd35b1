// A model known only by its simulations (core/model/black_box.hpp), with a C++ stl::SignalModel: the
// signal searches falsify it and its witnesses validate by running the model again; a witness
// whose input was changed is refused; the trees are refused before a run; a model that fails
// ends the trial with its message; bad specifications are refused.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/model/black_box.hpp"
#include "core/run/option_spec.hpp"
#include "core/requirements/requirement.hpp"
#include "core/witness/witness.hpp"
#include "core/witness/validator.hpp"
#include "suites/registry.hpp"
#include "core/run/method_entry.hpp"
#include "core/model/signal_model.hpp"

namespace hyfal {
namespace {

// y(t) = the running mean of u from 0 to t, at 0.1 s samples: y > 0.9 over a 10 s signal needs
// u near its top from the start.
class RunningMean final : public stl::SignalModel {
 public:
  mutable std::atomic<int> calls{0};
  bool fail = false;
  void simulate(std::span<const stl::InputPiece> pieces, std::span<const double>, std::vector<double>& time,
                std::vector<std::vector<double>>& outputs) const override {
    ++calls;
    if (fail) throw std::runtime_error("the model broke");
    time.clear();
    outputs[0].clear();
    double t = 0.0, integral = 0.0;
    time.push_back(0.0);
    outputs[0].push_back(pieces.empty() ? 0.0 : pieces[0].u[0]);
    for (const auto& p : pieces)
      for (int k = 0; k < 10; ++k) {
        t += p.duration / 10.0;
        integral += p.u[0] * p.duration / 10.0;
        time.push_back(t);
        outputs[0].push_back(integral / t);
      }
  }
};

std::shared_ptr<const System> mean_box(std::shared_ptr<const stl::SignalModel> model, const std::string& requirement) {
  BlackBoxSpec spec;
  spec.name = "mean";
  spec.input_names = {"u"};
  spec.input_box = {{0.0}, {1.0}};
  spec.output_names = {"y"};
  spec.horizon = 10.0;
  spec.step = 1.0;
  return stl::with_requirement(make_black_box(spec, std::move(model)), requirement);
}

PlannerOutcome run(const System& sys, const std::string& method, const std::vector<std::pair<std::string, std::string>>& sets,
                   std::uint64_t seed) {
  const MethodEntry* m = find_method(method);
  const Json options = resolve_options(m->options, sets);
  check_method_for_system(*m, sys);
  m->check_system(sys, options);
  return m->make(options)->solve({sys, sys.info().parameters, seed, {60.0, 1000000}});
}

TEST(BlackBox, TheSignalSearchesFalsifyItAndItsWitnessesValidateByRunningTheModelAgain) {
  const auto model = std::make_shared<RunningMean>();
  const auto sys = mean_box(model, "always[1,10] (y < 0.9)");
  for (const char* method : {"random", "cmaes", "adaptive", "adaptive-local"}) {
    const PlannerOutcome o = run(*sys, method, {{"budget", "400"}, {"horizon", "10"}}, 3);
    ASSERT_EQ(o.status, TrialStatus::falsified) << method;
    ASSERT_TRUE(o.trajectory) << method;
    EXPECT_TRUE(o.trajectory->initial_x.empty());
    const Witness w = make_witness(*sys, method, 3, *o.trajectory);
    const int before = model->calls;
    const ValidationReport v = validate_witness(*sys, witness_from_text(to_json(w).dump()));
    EXPECT_TRUE(v.valid) << method << ": " << v.reason;
    EXPECT_EQ(model->calls, before + 1);  // the validator ran the model once more
    ASSERT_TRUE(v.robustness);
    EXPECT_LT(*v.robustness, 0.0);
    Witness lowered = w;  // the same pieces at the bottom of the range (y = 0 throughout): refused
    for (auto& piece : lowered.trajectory.pieces) piece.u[0] = 0.0;
    EXPECT_FALSE(validate_witness(*sys, lowered).valid) << method;
  }
  // The same seed, the same run.
  const PlannerOutcome a = run(*sys, "cmaes", {{"budget", "400"}}, 5), b = run(*sys, "cmaes", {{"budget", "400"}}, 5);
  EXPECT_EQ(a.counters.nodes, b.counters.nodes);
  EXPECT_EQ(a.metrics.dump(), b.metrics.dump());
}

TEST(BlackBox, TreesAreRefusedAndAFailingModelEndsTheTrialWithItsMessage) {
  const auto model = std::make_shared<RunningMean>();
  const auto sys = mean_box(model, "always[1,10] (y < 0.9)");
  for (const char* method : {"rrt", "rrt-dstar", "enhanced-rrt", "rrft", "hydice"})
    EXPECT_THROW(check_method_for_system(*find_method(method), *sys), std::invalid_argument) << method;
  EXPECT_THROW(sys->make_propagator(), std::invalid_argument);
  model->fail = true;
  try {
    run(*sys, "random", {{"budget", "5"}}, 1);
    FAIL() << "a failing model must end the trial";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("the model broke"), std::string::npos) << e.what();
  }
}

// A model that stops before its input signal's end breaks its contract (SignalModel): its trace
// would be a prefix taken for the whole signal. The simulation throws, naming where the trace
// ends and the horizon; a search ends its trial with that message, never a falsification.
class EndsAtOne final : public stl::SignalModel {
 public:
  void simulate(std::span<const stl::InputPiece>, std::span<const double>, std::vector<double>& time,
                std::vector<std::vector<double>>& outputs) const override {
    time = {0.0, 1.0};
    outputs[0] = {0.0, 2.0};
  }
};

TEST(BlackBox, ATraceThatEndsBeforeTheInputIsAnError) {
  const auto sys = mean_box(std::make_shared<EndsAtOne>(), "eventually[0,5] (y > 3)");
  for (const char* method : {"random", "adaptive"}) {
    try {
      run(*sys, method, {{"budget", "5"}, {"horizon", "5"}}, 1);
      FAIL() << method << ": a trace shorter than its input must end the trial";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("ends at t = 1 s, before the horizon 5 s"), std::string::npos) << e.what();
    }
  }
}

// The signal of a witness may be shorter than its requirement's horizon (the option `horizon`):
// the model's trace is then a prefix, and it falsifies only when nothing after it can undo the
// violation (its upper bound < 0).
TEST(BlackBox, AWitnessShorterThanItsRequirementIsJudgedAsAPrefix) {
  const std::vector<stl::InputPiece> low{{1.0, {0.0}}, {1.0, {0.0}}}, high{{1.0, {1.0}}, {1.0, {1.0}}};
  const auto eventually = mean_box(std::make_shared<RunningMean>(), "eventually[0,10] (y > 0.95)");
  const ValidationReport r =
      validate_witness(*eventually, make_witness(*eventually, "hand", 0, stl::trajectory_of_inputs(*eventually, low, {})));
  EXPECT_FALSE(r.valid);
  ASSERT_TRUE(r.robustness);
  EXPECT_LT(*r.robustness, 0.0);
  EXPECT_NE(r.reason.find("ends at t = 2, before the requirement's horizon 10"), std::string::npos) << r.reason;
  const auto always = mean_box(std::make_shared<RunningMean>(), "always[0,10] (y < 0.5)");
  const ValidationReport q =
      validate_witness(*always, make_witness(*always, "hand", 0, stl::trajectory_of_inputs(*always, high, {})));
  EXPECT_TRUE(q.valid) << q.reason;
}

TEST(BlackBox, RefusesABadSpecification) {
  const auto model = std::make_shared<RunningMean>();
  BlackBoxSpec good;
  good.input_names = {"u"};
  good.input_box = {{0.0}, {1.0}};
  good.output_names = {"y"};
  good.horizon = 10.0;
  EXPECT_NO_THROW(make_black_box(good, model));
  std::vector<BlackBoxSpec> bad(8, good);
  bad[0].input_names.clear();
  bad[1].output_names = {"u"};         // named twice
  bad[2].output_names = {"2y"};        // not a name
  bad[3].input_box = {{1.0}, {0.0}};   // lo > hi
  bad[4].horizon = 0.0;
  bad[5].step = std::nan("");
  bad[6].output_names = {"safety"};    // the reserved signal
  bad[7].step = 11.0;                  // longer than the horizon: no piece fits
  for (std::size_t i = 0; i < bad.size(); ++i) EXPECT_THROW(make_black_box(bad[i], model), std::invalid_argument) << i;
  EXPECT_THROW(make_black_box(good, nullptr), std::invalid_argument);
}

}  // namespace
}  // namespace hyfal
