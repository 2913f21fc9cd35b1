// Navigation suite (suites/navigation/navigation.cpp, seed 002 Sect. 4.1): the Kruskal maze (spanning,
// symmetric, the p = 0.9 step only opens more passages), each vehicle's dynamics against hand
// derivatives and its bounds, the velocity reset on a terrain change, walls stopping a
// propagation, the drivers' intervals, generation at n = 1024 (time and memory), and the
// baseline RRT falsifying a small instance with a witness that validates.
#include <gtest/gtest.h>

#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <random>
#include <set>

#include "core/run/option_spec.hpp"
#include "core/simulate/model_system.hpp"
#include "core/witness/trajectory.hpp"
#include "core/witness/witness.hpp"
#include "core/witness/validator.hpp"
#include "core/model/decomposition.hpp"
#include "suites/navigation/navigation.hpp"
#include "suites/registry.hpp"
#include "core/run/method_entry.hpp"

namespace hyfal {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr NavSide kSides[4] = {NavSide::east, NavSide::north, NavSide::west, NavSide::south};

using Sets = std::vector<std::pair<std::string, std::string>>;

Json instance_key(const Sets& sets) {
  return resolve_options(find_suite("navigation")->parameters, sets);
}
std::shared_ptr<const System> make(const Sets& sets) { return find_suite("navigation")->make(instance_key(sets)); }

long max_rss_kib() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss;
}

// --- maze ------------------------------------------------------------------------------------

TEST(NavigationMaze, KruskalTreeSpansAndP09OnlyOpensMore) {
  for (const auto& [n, seed] : std::vector<std::pair<int, std::uint64_t>>{{2, 1}, {4, 1}, {5, 2}, {16, 3}, {37, 9}, {64, 11}}) {
    const NavigationInstance tree = navigation_kruskal_tree(n, seed);
    const NavigationInstance full = NavigationInstance::generate(n, seed, 1.0);
    EXPECT_EQ(tree.passages(), static_cast<std::size_t>(n) * n - 1) << "n = " << n;  // a tree
    EXPECT_TRUE(tree.connected()) << "n = " << n;
    EXPECT_TRUE(full.connected());
    std::size_t remaining = 0, opened = 0;
    for (Mode q = 0; q < full.terrains(); ++q) {
      EXPECT_EQ(tree.vehicle(q), full.vehicle(q));
      for (NavSide s : {NavSide::east, NavSide::north}) {
        if (tree.open(q, s)) {
          EXPECT_TRUE(full.open(q, s)) << "q = " << q;
        }
        const bool interior = s == NavSide::east ? full.col(q) + 1 < n : full.row(q) + 1 < n;
        if (interior && !tree.open(q, s)) {
          ++remaining;
          opened += full.open(q, s);
        }
      }
    }
    EXPECT_EQ(full.passages(), tree.passages() + opened);
    if (n == 64) {  // 3969 walls left by Kruskal; each removed with probability 0.1
      EXPECT_EQ(remaining, 2u * 64 * 63 - (64u * 64 - 1));
      EXPECT_NEAR(static_cast<double>(opened) / remaining, 0.1, 0.02);
    }
    for (int i = 0; i < NavigationInstance::kProperties; ++i) {
      EXPECT_EQ(tree.properties()[i].start, full.properties()[i].start);
      EXPECT_EQ(tree.properties()[i].unsafe, full.properties()[i].unsafe);
    }
  }
}

TEST(NavigationMaze, PassagesSymmetricBoundaryClosedLookupO1) {
  const NavigationInstance m = NavigationInstance::generate(13, 5, 2.0);
  const int n = m.n();
  for (Mode q = 0; q < m.terrains(); ++q) {
    const int r = m.row(q), c = m.col(q);
    EXPECT_EQ(q, static_cast<Mode>(r * n + c));
    if (c + 1 < n) {
      EXPECT_EQ(m.open(q, NavSide::east), m.open(q + 1, NavSide::west));
    } else {
      EXPECT_FALSE(m.open(q, NavSide::east));
    }
    if (r + 1 < n) {
      EXPECT_EQ(m.open(q, NavSide::north), m.open(q + n, NavSide::south));
    } else {
      EXPECT_FALSE(m.open(q, NavSide::north));
    }
    if (c == 0) {
      EXPECT_FALSE(m.open(q, NavSide::west));
    }
    if (r == 0) {
      EXPECT_FALSE(m.open(q, NavSide::south));
    }
    for (NavSide s : kSides)
      if (m.open(q, s)) {
        const Mode o = m.neighbour(q, s);
        EXPECT_EQ(std::abs(m.row(o) - r) + std::abs(m.col(o) - c), 1);
      }
    const auto centre = m.centre(q);
    EXPECT_EQ(m.terrain_at(centre[0], centre[1]), q);
    const auto lo = m.corner(q);
    EXPECT_EQ(m.terrain_at(lo[0], lo[1]), q);  // a shared side goes to the east/north terrain
  }
  EXPECT_EQ(m.terrain_at(-5.0, 1e9), static_cast<Mode>((n - 1) * n));  // clamped
}

