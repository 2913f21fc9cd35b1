#include "core/simulate/input_simulator.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

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

  const SimulatedTrace& run_model(std::span<const InputPiece> pieces, std::span<const double> p);
};

InputSimulator::InputSimulator(const System& system) : impl_(std::make_unique<Impl>(system)) {}
InputSimulator::~InputSimulator() = default;
void InputSimulator::set_interrupt(PropagationInterrupt interrupt) {
  if (impl_->prop)
    impl_->prop->set_interrupt(std::move(interrupt));
  else
    impl_->interrupt = std::move(interrupt), impl_->interrupted = false;
}
bool InputSimulator::interrupted() const { return impl_->prop ? impl_->prop->interrupted() : impl_->interrupted; }
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

const SimulatedTrace& InputSimulator::run(std::span<const InputPiece> pieces, std::span<const double> p) {
  const System& system = impl_->system;
  const SystemInfo& info = system.info();
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    if (pieces[i].u.size() != info.input_names.size())
      throw std::invalid_argument(fmt::format("input piece {}: {} values, the system has {} inputs", i,
                                              pieces[i].u.size(), info.input_names.size()));
    if (!(pieces[i].duration >= 0.0 && std::isfinite(pieces[i].duration)))
      throw std::invalid_argument(
          fmt::format("input piece {}: duration {} is not a finite number >= 0", i, pieces[i].duration));
  }
  SimulatedTrace& trace = impl_->trace;
  trace.time.clear();
  for (auto& s : trace.signals) s.clear();
  trace.end = PropagationEnd::completed;
  trace.problem.clear();
  trace.integration_steps = 0;
  trace.transitions = 0;
  trace.piece_ends.clear();
  if (impl_->model) return impl_->run_model(pieces, p);
  AllSignals sink(system, trace, p);
  Propagator& prop = *impl_->prop;
  prop.set_trace(&sink);
  Mode q = info.initial_mode;
  std::vector<double>& x = impl_->x;
  std::vector<double>& next = impl_->next;
  x = info.initial_state;
  next.resize(x.size());
  impl_->no_input.assign(info.input_names.size(), 0.0);
  sink.begin(0.0, pieces.empty() ? std::span<const double>(impl_->no_input) : std::span<const double>(pieces[0].u));
  sink.sample(0.0, q, x, std::nan(""));  // the first sample, with the first piece's input
  double t = 0.0;
  for (const InputPiece& piece : pieces) {
    const HeldInputEnd e = hold_input(
        prop, q, x, next, piece.u, p, t, piece.duration,
        [&](double now, Mode at) {
          if (!system.inputs(at).box.contains(piece.u)) {
            trace.problem =
                fmt::format("at t = {:.6g} the input lies outside the input box of mode {}", now, system.mode_name(at));
            return false;
          }
          sink.begin(now, piece.u);
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
  return trace;
}

SimulatedTrace simulate_inputs(const System& system, std::span<const InputPiece> pieces, std::span<const double> p) {
  InputSimulator simulator(system);
  return simulator.run(pieces, p);
}

}  // namespace hyfal::stl
