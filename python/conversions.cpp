// Conversions between Python objects and hyfal's values (python/conversions.hpp). A leaf: it
// calls nothing else in python/.
#include "python/conversions.hpp"

#include <cmath>
#include <string>

#include <fmt/format.h>
#include <fmt/ranges.h>

namespace hyfal::python {

DoubleArray to_double_array(py::handle obj, const std::string& what) {
  if (obj.is_none()) throw py::type_error(fmt::format("{}: expected numbers, got None", what));
  // Strings and bytes would become arrays of characters' codes or fail oddly: refused here.
  if (py::isinstance<py::str>(obj) || py::isinstance<py::bytes>(obj))
    throw py::type_error(fmt::format("{}: expected numbers, got a string", what));
  py::array raw = py::array::ensure(obj);
  if (!raw) {
    PyErr_Clear();
    throw py::value_error(fmt::format("{}: cannot be read as an array of numbers", what));
  }
  // Real numbers only: numpy would drop a complex number's imaginary part, or parse strings.
  const char kind = raw.dtype().kind();
  if (kind != 'b' && kind != 'i' && kind != 'u' && kind != 'f' && kind != 'O')
    throw py::type_error(fmt::format("{}: expected real numbers, got an array of dtype {}", what,
                                     py::str(raw.dtype()).cast<std::string>()));
  DoubleArray a = DoubleArray::ensure(raw);
  if (!a) {
    PyErr_Clear();
    throw py::value_error(fmt::format("{}: cannot be read as an array of numbers", what));
  }
  return a;
}

void require_finite(const double* data, std::size_t n, const std::string& what) {
  for (std::size_t i = 0; i < n; ++i)
    if (!std::isfinite(data[i]))
      throw py::value_error(fmt::format("{}: value {} at index {} is not a finite number", what, data[i], i));
}

DoubleArray to_vector(py::handle obj, const std::string& what, bool allow_scalar) {
  DoubleArray a = to_double_array(obj, what);
  if (a.ndim() == 0 && allow_scalar) a = a.reshape({1});
  if (a.ndim() != 1) throw py::value_error(fmt::format("{}: expected a 1-D array, got {} dimensions", what, a.ndim()));
  return a;
}

DoubleArray to_times(py::handle obj, const std::string& what) {
  DoubleArray t = to_vector(obj, what);
  const std::size_t n = static_cast<std::size_t>(t.shape(0));
  if (n == 0) throw py::value_error(fmt::format("{}: at least one sample is needed", what));
  const double* p = t.data();
  require_finite(p, n, what);
  for (std::size_t i = 1; i < n; ++i)
    if (p[i] < p[i - 1])
      throw py::value_error(
          fmt::format("{}: times must not decrease (index {}: {} after {})", what, i, p[i], p[i - 1]));
  return t;
}

namespace {

bool is_mapping(py::handle obj) { return py::isinstance<py::dict>(obj) || py::hasattr(obj, "keys"); }

}  // namespace

SignalTable::SignalTable(py::handle signals, py::handle names, bool allow_scalars) {
  if (is_mapping(signals)) {
    if (!names.is_none()) throw py::type_error("signals: names=... is for a 2-D array; a mapping names its signals");
    for (py::handle key : signals.attr("keys")()) {
      if (!py::isinstance<py::str>(key)) throw py::type_error("signals: the names (keys) must be strings");
      std::string name = key.cast<std::string>();
      DoubleArray column = to_vector(signals[key], fmt::format("signal '{}'", name), allow_scalars);
      const auto n = static_cast<std::size_t>(column.shape(0));
      if (columns_.empty())
        samples_ = n;
      else if (n != samples_)
        throw py::value_error(
            fmt::format("signal '{}': {} samples, but signal '{}' has {}", name, n, names_[0], samples_));
      names_.push_back(std::move(name));
      columns_.push_back(std::move(column));
    }
    return;
  }
  if (names.is_none())
    throw py::type_error("signals: a mapping name -> 1-D array, or a 2-D array (samples x signals) with names=[...]");
  for (py::handle n : names) {
    if (!py::isinstance<py::str>(n)) throw py::type_error("names: expected strings");
    names_.push_back(n.cast<std::string>());
  }
  matrix_ = to_double_array(signals, "signals");
  if (allow_scalars && matrix_.ndim() == 1) matrix_ = matrix_.reshape({py::ssize_t{1}, matrix_.shape(0)});
  if (matrix_.ndim() != 2)
    throw py::value_error(
        fmt::format("signals: expected a 2-D array (samples x signals), got {} dimensions", matrix_.ndim()));
  if (static_cast<std::size_t>(matrix_.shape(1)) != names_.size())
    throw py::value_error(
        fmt::format("signals: shape ({}, {}) has {} columns but {} names are given (rows are samples, "
                    "columns signals)",
                    matrix_.shape(0), matrix_.shape(1), matrix_.shape(1), names_.size()));
  samples_ = static_cast<std::size_t>(matrix_.shape(0));
  is_matrix_ = true;
}

void SignalTable::copy_signal(std::size_t k, double* out) const {
  if (!is_matrix_) {
    const double* p = columns_[k].data();
    for (std::size_t i = 0; i < samples_; ++i) {
      if (!std::isfinite(p[i]))
        throw py::value_error(
            fmt::format("signal '{}': value {} at index {} is not a finite number", names_[k], p[i], i));
      out[i] = p[i];
    }
    return;
  }
  const std::size_t cols = names_.size();
  const double* p = matrix_.data();
  for (std::size_t i = 0; i < samples_; ++i) {
    const double v = p[i * cols + k];
    if (!std::isfinite(v))
      throw py::value_error(fmt::format("signal '{}': value {} at index {} is not a finite number", names_[k], v, i));
    out[i] = v;
  }
}

std::string option_names(const std::vector<OptionSpec>& specs) {
  std::vector<std::string> keys;
  for (const auto& s : specs) keys.push_back(s.key);
  return fmt::format("{}", fmt::join(keys, ", "));
}

std::string setting_text(py::handle value) {
  if (py::isinstance<py::bool_>(value)) return value.cast<bool>() ? "true" : "false";
  if (py::isinstance<py::str>(value)) return value.cast<std::string>();
  if (py::isinstance<py::int_>(value)) return py::str(value).cast<std::string>();
  if (py::isinstance<py::float_>(value)) return py::repr(value).cast<std::string>();
  if (py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value) || py::isinstance<py::dict>(value))
    return py::module_::import("json").attr("dumps")(value).cast<std::string>();
  // numpy scalars and anything else numbers-like: through Python's own float/int.
  if (py::hasattr(value, "dtype")) return setting_text(value.attr("item")());
  throw py::type_error(fmt::format("a setting's value must be a bool, int, float, str or list, not {}",
                                   py::str(value.get_type().attr("__name__")).cast<std::string>()));
}

void set_read_only(py::array& a) { a.attr("setflags")(py::arg("write") = false); }

py::array_t<double> to_numpy(const std::vector<double>& values) {
  py::array_t<double> a(static_cast<py::ssize_t>(values.size()));
  std::copy(values.begin(), values.end(), a.mutable_data());
  return a;
}

py::array_t<std::int64_t> to_numpy(const std::vector<std::int64_t>& values) {
  py::array_t<std::int64_t> a(static_cast<py::ssize_t>(values.size()));
  std::copy(values.begin(), values.end(), a.mutable_data());
  return a;
}

py::array object_array(const py::list& items) {
  py::array a = py::module_::import("numpy").attr("empty")(py::len(items), py::arg("dtype") = "object");
  for (std::size_t i = 0; i < py::len(items); ++i) a[py::int_(i)] = items[i];
  return a;
}

py::object json_to_python(const Json& j) { return py::module_::import("json").attr("loads")(j.dump()); }

}  // namespace hyfal::python
