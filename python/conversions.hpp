// Conversions the binding files of the Python module `hyfal` share: arrays and settings with
// Python-side errors, results as numpy arrays, and running C++ work with the GIL released. A leaf
// of python/: it includes nothing else from python/ (python/conversions.cpp).
#pragma once
#include <chrono>
#include <cstddef>
#include <functional>
#include <future>
#include <stop_token>
#include <string>
#include <thread>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "core/model/system.hpp"
#include "core/run/option_spec.hpp"

namespace hyfal::python {

namespace py = pybind11;

// A float64 C-contiguous array (numpy converts lists, ints, other dtypes; no copy for a float64
// contiguous array).
using DoubleArray = py::array_t<double, py::array::c_style | py::array::forcecast>;

// `obj` as a float64 array; ValueError naming `what` when numpy cannot convert it.
DoubleArray to_double_array(py::handle obj, const std::string& what);

// `obj` as a 1-D float64 array of finite numbers (a 0-d array or a Python number is refused
// unless allow_scalar: it is then an array of one). ValueError naming `what` otherwise.
DoubleArray to_vector(py::handle obj, const std::string& what, bool allow_scalar = false);

// ValueError naming `what` and the first index holding NaN or an infinity.
void require_finite(const double* data, std::size_t n, const std::string& what);

// Sample times: 1-D, finite, non-decreasing, at least one. ValueError otherwise.
DoubleArray to_times(py::handle obj, const std::string& what);

// Signals given as a mapping name -> 1-D array (a dict, a pandas DataFrame: anything with keys()
// and []) or as a 2-D array of shape (samples, signals) with `names`. Values are read lazily
// (copy_signal), so only the signals a formula reads are converted and checked.
class SignalTable {
 public:
  // allow_scalars: a mapping's values may be numbers (one sample each).
  SignalTable(py::handle signals, py::handle names, bool allow_scalars = false);
  const std::vector<std::string>& names() const { return names_; }
  std::size_t samples() const { return samples_; }
  // Signal k's values into out[0, samples()): ValueError on a NaN or an infinity.
  void copy_signal(std::size_t k, double* out) const;

 private:
  std::vector<std::string> names_;
  std::vector<DoubleArray> columns_;  // mapping form
  DoubleArray matrix_;                // 2-D form
  bool is_matrix_ = false;
  std::size_t samples_ = 0;
};

// Python's `key=value` as the text `hyfal run --set key=value` would give (bool: true/false,
// int, float: repr, str as is, lists/tuples/dicts as JSON).
std::string setting_text(py::handle value);

// The keys of declared settings, "a, b, c": what an error about an unknown one lists.
std::string option_names(const std::vector<OptionSpec>& specs);

// A copy of `values` as a read-only 1-D numpy array.
py::array_t<double> to_numpy(const std::vector<double>& values);
py::array_t<std::int64_t> to_numpy(const std::vector<std::int64_t>& values);
// A 1-D numpy array of Python objects (strings, None, ...).
py::array object_array(const py::list& items);

// Marks an array read-only.
void set_read_only(py::array& a);

// JSON text as Python objects (json.loads).
py::object json_to_python(const Json& j);

// Runs work(stop) on a separate thread with the GIL released, checking every 50 ms for a signal
// (Ctrl-C): then stop is requested, the work is waited for, and KeyboardInterrupt raised. The
// work's exception, if any, is rethrown here.
template <class R>
R run_released(const std::function<R(std::stop_token)>& work) {
  std::stop_source stop;
  std::packaged_task<R()> task([&] { return work(stop.get_token()); });
  std::future<R> result = task.get_future();
  bool interrupted = false;
  {
    py::gil_scoped_release release;
    std::thread worker(std::move(task));
    while (result.wait_for(std::chrono::milliseconds(50)) != std::future_status::ready) {
      py::gil_scoped_acquire acquire;
      if (PyErr_CheckSignals() != 0) {
        interrupted = true;
        stop.request_stop();
        break;
      }
    }
    worker.join();
  }
  if (interrupted) throw py::error_already_set();
  return result.get();
}

}  // namespace hyfal::python