TEST(NavigationMaze, DeterministicVehiclesUniformPropertiesDistinct) {
  const NavigationInstance a = NavigationInstance::generate(64, 42, 1.0);
  const NavigationInstance b = NavigationInstance::generate(64, 42, 1.0);
  const NavigationInstance c = NavigationInstance::generate(64, 43, 1.0);
  int counts[3] = {0, 0, 0};
  bool differs = false;
  for (Mode q = 0; q < a.terrains(); ++q) {
    EXPECT_EQ(a.vehicle(q), b.vehicle(q));
    for (NavSide s : kSides) EXPECT_EQ(a.open(q, s), b.open(q, s));
    differs = differs || a.vehicle(q) != c.vehicle(q) || a.open(q, NavSide::east) != c.open(q, NavSide::east);
    ++counts[static_cast<int>(a.vehicle(q))];
  }
  EXPECT_TRUE(differs);
  for (int v = 0; v < 3; ++v) EXPECT_NEAR(counts[v] / 4096.0, 1.0 / 3.0, 0.03);
  std::set<std::pair<std::uint32_t, std::uint32_t>> distinct;
  for (const auto& p : a.properties()) {
    EXPECT_NE(p.start, p.unsafe);
    EXPECT_LT(p.start, a.terrains());
    EXPECT_LT(p.unsafe, a.terrains());
    distinct.insert({p.start, p.unsafe});
  }
  EXPECT_GT(distinct.size(), 35u);
  // The property picked by the suite: start at the centre, heading 0, at rest; goal at the
  // unsafe terrain's centre; the maze does not depend on driver or property.
  auto sys = make({{"n", "64"}, {"seed", "42"}, {"property", "7"}, {"driver", "highway"}});
  const auto& info = sys->info();
  const auto p7 = a.properties()[7];
  EXPECT_EQ(info.initial_mode, p7.start);
  const auto c0 = a.centre(p7.start), cu = a.centre(p7.unsafe);
  EXPECT_EQ(info.initial_state, (std::vector<double>{c0[0], c0[1], 0.0, 0.0, 0.0}));
  EXPECT_EQ(info.goal_point, (std::vector<double>{cu[0], cu[1], 0.0, 0.0, 0.0}));
  const auto maze = navigation_instance(*sys);
  ASSERT_TRUE(maze);
  for (Mode q = 0; q < a.terrains(); ++q) ASSERT_EQ(maze->open(q, NavSide::north), a.open(q, NavSide::north));
  EXPECT_LE(sys->spec(p7.unsafe, std::vector<double>{cu[0], cu[1], 0, 0, 0}, {}), 0.0);
  EXPECT_GT(sys->spec(p7.start, info.initial_state, {}), 0.0);
  EXPECT_EQ(navigation_instance(*find_suite("thermostat")->make(resolve_options(find_suite("thermostat")->parameters, {}))),
            nullptr);
}

TEST(NavigationMaze, Generation1024IsFastAndCompact) {
  const long rss0 = max_rss_kib();
  const auto t0 = std::chrono::steady_clock::now();
  const NavigationInstance m = NavigationInstance::generate(1024, 1, 1.0);
  const double gen_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const long rss1 = max_rss_kib();
  EXPECT_EQ(m.terrains(), 1024u * 1024u);
  EXPECT_EQ(m.memory_bytes(), 2u * 1024 * 1024 * 2 / 8);  // 2 + 2 bits per terrain: 512 KiB
  // Hang guards, not speed targets (those live in bench/bench_navigation.cpp): a sanitized build on a
  // loaded machine took 5.06 s where Release takes about 1 s.
  EXPECT_LT(gen_s, 60.0);
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
  constexpr long kRssBoundKiB = 4 * 48 * 1024;  // sanitizers' shadow memory multiplies RSS
#else
  constexpr long kRssBoundKiB = 48 * 1024;
#endif
  EXPECT_LT(rss1 - rss0, kRssBoundKiB) << "max RSS grew by " << rss1 - rss0 << " KiB";
  const auto t1 = std::chrono::steady_clock::now();
  auto sys = make({{"n", "1024"}});
  const double sys_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
  const long rss2 = max_rss_kib();
  EXPECT_LT(sys_s, 60.0);
  EXPECT_EQ(sys->inputs(12345).count(), 9u);
  const double spacing = sys->info().coverage.spacing;
  EXPECT_DOUBLE_EQ(spacing, 1.0);  // 1025 x 1025 coverage points at n = 1024
  const auto t2 = std::chrono::steady_clock::now();
  EXPECT_TRUE(m.connected());
  const double bfs_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t2).count();
  std::printf("[navigation] n = 1024: generate %.3f s, max RSS %ld -> %ld KiB (+%ld), instance %zu bytes; "
              "suite make %.3f s, max RSS -> %ld KiB; BFS %.3f s; passages %zu\n",
              gen_s, rss0, rss1, rss1 - rss0, m.memory_bytes(), sys_s, rss2, bfs_s, m.passages());
}

// --- dynamics --------------------------------------------------------------------------------

// A terrain of the given vehicle, with the given side open (or closed), away from the boundary
// when possible.
std::optional<Mode> find_terrain(const NavigationInstance& m, NavVehicle v, NavSide side, bool open) {
  for (Mode q = 0; q < m.terrains(); ++q)
    if (m.vehicle(q) == v && m.open(q, side) == open) return q;
  return std::nullopt;
}

std::vector<double> deriv(const System& sys, Mode q, std::vector<double> x, std::vector<double> u) {
  std::vector<double> dx(x.size());
  sys.derivative(q, x, u, {}, dx);
  return dx;
}

void expect_near(const std::vector<double>& a, const std::vector<double>& b, double tol) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) EXPECT_NEAR(a[i], b[i], tol) << "component " << i;
}

