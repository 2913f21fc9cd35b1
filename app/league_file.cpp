// A league table file (core/run/paper_table.hpp TableLeague): rows = requirements, each with its own
// suite and settings; columns = methods with options; the published tools' numbers; profiles
// smoke and quick (required), full and published (optional). Every setting is checked against
// the suite and method of every cell it reaches, so a file that reads is one every cell of which
// resolves.
#include <algorithm>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "app/table_file_reader.hpp"
#include "suites/registry.hpp"
#include "core/run/method_entry.hpp"

namespace hyfal::table_file {

namespace {

// Rows or columns, each a table { label, <what> = name, settings }, labels unique.
template <class Entry, class Find>
std::vector<Entry> read_entries(const TomlReader& r, const toml::table& league, const std::string& key,
                                const char* name_key, Find find) {
  const std::string path = TomlReader::join("league", key);
  const toml::array& a = r.array(r.require(league, "league", key), path);
  if (a.empty()) r.fail(a, path, "a league needs at least one");
  std::vector<Entry> entries;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const std::string at = TomlReader::index(path, i);
    const toml::table& t = r.table(a[i], at);
    r.check_keys(t, at, {"label", name_key, "settings"});
    Entry e;
    e.label = r.string(r.require(t, at, "label"), TomlReader::join(at, "label"));
    if (e.label.empty()) r.fail(t, TomlReader::join(at, "label"), "must not be empty");
    for (const Entry& before : entries)
      if (before.label == e.label) r.fail(t, TomlReader::join(at, "label"), fmt::format("'{}' is used twice", e.label));
    const toml::node& name_node = r.require(t, at, name_key);
    const std::string name = r.string(name_node, TomlReader::join(at, name_key));
    find(e, name, name_node, TomlReader::join(at, name_key));
    entries.push_back(std::move(e));
  }
  return entries;
}

// A settings table that every (row, column) cell must accept: each key a parameter of the
// cell's suite or an option of its method, each value of its type and range.
Settings read_cell_settings(const TomlReader& r, const toml::node& node, const std::string& path,
                            const std::vector<const LeagueRow*>& rows, const std::vector<const LeagueColumn*>& columns) {
  Settings settings;
  for (const LeagueRow* row : rows)
    for (const LeagueColumn* column : columns)
      settings = read_settings(r, node, path, SettingScope{find_suite(row->suite), {find_method(column->method)}});
  return settings;
}

template <class T>
std::vector<const T*> all_of(const std::vector<T>& v) {
  std::vector<const T*> out;
  for (const T& x : v) out.push_back(&x);
  return out;
}

PublishedTool read_published(const TomlReader& r, const toml::table& t, const std::string& at, const TableLeague& l) {
  r.check_keys(t, at, {"label", "source", "settings", "cells"});
  PublishedTool tool;
  tool.label = r.string(r.require(t, at, "label"), TomlReader::join(at, "label"));
  tool.source = r.string(r.require(t, at, "source"), TomlReader::join(at, "source"));
  tool.settings = r.string(r.require(t, at, "settings"), TomlReader::join(at, "settings"));
  const std::string cells_at = TomlReader::join(at, "cells");
  const toml::array& cells = r.array(r.require(t, at, "cells"), cells_at);
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const std::string c_at = TomlReader::index(cells_at, i);
    const toml::table& c = r.table(cells[i], c_at);
    r.check_keys(c, c_at, {"row", "falsified", "runs", "mean_simulations", "median_simulations", "mean_s"});
    PublishedCell cell;
    const toml::node& row_node = r.require(c, c_at, "row");
    cell.row = r.string(row_node, TomlReader::join(c_at, "row"));
    if (std::none_of(l.rows.begin(), l.rows.end(), [&](const LeagueRow& row) { return row.label == cell.row; }))
      r.fail(row_node, TomlReader::join(c_at, "row"), fmt::format("no league row is labelled '{}'", cell.row));
    for (const PublishedCell& before : tool.cells)
      if (before.row == cell.row) r.fail(row_node, TomlReader::join(c_at, "row"), fmt::format("'{}' twice", cell.row));
    cell.runs = static_cast<int>(r.integer(r.require(c, c_at, "runs"), TomlReader::join(c_at, "runs"), 1, kMaxTrials));
    cell.falsified =
        static_cast<int>(r.integer(r.require(c, c_at, "falsified"), TomlReader::join(c_at, "falsified"), 0, cell.runs));
    for (auto [key, into] : {std::pair{"mean_simulations", &cell.mean_simulations},
                             std::pair{"median_simulations", &cell.median_simulations}, std::pair{"mean_s", &cell.mean_s}})
      if (const auto* n = r.find(c, key)) {
        *into = r.number(*n, TomlReader::join(c_at, key));
        if (*into < 0.0) r.fail(*n, TomlReader::join(c_at, key), "must not be negative");
      }
    tool.cells.push_back(std::move(cell));
  }
  return tool;
}

