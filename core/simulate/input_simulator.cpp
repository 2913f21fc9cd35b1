#include "core/simulate/input_simulator.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "core/simulate/difference_quotient.hpp"
#include "core/simulate/held_input.hpp"

namespace hyfal::stl {

namespace {

// Records every signal of the system at each sample: outputs, the current input, s.
class AllSignals final : public SampleSink {
 public:
  AllSignals(const System& system, SimulatedTrace& trace, std::span<const double> p)
      : system_(system), trace_(trace), p_(p), outputs_(system.info().outputs.size()) {
    trace_.signals.resize(system_signals(system.info()).size());  // kept when already sized
  }
  void begin(double t0, std::span<const double> u) {
    t0_ = t0;
    u_ = u;
  }
  void sample(double t, Mode q, std::span<const double> x, double safety) override {
    if (!outputs_.empty()) system_.outputs(q, x, u_, p_, outputs_);
    trace_.time.push_back(t0_ + t);
    std::size_t s = 0;
    for (double y : outputs_) trace_.signals[s++].push_back(y);
    for (double u : u_) trace_.signals[s++].push_back(u);
    trace_.signals[s].push_back(std::isnan(safety) ? system_.spec(q, x, p_) : safety);
  }
  bool samples_unsafe_entries() const override { return true; }

 private:
  const System& system_;
  SimulatedTrace& trace_;
  std::span<const double> p_;
  std::vector<double> outputs_;
  double t0_ = 0.0;
  std::span<const double> u_;
};

// Records, beside AllSignals' signals, each sample's augmented state z = [x | S | T], mode and
// input piece (TangentPropagator, core/model/system.hpp), for signal_tangent.
class TangentSamples final : public SampleSink {
 public:
  // keep: the samples whose z is recorded (sorted; empty: every one); a sample at the same time as
  // the one before it is recorded with it (a reset's after-state, whose T the one before reads).
  TangentSamples(AllSignals& signals, const std::vector<double>& time, std::size_t n, std::span<const std::size_t> keep,
                 std::vector<double>& z, std::vector<std::size_t>& slot, std::vector<Mode>& modes,
                 std::vector<std::uint32_t>& pieces)
      : signals_(signals), time_(time), n_(n), keep_(keep), z_(z), slot_(slot), modes_(modes), pieces_(pieces) {}
  void set_piece(std::uint32_t piece) { piece_ = piece; }
  void sample(double t, Mode q, std::span<const double> z, double safety) override {
    const std::size_t i = slot_.size();
    signals_.sample(t, q, z.first(n_), safety);
    while (next_ < keep_.size() && keep_[next_] < i) ++next_;
    const bool with_previous = i > 0 && slot_.back() != SIZE_MAX && time_[i] == time_[i - 1];
    if (keep_.empty() || (next_ < keep_.size() && keep_[next_] == i) || with_previous) {
      slot_.push_back(z_.size() / z.size());
      z_.insert(z_.end(), z.begin(), z.end());
    } else {
      slot_.push_back(SIZE_MAX);
    }
    modes_.push_back(q);
    pieces_.push_back(piece_);
  }
  bool samples_unsafe_entries() const override { return signals_.samples_unsafe_entries(); }

 private:
  AllSignals& signals_;
  const std::vector<double>& time_;
  std::size_t n_;
  std::span<const std::size_t> keep_;
  std::size_t next_ = 0;
  std::vector<double>& z_;
  std::vector<std::size_t>& slot_;
  std::vector<Mode>& modes_;
  std::vector<std::uint32_t>& pieces_;
  std::uint32_t piece_ = 0;
};

}  // namespace

struct InputSimulator::Impl {
  explicit Impl(const System& s) : system(s), model(s.signal_model()) {
    if (!model) prop = s.make_propagator();
  }
  const System& system;
  const SignalModel* model;
  std::unique_ptr<Propagator> prop;  // a model's own (none for a signal model)
  SimulatedTrace trace;
  std::vector<double> x, next, no_input;
  // A signal model's: its interrupt (checked after each of its simulations, which nothing can cut
  // short), and its outputs.
  PropagationInterrupt interrupt;
  bool interrupted = false;
  std::vector<std::vector<double>> outputs;

