// STL on numpy arrays: hyfal.robustness, hyfal.robustness_interval (stl::OfflineMonitor,
// core/requirements/robustness.hpp) and hyfal.Monitor (stl::PrefixMonitor, prefix_monitor.hpp).
#include <algorithm>
#include <limits>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "core/requirements/formula.hpp"
#include "core/requirements/prefix_monitor.hpp"
#include "core/requirements/robustness.hpp"
#include "python/bindings.hpp"
#include "python/conversions.hpp"

namespace hyfal::python {

namespace {

// A parsed formula and its monitor (with its buffers) for one list of signal names. The formula
// is parsed over the signals it reads only (`used`: their positions in the names given), so a
// trace with many signals copies only those.
struct CompiledFormula {
  std::vector<std::size_t> used;
  stl::OfflineMonitor monitor;
  std::vector<double> values;  // the trace's used signals, signal-major (TraceView::values)
};

std::unique_ptr<CompiledFormula> compile(const std::string& text, const std::vector<std::string>& names) {
  // Parsed over every name first, so that an unknown signal is reported with the names given.
  stl::Formula all = stl::parse_requirement(text, names);
  std::vector<char> read(names.size(), 0);
  for (const auto& e : all.expressions)
    if (e.kind == stl::ExpressionNode::Kind::signal) read[static_cast<std::size_t>(e.signal)] = 1;
  std::vector<std::size_t> used;
  std::vector<std::string> used_names;
  for (std::size_t k = 0; k < names.size(); ++k)
    if (read[k]) {
      used.push_back(k);
      used_names.push_back(names[k]);
    }
  stl::Formula f = used.size() == names.size() ? std::move(all) : stl::parse_requirement(text, used_names);
  return std::make_unique<CompiledFormula>(CompiledFormula{std::move(used), stl::OfflineMonitor(std::move(f)), {}});
}

// Compiled formulas by (text, names), so that monitoring many traces parses once and reuses the
// monitor's buffers. Used under the GIL; an entry is taken out while a call uses it.
class FormulaCache {
 public:
  std::unique_ptr<CompiledFormula> take(const std::string& text, const std::vector<std::string>& names, std::string& key) {
    key = text;
    for (const auto& n : names) {
      key += '\x1f';
      key += n;
    }
    auto it = cache_.find(key);
    if (it == cache_.end()) return compile(text, names);
    std::unique_ptr<CompiledFormula> c = std::move(it->second);
    cache_.erase(it);
    return c;
  }
  void give_back(std::string key, std::unique_ptr<CompiledFormula> c) {
    if (cache_.size() >= 256) cache_.clear();
    cache_.emplace(std::move(key), std::move(c));
  }

 private:
  std::unordered_map<std::string, std::unique_ptr<CompiledFormula>> cache_;
};

FormulaCache& formula_cache() {
  static FormulaCache* cache = new FormulaCache();  // never destroyed: no order problem at exit
  return *cache;
}

// Traces at least this long are monitored with the GIL released.
constexpr std::size_t kReleaseGilSamples = 20000;

enum class Query { robustness, every_sample, interval, closed_interval };

// Parses and checks the arguments, monitors the trace as `query` asks, and returns the result
// (a float, a (float, array) pair, or a (lower, upper) pair).
py::object monitor_trace(const std::string& formula, py::handle t, py::handle signals, py::handle names, Query query) {
  const DoubleArray time = to_times(t, "t");
  const SignalTable table(signals, names);
  const std::size_t n = static_cast<std::size_t>(time.shape(0));
  if (!table.names().empty() && table.samples() != n)
    throw py::value_error(fmt::format("signals: {} samples, but t has {}", table.samples(), n));
  std::string key;
  std::unique_ptr<CompiledFormula> c = formula_cache().take(formula, table.names(), key);
  c->values.resize(c->used.size() * n);
  for (std::size_t k = 0; k < c->used.size(); ++k) table.copy_signal(c->used[k], c->values.data() + k * n);
  const stl::TraceView view{std::span<const double>(time.data(), n), c->values};
  double rho = 0.0;
  stl::Interval interval{};
  const auto evaluate = [&] {
    switch (query) {
      case Query::robustness: rho = c->monitor.robustness(view); break;
      case Query::every_sample: rho = c->monitor.robustness_at_every_sample(view); break;
      case Query::interval: interval = c->monitor.robustness_interval(view, false); break;
      case Query::closed_interval: interval = c->monitor.robustness_interval(view, false, true); break;
    }
  };
  if (n >= kReleaseGilSamples) {
    py::gil_scoped_release release;
    evaluate();
  } else {
    evaluate();
  }
  py::object result;
  if (query == Query::robustness) {
    result = py::float_(rho);
  } else if (query == Query::every_sample) {
    const auto row = c->monitor.node_signal(c->monitor.formula().root());
    py::array_t<double> every(static_cast<py::ssize_t>(row.size()));
    std::copy(row.begin(), row.end(), every.mutable_data());
    result = py::make_tuple(rho, every);
  } else {
    result = py::make_tuple(interval.lower, interval.upper);
  }
  formula_cache().give_back(std::move(key), std::move(c));
  return result;
}

// hyfal.Monitor: the robustness interval of a growing trace, sample by sample or in blocks.
class Monitor {
 public:
  Monitor(const std::string& formula, const std::vector<std::string>& signals)
      : names_(signals), monitor_(stl::parse_requirement(formula, signals)) {
    monitor_.initial_state(state_);
    bounds_ = stl::PrefixMonitor::bounds(state_);
  }