TEST(NavigationDynamics, HandDerivativesInputBoxesAndBounds) {
  auto sys = make({{"n", "8"}, {"seed", "3"}});
  const auto m = navigation_instance(*sys);
  for (NavVehicle v : {NavVehicle::scar, NavVehicle::suni, NavVehicle::sddrive}) {
    const auto q = find_terrain(*m, v, NavSide::east, true);
    ASSERT_TRUE(q) << navigation_vehicle_name(v);
    const auto c = m->centre(*q);
    const double th = 0.3;
    std::vector<double> x = {c[0], c[1], th, 0.0, 0.0}, u = {0.05, -0.02};
    std::vector<double> want;
    const NavVehicleLimits l = navigation_limits(v);
    switch (v) {
      case NavVehicle::scar:
        EXPECT_DOUBLE_EQ(l.a_max, 3.0);
        EXPECT_DOUBLE_EQ(l.b_max, 40 * kDeg);
        EXPECT_DOUBLE_EQ(l.u0_max, 0.8);
        EXPECT_DOUBLE_EQ(l.u1_max, 25 * kDeg);
        x[3] = 1.2, x[4] = 0.2;  // v, φ
        want = {1.2 * std::cos(th), 1.2 * std::sin(th), 1.2 * std::tan(0.2) / 0.8, 0.05, -0.02};
        break;
      case NavVehicle::suni:
        EXPECT_DOUBLE_EQ(l.a_max, 3.0);
        EXPECT_DOUBLE_EQ(l.b_max, 20 * kDeg);
        EXPECT_DOUBLE_EQ(l.u0_max, 0.3);
        EXPECT_DOUBLE_EQ(l.u1_max, 10 * kDeg);
        x[3] = -0.7, x[4] = 0.25;  // v, ω
        want = {-0.7 * std::cos(th), -0.7 * std::sin(th), 0.25, 0.05, -0.02};
        break;
      case NavVehicle::sddrive:
        // Read as rad/s by default; as printed (°/s) with NavWheelUnit::degrees.
        EXPECT_DOUBLE_EQ(l.a_max, 5);
        EXPECT_DOUBLE_EQ(l.b_max, 5);
        EXPECT_DOUBLE_EQ(l.u0_max, 10);
        EXPECT_DOUBLE_EQ(l.u1_max, 10);
        EXPECT_DOUBLE_EQ(navigation_limits(v, NavWheelUnit::degrees).a_max, 5 * kDeg);
        EXPECT_DOUBLE_EQ(navigation_limits(v, NavWheelUnit::degrees).u1_max, 10 * kDeg);
        x[3] = 0.05, x[4] = 0.08;  // ω_l, ω_r
        want = {0.5 * 0.2 * 0.13 * std::cos(th), 0.5 * 0.2 * 0.13 * std::sin(th), 0.2 * 0.03 / 0.8, 0.05, -0.02};
        break;
    }
    expect_near(deriv(*sys, *q, x, u), want, 1e-14);
    EXPECT_TRUE(sys->input_affine(*q));
    EXPECT_TRUE(sys->invariant(*q, x, {}));
    // Bounds on (a, b) belong to the invariant.
    auto y = x;
    y[3] = 1.0001 * l.a_max;
    EXPECT_FALSE(sys->invariant(*q, y, {}));
    y = x;
    y[4] = -1.0001 * l.b_max;
    EXPECT_FALSE(sys->invariant(*q, y, {}));
    y = x;
    y[3] = -l.a_max, y[4] = l.b_max;
    EXPECT_TRUE(sys->invariant(*q, y, {}));
    // Ū: a 3 x 3 grid over U, with u = 0.
    const InputSet& U = sys->inputs(*q);
    EXPECT_EQ(U.box.lo, (std::vector<double>{-l.u0_max, -l.u1_max}));
    EXPECT_EQ(U.box.hi, (std::vector<double>{l.u0_max, l.u1_max}));
    ASSERT_EQ(U.count(), 9u);
    bool zero = false;
    for (std::size_t j = 0; j < U.count(); ++j) zero = zero || (U.input(j)[0] == 0.0 && U.input(j)[1] == 0.0);
    EXPECT_TRUE(zero);
    EXPECT_EQ(sys->guard_count(*q), 4);
  }
}

TEST(NavigationDynamics, SpecIsSignedDistanceToTheUnsafeTerrain) {
  auto sys = make({{"n", "6"}, {"seed", "2"}, {"terrain_size", "2.0"}});
  const auto m = navigation_instance(*sys);
  const Mode u = m->properties()[0].unsafe;
  const auto lo = m->corner(u);
  auto s = [&](double x, double y) { return sys->spec(0, std::vector<double>{x, y, 0, 0, 0}, {}); };
  EXPECT_NEAR(s(lo[0] + 1.0, lo[1] + 1.0), -1.0, 1e-12);  // centre of a 2 m terrain
  EXPECT_NEAR(s(lo[0] + 0.5, lo[1] + 1.0), -0.5, 1e-12);
  EXPECT_NEAR(s(lo[0], lo[1] + 1.0), 0.0, 1e-12);          // on the boundary: unsafe
  EXPECT_NEAR(s(lo[0] - 3.0, lo[1] + 1.0), 3.0, 1e-12);
  EXPECT_NEAR(s(lo[0] - 3.0, lo[1] - 4.0), 5.0, 1e-12);    // off a corner
  EXPECT_NEAR(s(lo[0] + 2.5, lo[1] + 2.0), 0.5, 1e-12);
}

// The integrator tests each step with navigation_outside_box instead of the spec's sign: the two
// must agree everywhere, on the boundary and one ulp either side of it included.
TEST(NavigationDynamics, OutsideBoxIsExactlySpecPositive) {
  const std::array<double, 4> box{3.0, 5.0, 4.0, 6.0};
  std::mt19937_64 g(7);
  std::uniform_real_distribution<double> coord(1.0, 8.0);
  std::vector<double> xs{1.0, 3.0, 3.5, 4.0, 5.0, 6.0, 8.0};
  for (double v : std::vector<double>(xs)) {
    xs.push_back(std::nextafter(v, -1e9));
    xs.push_back(std::nextafter(v, 1e9));
  }
  for (int i = 0; i < 600; ++i) xs.push_back(coord(g));
  int inside = 0, outside = 0;
  for (double a : xs)
    for (double b : xs) {
      const double x[5] = {a, b, 0.0, 0.0, 0.0};
      const bool out = navigation_outside_box(box, x);
      ASSERT_EQ(out, navigation_box_spec(box, x) > 0.0) << a << ", " << b;
      (out ? outside : inside) += 1;
    }
  EXPECT_GT(inside, 1000);
  EXPECT_GT(outside, 1000);
}

