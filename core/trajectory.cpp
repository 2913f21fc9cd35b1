#include "core/trajectory.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

namespace hyfal {

namespace {

Json vec(const std::vector<double>& v) { return Json(v); }

// Reads j[key] as T, with a WitnessError that names the field when it is missing or mistyped.
template <class T>
T field(const Json& j, const char* key, const std::string& where) {
  if (!j.is_object() || !j.contains(key))
    throw WitnessError(fmt::format("witness: missing field '{}{}'", where, key));
  try {
    return j.at(key).get<T>();
  } catch (const Json::exception&) {
    throw WitnessError(fmt::format("witness: field '{}{}' has the wrong type", where, key));
  }
}

std::vector<double> numbers(const Json& j, const char* key, const std::string& where,
                            std::size_t expected_size) {
  auto v = field<std::vector<double>>(j, key, where);
  if (expected_size != static_cast<std::size_t>(-1) && v.size() != expected_size)
    throw WitnessError(fmt::format("witness: field '{}{}' has {} values, expected {}", where, key,
                                   v.size(), expected_size));
  for (double x : v)
    if (!std::isfinite(x))
      throw WitnessError(fmt::format("witness: field '{}{}' holds a non-finite value", where, key));
  return v;
}

}  // namespace

Witness make_witness(const System& system, std::string method, std::int64_t trial_seed, Trajectory trajectory) {
  const SystemInfo& info = system.info();
  Witness w;
  w.suite = info.suite;
  w.instance = info.instance;
  w.method = std::move(method);
  w.trial_seed = trial_seed;
  w.state_names = info.state_names;
  w.input_names = info.input_names;
  w.trajectory = std::move(trajectory);
  return w;
}

Json to_json(const Witness& w) {
  const Trajectory& t = w.trajectory;
  Json pieces = Json::array();
  for (const auto& p : t.pieces)
    pieces.push_back({{"mode", p.mode}, {"u", vec(p.u)}, {"duration", p.duration},
                      {"x_start", vec(p.x_start)}, {"x_end", vec(p.x_end)},
                      {"transition", p.transition}});
  return {{"format", "hyfal-witness/1"},
          {"suite", w.suite},
          {"instance", w.instance},
          {"method", w.method},
          {"trial_seed", w.trial_seed},
          {"parameters", vec(t.parameters)},
          {"state_names", w.state_names},
          {"input_names", w.input_names},
          {"initial", {{"mode", t.initial_mode}, {"x", vec(t.initial_x)}}},
          {"pieces", pieces},
          {"final", {{"mode", t.final_mode}, {"x", vec(t.final_x)}, {"spec", t.final_spec}}}};
}

Witness witness_from_json(const Json& j) {
  if (!j.is_object()) throw WitnessError("witness: the document is not a JSON object");
  if (field<std::string>(j, "format", "") != "hyfal-witness/1")
    throw WitnessError("witness: field 'format' is not \"hyfal-witness/1\"");
  Witness w;
  w.suite = field<std::string>(j, "suite", "");
  if (!j.contains("instance") || !j["instance"].is_object())
    throw WitnessError("witness: missing field 'instance' (an object)");
  w.instance = j["instance"];
  w.method = field<std::string>(j, "method", "");
  w.trial_seed = field<std::int64_t>(j, "trial_seed", "");
  w.state_names = field<std::vector<std::string>>(j, "state_names", "");
  w.input_names = field<std::vector<std::string>>(j, "input_names", "");
  const std::size_t n = w.state_names.size(), m = w.input_names.size();
  Trajectory& t = w.trajectory;
  t.parameters = numbers(j, "parameters", "", static_cast<std::size_t>(-1));
  if (!j.contains("initial")) throw WitnessError("witness: missing field 'initial'");
  t.initial_mode = field<Mode>(j["initial"], "mode", "initial.");
  t.initial_x = numbers(j["initial"], "x", "initial.", n);
  if (!j.contains("pieces") || !j["pieces"].is_array())
    throw WitnessError("witness: missing field 'pieces' (an array)");
  for (std::size_t i = 0; i < j["pieces"].size(); ++i) {
    const Json& pj = j["pieces"][i];
    const std::string where = fmt::format("pieces[{}].", i);
    TrajectoryPiece p;
    p.mode = field<Mode>(pj, "mode", where);
    p.u = numbers(pj, "u", where, m);
    p.duration = field<double>(pj, "duration", where);
    if (!(p.duration >= 0.0) || !std::isfinite(p.duration))
      throw WitnessError(fmt::format("witness: field '{}duration' must be finite and >= 0", where));
    p.x_start = numbers(pj, "x_start", where, n);
    p.x_end = numbers(pj, "x_end", where, n);
    p.transition = pj.contains("transition") ? field<int>(pj, "transition", where) : -1;
    t.pieces.push_back(std::move(p));
  }
  if (!j.contains("final")) throw WitnessError("witness: missing field 'final'");
  t.final_mode = field<Mode>(j["final"], "mode", "final.");
  t.final_x = numbers(j["final"], "x", "final.", n);
  t.final_spec = field<double>(j["final"], "spec", "final.");
  return w;
}

Trajectory trajectory_from_tree(const System& system, Propagator& propagator,
                                const NodeStore& tree, NodeId leaf,
                                std::span<const double> parameters) {
  Trajectory t;
  t.parameters.assign(parameters.begin(), parameters.end());
  const auto path = tree.path_to(leaf);
  const NodeId root = path.front();
  t.initial_mode = tree.info(root).mode;
  t.initial_x.assign(tree.state(root).begin(), tree.state(root).end());
  for (std::size_t i = 1; i < path.size(); ++i) {
    const NodeInfo& n = tree.info(path[i]);
    TrajectoryPiece p;
    p.mode = n.edge_mode;
    p.u.assign(tree.input(path[i]).begin(), tree.input(path[i]).end());
    p.duration = n.duration;
    p.transition = n.transition;
    const auto xs = tree.state(path[i - 1]);
    p.x_start.assign(xs.begin(), xs.end());
    p.x_end.resize(xs.size());
    propagator.flow(p.mode, xs, p.u, parameters, p.duration, p.x_end);
    t.pieces.push_back(std::move(p));
  }
  t.final_mode = tree.info(leaf).mode;
  t.final_x.assign(tree.state(leaf).begin(), tree.state(leaf).end());
  t.final_spec = system.spec(t.final_mode, t.final_x, parameters);
  return t;
}

namespace {

// Largest componentwise error relative to the tolerance scale (1 + |x_i|).
double scaled_error(std::span<const double> a, std::span<const double> b) {
  double e = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i)
    e = std::max(e, std::abs(a[i] - b[i]) / (1.0 + std::abs(b[i])));
  return e;
}

}  // namespace

