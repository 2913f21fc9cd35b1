#include "core/witness/validator.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "core/requirements/requirement.hpp"
#include "core/requirements/robustness.hpp"
#include "core/requirements/trace_monitor.hpp"
#include "core/simulate/input_signal.hpp"
#include "core/simulate/input_simulator.hpp"
#include "core/witness/trajectory.hpp"

namespace hyfal {

namespace {

// Largest componentwise error relative to the tolerance scale (1 + |x_i|).
double scaled_error(std::span<const double> a, std::span<const double> b) {
  double e = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) e = std::max(e, std::abs(a[i] - b[i]) / (1.0 + std::abs(b[i])));
  return e;
}

// Why a check of a witness failed; nothing when it passed.
using Failure = std::optional<std::string>;

// Every index and size the witness names, before anything uses one: a model may index its
// tables with a mode (navigation: its terrains) and the validator indexes guards with a
// transition. A failure here means it is no witness of this system at all (malformed).
Failure shape_mismatch(const System& system, const Witness& w) {
  const SystemInfo& info = system.info();
  const Trajectory& t = w.trajectory;
  const std::size_t n = info.dim();
  if (w.suite != info.suite) return fmt::format("witness is for suite '{}', not '{}'", w.suite, info.suite);
  if (t.initial_x.size() != n || t.final_x.size() != n)
    return fmt::format("witness states have {} values, the system has {}", t.initial_x.size(), n);
  if (t.parameters.size() != info.parameter_box.dim())
    return fmt::format("witness has {} parameters, the system has {}", t.parameters.size(), info.parameter_box.dim());
  if (!system.valid_mode(t.initial_mode))
    return fmt::format("initial.mode = {} is not a mode of suite '{}'", t.initial_mode, info.suite);
  for (std::size_t i = 0; i < t.pieces.size(); ++i) {
    const TrajectoryPiece& piece = t.pieces[i];
    if (!system.valid_mode(piece.mode))
      return fmt::format("pieces[{}].mode = {} is not a mode of suite '{}'", i, piece.mode, info.suite);
    const auto recorded = [n](const std::vector<double>& x) { return x.empty() || x.size() == n; };
    if (!recorded(piece.x_start) || !recorded(piece.x_end))
      return fmt::format("piece {} has states of the wrong size", i);
    const std::size_t m = system.inputs(piece.mode).dim();
    if (piece.u.size() != m) return fmt::format("piece {}: u has {} values, U has {}", i, piece.u.size(), m);
    if (piece.transition < -1 || piece.transition >= system.guard_count(piece.mode))
      return fmt::format("pieces[{}].transition = {}: mode {} has {} transitions (indices from 0)", i, piece.transition,
                         system.mode_name(piece.mode), system.guard_count(piece.mode));
  }
  if (!system.valid_mode(t.final_mode))
    return fmt::format("final.mode = {} is not a mode of suite '{}'", t.final_mode, info.suite);
  return std::nullopt;
}

// A declared linear input signal (Trajectory::linear_input) against the instance and the pieces:
// control points from 0 on, increasing, on the δt grid of a held signal whose instance admits
// interpolation, values in U, declared pieces no longer than δt and bounded in number; and every
// piece of the witness inside one declared piece, holding its value (the line at its midpoint:
// stl::linear_signal_pieces) up to rounding.
Failure linear_input_mismatch(const System& system, const Trajectory& t) {
  const SystemInfo& info = system.info();
  const LinearInput& in = *t.linear_input;
  const double dt = info.step_duration;
  if (info.held_inputs && !info.interpolated_inputs)
    return std::string(
        "the witness declares a linear input signal (input_signal), but this instance admits only inputs "
        "held constant for δt");
  if (in.times.size() < 2) return std::string("input_signal has fewer than 2 control points");
  if (in.times.front() != 0.0) return fmt::format("input_signal.times[0] = {:.9g}, not 0", in.times.front());
  if (!(in.piece <= dt * (1.0 + 1e-9)))
    return fmt::format("input_signal.piece = {:.6g} s is longer than δt = {:.6g} s", in.piece, dt);
  double declared = 0.0;
  for (std::size_t k = 0; k + 1 < in.times.size(); ++k) {
    const double length = in.times[k + 1] - in.times[k];
    if (!(length > 0.0)) return fmt::format("input_signal.times[{}] does not increase", k + 1);
    if (info.held_inputs) {
      const double now = in.times[k + 1];
      if (std::abs(now - std::round(now / dt) * dt) > 1e-6 * std::max(1.0, now))
        return fmt::format("input_signal.times[{}] = {:.9g} s is not a multiple of δt = {:.6g} s", k + 1, now, dt);
    }
    declared += std::max(1.0, std::ceil(length / in.piece - 1e-9));
  }
  if (!(declared <= 1e7)) return fmt::format("input_signal declares {:.3g} pieces, more than 1e7", declared);
  const Box& U = system.inputs(t.initial_mode).box;
  for (std::size_t k = 0; k < in.values.size(); ++k)
    for (std::size_t i = 0; i < U.dim(); ++i)
      if (in.values[k][i] < U.lo[i] - info.witness_tolerance || in.values[k][i] > U.hi[i] + info.witness_tolerance)
        return fmt::format("input_signal.values[{}][{}] = {} is outside U", k, i, in.values[k][i]);
  const std::vector<stl::InputPiece> expected = stl::linear_signal_pieces(in.times, in.values, in.piece);
  double now = 0.0, start = 0.0, end = expected.front().duration;
  std::size_t e = 0;
  const auto holds = [&](const TrajectoryPiece& piece, std::size_t at) {
    for (std::size_t k = 0; k < piece.u.size(); ++k)
      if (std::abs(piece.u[k] - expected[at].u[k]) > 1e-9 * std::max(1.0, U.hi[k] - U.lo[k])) return false;
    return true;
  };
  const auto next = [&] {
    start = end;
    end += expected[++e].duration;
  };
  for (std::size_t i = 0; i < t.pieces.size(); ++i) {
    const TrajectoryPiece& piece = t.pieces[i];
    const double slack = 1e-9 * std::max(1.0, end);
    // A piece of positive duration lies in the declared piece that holds its middle. One of none
    // (transitions at one instant) or of a rounding's length (a transition located just after
    // the boundary) on a boundary between two declared pieces belongs to either:
    // to the earlier where the flow under its input ended in them, to the later where the later's
    // input enabled them at once.
    if (piece.duration > 2.0 * slack) {
      while (now + 0.5 * piece.duration > end && e + 1 < expected.size()) next();
    } else {
      while (now > end + slack && e + 1 < expected.size()) next();
      if (!holds(piece, e) && now >= end - slack && e + 1 < expected.size() && holds(piece, e + 1)) next();
    }
    if (now < start - slack || now + piece.duration > end + slack)
      return fmt::format("pieces[{}] ([{:.9g}, {:.9g}] s) is not inside one piece of the declared linear signal", i,
                         now, now + piece.duration);
    if (!holds(piece, e))
      return fmt::format("pieces[{}]: input {} is not the declared linear signal's {} there", i,
                         fmt::join(piece.u, ", "), fmt::join(expected[e].u, ", "));
    now += piece.duration;
  }
  return std::nullopt;
}

// Durations, parameters and the start, against what the system allows (checked after every
// malformation: those are bad input). Durations bound the work a witness asks for: no method
// makes a piece longer than δt (the relative slack absorbs the rounding of r.duration).
Failure outside_the_system(const System& system, const Trajectory& t) {
  const SystemInfo& info = system.info();
  const double tol = info.witness_tolerance;
  const double longest = info.step_duration * (1.0 + 1e-9);
  for (std::size_t i = 0; i < t.pieces.size(); ++i)
    if (!(t.pieces[i].duration >= 0.0 && t.pieces[i].duration <= longest))
      return fmt::format("pieces[{}].duration = {:.6g} s is longer than any method extends a node (δt = {:.6g} s)", i,
                         t.pieces[i].duration, info.step_duration);
  if (t.linear_input) {
    if (Failure why = linear_input_mismatch(system, t)) return why;
  } else if (info.held_inputs && info.requirement) {  // a held signal changes only at multiples of δt (ARCH-COMP)
    double now = 0.0;
    for (std::size_t i = 0; i + 1 < t.pieces.size(); ++i) {
      now += t.pieces[i].duration;
      if (t.pieces[i + 1].u == t.pieces[i].u) continue;
      const double k = std::round(now / info.step_duration);
      if (std::abs(now - k * info.step_duration) > 1e-6 * std::max(1.0, now))
        return fmt::format(
            "pieces[{}] changes the input at t = {:.9g} s, not at a multiple of δt = {:.6g} s (the "
            "system's inputs are a signal held for δt)",
            i + 1, now, info.step_duration);
    }
  }
  for (std::size_t i = 0; i < t.parameters.size(); ++i)
    if (t.parameters[i] < info.parameter_box.lo[i] - tol || t.parameters[i] > info.parameter_box.hi[i] + tol)
      return fmt::format("parameter {} = {} is outside P", i, t.parameters[i]);
  bool known_start = scaled_error(t.initial_x, info.initial_state) <= tol;
  for (const auto& x0 : info.other_initial_states) known_start = known_start || scaled_error(t.initial_x, x0) <= tol;
  if (t.initial_mode != info.initial_mode || !known_start)
    return "the initial state is not one of the system's initial states";
  return std::nullopt;
}

// A tight, independent integrator: adaptive Dormand-Prince whatever the tree used.
IntegratorSettings tight_integrator(const SystemInfo& info) {
  IntegratorSettings tight;
  tight.kind = IntegratorKind::dopri5;
  tight.abs_tol = 1e-12;
  tight.rel_tol = 1e-12;
  tight.max_step = std::min(info.integrator.max_step, info.step_duration);
  tight.step = tight.max_step / 8;
  return tight;
}

// The work, bounded before it starts: sub-intervals of at most max_step over all pieces (each
// at least one). Witnesses of hyfal's methods need about 40 per piece and at most thousands of
// pieces; only a suite instance with a maximal step far below δt can ask for more.
Failure too_much_work(const Trajectory& t, double max_step) {
  if (!(max_step > 0.0)) return "the system's integrator has no positive maximal step";
  constexpr double kMaxSubIntervals = 1e7;
  double sub_intervals = 0.0;
  for (const auto& piece : t.pieces) sub_intervals += std::max(1.0, std::ceil(piece.duration / max_step));
  if (!(sub_intervals <= kMaxSubIntervals))
    return fmt::format(
        "re-simulating the witness needs {:.3g} integration intervals of at most {:.3g} s, "
        "more than {:.0e}",
        sub_intervals, max_step, kMaxSubIntervals);
  return std::nullopt;
}

// Whether the piece's input lies in U, and (a driver model) is admissible at its x_start.
Failure inadmissible_input(const System& system, Mode q, const TrajectoryPiece& piece, std::size_t i, double tol,
                           std::span<const double> simulated) {
  const InputSet& U = system.inputs(q);
  for (std::size_t k = 0; k < U.dim(); ++k)
    if (piece.u[k] < U.box.lo[k] - tol || piece.u[k] > U.box.hi[k] + tol)
      return fmt::format("piece {}: input {} = {} is outside U", i, k, piece.u[k]);
  if (!system.state_dependent_inputs()) return std::nullopt;
  // The recorded x_start (within tol of the re-simulation, checked before) is the state the
  // method chose u at; a driver's bands are discontinuous, so it is the one to judge by (the
  // re-simulated state where none is recorded).
  std::vector<double> lo(U.dim()), hi(U.dim());
  system.input_bounds(q, piece.x_start.empty() ? simulated : std::span<const double>(piece.x_start), lo, hi);
  for (std::size_t k = 0; k < U.dim(); ++k)
    if (piece.u[k] < lo[k] - tol || piece.u[k] > hi[k] + tol)
      return fmt::format("piece {}: input {} = {} is outside the admissible [{}, {}] at x_start", i, k, piece.u[k],
                         lo[k], hi[k]);
  return std::nullopt;
}

// The execution as re-simulated so far: where it is, and the largest error of a recorded state.
struct Replay {
  const System& system;
  Propagator& propagator;  // the tight one
  std::span<const double> p;
  double tol = 0.0, max_step = 0.0;
  Mode q = 0;
  std::vector<double> x, next;
  double max_state_error = 0.0;
  // STL: the trace's samples (rows of time and the requirement's signals), and the time so far.
  std::optional<stl::SignalSampler> sampler;
  std::vector<double> rows;
  double time = 0.0;