  py::tuple update(py::handle t, py::handle values, bool final_trace) {
    if (ended_) throw py::value_error("Monitor.update: the trace was ended (final=True); call reset() to start again");
    DoubleArray time = to_vector(t, "t", true);
    const auto k = static_cast<std::size_t>(time.shape(0));
    if (k == 0 && final_trace && bounds_.samples == 0)
      throw py::value_error("Monitor.update: a trace needs at least one sample");
    require_finite(time.data(), k, "t");
    const std::size_t width = 1 + names_.size();
    rows_.resize(k * width);
    if (py::isinstance<py::dict>(values) || py::hasattr(values, "keys")) {
      const SignalTable table(values, py::none(), true);
      std::vector<std::size_t> column(names_.size());
      for (std::size_t s = 0; s < names_.size(); ++s) {
        const auto it = std::find(table.names().begin(), table.names().end(), names_[s]);
        if (it == table.names().end()) throw py::key_error(fmt::format("Monitor.update: no value for signal '{}'", names_[s]));
        column[s] = static_cast<std::size_t>(it - table.names().begin());
      }
      for (const auto& name : table.names())
        if (std::find(names_.begin(), names_.end(), name) == names_.end())
          throw py::key_error(fmt::format("Monitor.update: '{}' is not one of the monitor's signals ({})", name,
                                          fmt::join(names_, ", ")));
      if (table.samples() != k)
        throw py::value_error(fmt::format("Monitor.update: {} values per signal for {} times", table.samples(), k));
      std::vector<double> buffer(k);
      for (std::size_t s = 0; s < names_.size(); ++s) {
        table.copy_signal(column[s], buffer.data());
        for (std::size_t i = 0; i < k; ++i) rows_[i * width + 1 + s] = buffer[i];
      }
    } else {
      // A sequence of one value per signal (one time), or a 2-D array (times x signals).
      DoubleArray v = to_double_array(values, "values");
      if (v.ndim() == 1 && k == 1) v = v.reshape({py::ssize_t{1}, v.shape(0)});
      if (v.ndim() != 2 || static_cast<std::size_t>(v.shape(0)) != k ||
          static_cast<std::size_t>(v.shape(1)) != names_.size())
        throw py::value_error(fmt::format("Monitor.update: values of shape {} for {} times and {} signals (expected ({}, {}), "
                                          "or ({},) for one time)",
                                          py::str(v.attr("shape")).cast<std::string>(), k, names_.size(), k,
                                          names_.size(), names_.size()));
      require_finite(v.data(), k * names_.size(), "values");
      for (std::size_t i = 0; i < k; ++i)
        for (std::size_t s = 0; s < names_.size(); ++s) rows_[i * width + 1 + s] = v.data()[i * names_.size() + s];
    }
    for (std::size_t i = 0; i < k; ++i) rows_[i * width] = time.data()[i];
    bounds_ = monitor_.extend(state_, rows_, final_trace, next_);
    std::swap(state_, next_);
    ended_ = final_trace;
    return py::make_tuple(bounds_.lower, bounds_.upper);
  }

  void reset() {
    monitor_.initial_state(state_);
    bounds_ = stl::PrefixMonitor::bounds(state_);
    ended_ = false;
  }

