#include "core/witness/trajectory.hpp"

#include <algorithm>
#include <stdexcept>

#include "core/simulate/held_input.hpp"

namespace hyfal {

HeldInputEnd append_held_input(Trajectory& t, Propagator& prop, Mode& q, std::vector<double>& x,
                               std::vector<double>& next, std::span<const double> u, std::span<const double> p,
                               double duration) {
  const HeldInputEnd e = hold_input(
      prop, q, x, next, u, p, 0.0, duration, [](double, Mode) { return true; },
      [&](const PropagationResult& r, Mode from, std::span<const double> x_start, double) {
        TrajectoryPiece tp;
        tp.mode = from;
        tp.u.assign(u.begin(), u.end());
        tp.duration = r.duration;
        tp.transition = r.end == PropagationEnd::jumped ? r.transition : -1;
        tp.x_start.assign(x_start.begin(), x_start.end());
        tp.x_end.resize(x_start.size());
        prop.flow(from, x_start, u, p, r.duration, tp.x_end);  // before the reset
        if (r.duration > 0.0 || tp.transition >= 0) t.pieces.push_back(std::move(tp));
      });
  q = e.result.mode;
  return e;
}

Trajectory trajectory_from_tree(const System& system, Propagator& propagator, const NodeStore& tree, NodeId leaf,
                                std::span<const double> parameters) {
  Trajectory t;
  t.parameters.assign(parameters.begin(), parameters.end());
  const auto path = tree.path_to(leaf);
  const NodeId root = path.front();
  t.initial_mode = tree.info(root).mode;
  t.initial_x.assign(tree.state(root).begin(), tree.state(root).end());
  if (system.info().requirement && system.info().held_inputs) {
    // A fresh propagator in STL mode, as the tree propagated its edges (the planner's may be
    // interrupted: its deadline passed as the falsifying node was found).
    NoSamples none;
    const auto prop = system.make_propagator();
    prop->set_trace(&none);
    std::vector<double> x, next;
    for (std::size_t i = 1; i < path.size(); ++i) {
      const NodeInfo& n = tree.info(path[i]);
      Mode q = n.edge_mode;
      const auto xs = tree.state(path[i - 1]);
      x.assign(xs.begin(), xs.end());
      // Held for δt, as every tree method asks (n.duration, the sum of the flow times, may differ
      // from it in the last bit, and an edge cut short by the invariant stops there again).
      append_held_input(t, *prop, q, x, next, tree.input(path[i]), parameters, system.info().step_duration);
      const auto xe = tree.state(path[i]);
      if (q != n.mode || !std::equal(x.begin(), x.end(), xe.begin(), xe.end()))
        throw std::logic_error("trajectory_from_tree: an edge re-simulates to another state than the tree's");
    }
  } else {
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
  }
  t.final_mode = tree.info(leaf).mode;
  t.final_x.assign(tree.state(leaf).begin(), tree.state(leaf).end());
  t.final_spec = system.spec(t.final_mode, t.final_x, parameters);
  return t;
}

namespace stl {

Trajectory trajectory_of_inputs(const System& system, std::span<const InputPiece> pieces, std::span<const double> p) {
  const SystemInfo& info = system.info();
  Trajectory t;
  t.parameters.assign(p.begin(), p.end());
  t.initial_mode = info.initial_mode;
  t.initial_x = info.initial_state;
  if (system.signal_model()) {  // no states: the pieces are the input signal itself
    for (const InputPiece& piece : pieces) t.pieces.push_back({info.initial_mode, piece.u, piece.duration, {}, {}, -1});
    t.final_mode = info.initial_mode;
    t.final_spec = system.spec(info.initial_mode, t.final_x, p);
    return t;
  }
  NoSamples none;
  const auto prop = system.make_propagator();
  prop->set_trace(&none);
  Mode q = info.initial_mode;
  std::vector<double> x = info.initial_state, next(x.size());
  for (const InputPiece& piece : pieces) {
    const HeldInputEnd e = append_held_input(t, *prop, q, x, next, piece.u, p, piece.duration);
    if (e.result.end == PropagationEnd::invariant || e.result.end == PropagationEnd::rejected) break;
  }
  t.final_mode = q;
  t.final_x = x;
  t.final_spec = system.spec(q, x, p);
  return t;
}

}  // namespace stl

}  // namespace hyfal