  // Records the error of a recorded state against the re-simulated one; returns it.
  double error_of(std::span<const double> recorded) {
    const double e = scaled_error(x, recorded);
    max_state_error = std::max(max_state_error, e);
    return e;
  }
};

// Flows the piece in short sub-intervals (their count is 64-bit and bounded: too_much_work);
// inside the piece the invariant must hold and no transition may be enabled (they are urgent).
Failure flow_through(Replay& run, const TrajectoryPiece& piece, std::size_t i) {
  const System& system = run.system;
  const Mode q = run.q;
  const auto sub = std::max<std::int64_t>(1, static_cast<std::int64_t>(std::ceil(piece.duration / run.max_step)));
  const double h = piece.duration / static_cast<double>(sub);
  for (std::int64_t s = 0; s < sub; ++s) {
    std::int64_t steps = -1;
    try {
      steps = run.propagator.flow(q, run.x, piece.u, run.p, h, run.next);
    } catch (const std::exception& e) {  // odeint gives up on a step size it cannot control
      return fmt::format("piece {}: the integrator failed: {}", i, e.what());
    }
    if (steps < 0) return fmt::format("piece {}: the state became non-finite", i);
    run.x.swap(run.next);
    const bool inside = (s + 1 < sub);
    const double at = h * static_cast<double>(s + 1);
    if (run.sampler) run.sampler->sample(at, q, run.x);
    if (!system.invariant(q, run.x, run.p) && inside)
      return fmt::format("piece {}: the invariant of mode {} fails at t = {:.6g}", i, system.mode_name(q), at);
    if (inside)
      for (int k = 0; k < system.guard_count(q); ++k)
        if (system.guard_with_input(q, k, run.x, piece.u, run.p) > run.tol)
          return fmt::format(
              "piece {}: transition {} is enabled at t = {:.6g} inside the piece, "
              "but transitions are urgent",
              i, k, at);
  }
  return std::nullopt;
}

// Re-simulates piece i from where the execution is: its mode, start, input, flow, end and jump.
// check_start / check_end: whether the recorded states are compared with the re-simulation (the
// re-simulation goes on from its own state either way).
Failure replay_piece(Replay& run, const TrajectoryPiece& piece, std::size_t i, bool check_start, bool check_end) {
  const System& system = run.system;
  if (piece.mode != run.q)
    return fmt::format("piece {} flows in mode {}, but the execution is in mode {}", i, system.mode_name(piece.mode),
                       system.mode_name(run.q));
  if (const double e0 = check_start && !piece.x_start.empty() ? run.error_of(piece.x_start) : 0.0; e0 > run.tol)
    return fmt::format("piece {}: x_start differs from the re-simulated state by {:.3g}", i, e0);
  if (Failure why = inadmissible_input(system, run.q, piece, i, run.tol, run.x)) return why;
  if (run.sampler) {
    if (i == 0) {  // the first sample, with the first piece's input (core/search/edge_monitor.hpp)
      run.sampler->begin(0.0, piece.u, run.p, run.rows);
      run.sampler->sample(0.0, run.q, run.x);
    }
    run.sampler->begin(run.time, piece.u, run.p, run.rows);
  }
  if (Failure why = flow_through(run, piece, i)) return why;
  run.time += piece.duration;
  if (const double e1 = check_end && !piece.x_end.empty() ? run.error_of(piece.x_end) : 0.0; e1 > run.tol)
    return fmt::format("piece {}: x_end differs from the re-simulated state by {:.3g}", i, e1);
  if (piece.transition >= 0) {  // a guard index of q (shape_mismatch checked it)
    const int k = piece.transition;
    if (system.guard_with_input(run.q, k, run.x, piece.u, run.p) < -run.tol)
      return fmt::format("piece {}: transition {} is not enabled at the end of the piece", i, k);
    run.q = system.jump(run.q, k, run.x, run.p);
    if (run.sampler) run.sampler->sample(piece.duration, run.q, run.x);  // after the reset, at the same time
  }
  return std::nullopt;
}

// Where the re-simulation ends against the recorded end: mode, state, s, and s <= 0.
Failure final_state_mismatch(Replay& run, const Trajectory& t, double& final_spec) {
  const System& system = run.system;
  const double ef = run.error_of(t.final_x);
  if (run.q != t.final_mode)
    return fmt::format("the final mode is {}, the execution ends in {}", system.mode_name(t.final_mode),
                       system.mode_name(run.q));
  if (ef > run.tol) return fmt::format("the final state differs from the re-simulated one by {:.3g}", ef);
  final_spec = system.spec(run.q, run.x, run.p);
  if (std::abs(final_spec - t.final_spec) > run.tol * (1.0 + std::abs(final_spec)))
    return fmt::format("the recorded final s = {:.6g} differs from the re-simulated s = {:.6g}", t.final_spec,
                       final_spec);
  if (run.sampler) return std::nullopt;  // an STL witness: the requirement decides (trace_violation)
  if (final_spec > run.tol)
    return fmt::format("the re-simulated final state is safe: s = {:.6g} > {:.3g}", final_spec, run.tol);
  return std::nullopt;
}

// A trace that ends before the requirement's horizon is a prefix: the requirement may still be
// met after its end (an `eventually`, `until` or `not always` at the top: ATc4-ATc6), so its
// offline robustness < 0 proves nothing. It falsifies only when every extension's robustness is
// negative: the prefix's upper bound (stl::OfflineMonitor::robustness_interval) < 0, as the tree
// searches judge a node. A trace that reaches the horizon, or a requirement without one, passes.
// `what`: the trace, as the reason names it.
Failure prefix_not_violating(const stl::TraceVerdict& v, double end, std::string_view what, const std::string& text) {
  if (v.complete || v.falsified()) return std::nullopt;
  return fmt::format(
      "{} ends at t = {:.6g}, before the requirement's horizon {:.6g}: as a prefix its robustness lies "
      "in [{:.6g}, {:.6g}], which what follows may make >= 0, for '{}'",
      what, end, v.horizon, v.bounds.lower, v.bounds.upper, text);
}

// An STL witness's trace against its requirement: the offline robustness of the re-simulated
// samples must be negative, and the witness must name the requirement its instance has; a trace
// shorter than the requirement's horizon must violate it whatever follows (prefix_not_violating).
Failure trace_violation(Replay& run, const Witness& w, ValidationReport& r) {
  const stl::Requirement& req = *run.system.info().requirement;
  if (!w.requirement) return "the instance has an STL requirement, but the witness records none";
  if (w.requirement->formula != req.text)
    return fmt::format("the witness's requirement '{}' is not its instance's '{}'", w.requirement->formula, req.text);
  if (run.rows.empty()) {  // no piece: the initial state alone, with no input
    const std::vector<double> u(run.system.info().input_names.size(), 0.0);
    run.sampler->begin(0.0, u, run.p, run.rows);
    run.sampler->sample(0.0, run.q, run.x);
  }
  const std::size_t width = run.sampler->row_width(), n = run.rows.size() / width, signals = width - 1;
  std::vector<double> time(n), values(signals * n);
  for (std::size_t i = 0; i < n; ++i) {
    time[i] = run.rows[i * width];
    for (std::size_t s = 0; s < signals; ++s) values[s * n + i] = run.rows[i * width + 1 + s];
  }
  stl::OfflineMonitor monitor(req.formula);
  const stl::TraceView view{time, values};
  const double rho = monitor.robustness(view);
  r.robustness = rho;
  r.samples = n;
  if (!(rho < 0.0))
    return fmt::format("the re-simulated trace ({} samples over [0, {:.6g}]) has robustness {:.6g} >= 0 for '{}'", n,
                       time.back(), rho, req.text);
  return prefix_not_violating(stl::judge_prefix(monitor, view), time.back(), "the re-simulated trace", req.text);
}

// A signal model's witness (System::signal_model: no states to re-simulate): its inputs in U,
// then its requirement judged on the model's own simulation of the witness's input signal, run
// again (the only independent check a black box admits).
// The witness's held input signal cut into the pieces of δt that a search simulates
// (SignalSimulations: pieces of exactly δt from 0; a tree's edges: the same grid), each holding the
// witness's input at its midpoint, up to the witness's length (SystemInfo::validation_by_replay).
std::vector<stl::InputPiece> input_signal_on_grid(const System& system, const Trajectory& t) {
  const double dt = system.info().step_duration;
  double total = 0.0;
  for (const TrajectoryPiece& piece : t.pieces) total += piece.duration;
  const auto n = static_cast<std::size_t>(std::max(0.0, std::ceil(total / dt - 1e-9)));
  std::vector<stl::InputPiece> pieces;
  std::size_t i = 0;
  double piece_end = t.pieces.empty() ? 0.0 : t.pieces[0].duration;
  for (std::size_t k = 0; k < n && !t.pieces.empty(); ++k) {
    const double mid = (static_cast<double>(k) + 0.5) * dt;
    while (i + 1 < t.pieces.size() && piece_end <= mid) piece_end += t.pieces[++i].duration;
    pieces.push_back({dt, t.pieces[i].u});
  }
  return pieces;
}

void validate_by_simulation(const System& system, const Witness& w, ValidationReport& r) {
  const Trajectory& t = w.trajectory;
  const auto fail = [&](std::string why) { r.reason = std::move(why); };
  for (std::size_t i = 0; i < t.pieces.size(); ++i)
    if (Failure why = inadmissible_input(system, t.pieces[i].mode, t.pieces[i], i, system.info().witness_tolerance,
                                         t.pieces[i].x_start))
      return fail(std::move(*why));
  const stl::Requirement* req = system.info().requirement.get();
  const bool replay = system.info().validation_by_replay && !system.signal_model();
  if (!req)
    return fail(
        replay
            ? "a witness replayed with the suite's own simulator is judged by an STL requirement; the instance has none"
            : "a model known only by its simulations is judged by an STL requirement; the instance has none");
  if (replay && t.linear_input)
    return fail("a replayed witness holds its input on pieces of δt; this one declares a linear signal");
  if (!w.requirement) return fail("the instance has an STL requirement, but the witness records none");
  if (w.requirement->formula != req->text)
    return fail(
        fmt::format("the witness's requirement '{}' is not its instance's '{}'", w.requirement->formula, req->text));
  std::vector<stl::InputPiece> pieces;
  if (replay)
    pieces = input_signal_on_grid(system, t);
  else
    for (const TrajectoryPiece& piece : t.pieces) pieces.push_back({piece.duration, piece.u});
  try {
    stl::InputSimulator simulator(system);
    const stl::SimulatedTrace& trace = simulator.run(pieces, t.parameters);
    stl::TraceMonitor monitor(*req);
    const double rho = monitor.robustness(trace);
    r.robustness = rho;
    r.samples = trace.samples();
    if (!(rho < 0.0))
      return fail(
          fmt::format("the model's simulation of the witness's input ({} samples) has robustness {:.6g} >= 0 for '{}'",
                      trace.samples(), rho, req->text));
    if (Failure why = prefix_not_violating(monitor.judge(trace), trace.time.empty() ? 0.0 : trace.time.back(),
                                           "the model's simulation of the witness's input", req->text))
      return fail(std::move(*why));
  } catch (const std::exception& e) {
    return fail(fmt::format("the model failed to simulate the witness's input: {}", e.what()));
  }
  r.valid = true;
  r.reason = replay ? fmt::format(
                          "valid: replayed with the suite's own simulator (validation_by_replay), {} input pieces "
                          "of {:.6g} s, robustness {:.6g} over {} samples",
                          pieces.size(), system.info().step_duration, *r.robustness, r.samples)
                    : fmt::format("valid: the model simulated the {} pieces again, robustness {:.6g} over {} samples",
                                  t.pieces.size(), *r.robustness, r.samples);
}

}  // namespace