// Propagates a vehicle heading east at speed `speed` from `gap` before the east side of q.
PropagationResult drive_east(const System& sys, Mode q, double gap, double speed, std::vector<double>& out,
                             std::vector<double> u = {0.0, 0.0}) {
  const auto m = navigation_instance(sys);
  const auto lo = m->corner(q);
  const double s = m->terrain_size();
  std::vector<double> x = {lo[0] + s - gap, lo[1] + 0.5 * s, 0.0, 0.0, 0.0};
  if (m->vehicle(q) == NavVehicle::sddrive) {
    x[3] = x[4] = speed / 0.2;  // v = r (ω_l + ω_r) / 2
  } else {
    x[3] = speed;
  }
  out.assign(5, 0.0);
  auto prop = sys.make_propagator();
  return prop->propagate(q, x, u, {}, sys.info().step_duration, out);
}

TEST(NavigationDynamics, CrossingAnOpenSideJumpsAndResetsVelocity) {
  auto sys = make({{"n", "8"}, {"seed", "3"}});
  const auto m = navigation_instance(*sys);
  for (NavVehicle v : {NavVehicle::scar, NavVehicle::suni, NavVehicle::sddrive}) {
    const auto q = find_terrain(*m, v, NavSide::east, true);
    ASSERT_TRUE(q);
    const double speed = v == NavVehicle::sddrive ? 0.015 : 1.0;
    std::vector<double> out;
    const auto r = drive_east(*sys, *q, 0.01, speed, out);
    EXPECT_EQ(r.end, PropagationEnd::jumped) << navigation_vehicle_name(v);
    EXPECT_EQ(r.transition, static_cast<int>(NavSide::east));
    EXPECT_EQ(r.mode, *q + 1);
    EXPECT_NEAR(r.duration, 0.01 / speed, 1e-6);
    EXPECT_EQ(out[3], 0.0);
    EXPECT_EQ(out[4], 0.0);
    const double side = m->corner(*q + 1)[0];
    EXPECT_NEAR(out[0], side, 1e-8);
    EXPECT_EQ(m->terrain_at(out[0], out[1]), *q + 1);
    EXPECT_TRUE(sys->invariant(r.mode, out, {}));
    // Hysteresis: the neighbour's guard back across the same side is not enabled, so the
    // vehicle at rest stays in the new terrain.
    auto prop = sys->make_propagator();
    std::vector<double> out2(5);
    const auto r2 = prop->propagate(r.mode, out, std::vector<double>{0.0, 0.0}, {}, 0.5, out2);
    EXPECT_EQ(r2.end, PropagationEnd::completed);
    EXPECT_EQ(r2.mode, *q + 1);
    EXPECT_EQ(out2, out);
  }
}

TEST(NavigationDynamics, AKeptWallStopsThePropagation) {
  auto sys = make({{"n", "8"}, {"seed", "3"}});
  const auto m = navigation_instance(*sys);
  for (NavVehicle v : {NavVehicle::scar, NavVehicle::suni}) {
    const auto q = find_terrain(*m, v, NavSide::east, false);
    ASSERT_TRUE(q);
    std::vector<double> out;
    const auto r = drive_east(*sys, *q, 0.1, 1.0, out);
    EXPECT_EQ(r.end, PropagationEnd::invariant) << navigation_vehicle_name(v);
    EXPECT_EQ(r.mode, *q);
    EXPECT_LT(r.duration, 0.1);
    EXPECT_GT(r.duration, 0.08);  // the last RK4 step before the wall
    const double wall = m->corner(*q)[0] + m->terrain_size();
    EXPECT_LT(out[0], wall);
    EXPECT_GT(out[0], wall - 0.011);
    EXPECT_EQ(out[3], 1.0);  // no reset: no transition
    EXPECT_TRUE(sys->invariant(*q, out, {}));
    EXPECT_LT(sys->guard(*q, 0, out, {}), 0.0);
  }
  // The outer boundary is a wall too: the west side of terrain 0.
  std::vector<double> x = {0.05, 0.5, std::numbers::pi, 1.0, 0.0}, out(5);
  if (m->vehicle(0) == NavVehicle::sddrive) x[3] = x[4] = 0.075;
  auto prop = sys->make_propagator();
  const auto r = prop->propagate(0, x, std::vector<double>{0.0, 0.0}, {}, 1.0, out);
  EXPECT_EQ(r.end, PropagationEnd::invariant);
  EXPECT_GT(out[0], 0.0);
}

TEST(NavigationDynamics, SpeedBoundStopsThePropagation) {
  auto sys = make({{"n", "3"}, {"seed", "1"}, {"terrain_size", "100.0"}, {"step", "2.0"}});
  const auto m = navigation_instance(*sys);
  std::optional<Mode> q;
  for (Mode r = 0; r < m->terrains() && !q; ++r)
    if (m->vehicle(r) == NavVehicle::scar) q = r;
  ASSERT_TRUE(q);
  const auto c = m->centre(*q);
  std::vector<double> x = {c[0], c[1], 0.0, 2.5, 0.0}, out(5);
  auto prop = sys->make_propagator();
  const auto r = prop->propagate(*q, x, std::vector<double>{0.8, 0.0}, {}, 2.0, out);
  EXPECT_EQ(r.end, PropagationEnd::invariant);
  EXPECT_NEAR(r.duration, 0.62, 0.011);  // 2.5 + 0.8 t reaches 3 at t = 0.625
  EXPECT_LE(out[3], 3.0);
  EXPECT_GT(out[3], 2.99);
}

