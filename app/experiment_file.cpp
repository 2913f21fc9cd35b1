#include "app/experiment_file.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <optional>
#include <tuple>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <toml++/toml.h>

#include "app/runner.hpp"
#include "app/table_file_reader.hpp"
#include "core/run/option_spec.hpp"
#include "core/run/method_entry.hpp"
#include "suites/registry.hpp"

namespace hyfal {

namespace {

using namespace table_file;

// A settings table of an experiment: each value, or each element of a list of values (a grid
// axis), checked as read_settings checks one.
std::vector<std::pair<std::string, std::vector<std::string>>> read_grid_settings(const TomlReader& r,
                                                                                const toml::node& node,
                                                                                const std::string& path,
                                                                                const SettingScope& scope) {
  std::vector<std::pair<std::string, std::vector<std::string>>> axes;
  for (const auto& [key, value] : TomlReader::in_file_order(r.table(node, path))) {
    const std::string where = TomlReader::join(path, key->str());
    const OptionSpec* spec = scope.find(std::string(key->str()));
    if (!spec) r.fail(key->source(), where, fmt::format("no such setting of {} (see 'hyfal list')", scope.owners()));
    std::vector<std::pair<const toml::node*, std::string>> values;  // each with its place in messages
    if (const auto* list = value->as_array()) {
      if (list->empty()) r.fail(*value, where, "an empty list has no value to run");
      for (std::size_t i = 0; i < list->size(); ++i) values.emplace_back(&(*list)[i], TomlReader::index(where, i));
    } else {
      values.emplace_back(value, where);
    }
    std::vector<std::string> texts;
    for (const auto& [v, at] : values) {
      std::string text = r.setting_text(*v, at);
      check_setting_value(r, *spec, text, *v, at);
      texts.push_back(std::move(text));
    }
    axes.emplace_back(std::string(key->str()), std::move(texts));
  }
  return axes;
}

// A paper value: a number, "N/A" (not reported) or "X" (the paper's timeout).
double read_paper_value(const TomlReader& r, const toml::node& node, const std::string& key) {
  if (const auto* s = node.as_string()) {
    if (s->get() == "N/A") return kNotReported;
    if (s->get() == "X") return kPaperTimeout;
    r.fail(node, key, fmt::format("'{}' is not a number, \"N/A\" (not reported) or \"X\" (timeout)", s->get()));
  }
  if (!node.as_integer() && !node.as_floating_point())
    r.fail(node, key, fmt::format("expected a number, \"N/A\" or \"X\", found {}", type_name(node)));
  return r.number(node, key);
}

std::vector<double> read_paper_values(const TomlReader& r, const toml::node& node, const std::string& key,
                                      std::size_t expected, std::string_view of_what) {
  const toml::array& a = r.array(node, key);
  if (a.size() != expected)
    r.fail(node, key, fmt::format("{} values, expected {} (one per {})", a.size(), expected, of_what));
  std::vector<double> v;
  for (std::size_t i = 0; i < a.size(); ++i) v.push_back(read_paper_value(r, a[i], TomlReader::index(key, i)));
  return v;
}

TableMetric read_metric(const TomlReader& r, const toml::node& node, const std::string& key) {
  const std::string name = r.string(node, key);
  if (name == "nodes") return TableMetric::nodes;
  if (name == "time_s") return TableMetric::time_s;
  if (name == "coverage") return TableMetric::coverage;
  if (name == "falsified_rate") return TableMetric::falsified_rate;
  r.fail(node, key, fmt::format("unknown metric '{}' (nodes, time_s, coverage, falsified_rate)", name));
}

std::vector<SweepValue> read_sweep_values(const TomlReader& r, const toml::node& node, const std::string& path,
                                          const SettingScope& scope) {
  std::vector<SweepValue> values;
  const toml::array& a = r.array(node, path);
  for (std::size_t i = 0; i < a.size(); ++i) {
    const std::string at = TomlReader::index(path, i);
    const toml::table& t = r.table(a[i], at);
    r.check_keys(t, at, {"label", "settings"});
    SweepValue v;
    v.label = r.string(r.require(t, at, "label"), TomlReader::join(at, "label"));
    if (const auto* s = r.find(t, "settings")) v.settings = read_settings(r, *s, TomlReader::join(at, "settings"), scope);
    values.push_back(std::move(v));
  }
  return values;
}

}  // namespace

PaperTable load_paper_table(std::string_view text, const std::string& file_name) {
  const TomlReader r(text, file_name);
  const toml::table& root = r.root();
  if (!r.find(root, "league"))
    r.check_keys(root, "", {"id", "title", "source", "suite", "notes", "series", "columns", "rows", "profile", "sweep"});
  PaperTable t;
  t.id = r.string(r.require(root, "", "id"), "id");
  if (t.id.empty() || t.id.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789-_.") != std::string::npos ||
      t.id.front() == '.')
    r.fail(*r.find(root, "id"), "id", fmt::format("'{}': use lower-case letters, digits, '-', '_' and '.' (it names the output files)", t.id));
  t.title = r.string(r.require(root, "", "title"), "title");
  t.source = r.string(r.require(root, "", "source"), "source");
  if (r.find(root, "league")) {
    if (const auto* n = r.find(root, "notes")) t.notes = r.string(*n, "notes");
    return read_league_table(r, std::move(t));
  }
  const toml::node& suite_node = r.require(root, "", "suite");
  t.suite = r.string(suite_node, "suite");
  const SuiteEntry* suite = find_suite(t.suite);
  if (!suite) r.fail(suite_node, "suite", fmt::format("unknown suite '{}' (see 'hyfal list')", t.suite));
  if (const auto* n = r.find(root, "notes")) t.notes = r.string(*n, "notes");
  if (const auto* n = r.find(root, "series")) t.series = r.strings(*n, "series");
  const toml::node* sweep_node = r.find(root, "sweep");

  // Rows first: their methods decide which settings the other layers may hold.
  const toml::array& rows = r.array(r.require(root, "", "rows"), "rows");
  if (rows.empty()) r.fail(rows, "rows", "a table needs at least one row");
  SettingScope all_methods_scope{suite, {}};
  std::vector<const toml::table*> row_tables;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const std::string at = TomlReader::index("rows", i);
    const toml::table& row = r.table(rows[i], at);
    r.check_keys(row, at, {"label", "method", "settings", "paper"});
    PaperRow pr;
    pr.label = r.string(r.require(row, at, "label"), TomlReader::join(at, "label"));
    const toml::node& method_node = r.require(row, at, "method");
    pr.method = r.string(method_node, TomlReader::join(at, "method"));
    const MethodEntry* method = find_method(pr.method);
    if (!method)
      r.fail(method_node, TomlReader::join(at, "method"), fmt::format("unknown method '{}' (see 'hyfal list')", pr.method));
    if (std::find(all_methods_scope.methods.begin(), all_methods_scope.methods.end(), method) ==
        all_methods_scope.methods.end())
      all_methods_scope.methods.push_back(method);
    if (const auto* s = r.find(row, "settings"))
      pr.settings = read_settings(r, *s, TomlReader::join(at, "settings"), SettingScope{suite, {method}});
    t.rows.push_back(std::move(pr));
    row_tables.push_back(&row);
  }

