#include "results/statistics.hpp"

#include <boost/math/distributions/normal.hpp>
#include <boost/math/distributions/students_t.hpp>
#include <boost/math/statistics/univariate_statistics.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <map>
#include <string_view>
#include <tuple>
#include <utility>
#include <vector>

namespace hyfal {

SampleSummary summarize(std::span<const double> sample) {
  SampleSummary summary{.n = sample.size()};  // the statistics start as NaN
  if (sample.empty()) return summary;

  std::vector<double> values(sample.begin(), sample.end());  // median reorders its input
  summary.median = boost::math::statistics::median(values);
  if (sample.size() == 1) {
    summary.mean = sample.front();
    return summary;
  }
  const auto [mean, variance] = boost::math::statistics::mean_and_sample_variance(sample);
  summary.mean = mean;
  summary.stddev = std::sqrt(variance);
  const boost::math::students_t t_distribution(static_cast<double>(sample.size() - 1));
  const double t_975 = boost::math::quantile(t_distribution, 0.975);
  const double half_width = t_975 * summary.stddev / std::sqrt(static_cast<double>(sample.size()));
  summary.ci_low = mean - half_width;
  summary.ci_high = mean + half_width;
  return summary;
}

std::vector<CensoredValue> censored_sample(std::span<const TrialRecord> trials, TrialMeasure measure) {
  std::vector<CensoredValue> sample;
  sample.reserve(trials.size());
  for (const TrialRecord& trial : trials) {
    if (trial.status == TrialStatus::error) continue;  // no value, not even a bound
    const double value = measure == TrialMeasure::wall_s ? trial.wall_s : static_cast<double>(trial.nodes);
    sample.push_back({value, is_right_censored(trial.status)});
  }
  return sample;
}

std::vector<CensoredValue> falsified_indicators(std::span<const TrialRecord> trials) {
  std::vector<CensoredValue> sample;
  sample.reserve(trials.size());
  for (const TrialRecord& trial : trials) sample.push_back({trial.status == TrialStatus::falsified ? 1.0 : 0.0, false});
  return sample;
}

namespace {

// Gehan's score of the pair (a, b): -1 if a is certainly smaller than b, +1 if certainly
// larger, 0 if the censoring leaves the order open or the values tie (Gehan 1965, Sect. 2).
int gehan_score(const CensoredValue& a, const CensoredValue& b) {
  if (!a.censored && !b.censored) return (a.value > b.value) - (a.value < b.value);
  if (!a.censored) return a.value <= b.value ? -1 : 0;  // b > its censoring point >= a
  if (!b.censored) return b.value <= a.value ? +1 : 0;
  return 0;  // both censored: either may be the larger
}

}  // namespace

std::optional<double> exact_gehan_p_value(std::span<const int> scores, std::size_t m, int w, double work_limit) {
  const std::size_t total = scores.size();
  if (m > total) return std::nullopt;
  // Σ u = 0: the sum of the complement is minus the sum of the subset, so count the smaller side.
  const std::size_t r = std::min(m, total - m);
  long long negative_sum = 0, positive_sum = 0;  // the least and the largest sum of any subset
  for (const int u : scores) (u < 0 ? negative_sum : positive_sum) += u;
  const auto width = static_cast<std::size_t>(positive_sum - negative_sum + 1);
  const double work = static_cast<double>(total) * static_cast<double>(r) * static_cast<double>(width);
  if (work > work_limit) return std::nullopt;

  // count[j][s - negative_sum]: how many subsets of size j of the items seen so far sum to s.
  // long double: the counts reach C(100, 50) ≈ 10^29, beyond any integer type; their relative
  // rounding error stays near 10^-19 per addition, far below what a p-value needs, and counts
  // below 2^64 (every split count up to N = 67) are exact, so small cases give exact fractions.
  std::vector<std::vector<long double>> count(r + 1, std::vector<long double>(width, 0.0L));
  // [low[j], high[j]]: the sum indices row j can have reached so far (an empty row: low > high),
  // so the loops skip the zeros at the ends, where most of a row is for small j.
  std::vector<long long> low(r + 1, static_cast<long long>(width)), high(r + 1, 0);
  low[0] = high[0] = -negative_sum;
  count[0][static_cast<std::size_t>(low[0])] = 1.0L;
  std::size_t seen = 0;
  for (const int u : scores) {
    ++seen;
    // Descending j: row j - 1 still holds the subsets without this item. Sum index t without
    // the item becomes t + u with it, inside [0, width) as every subset sum lies in
    // [negative_sum, positive_sum].
    for (std::size_t j = std::min(seen, r); j >= 1; --j) {
      if (low[j - 1] > high[j - 1]) continue;
      const std::vector<long double>& without = count[j - 1];
      std::vector<long double>& with = count[j];
      for (long long t = low[j - 1]; t <= high[j - 1]; ++t)
        with[static_cast<std::size_t>(t + u)] += without[static_cast<std::size_t>(t)];
      low[j] = std::min(low[j], low[j - 1] + u);
      high[j] = std::max(high[j], high[j - 1] + u);
    }
  }
  // Integer sums: |s| >= |w| needs no floating-point tolerance.
  const long long threshold = std::llabs(static_cast<long long>(w));
  long double splits = 0.0L, as_extreme = 0.0L;
  for (std::size_t t = 0; t < width; ++t) {
    const long double c = count[r][t];
    splits += c;
    if (std::llabs(static_cast<long long>(t) + negative_sum) >= threshold) as_extreme += c;
  }
  return static_cast<double>(std::min(1.0L, as_extreme / splits));
}

GehanTest gehan_test(std::span<const CensoredValue> x, std::span<const CensoredValue> y) {
  GehanTest test{.n_x = x.size(), .n_y = y.size()};
  if (x.empty() || y.empty()) return test;
  // The scores u_k of the pooled sample (Mantel 1967): O(N²), N is a table cell's trial count.
  // They are integers (counts of pairs), so W and the exact permutation distribution are too.
  std::vector<CensoredValue> pooled(x.begin(), x.end());
  pooled.insert(pooled.end(), y.begin(), y.end());
  std::vector<int> scores(pooled.size(), 0);
  int statistic = 0;
  double sum_of_squares = 0.0;
  for (std::size_t k = 0; k < pooled.size(); ++k) {
    for (const CensoredValue& other : pooled) scores[k] += gehan_score(pooled[k], other);
    if (k < x.size()) statistic += scores[k];  // the within-x pairs cancel: W = Σ_{k in x} u_k
    sum_of_squares += static_cast<double>(scores[k]) * static_cast<double>(scores[k]);
  }
  const double m = static_cast<double>(x.size()), n = static_cast<double>(y.size());
  const double total = m + n;
  test.statistic = statistic;
  test.variance = m * n / (total * (total - 1.0)) * sum_of_squares;
  if (test.variance > 0.0) {  // else every pair is undecided: no evidence either way, p = 1
    test.z = test.statistic / std::sqrt(test.variance);
    const boost::math::normal standard_normal;
    test.normal_p_value = std::min(1.0, 2.0 * boost::math::cdf(standard_normal, -std::abs(test.z)));
  }
  // The exact permutation p-value (Gehan 1965's null distribution itself) wherever the
  // dynamic programme is affordable; the normal approximation only beyond that.
  if (const std::optional<double> exact = exact_gehan_p_value(scores, x.size(), statistic)) {
    test.p_value = *exact;
    test.p_exact = true;
  } else {
    test.p_value = test.normal_p_value;
  }
  return test;
}

SampleComparison compare_samples(std::span<const CensoredValue> x, std::span<const CensoredValue> y,
                                 double alpha) {
  SampleComparison comparison;
  comparison.test = gehan_test(x, y);
  if (x.size() < 2 || y.size() < 2) return comparison;  // order stays too_few_trials
  if (comparison.test.p_value >= alpha)
    comparison.order = SampleOrder::within_noise;
  else
    comparison.order = comparison.test.statistic < 0 ? SampleOrder::x_smaller : SampleOrder::y_smaller;
  return comparison;
}

namespace {

// A trial's STL figures from its metrics JSON, where it has them (finite numbers only).
void requirement_metrics(const TrialRecord& trial, std::vector<double>& robustness, std::vector<double>& simulations) {
  if (trial.metrics.find("robustness") == std::string::npos && trial.metrics.find("simulations") == std::string::npos)
    return;  // most tables: no JSON parse per trial
  const nlohmann::json m = nlohmann::json::parse(trial.metrics, nullptr, false);
  if (!m.is_object()) return;
  const auto number = [&](const char* key) -> std::optional<double> {
    const auto it = m.find(key);
    if (it == m.end() || !it->is_number()) return std::nullopt;
    const double v = it->get<double>();
    return std::isfinite(v) ? std::optional<double>(v) : std::nullopt;
  };
  if (const auto r = number("robustness")) robustness.push_back(*r);
  if (const auto s = number("simulations"); s && trial.status == TrialStatus::falsified) simulations.push_back(*s);
}

}  // namespace

std::vector<GroupSummary> summarize_trials(std::span<const TrialRecord> trials) {
  using GroupKey = std::tuple<std::string_view, std::string_view, std::string_view,
                              std::string_view>;  // views into trials, which outlive the map
  std::map<GroupKey, std::size_t> group_index;
  std::vector<GroupSummary> groups;
  std::vector<std::vector<double>> wall_s_samples;
  std::vector<std::vector<double>> nodes_samples;
  std::vector<std::vector<double>> robustness_samples, simulations_samples;

  for (const TrialRecord& trial : trials) {
    const TrialKey& key = trial.key;
    const auto [position, inserted] = group_index.try_emplace(
        GroupKey{key.suite, key.instance, key.method, key.config}, groups.size());
    if (inserted) {
      GroupSummary group;
      group.suite = key.suite;
      group.instance = key.instance;
      group.method = key.method;
      group.config = key.config;
      groups.push_back(std::move(group));
      wall_s_samples.emplace_back();
      nodes_samples.emplace_back();
      robustness_samples.emplace_back();
      simulations_samples.emplace_back();
    }
    const std::size_t index = position->second;
    GroupSummary& group = groups[index];
    ++group.n;
    if (trial.validated) ++group.validated;
    switch (trial.status) {
      case TrialStatus::falsified: ++group.falsified; break;
      case TrialStatus::not_found: ++group.not_found; break;
      case TrialStatus::timeout: ++group.timeouts; break;
      case TrialStatus::node_cap: ++group.node_caps; break;
      case TrialStatus::budget: ++group.budgets; break;
      case TrialStatus::error: ++group.errors; break;
    }
    // An error says nothing about how long the method needs, not even a lower bound.
    if (trial.status != TrialStatus::error) {
      wall_s_samples[index].push_back(trial.wall_s);
      nodes_samples[index].push_back(static_cast<double>(trial.nodes));
      requirement_metrics(trial, robustness_samples[index], simulations_samples[index]);
    }
  }

  for (std::size_t index = 0; index < groups.size(); ++index) {
    GroupSummary& group = groups[index];
    group.falsified_rate = static_cast<double>(group.falsified) / static_cast<double>(group.n);
    group.wall_s = summarize(wall_s_samples[index]);
    group.nodes = summarize(nodes_samples[index]);
    group.robustness = summarize(robustness_samples[index]);
    group.simulations = summarize(simulations_samples[index]);
  }
  return groups;
}

}  // namespace hyfal