  // Tangents (run_with_tangents): the propagator of a piece's directions [its input (m) | the
  // parameters (np, when asked) | the state at its start (n)], the augmented input of the current
  // piece, and every kept sample's z, mode and piece; each piece's S at its end (n × D, the
  // piece's input, parameter and transition matrices); the pieces' inputs, weights and end times,
  // and p, for add_signal_tangents.
  std::unique_ptr<TangentPropagator> tangent;
  std::size_t directions = 0;       // D = m + np + n
  std::size_t parameter_count = 0;  // np
  std::size_t variables = 0;
  std::vector<double> augmented_input;
  std::vector<double> sample_z;
  std::vector<std::size_t> sample_slot;  // per sample: its z's place in sample_z, SIZE_MAX if not kept
  std::vector<Mode> sample_mode;
  std::vector<std::uint32_t> sample_piece;
  std::vector<double> piece_end_s;       // piece k's S at its end at [k n D, (k + 1) n D)
  std::vector<std::vector<double>> piece_u;
  std::vector<ControlWeights> piece_weights;
  std::vector<double> piece_end;
  std::vector<double> parameters;
  std::vector<double> scratch_x, scratch_u, scratch_p, scratch_y, scratch_y2, scratch_f, moving, row, piece_rows,
      adjoint;

  // ∂(signal at sample)/∂[the sample's piece's input | p | the state at that piece's start] into
  // row (D values).
  void sample_row(std::size_t signal, std::size_t sample, std::vector<double>& row);

  const SimulatedTrace& run_model(std::span<const InputPiece> pieces, std::span<const double> p);
  // The loop run() and run_with_tangents() share: each piece held through hold_input, from x (the
  // initial state, or z), its input given by input(k) (the piece's, or the augmented one).
  template <class PieceInput>
  void drive(Propagator& prop, SampleSink& sink, AllSignals& signals, std::span<const InputPiece> pieces,
             std::span<const double> p, PieceInput&& input);
  void check_pieces(std::span<const InputPiece> pieces) const;
  void clear_trace();
};

InputSimulator::InputSimulator(const System& system) : impl_(std::make_unique<Impl>(system)) {}
InputSimulator::~InputSimulator() = default;
void InputSimulator::set_interrupt(PropagationInterrupt interrupt) {
  impl_->interrupt = std::move(interrupt);
  impl_->interrupted = false;
  if (impl_->prop) impl_->prop->set_interrupt(impl_->interrupt);
  if (impl_->tangent) impl_->tangent->propagator().set_interrupt(impl_->interrupt);
}
bool InputSimulator::interrupted() const {
  if (!impl_->prop) return impl_->interrupted;
  return impl_->prop->interrupted() || (impl_->tangent && impl_->tangent->propagator().interrupted());
}
const SimulatedTrace& InputSimulator::trace() const { return impl_->trace; }

// A signal model's trace: its outputs at its samples, the input held at each (at a piece's end,
// that piece's: a sample belongs to the prefix that reaches it), the safety signal s(q0, no
// state) throughout, and piece_ends from the samples' times.
const SimulatedTrace& InputSimulator::Impl::run_model(std::span<const InputPiece> pieces, std::span<const double> p) {
  const SystemInfo& info = system.info();
  trace.signals.resize(system_signals(info).size());
  if (interrupted || std::chrono::steady_clock::now() >= interrupt.deadline || interrupt.stop.stop_requested()) {
    interrupted = true;
    trace.end = PropagationEnd::rejected;
    return trace;
  }
  outputs.resize(info.outputs.size());
  model->simulate(pieces, p, trace.time, outputs);
  // The contract (SignalModel): samples up to the input signal's end. A shorter trace would be a
  // prefix, which a search must not take for the whole signal.
  double length = 0.0;
  for (const InputPiece& piece : pieces) length += piece.duration;
  const double last = trace.time.empty() ? 0.0 : trace.time.back();
  if (last < length - 1e-9 * std::max(1.0, length))
    throw std::runtime_error(
        fmt::format("the model's trace ends at t = {:.6g} s, before the horizon {:.6g} s (its input "
                    "signal's end): simulate must return samples up to the last input time",
                    last, length));
  const std::size_t n = trace.time.size(), m = info.input_names.size();
  for (std::size_t k = 0; k < outputs.size(); ++k) trace.signals[k] = outputs[k];
  const double safety = system.spec(info.initial_mode, x, p);
  std::size_t piece = 0;
  double end = pieces.empty() ? 0.0 : pieces[0].duration;
  for (std::size_t i = 0; i < n; ++i) {
    while (piece + 1 < pieces.size() && trace.time[i] > end * (1.0 + 1e-12) + 1e-12) {
      trace.piece_ends.push_back(i);
      end += pieces[++piece].duration;
    }
    for (std::size_t j = 0; j < m; ++j)
      trace.signals[outputs.size() + j].push_back(pieces.empty() ? 0.0 : pieces[piece].u[j]);
    trace.signals[outputs.size() + m].push_back(safety);
  }
  while (trace.piece_ends.size() < pieces.size()) trace.piece_ends.push_back(n);
  if (std::chrono::steady_clock::now() >= interrupt.deadline || interrupt.stop.stop_requested()) {
    interrupted = true;
    trace.end = PropagationEnd::rejected;
  }
  return trace;
}

void InputSimulator::Impl::check_pieces(std::span<const InputPiece> pieces) const {
  const SystemInfo& info = system.info();
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    if (pieces[i].u.size() != info.input_names.size())
      throw std::invalid_argument(fmt::format("input piece {}: {} values, the system has {} inputs", i,
                                              pieces[i].u.size(), info.input_names.size()));
    if (!(pieces[i].duration >= 0.0 && std::isfinite(pieces[i].duration)))
      throw std::invalid_argument(
          fmt::format("input piece {}: duration {} is not a finite number >= 0", i, pieces[i].duration));
  }
}