// --- drivers ---------------------------------------------------------------------------------

TEST(NavigationDrivers, HandCases) {
  const auto iv = [](NavDriver d, NavVehicle v, double a, double b) {
    return navigation_driver_interval(d, v, std::vector<double>{0.0, 0.0, 0.0, a, b});
  };
  const double m1c = 25 * kDeg, m1u = 10 * kDeg, mdd = 10.0, wmax = 5.0;  // SDDrive in rad/s (default)
  auto expect_iv = [](const DriverInterval& got, std::array<double, 2> lo, std::array<double, 2> hi) {
    for (int i = 0; i < 2; ++i) {
      EXPECT_NEAR(got.lo[i], lo[i], 1e-14) << "lo " << i;
      EXPECT_NEAR(got.hi[i], hi[i], 1e-14) << "hi " << i;
    }
  };
  // Random: the whole box, whatever the state.
  expect_iv(iv(NavDriver::random, NavVehicle::scar, 2.0, 0.3), {-0.8, -m1c}, {0.8, m1c});
  expect_iv(iv(NavDriver::random, NavVehicle::sddrive, 0.08, 0.08), {-mdd, -mdd}, {mdd, mdd});
  // Student, SCar: v/v_max = 0.5 in (0.2, 1] -> [-max, (0.2-1) max] (brake); u1 random.
  expect_iv(iv(NavDriver::student, NavVehicle::scar, 1.5, 0.1), {-0.8, -m1c}, {-0.64, m1c});
  expect_iv(iv(NavDriver::student, NavVehicle::scar, -1.5, 0.1), {0.64, -m1c}, {0.8, m1c});
  expect_iv(iv(NavDriver::student, NavVehicle::scar, 0.6, 0.1), {-0.8, -m1c}, {0.8, m1c});  // a = 0.2: random
  // Student, SUni: both inputs follow f; ω/ω_max = -0.5 -> [(1-0.2) max, max].
  expect_iv(iv(NavDriver::student, NavVehicle::suni, 3.0, -10 * kDeg), {-0.3, 0.8 * m1u}, {-0.24, m1u});
  // Student, SDDrive: a = (ω_l + ω_r) / (2 ω_max) = 0.8 -> f = [0, 0.25 (1.2 - 1) max],
  // u1 = -f.
  expect_iv(iv(NavDriver::student, NavVehicle::sddrive, 0.8 * wmax, 0.8 * wmax), {0.0, -0.05 * mdd},
            {0.05 * mdd, 0.0});
  expect_iv(iv(NavDriver::student, NavVehicle::sddrive, -wmax, -0.5 * wmax), {-0.05 * mdd, 0.0},
            {0.0, 0.05 * mdd});
  // Highway, SCar: v/v_max = 0.5 in (0.4, 0.6], b = 0.6 -> [-0.6 max, (0.2 - 0.6) max].
  expect_iv(iv(NavDriver::highway, NavVehicle::scar, 1.5, 0.0), {-0.48, -m1c}, {-0.32, m1c});
  // a = 0.4 exactly belongs to (0.2, 0.4], b = 0.4 -> [-0.4 max, -0.2 max].
  expect_iv(iv(NavDriver::highway, NavVehicle::scar, 1.2, 0.0), {-0.32, -m1c}, {-0.16, m1c});
  // a = -0.9 in [-1, -0.8), b = 1 -> [(1 - 0.2) max, max].
  expect_iv(iv(NavDriver::highway, NavVehicle::scar, -2.7, 0.0), {0.64, -m1c}, {0.8, m1c});
  expect_iv(iv(NavDriver::highway, NavVehicle::scar, 0.3, 0.0), {-0.8, -m1c}, {0.8, m1c});  // a = 0.1
  // Highway, SDDrive: a = 0.5, b = 0.6 -> f = [0, 0.25 (1.2 - 0.6) max]; u1 = -f;
  // a = -0.3 in [-0.4, -0.2), b = 0.4 -> f = [0.25 (0.4 - 1.2) max, 0].
  expect_iv(iv(NavDriver::highway, NavVehicle::sddrive, 0.5 * wmax, 0.5 * wmax), {0.0, -0.15 * mdd},
            {0.15 * mdd, 0.0});
  expect_iv(iv(NavDriver::highway, NavVehicle::sddrive, -0.3 * wmax, -0.3 * wmax), {-0.2 * mdd, 0.0},
            {0.0, 0.2 * mdd});
  EXPECT_EQ(navigation_driver_from_name("highway"), NavDriver::highway);
  EXPECT_THROW(navigation_driver_from_name("racer"), std::invalid_argument);
}

TEST(NavigationDrivers, AlwaysInsideTheInputBox) {
  for (NavDriver d : {NavDriver::random, NavDriver::student, NavDriver::highway})
    for (NavVehicle v : {NavVehicle::scar, NavVehicle::suni, NavVehicle::sddrive}) {
      const NavVehicleLimits l = navigation_limits(v);
      for (int i = -200; i <= 200; ++i)
        for (int j = -20; j <= 20; ++j) {
          const std::vector<double> x = {0.0, 0.0, 0.0, l.a_max * i / 200.0, l.b_max * j / 20.0};
          const DriverInterval r = navigation_driver_interval(d, v, x);
          const double max[2] = {l.u0_max, l.u1_max};
          for (int k = 0; k < 2; ++k) {
            ASSERT_LE(r.lo[k], r.hi[k]) << navigation_driver_name(d) << " " << navigation_vehicle_name(v);
            ASSERT_GE(r.lo[k], -max[k] * (1 + 1e-15));
            ASSERT_LE(r.hi[k], max[k] * (1 + 1e-15));
          }
        }
    }
}

