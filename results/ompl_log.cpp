#include "results/ompl_log.hpp"

#include <algorithm>
#include <cctype>
#include <limits>
#include <map>
#include <set>
#include <tuple>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#ifndef HYFAL_VERSION
#error "HYFAL_VERSION (the project's version) must be defined"
#endif

namespace hyfal {

namespace {

using Json = nlohmann::json;

constexpr TrialStatus kStatuses[] = {TrialStatus::falsified, TrialStatus::not_found, TrialStatus::timeout,
                                     TrialStatus::node_cap, TrialStatus::budget, TrialStatus::error};

// The grammar's names and hosts are single tokens (the reader splits lines at whitespace).
std::string token(std::string s) {
  for (char& c : s)
    if (std::isspace(static_cast<unsigned char>(c))) c = '_';
  return s.empty() ? std::string("-") : s;
}

// A line of the log must stay one line (values come from stored text).
std::string one_line(std::string s) {
  for (char& c : s)
    if (c == '\n' || c == '\r') c = ' ';
  return s;
}

std::string real(double v) { return fmt::format("{}", v); }

struct Planner {
  std::string method, config;
  std::vector<const TrialRecord*> runs;
};

std::string write_log(const std::string& suite, const std::string& instance,
                      const std::vector<const TrialRecord*>& trials) {
  // Planners: (method, config) in order; a method with several configs names them apart.
  std::map<std::pair<std::string, std::string>, Planner> planners;
  std::map<std::string, std::set<std::string>> configs_of;
  for (const TrialRecord* t : trials) {
    Planner& p = planners[{t->key.method, t->key.config}];
    p.method = t->key.method;
    p.config = t->key.config;
    p.runs.push_back(t);
    configs_of[t->key.method].insert(t->key.config);
  }
  std::set<std::string> hosts, experiments;
  std::set<std::int64_t> master_seeds;
  std::string started = trials.front()->started_at;
  double time_limit = 0.0, total = 0.0;
  for (const TrialRecord* t : trials) {
    hosts.insert(t->host);
    experiments.insert(t->key.experiment);
    started = std::min(started, t->started_at);
    total += t->wall_s;
    const Json config = Json::parse(t->key.config, nullptr, false);
    if (config.is_object()) {
      if (config.contains("timeout_s") && config["timeout_s"].is_number())
        time_limit = std::max(time_limit, config["timeout_s"].get<double>());
      if (config.contains("master_seed") && config["master_seed"].is_number_integer())
        master_seeds.insert(config["master_seed"].get<std::int64_t>());
    }
  }
  std::set<std::size_t> run_counts;
  for (const auto& [key, p] : planners) run_counts.insert(p.runs.size());

  std::string out;
  auto line = [&out](const std::string& s) { out += s + "\n"; };
  line(fmt::format("hyfal version {}", HYFAL_VERSION));
  line(fmt::format("Experiment {}", token(suite + ":" + instance)));
  // Numeric instance parameters (and booleans, as 0/1) as experiment properties.
  std::vector<std::string> properties;
  const Json inst = Json::parse(instance, nullptr, false);
  if (inst.is_object())
    for (const auto& [key, value] : inst.items()) {
      const std::string name = token("instance_" + key);
      if (value.is_number_integer())
        properties.push_back(fmt::format("{} INTEGER = {}", name, value.dump()));
      else if (value.is_number())
        properties.push_back(fmt::format("{} REAL = {}", name, real(value.get<double>())));
      else if (value.is_boolean())
        properties.push_back(fmt::format("{} BOOLEAN = {}", name, value.get<bool>() ? 1 : 0));
    }
  line(fmt::format("{} experiment properties", properties.size()));
  for (const auto& p : properties) line(p);
  std::string host_list;
  for (const auto& h : hosts) host_list += (host_list.empty() ? "" : ",") + h;
  line(fmt::format("Running on {}", token(host_list)));
  line(fmt::format("Starting at {}", token(started)));
  line("<<<|");
  line(one_line("hyfal trials of suite " + suite));
  line(one_line("instance " + instance));
  std::string names;
  for (const auto& e : experiments) names += (names.empty() ? "" : ", ") + e;
  line(one_line("hyfal experiments " + names));
  line("|>>>");
  line(fmt::format("{} is the random seed", master_seeds.size() == 1 ? *master_seeds.begin() : 0));
  line(fmt::format("{} seconds per run", real(time_limit)));
  line("0 MB per run");
  if (run_counts.size() == 1) line(fmt::format("{} runs per planner", *run_counts.begin()));
  line(fmt::format("{} seconds spent to collect the data", real(total)));
  line("1 enum type");
  std::string statuses = "hyfal_status";
  for (TrialStatus s : kStatuses) {
    statuses += '|';
    statuses += to_string(s);
  }
  line(statuses);
  line(fmt::format("{} planners", planners.size()));

  static const char* const kRunProperties[] = {
      "time REAL",      "cpu time REAL",           "solved BOOLEAN",    "correct solution BOOLEAN",
      "graph states INTEGER", "propagations INTEGER", "integration steps INTEGER", "hyfal status ENUM",
      "trial index INTEGER",  "seed INTEGER"};
  for (auto& [key, p] : planners) {
    line(one_line(configs_of[p.method].size() == 1 ? p.method : p.method + " " + p.config));
    const Json config = Json::parse(p.config, nullptr, false);
    std::vector<std::string> common = {"method = " + p.method};
    if (config.is_object())
      for (const char* k : {"options", "max_nodes", "timeout_s", "master_seed"})
        if (config.contains(k)) common.push_back(fmt::format("{} = {}", k, config[k].dump()));
    line(fmt::format("{} common properties", common.size()));
    for (const auto& c : common) line(one_line(c));
    line(fmt::format("{} properties for each run", std::size(kRunProperties)));
    for (const char* prop : kRunProperties) line(prop);
    std::sort(p.runs.begin(), p.runs.end(),
              [](const TrialRecord* a, const TrialRecord* b) { return a->key.trial_index < b->key.trial_index; });
    line(fmt::format("{} runs", p.runs.size()));
    for (const TrialRecord* t : p.runs) {
      const bool solved = t->status == TrialStatus::falsified;
      const auto status_index = std::find(std::begin(kStatuses), std::end(kStatuses), t->status) - std::begin(kStatuses);
      line(fmt::format("{}; {}; {}; {}; {}; {}; {}; {}; {}; {}; ", real(t->wall_s), real(t->cpu_s), solved ? 1 : 0,
                       solved ? (t->validated ? "1" : "0") : "", t->nodes, t->propagations, t->integration_steps,
                       status_index, t->key.trial_index, t->seed));
    }
    line(".");
  }
  return out;
}

}  // namespace

std::vector<OmplLog> to_ompl_logs(std::span<const TrialRecord> trials) {
  std::map<std::pair<std::string, std::string>, std::vector<const TrialRecord*>> experiments;
  for (const TrialRecord& t : trials) experiments[{t.key.suite, t.key.instance}].push_back(&t);
  std::vector<OmplLog> logs;
  for (const auto& [key, group] : experiments) logs.push_back({key.first, key.second, write_log(key.first, key.second, group)});
  return logs;
}

}  // namespace hyfal