void InputSimulator::Impl::clear_trace() {
  trace.time.clear();
  for (auto& s : trace.signals) s.clear();
  trace.end = PropagationEnd::completed;
  trace.problem.clear();
  trace.integration_steps = 0;
  trace.transitions = 0;
  trace.piece_ends.clear();
}

template <class PieceInput>
void InputSimulator::Impl::drive(Propagator& prop, SampleSink& sink, AllSignals& signals,
                                 std::span<const InputPiece> pieces, std::span<const double> p, PieceInput&& input) {
  const SystemInfo& info = system.info();
  prop.set_trace(&sink);
  Mode q = info.initial_mode;
  next.resize(x.size());
  no_input.assign(info.input_names.size(), 0.0);
  signals.begin(0.0, pieces.empty() ? std::span<const double>(no_input) : std::span<const double>(pieces[0].u));
  if (!pieces.empty()) (void)input(0);
  sink.sample(0.0, q, x, std::nan(""));  // the first sample, with the first piece's input
  double t = 0.0;
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    const InputPiece& piece = pieces[k];
    const std::span<const double> u = input(k);
    const HeldInputEnd e = hold_input(
        prop, q, x, next, u, p, t, piece.duration,
        [&](double now, Mode at) {
          if (!system.inputs(at).box.contains(piece.u)) {
            trace.problem =
                fmt::format("at t = {:.6g} the input lies outside the input box of mode {}", now, system.mode_name(at));
            return false;
          }
          signals.begin(now, piece.u);
          return true;
        },
        [&](const PropagationResult& r, Mode, std::span<const double>, double) {
          trace.transitions += r.end == PropagationEnd::jumped;
        });
    trace.integration_steps += e.result.steps;
    if (e.stopped || e.result.end == PropagationEnd::rejected || e.result.end == PropagationEnd::invariant) {
      trace.end = e.stopped ? PropagationEnd::rejected : e.result.end;
      break;
    }
    q = e.result.mode;
    t = e.end_time;
    trace.piece_ends.push_back(trace.time.size());
  }
  prop.set_trace(nullptr);
}

const SimulatedTrace& InputSimulator::run(std::span<const InputPiece> pieces, std::span<const double> p) {
  impl_->check_pieces(pieces);
  impl_->clear_trace();
  if (impl_->model) return impl_->run_model(pieces, p);
  AllSignals sink(impl_->system, impl_->trace, p);
  impl_->x = impl_->system.info().initial_state;
  impl_->drive(*impl_->prop, sink, sink, pieces, p, [&](std::size_t k) { return std::span<const double>(pieces[k].u); });
  return impl_->trace;
}