TableProfile read_league_profile(const TomlReader& r, const toml::table& t, const std::string& path, const TableLeague& l) {
  r.check_keys(t, path, {"trials", "timeout_s", "max_nodes", "settings", "rows", "column_settings"});
  TableProfile p = read_profile_caps(r, t, path);
  std::vector<const LeagueRow*> rows = all_of(l.rows);
  if (const auto* n = r.find(t, "rows")) {
    std::vector<std::string> labels;
    for (const LeagueRow& row : l.rows) labels.push_back(row.label);
    p.row_labels = read_label_subset(r, *n, TomlReader::join(path, "rows"), labels, "league row");
    rows.clear();
    for (const LeagueRow& row : l.rows)
      if (std::find(p.row_labels.begin(), p.row_labels.end(), row.label) != p.row_labels.end()) rows.push_back(&row);
  }
  if (const auto* s = r.find(t, "settings"))
    p.settings = read_cell_settings(r, *s, TomlReader::join(path, "settings"), rows, all_of(l.columns));
  if (const auto* n = r.find(t, "column_settings")) {
    const std::string at = TomlReader::join(path, "column_settings");
    for (const auto& [key, value] : r.table(*n, at)) {
      const std::string label(key.str());
      const auto column = std::find_if(l.columns.begin(), l.columns.end(), [&](const LeagueColumn& c) { return c.label == label; });
      if (column == l.columns.end()) r.fail(value, TomlReader::join(at, label), "not a column label of league.columns");
      p.column_settings.emplace_back(label, read_cell_settings(r, value, TomlReader::join(at, label), rows, {&*column}));
    }
  }
  return p;
}

}  // namespace

PaperTable read_league_table(const TomlReader& r, PaperTable t) {
  const toml::table& root = r.root();
  r.check_keys(root, "", {"id", "title", "source", "notes", "league", "profile"});
  const toml::table& league = r.table(*r.find(root, "league"), "league");
  r.check_keys(league, "league", {"rows", "columns", "published"});
  TableLeague l;
  l.columns = read_entries<LeagueColumn>(r, league, "columns", "method",
                                         [&](LeagueColumn& c, const std::string& name, const toml::node& at, const std::string& key) {
                                           if (!find_method(name))
                                             r.fail(at, key, fmt::format("unknown method '{}' (see 'hyfal list')", name));
                                           c.method = name;
                                         });
  l.rows = read_entries<LeagueRow>(r, league, "rows", "suite",
                                   [&](LeagueRow& row, const std::string& name, const toml::node& at, const std::string& key) {
                                     if (!find_suite(name))
                                       r.fail(at, key, fmt::format("unknown suite '{}' (see 'hyfal list')", name));
                                     row.suite = name;
                                   });
  // Settings: a row's reach every column's method, a column's every row's suite.
  const toml::array& rows = *league.get("rows")->as_array();
  for (std::size_t i = 0; i < l.rows.size(); ++i)
    if (const auto* s = rows[i].as_table()->get("settings"))
      l.rows[i].settings = read_cell_settings(r, *s, TomlReader::join(TomlReader::index("league.rows", i), "settings"),
                                              {&l.rows[i]}, all_of(l.columns));
  const toml::array& columns = *league.get("columns")->as_array();
  for (std::size_t i = 0; i < l.columns.size(); ++i)
    if (const auto* s = columns[i].as_table()->get("settings"))
      l.columns[i].settings = read_cell_settings(
          r, *s, TomlReader::join(TomlReader::index("league.columns", i), "settings"), all_of(l.rows), {&l.columns[i]});
  if (const auto* p = r.find(league, "published")) {
    const toml::array& tools = r.array(*p, "league.published");
    for (std::size_t i = 0; i < tools.size(); ++i) {
      const std::string at = TomlReader::index("league.published", i);
      l.published.push_back(read_published(r, r.table(tools[i], at), at, l));
    }
  }

  const toml::table& profiles = r.table(r.require(root, "", "profile"), "profile");
  r.check_keys(profiles, "profile", {"smoke", "quick", "full", "published"});
  t.smoke = read_league_profile(r, r.table(r.require(profiles, "profile", "smoke"), "profile.smoke"), "profile.smoke", l);
  t.quick = read_league_profile(r, r.table(r.require(profiles, "profile", "quick"), "profile.quick"), "profile.quick", l);
  if (const auto* n = r.find(profiles, "full"))
    t.full = read_league_profile(r, r.table(*n, "profile.full"), "profile.full", l);
  if (const auto* n = r.find(profiles, "published"))
    t.published = read_league_profile(r, r.table(*n, "profile.published"), "profile.published", l);
  t.league = std::move(l);
  return t;
}

}  // namespace hyfal::table_file