// A velocity one rounding error beyond its bound (the invariant tolerates it; RK4 stores
// ω = 1.0000000000000007 ω_max after 2 s of full steering on SUni) is still the top band of
// Student and Highway, not Random.
TEST(NavigationDrivers, AStateOneUlpBeyondTheBoundKeepsTheDriversBand) {
  const double inf = std::numeric_limits<double>::infinity();
  for (NavDriver d : {NavDriver::student, NavDriver::highway})
    for (NavVehicle v : {NavVehicle::scar, NavVehicle::suni, NavVehicle::sddrive}) {
      const NavVehicleLimits l = navigation_limits(v);
      for (double sign : {1.0, -1.0}) {
        const std::vector<double> at = {0.0, 0.0, 0.0, sign * l.a_max, sign * l.b_max};
        std::vector<double> beyond = at;
        beyond[3] = std::nextafter(at[3], sign * inf);
        beyond[4] = std::nextafter(at[4], sign * inf);
        std::vector<double> rounded = at;  // the value seen in a stored tree node
        rounded[4] = sign * l.b_max * 1.0000000000000007;
        const DriverInterval want = navigation_driver_interval(d, v, at);
        const DriverInterval random = navigation_driver_interval(NavDriver::random, v, at);
        for (const auto& x : {beyond, rounded}) {
          const DriverInterval got = navigation_driver_interval(d, v, x);
          const std::string what = std::string(navigation_driver_name(d)) + " " + std::string(navigation_vehicle_name(v)) +
                                   (sign > 0 ? " +" : " -");
          EXPECT_EQ(got.lo, want.lo) << what;
          EXPECT_EQ(got.hi, want.hi) << what;
        }
        // At the bound the driver forbids part of U (it brakes), so the two differ.
        EXPECT_TRUE(want.lo != random.lo || want.hi != random.hi) << navigation_vehicle_name(v);
      }
    }
  // A NaN velocity is in no band: Random, never an inverted interval.
  const DriverInterval nan = navigation_driver_interval(NavDriver::student, NavVehicle::suni,
                                                        std::vector<double>{0.0, 0.0, 0.0, std::nan(""), 0.0});
  EXPECT_LE(nan.lo[0], nan.hi[0]);
}

// The validator judges u by the driver at each piece's recorded x_start: a witness whose
// second piece starts with ω one ulp above ω_max on SUni and keeps steering (u1 = 0, which
// Random allows, Student and Highway do not: their top band brakes) is rejected.
TEST(NavigationDrivers, WitnessWithAnInputOutsideTheDriversBandAtTheBoundIsRejected) {
  // A property whose start terrain is SUni.
  const NavigationInstance maze = NavigationInstance::generate(4, 1, 1.0);
  int property = -1;
  for (int i = 0; i < NavigationInstance::kProperties && property < 0; ++i)
    if (maze.vehicle(maze.properties()[i].start) == NavVehicle::suni) property = i;
  ASSERT_GE(property, 0);
  const NavVehicleLimits l = navigation_limits(NavVehicle::suni);
  for (const char* driver : {"student", "highway"}) {
    auto sys = make({{"n", "4"}, {"seed", "1"}, {"property", std::to_string(property)}, {"driver", driver}});
    const SystemInfo& info = sys->info();
    auto prop = sys->make_propagator();
    // Piece 0: at rest, full steering until ω reaches ω_max (SUni's u1 is ω').
    TrajectoryPiece p0;
    p0.mode = info.initial_mode;
    p0.u = {0.0, l.u1_max};
    p0.duration = l.b_max / l.u1_max;
    p0.x_start = info.initial_state;
    p0.x_end.resize(5);
    prop->flow(p0.mode, p0.x_start, p0.u, {}, p0.duration, p0.x_end);
    ASSERT_NEAR(p0.x_end[4], l.b_max, 1e-12);
    // Piece 1 starts one ulp beyond the bound, then keeps ω (u1 = 0) or brakes (u1 = -max).
    TrajectoryPiece p1;
    p1.mode = info.initial_mode;
    p1.x_start = p0.x_end;
    p1.x_start[4] = std::nextafter(l.b_max, 2.0 * l.b_max);
    p1.duration = 0.5;
    std::vector<double> lo(2), hi(2);
    sys->input_bounds(p1.mode, p1.x_start, lo, hi);
    // Student's band (0.2, 1] and Highway's b = 1 band: [-max, (0.2 - 1) max], not Random's [-max, max].
    EXPECT_EQ(lo[1], -l.u1_max) << driver;
    EXPECT_DOUBLE_EQ(hi[1], -0.8 * l.u1_max) << driver;
    auto witness_with = [&](double u1) {
      TrajectoryPiece q1 = p1;
      q1.u = {0.0, u1};
      q1.x_end.resize(5);
      prop->flow(q1.mode, q1.x_start, q1.u, {}, q1.duration, q1.x_end);
      Trajectory t;
      t.initial_mode = info.initial_mode;
      t.initial_x = info.initial_state;
      t.pieces = {p0, q1};
      t.final_mode = q1.mode;
      t.final_x = q1.x_end;
      t.final_spec = sys->spec(t.final_mode, t.final_x, {});
      return make_witness(*sys, "test", 0, std::move(t));
    };
    const ValidationReport keep = validate_witness(*sys, witness_with(0.0));
    EXPECT_FALSE(keep.valid) << driver;
    EXPECT_NE(keep.reason.find("piece 1: input 1 = 0 is outside the admissible"), std::string::npos)
        << driver << ": " << keep.reason;
    // Braking passes the input check (the witness is still invalid: it does not reach the unsafe
    // terrain, which is what the validator says last).
    const ValidationReport brake = validate_witness(*sys, witness_with(-l.u1_max));
    EXPECT_FALSE(brake.valid);
    EXPECT_EQ(brake.reason.find("admissible"), std::string::npos) << driver << ": " << brake.reason;
  }
}

