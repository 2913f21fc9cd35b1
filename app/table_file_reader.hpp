// The TOML reading that table files and experiment files share (app/experiment_file.cpp,
// app/league_file.cpp): a reader whose every failure is one line naming the file, line, column and
// key (ExperimentFileError), setting layers checked against the suites and methods that receive
// them, and a table's run profiles. Internal to app/.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <toml++/toml.h>

#include "app/experiment_file.hpp"
#include "app/runner.hpp"
#include "core/run/option_spec.hpp"
#include "core/run/method_entry.hpp"

namespace hyfal::table_file {

using ::hyfal::one_line;  // a key or value quoted from the file may hold control characters

inline std::string_view type_name(const toml::node& node) {
  switch (node.type()) {
    case toml::node_type::table: return "a table";
    case toml::node_type::array: return "an array";
    case toml::node_type::string: return "a string";
    case toml::node_type::integer: return "an integer";
    case toml::node_type::floating_point: return "a float";
    case toml::node_type::boolean: return "a boolean";
    case toml::node_type::date: return "a date";
    case toml::node_type::time: return "a time";
    case toml::node_type::date_time: return "a date-time";
    default: return "nothing";
  }
}

// Reads typed values out of one parsed file; every failure is an ExperimentFileError naming the
// file, the line and column of the offending node (or of the table that lacks a key) and the key.
class TomlReader {
 public:
  TomlReader(std::string_view text, std::string file) : file_(std::move(file)) {
    try {
      root_ = toml::parse(text, file_);
    } catch (const toml::parse_error& e) {
      throw ExperimentFileError(one_line(fmt::format("{}: {}", where(e.source()), e.description())));
    }
  }

  const toml::table& root() const { return root_; }

  [[noreturn]] void fail(const toml::source_region& at, const std::string& key, std::string_view what) const {
    throw ExperimentFileError(one_line(fmt::format("{}: {}: {}", where(at), key, what)));
  }
  [[noreturn]] void fail(const toml::node& at, const std::string& key, std::string_view what) const {
    fail(at.source(), key, what);
  }

  // Refuses a key of `table` not in `known` (a misspelt key would otherwise be ignored).
  void check_keys(const toml::table& table, const std::string& path, std::initializer_list<std::string_view> known) const {
    for (auto&& [key, node] : table) {
      if (std::find(known.begin(), known.end(), key.str()) != known.end()) continue;
      std::string list;
      for (const auto k : known) list += (list.empty() ? "" : ", ") + std::string(k);
      fail(key.source(), join(path, key.str()), fmt::format("unknown key (known here: {})", list));
    }
  }

  static std::string join(const std::string& path, std::string_view key) {
    return path.empty() ? std::string(key) : path + "." + std::string(key);
  }
  static std::string index(const std::string& path, std::size_t i) { return fmt::format("{}[{}]", path, i); }

  const toml::node* find(const toml::table& table, std::string_view key) const { return table.get(key); }
  const toml::node& require(const toml::table& table, const std::string& path, std::string_view key) const {
    const toml::node* node = table.get(key);
    if (!node) fail(table.source(), join(path, key), "missing");
    return *node;
  }

  std::string string(const toml::node& node, const std::string& key) const {
    if (const auto* s = node.as_string()) return s->get();
    fail(node, key, fmt::format("expected a string, found {}", type_name(node)));
  }
  std::int64_t integer(const toml::node& node, const std::string& key, std::int64_t lo, std::int64_t hi) const {
    const auto* i = node.as_integer();
    if (!i) fail(node, key, fmt::format("expected an integer, found {}", type_name(node)));
    if (i->get() < lo || i->get() > hi) fail(node, key, fmt::format("{} is not in [{}, {}]", i->get(), lo, hi));
    return i->get();
  }
  // A finite number (an integer is one too).
  double number(const toml::node& node, const std::string& key) const {
    double v;
    if (const auto* f = node.as_floating_point())
      v = f->get();
    else if (const auto* i = node.as_integer())
      v = static_cast<double>(i->get());
    else
      fail(node, key, fmt::format("expected a number, found {}", type_name(node)));
    if (!std::isfinite(v)) fail(node, key, "expected a finite number");
    return v;
  }
  bool boolean(const toml::node& node, const std::string& key) const {
    if (const auto* b = node.as_boolean()) return b->get();
    fail(node, key, fmt::format("expected true or false, found {}", type_name(node)));
  }
  const toml::table& table(const toml::node& node, const std::string& key) const {
    if (const auto* t = node.as_table()) return *t;
    fail(node, key, fmt::format("expected a table, found {}", type_name(node)));
  }
  const toml::array& array(const toml::node& node, const std::string& key) const {
    if (const auto* a = node.as_array()) return *a;
    fail(node, key, fmt::format("expected an array, found {}", type_name(node)));
  }
  std::vector<std::string> strings(const toml::node& node, const std::string& key) const {
    std::vector<std::string> out;
    const toml::array& a = array(node, key);
    for (std::size_t i = 0; i < a.size(); ++i) out.push_back(string(a[i], index(key, i)));
    return out;
  }

