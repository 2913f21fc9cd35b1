// Tests of results/paper_report: the paper's numbers beside ours, ratios to the first row,
// the ordering verdicts of a table (the test itself: test_verdicts), metric extraction from
// TrialRecord::metrics, Markdown and CSV.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "results/paper_report.hpp"
#include "results/sweep_report.hpp"

namespace hyfal {
namespace {

TrialRecord trial(std::int64_t nodes, double wall_s, TrialStatus status = TrialStatus::falsified,
                  std::string metrics = "{}") {
  TrialRecord r;
  r.key = {"t/smoke", "suite", "{}", "rrt", "{}", 0};
  r.status = status;
  r.nodes = nodes;
  r.wall_s = wall_s;
  r.metrics = std::move(metrics);
  return r;
}

ReportHeader header_of(std::string profile) {
  ReportHeader h;
  h.profile = std::move(profile);
  return h;
}

// Two rows (A, B), two columns (nodes, coverage).
PaperTable two_by_two(double a_nodes, double b_nodes, double a_cov, double b_cov) {
  PaperTable t;
  t.id = "test-table";
  t.title = "Test table";
  t.source = "seed 000 Table X";
  t.suite = "suite";
  t.notes = "hand-made";
  t.columns = {{"nodes", TableMetric::nodes, ""}, {"coverage", TableMetric::coverage, "coverage"}};
  t.rows = {{"A", "rrt", {{"step", "0.1"}}, {a_nodes, a_cov}}, {"B", "rrt", {}, {b_nodes, b_cov}}};
  return t;
}

std::vector<std::vector<TrialRecord>> two_by_two_trials() {
  return {
      // A: nodes 100, 200, 300 -> 200; coverage 0.5, 0.7 (the third trial has none) -> 0.6
      {trial(100, 1.0, TrialStatus::falsified, R"({"coverage":0.5})"),
       trial(200, 2.0, TrialStatus::falsified, R"({"coverage":0.7,"beta":3})"),
       trial(300, 3.0, TrialStatus::not_found, "{}")},
      // B: nodes 400, 600 -> 500; coverage 0.2, 0.4 -> 0.3
      {trial(400, 4.0, TrialStatus::falsified, R"({"coverage":0.2})"),
       trial(600, 6.0, TrialStatus::falsified, R"({"coverage":0.4})")},
  };
}

// Row A's coverage is the mean of the 2 of its 3 trials that recorded one: the cell says so;
// row B's 2 of 2 needs no count.
TEST(PaperReport, ACoverageCellSaysHowManyTrialsItAverages) {
  const std::string md =
      to_markdown(make_paper_report(two_by_two(1000, 2500, 0.8, 0.4), two_by_two_trials()), header_of("smoke"));
  EXPECT_NE(md.find("| 0.600 (2 of 3 trials) |"), std::string::npos) << md;
  EXPECT_EQ(md.find("of 2 trials)"), std::string::npos) << md;
}

TEST(PaperReport, MeansAndRatiosToTheFirstRow) {
  const PaperReport r = make_paper_report(two_by_two(1000, 2500, 0.8, 0.4), two_by_two_trials());
  ASSERT_EQ(r.rows.size(), 2u);
  ASSERT_EQ(r.rows[0].cells.size(), 2u);
  const auto& a = r.rows[0];
  const auto& b = r.rows[1];
  EXPECT_EQ(a.n, 3u);
  EXPECT_EQ(b.n, 2u);
  EXPECT_DOUBLE_EQ(a.falsified_rate, 2.0 / 3.0);
  EXPECT_DOUBLE_EQ(b.falsified_rate, 1.0);
  EXPECT_DOUBLE_EQ(a.cells[0].ours, 200.0);
  EXPECT_DOUBLE_EQ(b.cells[0].ours, 500.0);
  EXPECT_DOUBLE_EQ(a.cells[1].ours, 0.6);
  EXPECT_DOUBLE_EQ(b.cells[1].ours, 0.3);
  EXPECT_EQ(a.cells[1].sample.n, 2u) << "only trials that have the metric count";
  EXPECT_DOUBLE_EQ(a.cells[0].paper, 1000.0);
  EXPECT_DOUBLE_EQ(a.cells[0].paper_ratio, 1.0);
  EXPECT_DOUBLE_EQ(a.cells[0].ours_ratio, 1.0);
  EXPECT_DOUBLE_EQ(b.cells[0].paper_ratio, 2.5);
  EXPECT_DOUBLE_EQ(b.cells[0].ours_ratio, 2.5);
  EXPECT_DOUBLE_EQ(b.cells[1].paper_ratio, 0.5);
  EXPECT_DOUBLE_EQ(b.cells[1].ours_ratio, 0.5);
  EXPECT_DOUBLE_EQ(a.nodes.median, 200.0);
  EXPECT_DOUBLE_EQ(a.wall_s.mean, 2.0);
  EXPECT_LT(a.nodes.ci_low, 200.0);
  EXPECT_GT(a.nodes.ci_high, 200.0);
  ASSERT_EQ(r.orderings.size(), 2u);
  // Ours follow the paper's order in both columns, but 3 and 2 trials cannot make it significant.
  EXPECT_EQ(r.orderings[0].verdict, OrderingVerdict::within_noise);
  EXPECT_EQ(r.orderings[1].verdict, OrderingVerdict::within_noise);
  EXPECT_EQ(r.orderings[1].paper_order, (std::vector<std::size_t>{1, 0}));  // B < A by coverage
  EXPECT_EQ(r.orderings[1].ours_order, (std::vector<std::size_t>{1, 0}));
  // Nodes A {100, 200, 300} vs B {400, 600}: W = -6, u = -4, -2, 0 | 2, 4, Var W = 6 / 20 · 40 = 12.
  ASSERT_EQ(r.orderings[0].pairs.size(), 1u);
  EXPECT_DOUBLE_EQ(r.orderings[0].pairs[0].test.statistic, -6.0);
  EXPECT_NEAR(r.orderings[0].pairs[0].test.variance, 12.0, 1e-12);
  // Exact: of the C(5, 2) = 10 choices of B's two scores only {2, 4} and {-4, -2} reach |6|: p = 0.2.
  EXPECT_TRUE(r.orderings[0].pairs[0].test.p_exact);
  EXPECT_DOUBLE_EQ(r.orderings[0].pairs[0].test.p_value, 0.2);
  // The test sees the coverage values of the trials that have them: 2 and 2.
  EXPECT_EQ(r.rows[0].cells[1].observations.size(), 2u);
}

// n = 10 per row, clearly apart: the verdicts become significant.
std::vector<std::vector<TrialRecord>> ten_and_ten(std::int64_t a_first, std::int64_t b_first) {
  std::vector<std::vector<TrialRecord>> trials(2);
  for (std::int64_t i = 0; i < 10; ++i) {
    trials[0].push_back(trial(a_first + i, 1.0, TrialStatus::falsified, R"({"coverage":0.1})"));
    trials[1].push_back(trial(b_first + i, 1.0, TrialStatus::falsified, R"({"coverage":0.1})"));
  }
  return trials;
}

TEST(PaperReport, TimeAndFalsifiedRateColumnsAndErrorsExcluded) {
  PaperTable t = two_by_two(1, 2, 3, 4);
  t.columns = {{"time (s)", TableMetric::time_s, ""}, {"rate", TableMetric::falsified_rate, ""}};
  auto trials = two_by_two_trials();
  trials[1].push_back(trial(1'000'000, 100.0, TrialStatus::error));  // counts in n and the rate only
  const PaperReport r = make_paper_report(t, trials);
  EXPECT_DOUBLE_EQ(r.rows[1].cells[0].ours, 5.0);
  EXPECT_DOUBLE_EQ(r.rows[1].cells[1].ours, 2.0 / 3.0);
  EXPECT_EQ(r.rows[1].n, 3u);
  EXPECT_EQ(r.rows[1].errors, 1u);
  EXPECT_DOUBLE_EQ(r.rows[1].nodes.mean, 500.0);
  EXPECT_DOUBLE_EQ(r.rows[0].cells[0].ours, 2.0);
}

TEST(PaperReport, OrderingVerdictsHoldReversedAndWithinNoise) {
  // Paper: B needs fewer nodes than A; ours: A {100..109} fewer than B {200..209}: reversed.
  const PaperReport reversed = make_paper_report(two_by_two(1000, 500, 0.8, 0.4), ten_and_ten(100, 200));
  EXPECT_EQ(reversed.orderings[0].verdict, OrderingVerdict::reversed);
  // Coverage: paper B < A, ours all 0.1: within noise (it was a failure under the 1 % tie band).
  EXPECT_EQ(reversed.orderings[1].verdict, OrderingVerdict::within_noise);
  const std::string md = to_markdown(reversed, header_of("smoke"));
  EXPECT_NE(md.find("- ordering (nodes): paper B < A — ours A < B — B < A: reversed (p < 0.001) — reversed: 0 hold, "
                    "0 within noise, 1 reversed\n"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("- ordering (coverage): paper B < A — ours A ≈ B — B < A: within noise (p = 1.0) — within noise: "
                    "0 hold, 1 within noise, 0 reversed\n"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("Summary over the columns' adjacent pairs: 0 hold, 1 within noise, 1 reversed."), std::string::npos)
      << md;
  EXPECT_NE(md.find("Gehan's generalized Wilcoxon test (Gehan 1965, Biometrika 52: 203-223"), std::string::npos) << md;
  EXPECT_EQ(md.find("1 %"), std::string::npos) << "the tie band is gone\n" << md;

  // The same trials under the paper's order A < B: holds.
  const PaperReport holds = make_paper_report(two_by_two(500, 1000, 0.8, 0.4), ten_and_ten(100, 200));
  EXPECT_EQ(holds.orderings[0].verdict, OrderingVerdict::holds);
  EXPECT_NE(to_markdown(holds, header_of("smoke")).find("— A < B: holds (p < 0.001) — holds: 1 hold"), std::string::npos);
}

// A table of one row (seed 003's RRFT tables) has no order to check: no Ordering section, where
// it used to list every column as "not checked (fewer than two rows ...)" (issue 27).
TEST(PaperReport, OneRowHasNoOrderingSection) {
  PaperTable t = two_by_two(1000, 2500, 0.8, 0.4);
  t.rows.pop_back();
  const std::vector<std::vector<TrialRecord>> trials{two_by_two_trials()[0]};
  const std::string one = to_markdown(make_paper_report(t, trials), header_of("smoke"));
  EXPECT_EQ(one.find("## Ordering"), std::string::npos) << one;
  EXPECT_EQ(one.find("not checked"), std::string::npos) << one;
  EXPECT_NE(one.find("## Trials"), std::string::npos) << one;
  const std::string two = to_markdown(make_paper_report(two_by_two(1000, 2500, 0.8, 0.4), two_by_two_trials()),
                                      header_of("smoke"));
  EXPECT_NE(two.find("## Ordering"), std::string::npos) << two;
}

TEST(PaperReport, TimeoutsAreCensoredInTheOrderingTest) {
  // Paper: A is faster than B. Ours: A finishes 10 trials in 1..10 s, B times out in all 10 at
  // 9.5 s. By the recorded times B would look faster; as censored values it is certainly slower.
  PaperTable t = two_by_two(1, 2, 3, 4);
  t.columns = {{"time (s)", TableMetric::time_s, ""}};
  std::vector<std::vector<TrialRecord>> trials(2);
  for (int i = 0; i < 10; ++i) {
    trials[0].push_back(trial(10, 1.0 + i * 0.9));  // 1.0 .. 9.1 s
    trials[1].push_back(trial(10, 9.5, TrialStatus::timeout));
  }
  const PaperReport r = make_paper_report(t, trials);
  EXPECT_EQ(r.rows[1].cells[0].observations.front(), (CensoredValue{9.5, true}));
  EXPECT_EQ(r.orderings[0].verdict, OrderingVerdict::holds);
}

TEST(PaperReport, NaNPaperValuesAreSkipped) {
  PaperTable t = two_by_two(1000, 2500, 0.8, 0.4);
  t.rows.insert(t.rows.begin() + 1, PaperRow{"C", "rrt", {}, {kNotReported, kNotReported}});
  auto trials = two_by_two_trials();
  // C is by far the slowest in ours: it would break the nodes order if it were not skipped.
  trials.insert(trials.begin() + 1, std::vector<TrialRecord>{trial(9000, 9.0)});
  const PaperReport r = make_paper_report(t, trials);
  EXPECT_TRUE(std::isnan(r.rows[1].cells[0].paper));
  EXPECT_TRUE(std::isnan(r.rows[1].cells[0].paper_ratio));
  EXPECT_DOUBLE_EQ(r.rows[1].cells[0].ours_ratio, 45.0);
  EXPECT_EQ(r.orderings[0].paper_order, (std::vector<std::size_t>{0, 2}));
  EXPECT_EQ(r.orderings[0].ours_order, (std::vector<std::size_t>{0, 2}));
  ASSERT_EQ(r.orderings[0].pairs.size(), 1u);  // A and B only
  EXPECT_EQ(r.orderings[0].pairs[0].first, 0u);
  EXPECT_EQ(r.orderings[0].pairs[0].second, 2u);
  EXPECT_EQ(r.orderings[0].verdict, OrderingVerdict::within_noise);  // 3 vs 2 trials
  const std::string md = to_markdown(r, header_of("smoke"));
  EXPECT_NE(md.find("| C | rrt | N/A | – | 9000 | 45.0 |"), std::string::npos) << md;

  // A NaN paper value in the first row leaves every paper ratio of that column unknown.
  PaperTable u = two_by_two(kNotReported, 2500, 0.8, 0.4);
  const PaperReport s = make_paper_report(u, two_by_two_trials());
  EXPECT_TRUE(std::isnan(s.rows[1].cells[0].paper_ratio));
  EXPECT_EQ(s.orderings[0].verdict, OrderingVerdict::not_checked);  // one row left
  // A paper vector shorter than the columns reads as NaN.
  u.rows[1].paper = {2500};
  EXPECT_TRUE(std::isnan(make_paper_report(u, two_by_two_trials()).rows[1].cells[1].paper));
}

TEST(PaperReport, FalsifiedRateIsTestedOnTheIndicators) {
  // Paper: A's rate 0.2 is below B's 0.9; ours 0.1 (1 of 10) and 0.9 (9 of 10, one error).
  PaperTable t = two_by_two(0.2, 0.9, 3, 4);
  t.columns = {{"rate", TableMetric::falsified_rate, ""}};
  std::vector<std::vector<TrialRecord>> trials(2);
  for (int i = 0; i < 10; ++i) {
    trials[0].push_back(trial(10, 1.0, i < 1 ? TrialStatus::falsified : TrialStatus::not_found));  // 0.1
    trials[1].push_back(trial(10, 1.0, i < 9 ? TrialStatus::falsified : TrialStatus::error));      // 0.9
  }
  const PaperReport r = make_paper_report(t, trials);
  ASSERT_EQ(r.rows[1].cells[0].observations.size(), 10u) << "errors count, as not falsified";
  EXPECT_DOUBLE_EQ(r.rows[1].cells[0].ours, 0.9);
  EXPECT_NEAR(r.rows[1].cells[0].sample.stddev, std::sqrt(0.1), 1e-12);  // 9 ones, 1 zero: var = 0.9 / 9
  EXPECT_EQ(r.orderings[0].verdict, OrderingVerdict::holds);
}

TEST(PaperReport, MetricKeyExtraction) {
  const std::vector<TrialRecord> trials{
      trial(1, 1, TrialStatus::falsified, R"({"coverage":0.25,"beta":2})"),
      trial(1, 1, TrialStatus::falsified, R"({"beta":4})"),
      trial(1, 1, TrialStatus::falsified, R"({"coverage":"high"})"),  // not a number
      trial(1, 1, TrialStatus::falsified, "not json"),
      trial(1, 1, TrialStatus::falsified, "[1,2]"),
      trial(1, 1, TrialStatus::timeout, R"({"coverage":1})"),
  };
  EXPECT_EQ(metric_values(trials, "coverage"), (std::vector<double>{0.25, 1.0}));
  EXPECT_EQ(metric_values(trials, "beta"), (std::vector<double>{2.0, 4.0}));
  EXPECT_TRUE(metric_values(trials, "trees").empty());

  PaperTable t = two_by_two(1, 2, 3, 4);
  t.columns[1].metric_key = "beta";
  const PaperReport r = make_paper_report(t, {trials, {}});
  EXPECT_DOUBLE_EQ(r.rows[0].cells[1].ours, 3.0);
  EXPECT_TRUE(std::isnan(r.rows[1].cells[1].ours)) << "no trials: no value";
  EXPECT_EQ(r.orderings[1].verdict, OrderingVerdict::not_checked);
}

TEST(PaperReport, CensoredMeansAreMarked) {
  auto trials = two_by_two_trials();
  trials[1].push_back(trial(700, 7.0, TrialStatus::timeout));
  const PaperReport r = make_paper_report(two_by_two(1000, 2500, 0.8, 0.4), trials);
  EXPECT_EQ(r.rows[1].cells[0].ours_bound, Bound::lower);
  EXPECT_EQ(r.rows[1].cells[0].ours_ratio_bound, Bound::lower);
  EXPECT_EQ(r.rows[1].cells[1].ours_bound, Bound::exact) << "coverage is not censored";
  EXPECT_EQ(r.rows[0].cells[0].ours_bound, Bound::exact);
  const std::string md = to_markdown(r, header_of("smoke"));
  EXPECT_NE(md.find("| B | rrt | 2500 | 2.50 | ≥567 | ≥2.83 |"), std::string::npos) << md;
  EXPECT_NE(md.find("1 ⏱"), std::string::npos) << md;
  EXPECT_NE(md.find("≥ right-censored"), std::string::npos) << md;

  // A censored first row makes the other rows' ratios upper bounds.
  std::swap(trials[0], trials[1]);
  const PaperReport s = make_paper_report(two_by_two(1000, 2500, 0.8, 0.4), trials);
  EXPECT_EQ(s.rows[0].cells[0].ours_ratio_bound, Bound::exact);
  EXPECT_EQ(s.rows[1].cells[0].ours_ratio_bound, Bound::upper);
}

TEST(PaperReport, MarkdownHeader) {
  const PaperReport r = make_paper_report(two_by_two(1000, 2500, 0.8, 0.4), two_by_two_trials());
  ReportHeader h;
  h.profile = "quick";
  h.trials = 3;
  h.timeout_s = 10;
  h.max_nodes = 5000;
  h.host = "box";
  h.nproc = 16;
  h.cpu_model = "Some CPU";
  h.date_utc = "2026-01-02 03:04:05 UTC";
  h.git_commit = "abcdef123456";
  const std::string md = to_markdown(r, h);
  for (const char* needle :
       {"# test-table: Test table\n", "- source: seed 000 Table X\n", "quick: 3 trials per row, timeout 10 s",
        "box, nproc 16, Some CPU", "- date (UTC): 2026-01-02 03:04:05 UTC\n", "- git commit: abcdef123456\n",
        "- notes: hand-made\n", "## nodes\n", "## coverage\n",
        "| row | method | paper | paper × of row 1 | ours | ours × of row 1 |",
        "| A | rrt | 1000 | 1.00 | 200 | 1.00 |", "| B | rrt | 2500 | 2.50 | 500 | 2.50 |",
        "| A | rrt | 0.8 | 1.00 | 0.600 (2 of 3 trials) | 1.00 |",
        "| row | method | settings | n | falsified | falsified rate | nodes mean | nodes median | nodes std | nodes 95% CI "
        "| time mean (s) | time median (s) | time std (s) | time 95% CI (s) | timeouts |",
        // A: nodes 100, 200, 300 (mean and median 200, std 100), times 1, 2, 3 s (std 1).
        "| A | rrt | step=0.1 | 3 | 2 | 0.67 | 200 | 200 | 100 | [-48.4, 448] | 2.00 | 2.00 | 1.00 | [-0.484, 4.48] | 0 |"})
    EXPECT_NE(md.find(needle), std::string::npos) << needle << "\n" << md;
}

TEST(PaperReport, CsvLinesAndEscaping) {
  PaperTable t = two_by_two(1000, kNotReported, 0.8, 0.4);
  t.rows[0].label = "t2go, \"fast\"";
  t.columns[1].name = "coverage\nafter 5000";
  const PaperReport r = make_paper_report(t, two_by_two_trials());
  const std::string csv = to_csv(r, header_of("smoke"));
  const std::string header =
      "table,profile,row,method,column,paper,ours,paper_ratio,ours_ratio,n,falsified_rate,median,ci_low,ci_high,"
      "timeouts,std,falsified,node_caps,nodes_mean,nodes_median,nodes_std,nodes_ci_low,nodes_ci_high,time_mean_s,"
      "time_median_s,time_std_s,time_ci_low_s,time_ci_high_s,paper_previous,verdict,p_value,budgets\r\n";
  ASSERT_EQ(csv.substr(0, header.size()), header);
  std::size_t lines = 0;
  for (std::size_t p = 0; (p = csv.find("\r\n", p)) != std::string::npos; p += 2) ++lines;
  EXPECT_EQ(lines, 5u) << "header + 2 rows x 2 columns";
  EXPECT_NE(csv.find("test-table,smoke,\"t2go, \"\"fast\"\"\",rrt,nodes,1000,200,1,1,3,"), std::string::npos) << csv;
  EXPECT_NE(csv.find(",\"coverage\nafter 5000\",0.8,0.6,1,1,2,"), std::string::npos) << csv;
  // B's nodes: paper N/A -> empty paper and paper_ratio; ours 500, ratio 2.5; median 500.
  EXPECT_NE(csv.find("test-table,smoke,B,rrt,nodes,,500,,2.5,2,1,500,"), std::string::npos) << csv;
  // A's nodes, after timeouts: std 100, 2 falsified, 0 node caps, nodes mean 200, median 200,
  // std 100, CI; the first of the paper's order, so no pair verdict (three empty fields).
  const std::size_t a_nodes = csv.find("\"t2go, \"\"fast\"\"\",rrt,nodes,");
  ASSERT_NE(a_nodes, std::string::npos);
  const std::string a_line = csv.substr(a_nodes, csv.find("\r\n", a_nodes) - a_nodes);
  EXPECT_NE(a_line.find(",0,100,2,0,200,200,100,"), std::string::npos) << a_line;
  EXPECT_EQ(a_line.substr(a_line.size() - 5), ",,,,0") << a_line;  // no pair verdict; no budget stop
  // Coverage: paper B (0.4) < A (0.8), so A's line carries the pair B < A.
  const std::size_t a_coverage = csv.find(",\"coverage\nafter 5000\",0.8,");
  ASSERT_NE(a_coverage, std::string::npos);
  const std::string coverage_line = csv.substr(a_coverage, csv.find("\r\n", a_coverage) - a_coverage);
  EXPECT_NE(coverage_line.find(",B,within noise,0."), std::string::npos) << coverage_line;
  EXPECT_EQ(coverage_line.substr(coverage_line.size() - 2), ",0") << coverage_line;
}

TEST(PaperReport, RowCountMismatchThrows) {
  EXPECT_THROW(make_paper_report(two_by_two(1, 2, 3, 4), {{}}), std::invalid_argument);
}

// --- sweep tables (seed 002 Table 1 shape) -------------------------------------------------------

TEST(SweepReport, CellMeansTimeoutsAndOrderingPerColumn) {
  PaperTable t;
  t.id = "sweep";
  t.rows = {{"RRT", "rrt", {}, {}}, {"HyDICE", "hydice", {}, {}}};
  TableSweep sw;
  sw.columns = {{"2²", {{"n", "2"}}}, {"4²", {{"n", "4"}}}, {"8²", {{"n", "8"}}}};
  sw.blocks = {{"RandomDriver", {{"driver", "random"}}}};
  sw.instance_key = "property";
  sw.paper = {{{0.1, 0.3, kPaperTimeout}, {0.4, 0.6, 1.2}}};
  sw.paper_timeout_s = 3600;
  t.sweep = sw;
  using Cells = std::vector<std::vector<std::vector<std::vector<TrialRecord>>>>;
  Cells trials(1, std::vector<std::vector<std::vector<TrialRecord>>>(2, std::vector<std::vector<TrialRecord>>(3)));
  trials[0][0][0] = {trial(10, 1.0), trial(10, 3.0)};                            // RRT 2²: mean 2
  trials[0][1][0] = {trial(10, 0.5), trial(10, 1.5)};                            // HyDICE 2²: mean 1
  trials[0][0][1] = {trial(10, 20.0, TrialStatus::timeout), trial(10, 2.0)};     // censored
  trials[0][1][1] = {trial(10, 0.2), trial(10, 0.4), trial(10, 1.0, TrialStatus::error)};
  const SweepReport r = make_sweep_report(t, trials, 2);  // the profile ran 2², 4²
  const SweepCell& a = r.cells[0][0][0];
  EXPECT_TRUE(a.run);
  EXPECT_EQ(a.n, 2u);
  EXPECT_DOUBLE_EQ(a.mean_s, 2.0);
  EXPECT_DOUBLE_EQ(a.paper, 0.1);
  EXPECT_TRUE(r.cells[0][0][1].censored());
  EXPECT_FALSE(r.cells[0][0][1].all_stopped());
  EXPECT_DOUBLE_EQ(r.cells[0][0][1].mean_s, 11.0);
  EXPECT_EQ(r.cells[0][1][1].errors, 1u);
  EXPECT_NEAR(r.cells[0][1][1].mean_s, 0.3, 1e-12);  // errors excluded
  EXPECT_FALSE(r.cells[0][0][2].run);
  EXPECT_TRUE(std::isinf(r.cells[0][0][2].paper));
  EXPECT_DOUBLE_EQ(a.wall_s.stddev, std::sqrt(2.0));
  EXPECT_DOUBLE_EQ(a.nodes.mean, 10.0);
  EXPECT_EQ(r.cells[0][0][1].observations, (std::vector<CensoredValue>{{20.0, true}, {2.0, false}}));
  ASSERT_EQ(r.orderings[0].size(), 2u);
  // Paper RRT < HyDICE, ours the other way, but two trials per cell cannot be significant.
  EXPECT_EQ(r.orderings[0][0].verdict, OrderingVerdict::within_noise);
  EXPECT_EQ(r.orderings[0][1].verdict, OrderingVerdict::within_noise);
  ReportHeader h;
  h.profile = "quick";
  const std::string md = to_markdown(r, h);
  EXPECT_NE(md.find("## RandomDriver"), std::string::npos);
  EXPECT_NE(md.find("| HyDICE | 1.00 | 0.300 [2/3] |"), std::string::npos) << md;  // the error is not falsified
  EXPECT_NE(md.find("≥11.0"), std::string::npos);
  EXPECT_NE(md.find("| RRT | 0.1 | 0.3 | X |"), std::string::npos) << md;
  EXPECT_NE(md.find("| method | column | n | falsified | stopped | time mean | time median | time std | time 95% CI |"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("| RRT | 4² | 2 | 1 | 1 | ≥11.0 | ≥11.0 | 12.7 | ≥[-103, 125] | ≥10 | ≥10 | 0 | ≥[10, 10] |"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("- 2²: paper RRT < HyDICE — ours HyDICE ≈ RRT — RRT < HyDICE: within noise (p = "), std::string::npos)
      << md;
  EXPECT_NE(md.find("Summary over the table's adjacent pairs: 0 hold, 2 within noise, 0 reversed."), std::string::npos)
      << md;
  const std::string csv = to_csv(r, h);
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 1 + 4);  // header + 2 rows x 2 run columns
  EXPECT_EQ(csv.substr(0, csv.find("\r\n")),
            "table,profile,block,row,method,column,paper,ours_mean,ours_median,n,falsified,falsified_rate,timeouts,"
            "errors,time_std_s,time_ci_low_s,time_ci_high_s,nodes_mean,nodes_median,nodes_std,nodes_ci_low,"
            "nodes_ci_high,paper_previous,verdict,p_value,skipped,statistic");
  // HyDICE 2² comes after RRT in the paper's order: its line carries that pair's verdict.
  EXPECT_NE(csv.find(",RandomDriver,HyDICE,hydice,2²,0.4,1,1,2,2,1,0,0,"), std::string::npos) << csv;
  EXPECT_NE(csv.find(",RRT,within noise,"), std::string::npos) << csv;
  EXPECT_THROW(make_sweep_report(t, Cells(2), 2), std::invalid_argument);

  // A column without paper values: nothing to order, said so.
  t.sweep->paper = {{{kNotReported, 0.3, kPaperTimeout}, {kNotReported, 0.6, 1.2}}};
  const std::string unchecked = to_markdown(make_sweep_report(t, trials, 2), h);
  EXPECT_NE(unchecked.find("- 2²: paper – — ours – — not checked (fewer than two rows have a paper value)\n"),
            std::string::npos)
      << unchecked;
}

// A table of our own (ompl-navigation: no paper numbers) prints no paper table of N/A, no
// "paper / ours" comparisons and no orderings of the paper's (there is none to test).
TEST(SweepReport, WithoutPaperNumbersThePapersSideIsLeftOut) {
  PaperTable t;
  t.id = "ours-only";
  t.rows = {{"RRT", "rrt", {}, {}}, {"HyDICE", "hydice", {}, {}}};
  TableSweep sw;
  sw.columns = {{"2²", {{"n", "2"}}}, {"4²", {{"n", "4"}}}};
  sw.paper = {{{kNotReported, kNotReported}, {kNotReported, kNotReported}}};
  sw.paper_timeout_s = 150;
  t.sweep = sw;
  using Cells = std::vector<std::vector<std::vector<std::vector<TrialRecord>>>>;
  Cells trials(1, std::vector<std::vector<std::vector<TrialRecord>>>(2, std::vector<std::vector<TrialRecord>>(2)));
  trials[0][0][0] = {trial(10, 1.0), trial(10, 3.0)};
  trials[0][1][0] = {trial(10, 0.5), trial(10, 1.5)};
  trials[0][0][1] = {trial(10, 20.0, TrialStatus::timeout), trial(10, 20.0, TrialStatus::timeout)};
  trials[0][1][1] = {trial(10, 0.2), trial(10, 0.4)};
  ReportHeader h;
  h.profile = "quick";
  const std::string md = to_markdown(make_sweep_report(t, trials, 2), h);
  EXPECT_NE(md.find("\nours\n\n| method | 2² | 4² |\n"), std::string::npos) << md;
  EXPECT_EQ(md.find("\npaper\n"), std::string::npos) << md;
  EXPECT_EQ(md.find("N/A"), std::string::npos) << md;
  EXPECT_EQ(md.find("Paper: X"), std::string::npos) << md;
  EXPECT_NE(md.find("\nfastest per column (ours): 2² HyDICE; 4² HyDICE.\n"), std::string::npos) << md;
  EXPECT_NE(md.find("\nfirst column where every trial timed out (ours X): RRT 4²; HyDICE none; (ours only up to 4²).\n"),
            std::string::npos)
      << md;
  EXPECT_EQ(md.find("paper / ours"), std::string::npos) << md;
  EXPECT_EQ(md.find("ordering per column"), std::string::npos) << md;
  EXPECT_EQ(md.find("Summary over"), std::string::npos) << md;
  EXPECT_NE(md.find("statistics per cell"), std::string::npos) << md;
  // The CSV keeps its columns (paper empty): a reader of it finds the same fields in every table.
  EXPECT_NE(to_csv(make_sweep_report(t, trials, 2), h).find(",RRT,rrt,2²,,2,2,"), std::string::npos);
}

TEST(SweepReport, TenTrialsPerCellGiveSignificantVerdicts) {
  PaperTable t;
  t.id = "sweep";
  t.rows = {{"RRT", "rrt", {}, {}}, {"HyDICE", "hydice", {}, {}}};
  TableSweep sw;
  sw.columns = {{"2²", {{"n", "2"}}}};
  sw.paper = {{{kPaperTimeout}, {0.4}}};  // paper: HyDICE 0.4 s < RRT X
  sw.paper_timeout_s = 3600;
  t.sweep = sw;
  using Cells = std::vector<std::vector<std::vector<std::vector<TrialRecord>>>>;
  Cells trials(1, std::vector<std::vector<std::vector<TrialRecord>>>(2, std::vector<std::vector<TrialRecord>>(1)));
  for (int i = 0; i < 10; ++i) {
    trials[0][0][0].push_back(trial(10, 2.0, TrialStatus::timeout));  // RRT: X at our 2 s cap
    trials[0][1][0].push_back(trial(10, 0.1 * (i + 1)));              // HyDICE: 0.1 .. 1.0 s
  }
  const SweepReport r = make_sweep_report(t, trials, 1);
  ASSERT_EQ(r.orderings[0].size(), 1u);
  EXPECT_EQ(r.orderings[0][0].verdict, OrderingVerdict::holds);
  // Swap the paper's values: ours now reverse the claim.
  t.sweep->paper = {{{0.4}, {kPaperTimeout}}};
  EXPECT_EQ(make_sweep_report(t, trials, 1).orderings[0][0].verdict, OrderingVerdict::reversed);
}

}  // namespace
// A profile that runs some columns (the paper profile's columns by label) and skips a row's
// columns after its first all-stopped one.
TEST(SweepReport, ShowsOnlyTheColumnsRunAndMarksSkippedCells) {
  PaperTable t;
  t.id = "sweep";
  t.rows = {{"RRT", "rrt", {}, {}}, {"HyDICE", "hydice", {}, {}}};
  TableSweep sw;
  sw.columns = {{"2²", {{"n", "2"}}}, {"4²", {{"n", "4"}}}, {"8²", {{"n", "8"}}}, {"16²", {{"n", "16"}}}};
  sw.instance_key = "property";
  sw.paper = {{{0.1, 0.3, kPaperTimeout, kPaperTimeout}, {0.4, 0.6, 1.2, 2.0}}};
  sw.paper_timeout_s = 3600;
  t.sweep = sw;
  TableProfile profile;
  profile.column_labels = {"2²", "8²", "16²"};  // not 4²
  const std::vector<bool> run = columns_run(*t.sweep, profile);
  EXPECT_EQ(run, (std::vector<bool>{true, false, true, true}));
  using Cells = std::vector<std::vector<std::vector<std::vector<TrialRecord>>>>;
  Cells trials(1, std::vector<std::vector<std::vector<TrialRecord>>>(2, std::vector<std::vector<TrialRecord>>(4)));
  trials[0][0][0] = {trial(10, 30.0, TrialStatus::timeout), trial(10, 30.0, TrialStatus::timeout)};  // RRT: X
  trials[0][1][0] = {trial(10, 0.5), trial(10, 1.5)};
  trials[0][1][2] = {trial(10, 1.0), trial(10, 2.0)};
  trials[0][1][3] = {trial(10, 3.0), trial(10, 4.0)};
  const SweepReport r = make_sweep_report(t, trials, run, true);
  EXPECT_TRUE(r.cells[0][0][0].all_stopped());
  EXPECT_FALSE(r.cells[0][0][1].run);
  EXPECT_FALSE(r.cells[0][0][1].skipped);  // not run by the profile: not a skip
  EXPECT_TRUE(r.cells[0][0][2].skipped);
  EXPECT_TRUE(r.cells[0][0][3].skipped);
  EXPECT_FALSE(r.cells[0][1][3].skipped);
  ReportHeader h;
  h.profile = "paper";
  h.skip_after_all_stopped = true;
  h.timeout_s = 60;
  h.row_timeout_s = {{"RRT", 30.0}};
  h.trials_run = 8;
  h.cpu_s = 7200;
  const std::string md = to_markdown(r, h);
  EXPECT_NE(md.find("| method | 2² | 8² | 16² |\n"), std::string::npos) << md;  // ours: the columns run
  EXPECT_NE(md.find("| method | 2² | 4² | 8² | 16² |\n"), std::string::npos) << md;  // the paper's: all
  EXPECT_NE(md.find("| RRT | X (≥30.0) [0/2] | X (skipped) | X (skipped) |"), std::string::npos) << md;
  EXPECT_NE(md.find("timeout 60 s (RRT 30 s)"), std::string::npos) << md;
  EXPECT_NE(md.find("- CPU time: 2.00 h over 8 trials"), std::string::npos) << md;
  EXPECT_NE(md.find("RRT 8² / 2²;"), std::string::npos) << md;  // first X: paper 8², ours 2²
  EXPECT_NE(md.find("(ours only in 2², 8², 16²)"), std::string::npos) << md;
  EXPECT_NE(md.find("not checked (RRT X (skipped): not run after a column where every trial reached its cap)"),
            std::string::npos)
      << md;
  const std::string csv = to_csv(r, h);
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 1 + 6);  // 2 rows x 3 run columns
  EXPECT_NE(csv.find(",RRT,rrt,8²,X,,,0,0,,0,0,"), std::string::npos) << csv;
  EXPECT_EQ(csv.find(",4²,"), std::string::npos) << csv;
}

}  // namespace hyfal