bool InputSimulator::has_tangents() const {
  if (impl_->model) return false;
  if (!impl_->tangent) impl_->tangent = impl_->system.make_tangent_propagator(0);
  return impl_->tangent != nullptr;
}

std::size_t InputSimulator::variables() const { return impl_->variables; }

std::size_t InputSimulator::tangent_sample_size(bool parameters) const {
  const SystemInfo& info = impl_->system.info();
  const std::size_t n = info.initial_state.size();
  const std::size_t dirs = n + info.input_names.size() + (parameters ? info.parameters.size() : 0);
  return n * (1 + dirs) + dirs;
}

const SimulatedTrace& InputSimulator::run_with_tangents(std::span<const InputPiece> pieces,
                                                        std::span<const ControlWeights> weights, std::size_t points,
                                                        std::span<const double> p, std::span<const std::size_t> keep,
                                                        bool parameters) {
  Impl& d = *impl_;
  d.check_pieces(pieces);
  if (weights.size() != pieces.size())
    throw std::invalid_argument(fmt::format("{} control weights for {} input pieces", weights.size(), pieces.size()));
  for (std::size_t k = 0; k < weights.size(); ++k)
    if (weights[k].point + (weights[k].next != 0.0 ? 1 : 0) >= points)
      throw std::invalid_argument(fmt::format("input piece {} reads control point {}, past the {} points", k,
                                              weights[k].point + (weights[k].next != 0.0 ? 1 : 0), points));
  if (d.model) throw std::logic_error("a model known only by its simulations has no tangents");
  const SystemInfo& info = d.system.info();
  const std::size_t m = info.input_names.size(), n = info.initial_state.size();
  const std::size_t np = parameters ? p.size() : 0;
  const std::size_t dirs = m + np + n;
  if (!d.tangent || d.directions != dirs) {
    d.tangent = d.system.make_tangent_propagator(dirs);
    d.directions = dirs;
    if (d.tangent) d.tangent->propagator().set_interrupt(d.interrupt);
  }
  if (!d.tangent) throw std::logic_error("this system has no tangents (gradients need a model integrated by RK4)");
  d.tangent->set_parameter_directions(m, np);
  d.parameter_count = np;
  d.variables = points * m;
  d.clear_trace();
  d.sample_z.clear();
  d.sample_slot.clear();
  d.sample_mode.clear();
  d.sample_piece.clear();
  d.piece_end_s.clear();
  d.piece_u.assign(pieces.size(), {});
  d.piece_weights.assign(weights.begin(), weights.end());
  d.piece_end.resize(pieces.size());
  double end = 0.0;
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    d.piece_u[k] = pieces[k].u;
    end += pieces[k].duration;
    d.piece_end[k] = end;
  }
  d.parameters.assign(p.begin(), p.end());
  AllSignals signals(d.system, d.trace, p);
  TangentSamples sink(signals, d.trace.time, n, keep, d.sample_z, d.sample_slot, d.sample_mode, d.sample_piece);
  d.x.assign(n * (1 + dirs) + dirs, 0.0);
  std::copy(info.initial_state.begin(), info.initial_state.end(), d.x.begin());
  // U: direction j < m moves input j by one; the others move no input.
  d.augmented_input.assign(m * (1 + dirs), 0.0);
  for (std::size_t j = 0; j < m; ++j) d.augmented_input[m + j * m + j] = 1.0;
  // The first piece starts from the fixed initial state: its state directions are not propagated.
  d.tangent->set_active_variables(m + np);
  std::size_t last = SIZE_MAX;
  d.drive(d.tangent->propagator(), sink, signals, pieces, p, [&](std::size_t k) {
    if (k != last) {
      // The previous piece's end: keep its S. Then restart the directions: S = [0 | 0 | I], and
      // T = 0 (a piece's start time is fixed).
      const auto s = d.x.begin() + static_cast<std::ptrdiff_t>(n);
      if (last != SIZE_MAX) {
        d.piece_end_s.insert(d.piece_end_s.end(), s, s + static_cast<std::ptrdiff_t>(n * dirs));
        d.tangent->set_active_variables(dirs);
      }
      last = k;
      sink.set_piece(static_cast<std::uint32_t>(k));
      std::copy(pieces[k].u.begin(), pieces[k].u.end(), d.augmented_input.begin());
      std::fill(s, d.x.end(), 0.0);
      for (std::size_t i = 0; i < n; ++i) s[static_cast<std::ptrdiff_t>((m + np + i) * n + i)] = 1.0;
    }
    return std::span<const double>(d.augmented_input);
  });
  return d.trace;
}