  if (!sweep_node) {
    const toml::array& columns = r.array(r.require(root, "", "columns"), "columns");
    if (columns.empty()) r.fail(columns, "columns", "a table needs at least one column");
    for (std::size_t i = 0; i < columns.size(); ++i) {
      const std::string at = TomlReader::index("columns", i);
      const toml::table& c = r.table(columns[i], at);
      r.check_keys(c, at, {"name", "metric", "metric_key"});
      PaperColumn col;
      col.name = r.string(r.require(c, at, "name"), TomlReader::join(at, "name"));
      col.metric = read_metric(r, r.require(c, at, "metric"), TomlReader::join(at, "metric"));
      if (const auto* k = r.find(c, "metric_key")) {
        col.metric_key = r.string(*k, TomlReader::join(at, "metric_key"));
        if (col.metric != TableMetric::coverage)
          r.fail(*k, TomlReader::join(at, "metric_key"), "only metric = \"coverage\" reads a per-trial metric");
      }
      if (col.metric == TableMetric::coverage && col.metric_key.empty())
        r.fail(c, TomlReader::join(at, "metric_key"), "metric = \"coverage\" needs the per-trial metric's name");
      t.columns.push_back(std::move(col));
    }
    for (std::size_t i = 0; i < t.rows.size(); ++i) {
      const std::string at = TomlReader::index("rows", i);
      t.rows[i].paper = read_paper_values(r, r.require(*row_tables[i], at, "paper"), TomlReader::join(at, "paper"),
                                          t.columns.size(), "column");
    }
  } else {
    if (const auto* c = r.find(root, "columns")) r.fail(*c, "columns", "a sweep table's columns are sweep.columns");
    for (std::size_t i = 0; i < t.rows.size(); ++i)
      if (const auto* p = r.find(*row_tables[i], "paper"))
        r.fail(*p, TomlReader::join(TomlReader::index("rows", i), "paper"), "a sweep table's numbers are sweep.paper");
    const toml::table& s = r.table(*sweep_node, "sweep");
    r.check_keys(s, "sweep", {"columns", "blocks", "instance_key", "paper", "paper_timeout_s", "median"});
    TableSweep sw;
    sw.columns = read_sweep_values(r, r.require(s, "sweep", "columns"), "sweep.columns", all_methods_scope);
    if (sw.columns.empty()) r.fail(*r.find(s, "columns"), "sweep.columns", "a sweep needs at least one column");
    if (const auto* b = r.find(s, "blocks")) sw.blocks = read_sweep_values(r, *b, "sweep.blocks", all_methods_scope);
    if (const auto* k = r.find(s, "instance_key")) {
      sw.instance_key = r.string(*k, "sweep.instance_key");
      if (!sw.instance_key.empty() && !all_methods_scope.find(sw.instance_key))
        r.fail(*k, "sweep.instance_key",
               fmt::format("no such setting of {} (see 'hyfal list')", all_methods_scope.owners()));
    }
    if (const auto* p = r.find(s, "paper_timeout_s")) {
      sw.paper_timeout_s = r.number(*p, "sweep.paper_timeout_s");
      if (sw.paper_timeout_s < 0.0) r.fail(*p, "sweep.paper_timeout_s", "must not be negative");
    }
    if (const auto* m = r.find(s, "median")) sw.median = r.boolean(*m, "sweep.median");
    if (const auto* p = r.find(s, "paper")) {
      // [block][row][column]: one block when the sweep has no blocks.
      const std::size_t blocks = sw.blocks.empty() ? 1 : sw.blocks.size();
      const toml::array& per_block = r.array(*p, "sweep.paper");
      if (per_block.size() != blocks)
        r.fail(*p, "sweep.paper", fmt::format("{} blocks, expected {} ([block][row][column])", per_block.size(), blocks));
      for (std::size_t b = 0; b < blocks; ++b) {
        const std::string at = TomlReader::index("sweep.paper", b);
        const toml::array& per_row = r.array(per_block[b], at);
        if (per_row.size() != t.rows.size())
          r.fail(per_block[b], at, fmt::format("{} rows, expected {} (one per row)", per_row.size(), t.rows.size()));
        std::vector<std::vector<double>> block;
        for (std::size_t i = 0; i < per_row.size(); ++i)
          block.push_back(read_paper_values(r, per_row[i], TomlReader::index(at, i), sw.columns.size(), "sweep column"));
        sw.paper.push_back(std::move(block));
      }
    }
    t.sweep = std::move(sw);
  }

