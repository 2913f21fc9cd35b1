// Jobs and results as they travel between the ranks of a distributed run (parallel/trial_wire):
// a decoded result is the record the worker computed, every double exact (NaN and infinities
// included) and the witness text byte for byte; a decoded job runs the same trial.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/run/option_spec.hpp"
#include "core/util/rng.hpp"
#include "parallel/trial_wire.hpp"
#include "suites/registry.hpp"
#include "core/run/method_entry.hpp"

namespace hyfal {
namespace {

std::shared_ptr<const System> build(const std::string& suite, const std::string& instance) {
  const SuiteEntry* s = find_suite(suite);
  return s ? s->make(Json::parse(instance)) : nullptr;
}

TrialJob thermostat_job(int index) {
  const SuiteEntry* suite = find_suite("thermostat");
  const MethodEntry* method = find_method("rrt");
  TrialJob job;
  const Json instance = resolve_options(suite->parameters, {});
  job.system = suite->make(instance);
  job.method = method;
  job.method_options = resolve_options(method->options, {{"batch", "2"}});
  job.key = {"wire", "thermostat", instance.dump(), "rrt", "{\"x\":1}", index};
  job.limits = {12.5, 123456};
  job.seed = trial_seed(7, job.key.suite, job.key.instance, job.key.method, index);
  job.priority = 3;
  return job;
}

TEST(TrialWire, AJobDecodesToTheSameTrial) {
  const TrialJob job = thermostat_job(4);
  int built = 0;
  const TrialJob back = decode_job(encode_job(job), [&](const std::string& s, const std::string& i) {
    ++built;
    return build(s, i);
  });
  EXPECT_EQ(built, 1);
  EXPECT_EQ(back.key, job.key);
  EXPECT_EQ(back.method, job.method);
  EXPECT_EQ(back.method_options, job.method_options);
  EXPECT_EQ(back.limits.timeout_s, job.limits.timeout_s);
  EXPECT_EQ(back.limits.max_nodes, job.limits.max_nodes);
  EXPECT_EQ(back.seed, job.seed);
  EXPECT_EQ(back.priority, job.priority);
  // The decoded job runs the very same trial.
  const EngineOptions options;
  const TrialResult a = compute_trial(job, options), b = compute_trial(back, options);
  EXPECT_EQ(a.record.status, b.record.status);
  EXPECT_EQ(a.record.nodes, b.record.nodes);
  EXPECT_EQ(a.record.propagations, b.record.propagations);
  EXPECT_EQ(a.witness_text, b.witness_text);
  EXPECT_FALSE(a.witness_text.empty());
}

TEST(TrialWire, AResultDecodesExactly) {
  TrialResult r;
  r.record.key = {"e", "suite", "{\"n\":2}", "m", "{}", 17};
  r.record.seed = std::numeric_limits<std::int64_t>::max();
  r.record.status = TrialStatus::timeout;
  r.record.validated = true;
  r.record.wall_s = 0.1 + 0.2;  // not a short decimal
  r.record.cpu_s = 1e-300;
  r.record.nodes = 1LL << 40;
  r.record.propagations = 3;
  r.record.integration_steps = 5;
  r.record.witness = "";
  r.record.error = "line one\nline \"two\"";
  r.record.threads = 4;
  r.record.host = "n07";
  r.record.git_commit = "abc";
  r.record.started_at = "2026-12-02T00:00:00.000Z";
  r.record.finished_at = "2026-12-02T00:00:01.000Z";
  r.record.metrics = "{\"beta\":0.25}";
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  r.record.series = {{"coverage", {{1.0, 0.1}, {2.0, nan}, {3.0, -inf}, {4.0, 1.0 / 3.0}}}, {"empty", {}}};
  r.witness_text = "{\n \"format\": \"hyfal-witness/1\"\n}\n";

  const TrialResult back = decode_result(encode_result(r));
  const TrialRecord& a = r.record;
  const TrialRecord& b = back.record;
  EXPECT_EQ(b.key, a.key);
  EXPECT_EQ(b.seed, a.seed);
  EXPECT_EQ(b.status, a.status);
  EXPECT_EQ(b.validated, a.validated);
  EXPECT_EQ(b.wall_s, a.wall_s);
  EXPECT_EQ(b.cpu_s, a.cpu_s);
  EXPECT_EQ(b.nodes, a.nodes);
  EXPECT_EQ(b.propagations, a.propagations);
  EXPECT_EQ(b.integration_steps, a.integration_steps);
  EXPECT_EQ(b.error, a.error);
  EXPECT_EQ(b.threads, a.threads);
  EXPECT_EQ(b.host, a.host);
  EXPECT_EQ(b.metrics, a.metrics);
  EXPECT_EQ(b.started_at, a.started_at);
  ASSERT_EQ(b.series.size(), 2u);
  EXPECT_EQ(b.series[0].first, "coverage");
  ASSERT_EQ(b.series[0].second.size(), 4u);
  EXPECT_EQ(b.series[0].second[0], a.series[0].second[0]);
  EXPECT_TRUE(std::isnan(b.series[0].second[1].second));
  EXPECT_EQ(b.series[0].second[2].second, -inf);
  EXPECT_EQ(b.series[0].second[3].second, 1.0 / 3.0);
  EXPECT_TRUE(b.series[1].second.empty());
  EXPECT_EQ(back.witness_text, r.witness_text);
}

TEST(TrialWire, BytesThatAreNoMessageAreRefused) {
  const auto resolve = [](const std::string& s, const std::string& i) { return build(s, i); };
  EXPECT_THROW(decode_result("not cbor"), std::invalid_argument);
  EXPECT_THROW(decode_job("", resolve), std::invalid_argument);
  const std::string job = encode_job(thermostat_job(0));
  EXPECT_THROW(decode_result(job), std::invalid_argument);  // a job is not a result
  TrialJob unknown = thermostat_job(0);
  unknown.key.method = "no-such-method";
  EXPECT_THROW(decode_job(encode_job(unknown), resolve), std::invalid_argument);
}

}  // namespace
}  // namespace hyfal