void InputSimulator::Impl::sample_row(std::size_t signal, std::size_t sample, std::vector<double>& out) {
  const SystemInfo& info = system.info();
  const std::size_t m = info.input_names.size(), n = info.initial_state.size(), dirs = directions;
  const std::size_t np = parameter_count;
  const std::size_t outputs = info.outputs.size();
  const std::size_t samples = sample_mode.size();
  const std::size_t dz = n * (1 + dirs) + dirs;
  out.assign(dirs, 0.0);
  const double* z = sample_z.data() + sample_slot[sample] * dz;
  const Mode q = sample_mode[sample];
  const std::size_t piece = sample_piece[sample];
  const std::vector<double>& u = piece_u.empty() ? no_input : piece_u[piece];
  if (signal >= outputs && signal < outputs + m) {  // an input: its own direction
    if (!piece_u.empty()) out[signal - outputs] = 1.0;
    return;
  }
  // The time tangent of the sample: T, unless it stands at its piece's end (a fixed time); the
  // state before a reset takes the one after it (the same instant, whose T the jump set).
  const double time = trace.time[sample];
  const bool at_piece_end = !piece_end.empty() && std::abs(time - piece_end[piece]) <= 1e-12 * std::max(1.0, time);
  std::size_t from = sample;
  while (from + 1 < samples && trace.time[from + 1] == time) ++from;
  const double* tt = sample_z.data() + sample_slot[from] * dz + n * (1 + dirs);
  // dx_v = S_v + f T_v.
  moving.assign(z + n, z + n + n * dirs);
  if (!at_piece_end) {
    scratch_f.resize(n);
    system.derivative(q, std::span<const double>(z, n), u, parameters, scratch_f);
    for (std::size_t v = 0; v < dirs; ++v)
      if (tt[v] != 0.0)
        for (std::size_t i = 0; i < n; ++i) moving[v * n + i] += scratch_f[i] * tt[v];
  }
  // The signal's slopes in x (and u) by central differences, then the chain rule.
  scratch_x.assign(z, z + n);
  scratch_u.assign(u.begin(), u.end());
  scratch_y.resize(outputs);
  scratch_y2.resize(outputs);
  auto value = [&](std::vector<double>& y) {
    if (signal == outputs + m) return system.spec(q, scratch_x, parameters);
    system.outputs(q, scratch_x, scratch_u, parameters, y);
    return y[signal];
  };
  const double y0 = value(scratch_y);
  for (std::size_t i = 0; i < n; ++i) {
    const double h = difference_step(z[i]);
    scratch_x[i] = z[i] + h;
    const double a = value(scratch_y);
    scratch_x[i] = z[i] - h;
    const double b = value(scratch_y2);
    scratch_x[i] = z[i];
    const double slope = difference_quotient(b, y0, a, h);
    if (slope == 0.0) continue;
    for (std::size_t v = 0; v < dirs; ++v) out[v] += slope * moving[v * n + i];
  }
  if (signal < outputs && !piece_u.empty())
    for (std::size_t j = 0; j < m; ++j) {
      const double h = difference_step(u[j]);
      scratch_u[j] = u[j] + h;
      const double a = value(scratch_y);
      scratch_u[j] = u[j] - h;
      const double b = value(scratch_y2);
      scratch_u[j] = u[j];
      out[j] += difference_quotient(b, y0, a, h);
    }
  // The signal's own slope in p (F16's outputs read the attitude p in its start mode).
  scratch_p = parameters;
  for (std::size_t j = 0; j < np; ++j) {
    const double h = difference_step(parameters[j]);
    auto at = [&](double pj, std::vector<double>& y) {
      scratch_p[j] = pj;
      const double r = signal == outputs + m
                           ? system.spec(q, scratch_x, scratch_p)
                           : (system.outputs(q, scratch_x, scratch_u, scratch_p, y), y[signal]);
      scratch_p[j] = parameters[j];
      return r;
    };
    const double a = at(parameters[j] + h, scratch_y), b = at(parameters[j] - h, scratch_y2);
    out[m + j] += difference_quotient(b, y0, a, h);
  }
}

