#include "parallel/trial_wire.hpp"
#include "core/run/method_entry.hpp"

#include <stdexcept>
#include <utility>

namespace hyfal {

namespace {

Json key_to_json(const TrialKey& k) {
  return {{"experiment", k.experiment}, {"suite", k.suite},   {"instance", k.instance},
          {"method", k.method},         {"config", k.config}, {"trial_index", k.trial_index}};
}

TrialKey key_from_json(const Json& j) {
  return TrialKey{j.at("experiment").get<std::string>(), j.at("suite").get<std::string>(),
                  j.at("instance").get<std::string>(),   j.at("method").get<std::string>(),
                  j.at("config").get<std::string>(),     j.at("trial_index").get<std::int64_t>()};
}

Json parse_cbor(const std::string& bytes, const char* what) {
  Json j = Json::from_cbor(bytes, /*strict=*/true, /*allow_exceptions=*/false);
  if (j.is_discarded() || !j.is_object()) throw std::invalid_argument(std::string("malformed ") + what + " message");
  return j;
}

template <class F>
auto decoding(const char* what, F&& f) {
  try {
    return f();
  } catch (const Json::exception& e) {
    throw std::invalid_argument(std::string("malformed ") + what + " message: " + e.what());
  }
}

}  // namespace

std::string encode_job(const TrialJob& job) {
  const Json j = {{"key", key_to_json(job.key)},
                  {"options", job.method_options},
                  {"timeout_s", job.limits.timeout_s},
                  {"max_nodes", job.limits.max_nodes},
                  {"seed", job.seed},
                  {"priority", job.priority}};
  const std::vector<std::uint8_t> bytes = Json::to_cbor(j);
  return {bytes.begin(), bytes.end()};
}

TrialJob decode_job(const std::string& bytes, const SystemResolver& resolve) {
  const Json j = parse_cbor(bytes, "job");
  TrialJob job = decoding("job", [&] {
    TrialJob t;
    t.key = key_from_json(j.at("key"));
    t.method_options = j.at("options");
    t.limits.timeout_s = j.at("timeout_s").get<double>();
    t.limits.max_nodes = j.at("max_nodes").get<std::int64_t>();
    t.seed = j.at("seed").get<std::int64_t>();
    t.priority = j.at("priority").get<int>();
    return t;
  });
  job.method = find_method(job.key.method);
  if (!job.method) throw std::invalid_argument("job names method '" + job.key.method + "', which this build lacks");
  job.system = resolve(job.key.suite, job.key.instance);
  if (!job.system) throw std::invalid_argument("job names suite '" + job.key.suite + "', which this build lacks");
  return job;
}

std::string encode_result(const TrialResult& result) {
  const TrialRecord& r = result.record;
  Json series = Json::array();
  for (const auto& [name, points] : r.series) {
    Json xs = Json::array(), ys = Json::array();
    for (const auto& [x, y] : points) {
      xs.push_back(x);
      ys.push_back(y);
    }
    series.push_back({{"name", name}, {"x", std::move(xs)}, {"y", std::move(ys)}});
  }
  const Json j = {{"key", key_to_json(r.key)},
                  {"seed", r.seed},
                  {"status", std::string(to_string(r.status))},
                  {"validated", r.validated},
                  {"wall_s", r.wall_s},
                  {"cpu_s", r.cpu_s},
                  {"nodes", r.nodes},
                  {"propagations", r.propagations},
                  {"integration_steps", r.integration_steps},
                  {"witness", r.witness},
                  {"error", r.error},
                  {"threads", r.threads},
                  {"host", r.host},
                  {"git_commit", r.git_commit},
                  {"started_at", r.started_at},
                  {"finished_at", r.finished_at},
                  {"metrics", r.metrics},
                  {"series", std::move(series)},
                  {"witness_text", result.witness_text}};
  const std::vector<std::uint8_t> bytes = Json::to_cbor(j);
  return {bytes.begin(), bytes.end()};
}

TrialResult decode_result(const std::string& bytes) {
  const Json j = parse_cbor(bytes, "result");
  return decoding("result", [&] {
    TrialResult out;
    TrialRecord& r = out.record;
    r.key = key_from_json(j.at("key"));
    r.seed = j.at("seed").get<std::int64_t>();
    const auto status = parse_trial_status(j.at("status").get<std::string>());
    if (!status) throw std::invalid_argument("malformed result message: unknown status");
    r.status = *status;
    r.validated = j.at("validated").get<bool>();
    r.wall_s = j.at("wall_s").get<double>();
    r.cpu_s = j.at("cpu_s").get<double>();
    r.nodes = j.at("nodes").get<std::int64_t>();
    r.propagations = j.at("propagations").get<std::int64_t>();
    r.integration_steps = j.at("integration_steps").get<std::int64_t>();
    r.witness = j.at("witness").get<std::string>();
    r.error = j.at("error").get<std::string>();
    r.threads = j.at("threads").get<int>();
    r.host = j.at("host").get<std::string>();
    r.git_commit = j.at("git_commit").get<std::string>();
    r.started_at = j.at("started_at").get<std::string>();
    r.finished_at = j.at("finished_at").get<std::string>();
    r.metrics = j.at("metrics").get<std::string>();
    for (const Json& s : j.at("series")) {
      const Json& xs = s.at("x");
      const Json& ys = s.at("y");
      if (xs.size() != ys.size()) throw std::invalid_argument("malformed result message: series x and y differ in length");
      std::vector<std::pair<double, double>> points;
      points.reserve(xs.size());
      for (std::size_t i = 0; i < xs.size(); ++i) points.emplace_back(xs[i].get<double>(), ys[i].get<double>());
      r.series.emplace_back(s.at("name").get<std::string>(), std::move(points));
    }
    out.witness_text = j.at("witness_text").get<std::string>();
    return out;
  });
}

}  // namespace hyfal
