// Falsification and results: hyfal.falsify runs trials through the runner of `hyfal run`
// (app/runner.hpp resolve_trial_group and prepare_jobs: the same instance keys, configs and trial
// seeds) on the trial engine (parallel/trial_engine.hpp run_trials); hyfal.read_results reads a
// results database (results/store.hpp) into numpy columns.
#include <stdlib.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "app/runner.hpp"
#include "core/run/option_spec.hpp"
#include "core/witness/trajectory.hpp"
#include "core/witness/witness.hpp"
#include "parallel/trial_engine.hpp"
#include "core/model/black_box.hpp"
#include "core/requirements/requirement.hpp"
#include "core/util/rng.hpp"
#include "python/python_black_box.hpp"
#include "python/bindings.hpp"
#include "python/conversions.hpp"
#include "python/suite.hpp"
#include "results/store.hpp"
#include "suites/registry.hpp"
#include "core/run/method_entry.hpp"
#include "core/model/signal_model.hpp"

namespace hyfal::python {

namespace fs = std::filesystem;

namespace {

// A falsifying trial's witness (the hyfal-witness/1 file `hyfal run` writes), its input signal as
// arrays, and the trace of that signal (simulated on first access).
struct PyWitness {
  Witness witness;
  std::string text;
  Suite suite;
  std::optional<Trace> trace;
};

// The witness's pieces that hold an input for some time (zero-length ones hold none), as
// `hyfal witness --format arch-csv` writes them.
std::vector<stl::InputPiece> witness_pieces(const Witness& w) {
  std::vector<stl::InputPiece> pieces;
  for (const auto& p : w.trajectory.pieces)
    if (p.duration > 0.0) pieces.push_back({p.duration, p.u});
  return pieces;
}

// The input signal's times: 0, then each piece's end (the ARCH-COMP CSV's time column).
std::vector<double> witness_times(const Witness& w) {
  std::vector<double> t{0.0};
  for (const auto& p : witness_pieces(w)) t.push_back(t.back() + p.duration);
  return t;
}

// The input signal as `hyfal simulate` reads that CSV back: value k held from times[k] to
// times[k + 1] (durations of the summed times, which may differ from the pieces' in the last bit).
std::vector<stl::InputPiece> replayed_pieces(const Witness& w) {
  std::vector<stl::InputPiece> pieces = witness_pieces(w);
  const std::vector<double> t = witness_times(w);
  for (std::size_t k = 0; k < pieces.size(); ++k) pieces[k].duration = t[k + 1] - t[k];
  return pieces;
}

py::object witness_trace(PyWitness& w) {
  const Trajectory& t = w.witness.trajectory;
  const SystemInfo& info = w.suite.system->info();
  // simulate() starts from the instance's initial state: a witness from another one (a forest's
  // other roots) has no such trace.
  if (t.initial_mode != info.initial_mode || t.initial_x != info.initial_state) return py::none();
  if (!w.trace) w.trace = simulate_pieces(w.suite, replayed_pieces(w.witness), t.parameters);
  return py::cast(*w.trace);
}

double metric(const TrialRecord& r, const char* name) {
  try {
    const Json m = Json::parse(r.metrics);
    if (m.is_object() && m.contains(name) && m[name].is_number()) return m[name].get<double>();
  } catch (const Json::exception&) {
  }
  return std::numeric_limits<double>::quiet_NaN();
}

// The per-trial table (the database's `trials` columns, plus robustness and simulations from the
// metrics: NaN where absent) as numpy arrays. witnesses: the witness column's values (falsify);
// null: the stored paths.
py::dict columns(const std::vector<TrialRecord>& rows, const py::list* witnesses) {
  const std::size_t n = rows.size();
  const auto strings = [&](auto get) {
    py::list items;
    for (const auto& r : rows) items.append(py::str(get(r)));
    return object_array(items);
  };
  const auto optional_strings = [&](auto get) {
    py::list items;
    for (const auto& r : rows) {
      const std::string& s = get(r);
      items.append(s.empty() ? py::object(py::none()) : py::object(py::str(s)));
    }
    return object_array(items);
  };
  const auto integers = [&](auto get) {
    std::vector<std::int64_t> v;
    for (const auto& r : rows) v.push_back(static_cast<std::int64_t>(get(r)));
    return to_numpy(v);
  };
  const auto reals = [&](auto get) {
    std::vector<double> v;
    for (const auto& r : rows) v.push_back(get(r));
    return to_numpy(v);
  };
  py::dict d;
  d["experiment"] = strings([](const TrialRecord& r) { return r.key.experiment; });
  d["suite"] = strings([](const TrialRecord& r) { return r.key.suite; });
  d["instance"] = strings([](const TrialRecord& r) { return r.key.instance; });
  d["method"] = strings([](const TrialRecord& r) { return r.key.method; });
  d["config"] = strings([](const TrialRecord& r) { return r.key.config; });
  d["trial_index"] = integers([](const TrialRecord& r) { return r.key.trial_index; });
  d["seed"] = integers([](const TrialRecord& r) { return r.seed; });
  d["status"] = strings([](const TrialRecord& r) { return std::string(to_string(r.status)); });
  py::array_t<bool> validated(static_cast<py::ssize_t>(n));
  for (std::size_t i = 0; i < n; ++i) validated.mutable_data()[i] = rows[i].validated;
  d["validated"] = validated;
  d["wall_s"] = reals([](const TrialRecord& r) { return r.wall_s; });
  d["cpu_s"] = reals([](const TrialRecord& r) { return r.cpu_s; });
  d["nodes"] = integers([](const TrialRecord& r) { return r.nodes; });
  d["propagations"] = integers([](const TrialRecord& r) { return r.propagations; });
  d["integration_steps"] = integers([](const TrialRecord& r) { return r.integration_steps; });
  d["robustness"] = reals([](const TrialRecord& r) { return metric(r, "robustness"); });
  d["simulations"] = reals([](const TrialRecord& r) { return metric(r, "simulations"); });
  if (witnesses)
    d["witness"] = object_array(*witnesses);
  else
    d["witness"] = optional_strings([](const TrialRecord& r) -> const std::string& { return r.witness; });
  d["error"] = optional_strings([](const TrialRecord& r) -> const std::string& { return r.error; });
  d["threads"] = integers([](const TrialRecord& r) { return r.threads; });
  d["host"] = strings([](const TrialRecord& r) { return r.host; });
  d["git_commit"] = strings([](const TrialRecord& r) { return r.git_commit; });
  d["started_at"] = strings([](const TrialRecord& r) { return r.started_at; });
  d["finished_at"] = strings([](const TrialRecord& r) { return r.finished_at; });
  d["metrics"] = strings([](const TrialRecord& r) { return r.metrics; });
  return d;
}

std::string method_names() {
  std::vector<std::string> names;
  for (const auto& m : all_methods()) names.push_back(m.name);
  return fmt::format("{}", fmt::join(names, ", "));
}

const MethodEntry& method_named(const std::string& name) {
  const MethodEntry* m = find_method(name);
  if (!m) throw py::key_error(fmt::format("unknown method '{}' (methods: {})", name, method_names()));
  return *m;
}

// A folder for the witnesses of one falsify() call, removed with everything in it at the end.
class TemporaryFolder {
 public:
  TemporaryFolder() {
    std::string pattern = (fs::temp_directory_path() / "hyfal-py-XXXXXX").string();
    if (!::mkdtemp(pattern.data())) throw EnvironmentError(fmt::format("cannot create a temporary folder '{}'", pattern));
    path_ = pattern;
  }
  ~TemporaryFolder() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  TemporaryFolder(const TemporaryFolder&) = delete;
  TemporaryFolder& operator=(const TemporaryFolder&) = delete;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  if (!in) throw EnvironmentError(fmt::format("cannot read the witness '{}'", path));
  return ss.str();
}

// The checks every falsify() makes of its run options; the master seed.
std::uint64_t check_run_options(long long trials, long long threads, py::handle seed_arg, double timeout,
                                long long max_nodes, const std::string& experiment) {
  if (trials < 1 || trials > kMaxTrials)
    throw py::value_error(fmt::format("trials={}: must be in [1, {}]", trials, kMaxTrials));
  if (threads < 0 || threads > kMaxThreads)
    throw py::value_error(fmt::format("threads={}: must be in [0, {}] (0: all cores)", threads, kMaxThreads));
  if (!(timeout > 0.0)) throw py::value_error(fmt::format("timeout={}: must be a positive number of seconds", timeout));
  if (max_nodes < 1) throw py::value_error(fmt::format("max_nodes={}: must be at least 1", max_nodes));
  if (!py::isinstance<py::int_>(seed_arg) || py::isinstance<py::bool_>(seed_arg))
    throw py::type_error("seed: an integer in [0, 2^64)");
  std::uint64_t seed = 0;
  try {
    seed = seed_arg.cast<std::uint64_t>();
  } catch (const py::cast_error&) {
    throw py::value_error("seed: an integer in [0, 2^64)");
  }
  check_experiment_name(experiment);
  return seed;
}

// Runs the jobs on the trial engine with the GIL released, their witnesses read back from a
// temporary folder (the engine writes them as `hyfal run` does) that is removed: nothing is left
// behind. The per-trial columns, trial_index order.
py::dict run_and_collect(const std::vector<TrialJob>& jobs, long long threads, const Suite& suite_of_group) {
  TemporaryFolder folder;
  EngineOptions engine = make_engine_options(static_cast<int>(threads), folder.path(), false);
  auto records = run_released<std::vector<TrialRecord>>([&](std::stop_token stop) {
    EngineOptions eo = engine;
    eo.cancel = stop;
    std::vector<TrialRecord> out;
    std::mutex mutex;
    run_trials(jobs, eo, [&](const TrialRecord& r) {
      std::lock_guard lock(mutex);
      out.push_back(r);
    });
    return out;
  });
  std::sort(records.begin(), records.end(),
            [](const TrialRecord& a, const TrialRecord& b) { return a.key.trial_index < b.key.trial_index; });
  py::list witnesses;
  for (TrialRecord& r : records) {
    if (r.witness.empty()) {
      witnesses.append(py::none());
      continue;
    }
    PyWitness w;
    w.text = read_text(r.witness);
    w.witness = witness_from_text(w.text);
    w.suite = suite_of_group;
    witnesses.append(py::cast(std::move(w)));
    r.witness.clear();  // its file is gone with the folder
  }
  return columns(records, &witnesses);
}

// falsify() of a hyfal.BlackBox: the jobs `hyfal run` would make of a suite instance (the
// instance key, config and trial seeds alike), of the black box with its requirement; a method
// that cannot drive it, and a model that failed, are Python exceptions.
py::dict falsify_black_box(const BlackBox& box, py::handle requirement, const std::string& method_name, py::handle budget,
                           long long trials, long long threads, py::handle seed_arg, double timeout, long long max_nodes,
                           const std::string& experiment, const py::kwargs& options) {
  const MethodEntry& method = method_named(method_name);
  if (!py::isinstance<py::str>(requirement))
    throw py::type_error("requirement: a formula over the black box's signals and inputs (a string)");
  const std::uint64_t seed = check_run_options(trials, threads, seed_arg, timeout, max_nodes, experiment);
  Settings sets;
  if (!budget.is_none()) sets.emplace_back("budget", setting_text(budget));
  for (auto [key, value] : options) sets.emplace_back(key.cast<std::string>(), setting_text(value));
  for (const auto& [key, value] : sets)
    if (!has_option(method.options, key))
      throw py::key_error(fmt::format("method '{}' has no option '{}' (options: {})", method.name, key,
                                      option_names(method.options)));
  if (has_option(method.options, "horizon") &&
      std::none_of(sets.begin(), sets.end(), [](const auto& s) { return s.first == "horizon"; }))
    sets.emplace_back("horizon", fmt::format("{}", box.spec.horizon));  // the box's signal length
  std::shared_ptr<const System> system;
  Json resolved;
  // Refusals are ValueErrors: hyfal's own as their classes (python/module.cpp), a plain
  // std::invalid_argument as ValueError (pybind11's translation).
  system = stl::with_requirement(box.system, requirement.cast<std::string>());
  check_method_for_system(method, *system);
  resolved = resolve_options(method.options, sets);
  if (method.check_system) method.check_system(*system, resolved);
  const std::string instance = system->info().instance.dump();
  const Json config = {{"master_seed", seed}, {"max_nodes", max_nodes}, {"timeout_s", timeout},
                       {"options", canonical_instance(method.options, resolved)}};
  std::vector<TrialJob> jobs;
  for (long long i = 0; i < trials; ++i) {
    TrialJob job;
    job.key = {experiment, system->info().suite, instance, method.name, config.dump(), i};
    job.system = system;
    job.method = &method;
    job.method_options = resolved;
    job.limits = {timeout, max_nodes};
    job.seed = trial_seed(seed, job.key.suite, instance, method.name, i);
    jobs.push_back(std::move(job));
  }
  py::dict result = run_and_collect(jobs, threads, Suite{nullptr, {}, system->info().instance, system});
  const py::array errors = result["error"];
  for (py::ssize_t i = 0; i < errors.size(); ++i) {
    const py::object e = errors.attr("__getitem__")(i);
    if (!e.is_none()) throw std::runtime_error(fmt::format("trial {}: {}", i, e.cast<std::string>()));
  }
  return result;
}

py::dict falsify(py::handle suite_arg, py::handle requirement, const std::string& method_name, py::handle budget,
                 long long trials, long long threads, py::handle seed_arg, double timeout, long long max_nodes,
                 const std::string& experiment, const py::kwargs& options) {
  if (inside_model_simulate())
    throw std::runtime_error("falsify cannot be called from inside a model's simulate (it would wait on the trial "
                             "that is running the model)");
  if (py::isinstance<BlackBox>(suite_arg))
    return falsify_black_box(suite_arg.cast<const BlackBox&>(), requirement, method_name, budget, trials, threads, seed_arg,
                             timeout, max_nodes, experiment, options);
  // The suite: a name, or a hyfal.Suite with the parameters it was made with.
  const SuiteEntry* suite = nullptr;
  Settings settings;
  if (py::isinstance<Suite>(suite_arg)) {
    const Suite& s = suite_arg.cast<const Suite&>();
    suite = s.entry;
    settings = s.settings;
  } else if (py::isinstance<py::str>(suite_arg)) {
    const std::string name = suite_arg.cast<std::string>();
    suite = find_suite(name);
    if (!suite) {
      std::vector<std::string> names;
      for (const auto& s : all_suites()) names.push_back(s.name);
      throw py::key_error(fmt::format("unknown suite '{}' (suites: {})", name, fmt::join(names, ", ")));
    }
  } else {
    throw py::type_error("suite: a suite name or a hyfal.Suite");
  }
  const MethodEntry& method = method_named(method_name);
  Settings extra;
  if (!requirement.is_none()) {
    if (!py::isinstance<py::str>(requirement))
      throw py::type_error("requirement: a declared id or a formula (a string), or None");
    extra.emplace_back("requirement", requirement.cast<std::string>());
  }
  if (!budget.is_none()) {
    if (!has_option(method.options, "budget"))
      throw py::key_error(fmt::format("method '{}' has no option 'budget' (options: {})", method.name,
                                      option_names(method.options)));
    extra.emplace_back("budget", setting_text(budget));
  }
  for (auto [key, value] : options) extra.emplace_back(key.cast<std::string>(), setting_text(value));
  for (const auto& [key, value] : extra)
    if (!has_option(suite->parameters, key) && !has_option(method.options, key))
      throw py::key_error(fmt::format("suite '{}' and method '{}' have no setting '{}' (suite parameters: {}; method "
                                      "options: {})",
                                      suite->name, method.name, key, option_names(suite->parameters),
                                      option_names(method.options)));
  overlay_settings(settings, extra);  // a keyword replaces the Suite's value of the same key
  const std::uint64_t seed = check_run_options(trials, threads, seed_arg, timeout, max_nodes, experiment);

  TrialGroupSpec spec;
  spec.experiment = experiment;
  spec.suite = suite;
  spec.method = &method;
  spec.settings = settings;
  spec.trials = static_cast<int>(trials);
  spec.timeout_s = timeout;
  spec.max_nodes = max_nodes;
  spec.seed = seed;
  const TrialGroup group = resolve_trial_group(spec);
  const std::vector<TrialJob> jobs = prepare_jobs(group, {});
  return run_and_collect(jobs, threads, Suite{suite, settings, group.instance, group.system});
}

}  // namespace

void bind_falsify(py::module_& m) {
  m.def(
      "methods",
      [] {
        std::vector<std::string> names;
        for (const auto& me : all_methods()) names.push_back(me.name);
        return names;
      },
      "The method names (`hyfal list`).");
  m.def(
      "method_options", [](const std::string& name) { return option_specs(method_named(name).options); },
      py::arg("method"), "A method's options: key, default, range (valid values), help.");

  py::class_<PyWitness>(m, "Witness", R"doc(A falsifying trial's witness: its input signal (.time, .inputs: the
values held from each time to the next, the last repeating the one before, as `hyfal witness --format arch-csv`
writes them: Suite.simulate(w.inputs, w.time) replays it), .trace (that simulation: a hyfal.Trace), .robustness
(as the validator re-simulated it), .json (the witness file's text: save it and `hyfal validate` it).)doc")
      .def_property_readonly("time",
                             [](const PyWitness& w) { return to_numpy(witness_times(w.witness)); })
      .def_property_readonly("inputs",
                             [](const PyWitness& w) {
                               const auto pieces = witness_pieces(w.witness);
                               py::dict d;
                               for (std::size_t i = 0; i < w.witness.input_names.size(); ++i) {
                                 std::vector<double> v;
                                 for (const auto& p : pieces) v.push_back(p.u[i]);
                                 v.push_back(pieces.empty() ? 0.0 : pieces.back().u[i]);
                                 d[py::str(w.witness.input_names[i])] = to_numpy(v);
                               }
                               return d;
                             })
      .def_property_readonly("input_names", [](const PyWitness& w) { return w.witness.input_names; })
      .def_property_readonly("trace", [](PyWitness& w) { return witness_trace(w); },
                             "Suite.simulate(w.inputs, w.time): the input signal simulated from the initial state, as "
                             "`hyfal witness --format arch-csv` then `hyfal simulate` do (None for a witness from "
                             "another initial state)")
      .def_property_readonly("robustness",
                             [](const PyWitness& w) -> py::object {
                               if (!w.witness.requirement) return py::none();
                               return py::float_(w.witness.requirement->robustness);
                             })
      .def_property_readonly("requirement",
                             [](const PyWitness& w) -> py::object {
                               if (!w.witness.requirement) return py::none();
                               return py::str(w.witness.requirement->formula);
                             })
      .def_property_readonly("parameters", [](const PyWitness& w) { return to_numpy(w.witness.trajectory.parameters); })
      .def_property_readonly("initial_state", [](const PyWitness& w) { return to_numpy(w.witness.trajectory.initial_x); })
      .def_property_readonly("final_state", [](const PyWitness& w) { return to_numpy(w.witness.trajectory.final_x); })
      .def_property_readonly("state_names", [](const PyWitness& w) { return w.witness.state_names; })
      .def_property_readonly("pieces", [](const PyWitness& w) { return w.witness.trajectory.pieces.size(); },
                             "flow pieces (between transitions) in the witness file")
      .def_property_readonly("method", [](const PyWitness& w) { return w.witness.method; })
      .def_property_readonly("trial_seed", [](const PyWitness& w) { return w.witness.trial_seed; })
      .def_property_readonly("json", [](const PyWitness& w) { return w.text; })
      .def("__repr__", [](const PyWitness& w) {
        return fmt::format("<hyfal.Witness {} {}: {} pieces over {:.6g} s{}>", w.witness.suite, w.witness.method,
                           w.witness.trajectory.pieces.size(),
                           [&] {
                             double t = 0.0;
                             for (const auto& p : w.witness.trajectory.pieces) t += p.duration;
                             return t;
                           }(),
                           w.witness.requirement ? fmt::format(", robustness {:.6g}", w.witness.requirement->robustness)
                                                 : std::string());
      });

  m.def("falsify", &falsify, py::arg("suite"), py::kw_only(), py::arg("requirement") = py::none(),
        py::arg("method") = "rrt", py::arg("budget") = py::none(), py::arg("trials") = 10, py::arg("threads") = 0,
        py::arg("seed") = 1, py::arg("timeout") = 60.0, py::arg("max_nodes") = 1'000'000,
        py::arg("experiment") = "default",
        R"doc(Runs trials 0..trials-1 of a method on a suite instance as `hyfal run` does (the same instance key,
config and trial seeds: the same statuses, node counts and robustness for the same settings), on `threads` threads
(0: all cores), with the GIL released (Ctrl-C stops it). Nothing is written: witnesses are read back from a
temporary folder that is removed.

suite: a name or a hyfal.Suite (its parameters). requirement: a declared id or a formula (the suite's `requirement`
parameter). budget: the method's `budget` option (simulations for the optimisers, simulation-equivalents for the
trees). timeout, max_nodes, seed: `--timeout`, `--max-nodes`, `--seed`. Further keywords: suite parameters or method
options (`--set key=value`).

Returns a dict of numpy arrays, one entry per trial (trial_index order): the results database's columns (status:
falsified, not_found, timeout, node_cap (max_nodes reached), budget (the method's budget spent) or error; nodes,
propagations, wall_s, ...), robustness and simulations (NaN where a trial has none), and witness (a
hyfal.Witness for a falsifying trial, else None). pandas.DataFrame(result) works.)doc");

  m.def(
      "read_results",
      [](const std::string& path, std::optional<std::string> experiment) {
        std::error_code ec;
        if (!fs::exists(path, ec)) {
          PyErr_SetObject(PyExc_FileNotFoundError,
                          py::make_tuple(2, fmt::format("no results database at '{}'", path), path).ptr());
          throw py::error_already_set();
        }
        std::vector<TrialRecord> rows;
        {
          py::gil_scoped_release release;
          TrialStore store = TrialStore::open_read_only(path);
          rows = store.load(experiment);
        }
        return columns(rows, nullptr);
      },
      py::arg("path"), py::kw_only(), py::arg("experiment") = py::none(),
      R"doc(The trials of a results database (`hyfal run --db PATH`), read-only as `hyfal table` reads it: a dict
column -> numpy array (the `trials` table, ordered by suite, instance, method, config, trial_index; robustness and
simulations from the metrics, NaN where absent). pandas.DataFrame(hyfal.read_results(path)) works.)doc");
}

}  // namespace hyfal::python