ValidationReport validate_witness(const System& system, const Witness& w) {
  const Trajectory& t = w.trajectory;
  ValidationReport r;
  const auto fail = [&](std::string why) {
    r.reason = std::move(why);
    return r;
  };
  if (Failure why = shape_mismatch(system, w)) {
    r.malformed = true;
    return fail(std::move(*why));
  }
  if (Failure why = outside_the_system(system, t)) return fail(std::move(*why));
  if (system.signal_model() || system.info().validation_by_replay) {
    validate_by_simulation(system, w, r);
    return r;
  }
  const IntegratorSettings tight = tight_integrator(system.info());
  if (Failure why = too_much_work(t, tight.max_step)) return fail(std::move(*why));

  const auto propagator = system.make_propagator(tight);
  Replay run{system,
             *propagator,
             t.parameters,
             system.info().witness_tolerance,
             tight.max_step,
             t.initial_mode,
             t.initial_x,
             std::vector<double>(t.initial_x.size()),
             0.0,
             std::nullopt,
             {},
             0.0};
  if (system.info().requirement) run.sampler.emplace(system, *system.info().requirement);
  Failure why;
  // The recorded states are compared at every piece's ends; a linear signal's (linear_input),
  // cut into pieces of the integration step, only where a held signal's would be: at multiples of
  // δt and at transitions. In between, the model's own integrator may stray from the tight
  // re-simulation for a step or two and come back (AT's converter with the car at rest: 0.0108 of
  // the witness tolerance 0.01 after the first 0.01 s, measured), which the pieces of δt never
  // show; the robustness is the re-simulation's either way.
  const double dt = system.info().step_duration;
  double now = 0.0;
  bool checked = true;  // the previous piece's end (the start: the initial state)
  for (std::size_t i = 0; i < t.pieces.size() && !why; ++i) {
    now += t.pieces[i].duration;
    const bool on_grid = std::abs(now - std::round(now / dt) * dt) <= 1e-9 * std::max(1.0, now);
    const bool check_end = !t.linear_input || on_grid || t.pieces[i].transition >= 0 || i + 1 == t.pieces.size();
    why = replay_piece(run, t.pieces[i], i, checked, check_end);
    checked = check_end;
  }
  if (!why) why = final_state_mismatch(run, t, r.final_spec);
  if (!why && run.sampler) why = trace_violation(run, w, r);
  r.max_state_error = run.max_state_error;
  if (why) return fail(std::move(*why));
  r.valid = true;
  r.reason = r.robustness ? fmt::format(
                                "valid: {} pieces re-simulated, max state error {:.3g}, robustness {:.6g} "
                                "over {} samples",
                                t.pieces.size(), r.max_state_error, *r.robustness, r.samples)
                          : fmt::format("valid: {} pieces re-simulated, max state error {:.3g}, final s = {:.6g}",
                                        t.pieces.size(), r.max_state_error, r.final_spec);
  return r;
}

}  // namespace hyfal