ValidationReport validate_witness(const System& system, const Witness& w) {
  const SystemInfo& info = system.info();
  const Trajectory& t = w.trajectory;
  const double tol = info.witness_tolerance;
  ValidationReport r;
  auto fail = [&](std::string why) {
    r.valid = false;
    r.reason = std::move(why);
    return r;
  };
  const std::size_t n = info.dim();
  if (w.suite != info.suite) return fail(fmt::format("witness is for suite '{}', not '{}'", w.suite, info.suite));
  if (t.initial_x.size() != n || t.final_x.size() != n)
    return fail(fmt::format("witness states have {} values, the system has {}", t.initial_x.size(), n));
  if (t.parameters.size() != info.parameter_box.dim())
    return fail(fmt::format("witness has {} parameters, the system has {}", t.parameters.size(),
                            info.parameter_box.dim()));
  for (std::size_t i = 0; i < t.parameters.size(); ++i)
    if (t.parameters[i] < info.parameter_box.lo[i] - tol || t.parameters[i] > info.parameter_box.hi[i] + tol)
      return fail(fmt::format("parameter {} = {} is outside P", i, t.parameters[i]));
  bool known_start = scaled_error(t.initial_x, info.initial_state) <= tol;
  for (const auto& x0 : info.other_initial_states) known_start = known_start || scaled_error(t.initial_x, x0) <= tol;
  if (t.initial_mode != info.initial_mode || !known_start)
    return fail("the initial state is not one of the system's initial states");

  // A tight, independent integrator: adaptive Dormand-Prince whatever the tree used.
  IntegratorSettings tight;
  tight.kind = IntegratorKind::dopri5;
  tight.abs_tol = 1e-12;
  tight.rel_tol = 1e-12;
  tight.max_step = std::min(info.integrator.max_step, info.step_duration);
  tight.step = tight.max_step / 8;
  auto prop = system.make_propagator(tight);
  const std::span<const double> p = t.parameters;

  Mode q = t.initial_mode;
  std::vector<double> x = t.initial_x, next(n);
  for (std::size_t i = 0; i < t.pieces.size(); ++i) {
    const TrajectoryPiece& piece = t.pieces[i];
    if (piece.mode != q)
      return fail(fmt::format("piece {} flows in mode {}, but the execution is in mode {}", i,
                              system.mode_name(piece.mode), system.mode_name(q)));
    if (piece.x_start.size() != n || piece.x_end.size() != n)
      return fail(fmt::format("piece {} has states of the wrong size", i));
    const double e0 = scaled_error(x, piece.x_start);
    r.max_state_error = std::max(r.max_state_error, e0);
    if (e0 > tol) return fail(fmt::format("piece {}: x_start differs from the re-simulated state by {:.3g}", i, e0));
    const InputSet& U = system.inputs(q);
    if (piece.u.size() != U.dim()) return fail(fmt::format("piece {}: u has {} values, U has {}", i, piece.u.size(), U.dim()));
    for (std::size_t k = 0; k < U.dim(); ++k)
      if (piece.u[k] < U.box.lo[k] - tol || piece.u[k] > U.box.hi[k] + tol)
        return fail(fmt::format("piece {}: input {} = {} is outside U", i, k, piece.u[k]));
    if (system.state_dependent_inputs()) {  // a driver model: u must be admissible at x_start
      // The recorded x_start (within tol of the re-simulation, checked above) is the state the
      // method chose u at; a driver's bands are discontinuous, so it is the one to judge by.
      std::vector<double> lo(U.dim()), hi(U.dim());
      system.input_bounds(q, piece.x_start, lo, hi);
      for (std::size_t k = 0; k < U.dim(); ++k)
        if (piece.u[k] < lo[k] - tol || piece.u[k] > hi[k] + tol)
          return fail(fmt::format("piece {}: input {} = {} is outside the admissible [{}, {}] at x_start", i, k,
                                  piece.u[k], lo[k], hi[k]));
    }
    // Flow in short sub-intervals; inside the piece the invariant must hold and no transition
    // may be enabled (they are urgent).
    const int sub = std::max(1, static_cast<int>(std::ceil(piece.duration / tight.max_step)));
    const double h = piece.duration / sub;
    for (int s = 0; s < sub; ++s) {
      if (prop->flow(q, x, piece.u, p, h, next) < 0)
        return fail(fmt::format("piece {}: the state became non-finite", i));
      x.swap(next);
      const bool inside = (s + 1 < sub);
      if (!system.invariant(q, x, p) && inside)
        return fail(fmt::format("piece {}: the invariant of mode {} fails at t = {:.6g}", i,
                                system.mode_name(q), h * (s + 1)));
      if (inside)
        for (int k = 0; k < system.guard_count(q); ++k)
          if (system.guard(q, k, x, p) > tol)
            return fail(fmt::format("piece {}: transition {} is enabled at t = {:.6g} inside the piece, "
                                    "but transitions are urgent", i, k, h * (s + 1)));
    }
    const double e1 = scaled_error(x, piece.x_end);
    r.max_state_error = std::max(r.max_state_error, e1);
    if (e1 > tol) return fail(fmt::format("piece {}: x_end differs from the re-simulated state by {:.3g}", i, e1));
    if (piece.transition >= 0) {
      const int k = piece.transition;
      if (k >= system.guard_count(q))
        return fail(fmt::format("piece {}: mode {} has no transition {}", i, system.mode_name(q), k));
      if (system.guard(q, k, x, p) < -tol)
        return fail(fmt::format("piece {}: transition {} is not enabled at the end of the piece", i, k));
      q = system.jump(q, k, x, p);
    }
  }
  const double ef = scaled_error(x, t.final_x);
  r.max_state_error = std::max(r.max_state_error, ef);
  if (q != t.final_mode) return fail(fmt::format("the final mode is {}, the execution ends in {}", system.mode_name(t.final_mode), system.mode_name(q)));
  if (ef > tol) return fail(fmt::format("the final state differs from the re-simulated one by {:.3g}", ef));
  r.final_spec = system.spec(q, x, p);
  if (std::abs(r.final_spec - t.final_spec) > tol * (1.0 + std::abs(r.final_spec)))
    return fail(fmt::format("the recorded final s = {:.6g} differs from the re-simulated s = {:.6g}",
                            t.final_spec, r.final_spec));
  if (r.final_spec > tol)
    return fail(fmt::format("the re-simulated final state is safe: s = {:.6g} > {:.3g}", r.final_spec, tol));
  r.valid = true;
  r.reason = fmt::format("valid: {} pieces re-simulated, max state error {:.3g}, final s = {:.6g}",
                         t.pieces.size(), r.max_state_error, r.final_spec);
  return r;
}

}  // namespace hyfal
