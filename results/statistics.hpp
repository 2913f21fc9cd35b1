// Summaries of trial samples: the numbers the report tables print.
#pragma once
#include <cstddef>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "core/trial_record.hpp"

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
  std::size_t not_found = 0;
  std::size_t errors = 0;
  double falsified_rate = 0.0;
  SampleSummary wall_s;
  SampleSummary nodes;
};

// Groups trials by (suite, instance, method, config), groups in order of first appearance;
// the experiment is not part of the group, so pass one experiment's trials to keep them apart.
std::vector<GroupSummary> summarize_trials(std::span<const TrialRecord> trials);

}  // namespace hyfal
