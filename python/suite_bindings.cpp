// The suites' models: hyfal.suites(), hyfal.Suite (the registry, suites/registry.hpp), its
// simulate() (stl::InputSimulator and stl::linear_signal_pieces, the path of `hyfal simulate`) and
// its requirements' robustness on a trace (stl::TraceMonitor).
#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "core/run/option_spec.hpp"
#include "core/requirements/requirement.hpp"
#include "core/simulate/input_simulator.hpp"
#include "core/requirements/robustness_gradient.hpp"
#include "core/model/signal_model.hpp"
#include "core/simulate/input_signal.hpp"
#include "core/requirements/trace_monitor.hpp"
#include "python/bindings.hpp"
#include "python/conversions.hpp"
#include "python/suite.hpp"
#include "suites/registry.hpp"

namespace hyfal::python {

namespace {

std::string suite_names() {
  std::vector<std::string> names;
  for (const auto& s : all_suites()) names.push_back(s.name);
  return fmt::format("{}", fmt::join(names, ", "));
}

const char* end_name(PropagationEnd e) {
  switch (e) {
    case PropagationEnd::completed: return "completed";
    case PropagationEnd::jumped: return "jumped";
    case PropagationEnd::invariant: return "invariant";
    case PropagationEnd::unsafe: return "unsafe";
    case PropagationEnd::rejected: return "rejected";
  }
  return "rejected";
}

}  // namespace

py::list option_specs(const std::vector<OptionSpec>& specs) {
  py::list out;
  for (const auto& o : specs) {
    py::dict d;
    d["key"] = o.key;
    d["default"] = json_to_python(o.default_value);
    d["range"] = o.range.empty() ? (o.default_value.is_boolean() ? "true|false" : "any") : o.range;
    d["help"] = o.help;
    out.append(d);
  }
  return out;
}

namespace {

// A view of `data` (n doubles) that keeps `owner` alive, read-only.
py::array view(const double* data, std::size_t n, py::handle owner) {
  py::array a(py::dtype::of<double>(), {static_cast<py::ssize_t>(n)}, {static_cast<py::ssize_t>(sizeof(double))}, data,
              owner);
  set_read_only(a);
  return a;
}

// The requirement argument: an id the suite declares or a formula over its signals; None: the
// instance's own (the `requirement` parameter).
stl::Requirement requirement_of(const Suite& s, py::handle requirement) {
  const SystemInfo& info = s.system->info();
  if (requirement.is_none()) {
    if (!info.requirement)
      throw py::value_error(fmt::format("suite '{}': no requirement given and the instance has none (requirement=...)",
                                        s.entry->name));
    return *info.requirement;
  }
  if (!py::isinstance<py::str>(requirement))
    throw py::type_error("requirement: a declared id or a formula (a string), or None");
  return stl::resolve_requirement(info, requirement.cast<std::string>());
}

// A trace argument as the monitor reads it: a hyfal.Trace (used as is), or a mapping holding
// 'time' (or 't') and the signals the requirement reads, by name.
std::shared_ptr<const stl::SimulatedTrace> trace_of(const Suite& s, const stl::Requirement& r, py::handle trace) {
  if (py::isinstance<Trace>(trace)) {
    const Trace& t = trace.cast<const Trace&>();
    if (t.names != [&] {
          std::vector<std::string> n;
          for (const auto& si : stl::system_signals(s.system->info())) n.push_back(si.name);
          return n;
        }())
      throw py::value_error(fmt::format("the trace's signals ({}) are not suite '{}''s", fmt::join(t.names, ", "),
                                        s.entry->name));
    return t.trace;
  }
  if (!(py::isinstance<py::dict>(trace) || py::hasattr(trace, "keys")))
    throw py::type_error("trace: a hyfal.Trace, or a mapping with 'time' and the signals by name");
  py::object time_key = py::str("time");
  if (!trace.attr("__contains__")(time_key).cast<bool>()) time_key = py::str("t");
  if (!trace.attr("__contains__")(time_key).cast<bool>()) throw py::key_error("trace: no 'time' (or 't') entry");
  const DoubleArray time = to_times(trace[time_key], "trace['time']");
  const std::size_t n = static_cast<std::size_t>(time.shape(0));
  auto out = std::make_shared<stl::SimulatedTrace>();
  out->time.assign(time.data(), time.data() + n);
  const auto signals = stl::system_signals(s.system->info());
  out->signals.resize(signals.size());
  for (int source : r.sources) {
    const std::string& name = signals[static_cast<std::size_t>(source)].name;
    if (!trace.attr("__contains__")(py::str(name)).cast<bool>())
      throw py::key_error(fmt::format("trace: no signal '{}' (the requirement reads it)", name));
    const DoubleArray v = to_vector(trace[py::str(name)], fmt::format("trace['{}']", name));
    if (static_cast<std::size_t>(v.shape(0)) != n)
      throw py::value_error(fmt::format("trace['{}']: {} samples, but time has {}", name, v.shape(0), n));
    require_finite(v.data(), n, fmt::format("trace['{}']", name));
    out->signals[static_cast<std::size_t>(source)].assign(v.data(), v.data() + n);
  }
  return out;
}

// The input signal's pieces from Python arguments, checked as `hyfal simulate` checks its CSV
// (stl::sampled_signal_problem: times from 0, increasing; values inside the input box up to 1e-9,
// then clamped into it); zoh: value k held from times[k] to times[k+1]; linear: control points.
std::vector<stl::InputPiece> input_pieces(const Suite& s, py::handle inputs, py::handle times_arg,
                                          const std::string& interpolation,
                                          std::vector<stl::ControlWeights>* weights = nullptr) {
  const SystemInfo& info = s.system->info();
  if (interpolation != "zoh" && interpolation != "linear")
    throw py::value_error(fmt::format("interpolation '{}': expected 'zoh' or 'linear'", interpolation));
  const DoubleArray times = to_vector(times_arg, "times");
  const std::size_t n = static_cast<std::size_t>(times.shape(0));
  const double* t = times.data();
  require_finite(t, n, "times");
  const std::vector<std::string>& names = info.input_names;
  const std::size_t m = names.size();
  const Box& box = s.system->inputs(info.initial_mode).box;
  std::vector<std::vector<double>> rows(n, std::vector<double>(m));
  std::vector<std::string> column_name(m);  // how the caller named each input's values
  const auto set_column = [&](std::size_t i, const double* v, std::size_t stride, const std::string& what) {
    column_name[i] = what;
    for (std::size_t k = 0; k < n; ++k) {
      const double x = v[k * stride];
      if (!std::isfinite(x)) throw py::value_error(fmt::format("{}: value {} at index {} is not a finite number", what, x, k));
      rows[k][i] = x;
    }
  };
  if (py::isinstance<py::dict>(inputs) || py::hasattr(inputs, "keys")) {
    std::vector<char> given(m, 0);
    for (py::handle key : inputs.attr("keys")()) {
      if (!py::isinstance<py::str>(key)) throw py::type_error("inputs: the names (keys) must be strings");
      const std::string name = key.cast<std::string>();
      const std::size_t i = stl::input_named(info, name);  // a name, or an alias (ARCH-COMP's throttle, brake)
      if (i == m)
        throw py::key_error(fmt::format("inputs: '{}' is not an input of suite '{}' (inputs: {})", name, s.entry->name,
                                        fmt::join(names, ", ")));
      if (given[i]) throw py::key_error(fmt::format("inputs: input '{}' is given twice", names[i]));
      given[i] = 1;
      const DoubleArray v = to_vector(inputs[key], fmt::format("inputs['{}']", name));
      if (static_cast<std::size_t>(v.shape(0)) != n)
        throw py::value_error(fmt::format("inputs['{}']: {} values for {} times", name, v.shape(0), n));
      set_column(i, v.data(), 1, fmt::format("inputs['{}']", name));
    }
    for (std::size_t i = 0; i < m; ++i)
      if (!given[i]) throw py::key_error(fmt::format("inputs: no values for input '{}'", names[i]));
  } else {
    DoubleArray v = to_double_array(inputs, "inputs");
    if (v.ndim() == 1 && m == 1) v = v.reshape({v.shape(0), py::ssize_t{1}});
    if (v.ndim() != 2 || static_cast<std::size_t>(v.shape(0)) != n || static_cast<std::size_t>(v.shape(1)) != m)
      throw py::value_error(fmt::format("inputs: shape {}, expected ({}, {}): one row per time, one column per input ({})",
                                        py::str(v.attr("shape")).cast<std::string>(), n, m, fmt::join(names, ", ")));
    for (std::size_t i = 0; i < m; ++i) set_column(i, v.data() + i, m, fmt::format("inputs[:, {}] ({})", i, names[i]));
  }
  using Kind = stl::SampledSignalProblem::Kind;
  const std::span<const double> sample_times(t, n);
  if (const auto p = stl::sampled_signal_problem(sample_times, rows, box)) {
    switch (p->kind) {
      case Kind::too_few: throw py::value_error("times: at least two are needed (a start and an end time)");
      case Kind::first_time: throw py::value_error(fmt::format("times: the first time must be 0, not {}", p->value));
      case Kind::not_increasing:
        throw py::value_error(fmt::format("times: time {} at index {} does not increase", p->value, p->sample));
      case Kind::outside:
        throw py::value_error(fmt::format("{}: {} at index {} is outside [{}, {}]", column_name[p->input], p->value, p->sample,
                                          box.lo[p->input], box.hi[p->input]));
    }
  }
  // As `hyfal simulate --interpolation linear`: pieces of the integrator's (largest) step.
  return stl::sampled_signal_pieces(sample_times, std::move(rows), box,
                                    interpolation == "linear" ? stl::linear_piece_step(info) : 0.0, weights);
}

py::dict verdict_dict(const stl::TraceVerdict& v) {
  py::dict d;
  d["lower"] = v.bounds.lower;
  d["upper"] = v.bounds.upper;
  d["complete"] = v.complete;
  d["horizon"] = v.horizon;
  d["falsified"] = v.falsified();
  d["satisfied"] = v.satisfied();
  return d;
}

}  // namespace

Suite make_suite(const std::string& name, const Settings& settings) {
  Suite s;
  s.entry = find_suite(name);
  if (!s.entry) throw py::key_error(fmt::format("unknown suite '{}' (suites: {})", name, suite_names()));
  for (const auto& [key, value] : settings)
    if (!has_option(s.entry->parameters, key))
      throw py::key_error(fmt::format("suite '{}' has no parameter '{}' (parameters: {})", name, key,
                                      option_names(s.entry->parameters)));
  s.settings = settings;
  s.instance = canonical_instance(s.entry->parameters, resolve_options(s.entry->parameters, settings));
  s.system = s.entry->make(s.instance);  // a refusal: ValueError (an InputError's own class)
  return s;
}

Trace make_trace(std::shared_ptr<const stl::SimulatedTrace> trace, std::vector<std::string> names) {
  Trace t;
  t.trace = trace;
  t.names = std::move(names);
  // The arrays are views of the C++ trace, which a capsule keeps alive.
  py::capsule owner(new std::shared_ptr<const stl::SimulatedTrace>(trace),
                    [](void* p) { delete static_cast<std::shared_ptr<const stl::SimulatedTrace>*>(p); });
  t.time = view(trace->time.data(), trace->time.size(), owner);
  for (std::size_t k = 0; k < t.names.size() && k < trace->signals.size(); ++k)
    t.signals[py::str(t.names[k])] = view(trace->signals[k].data(), trace->signals[k].size(), owner);
  return t;
}

Trace simulate_pieces(const Suite& s, const std::vector<stl::InputPiece>& pieces, const std::vector<double>& p) {
  const System& system = *s.system;
  auto trace = run_released<std::shared_ptr<stl::SimulatedTrace>>([&](std::stop_token stop) {
    stl::InputSimulator simulator(system);
    simulator.set_interrupt({std::chrono::steady_clock::time_point::max(), stop});
    return std::make_shared<stl::SimulatedTrace>(simulator.run(pieces, p));
  });
  std::vector<std::string> names;
  for (const auto& si : stl::system_signals(system.info())) names.push_back(si.name);
  return make_trace(std::move(trace), std::move(names));
}

void bind_suites(py::module_& m) {
  m.def(
      "suites",
      [] {
        std::vector<std::string> names;
        for (const auto& s : all_suites()) names.push_back(s.name);
        return names;
      },
      "The suite names (`hyfal list`).");

  py::class_<Trace>(m, "Trace", R"doc(A simulated trace: .time and .signals (a dict name -> array, every signal of the
suite: outputs, inputs, safety), read-only numpy arrays; trace['y1'] is trace.signals['y1']. .end says how the
simulation ended ('completed', 'invariant': the system's invariant such as its horizon stopped it, 'rejected'),
.problem why an input signal did not fit.)doc")
      .def_readonly("time", &Trace::time)
      .def_readonly("signals", &Trace::signals)
      .def_property_readonly("names", [](const Trace& t) { return t.names; })
      .def_property_readonly("end", [](const Trace& t) { return std::string(end_name(t.trace->end)); })
      .def_property_readonly("problem", [](const Trace& t) { return t.trace->problem; })
      .def_property_readonly("integration_steps", [](const Trace& t) { return t.trace->integration_steps; })
      .def_property_readonly("transitions", [](const Trace& t) { return t.trace->transitions; })
      .def_property_readonly("piece_ends",
                             [](const Trace& t) {
                               std::vector<std::int64_t> v(t.trace->piece_ends.begin(), t.trace->piece_ends.end());
                               return to_numpy(v);
                             })
      .def("__getitem__", [](const Trace& t, const std::string& name) -> py::object {
        if (name == "time" || name == "t") return t.time;
        if (!t.signals.contains(name))
          throw py::key_error(fmt::format("the trace has no signal '{}' (signals: {})", name, fmt::join(t.names, ", ")));
        return t.signals[py::str(name)];
      })
      .def("__contains__", [](const Trace& t, const std::string& name) {
        return name == "time" || name == "t" || t.signals.contains(name);
      })
      .def("keys", [](const Trace& t) {
        std::vector<std::string> k{"time"};
        k.insert(k.end(), t.names.begin(), t.names.end());
        return k;
      }, "'time', then the signals: dict(trace) and pandas.DataFrame(dict(trace)) work")
      .def("__len__", [](const Trace& t) { return t.trace->time.size(); })
      .def("__repr__", [](const Trace& t) {
        return fmt::format("<hyfal.Trace: {} samples over [0, {:.6g}], signals {}; {}>", t.trace->time.size(),
                           t.trace->time.empty() ? 0.0 : t.trace->time.back(), fmt::join(t.names, ", "),
                           end_name(t.trace->end));
      });

  py::class_<Suite>(m, "Suite", R"doc(Suite(name, **parameters): a suite instance (`hyfal list` shows the parameters;
the same values as `--set key=value`), e.g. hyfal.Suite('at', requirement='AT1').)doc")
      .def(py::init([](const std::string& name, py::kwargs parameters) {
             Settings settings;
             for (auto [key, value] : parameters) settings.emplace_back(key.cast<std::string>(), setting_text(value));
             return make_suite(name, settings);
           }),
           py::arg("name"))
      .def_property_readonly("name", [](const Suite& s) { return s.entry->name; })
      .def_property_readonly("description", [](const Suite& s) { return s.entry->description; })
      .def_property_readonly("parameters", [](const Suite& s) { return json_to_python(s.instance); },
                             "the canonical instance (parameters left at a default that is not keyed are absent)")
      .def_property_readonly("instance", [](const Suite& s) { return s.instance.dump(); },
                             "the canonical instance as JSON text (the results database's `instance`)")
      .def_property_readonly("parameter_specs", [](const Suite& s) { return option_specs(s.entry->parameters); },
                             "every parameter: key, default, range (valid values), help")
      .def_property_readonly("signals",
                             [](const Suite& s) {
                               std::vector<std::string> names;
                               for (const auto& si : stl::system_signals(s.system->info())) names.push_back(si.name);
                               return names;
                             },
                             "the signals a requirement may read: outputs, inputs, then safety")
      .def_property_readonly("signal_units",
                             [](const Suite& s) {
                               py::dict d;
                               for (const auto& si : stl::system_signals(s.system->info())) d[py::str(si.name)] = si.unit;
                               return d;
                             })
      .def_property_readonly("outputs",
                             [](const Suite& s) {
                               std::vector<std::string> names;
                               for (const auto& si : s.system->info().outputs) names.push_back(si.name);
                               return names;
                             })
      .def_property_readonly("inputs", [](const Suite& s) { return s.system->info().input_names; })
      .def_property_readonly("input_ranges",
                             [](const Suite& s) {
                               const SystemInfo& info = s.system->info();
                               const Box& box = s.system->inputs(info.initial_mode).box;
                               py::dict d;
                               for (std::size_t i = 0; i < info.input_names.size(); ++i)
                                 d[py::str(info.input_names[i])] = py::make_tuple(box.lo[i], box.hi[i]);
                               return d;
                             },
                             "name -> (lo, hi): the input box of the initial mode (what simulate() accepts)")
      .def_property_readonly("horizon",
                             [](const Suite& s) -> py::object {
                               if (s.instance.contains("horizon") && s.instance["horizon"].is_number())
                                 return py::float_(s.instance["horizon"].get<double>());
                               return py::none();
                             },
                             "the `horizon` parameter where the suite has one (at, cc, thermostat), else None")
      .def_property_readonly("step", [](const Suite& s) { return s.system->info().step_duration; },
                             "δt: one tree extension (an input piece)")
      .def_property_readonly("integration_step", [](const Suite& s) { return s.system->info().integrator.step; })
      .def_property_readonly("requirements",
                             [](const Suite& s) {
                               py::dict d;
                               for (const auto& r : s.system->info().requirements) d[py::str(r.id)] = r.formula;
                               return d;
                             },
                             "the declared requirements: id -> formula")
      .def_property_readonly("requirement_meanings",
                             [](const Suite& s) {
                               py::dict d;
                               for (const auto& r : s.system->info().requirements) d[py::str(r.id)] = r.meaning;
                               return d;
                             })
      .def_property_readonly("requirement",
                             [](const Suite& s) -> py::object {
                               const auto& r = s.system->info().requirement;
                               if (!r) return py::none();
                               return py::str(r->text);
                             },
                             "the instance's requirement (the `requirement` parameter) as a formula, or None")
      .def(
          "simulate",
          [](const Suite& s, py::handle inputs, py::handle times, const std::string& interpolation) {
            const auto pieces = input_pieces(s, inputs, times, interpolation);
            return simulate_pieces(s, pieces, s.system->info().parameters);
          },
          py::arg("inputs"), py::arg("times"), py::kw_only(), py::arg("interpolation") = "zoh",
          R"doc(Simulates the instance from its initial state under an input signal, as `hyfal simulate` does.
inputs: a mapping input name (or alias) -> values, one per time, or a 2-D array (times x inputs).
times: from 0, increasing. interpolation 'zoh': value k holds from times[k] to times[k+1] (the last value is
unused); 'linear': control points joined by lines. Returns a hyfal.Trace.)doc")
      .def(
          "robustness",
          [](const Suite& s, py::handle requirement, py::handle trace) {
            const stl::Requirement r = requirement_of(s, requirement);
            const auto t = trace_of(s, r, trace);
            if (t->time.empty()) throw py::value_error("trace: no samples");
            stl::TraceMonitor monitor(r);
            return monitor.robustness(*t);
          },
          py::arg("requirement"), py::arg("trace"),
          R"doc(rho(requirement, 0) of a trace as it ends: requirement a declared id ('AT1') or a formula over the
suite's signals (None: the instance's requirement); trace a hyfal.Trace or a mapping with 'time' and signals.)doc")
      .def(
          "robustness_gradient",
          [](const Suite& s, py::handle requirement, py::handle inputs, py::handle times, const std::string& interpolation) {
            const stl::Requirement r = requirement_of(s, requirement);
            std::vector<stl::ControlWeights> weights;
            const auto pieces = input_pieces(s, inputs, times, interpolation, &weights);
            const SystemInfo& info = s.system->info();
            const std::size_t m = info.input_names.size();
            const std::size_t points = static_cast<std::size_t>(py::len(times));
            std::vector<double> g(points * m);
            // A suite searched over its parameters (f16's attitude): their slopes too.
            const bool parameters = info.parameter_box.has_width();
            std::vector<double> gp(parameters ? info.parameters.size() : 0);
            const double rho = run_released<double>([&](std::stop_token stop) {
              stl::RobustnessGradient gradient(*s.system, r);
              gradient.simulator().set_interrupt({std::chrono::steady_clock::time_point::max(), stop});
              return gradient.evaluate(pieces, weights, points, info.parameters, g, gp);
            });
            const auto column = [&](std::size_t j) {
              py::array_t<double> a(static_cast<py::ssize_t>(points));
              auto w = a.mutable_unchecked<1>();
              for (std::size_t k = 0; k < points; ++k) w(static_cast<py::ssize_t>(k)) = g[k * m + j];
              return a;
            };
            py::dict grad;  // keyed as the caller keyed the inputs (a name or an alias), else by name
            if (py::isinstance<py::dict>(inputs) || py::hasattr(inputs, "keys")) {
              for (py::handle key : inputs.attr("keys")())
                grad[key] = column(stl::input_named(info, key.cast<std::string>()));
            } else {
              for (std::size_t j = 0; j < m; ++j) grad[py::str(info.input_names[j])] = column(j);
            }
            for (std::size_t j = 0; j < gp.size(); ++j) grad[py::str(info.parameter_names[j])] = gp[j];
            return py::make_tuple(rho, grad);
          },
          py::arg("requirement"), py::arg("inputs"), py::arg("times"), py::kw_only(), py::arg("interpolation") = "zoh",
          R"doc(rho(requirement, 0) of the simulation of an input signal and its gradient: returns (rho, grad), grad a
dict input -> array of d rho / d(value at each time), keyed as `inputs` is (by input name when it is an array),
and, on a suite searched over its parameters (f16's roll, pitch, yaw), parameter name -> d rho / d(its value)
as a float (at the instance's values), the shape of each input's values (under 'zoh' the last value
is unused: its derivative is 0). inputs, times and interpolation as simulate() takes them; requirement as
robustness() takes it. rho is the exact robustness of the simulation (simulate()'s trace, bit for bit); the
gradient comes from the model's own tangents, through every transition (the saltation of a state event),
and from the monitor's critical sample (a subgradient where a min or max ties). One call costs one
simulation with tangents. ValueError for a system without gradients (a hyfal.BlackBox, a suite integrated
by another method than RK4).)doc")
      .def(
          "judge",
          [](const Suite& s, py::handle requirement, py::handle trace) {
            const stl::Requirement r = requirement_of(s, requirement);
            const auto t = trace_of(s, r, trace);
            if (t->time.empty()) throw py::value_error("trace: no samples");
            stl::TraceMonitor monitor(r);
            return verdict_dict(monitor.judge(*t));
          },
          py::arg("requirement"), py::arg("trace"),
          R"doc(What `hyfal simulate` prints for a requirement: a trace that reaches its horizon gives lower == upper
== the robustness; a shorter one is a prefix with its interval. Returns a dict: lower, upper, complete, horizon,
falsified, satisfied.)doc")
      .def("__repr__", [](const Suite& s) { return fmt::format("<hyfal.Suite {} {}>", s.entry->name, s.instance.dump()); });
}

}  // namespace hyfal::python