  const toml::table& profiles = r.table(r.require(root, "", "profile"), "profile");
  r.check_keys(profiles, "profile", {"smoke", "quick", "full", "paper"});
  std::vector<std::string> sweep_columns;  // the sweep's column labels
  if (t.sweep)
    for (const SweepValue& c : t.sweep->columns) sweep_columns.push_back(c.label);
  for (auto [name, profile] : {std::pair{"smoke", &t.smoke}, std::pair{"quick", &t.quick}, std::pair{"paper", &t.paper}}) {
    const std::string at = TomlReader::join("profile", name);
    *profile = read_profile(r, r.table(r.require(profiles, "profile", name), at), at, all_methods_scope,
                            t.sweep.has_value(), sweep_columns, t.rows);
  }
  if (const auto* full = r.find(profiles, "full"))  // optional: between quick and paper
    t.full = read_profile(r, r.table(*full, "profile.full"), "profile.full", all_methods_scope, t.sweep.has_value(),
                          sweep_columns, t.rows);
  return t;
}

namespace {

using GridAxes = std::vector<std::pair<std::string, std::vector<std::string>>>;

// Every combination of the axes' values, in order, the last axis varying fastest.
std::vector<Settings> expand_grid(const GridAxes& axes) {
  std::vector<Settings> points{{}};
  for (const auto& [key, values] : axes) {
    std::vector<Settings> next;
    for (const Settings& p : points)
      for (const std::string& v : values) {
        next.push_back(p);
        next.back().emplace_back(key, v);
      }
    points = std::move(next);
  }
  return points;
}

GroupMeasure read_measure(const TomlReader& r, const toml::node& node, const std::string& key) {
  const std::string name = r.string(node, key);
  for (const GroupMeasure m : {GroupMeasure::falsified_rate, GroupMeasure::time_mean_s, GroupMeasure::time_median_s,
                               GroupMeasure::nodes_mean, GroupMeasure::nodes_median})
    if (to_string(m) == name) return m;
  r.fail(node, key,
         fmt::format("unknown value '{}' (falsified_rate, time_mean_s, time_median_s, nodes_mean, nodes_median)", name));
}

// A bound on the groups, so that a typo in a list cannot ask for an absurd grid.
constexpr std::size_t kMaxGroups = 100'000;

std::size_t grid_size(const GridAxes& axes) {  // saturating at kMaxGroups + 1
  std::size_t n = 1;
  for (const auto& [k, values] : axes) n = std::min(n * values.size(), kMaxGroups + 1);
  return n;
}

[[noreturn]] void fail_too_many(const TomlReader& r, const toml::node& at, const std::string& key) {
  r.fail(at, key, fmt::format("the experiment has more than {} groups", kMaxGroups));
}

// A key given as a list somewhere is a grid axis, and so a dimension of the table.
void note_grid_keys(const toml::node& settings, const GridAxes& axes, std::vector<std::string>& setting_keys) {
  for (const auto& [key, values] : axes)
    if (settings.as_table()->get(key)->is_array() &&
        std::find(setting_keys.begin(), setting_keys.end(), key) == setting_keys.end())
      setting_keys.push_back(key);
}

// name, trials, timeout_s, max_nodes, seed.
void read_run_keys(const TomlReader& r, const toml::table& root, ExperimentFile& e) {
  const toml::node& name_node = r.require(root, "", "name");
  e.name = r.string(name_node, "name");
  try {
    check_experiment_name(e.name);
  } catch (const UsageError& error) {
    r.fail(name_node, "name", error.what());
  }
  e.trials = static_cast<int>(r.integer(r.require(root, "", "trials"), "trials", 1, kMaxTrials));
  const toml::node& timeout = r.require(root, "", "timeout_s");
  e.timeout_s = r.number(timeout, "timeout_s");
  if (!(e.timeout_s > 0.0)) r.fail(timeout, "timeout_s", "must be positive");
  e.max_nodes = r.integer(r.require(root, "", "max_nodes"), "max_nodes", 1, INT64_MAX);
  if (const auto* s = r.find(root, "seed")) e.seed = static_cast<std::uint64_t>(r.integer(*s, "seed", 0, INT64_MAX));
}

struct SuitePoint {
  const SuiteEntry* suite;
  Settings settings;
};

// [[suites]]: each suite's instance grid, expanded; its list-valued keys noted as dimensions.
std::vector<SuitePoint> read_suite_instances(const TomlReader& r, const toml::table& root,
                                             std::vector<std::string>& setting_keys) {
  std::vector<SuitePoint> instances;
  const toml::array& suites = r.array(r.require(root, "", "suites"), "suites");
  if (suites.empty()) r.fail(suites, "suites", "an experiment needs at least one suite");
  for (std::size_t i = 0; i < suites.size(); ++i) {
    const std::string at = TomlReader::index("suites", i);
    const toml::table& t = r.table(suites[i], at);
    r.check_keys(t, at, {"name", "settings"});
    const toml::node& n = r.require(t, at, "name");
    const SuiteEntry* suite = find_suite(r.string(n, TomlReader::join(at, "name")));
    if (!suite) r.fail(n, TomlReader::join(at, "name"), fmt::format("unknown suite '{}' (see 'hyfal list')", r.string(n, at)));
    GridAxes axes;
    if (const auto* s = r.find(t, "settings")) {
      axes = read_grid_settings(r, *s, TomlReader::join(at, "settings"), SettingScope{suite, {}});
      note_grid_keys(*s, axes, setting_keys);
      if (instances.size() + grid_size(axes) > kMaxGroups) fail_too_many(r, *s, TomlReader::join(at, "settings"));
    }
    for (Settings& point : expand_grid(axes)) instances.push_back({suite, std::move(point)});
  }
  return instances;
}

struct MethodPoint {
  const MethodEntry* method;
  std::string label;
  Settings options;
};

// [[methods]]: each method's option grid, expanded; its list-valued keys noted as dimensions.
std::vector<MethodPoint> read_method_variants(const TomlReader& r, const toml::table& root, std::size_t instances,
                                              std::vector<std::string>& setting_keys) {
  std::vector<MethodPoint> variants;
  const toml::array& methods = r.array(r.require(root, "", "methods"), "methods");
  if (methods.empty()) r.fail(methods, "methods", "an experiment needs at least one method");
  for (std::size_t i = 0; i < methods.size(); ++i) {
    const std::string at = TomlReader::index("methods", i);
    const toml::table& t = r.table(methods[i], at);
    r.check_keys(t, at, {"name", "label", "options"});
    const toml::node& n = r.require(t, at, "name");
    const std::string method_name = r.string(n, TomlReader::join(at, "name"));
    const MethodEntry* method = find_method(method_name);
    if (!method) r.fail(n, TomlReader::join(at, "name"), fmt::format("unknown method '{}' (see 'hyfal list')", method_name));
    std::string label = method->name;
    if (const auto* l = r.find(t, "label")) label = r.string(*l, TomlReader::join(at, "label"));
    GridAxes axes;
    if (const auto* o = r.find(t, "options")) {
      // Options only: a suite setting belongs to the suite's entry, where it is one instance for
      // every method.
      static const SuiteEntry kNoParameters{};
      axes = read_grid_settings(r, *o, TomlReader::join(at, "options"), SettingScope{&kNoParameters, {method}});
      note_grid_keys(*o, axes, setting_keys);
      if ((variants.size() + grid_size(axes)) * instances > kMaxGroups) fail_too_many(r, *o, TomlReader::join(at, "options"));
    }
    for (Settings& point : expand_grid(axes)) variants.push_back({method, label, std::move(point)});
  }
  return variants;
}

bool is_placed(const ExperimentFile& e, const std::string& d) {
  for (const auto* list : {&e.blocks, &e.rows, &e.columns})
    if (std::find(list->begin(), list->end(), d) != list->end()) return true;
  return false;
}

// [table] blocks, rows and columns: each a list of the experiment's dimensions, none placed twice.
// Returns whether rows and columns were given.
std::pair<bool, bool> read_placed_dimensions(const TomlReader& r, const toml::table& table,
                                             const std::vector<std::string>& dimensions, ExperimentFile& e) {
  bool rows_given = false, columns_given = false;
  std::vector<std::string> placed;
  for (auto [key, list] : {std::pair{"blocks", &e.blocks}, std::pair{"rows", &e.rows}, std::pair{"columns", &e.columns}}) {
    const toml::node* node = r.find(table, key);
    if (!node) continue;
    const std::string at = TomlReader::join("table", key);
    *list = r.strings(*node, at);
    rows_given = rows_given || std::string_view(key) == "rows";
    columns_given = columns_given || std::string_view(key) == "columns";
    for (std::size_t i = 0; i < list->size(); ++i) {
      const std::string& d = (*list)[i];
      const toml::node& element = (*node->as_array())[i];
      if (std::find(dimensions.begin(), dimensions.end(), d) == dimensions.end()) {
        std::string known;
        for (const auto& k : dimensions) known += (known.empty() ? "" : ", ") + k;
        r.fail(element, TomlReader::index(at, i), fmt::format("'{}' is not a dimension of this experiment ({})", d, known));
      }
      if (std::find(placed.begin(), placed.end(), d) != placed.end())
        r.fail(element, TomlReader::index(at, i), fmt::format("'{}' is placed twice", d));
      placed.push_back(d);
    }
  }
  return {rows_given, columns_given};
}

// [table]: which dimensions form blocks, rows and columns (defaults: methods down, suites
// across), and what a cell shows. Returns the `baseline` key's node, checked once rows exist.
const toml::node* read_layout(const TomlReader& r, const toml::table& root, const std::vector<std::string>& dimensions,
                              ExperimentFile& e) {
  bool rows_given = false, columns_given = false;
  const toml::node* baseline = nullptr;
  if (const auto* t = r.find(root, "table")) {
    const toml::table& table = r.table(*t, "table");
    r.check_keys(table, "table", {"rows", "columns", "blocks", "value", "baseline"});
    std::tie(rows_given, columns_given) = read_placed_dimensions(r, table, dimensions, e);
    if (const auto* v = r.find(table, "value")) e.value = read_measure(r, *v, "table.value");
    if ((baseline = r.find(table, "baseline"))) e.baseline = r.string(*baseline, "table.baseline");
  }
  if (!rows_given && !is_placed(e, "method")) e.rows.push_back("method");
  if (!columns_given && !is_placed(e, "suite")) e.columns.push_back("suite");
  return baseline;
}

// Every method variant on every suite instance.
std::vector<ExperimentGroup> make_groups(const std::vector<SuitePoint>& instances, const std::vector<MethodPoint>& variants) {
  std::vector<ExperimentGroup> groups;
  for (const SuitePoint& instance : instances)
    for (const MethodPoint& variant : variants) {
      ExperimentGroup g;
      g.suite = instance.suite;
      g.method = variant.method;
      g.method_label = variant.label;
      g.settings = instance.settings;
      g.settings.insert(g.settings.end(), variant.options.begin(), variant.options.end());
      groups.push_back(std::move(g));
    }
  return groups;
}

// A dimension's value in a group: a setting the group does not set reads "default".
std::string dimension_value(const ExperimentGroup& g, const std::string& d) {
  if (d == "suite") return g.suite->name;
  if (d == "method") return g.method_label;
  for (const auto& [k, v] : g.settings)
    if (k == d) return k + "=" + v;
  return d + "=default";
}

// Each group's block, row and column labels; a dimension that varies but is not placed would put
// several groups in one cell, so it joins the rows first.
void place_groups(const std::vector<std::string>& dimensions, ExperimentFile& e) {
  for (const std::string& d : dimensions)
    if (!is_placed(e, d))
      for (const ExperimentGroup& g : e.groups)
        if (dimension_value(g, d) != dimension_value(e.groups.front(), d)) {
          e.rows.push_back(d);
          break;
        }
  const auto label = [&](const ExperimentGroup& g, const std::vector<std::string>& dims) {
    std::string s;
    for (const std::string& d : dims) s += (s.empty() ? "" : ", ") + dimension_value(g, d);
    return s;
  };
  for (ExperimentGroup& g : e.groups) g.place = {label(g, e.blocks), label(g, e.rows), label(g, e.columns)};
}

// The baseline row the verdicts compare against: the one the file names, else the first row.
void resolve_baseline(const TomlReader& r, const toml::node* baseline, ExperimentFile& e) {
  std::vector<std::string> rows;
  for (const ExperimentGroup& g : e.groups)
    if (std::find(rows.begin(), rows.end(), g.place.row) == rows.end()) rows.push_back(g.place.row);
  if (!baseline) {
    e.baseline = rows.empty() ? "" : rows.front();
    return;
  }
  if (std::find(rows.begin(), rows.end(), e.baseline) == rows.end()) {
    std::string known;
    for (const auto& row : rows) known += (known.empty() ? "'" : ", '") + row + "'";
    r.fail(*baseline, "table.baseline", fmt::format("'{}' names no row of the table (rows: {})", e.baseline, known));
  }
}

}  // namespace

