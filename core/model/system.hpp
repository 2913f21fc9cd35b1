// The hybrid-system model every suite provides and every planner consumes.
//
// A suite writes one concrete model type satisfying the HybridModel concept (flow, guards,
// resets, invariant, specification as inline member functions); ModelSystem<M> (system.hpp)
// erases its type behind the small abstract System interface, so planners pay one virtual call
// per propagation while the integrator calls the model's flow directly (no virtual call per
// RK stage).
//
// Conventions (seed 002 Sect. 2, seed 000 Problem 2.2, seed 003 Def. 2):
//  - A mode is a 64-bit id; multi-agent suites pack per-agent modes into it (ModePacking).
//    valid_mode(q) says whether q is one of the model's modes (every field of a packed mode in
//    range, unused high bits zero). Every other member may assume a valid q (they index tables
//    with it), so a mode read from outside (a witness file) must pass valid_mode first.
//  - Guard k of mode q is a function g_k(q, x; p); the transition is enabled iff g_k > 0.
//    Transitions are urgent: the flow stops when a guard turns positive (localized to within
//    event_time_tol, at the last time before it does), the reset jump(q, k, x; p) is applied
//    and gives the next mode. A guard already positive at the start fires at once. When several
//    become enabled in one step the earliest wins; at equal times the lower index k wins.
//    A model whose guards read the input (a gear-shift schedule over the throttle) writes
//    `double guard(q, k, x, u, p)` instead: u is the propagation's constant input, and callers
//    outside the integrator use System::guard_with_input.
//    Optional: `double guard_peak(q, k, x, u, p)`, a function whose sign change marks where g_k
//    peaks along the flow (a band |e| < tol: e itself; a disc: the relative position dotted with
//    the relative velocity), 0 where there is nothing to watch. Guards are tested at step ends;
//    a band crossed, or a disc grazed, entirely inside one step leaves g_k <= 0 at both ends.
//    When guard_peak changes sign within a step, the integrator locates its zero, evaluates g_k
//    there and, if it is > 0, localizes the transition before it as usual. With it, `double
//    guard_step_change(q, k)`: a bound on how much g_k can change within one integration step
//    (+inf: none known); where g_k is below minus that bound at a step end, no peak above 0 can
//    lie in a step that ends or starts there, and guard_peak is not evaluated.
//    Optional: `static constexpr bool guards_affine = true;` when every guard is affine in x (a
//    gap minus a threshold): RK4 with StepInterpolation::hermite then locates an event on the
//    cubic that g_k is along the step's interpolant, without computing states (g_k is evaluated
//    at the origin and at the interpolant's coefficient vectors: g_k(c) − g_k(0) is its linear
//    part).
//    Optional: `static constexpr int flowing_dim = n;` when the flow is zero in every component
//    from n on in every mode (states only the jumps change: a sampled controller's memory, a
//    register): the flow then need only write dx[0, n) (every caller sees zeros beyond:
//    ModelSystem::derivative and the odeint stepper's field write them, and the fixed steppers'
//    buffers are never written there); ROS34PW2 integrates the first n components only and carries
//    the rest (its Jacobian is n × n); RK4 and dopri5 integrate them all (at flow 0).
//    Optional: `static constexpr std::array<int, K> flow_unread = {...};` the components the flow
//    never reads in any mode (time, clocks): ROS34PW2 then sets their Jacobian columns to 0 instead
//    of differencing the flow (a declaration that is wrong gives a wrong Jacobian, which a W-method
//    survives with a larger error; core/simulate/rosenbrock.hpp), and the tangents skip them
//    (core/simulate/tangent_model.hpp; there a wrong declaration gives wrong gradients, which the
//    finite-difference tests would show).
//  - invariant(q, x; p) false: the flow stops at the last valid state (seed 002 Alg. 3).
//  - spec(q, x; p) <= 0 is unsafe. Crossing into it is localized like an event. Optional:
//    `bool outside_unsafe(q, x, p)`, exactly spec(q, x, p) > 0 but cheaper (no distance); the
//    integrator then tests each step with it and evaluates spec only where it needs the value.
//  - Optional: `void outputs(q, x, u, p, y)`, the suite's output signals y (SystemInfo::outputs
//    names them, with units), read by STL requirements (core/requirements/requirement.hpp). A
//    discrete output (a gear) is a function of q. Every system also has its inputs and `safety`
//    (= spec) as signals.
#pragma once
#include <algorithm>
#include <chrono>
#include <concepts>
#include <cstdint>
#include <memory>
#include <span>
#include <stop_token>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

