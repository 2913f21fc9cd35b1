// Tests of the ordering verdicts: Gehan's generalized Wilcoxon test for right-censored samples
// (results/statistics) and the per-pair verdicts of check_ordering (results/paper_report).
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "results/experiment_report.hpp"
#include "results/paper_report.hpp"
#include "results/statistics.hpp"

namespace hyfal {
namespace {

CensoredValue exact(double value) { return {value, false}; }
CensoredValue censored(double value) { return {value, true}; }

std::vector<CensoredValue> exact_range(double first, double last) {
  std::vector<CensoredValue> sample;
  for (double v = first; v <= last; v += 1.0) sample.push_back(exact(v));
  return sample;
}

// --- Gehan's statistic --------------------------------------------------------------------------

TEST(GehanTest, HandComputedExample) {
  // x = {1, 3, 5+}, y = {2, 4+, 6} ("+": censored at that value).
  // Pair scores U(x_i, y_j) (-1: x_i certainly smaller, +1: certainly larger, 0: open):
  //   1 vs 2, 4+, 6:   -1, -1 (1 <= 4), -1          -> -3
  //   3 vs 2, 4+, 6:   +1, -1 (3 <= 4), -1          -> -1
  //   5+ vs 2, 4+, 6:  +1 (2 <= 5), 0 (both censored), 0 (6 > 5: open)  -> +1
  //   W = -3 - 1 + 1 = -3.
  // Pooled scores u_k = #certainly smaller - #certainly larger among the six values:
  //   1: 0 - 5 = -5;  2: 1 - 4 = -3;  3: 2 - 3 = -1;  4+: 3 - 0 = 3;  5+: 3 - 0 = 3;  6: 3 - 0 = 3
  //   (sum 0; W = u(1) + u(3) + u(5+) = -5 - 1 + 3 = -3, as above).
  // Σ u_k² = 25 + 9 + 1 + 9 + 9 + 9 = 62; Var W = m n / (N (N - 1)) Σ u_k² = 9 / 30 · 62 = 18.6.
  // z = -3 / √18.6 = -0.695608; normal p = 2 Φ(-0.695608) = 0.486674.
  // Exact permutation p: the C(6, 3) = 20 choices of three of the scores {-5, -3, -1, 3, 3, 3}
  // sum to -9 (once), -5, -3, -1, 1, 3, 5 (three times each) and 9 (once); |sum| >= 3 in
  // 1 + 3 + 3 + 3 + 3 + 1 = 14 of them, so p = 14 / 20 = 0.7.
  const std::vector<CensoredValue> x{exact(1), exact(3), censored(5)};
  const std::vector<CensoredValue> y{exact(2), censored(4), exact(6)};
  const GehanTest test = gehan_test(x, y);
  EXPECT_EQ(test.n_x, 3u);
  EXPECT_EQ(test.n_y, 3u);
  EXPECT_DOUBLE_EQ(test.statistic, -3.0);
  EXPECT_NEAR(test.variance, 18.6, 1e-12);
  EXPECT_NEAR(test.z, -0.6956083436, 1e-9);
  EXPECT_NEAR(test.normal_p_value, 0.4866741395, 1e-9);
  EXPECT_TRUE(test.p_exact);
  EXPECT_DOUBLE_EQ(test.p_value, 0.7);
  // Swapping the samples flips the sign only.
  const GehanTest swapped = gehan_test(y, x);
  EXPECT_DOUBLE_EQ(swapped.statistic, 3.0);
  EXPECT_NEAR(swapped.variance, 18.6, 1e-12);
  EXPECT_NEAR(swapped.normal_p_value, test.normal_p_value, 1e-12);
  EXPECT_DOUBLE_EQ(swapped.p_value, 0.7);
}

TEST(GehanTest, ThreeAgainstThreeTotallySeparatedIsWithinNoise) {
  // x = 1, 2, 3 below y = 4, 5, 6: W = -9, u = -5, -3, -1, 1, 3, 5, Var W = 9 / 30 · 70 = 21,
  // z = -1.964, normal p = 0.0495 < 0.05. But only 2 of the C(6, 3) = 20 splits are as extreme
  // ({1, 2, 3} and {4, 5, 6} as x): the exact p is 2 / 20 = 0.1, and 3 trials a side cannot show
  // a difference at α = 0.05.
  const std::vector<CensoredValue> x = exact_range(1, 3), y = exact_range(4, 6);
  const SampleComparison comparison = compare_samples(x, y);
  EXPECT_DOUBLE_EQ(comparison.test.statistic, -9.0);
  EXPECT_NEAR(comparison.test.variance, 21.0, 1e-12);
  EXPECT_NEAR(comparison.test.normal_p_value, 0.0495, 1e-4);
  EXPECT_LT(comparison.test.normal_p_value, kSignificanceLevel);
  EXPECT_TRUE(comparison.test.p_exact);
  EXPECT_DOUBLE_EQ(comparison.test.p_value, 0.1);
  EXPECT_EQ(comparison.order, SampleOrder::within_noise);
  EXPECT_EQ(compare_samples(y, x).order, SampleOrder::within_noise);
}

// The exact p-value against brute force: every split of the pooled sample into m and n values,
// each one's W by gehan_test itself, on random small samples with ties (values 1..4) and about a
// third censored.
TEST(GehanTest, ExactPValueMatchesEnumerationOfEverySplit) {
  std::mt19937 random(20261202u);
  for (int round = 0; round < 40; ++round) {
    const std::size_t m = 1 + random() % 6, n = 1 + random() % 6;
    std::vector<CensoredValue> pooled;
    for (std::size_t k = 0; k < m + n; ++k)
      pooled.push_back({static_cast<double>(1 + random() % 4), random() % 3 == 0});
    const std::vector<CensoredValue> x(pooled.begin(), pooled.begin() + static_cast<std::ptrdiff_t>(m));
    const std::vector<CensoredValue> y(pooled.begin() + static_cast<std::ptrdiff_t>(m), pooled.end());
    const GehanTest test = gehan_test(x, y);

    int splits = 0, as_extreme = 0;
    for (unsigned mask = 0; mask < (1u << pooled.size()); ++mask) {
      if (static_cast<std::size_t>(__builtin_popcount(mask)) != m) continue;
      std::vector<CensoredValue> first, second;
      for (std::size_t k = 0; k < pooled.size(); ++k) ((mask >> k) & 1u ? first : second).push_back(pooled[k]);
      // W is an integer: compare with a margin instead of relying on exact floating equality.
      if (std::abs(gehan_test(first, second).statistic) >= std::abs(test.statistic) - 0.5) ++as_extreme;
      ++splits;
    }
    ASSERT_TRUE(test.p_exact) << "round " << round;
    EXPECT_NEAR(test.p_value, static_cast<double>(as_extreme) / splits, 1e-12)
        << "round " << round << ", m = " << m << ", n = " << n << ", W = " << test.statistic;
  }
}

TEST(GehanTest, LargeSamplesAreExactAndFastUpToTheBound) {
  // 40 against 40, totally separated: the exact p is 2 / C(80, 40) = 1.8603e-23 (the DP counts
  // beyond 2^64 in long double, so agree to a relative 1e-12, not exactly).
  const auto start = std::chrono::steady_clock::now();
  const GehanTest separated = gehan_test(exact_range(1, 40), exact_range(41, 80));
  EXPECT_TRUE(separated.p_exact);
  const double two_over_c_80_40 = 2.0 / 107507208733336176461620.0;
  EXPECT_NEAR(separated.p_value / two_over_c_80_40, 1.0, 1e-12);
  // 40 against 40, overlapping, with ties and censoring: exact, and near the normal
  // approximation, which is good at this size.
  std::vector<CensoredValue> x, y;
  for (int k = 0; k < 40; ++k) {
    x.push_back({static_cast<double>(k % 25), k % 7 == 0});
    y.push_back({static_cast<double>(3 + k % 25), k % 5 == 0});
  }
  const GehanTest overlapping = gehan_test(x, y);
  EXPECT_TRUE(overlapping.p_exact);
  EXPECT_GT(overlapping.p_value, 0.0);
  EXPECT_LT(overlapping.p_value, 1.0);
  EXPECT_NEAR(overlapping.p_value, overlapping.normal_p_value, 0.01);
  // The worst case within the documented bound: 50 against 50 distinct values (Σ |u_k| = N² / 2).
  const GehanTest worst = gehan_test(exact_range(1, 50), exact_range(26, 75));
  EXPECT_TRUE(worst.p_exact);
  EXPECT_NEAR(worst.p_value, worst.normal_p_value, 0.01);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_LT(seconds, 5.0);  // tens of milliseconds in a release build; generous for sanitizers
}

TEST(GehanTest, BeyondTheBoundTheNormalApproximationIsUsed) {
  const GehanTest large = gehan_test(exact_range(1, 150), exact_range(101, 250));
  EXPECT_FALSE(large.p_exact);
  EXPECT_DOUBLE_EQ(large.p_value, large.normal_p_value);
  EXPECT_LT(large.p_value, 1e-3);
  // The DP itself: declines beyond the work limit, counts below it.
  const std::vector<int> scores{-5, -3, -1, 1, 3, 5};
  EXPECT_FALSE(exact_gehan_p_value(scores, 3, -9, /*work_limit=*/10.0).has_value());
  EXPECT_DOUBLE_EQ(exact_gehan_p_value(scores, 3, -9).value(), 0.1);
  EXPECT_DOUBLE_EQ(exact_gehan_p_value(scores, 3, 1).value(), 1.0);
  EXPECT_DOUBLE_EQ(exact_gehan_p_value(scores, 0, 0).value(), 1.0);
}

TEST(GehanTest, CensoredPairsFollowGehansScoring) {
  // x exact, y censored at c: x certainly smaller iff x <= c.
  EXPECT_DOUBLE_EQ(gehan_test(std::vector{exact(5)}, std::vector{censored(5)}).statistic, -1.0);
  EXPECT_DOUBLE_EQ(gehan_test(std::vector{exact(4)}, std::vector{censored(5)}).statistic, -1.0);
  EXPECT_DOUBLE_EQ(gehan_test(std::vector{exact(6)}, std::vector{censored(5)}).statistic, 0.0);
  // x censored at c, y exact: x certainly larger iff y <= c.
  EXPECT_DOUBLE_EQ(gehan_test(std::vector{censored(5)}, std::vector{exact(5)}).statistic, 1.0);
  EXPECT_DOUBLE_EQ(gehan_test(std::vector{censored(5)}, std::vector{exact(7)}).statistic, 0.0);
  // Both censored: open, whatever the values; exact ties: 0.
  EXPECT_DOUBLE_EQ(gehan_test(std::vector{censored(3)}, std::vector{censored(9)}).statistic, 0.0);
  EXPECT_DOUBLE_EQ(gehan_test(std::vector{exact(3)}, std::vector{exact(3)}).statistic, 0.0);
  EXPECT_DOUBLE_EQ(gehan_test(std::vector{exact(3)}, std::vector{exact(9)}).statistic, -1.0);
}

// The variance is the exact permutation variance of W: enumerate every split of the pooled
// sample into m and n values (C(8, 4) = 70 here) and compare, with ties and censoring present.
TEST(GehanTest, VarianceIsThePermutationVariance) {
  const std::vector<CensoredValue> x{exact(1), exact(2), censored(2), exact(4)};
  const std::vector<CensoredValue> y{exact(2), censored(3), exact(5), censored(5)};
  std::vector<CensoredValue> pooled(x);
  pooled.insert(pooled.end(), y.begin(), y.end());
  double sum = 0.0, sum_of_squares = 0.0;
  int splits = 0;
  for (unsigned mask = 0; mask < (1u << pooled.size()); ++mask) {
    if (__builtin_popcount(mask) != 4) continue;
    std::vector<CensoredValue> first, second;
    for (std::size_t k = 0; k < pooled.size(); ++k) ((mask >> k) & 1u ? first : second).push_back(pooled[k]);
    const double w = gehan_test(first, second).statistic;
    sum += w;
    sum_of_squares += w * w;
    ++splits;
  }
  ASSERT_EQ(splits, 70);
  EXPECT_NEAR(sum / splits, 0.0, 1e-12);  // E W = 0 under the permutation null
  const double permutation_variance = sum_of_squares / splits;
  EXPECT_GT(permutation_variance, 0.0);
  EXPECT_NEAR(gehan_test(x, y).variance, permutation_variance, 1e-9);
}

TEST(GehanTest, AllCensoredHasNoEvidence) {
  const std::vector<CensoredValue> x(5, censored(10.0));
  const std::vector<CensoredValue> y{censored(10.0), censored(10.2), censored(9.9), censored(10.1), censored(10.0)};
  const GehanTest test = gehan_test(x, y);
  EXPECT_DOUBLE_EQ(test.statistic, 0.0);
  EXPECT_DOUBLE_EQ(test.variance, 0.0);
  EXPECT_DOUBLE_EQ(test.p_value, 1.0);
  EXPECT_EQ(compare_samples(x, y).order, SampleOrder::within_noise);
}

// --- verdicts of two samples --------------------------------------------------------------------

TEST(CompareSamples, IdenticalSamplesAreWithinNoise) {
  const std::vector<CensoredValue> sample = exact_range(1, 10);
  const SampleComparison comparison = compare_samples(sample, sample);
  EXPECT_EQ(comparison.order, SampleOrder::within_noise);
  EXPECT_DOUBLE_EQ(comparison.test.statistic, 0.0);
  EXPECT_DOUBLE_EQ(comparison.test.p_value, 1.0);
}

TEST(CompareSamples, SeparatedSamplesOfTenAreSignificant) {
  // x = 1..10, y = 11..20: W = -100; no ties, so u_k = 2k - 21 and Σ u_k² = 2660,
  // Var W = 100 / 380 · 2660 = 700, z = -100 / √700 = -3.78, p = 1.6e-4.
  const std::vector<CensoredValue> x = exact_range(1, 10), y = exact_range(11, 20);
  const SampleComparison comparison = compare_samples(x, y);
  EXPECT_EQ(comparison.order, SampleOrder::x_smaller);
  EXPECT_DOUBLE_EQ(comparison.test.statistic, -100.0);
  EXPECT_NEAR(comparison.test.variance, 700.0, 1e-9);
  EXPECT_LT(comparison.test.p_value, 1e-3);
  EXPECT_EQ(compare_samples(y, x).order, SampleOrder::y_smaller);
}

TEST(CompareSamples, OverlappingSamplesAreWithinNoise) {
  // x = 1..10 and y = 2..11 overlap in nine values: of the 100 pairs 55 have x < y, 36 x > y
  // and 9 tie, so W = 36 - 55 = -19, z ≈ -0.72: far from significant.
  const SampleComparison comparison = compare_samples(exact_range(1, 10), exact_range(2, 11));
  EXPECT_EQ(comparison.order, SampleOrder::within_noise);
  EXPECT_DOUBLE_EQ(comparison.test.statistic, -19.0);
  EXPECT_GT(comparison.test.p_value, 0.4);
}

TEST(CompareSamples, TimeoutsRankLast) {
  // Ten trials that finished within the 10 s cap against ten that all timed out at it: the
  // timeouts are certainly slower, although their recorded times are no larger.
  const std::vector<CensoredValue> finished = exact_range(1, 10);
  const std::vector<CensoredValue> timed_out(10, censored(10.0));
  EXPECT_EQ(compare_samples(finished, timed_out).order, SampleOrder::x_smaller);
  EXPECT_EQ(compare_samples(timed_out, finished).order, SampleOrder::y_smaller);
  // Exact values above the censoring point: every pair is open, so nothing can be said.
  const std::vector<CensoredValue> slower = exact_range(11, 20);
  const SampleComparison open = compare_samples(slower, timed_out);
  EXPECT_DOUBLE_EQ(open.test.statistic, 0.0);
  EXPECT_EQ(open.order, SampleOrder::within_noise);
}

TEST(CompareSamples, FewerThanTwoValuesAreTooFewTrials) {
  EXPECT_EQ(compare_samples(std::vector{exact(1)}, exact_range(11, 20)).order, SampleOrder::too_few_trials);
  EXPECT_EQ(compare_samples(exact_range(11, 20), std::vector<CensoredValue>{}).order, SampleOrder::too_few_trials);
  EXPECT_EQ(compare_samples(std::vector{exact(1)}, std::vector{exact(2)}).order, SampleOrder::too_few_trials);
}

TEST(CensoredSample, StoppedTrialsAreCensoredAndErrorsLeftOut) {
  std::vector<TrialRecord> trials(5);
  const TrialStatus statuses[] = {TrialStatus::falsified, TrialStatus::timeout, TrialStatus::node_cap,
                                  TrialStatus::not_found, TrialStatus::error};
  for (std::size_t i = 0; i < trials.size(); ++i) {
    trials[i].status = statuses[i];
    trials[i].wall_s = 1.5 + static_cast<double>(i);
    trials[i].nodes = 100 + static_cast<std::int64_t>(i);
  }
  EXPECT_EQ(censored_sample(trials, TrialMeasure::wall_s),
            (std::vector<CensoredValue>{exact(1.5), censored(2.5), censored(3.5), exact(4.5)}));
  EXPECT_EQ(censored_sample(trials, TrialMeasure::nodes),
            (std::vector<CensoredValue>{exact(100), censored(101), censored(102), exact(103)}));
}

// --- verdicts of a table column -------------------------------------------------------------------

TEST(CheckOrdering, HoldsReversedWithinNoiseAndTooFew) {
  const auto fast = exact_range(1, 10), slow = exact_range(11, 20), alike = exact_range(2, 11);
  // Paper: row 0 < row 1.
  const OrderingCheck holds = check_ordering({1.0, 2.0}, {5.5, 15.5}, {fast, slow});
  ASSERT_EQ(holds.pairs.size(), 1u);
  EXPECT_EQ(holds.pairs[0].first, 0u);
  EXPECT_EQ(holds.pairs[0].second, 1u);
  EXPECT_EQ(holds.pairs[0].verdict, OrderingVerdict::holds);
  EXPECT_EQ(holds.verdict, OrderingVerdict::holds);

  const OrderingCheck reversed = check_ordering({1.0, 2.0}, {15.5, 5.5}, {slow, fast});
  EXPECT_EQ(reversed.pairs[0].verdict, OrderingVerdict::reversed);
  EXPECT_EQ(reversed.verdict, OrderingVerdict::reversed);
  EXPECT_EQ(reversed.ours_order, (std::vector<std::size_t>{1, 0}));
  EXPECT_EQ(reversed.ours_tied_with_previous, (std::vector<bool>{false, false}));

  // Ours swapped by a little, within noise: not a failure any more.
  const OrderingCheck noise = check_ordering({1.0, 2.0}, {6.5, 5.5}, {alike, fast});
  EXPECT_EQ(noise.pairs[0].verdict, OrderingVerdict::within_noise);
  EXPECT_EQ(noise.verdict, OrderingVerdict::within_noise);
  EXPECT_EQ(noise.ours_tied_with_previous, (std::vector<bool>{false, true}));

  const OrderingCheck few = check_ordering({1.0, 2.0}, {1.0, 15.5}, {{exact(1)}, slow});
  EXPECT_EQ(few.pairs[0].verdict, OrderingVerdict::too_few_trials);
  EXPECT_EQ(few.verdict, OrderingVerdict::too_few_trials);
}

TEST(CheckOrdering, PaperTiesHoldWithinNoiseAndDifferOtherwise) {
  const auto fast = exact_range(1, 10), slow = exact_range(11, 20);
  const OrderingCheck tie = check_ordering({3.0, 3.0}, {5.5, 5.5}, {fast, fast});
  ASSERT_EQ(tie.pairs.size(), 1u);
  EXPECT_TRUE(tie.pairs[0].paper_tied);
  EXPECT_EQ(tie.pairs[0].verdict, OrderingVerdict::holds);
  const OrderingCheck differs = check_ordering({3.0, 3.0}, {5.5, 15.5}, {fast, slow});
  EXPECT_EQ(differs.pairs[0].verdict, OrderingVerdict::differs);
  EXPECT_EQ(differs.verdict, OrderingVerdict::differs);
}

TEST(CheckOrdering, AdjacentPairsOfThePapersOrderAndTheirCounts) {
  const auto a = exact_range(1, 10), b = exact_range(11, 20), c = exact_range(12, 21);
  // Paper order: row 2 < row 0 < row 1 (values 1, 2, 3); ours a < b ≈ c for rows 2, 0, 1.
  const OrderingCheck check = check_ordering({2.0, 3.0, 1.0}, {15.5, 16.5, 5.5}, {b, c, a}, 7);
  EXPECT_EQ(check.column, 7u);
  EXPECT_EQ(check.paper_order, (std::vector<std::size_t>{2, 0, 1}));
  ASSERT_EQ(check.pairs.size(), 2u);
  EXPECT_EQ(check.pairs[0].first, 2u);
  EXPECT_EQ(check.pairs[0].second, 0u);
  EXPECT_EQ(check.pairs[0].verdict, OrderingVerdict::holds);
  EXPECT_EQ(check.pairs[1].verdict, OrderingVerdict::within_noise);
  EXPECT_EQ(check.verdict, OrderingVerdict::within_noise);
  EXPECT_EQ(check.count(OrderingVerdict::holds), 1u);
  EXPECT_EQ(check.count(OrderingVerdict::within_noise), 1u);
  EXPECT_EQ(check.count(OrderingVerdict::reversed), 0u);
  EXPECT_EQ(check.pair_ending_at(0), &check.pairs[0]);
  EXPECT_EQ(check.pair_ending_at(2), nullptr);  // the first of the paper's order

  const std::vector<std::string> labels{"B", "C", "A"};
  const std::string text = pairs_text(check, labels);
  EXPECT_EQ(text.substr(0, text.find(';')), "A < B: holds (p < 0.001)") << text;
  EXPECT_NE(text.find("; B < C: within noise (p = 0."), std::string::npos) << text;
  EXPECT_EQ(verdict_counts_text({&check}), "1 hold, 1 within noise, 0 reversed");

  const OrderingCheck few = check_ordering({1.0, 2.0}, {1.0, 2.0}, {{exact(1)}, {exact(2)}});
  EXPECT_EQ(pairs_text(few, {"X", "Y"}), "X < Y: too few trials (n = 1, 1)");
  EXPECT_EQ(verdict_counts_text({&check, &few}), "1 hold, 1 within noise, 0 reversed, 1 too few trials");
}

TEST(CheckOrdering, MissingValuesAreNotChecked) {
  const auto a = exact_range(1, 10);
  EXPECT_EQ(check_ordering({1.0, 2.0}, {1.0, kNotReported}, {a, {}}).verdict, OrderingVerdict::not_checked);
  EXPECT_EQ(check_ordering({1.0}, {1.0}, {a}).verdict, OrderingVerdict::not_checked);
  // A row the paper does not report is left out of the pairs.
  const OrderingCheck skipped = check_ordering({1.0, kNotReported, 2.0}, {5.5, 99.0, 15.5}, {a, a, exact_range(11, 20)});
  ASSERT_EQ(skipped.pairs.size(), 1u);
  EXPECT_EQ(skipped.pairs[0].second, 2u);
  EXPECT_EQ(skipped.verdict, OrderingVerdict::holds);
}

// --- experiments: each row against the baseline row ------------------------------------------

TrialRecord trial_of(TrialStatus status, double wall_s, std::int64_t nodes) {
  TrialRecord t;
  t.status = status;
  t.wall_s = wall_s;
  t.nodes = nodes;
  return t;
}

// On 0/1 samples compare_samples is Fisher's exact test: the hypergeometric probabilities of the
// tables at least as far from the expected count, counted by hand.
TEST(FalsifiedRate, IsFishersExactTest) {
  const auto trials = [](int falsified, int stopped) {
    std::vector<TrialRecord> v;
    for (int k = 0; k < falsified; ++k) v.push_back(trial_of(TrialStatus::falsified, 1.0, 10));
    for (int k = 0; k < stopped; ++k) v.push_back(trial_of(TrialStatus::timeout, 5.0, 10));
    return v;
  };
  // 5 of 5 against 0 of 5: K = 5 of the 5 ones in the first 5 of 10; P(K = 5) = P(K = 0) = 1 / C(10, 5).
  const SampleComparison all = compare_samples(falsified_indicators(trials(5, 0)), falsified_indicators(trials(0, 5)));
  EXPECT_TRUE(all.test.p_exact);
  EXPECT_NEAR(all.test.p_value, 2.0 / 252.0, 1e-12);
  EXPECT_EQ(all.order, SampleOrder::y_smaller);  // the first rate is higher
  // 4 of 5 against 1 of 5: |K - 2.5| >= 1.5 for K = 0, 1, 4, 5: (1 + 25 + 25 + 1) / 252.
  const SampleComparison some = compare_samples(falsified_indicators(trials(4, 1)), falsified_indicators(trials(1, 4)));
  EXPECT_NEAR(some.test.p_value, 52.0 / 252.0, 1e-12);
  EXPECT_EQ(some.order, SampleOrder::within_noise);
  // Errors count as not falsified, as in the rate.
  EXPECT_EQ(falsified_indicators(std::vector<TrialRecord>{trial_of(TrialStatus::error, 0, 0)}),
            (std::vector<CensoredValue>{{0.0, false}}));
}

TEST(ExperimentVerdicts, EachRowAgainstTheBaselineInItsColumn) {
  std::vector<TrialRecord> fast, slow, stopped;
  for (int k = 0; k < 10; ++k) {
    fast.push_back(trial_of(TrialStatus::falsified, 0.1 * (k + 1), 100 + k));
    slow.push_back(trial_of(TrialStatus::falsified, 5.0 + k, 5000 + k));
    stopped.push_back(trial_of(TrialStatus::timeout, 2.0, 3000));  // every trial at the 2 s cap
  }
  const std::vector<std::vector<TrialRecord>> trials{slow, fast, stopped, fast, {fast[0]}};
  const std::vector<GroupPlace> places{{"", "base", "c1"}, {"", "new", "c1"}, {"", "capped", "c1"},
                                       {"", "new", "c2"},  // no baseline group in c2: left out
                                       {"", "base", "c3"}};
  const ExperimentVerdicts v = compare_with_baseline(trials, places, "base");
  ASSERT_EQ(v.comparisons.size(), 2u);
  EXPECT_EQ(v.comparisons[0].group, 1u);
  EXPECT_EQ(v.comparisons[0].baseline, 0u);
  EXPECT_EQ(v.comparisons[0].time.order, SampleOrder::x_smaller);
  EXPECT_EQ(v.comparisons[0].nodes.order, SampleOrder::x_smaller);
  EXPECT_EQ(v.comparisons[0].falsified.order, SampleOrder::within_noise);
  // Stopped at 2 s, below every baseline time (5 s and more): censored, so no faster nor slower
  // can be told from times, but fewer nodes than the baseline's cannot either (3000 censored < 5000).
  EXPECT_EQ(v.comparisons[1].time.order, SampleOrder::within_noise);
  EXPECT_EQ(v.comparisons[1].falsified.order, SampleOrder::x_smaller);  // 0 of 10 against 10 of 10: lower
  EXPECT_EQ(verdict_text(ComparedMeasure::time, v.comparisons[0].time), "faster (p < 0.001)");
  EXPECT_EQ(verdict_text(ComparedMeasure::falsified, v.comparisons[1].falsified), "lower (p < 0.001)");
  EXPECT_EQ(verdict_word(ComparedMeasure::nodes, SampleOrder::y_smaller), "more");
  const std::string md = to_markdown(v, places);
  EXPECT_NE(md.find("## Verdicts against base\n\n| row | column | time | nodes | falsified rate |\n"), std::string::npos)
      << md;
  EXPECT_NE(md.find("| new | c1 | faster (p < 0.001) | fewer (p < 0.001) | within noise (p = 1.0) |\n"),
            std::string::npos)
      << md;
  const auto fields = verdict_csv_fields(v, places.size());
  EXPECT_EQ(fields[0], std::vector<std::string>(7));  // the baseline's own group
  EXPECT_EQ(fields[1][0], "base");
  EXPECT_EQ(fields[1][1], "faster");
  EXPECT_EQ(fields[3], std::vector<std::string>(7));  // no baseline in its column
}

}  // namespace
}  // namespace hyfal