// --- parameters and export -------------------------------------------------------------------

TEST(NavigationSuite, BadValuesThrow) {
  EXPECT_THROW(make({{"n", "0"}}), std::invalid_argument);
  EXPECT_THROW(make({{"n", "5000"}}), std::invalid_argument);
  EXPECT_THROW(make({{"inputs", "best"}}), std::invalid_argument);
  EXPECT_THROW(make({{"driver_draws", "0"}}), std::invalid_argument);
  EXPECT_THROW(make({{"property", "40"}}), std::invalid_argument);
  EXPECT_THROW(make({{"property", "-1"}}), std::invalid_argument);
  EXPECT_THROW(make({{"driver", "racer"}}), std::invalid_argument);
  EXPECT_THROW(make({{"terrain_size", "0"}}), std::invalid_argument);
  EXPECT_THROW(make({{"step", "-1"}}), std::invalid_argument);
  EXPECT_THROW(make({{"integration_step", "3.0"}}), std::invalid_argument);
  EXPECT_THROW(make({{"input_levels", "1"}}), std::invalid_argument);
  EXPECT_NO_THROW(make({{"driver", "student"}, {"property", "39"}}));
}

TEST(NavigationSuite, InstanceJsonExport) {
  const Json key = instance_key({{"n", "32"}, {"seed", "7"}});
  const Json j = navigation_instance_json(key);
  const NavigationInstance m = NavigationInstance::generate(32, 7, 1.0);
  EXPECT_EQ(j.at("format"), "hyfal-navigation/1");
  EXPECT_EQ(j.at("instance"), key);
  EXPECT_EQ(j.at("n"), 32);
  EXPECT_EQ(j.at("seed"), 7);
  EXPECT_EQ(j.at("driver"), "random");
  const std::string dyn = j.at("dynamics").get<std::string>();
  ASSERT_EQ(dyn.size(), 1024u);
  for (Mode q = 0; q < m.terrains(); ++q) EXPECT_EQ(dyn[q], "CUD"[static_cast<int>(m.vehicle(q))]);
  ASSERT_EQ(j.at("passages").size(), m.passages());
  for (const auto& p : j.at("passages")) {
    const Mode a = p.at(0).get<Mode>(), b = p.at(1).get<Mode>();
    ASSERT_LT(a, b);
    EXPECT_TRUE(b == a + 1 ? m.open(a, NavSide::east) : (b == a + 32 && m.open(a, NavSide::north)));
  }
  ASSERT_EQ(j.at("properties").size(), 40u);
  EXPECT_EQ(j.at("properties").at(3).at(0).get<std::uint32_t>(), m.properties()[3].start);
  EXPECT_EQ(j.at("properties").at(3).at(1).get<std::uint32_t>(), m.properties()[3].unsafe);
  EXPECT_DOUBLE_EQ(j.at("constants").at("SCar").at("L").get<double>(), 0.8);
  EXPECT_EQ(j.at("property_places"), "terrains");
  EXPECT_EQ(navigation_instance_json(instance_key({{"n", "1"}})).at("property_places"), "quarters");
  EXPECT_THROW(navigation_instance_json(instance_key({{"n", "0"}})), std::invalid_argument);
}

// --- one terrain (the paper's 1² column) -------------------------------------------------------

TEST(NavigationOneTerrain, PropertiesAreDistinctQuartersOfTheTerrain) {
  int seen[4][4] = {};
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    const NavigationInstance m = NavigationInstance::generate(1, seed, 2.0);
    EXPECT_EQ(m.places(), 4u);
    EXPECT_EQ(m.passages(), 0u);
    for (const NavigationProperty& p : m.properties()) {
      ASSERT_LT(p.start, 4u);
      ASSERT_LT(p.unsafe, 4u);
      ASSERT_NE(p.start, p.unsafe);
      ++seen[p.start][p.unsafe];
    }
  }
  for (int a = 0; a < 4; ++a)
    for (int b = 0; b < 4; ++b)
      if (a != b) EXPECT_GT(seen[a][b], 30) << a << " -> " << b;  // 800 draws over 12 pairs
  const NavigationInstance m = NavigationInstance::generate(1, 1, 2.0);
  EXPECT_EQ(m.place_box(0), (std::array<double, 4>{0.0, 0.0, 1.0, 1.0}));
  EXPECT_EQ(m.place_box(1), (std::array<double, 4>{1.0, 0.0, 2.0, 1.0}));
  EXPECT_EQ(m.place_box(2), (std::array<double, 4>{0.0, 1.0, 1.0, 2.0}));
  EXPECT_EQ(m.place_box(3), (std::array<double, 4>{1.0, 1.0, 2.0, 2.0}));
  EXPECT_EQ(NavigationInstance::generate(3, 1, 2.0).place_box(4), (std::array<double, 4>{2.0, 2.0, 4.0, 4.0}));
}