namespace hyfal::stl {
class SignalModel;
}  // namespace hyfal::stl

namespace hyfal {

class Decomposition;  // core/model/decomposition.hpp

using Mode = std::uint64_t;
using Json = nlohmann::json;

// Axis-aligned box [lo, hi] in R^n.
struct Box {
  std::vector<double> lo, hi;
  std::size_t dim() const { return lo.size(); }
  bool contains(std::span<const double> x) const {
    for (std::size_t i = 0; i < lo.size(); ++i)
      if (!(x[i] >= lo[i] && x[i] <= hi[i])) return false;
    return true;
  }
  // An axis of non-zero width: something to search (a P that is a point is not).
  bool has_width() const {
    for (std::size_t i = 0; i < lo.size(); ++i)
      if (hi[i] > lo[i]) return true;
    return false;
  }
};

// Packs `agents` per-agent modes of `bits` bits each into one Mode (multi-agent suites).
struct ModePacking {
  int bits = 1;
  Mode get(Mode q, int agent) const { return (q >> (agent * bits)) & ((Mode{1} << bits) - 1); }
  Mode set(Mode q, int agent, Mode v) const {
    const Mode mask = ((Mode{1} << bits) - 1) << (agent * bits);
    return (q & ~mask) | ((v << (agent * bits)) & mask);
  }
};

// The input set U_q (a box) and its user-defined discretization Ū_q (seed 003 Def. 2),
// stored flat: input j is values[j*m .. j*m+m).
struct InputSet {
  Box box;
  std::vector<double> values;
  std::size_t dim() const { return box.dim(); }
  std::size_t count() const { return box.dim() == 0 ? 1 : values.size() / box.dim(); }
  std::span<const double> input(std::size_t j) const { return {values.data() + j * box.dim(), box.dim()}; }
  // Ū as the tensor grid with `levels` points per input dimension (endpoints included).
  static InputSet grid(Box box, int levels);
};

// rk4: classical fixed-step RK4 (core/simulate/rk4.hpp); dopri5: adaptive Dormand-Prince 5 with dense
// output; rosenbrock: ROS34PW2 (core/simulate/rosenbrock.hpp), linearly implicit and L-stable, for a stiff
// flow, with step-size control to abs_tol and rel_tol from a first step `step` (every propagation
// starts there: no step size is carried from one to the next) up to max_step (a fixed step when
// the tolerances are too loose to reject any and max_step = step). RK4 and ROS34PW2 share
// `interpolation` and event location.
enum class IntegratorKind { rk4, dopri5, rosenbrock };

// RK4 and ROS34PW2: the states inside a step, where events are located (dopri5 always uses its dense
// output).
//  - restep: a fresh RK4 step of length tau from the step's start, each a genuine RK4 solution;
//    toms748 brackets the event (the default).
//  - hermite: the cubic Hermite interpolant through the step's end states and their
//    derivatives (one more flow evaluation in a step where a guard changes sign, then a cubic per
//    state; exact where the solution is a polynomial of degree <= 3), and a regula falsi
//    (Anderson-Björck; Newton's method for guards_affine, core/simulate/root_bracket.hpp) brackets the
//    event: for a model that switches at almost every step, where the re-steps and toms748's own
//    arithmetic were two thirds of a simulation (suites/cc/cc.cpp's `interpolation`).
enum class StepInterpolation { restep, hermite };

struct IntegratorSettings {
  IntegratorKind kind = IntegratorKind::rk4;
  double step = 0.01;      // rk4: fixed step; dopri5: initial step
  double max_step = 0.05;  // dopri5: largest step, so that no event is stepped over
  double abs_tol = 1e-9;   // dopri5 error control
  double rel_tol = 1e-9;
  double event_time_tol = 1e-12;                                // width of the final bracket around an event time
  StepInterpolation interpolation = StepInterpolation::restep;  // rk4 only
};

// Guards g_k(q, x; p), or g_k(q, x, u; p) for a model whose guards read the input.
template <class M>
concept InputGuards = requires(const M m, Mode q, int k, const double* x, const double* u, const double* p) {
  { m.guard(q, k, x, u, p) } -> std::convertible_to<double>;
};
template <class M>
concept StateGuards = requires(const M m, Mode q, int k, const double* x, const double* p) {
  { m.guard(q, k, x, p) } -> std::convertible_to<double>;
};

// Compile-time model interface; see the conventions above.
template <class M>
concept HybridModel = (StateGuards<M> || InputGuards<M>)&&requires(const M m, Mode q, int k, const double* x,
                                                                   double* xm, const double* u, const double* p,
                                                                   double* dx) {
  { m.dim() } -> std::convertible_to<int>;
  { m.valid_mode(q) } -> std::same_as<bool>;
  {m.flow(q, x, u, p, dx)};
  { m.guard_count(q) } -> std::convertible_to<int>;
  { m.jump(q, k, xm, p) } -> std::convertible_to<Mode>;
  { m.invariant(q, x, p) } -> std::convertible_to<bool>;
  { m.spec(q, x, p) } -> std::convertible_to<double>;
};

// How one propagation ended.
enum class PropagationEnd {
  completed,  // flowed the whole duration
  jumped,     // stopped at an urgent transition and applied its reset
  invariant,  // stopped at the last state before the invariant failed
  unsafe,     // reached s <= 0 (localized)
  rejected    // NaN/Inf, a Zeno chain of zero-time jumps, or interrupted (PropagationInterrupt):
              // the result must not enter a tree
};

// When a propagation must give up: a trial's deadline and its cancellation. A tiny integration
// step (or a stiff flow under adaptive steps) can make one propagation outlast any trial budget,
// so the budget is checked inside it too, not only between propagations.
struct PropagationInterrupt {
  std::chrono::steady_clock::time_point deadline = std::chrono::steady_clock::time_point::max();
  std::stop_token stop;
};

// Receives the samples of a propagation's trace (STL requirements, core/requirements/): the
// state after every integration step, and at an event both the state before the reset (mode q)
// and after it (the next mode), both at the event's time. t is the time since the propagation's
// start. The start state is not sampled (it is the end of the trace so far).
class SampleSink {
 public:
  virtual ~SampleSink() = default;
  // `safety`: s(q, x; p) when the caller has it at hand, NaN otherwise (the sink computes it if
  // it needs it).
  virtual void sample(double t, Mode q, std::span<const double> x, double safety) = 0;
  // True when the sink reads the `safety` signal: then entries into s <= 0 are localized and
  // sampled like events (without stopping, see Propagator::set_trace).
  virtual bool samples_unsafe_entries() const { return false; }
};

struct PropagationResult {
  PropagationEnd end = PropagationEnd::completed;
  double duration = 0.0;   // flow time taken in the start mode
  Mode mode = 0;           // mode after the propagation (after the reset when jumped)
  int transition = -1;     // guard index taken, -1 when none
  double spec = 0.0;       // s at the end state
  std::int64_t steps = 0;  // integration steps taken
};

// One thread's integrator with its own workspace (no allocation per step or propagation).
class Propagator {
 public:
  virtual ~Propagator() = default;
  // From now on propagate() ends as `rejected` once the deadline has passed or a stop is
  // requested, and every later propagate() at once (sticky: the trial is over). flow() is never
  // interrupted: it re-flows pieces already found (witnesses).
  void set_interrupt(PropagationInterrupt interrupt) {
    interrupt_ = std::move(interrupt);
    interrupted_ = false;
    since_check_ = 0;
  }
  bool interrupted() const { return interrupted_; }
  // STL mode (a non-null sink): every propagate() sends its trace's samples to `sink`, and the
  // unsafe set no longer stops the flow (the requirement, not s <= 0, decides falsification);
  // entries into it are sampled when the sink reads `safety`. Null: reachability (the default).
  void set_trace(SampleSink* sink) { sink_ = sink; }
  SampleSink* trace() const { return sink_; }
  // Flows (q, x) under constant u for at most `duration`; see PropagationEnd. out has dim().
  virtual PropagationResult propagate(Mode q, std::span<const double> x, std::span<const double> u,
                                      std::span<const double> p, double duration, std::span<double> out) = 0;
  // Flows in mode q for exactly `duration`, ignoring guards, invariant and spec: the pieces
  // of a witness. Returns the number of steps, or -1 when the state became non-finite.
  virtual std::int64_t flow(Mode q, std::span<const double> x, std::span<const double> u, std::span<const double> p,
                            double duration, std::span<double> out) = 0;