void InputSimulator::add_signal_tangents(std::span<const SignalTerm> terms, std::span<double> out,
                                         std::span<double> parameters_out) {
  Impl& d = *impl_;
  const SystemInfo& info = d.system.info();
  const std::size_t m = info.input_names.size(), n = info.initial_state.size(), dirs = d.directions;
  const std::size_t np = d.parameter_count;
  const std::size_t samples = d.sample_mode.size();
  if (out.size() != d.variables)
    throw std::invalid_argument(
        fmt::format("signal tangents: room for {} values, {} variables", out.size(), d.variables));
  if (!parameters_out.empty() && parameters_out.size() != np)
    throw std::invalid_argument(fmt::format("signal tangents: room for {} parameter slopes, {} run with tangents",
                                            parameters_out.size(), np));
  std::size_t last_piece = 0;
  for (const SignalTerm& t : terms) {
    if (t.sample >= samples || t.signal > info.outputs.size() + m)
      throw std::invalid_argument(
          fmt::format("signal tangents: signal {} at sample {} of {}", t.signal, t.sample, samples));
    if (d.sample_slot[t.sample] == SIZE_MAX)
      throw std::logic_error(fmt::format("signal tangents: sample {} was not kept by run_with_tangents", t.sample));
    last_piece = std::max<std::size_t>(last_piece, d.sample_piece[t.sample]);
  }
  if (terms.empty()) return;
  // Each piece's terms, with respect to [its input | p | its start state].
  d.piece_rows.assign((last_piece + 1) * dirs, 0.0);
  for (const SignalTerm& t : terms) {
    d.sample_row(t.signal, t.sample, d.row);
    double* acc = d.piece_rows.data() + d.sample_piece[t.sample] * dirs;
    for (std::size_t v = 0; v < dirs; ++v) acc[v] += t.weight * d.row[v];
  }
  // Backwards over the pieces: λ, the derivative with respect to the state at the next piece's
  // start (this piece's end), reaches this piece's input, p and start state through S at its end.
  d.adjoint.assign(n, 0.0);
  for (std::size_t k = last_piece + 1; k-- > 0;) {
    double* acc = d.piece_rows.data() + k * dirs;
    if (k < last_piece) {
      const double* s = d.piece_end_s.data() + k * n * dirs;
      for (std::size_t v = 0; v < dirs; ++v) {
        double a = 0.0;
        for (std::size_t i = 0; i < n; ++i) a += d.adjoint[i] * s[v * n + i];
        acc[v] += a;
      }
    }
    std::copy(acc + m + np, acc + dirs, d.adjoint.begin());
    if (!parameters_out.empty())
      for (std::size_t j = 0; j < np; ++j) parameters_out[j] += acc[m + j];
    if (d.piece_weights.empty()) continue;  // no input pieces: no control point
    const ControlWeights& w = d.piece_weights[k];
    for (std::size_t j = 0; j < m; ++j) {
      out[w.point * m + j] += w.here * acc[j];
      if (w.next != 0.0) out[(w.point + 1) * m + j] += w.next * acc[j];
    }
  }
}

void InputSimulator::signal_tangent(std::size_t signal, std::size_t sample, std::span<double> out) {
  std::fill(out.begin(), out.end(), 0.0);
  const SignalTerm term{signal, sample, 1.0};
  add_signal_tangents(std::span<const SignalTerm>(&term, 1), out);
}

SimulatedTrace simulate_inputs(const System& system, std::span<const InputPiece> pieces, std::span<const double> p) {
  InputSimulator simulator(system);
  return simulator.run(pieces, p);
}

}  // namespace hyfal::stl
