#include "results/statistics.hpp"

#include <boost/math/distributions/normal.hpp>
#include <boost/math/distributions/students_t.hpp>
#include <boost/math/statistics/univariate_statistics.hpp>

#include <algorithm>
#include <cmath>
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

GehanTest gehan_test(std::span<const CensoredValue> x, std::span<const CensoredValue> y) {
  GehanTest test{.n_x = x.size(), .n_y = y.size()};
  if (x.empty() || y.empty()) return test;
  // The scores u_k of the pooled sample (Mantel 1967): O(N²), N is a table cell's trial count.
  std::vector<CensoredValue> pooled(x.begin(), x.end());
  pooled.insert(pooled.end(), y.begin(), y.end());
  double statistic = 0.0, sum_of_squares = 0.0;
  for (std::size_t k = 0; k < pooled.size(); ++k) {
    double score = 0.0;
    for (const CensoredValue& other : pooled) score += gehan_score(pooled[k], other);
    if (k < x.size()) statistic += score;  // the within-x pairs cancel: W = Σ_{k in x} u_k
    sum_of_squares += score * score;
  }
  const double m = static_cast<double>(x.size()), n = static_cast<double>(y.size());
  const double total = m + n;
  test.statistic = statistic;
  test.variance = m * n / (total * (total - 1.0)) * sum_of_squares;
  if (test.variance <= 0.0) return test;  // every pair undecided: no evidence either way
  test.z = statistic / std::sqrt(test.variance);
  const boost::math::normal standard_normal;
  test.p_value = std::min(1.0, 2.0 * boost::math::cdf(standard_normal, -std::abs(test.z)));
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

std::vector<GroupSummary> summarize_trials(std::span<const TrialRecord> trials) {
  using GroupKey = std::tuple<std::string_view, std::string_view, std::string_view,
                              std::string_view>;  // views into trials, which outlive the map
  std::map<GroupKey, std::size_t> group_index;
  std::vector<GroupSummary> groups;
  std::vector<std::vector<double>> wall_s_samples;
  std::vector<std::vector<double>> nodes_samples;

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
      case TrialStatus::error: ++group.errors; break;
    }
    // An error says nothing about how long the method needs, not even a lower bound.
    if (trial.status != TrialStatus::error) {
      wall_s_samples[index].push_back(trial.wall_s);
      nodes_samples[index].push_back(static_cast<double>(trial.nodes));
    }
  }

  for (std::size_t index = 0; index < groups.size(); ++index) {
    GroupSummary& group = groups[index];
    group.falsified_rate = static_cast<double>(group.falsified) / static_cast<double>(group.n);
    group.wall_s = summarize(wall_s_samples[index]);
    group.nodes = summarize(nodes_samples[index]);
  }
  return groups;
}

}  // namespace hyfal