  const std::vector<std::string>& signals() const { return names_; }
  std::string formula() const { return monitor_.formula().text; }
  double lower() const { return bounds_.lower; }
  double upper() const { return bounds_.upper; }
  bool complete() const { return bounds_.complete; }
  bool ended() const { return ended_; }
  std::int64_t samples() const { return bounds_.samples; }
  double time() const { return bounds_.time; }
  std::size_t state_size() const { return state_.size(); }

 private:
  std::vector<std::string> names_;
  stl::PrefixMonitor monitor_;
  std::vector<double> state_, next_, rows_;
  stl::PrefixBounds bounds_;
  bool ended_ = false;
};

}  // namespace

void bind_stl(py::module_& m) {
  m.def(
      "robustness",
      [](const std::string& formula, py::handle t, py::handle signals, py::handle names, bool per_sample) {
        return monitor_trace(formula, t, signals, names, per_sample ? Query::every_sample : Query::robustness);
      },
      py::arg("formula"), py::arg("t"), py::arg("signals"), py::kw_only(), py::arg("names") = py::none(),
      py::arg("per_sample") = false,
      R"doc(Robustness rho(formula, 0) of a sampled trace (the semantics of `hyfal simulate` and the searches:
core/requirements/robustness.hpp; signals hold their value between samples; two samples may share a time).

formula: ARCH-COMP notation, e.g. "always[0,30] (y2 < 3000) -> always[0,4] (y1 < 35)".
t: 1-D sample times, finite and non-decreasing.
signals: a mapping name -> 1-D array (dict, pandas DataFrame), or a 2-D array (samples x signals) with names=[...].
per_sample: also return rho(formula, i) at every sample i, as (rho, array).
Raises hyfal.RequirementError (a ValueError naming the column) for a formula it cannot parse, ValueError for
bad shapes, NaN or infinite values (in the signals the formula reads) and decreasing times.)doc");
  m.def(
      "robustness_interval",
      [](const std::string& formula, py::handle t, py::handle signals, py::handle names, bool closed) {
        return monitor_trace(formula, t, signals, names, closed ? Query::closed_interval : Query::interval);
      },
      py::arg("formula"), py::arg("t"), py::arg("signals"), py::kw_only(), py::arg("names") = py::none(),
      py::arg("closed_at_last_time") = false,
      R"doc((lower, upper): the robustness of every extension of the trace, taken as a prefix, lies in it
(OfflineMonitor::robustness_interval). closed_at_last_time: extensions add no sample at the last time.
Arguments as hyfal.robustness.)doc");

  py::class_<Monitor>(m, "Monitor", R"doc(Online (prefix) robustness of a growing trace: stl::PrefixMonitor, the
monitor of the tree searches. Monitor(formula, signals=[names]); update(t, values) adds one sample (t a number,
values one number per signal or a dict) or several (t a 1-D array, values a (len(t), len(signals)) array or a dict of
arrays) and returns (lower, upper): every extension's robustness lies in it. update(..., final=True) ends the trace:
then lower == upper == hyfal.robustness of the whole trace.)doc")
      .def(py::init<const std::string&, const std::vector<std::string>&>(), py::arg("formula"), py::arg("signals"))
      .def("update", &Monitor::update, py::arg("t"), py::arg("values"), py::kw_only(), py::arg("final") = false)
      .def("reset", &Monitor::reset, "Forget every sample (the empty trace).")
      .def_property_readonly("signals", &Monitor::signals)
      .def_property_readonly("formula", &Monitor::formula)
      .def_property_readonly("lower", &Monitor::lower)
      .def_property_readonly("upper", &Monitor::upper)
      .def_property_readonly("interval", [](const Monitor& mo) { return py::make_tuple(mo.lower(), mo.upper()); })
      .def_property_readonly("complete", &Monitor::complete,
                             "lower == upper: no extension can change the robustness (horizon passed, or final)")
      .def_property_readonly("ended", &Monitor::ended)
      .def_property_readonly("samples", &Monitor::samples)
      .def_property_readonly("time", &Monitor::time, "the last sample's time (0 before any)")
      .def_property_readonly("state_size", &Monitor::state_size, "doubles held: a header plus the pending samples")
      .def("__repr__", [](const Monitor& mo) {
        return fmt::format("<hyfal.Monitor '{}': {} samples, [{:.6g}, {:.6g}]{}>", mo.formula(), mo.samples(), mo.lower(),
                           mo.upper(), mo.complete() ? ", complete" : "");
      });
}

}  // namespace hyfal::python