ExperimentFile load_experiment_file(std::string_view text, const std::string& file_name) {
  const TomlReader r(text, file_name);
  const toml::table& root = r.root();
  r.check_keys(root, "", {"name", "trials", "timeout_s", "max_nodes", "seed", "suites", "methods", "table"});
  ExperimentFile e;
  read_run_keys(r, root, e);
  std::vector<std::string> setting_keys;  // every list-valued setting key of the file: possible dimensions
  const std::vector<SuitePoint> instances = read_suite_instances(r, root, setting_keys);
  const std::vector<MethodPoint> variants = read_method_variants(r, root, instances.size(), setting_keys);
  std::vector<std::string> dimensions = {"suite", "method"};
  dimensions.insert(dimensions.end(), setting_keys.begin(), setting_keys.end());
  const toml::node* baseline = read_layout(r, root, dimensions, e);
  e.groups = make_groups(instances, variants);
  place_groups(dimensions, e);
  resolve_baseline(r, baseline, e);
  return e;
}

const std::vector<PaperTable>& builtin_paper_tables() {
  static const std::vector<PaperTable> tables = [] {
    std::vector<PaperTable> v;
    for (const EmbeddedFile& f : embedded_paper_table_files()) {
      PaperTable t = load_paper_table(f.text, std::string(f.path));
      const std::string_view path = f.path;
      const std::string folder(path.substr(0, path.rfind('/') + 1));  // experiments/paper/ or experiments/ompl/
      const std::string expected = folder + t.id + ".toml";
      if (f.path != expected)
        throw ExperimentFileError(fmt::format("{}: id: '{}' must be the file's name ({})", f.path, t.id, expected));
      v.push_back(std::move(t));
    }
    return v;
  }();
  return tables;
}

const PaperTable* find_builtin_paper_table(std::string_view id) {
  for (const PaperTable& t : builtin_paper_tables())
    if (t.id == id) return &t;
  return nullptr;
}

}  // namespace hyfal