  // A setting's value as the text `--set key=value` would give: strings as they are, integers in
  // decimal, floats in their shortest round-trip form, booleans as true / false.
  std::string setting_text(const toml::node& node, const std::string& key) const {
    if (const auto* s = node.as_string()) return s->get();
    if (const auto* i = node.as_integer()) return std::to_string(i->get());
    if (const auto* b = node.as_boolean()) return b->get() ? "true" : "false";
    if (const auto* f = node.as_floating_point()) {
      if (!std::isfinite(f->get())) fail(node, key, "expected a finite number");
      return fmt::format("{}", f->get());
    }
    fail(node, key, fmt::format("expected a string, number or boolean, found {}", type_name(node)));
  }

  // The entries of a table in the order the file gives them (toml++ keeps them sorted by key):
  // settings apply in that order, and a table read back equals the one written.
  static std::vector<std::pair<const toml::key*, const toml::node*>> in_file_order(const toml::table& table) {
    std::vector<std::pair<const toml::key*, const toml::node*>> entries;
    for (auto&& [key, node] : table) entries.emplace_back(&key, &node);
    std::stable_sort(entries.begin(), entries.end(), [](const auto& a, const auto& b) {
      const auto& x = a.first->source().begin;
      const auto& y = b.first->source().begin;
      return x.line != y.line ? x.line < y.line : x.column < y.column;
    });
    return entries;
  }

 private:
  std::string where(const toml::source_region& at) const {
    if (at.begin.line == 0) return file_;
    return fmt::format("{}:{}:{}", file_, at.begin.line, at.begin.column);
  }

  std::string file_;
  toml::table root_;
};

// The settings a layer may hold: parameters of the suite, then options of the methods that receive
// the layer (one row's method, or every row's for profile, block and column settings).
struct SettingScope {
  const SuiteEntry* suite = nullptr;
  std::vector<const MethodEntry*> methods;

