// The ARCH-COMP league (issue 29): the committed league file reads (rows with their own suites,
// methods, published numbers, profiles), a bad league file is refused in one line naming the key,
// the report picks each row's leader and tests the others against it on censored simulations
// and on the rate, and a tree search stops at its simulation budget as an optimiser does.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "app/experiment_file.hpp"
#include "core/run/option_spec.hpp"
#include "core/run/planner.hpp"
#include "core/run/method_entry.hpp"
#include "results/league_report.hpp"
#include "suites/registry.hpp"

namespace hyfal {
namespace {

std::string setting(const Settings& s, const std::string& key) {
  for (const auto& [k, v] : s)
    if (k == key) return v;
  return "(none)";
}

TEST(LeagueFile, TheCommittedLeagueReads) {
  const PaperTable* t = find_builtin_paper_table("arch-fals");
  ASSERT_NE(t, nullptr);
  ASSERT_TRUE(t->league.has_value());
  const TableLeague& l = *t->league;
  EXPECT_EQ(l.rows.size(), 45u);
  EXPECT_EQ(l.columns.size(), 11u);
  EXPECT_EQ(l.columns[9].method, "rrft");
  EXPECT_EQ(l.columns[10].method, "gradient");
  EXPECT_EQ(l.rows.back().suite, "sc");
  EXPECT_EQ(l.columns[6].method, "adaptive");
  EXPECT_EQ(l.columns[7].method, "adaptive-local");
  EXPECT_EQ(setting(l.columns[8].settings, "input_refinement"), "2");
  EXPECT_EQ(l.rows.front().label, "AT1");
  EXPECT_EQ(l.rows.front().suite, "at");
  EXPECT_EQ(setting(l.rows.front().settings, "requirement"), "AT1");
  EXPECT_EQ(setting(l.rows[16].settings, "input_instance"), "2");
  EXPECT_EQ(l.columns.front().method, "rrt");
  EXPECT_EQ(setting(l.columns.front().settings, "robustness_bias"), "0.5");
  EXPECT_EQ(l.published.size(), 8u);
  EXPECT_EQ(t->quick.trials, 10);
  EXPECT_EQ(t->quick.row_labels.size(), 36u);
  EXPECT_EQ(setting(t->quick.settings, "budget"), "1500");
  ASSERT_TRUE(t->full && t->published);
  EXPECT_EQ(t->full->trials, 50);
  EXPECT_EQ(t->published->trials, 50);
  EXPECT_EQ(setting(t->published->settings, "budget"), "300");
  EXPECT_EQ(setting(t->published->settings, "step"), "7.5");
  // FalStar's adaptive search on FalStar's own 1 s input grid, in the published profile only.
  ASSERT_EQ(t->published->column_settings.size(), 2u);
  EXPECT_EQ(t->published->column_settings.front().first, "adaptive (FalStar)");
  EXPECT_EQ(setting(t->published->column_settings.front().second, "step"), "1");
  EXPECT_TRUE(t->quick.column_settings.empty());
  // Every published cell names a row the published or the quick profile runs, so the comparison is shown.
  const auto runs = [](const TableProfile& p, const std::string& row) {
    return std::find(p.row_labels.begin(), p.row_labels.end(), row) != p.row_labels.end();
  };
  for (const PublishedTool& tool : l.published)
    for (const PublishedCell& c : tool.cells)
      EXPECT_TRUE(runs(*t->published, c.row) || runs(t->quick, c.row)) << tool.label << " " << c.row;
}

const char* const kLeague = R"(id = "tiny-league"
title = "t"
source = "s"
[league]
rows = [
  { label = "A", suite = "thermostat", settings = { requirement = "T3" } },
  { label = "B", suite = "cc", settings = { requirement = "CC1" } },
]
columns = [
  { label = "tree", method = "rrt", settings = { robustness_bias = 0.5 } },
  { label = "random", method = "random" },
]
[[league.published]]
label = "P"
source = "paper"
settings = "5 runs"
cells = [{ row = "A", falsified = 3, runs = 5, mean_simulations = 2.5 }]
[profile.smoke]
trials = 2
timeout_s = 5
max_nodes = 1000
settings = { budget = 10 }
[profile.quick]
trials = 3
timeout_s = 5
max_nodes = 1000
rows = ["B"]
)";

std::string edited(const std::string& from, const std::string& to) {
  std::string text = kLeague;
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

std::string refusal(const std::string& text) {
  try {
    (void)load_paper_table(text, "tiny.toml");
  } catch (const ExperimentFileError& e) {
    return e.what();
  }
  return "(accepted)";
}

TEST(LeagueFile, ATinyLeagueReadsAndBadOnesAreRefusedInOneLineNamingTheKey) {
  const PaperTable t = load_paper_table(kLeague, "tiny.toml");
  ASSERT_TRUE(t.league);
  EXPECT_EQ(t.quick.row_labels, std::vector<std::string>{"B"});
  EXPECT_FALSE(t.full.has_value());
  EXPECT_EQ(t.league->published.front().cells.front().mean_simulations, 2.5);
  EXPECT_TRUE(std::isnan(t.league->published.front().cells.front().mean_s));

  const std::vector<std::pair<std::string, std::string>> bad = {
      {edited("suite = \"cc\"", "suite = \"ccc\""), "tiny.toml:7:"},
      {edited("method = \"random\"", "method = \"rand\""), "league.columns[1].method"},
      // A profile's settings reach every cell: random has no robustness_bias.
      {edited("settings = { budget = 10 }", "settings = { robustness_bias = 0.1 }"), "profile.smoke.settings.robustness_bias"},
      // A row's settings reach every column's method too.
      {edited("requirement = \"T3\" }", "requirement = \"T3\", robustness_bias = 0.1 }"),
       "league.rows[0].settings.robustness_bias"},
      {edited("{ label = \"B\"", "{ label = \"A\""), "league.rows[1].label"},
      {edited("row = \"A\"", "row = \"C\""), "league.published[0].cells[0].row"},
      {edited("falsified = 3", "falsified = 6"), "league.published[0].cells[0].falsified"},
      {edited("rows = [\"B\"]", "rows = [\"Z\"]"), "profile.quick.rows[0]"},
      {edited("[profile.quick]", "[profile.paper]"), "profile.paper"},
      {edited("rows = [\n  {", "rowz = [\n  {"), "league.rowz"},
      // A profile's column settings name a column, and that column's method or every row's suite takes them.
      {edited("rows = [\"B\"]", "rows = [\"B\"]\ncolumn_settings = { nosuch = { budget = 5 } }"),
       "profile.quick.column_settings.nosuch"},
      {edited("rows = [\"B\"]", "rows = [\"B\"]\ncolumn_settings = { random = { robustness_bias = 0.1 } }"),
       "profile.quick.column_settings.random.robustness_bias"},
  };
  for (const auto& [text, key] : bad) {
    const std::string m = refusal(text);
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    EXPECT_EQ(m.rfind("tiny.toml:", 0), 0u) << m;
    EXPECT_NE(m.find(key), std::string::npos) << key << ": " << m;
  }
}

TrialRecord run_of(TrialStatus status, double simulations) {
  TrialRecord t;
  t.status = status;
  t.validated = status == TrialStatus::falsified;
  t.wall_s = 0.5;
  t.nodes = static_cast<std::int64_t>(simulations);
  t.metrics = fmt::format(R"({{"robustness":{},"simulations":{}}})", status == TrialStatus::falsified ? -1.0 : 2.0,
                          simulations);
  return t;
}

TEST(LeagueReport, TheLeaderFalsifiesMostAndTheOthersAreTestedOnCensoredSimulations) {
  PaperTable t = load_paper_table(kLeague, "tiny.toml");
  std::vector<std::vector<std::vector<TrialRecord>>> trials(2, std::vector<std::vector<TrialRecord>>(2));
  for (const double s : {2.0, 3.0, 3.0, 4.0, 5.0}) trials[0][1].push_back(run_of(TrialStatus::falsified, s));
  trials[0][0].push_back(run_of(TrialStatus::falsified, 10.0));  // one success, then the budget
  for (int i = 0; i < 4; ++i) trials[0][0].push_back(run_of(TrialStatus::node_cap, 100.0));
  const LeagueReport r = make_league_report(t, trials, {true, false});
  EXPECT_EQ(r.verdicts[0].leader, 1);  // random: 5/5
  const LeagueCell& tree = r.cells[0][0];
  EXPECT_EQ(tree.falsified, 1u);
  EXPECT_EQ(tree.budget_stops, 4u);
  EXPECT_EQ(tree.simulations.mean, 10.0);  // of the falsifying run only
  ASSERT_EQ(tree.observations.size(), 5u);
  EXPECT_TRUE(tree.observations[1].censored);
  // Every leader's run certainly needs fewer simulations than each of the tree's: the smallest
  // exact p of 5 against 5 (2/252), and Fisher's exact p of 5/5 against 1/5 (0.048).
  const LeagueComparison& c = r.verdicts[0].against_leader[0];
  EXPECT_EQ(c.simulations.order, SampleOrder::y_smaller);
  EXPECT_NEAR(c.simulations.test.p_value, 2.0 / 252.0, 1e-12);
  EXPECT_EQ(c.rate.order, SampleOrder::x_smaller);  // the tree's rate is the lower
  EXPECT_NEAR(c.rate.test.p_value, 0.0476190, 1e-6);

  ReportHeader h;
  h.profile = "smoke";
  const std::string md = to_markdown(r, h);
  EXPECT_NE(md.find("| A | thermostat | 1/5 · 10.0 (10.0) | **5/5 · 3.40 (3.00)** |"), std::string::npos) << md;
  EXPECT_NE(md.find("more sims (p = 0.0079), lower rate (p = 0.048)"), std::string::npos) << md;
  EXPECT_EQ(md.find("| B |"), std::string::npos) << "a row the profile did not run is not shown";
  EXPECT_NE(md.find("| A | 1/5 · 10.0 (10.0) | 5/5 · 3.40 (3.00) | 3/5 · 2.50 (–) |"), std::string::npos) << md;
  const std::string csv = to_csv(r, h);
  std::size_t lines = 0;
  for (std::size_t at = 0; at < csv.size();) {
    const std::size_t end = csv.find("\r\n", at);
    const std::string line = csv.substr(at, end - at);
    EXPECT_EQ(std::count(line.begin(), line.end(), ','), 27) << line;
    at = end + 2;
    ++lines;
  }
  EXPECT_EQ(lines, 4u);  // header, two cells, one published
  EXPECT_NE(csv.find("tiny-league,smoke,P,A,thermostat,P,,5,3,,0.6,"), std::string::npos) << csv;
  EXPECT_EQ(md.find("## Witnesses near the threshold"), std::string::npos) << "no scales given: no section";

  // With a threshold scale per row: a falsifying run whose robustness lies within 1 % of it is
  // counted (|-0.5| <= 1 for a scale of 100; -5 is not), the others are not.
  std::vector<std::vector<std::vector<TrialRecord>>> near(2, std::vector<std::vector<TrialRecord>>(2));
  for (const char* m : {R"({"simulations": 2, "robustness": -0.5})", R"({"simulations": 3, "robustness": -5})",
                        R"({"simulations": 4, "robustness": -1})"}) {
    TrialRecord t = run_of(TrialStatus::falsified, 1.0);
    t.metrics = m;
    near[0][1].push_back(t);
  }
  TrialRecord capped = run_of(TrialStatus::node_cap, 100.0);
  capped.metrics = R"({"simulations": 100, "robustness": 0.2})";
  near[0][0].push_back(capped);
  const LeagueReport rn = make_league_report(t, near, {true, false}, {100.0, 40.0});
  EXPECT_EQ(rn.cells[0][1].near_threshold, 2u);
  EXPECT_EQ(rn.cells[0][0].near_threshold, 0u);  // not falsified: not a witness
  const std::string mdn = to_markdown(rn, h);
  EXPECT_NE(mdn.find("| A | 1.00 | 0 of 0 | 2 of 3 |"), std::string::npos) << mdn;
  EXPECT_NE(to_csv(rn, h).find(",2\r\n"), std::string::npos);
}

// A cell whose method cannot drive the row's suite (a search over input signals on F16, which has
// none) does not apply: "n/a" in the league and the verdicts, no line in the CSV and the statistics,
// never the leader, and its reason listed once for its cells.
TEST(LeagueReport, ACellThatDoesNotApplyIsShownAsSuchAndJudgedNowhere) {
  PaperTable t = load_paper_table(kLeague, "tiny.toml");
  std::vector<std::vector<std::vector<TrialRecord>>> trials(2, std::vector<std::vector<TrialRecord>>(2));
  for (const double s : {2.0, 3.0}) trials[0][1].push_back(run_of(TrialStatus::falsified, s));
  const std::vector<std::vector<std::string>> why = {
      {"method 'rrt' on suite 'thermostat': suite 'thermostat' has no inputs, and this method does not search its "
       "parameters P (p); use random",
       ""},
      {"", ""}};
  const LeagueReport r = make_league_report(t, trials, {true, false}, {}, why);
  EXPECT_EQ(r.verdicts[0].leader, 1);
  EXPECT_FALSE(r.cells[0][0].not_applicable.empty());
  ReportHeader h;
  h.profile = "smoke";
  const std::string md = to_markdown(r, h);
  EXPECT_NE(md.find("| A | thermostat | n/a | **2/2 · 2.50 (2.50)** |"), std::string::npos) << md;
  EXPECT_NE(md.find("| A | random | n/a | leader |"), std::string::npos) << md;
  EXPECT_NE(md.find("- A × tree: suite 'thermostat' has no inputs, and this method does not search"), std::string::npos) << md;
  EXPECT_EQ(md.find("| A | tree | 0 |"), std::string::npos) << "no statistics line for it";
  const std::string csv = to_csv(r, h);
  EXPECT_EQ(csv.find(",A,thermostat,tree,"), std::string::npos) << csv;
  EXPECT_NE(csv.find(",A,thermostat,random,"), std::string::npos) << csv;
  EXPECT_THROW(make_league_report(t, trials, {true, false}, {}, {{"", ""}}), std::invalid_argument);

  // A row nobody falsifies has no leader (nothing bold, no comparisons).
  std::vector<std::vector<std::vector<TrialRecord>>> none(2, std::vector<std::vector<TrialRecord>>(2));
  for (int i = 0; i < 3; ++i) none[0][1].push_back(run_of(TrialStatus::node_cap, 100.0));
  const LeagueReport rn = make_league_report(t, none, {true, false}, {}, why);
  EXPECT_EQ(rn.verdicts[0].leader, -1);
  const std::string mdn = to_markdown(rn, h);
  EXPECT_NE(mdn.find("| A | thermostat | n/a | 0/3 |"), std::string::npos) << mdn;
  EXPECT_NE(mdn.find("| A | – | n/a | – |"), std::string::npos) << mdn;
}

// A tree given a budget stops once its simulated time reaches budget x the requirement's horizon
// (status budget, as an optimiser at its budget), within one extension of it.
TEST(SimulationBudget, ATreeStopsAtItsBudgetAsAnOptimiserDoes) {
  const SuiteEntry* at = find_suite("at");
  const auto sys = at->make(resolve_options(at->parameters, {{"requirement", "AT1"}}));
  for (const char* method : {"rrt", "rrt-dstar"}) {
    const MethodEntry* m = find_method(method);
    auto planner = m->make(resolve_options(m->options, {{"budget", "20"}}));
    const PlannerOutcome out = planner->solve({*sys, sys->info().parameters, 7, {60.0, 1'000'000}});
    EXPECT_EQ(out.status, TrialStatus::budget) << method;
    const double sims = out.counters.simulated_time / 20.0;  // AT1's horizon: 20 s
    EXPECT_GE(sims, 20.0) << method;
    EXPECT_LT(sims, 20.0 + 9 * 1.0 / 20.0 + 1e-9) << method << ": one extension is at most 9 pieces of 1 s";
  }
  // A budget needs a requirement to count simulations in.
  const auto reach = at->make(resolve_options(at->parameters, {}));
  const MethodEntry* rrt = find_method("rrt");
  EXPECT_THROW(rrt->check_system(*reach, resolve_options(rrt->options, {{"budget", "20"}})), std::invalid_argument);
  EXPECT_NO_THROW(rrt->check_system(*reach, resolve_options(rrt->options, {})));
}

}  // namespace
}  // namespace hyfal
