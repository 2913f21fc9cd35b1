#include "results/statistics.hpp"

#include <boost/math/distributions/students_t.hpp>
#include <boost/math/statistics/univariate_statistics.hpp>

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