  const OptionSpec* find(const std::string& key) const {
    for (const OptionSpec& p : suite->parameters)
      if (p.key == key) return &p;
    for (const MethodEntry* m : methods)
      for (const OptionSpec& o : m->options)
        if (o.key == key) return &o;
    return nullptr;
  }
  std::string owners() const {
    std::string s = suite->name.empty() ? "" : fmt::format("suite '{}'", suite->name);
    for (const MethodEntry* m : methods) s += fmt::format("{}method '{}'", s.empty() ? "" : ", ", m->name);
    return s;
  }
};

// A setting's value of its declared type and in its declared range.
inline void check_setting_value(const TomlReader& r, const OptionSpec& spec, const std::string& text, const toml::node& value,
                         const std::string& where) {
  try {
    (void)parse_setting(spec, text);
  } catch (const OptionError& e) {
    // Its "--set key=text: " prefix names what the message already names.
    std::string_view why = e.what();
    if (const auto colon = why.find(": "); why.rfind("--set ", 0) == 0 && colon != std::string_view::npos)
      why.remove_prefix(colon + 2);
    r.fail(value, where, why);
  }
}

// A settings table: each key declared by the scope, each value of its type and in its range.
inline Settings read_settings(const TomlReader& r, const toml::node& node, const std::string& path, const SettingScope& scope) {
  Settings settings;
  for (const auto& [key, value] : TomlReader::in_file_order(r.table(node, path))) {
    const std::string where = TomlReader::join(path, key->str());
    const OptionSpec* spec = scope.find(std::string(key->str()));
    if (!spec) r.fail(key->source(), where, fmt::format("no such setting of {} (see 'hyfal list')", scope.owners()));
    std::string text = r.setting_text(*value, where);
    check_setting_value(r, *spec, text, *value, where);
    settings.emplace_back(std::string(key->str()), std::move(text));
  }
  return settings;
}

using ::hyfal::kMaxTrials;  // the limit `hyfal run --trials` has

// What every profile has: trials, the per-trial caps (required), and settings for every row
// (optional; not read here, since what may hold them differs between kinds of table).
inline TableProfile read_profile_caps(const TomlReader& r, const toml::table& t, const std::string& path) {
  TableProfile p;
  p.trials = static_cast<int>(r.integer(r.require(t, path, "trials"), TomlReader::join(path, "trials"), 1, kMaxTrials));
  const toml::node& timeout = r.require(t, path, "timeout_s");
  p.timeout_s = r.number(timeout, TomlReader::join(path, "timeout_s"));
  if (!(p.timeout_s > 0.0)) r.fail(timeout, TomlReader::join(path, "timeout_s"), "must be positive");
  p.max_nodes = r.integer(r.require(t, path, "max_nodes"), TomlReader::join(path, "max_nodes"), 1, INT64_MAX);
  return p;
}

// A list of labels, each one of `known` and none twice (a profile's columns or rows to run).
inline std::vector<std::string> read_label_subset(const TomlReader& r, const toml::node& node, const std::string& at,
                                                  const std::vector<std::string>& known, std::string_view what) {
  std::vector<std::string> chosen;
  const toml::array& labels = r.array(node, at);
  if (labels.empty()) r.fail(node, at, "an empty list runs nothing");
  for (std::size_t i = 0; i < labels.size(); ++i) {
    const std::string label = r.string(labels[i], TomlReader::index(at, i));
    if (std::find(known.begin(), known.end(), label) == known.end())
      r.fail(labels[i], TomlReader::index(at, i), fmt::format("no {} is labelled '{}'", what, label));
    if (std::find(chosen.begin(), chosen.end(), label) != chosen.end())
      r.fail(labels[i], TomlReader::index(at, i), fmt::format("'{}' is listed twice", label));
    chosen.push_back(label);
  }
  return chosen;
}

inline TableProfile read_profile(const TomlReader& r, const toml::table& t, const std::string& path, const SettingScope& scope,
                          bool sweep, const std::vector<std::string>& sweep_labels, const std::vector<PaperRow>& rows) {
  r.check_keys(t, path,
               {"trials", "timeout_s", "max_nodes", "settings", "instances", "columns", "row_timeout_s",
                "skip_after_all_stopped"});
  TableProfile p = read_profile_caps(r, t, path);
  if (const auto* s = r.find(t, "settings")) p.settings = read_settings(r, *s, TomlReader::join(path, "settings"), scope);
  if (const auto* n = r.find(t, "row_timeout_s")) {
    const std::string at = TomlReader::join(path, "row_timeout_s");
    const toml::table& caps = r.table(*n, at);
    for (const auto& [key, value] : caps) {
      const std::string label(key.str());
      const std::string key_at = TomlReader::join(at, label);
      if (std::none_of(rows.begin(), rows.end(), [&](const PaperRow& row) { return row.label == label; }))
        r.fail(value, key_at, "no row has this label");
      const double seconds = r.number(value, key_at);
      if (!(seconds > 0.0)) r.fail(value, key_at, "must be positive");
      p.row_timeout_s.emplace_back(label, seconds);
    }
  }
  if (const auto* n = r.find(t, "skip_after_all_stopped"))
    p.skip_after_all_stopped = r.boolean(*n, TomlReader::join(path, "skip_after_all_stopped"));
  for (const char* key : {"instances", "columns", "skip_after_all_stopped"})
    if (const auto* n = r.find(t, key); n && !sweep) r.fail(*n, TomlReader::join(path, key), "only a sweep table has it");
  if (const auto* n = r.find(t, "instances"))
    p.instances = static_cast<int>(r.integer(*n, TomlReader::join(path, "instances"), 1, kMaxTrials));
  if (const auto* n = r.find(t, "columns"); n && n->is_array()) {  // labels of the columns to run
    p.column_labels = read_label_subset(r, *n, TomlReader::join(path, "columns"), sweep_labels, "sweep column");
  } else if (n) {
    p.columns = static_cast<int>(
        r.integer(*n, TomlReader::join(path, "columns"), -1, static_cast<std::int64_t>(sweep_labels.size())));
    if (p.columns == 0) r.fail(*n, TomlReader::join(path, "columns"), "0 columns run nothing (-1 = all)");
  }
  return p;
}


// The rest of a league table file (a root with `league`; app/league_file.cpp): `header` holds
// what every table file has (id, title, source, notes), read already.
PaperTable read_league_table(const TomlReader& r, PaperTable header);

}  // namespace hyfal::table_file
