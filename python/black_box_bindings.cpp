// hyfal.BlackBox: a Python function `simulate(time, inputs) -> (time, signals)` as a
// stl::SignalModel (core/model/signal_model.hpp) behind make_black_box (core/model/black_box.hpp),
// so that the signal searches of hyfal.falsify drive it as they drive a suite, and the validator
// re-checks a witness by calling the function again. The function is called with the GIL held
// (hyfal.falsify releases it otherwise), so trials on several threads call it one at a time.
#include "python/python_black_box.hpp"
#include "core/model/signal_model.hpp"

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>

namespace hyfal::python {

namespace {

thread_local int models_running = 0;  // this thread's calls of a model's simulate in progress

// Marks this thread as inside a model's simulate for the object's lifetime.
struct InsideModel {
  InsideModel() { ++models_running; }
  ~InsideModel() { --models_running; }
  InsideModel(const InsideModel&) = delete;
  InsideModel& operator=(const InsideModel&) = delete;
};

}  // namespace

bool inside_model_simulate() { return models_running > 0; }

namespace {

class PythonModel final : public stl::SignalModel {
 public:
  PythonModel(py::function fn, std::vector<std::string> inputs, std::vector<std::string> signals)
      : fn_(std::move(fn)), inputs_(std::move(inputs)), signals_(std::move(signals)) {}
  ~PythonModel() override {
    py::gil_scoped_acquire gil;
    fn_ = py::function();
  }

  // The input signal as hyfal.Witness gives it: times 0, then each piece's end; each input's
  // value held from times[k] to times[k + 1], the last repeating the one before.
  void simulate(std::span<const stl::InputPiece> pieces, std::span<const double>, std::vector<double>& time,
                std::vector<std::vector<double>>& outputs) const override {
    py::gil_scoped_acquire gil;
    const InsideModel inside;  // hyfal.falsify refuses to run from in here
    try {
      std::vector<double> t{0.0};
      for (const auto& p : pieces) t.push_back(t.back() + p.duration);
      py::dict u;
      for (std::size_t i = 0; i < inputs_.size(); ++i) {
        py::array_t<double> values(static_cast<py::ssize_t>(t.size()));
        double* v = values.mutable_data();
        for (std::size_t k = 0; k < pieces.size(); ++k) v[k] = pieces[k].u[i];
        v[pieces.size()] = pieces.empty() ? 0.0 : pieces.back().u[i];
        u[py::str(inputs_[i])] = values;
      }
      py::array_t<double> times(static_cast<py::ssize_t>(t.size()), t.data());
      const py::object result = fn_(times, u);
      read(result, time, outputs);
    } catch (py::error_already_set& e) {
      throw std::runtime_error(fmt::format("the model's simulate raised {}", e.what()));
    }
  }

 private:
  // (time, {signal: values}): every declared signal, one finite value per time; times finite,
  // from >= 0, non-decreasing.
  void read(const py::object& result, std::vector<double>& time, std::vector<std::vector<double>>& outputs) const {
    if (!py::isinstance<py::tuple>(result) || py::len(result) != 2)
      throw std::runtime_error("the model's simulate must return (time, signals): a 1-D array and a dict name -> array");
    const py::tuple pair = result.cast<py::tuple>();
    // The conversions' own checks (python/conversions.hpp), read as the model's fault: the trial
    // fails with the message (falsify raises it as RuntimeError).
    const auto as_vector = [](py::handle obj, const std::string& what) {
      try {
        const DoubleArray a = to_vector(obj, "the model's " + what);
        const auto n = static_cast<std::size_t>(a.shape(0));
        require_finite(a.data(), n, "the model's " + what);
        return std::vector<double>(a.data(), a.data() + n);
      } catch (const py::builtin_exception& e) {
        throw std::runtime_error(e.what());
      }
    };
    time = as_vector(pair[0], "time");
    if (time.empty()) throw std::runtime_error("the model's time is empty");
    if (time.front() < 0.0) throw std::runtime_error(fmt::format("the model's time starts at {} < 0", time.front()));
    for (std::size_t k = 1; k < time.size(); ++k)
      if (time[k] < time[k - 1]) throw std::runtime_error(fmt::format("the model's time decreases at index {}", k));
    if (!py::isinstance<py::dict>(pair[1])) throw std::runtime_error("the model's signals are not a dict name -> array");
    const py::dict signals = pair[1].cast<py::dict>();
    for (std::size_t s = 0; s < signals_.size(); ++s) {
      const py::str key(signals_[s]);
      if (!signals.contains(key)) throw std::runtime_error(fmt::format("the model returned no signal '{}'", signals_[s]));
      outputs[s] = as_vector(signals[key], fmt::format("signal '{}'", signals_[s]));
      if (outputs[s].size() != time.size())
        throw std::runtime_error(fmt::format("the model's signal '{}' has {} values for {} times", signals_[s],
                                             outputs[s].size(), time.size()));
    }
  }

