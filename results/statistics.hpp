// Summaries of trial samples, the numbers the report tables print, and the two-sample test the
// tables' ordering verdicts rest on (Gehan's generalized Wilcoxon test for right-censored data).
#pragma once
#include <cstddef>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/run/trial_record.hpp"

namespace hyfal {

// Mean, median, sample standard deviation (n - 1) and the two-sided 95 % confidence interval
// of the mean, mean ± t(0.975, n - 1) · stddev / √n. Every field but n is NaN for n == 0;
// stddev, ci_low and ci_high are NaN for n == 1.
struct SampleSummary {
  std::size_t n = 0;
  double mean = std::numeric_limits<double>::quiet_NaN();
  double median = std::numeric_limits<double>::quiet_NaN();
  double stddev = std::numeric_limits<double>::quiet_NaN();
  double ci_low = std::numeric_limits<double>::quiet_NaN();
  double ci_high = std::numeric_limits<double>::quiet_NaN();
};

SampleSummary summarize(std::span<const double> sample);

// The trials of one (suite, instance, method, config). n counts every trial; the status counts
// add up to n. falsified_rate = falsified / n, so errors count as not falsified.
// wall_s and nodes summarize every trial except errors: a timed-out or node-capped trial
// contributes the time and nodes it had when it was stopped, a lower bound of the true value
// (right-censored), which is why the table writers mark such groups.
struct GroupSummary {
  std::string suite;
  std::string instance;
  std::string method;
  std::string config;
  std::size_t n = 0;
  std::size_t falsified = 0;
  std::size_t validated = 0;
  std::size_t timeouts = 0;
  std::size_t node_caps = 0;
  std::size_t budgets = 0;  // stopped by the method's budget (TrialStatus::budget)
  std::size_t not_found = 0;
  std::size_t errors = 0;
  double falsified_rate = 0.0;
  SampleSummary wall_s;
  SampleSummary nodes;
  // STL requirements (a trial's metrics "robustness" and "simulations", parallel/trial_engine.cpp;
  // n = 0 without): the robustness of every trial but errors (a falsified one's witness's, else
  // the best upper bound found), and the simulation-equivalents of the falsified trials (what
  // ARCH-COMP reports: simulations of the successful runs).
  SampleSummary robustness;
  SampleSummary simulations;
  bool has_requirement_data() const { return robustness.n > 0 || simulations.n > 0; }
};

// Whether a trial's time and nodes are right-censored: the trial was stopped by the time limit,
// the node cap or the method's budget, so the values it recorded are lower bounds of what the method needs. Errors carry
// no value at all (they are left out of every sample); a gave-up search (not_found) ended on its
// own, so its values are exact.
constexpr bool is_right_censored(TrialStatus status) {
  return status == TrialStatus::timeout || status == TrialStatus::node_cap || status == TrialStatus::budget;
}

// One value of a sample. censored: the true value is larger than `value` (right-censored at it).
struct CensoredValue {
  double value = 0.0;
  bool censored = false;
  friend bool operator==(const CensoredValue&, const CensoredValue&) = default;
};

enum class TrialMeasure { wall_s, nodes };

// The wall times or node counts of `trials`, errors left out, stopped trials censored at the value
// they had when stopped (is_right_censored), in trial order.
std::vector<CensoredValue> censored_sample(std::span<const TrialRecord> trials, TrialMeasure measure);

// Whether each trial falsified, as the exact values 1 (falsified) or 0 (errors count as not
// falsified, as in GroupSummary::falsified_rate), in trial order: the sample the tables' tests of
// a falsified rate compare. On such 0/1 samples compare_samples is Fisher's exact test: Gehan's
// scores of 0/1 values make W = K N - m O (K: the ones among the first sample's m, O: all ones, N:
// all trials), linear in K, so the exact permutation p-value is P(|K' - m O / N| >= |K - m O / N|)
// under the hypergeometric distribution of K' (the two-sided Fisher test whose tables are at
// least as far from the expected count as the one observed).
std::vector<CensoredValue> falsified_indicators(std::span<const TrialRecord> trials);

// Gehan's generalized Wilcoxon test of two right-censored samples (Gehan 1965, "A generalized
// Wilcoxon test for comparing arbitrarily singly-censored samples", Biometrika 52: 203-223),
// with the permutation variance of Mantel's scores (Mantel 1967, "Ranking procedures for
// arbitrarily restricted observation", Biometrics 23: 65-78).
//
// Every pair (x_i, y_j) scores U_ij = -1 if x_i is certainly smaller than y_j, +1 if certainly
// larger, 0 if the order cannot be told (a tie of exact values, two censored values, or an exact
// value above a censored one). "Certainly smaller": x_i exact and either y_j exact with
// x_i < y_j, or y_j censored at c with x_i <= c. The statistic is W = Σ_i Σ_j U_ij. Under the
// null hypothesis (both samples from one distribution, censoring alike) every split of the
// pooled sample into groups of m and n is equally likely; with the score of each pooled value,
// u_k = #{pooled values certainly smaller} - #{certainly larger}, W = Σ_{k in x} u_k, and its
// permutation variance is Var W = m n / (N (N - 1)) · Σ_k u_k², N = m + n (Σ_k u_k = 0).
// z = W / √Var W. Var W = 0 (every pair undecided, e.g. all values censored) gives z = 0, p = 1.
//
// The two-sided p-value is P(|W'| >= |W|) under that permutation null, W' the statistic of a
// split drawn uniformly from all C(N, m). Gehan (1965) derives the test from exactly this
// permutation distribution and uses its normal limit for large samples; at the tables' small
// sample sizes the normal limit is anti-conservative (3 vs 3 totally separated: normal
// p = 0.0495, exact p = 2/20 = 0.1), so where it is affordable the p-value is the exact
// permutation probability (exact_gehan_p_value below; p_exact = true), and the normal
// approximation p = 2 Φ(-|z|) otherwise (p_exact = false).
struct GehanTest {
  std::size_t n_x = 0, n_y = 0;
  double statistic = 0.0;  // W; negative: x tends to be smaller than y
  double variance = 0.0;   // permutation variance of W
  double z = 0.0;
  double normal_p_value = 1.0;  // two-sided, 2 Φ(-|z|)
  double p_value = 1.0;         // two-sided: the exact permutation p if p_exact, else normal_p_value
  bool p_exact = false;
};

// The bound on the exact computation: the dynamic programme of exact_gehan_p_value costs at most
// N · min(m, n) · (Σ_k |u_k| + 1) additions, and it runs while that bound is at most this many.
// As Σ_k |u_k| <= N² / 2 (Σ_k u_k = 0 and the positive scores sum to at most the |P| (N - |P|)
// pairs between the values P with u_k > 0 and the rest), every pair of samples with
// N = m + n <= 100 is computed exactly (at most 2.5 · 10^7 additions, tens of milliseconds), and
// larger ones while their scores allow it (ties and censoring shrink Σ_k |u_k|).
inline constexpr double kExactPermutationWorkLimit = 3.0e7;

// The exact two-sided permutation p-value P(|Σ_{k in S} u_k| >= |w|) over the C(N, m) subsets S of
// size m of the integer scores `scores` (N = scores.size()), by counting the subsets of each size
// with each sum (a knapsack-style dynamic programme over items, subset size and sum, polynomial
// instead of C(N, m)). Requires Σ_k u_k = 0 (so a subset and its complement have sums of opposite
// sign, and the smaller of m, n is counted). Empty when the work exceeds `work_limit`.
std::optional<double> exact_gehan_p_value(std::span<const int> scores, std::size_t m, int w,
                                          double work_limit = kExactPermutationWorkLimit);

GehanTest gehan_test(std::span<const CensoredValue> x, std::span<const CensoredValue> y);

// The significance level of the tables' ordering verdicts (two-sided).
inline constexpr double kSignificanceLevel = 0.05;

// Which sample tends to be smaller, by gehan_test at `alpha`: too_few_trials when either sample
// has fewer than two values (no test can tell one value from another), within_noise when the
// test does not reject at `alpha`.
enum class SampleOrder { x_smaller, y_smaller, within_noise, too_few_trials };

struct SampleComparison {
  SampleOrder order = SampleOrder::too_few_trials;
  GehanTest test;
};

SampleComparison compare_samples(std::span<const CensoredValue> x, std::span<const CensoredValue> y,
                                 double alpha = kSignificanceLevel);

// Groups trials by (suite, instance, method, config), groups in order of first appearance;
// the experiment is not part of the group, so pass one experiment's trials to keep them apart.
std::vector<GroupSummary> summarize_trials(std::span<const TrialRecord> trials);

}  // namespace hyfal