TEST(NavigationOneTerrain, StartAtAQuarterCentreUnsafeIsAnotherQuarterAndItsRegion) {
  for (int property = 0; property < 6; ++property) {
    auto sys = make({{"n", "1"}, {"property", std::to_string(property)}, {"terrain_size", "2"}});
    const NavigationProperty p = navigation_instance(*sys)->properties()[property];
    const SystemInfo& info = sys->info();
    EXPECT_EQ(info.initial_mode, 0);
    EXPECT_DOUBLE_EQ(info.initial_state[0], 0.5 + (p.start % 2));
    EXPECT_DOUBLE_EQ(info.initial_state[1], 0.5 + (p.start / 2));
    EXPECT_GT(sys->spec(0, info.initial_state, {}), 0.0);
    const std::vector<double> inside = {0.5 + (p.unsafe % 2), 0.5 + (p.unsafe / 2), 0.0, 0.0, 0.0};
    EXPECT_LE(sys->spec(0, inside, {}), -0.5 + 1e-12);
    const Decomposition* d = sys->decomposition();
    ASSERT_NE(d, nullptr);
    for (RegionId r = 0; r < 4; ++r) EXPECT_EQ(d->is_unsafe(r), r == p.unsafe) << r;
  }
}

TEST(NavigationOneTerrain, EveryMethodFalsifiesWithAValidWitness) {
  auto sys = make({{"n", "1"}, {"property", "0"}});
  for (const char* method : {"rrt", "rrt-dstar", "hydice", "hydice-noleads"}) {
    auto planner = find_method(method)->make(resolve_options(find_method(method)->options, {}));
    const PlannerContext ctx{*sys, sys->info().parameters, 7, PlannerLimits{15.0, 200'000}, {}};
    const PlannerOutcome out = planner->solve(ctx);
    ASSERT_EQ(out.status, TrialStatus::falsified) << method;
    const ValidationReport report = validate_witness(*sys, make_witness(*sys, method, 7, *out.trajectory));
    EXPECT_TRUE(report.valid) << method << ": " << report.reason;
  }
}

// --- input policy ------------------------------------------------------------------------------

// inputs=driver (default): the RRT extension applies driver_draws controls drawn uniformly from
// the driver's interval, not the grid: the tree's edges carry non-grid inputs, each inside the
// driver's box at its node; inputs=grid: every edge input is a grid point.
TEST(NavigationInputPolicy, DriverDrawsAreContinuousAndAdmissibleGridIsTheGrid) {
  for (const char* policy : {"driver", "grid"}) {
    auto sys = make({{"n", "4"}, {"driver", "random"}, {"inputs", policy}});
    EXPECT_EQ(sys->info().continuous_random_inputs, std::string(policy) == "driver");
    auto planner = find_method("rrt")->make(resolve_options(find_method("rrt")->options, {}));
    const PlannerContext ctx{*sys, sys->info().parameters, 3, PlannerLimits{10.0, 20000}, {}};
    const PlannerOutcome out = planner->solve(ctx);
    ASSERT_TRUE(out.trajectory) << policy << ": " << static_cast<int>(out.status);
    int off_grid = 0;
    for (const auto& piece : out.trajectory->pieces) {
      std::vector<double> lo(2), hi(2);
      sys->input_bounds(piece.mode, piece.x_start, lo, hi);
      for (int i = 0; i < 2; ++i) {
        EXPECT_GE(piece.u[i], lo[i]);
        EXPECT_LE(piece.u[i], hi[i]);
        off_grid += piece.u[i] != lo[i] && piece.u[i] != hi[i] && piece.u[i] != lo[i] + 0.5 * (hi[i] - lo[i]);
      }
    }
    if (std::string(policy) == "grid") EXPECT_EQ(off_grid, 0);
    else EXPECT_GT(off_grid, 0);
  }
}

// --- baseline RRT ----------------------------------------------------------------------------

TEST(NavigationRrt, FalsifiesASmallInstanceWithAValidWitness) {
  // The first (seed, property) of n = 4 whose start and unsafe terrains are adjacent through an
  // open passage, with a fast vehicle (not SDDrive) in the start terrain.
  std::optional<std::pair<int, int>> pick;
  for (int seed = 1; seed <= 50 && !pick; ++seed) {
    const NavigationInstance m = NavigationInstance::generate(4, seed, 1.0);
    for (int i = 0; i < NavigationInstance::kProperties && !pick; ++i) {
      const auto p = m.properties()[i];
      if (m.vehicle(p.start) == NavVehicle::sddrive) continue;
      for (NavSide s : kSides)
        if (m.open(p.start, s) && m.neighbour(p.start, s) == p.unsafe) pick = {seed, i};
    }
  }
  ASSERT_TRUE(pick);
  auto sys = make({{"n", "4"}, {"seed", std::to_string(pick->first)}, {"property", std::to_string(pick->second)}});
  auto planner = find_method("rrt")->make(resolve_options(find_method("rrt")->options, {}));
  const PlannerContext ctx{*sys, sys->info().parameters, 12345, PlannerLimits{15.0, 200'000}, {}};
  const PlannerOutcome out = planner->solve(ctx);
  ASSERT_EQ(out.status, TrialStatus::falsified) << "nodes " << out.counters.nodes;
  ASSERT_TRUE(out.trajectory);
  Witness w;
  w.suite = sys->info().suite;
  w.instance = sys->info().instance;
  w.method = "rrt";
  w.state_names = sys->info().state_names;
  w.input_names = sys->info().input_names;
  w.trajectory = *out.trajectory;
  const ValidationReport report = validate_witness(*sys, w);
  EXPECT_TRUE(report.valid) << report.reason;
  EXPECT_LE(report.final_spec, 1e-6);
  const auto m = navigation_instance(*sys);
  const Mode unsafe = m->properties()[pick->second].unsafe;
  const auto& fx = out.trajectory->final_x;
  EXPECT_EQ(m->terrain_at(fx[0], fx[1]) == unsafe || sys->spec(0, fx, {}) <= 0.0, true);
  std::printf("[navigation] rrt n = 4 seed %d property %d: %lld nodes, %zu pieces; %s\n", pick->first, pick->second,
              static_cast<long long>(out.counters.nodes), out.trajectory->pieces.size(), report.reason.c_str());
}

}  // namespace
}  // namespace hyfal
