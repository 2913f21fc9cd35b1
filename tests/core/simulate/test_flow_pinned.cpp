// The flows of the suites that do linear algebra (linear, blimp, guard-intruder) and the
// closed-form time-to-go of seed 000 Sect. III-A pinned bit for bit, so that rewriting them (issue
// 15: Eigen's fixed-size types) cannot change a result by a rounding: every planner's tree, and
// so every committed table, is a deterministic function of these numbers.
//
// Per suite: f(q, x, u) at 100 states drawn uniformly in the sampling box (splitmix64, fixed
// seed), for every mode q and every u of Ū; one extension (δt) from the initial state under
// every u of Ū (end state, end kind, steps, spec); t2go(q, x, y) over 64 pairs drawn the same
// way. Each is folded into one hash of the doubles' bit patterns (splitmix64 chain).
// Recorded at commit eb24ab1 (main, before the change), Release build, x86-64, GCC 12, glibc 2.36: the
// libm functions (sin, cos, tanh, atan2, hypot) are part of what is pinned, so another libm may
// need a new recording — as test_hydice_pinned.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <span>
#include <string>
#include <vector>

#include "core/search/metrics/time_to_go.hpp"
#include "core/search/nearest_neighbors.hpp"
#include "core/run/option_spec.hpp"
#include "core/util/rng.hpp"
#include "core/simulate/model_system.hpp"
#include "suites/registry.hpp"

namespace hyfal {
namespace {

struct Hash {
  std::uint64_t h = 0x9e3779b97f4a7c15ull;
  void add(double v) {
    std::uint64_t b;
    std::memcpy(&b, &v, sizeof b);
    h = splitmix64(h ^ b);
  }
  void add(std::uint64_t v) { h = splitmix64(h ^ v); }
};

std::shared_ptr<const System> instance(const char* suite) {
  const SuiteEntry* s = find_suite(suite);
  EXPECT_NE(s, nullptr) << suite;
  return s->make(resolve_options(s->parameters, {}));
}

// `count` points uniform in the sampling box, flat.
std::vector<double> draw_states(const SystemInfo& info, int count, std::uint64_t seed) {
  const std::size_t n = info.dim();
  std::vector<double> xs(count * n);
  std::uint64_t z = seed;
  for (int k = 0; k < count; ++k)
    for (std::size_t i = 0; i < n; ++i) {
      z = splitmix64(z);
      const double unit = static_cast<double>(z >> 11) * 0x1p-53;
      xs[k * n + i] = info.sampling_box.lo[i] + (info.sampling_box.hi[i] - info.sampling_box.lo[i]) * unit;
    }
  return xs;
}

std::vector<Mode> modes(const System& sys) {
  std::vector<Mode> qs;
  for (Mode q = 0; sys.valid_mode(q); ++q) qs.push_back(q);
  return qs;
}

std::uint64_t flow_hash(const char* suite) {
  const auto sys = instance(suite);
  const SystemInfo& info = sys->info();
  const std::size_t n = info.dim();
  const std::vector<double> xs = draw_states(info, 100, 15);
  std::vector<double> dx(n);
  Hash h;
  for (Mode q : modes(*sys)) {
    const InputSet& U = sys->inputs(q);
    for (int k = 0; k < 100; ++k)
      for (std::size_t j = 0; j < U.count(); ++j) {
        sys->derivative(q, std::span<const double>(xs.data() + k * n, n), U.input(j), info.parameters, dx);
        for (double v : dx) h.add(v);
      }
  }
  return h.h;
}

std::uint64_t propagation_hash(const char* suite) {
  const auto sys = instance(suite);
  const SystemInfo& info = sys->info();
  const auto prop = sys->make_propagator();
  std::vector<double> out(info.dim());
  const InputSet& U = sys->inputs(info.initial_mode);
  Hash h;
  for (std::size_t j = 0; j < U.count(); ++j) {
    const PropagationResult r = prop->propagate(info.initial_mode, info.initial_state, U.input(j),
                                                info.parameters, info.step_duration, out);
    h.add(static_cast<std::uint64_t>(r.end));
    h.add(static_cast<std::uint64_t>(r.steps));
    h.add(r.mode);
    h.add(r.duration);
    h.add(r.spec);
    for (double v : out) h.add(v);
  }
  return h.h;
}

std::uint64_t t2go_hash(const char* suite) {
  const auto sys = instance(suite);
  const SystemInfo& info = sys->info();
  const std::size_t n = info.dim();
  const std::vector<double> xs = draw_states(info, 64, 16), ys = draw_states(info, 64, 17);
  const WeightedEuclidean metric(info.metric_weights);
  TimeToGo t2go(*sys, metric, info.parameters);
  Hash h;
  for (Mode q : modes(*sys))
    for (int k = 0; k < 64; ++k) {
      const std::span<const double> x(xs.data() + k * n, n), y(ys.data() + k * n, n);
      h.add(t2go(q, x, y));
      h.add(t2go.approach_speed(q, x, y));
    }
  return h.h;
}

std::string hex(std::uint64_t v) {
  char buf[24];
  std::snprintf(buf, sizeof buf, "0x%016llxull", static_cast<unsigned long long>(v));
  return buf;
}

struct Pin {
  const char* suite;
  std::uint64_t flow, propagation, t2go;
};

const Pin kPins[] = {
    {"linear", 0x3694eef56fdec1b7ull, 0x5e4733df0f15dd66ull, 0x39951f72c3242947ull},
    {"blimp", 0x39118e3c780e42ceull, 0x94bb7f6d029b1f39ull, 0x950c3b3c2d15706eull},
    {"guard-intruder", 0x4228d832544ab86full, 0x98e77f097f46806bull, 0x163b9f892b928a22ull},
};

TEST(FlowPinned, DerivativesAreBitForBitAsRecorded) {
  for (const Pin& p : kPins) EXPECT_EQ(hex(flow_hash(p.suite)), hex(p.flow)) << p.suite;
}

TEST(FlowPinned, OneExtensionPerInputIsBitForBitAsRecorded) {
  for (const Pin& p : kPins) EXPECT_EQ(hex(propagation_hash(p.suite)), hex(p.propagation)) << p.suite;
}

TEST(FlowPinned, TimeToGoIsBitForBitAsRecorded) {
  for (const Pin& p : kPins) EXPECT_EQ(hex(t2go_hash(p.suite)), hex(p.t2go)) << p.suite;
}

}  // namespace
}  // namespace hyfal