  py::function fn_;
  std::vector<std::string> inputs_, signals_;
};

BlackBox make(py::function simulate, const py::dict& inputs, const std::vector<std::string>& signals, double horizon,
              double step, const std::string& name) {
  BlackBoxSpec spec;
  spec.name = name;
  for (auto [key, range] : inputs) {
    if (!py::isinstance<py::str>(key)) throw py::type_error("inputs: a dict name -> (lo, hi)");
    spec.input_names.push_back(key.cast<std::string>());
    py::sequence pair;
    try {
      pair = range.cast<py::sequence>();
    } catch (const py::cast_error&) {
      throw py::type_error(fmt::format("inputs['{}']: a pair (lo, hi)", spec.input_names.back()));
    }
    if (py::len(pair) != 2) throw py::value_error(fmt::format("inputs['{}']: a pair (lo, hi)", spec.input_names.back()));
    spec.input_box.lo.push_back(pair[0].cast<double>());
    spec.input_box.hi.push_back(pair[1].cast<double>());
  }
  spec.output_names = signals;
  spec.horizon = horizon;
  spec.step = step;
  BlackBox box;
  box.spec = spec;
  // A refusal (step > horizon, ...): ValueError, from make_black_box's std::invalid_argument.
  box.system = make_black_box(spec, std::make_shared<PythonModel>(std::move(simulate), spec.input_names, signals));
  return box;
}

}  // namespace

void bind_black_box(py::module_& m) {
  py::class_<BlackBox>(m, "BlackBox", R"doc(A model of your own, known only by its simulations.

simulate(time, inputs) -> (time, signals): time is a 1-D array (0, then the end of each input piece of `step`
seconds), inputs a dict name -> array (value k held from time[k] to time[k + 1], the last repeating the one before);
it returns the model's own sample times (from >= 0, non-decreasing, reaching time[-1]: a shorter trace is a
RuntimeError, never judged as the whole) and a dict holding each of `signals` at them. It must not call
hyfal.falsify (RuntimeError). inputs: name -> (lo, hi). horizon: the input signal's length, s (unless a requirement's
is given to falsify); step: δt, the input pieces' length, at most the horizon. STL formulas read the signals and the inputs by name.

hyfal.falsify(box, requirement=..., method=...) drives it with the searches over input signals (random, annealing,
cmaes, nelder-mead, adaptive, adaptive-local); a witness is re-checked by calling simulate again. The adaptive
search prunes by the prefix of a trace: sound for a causal model (outputs up to t depend on inputs up to t).)doc")
      .def(py::init(&make), py::kw_only(), py::arg("simulate"), py::arg("inputs"), py::arg("signals"), py::arg("horizon"),
           py::arg("step") = 1.0, py::arg("name") = "model")
      .def_property_readonly("name", [](const BlackBox& b) { return b.spec.name; })
      .def_property_readonly("inputs",
                             [](const BlackBox& b) {
                               py::dict d;
                               for (std::size_t i = 0; i < b.spec.input_names.size(); ++i)
                                 d[py::str(b.spec.input_names[i])] = py::make_tuple(b.spec.input_box.lo[i], b.spec.input_box.hi[i]);
                               return d;
                             })
      .def_property_readonly("signals", [](const BlackBox& b) { return b.spec.output_names; })
      .def_property_readonly("horizon", [](const BlackBox& b) { return b.spec.horizon; })
      .def_property_readonly("step", [](const BlackBox& b) { return b.spec.step; })
      .def("__repr__", [](const BlackBox& b) {
        return fmt::format("<hyfal.BlackBox '{}': {} inputs, {} signals, horizon {:.6g} s, step {:.6g} s>", b.spec.name,
                           b.spec.input_names.size(), b.spec.output_names.size(), b.spec.horizon, b.spec.step);
      });
}

}  // namespace hyfal::python