 protected:
  // Integration steps between two reads of the clock: a read costs about as much as a few RK4
  // stages of a small model, so 1024 keeps the check well below 1 % of the work while a trial
  // overruns its deadline by 1024 steps at most.
  static constexpr int kInterruptInterval = 1024;
  // Called once per integration step; true when the propagation must end now.
  bool interrupt_due() {
    if (interrupted_) return true;
    if (++since_check_ < kInterruptInterval) return false;
    since_check_ = 0;
    interrupted_ = interrupt_.stop.stop_requested() || std::chrono::steady_clock::now() >= interrupt_.deadline;
    return interrupted_;
  }
  SampleSink* sink_ = nullptr;

 private:
  PropagationInterrupt interrupt_;
  bool interrupted_ = false;
  int since_check_ = 0;
};

// A propagator of a state together with its tangents: the derivatives of the state with respect
// to P directions (stl::InputSimulator's are, within each input piece, the state at the piece's
// start and the piece's input: P = n + m), for gradient-based falsification
// (core/simulate/tangent_model.hpp says how they are computed; stl::SensitivitySimulator drives
// one). It propagates the augmented state z = [x (n) | S (n × P, variable by variable: S[v n + i]
// = ∂x_i/∂c_v at a fixed time) | T (P: ∂t/∂c_v of the time the state stands at, non-zero only
// after a state event inside an input piece, whose time moves with the inputs)] under the
// augmented input [u (m) | U (m × P, variable by variable: U[v m + j] = ∂u_j/∂c_v)], with exactly
// the plain propagator's steps and events: z's first n entries are the same bits as a plain
// propagation's state.
class TangentPropagator {
 public:
  virtual ~TangentPropagator() = default;
  // The propagator of z (its dim() is n (1 + P) + P), used as any other: hold_input, a trace.
  virtual Propagator& propagator() = 0;
  // Only variables [0, k) have a non-zero tangent so far (later control points are not yet
  // reached): their columns are propagated, the rest left at 0. Default: all P.
  virtual void set_active_variables(std::size_t k) = 0;
  // Directions [first, first + count) move the system's parameters p_0 .. p_{count−1}, which the
  // flow, guards, resets (F16's start jump) may read; the other directions move no parameter.
  virtual void set_parameter_directions(std::size_t first, std::size_t count) = 0;
};

// The grid G of the coverage measure c(T, G) (seed 000 eq. II.1, seed 003 eq. 3): spacing δx
// over `box`, in the projection of the state onto `dims` (all dimensions when empty).
struct CoverageSpec {
  std::vector<int> dims;
  Box box;
  double spacing = 0.0;  // 0: the suite defines no coverage grid
};

// A named signal of a system: an output (M::outputs), an input, or `safety`.
struct SignalInfo {
  std::string name;
  std::string unit;     // "" when dimensionless
  std::string meaning;  // one line, for `hyfal list`
};

// A requirement a suite declares (the ARCH-COMP ids, or its own), in the notation of
// core/requirements/formula.hpp over the system's signals.
struct DeclaredRequirement {
  std::string id;
  std::string formula;
  std::string meaning;
};

namespace stl {
struct Requirement;  // core/requirements/requirement.hpp
}

// Static facts about one system instance.
struct SystemInfo {
  std::string suite;
  Json instance;  // canonical instance key
  std::vector<std::string> state_names;
  std::vector<std::string> input_names;
  std::vector<std::string> parameter_names;
  Box parameter_box;               // time-invariant parameters P (may be 0-dimensional)
  std::vector<double> parameters;  // p used by methods that do not search over P
  Mode initial_mode = 0;
  std::vector<double> initial_state;
  // Further initial states (same mode): planners grow one tree per initial state (a forest, as
  // seed 000 Fig. 12); a witness may start from any of them.
  std::vector<std::vector<double>> other_initial_states;
  Box sampling_box;                    // where x_rand is drawn
  std::vector<double> metric_weights;  // rho(x, y) = sqrt(sum w_i (x_i - y_i)^2)
  std::vector<double> goal_point;      // µ of the biased sampler, a point with s <= 0 (seed 000 III.6)
  CoverageSpec coverage;
  // δt of one tree extension (seed 000 Sect. II-A). Every method propagates a node for at most
  // δt (core/planners/*), so it is also the longest piece a witness may have (validate_witness).
  double step_duration = 0.1;
  // How a planner that draws random inputs (HyDICE) should draw them when not told otherwise:
  // false = a random element of the discretized Ū (the suite's choice of levels), true =
  // uniformly over the admissible box (the paper's model draws continuous inputs, e.g. the
  // drivers of seed 002 Sect. 4.1.2).
  bool continuous_random_inputs = false;
  // With continuous_random_inputs: how many inputs a method that tries every input of Ū and keeps
  // the best (rrt, rrt-dstar, rrft, enhanced-rrt) draws per extension instead (core/search/input_grid.hpp).
  int random_inputs_per_extension = 1;
  // The inputs are an external signal, constant over pieces of δt whatever the system does (the
  // ARCH-COMP input instances): the same box in every mode and at every state. Under an STL
  // requirement a tree edge then holds its input for the whole δt through the transitions on the
  // way (core/simulate/held_input.hpp), so that a tree's input signal is one the instance admits, and the
  // validator checks that a witness's input changes only at multiples of δt. Otherwise (false,
  // or reachability of s <= 0) an edge ends at the first transition (seed 002 Alg. 3).
  bool held_inputs = false;
  // With held_inputs: the instance also admits a signal linear between control points on the
  // δt grid (ARCH-COMP instance 1: any piecewise-continuous signal; instance 2 demands piecewise
  // constant). A witness that declares its control points (Trajectory::linear_input) may then
  // change its input between multiples of δt, along the line between them (validate_witness).
  bool interpolated_inputs = false;
  IntegratorSettings integrator;
  double witness_tolerance = 1e-6;  // validation tolerance on states and on s
  // A witness records the states of the pieces where the input changes (and of the first and
  // last), not of every piece (make_witness): for a model with a transition at every controller
  // tick (AFC: 5,011 pieces of 137 states, 33 MB of JSON otherwise). The validator re-simulates
  // every piece all the same, and compares the states recorded.
  bool sparse_witness_states = false;
  // The validator replays a witness with the suite's own simulator: it re-runs its input signal,
  // cut into the pieces of δt a search simulates (held inputs only), and judges the requirement on
  // that run, as ARCH-COMP's organisers re-run Simulink. Instead of the independent tight
  // re-simulation, for a closed loop that is chaotic at the level of rounding, where no other
  // integrator follows the search's run for long (NN: a change of 1e-15 in the initial position
  // grows past 1e-3 within 6 s, suites/nn/nn.cpp). A replay shows that the model as the suite
  // integrates it falsifies, not that the falsification survives another integration.
  bool validation_by_replay = false;
  // STL: the output signals (values from M::outputs, in this order), the inputs' units (empty, or
  // one per input), the requirements the suite declares, and the one this instance falsifies
  // (null: reachability of s <= 0; set from the `requirement` instance parameter).
  std::vector<SignalInfo> outputs;
  std::vector<std::string> input_units;
  // Other names of each input (empty, or one list per input): the words the benchmark's own
  // description uses (ARCH-COMP's `throttle`, `brake`), which an input CSV's header may give.
  std::vector<std::vector<std::string>> input_aliases;
  std::vector<DeclaredRequirement> requirements;
  std::shared_ptr<const stl::Requirement> requirement;
  std::size_t dim() const { return initial_state.size(); }
};

// A system instance, type-erased. Shared read-only between threads.
class System {
 public:
  virtual ~System() = default;
  virtual const SystemInfo& info() const = 0;
  // True when q is a mode of this system; every member taking a Mode requires one that is.
  virtual bool valid_mode(Mode q) const = 0;
  virtual const InputSet& inputs(Mode q) const = 0;
  virtual std::string mode_name(Mode q) const { return std::to_string(q); }
  virtual void derivative(Mode q, std::span<const double> x, std::span<const double> u, std::span<const double> p,
                          std::span<double> dx) const = 0;
  // True when f(q, x, u; p) is affine in u (then max over a box of a linear form of f has a
  // closed form, seed 000 Sect. III-A). A model declares it with `static constexpr bool
  // input_affine = true;`.
  virtual bool input_affine(Mode q) const { return false; }
  // State-dependent admissible inputs — a driver model (seed 002 Sect. 4.1.2): at state x in
  // mode q only the box [lo, hi] ⊆ U_q may be applied. When false (the default) U_q applies at
  // every state. Methods draw u from input_bounds (HyDICE) or map Ū_q onto it (InputGrid,
  // core/search/input_grid.hpp); the witness validator checks every piece's u against it.
  virtual bool state_dependent_inputs() const { return false; }
  virtual void input_bounds(Mode q, std::span<const double> x, std::span<double> lo, std::span<double> hi) const {
    const Box& b = inputs(q).box;
    std::copy(b.lo.begin(), b.lo.end(), lo.begin());
    std::copy(b.hi.begin(), b.hi.end(), hi.begin());
  }
  virtual int guard_count(Mode q) const = 0;
  virtual double guard(Mode q, int k, std::span<const double> x, std::span<const double> p) const = 0;
  // g_k under the input u of the piece that flows: the same as guard() unless the model's guards
  // read the input (then guard() without u throws std::logic_error).
  virtual double guard_with_input(Mode q, int k, std::span<const double> x, std::span<const double> u,
                                  std::span<const double> p) const {
    return guard(q, k, x, p);
  }
  virtual Mode jump(Mode q, int k, std::span<double> x, std::span<const double> p) const = 0;
  virtual bool invariant(Mode q, std::span<const double> x, std::span<const double> p) const = 0;
  virtual double spec(Mode q, std::span<const double> x, std::span<const double> p) const = 0;
  // The output signals at (q, x) under u (SystemInfo::outputs.size() values).
  virtual void outputs(Mode q, std::span<const double> x, std::span<const double> u, std::span<const double> p,
                       std::span<double> y) const {}
  virtual std::unique_ptr<Propagator> make_propagator(const IntegratorSettings& s) const = 0;
  std::unique_ptr<Propagator> make_propagator() const { return make_propagator(info().integrator); }
  // A propagator of the state and its tangents with respect to `variables` search variables
  // (TangentPropagator) with the settings s; null when the system has none (a black box, an
  // integrator other than RK4: its step-size control would see the tangents).
  virtual std::unique_ptr<TangentPropagator> make_tangent_propagator(std::size_t variables,
                                                                     const IntegratorSettings& s) const {
    return nullptr;
  }
  std::unique_ptr<TangentPropagator> make_tangent_propagator(std::size_t variables) const {
    return make_tangent_propagator(variables, info().integrator);
  }
  // The region decomposition of seed 002 Sect. 3.2 (HyDICE), when the suite provides one.
  virtual const Decomposition* decomposition() const { return nullptr; }
  // A model known only by its simulations (a black box: core/model/black_box.hpp), when it is one:
  // then it has no states, modes or flows, and only the searches over input signals, which
  // simulate whole signals (core/planners/signal_search.hpp), can drive it.
  virtual const stl::SignalModel* signal_model() const { return nullptr; }
};

}  // namespace hyfal
