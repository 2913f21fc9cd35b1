// Navigation — seed 002 Sect. 4.1 (Plaku, Kavraki & Vardi, HyDICE; after Fehnker & Ivančić's
// navigation benchmark): a robotic vehicle whose second-order dynamics change with the terrain.
//
// Terrains and modes. The environment [0, n s]² is divided into n x n square terrains of side
// s = terrain_size; terrain q = row * n + col covers [col s, (col+1) s] x [row s, (row+1) s]
// and is mode q (Mode = terrain index, row-major). Its dynamics is drawn uniformly from
// {SCar, SUni, SDDrive} (seed 002 Sect. 4.1.3).
//
// State x = (x, y, θ, a, b), input u = (u0, u1), the same layout for the three vehicles
// (seed 002 Sect. 4.1.1, the paper's constants):
//   SCar    (a, b) = (v, φ):     x' = v cos θ, y' = v sin θ, θ' = v tan(φ) / L, v' = u0, φ' = u1
//           L = 0.8 m, |v| <= 3 m/s, |φ| <= 40°, |u0| <= 0.8 m/s², |u1| <= 25°/s
//   SUni    (a, b) = (v, ω):     x' = v cos θ, y' = v sin θ, θ' = ω, v' = u0, ω' = u1
//           |v| <= 3 m/s, |ω| <= 20°/s, |u0| <= 0.3 m/s², |u1| <= 10°/s²
//   SDDrive (a, b) = (ω_l, ω_r): x' = r/2 (ω_l + ω_r) cos θ, y' = r/2 (ω_l + ω_r) sin θ,
//           θ' = r (ω_r - ω_l) / L, ω_l' = u0, ω_r' = u1
//           r = 0.2 m, L = 0.8 m, |ω_l|, |ω_r| <= 5°/s, |u0|, |u1| <= 10°/s²
//   Taken literally, SDDrive's 5°/s wheels give a top speed r ω_max = 1.75 cm/s and a top turn
//   rate 2.5°/s: an SDDrive terrain would take about a minute to cross, 40 times slower than the
//   other two vehicles, and every SDDrive terrain a wall for the planners. We read the wheel
//   limits as 5 rad/s and 10 rad/s² (top speed 1 m/s, top turn rate 2.5 rad/s, like SCar and
//   SUni); `sddrive_wheel_unit=deg` gives the printed °/s, °/s².
// The bounds on (a, b) are part of the mode's invariant, not a saturation in the flow: a
// saturated right-hand side has a kink where fixed-step RK4 loses its order, and the witness
// validator (adaptive Dormand-Prince) would then disagree with the tree by O(ε²). With the
// invariant the flow stays smooth and a propagation that would exceed a bound stops at its last
// valid state (seed 002 Alg. 3); Ū contains u = 0 (odd input_levels), so the vehicle can cruise
// at a bound. input_affine = true (a' = u0, b' = u1).
//
// Walls (seed 002 Sect. 4.1.3). All 2n(n-1) interior walls are visited in a random order
// (Fisher-Yates shuffle); a wall between two terrains in distinct union-find sets is removed and
// the sets joined (randomized Kruskal: the removed walls form a spanning tree of the grid). Then
// each remaining wall is kept with probability p = 0.9 (removed with 0.1). The outer boundary
// is a wall. Storage: 2 bits per terrain (east/north side open), 2 bits per terrain for its
// vehicle; n = 1024 takes 512 KiB, generation needs a temporary 13 MB (shuffled wall list and
// union-find parents/ranks). No per-mode heap object; every lookup is O(1) bit arithmetic.
//
// Transitions. guard_count(q) = 4, guard k = side k (0 east, 1 north, 2 west, 3 south):
//   open side:  g_k = (distance of (x, y) beyond side k) - h, h = 1e-9 m; jump = the neighbour
//               across the side, with (a, b) := (0, 0) (the paper resets the velocity
//               components; and (a, b) mean different things in the next terrain's vehicle).
//   wall side:  g_k = -1 (never enabled); the invariant forbids (x, y) on or beyond the wall, so
//               a propagation into a wall stops at its last valid state (PropagationEnd::invariant).
//   Hysteresis h: transitions are taken at the last time before the guard turns positive, i.e.
//   within |v| * 1e-12 s of the crossing; with h = 0 the neighbour's guard back across the same
//   side would already be positive there and the vehicle would jump back at once, forever.
//   h = 1e-9 m is far above that localization error and physically irrelevant.
// Invariant of mode q: |a| <= a_max, |b| <= b_max of its vehicle, and (x, y) strictly inside
// the terrain or beyond an open side (at most h beyond it: the guard fires there).
//
// Drivers (seed 002 Sect. 4.1.2). The paper's drivers draw u from a state-dependent interval;
// in hyfal a method applies u from Ū_q, which cannot depend on the state. So Ū_q is a grid over
// the vehicle's input box (input_levels points per input, endpoints included; default 3: full
// negative / zero / full positive, 9 inputs), the same for every driver, and the drivers are
// navigation_driver_interval() (suites/navigation/navigation.hpp) for planners that draw u from them (the
// HyDICE planner). The pseudo-code is implemented literally, reading "0.0.2" as "0, 0.2":
//   Random  f(a,i,c,L,R) = [-m_i, m_i]
//   Student a in (0.2, 1]: [-L m_i, R(c-1) m_i]; a in [-1, -0.2): [R(1-c) m_i, L m_i]; else Random
//   Highway b in {0.4, 0.6, 0.8, 1}: a in (b-0.2, b]: [-L b m_i, R(c-b) m_i];
//           a in [-b, 0.2-b): [R(b-c) m_i, L b m_i]; else Random
//   SCar:    u0 = f(v/v_max, 0, 0.2, 1, 1),   u1 = Random
//   SUni:    u0 = f(v/v_max, 0, 0.2, 1, 1),   u1 = f(ω/ω_max, 1, 0.2, 1, 1)
//   SDDrive: u0 = f(a, 0, 1.2, 0, 0.25),      u1 = -f(a, 1, 1.2, 0, 0.25),  a = (ω_l+ω_r)/(2 ω_max)
// (m_i = the input's bound. As printed, Highway with c = 0.2 brakes whenever |a| > 0.2; we do
// not second-guess it.) The driver is part of the instance key.
//
// Input policy (`inputs`), the same for every method (a comparison of methods must not also be
// a comparison of input sets). driver (default): Alg. 3:1 of seed 002, "u <- sample control from
// U_q", is part of the one PropagateForward that every method of its experiments extends the tree
// with, and the drivers choose u "pseudo-uniformly at random" from their intervals (Sect.
// 4.1.2). So every method applies controls drawn from the driver's interval at the node: HyDICE
// one per propagation; a method that would try every input of Ū and keep the best toward x_rand
// (rrt, rrt-dstar, rrft, enhanced-rrt) draws driver_draws of them (default 1: the extension is
// then PropagateForward from x_near, as in the paper's baselines; core/search/input_grid.hpp). grid: Ū =
// the input_levels grid mapped onto the driver's interval, for every method (HyDICE with
// inputs=auto draws a random element of Ū). Measured (RRT, RandomDriver, 16², property 0, one
// core): driver_draws = 1 solved 3 of 3 trials in 14-31 s; best of 9 draws solved 1 of 2 in 60 s
// (9 propagations per extension, most of them from nodes that cannot move); the 3-level grid
// none in 20 s, and on StudentDriver 2² the grid's result hinged on the levels (no solution in
// 20 s at 3, 0.2 s at 5, 0.08 s at 7: 3 levels offer only full, zero or reversed acceleration).
//
// Safety properties (seed 002 Sect. 4.1.4): 40 per instance, (start, unsafe) terrains drawn
// uniformly from the instance seed, distinct. `property` picks one. Start: the centre of the
// start terrain, θ = 0, at rest. Unsafe: (x, y) in the unsafe terrain (closed square), any mode;
// s = signed Euclidean distance to that square (s <= 0 inside).
// n = 1 (the paper's 1² column): one terrain leaves no other terrain to be unsafe, yet the paper
// reports times for 1² as short as for 2² (0.1-0.4 s), i.e. a small but real task. We draw the
// start and unsafe places among the terrain's four quarters (distinct, from the same stream):
// start at the centre of one quarter, unsafe = another quarter (a square of side s/2, also one
// HyDICE region), no walls inside. NavigationInstance::place_box says which square a place is.
//
// Randomness: SplitMix64 streams keyed by (seed, purpose) — vehicles, wall order, wall keeping,
// properties — and Lemire's unbiased bounded integers, so an instance is identical on every
// platform (std::shuffle and std::uniform_int_distribution are implementation-defined). The
// maze does not depend on driver or property.
//
// Choices for the planners (the paper gives none; kept here, in one place):
//  - terrain_size s = 1 m (the unit cells of Fehnker & Ivančić's benchmark). From rest, SCar
//    crosses 1 m in 1.6 s, SUni in 2.6 s, SDDrive in 1.3 s (a minute with the printed °/s).
//  - T = step = 2 s per extension (about one terrain crossed at full speed; the drivers cap the
//    speed, so a shorter T needs more extensions per terrain: HyDICE at 1024², property 0, one
//    core: T = 1 s timed out in 300 s under Student and Highway (3.2-3.6M nodes), T = 2 s
//    solved them in 56 s and 39 s CPU); ε = integration_step = 0.01 s, fixed-step RK4 (the fastest
//    rate, SCar's θ' <= 3 tan 40° / 0.8 = 3.1 rad/s, bounds the RK4 error at ~1e-8 over an
//    extension, well inside the 1e-6 witness tolerance; RRT witnesses re-simulate to ~1e-12).
//  - x_rand: (x, y) over the whole environment, θ in [-π, π] (θ is not wrapped), a in [-3, 3],
//    b in [-40°, 40°] (the largest bounds over the three vehicles).
//  - Metric weights (1, 1, (0.1 s)², (0.1 s / 3)², (0.1 s / 40°)²): position dominates; a
//    radian of heading, the full speed range 3 m/s, or a full 40° of b each count as a tenth of
//    a terrain.
//  - goal_point: the centre of the unsafe terrain, θ = 0, at rest.
//  - HyDICE decomposition (seed 002 Sect. 3.2): 2 x 2 regions per terrain, neighbours across open
//    passages only, coverage cells of s / 16; hops_to_unsafe = the exact region distance in G_D
//    (a BFS once per instance), the lead search's A* heuristic (NavigationDecomposition below).
//  - Coverage grid over (x, y), spacing n s / min(4n, 1024): a quarter terrain up to n = 256,
//    then at most 1025 x 1025 points (spacing s at n = 1024, 4 MB of grid).
#include "suites/navigation/navigation.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <stdexcept>

#include <fmt/format.h>

#include "core/model/decomposition.hpp"
#include "core/util/rng.hpp"
#include "suites/registry.hpp"

namespace hyfal {

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kCarL = 0.8;       // SCar: distance between the axles, m
constexpr double kWheelR = 0.2;     // SDDrive: wheel radius, m
constexpr double kAxleL = 0.8;      // SDDrive: axle length, m
constexpr double kHysteresis = 1e-9;  // m, see the header
constexpr double kBoundSlack = 1.0 + 1e-9;  // relative slack on the |a|, |b| bounds

constexpr NavVehicleLimits kLimits[3] = {
    {3.0, 40.0 * kDeg, 0.8, 25.0 * kDeg},         // SCar: v, φ; u0 m/s², u1 rad/s
    {3.0, 20.0 * kDeg, 0.3, 10.0 * kDeg},         // SUni: v, ω; u0 m/s², u1 rad/s²
    {5.0, 5.0, 10.0, 10.0},                       // SDDrive: ω_l, ω_r rad/s; u rad/s² (read as rad: see header)
};
constexpr NavVehicleLimits kSDDriveDegrees = {5.0 * kDeg, 5.0 * kDeg, 10.0 * kDeg, 10.0 * kDeg};


NavSide side_of(int k) { return static_cast<NavSide>(k); }

}  // namespace

NavVehicleLimits navigation_limits(NavVehicle v, NavWheelUnit unit) {
  if (v == NavVehicle::sddrive && unit == NavWheelUnit::degrees) return kSDDriveDegrees;
  return kLimits[static_cast<int>(v)];
}

std::string_view navigation_vehicle_name(NavVehicle v) {
  switch (v) {
    case NavVehicle::scar: return "SCar";
    case NavVehicle::suni: return "SUni";
    case NavVehicle::sddrive: return "SDDrive";
  }
  return "?";
}

std::string_view navigation_driver_name(NavDriver d) {
  switch (d) {
    case NavDriver::random: return "random";
    case NavDriver::student: return "student";
    case NavDriver::highway: return "highway";
  }
  return "?";
}

NavDriver navigation_driver_from_name(std::string_view name) {
  if (name == "random") return NavDriver::random;
  if (name == "student") return NavDriver::student;
  if (name == "highway") return NavDriver::highway;
  throw std::invalid_argument(fmt::format("navigation: driver must be random, student or highway, not '{}'", name));
}

// --- the instance ------------------------------------------------------------------------------

NavigationInstance NavigationInstance::generate(int n, std::uint64_t seed, double terrain_size,
                                                double keep_probability) {
  if (n < 1 || n > 4096) throw std::invalid_argument("navigation: n must be in [1, 4096]");
  if (!(terrain_size > 0.0) || !std::isfinite(terrain_size))
    throw std::invalid_argument("navigation: terrain_size must be a finite number > 0");
  if (!(keep_probability >= 0.0 && keep_probability <= 1.0))
    throw std::invalid_argument("navigation: the wall keep probability must be in [0, 1]");
  NavigationInstance g;
  g.n_ = n;
  g.seed_ = seed;
  g.size_ = terrain_size;
  const std::uint32_t un = static_cast<std::uint32_t>(n);
  const std::uint32_t count = un * un;
  const std::size_t words = (count + 31) / 32;
  g.vehicles_.assign(words, 0);
  g.open_.assign(words, 0);

  InstanceStream vehicles(seed, "navigation/vehicles");
  for (std::uint32_t q = 0; q < count; ++q)
    g.vehicles_[q >> 5] |= vehicles.below(3) << ((q & 31) * 2);

  {  // Randomized Kruskal. Wall w = 2 q + d: the east (d = 0) or north (d = 1) side of q.
    std::vector<std::uint32_t> walls;
    walls.reserve(2 * static_cast<std::size_t>(un) * (un - 1));
    for (std::uint32_t q = 0; q < count; ++q) {
      if (q % un + 1 < un) walls.push_back(2 * q);
      if (q / un + 1 < un) walls.push_back(2 * q + 1);
    }
    InstanceStream order(seed, "navigation/wall-order");
    for (std::size_t i = walls.size(); i-- > 1;) std::swap(walls[i], walls[order.below(i + 1)]);  // n = 1: no walls
    std::vector<std::uint32_t> parent(count);
    std::vector<std::uint8_t> rank(count, 0);
    for (std::uint32_t q = 0; q < count; ++q) parent[q] = q;
    auto find = [&](std::uint32_t q) {
      while (parent[q] != q) q = parent[q] = parent[parent[q]];  // path halving
      return q;
    };
    std::uint32_t joined = 0;
    for (const std::uint32_t w : walls) {
      const std::uint32_t q = w >> 1, d = w & 1;
      std::uint32_t a = find(q), b = find(d ? q + un : q + 1);
      if (a == b) continue;
      if (rank[a] < rank[b]) std::swap(a, b);
      parent[b] = a;
      if (rank[a] == rank[b]) ++rank[a];
      g.open_[q >> 5] |= std::uint64_t{1} << ((q & 31) * 2 + d);
      if (++joined + 1 == count) break;  // the tree is complete: every other wall stays
    }
  }

  if (keep_probability < 1.0) {  // each remaining wall is kept with probability p
    InstanceStream keep(seed, "navigation/wall-keep");
    for (std::uint32_t q = 0; q < count; ++q)
      for (std::uint32_t d = 0; d < 2; ++d) {
        const bool exists = d == 0 ? q % un + 1 < un : q / un + 1 < un;
        if (!exists || g.bit(q, static_cast<int>(d))) continue;
        if (!(keep.uniform01() < keep_probability)) g.open_[q >> 5] |= std::uint64_t{1} << ((q & 31) * 2 + d);
      }
  }

  InstanceStream props(seed, "navigation/properties");
  const std::uint64_t places = g.places();
  for (auto& p : g.properties_) {
    p.start = static_cast<std::uint32_t>(props.below(places));
    p.unsafe = static_cast<std::uint32_t>(props.below(places - 1));
    if (p.unsafe >= p.start) ++p.unsafe;
  }
  return g;
}

NavigationInstance navigation_kruskal_tree(int n, std::uint64_t seed, double terrain_size) {
  return NavigationInstance::generate(n, seed, terrain_size, 1.0);
}

Mode NavigationInstance::terrain_at(double x, double y) const {
  auto cell = [this](double v) {
    double c = std::floor(v / size_);
    if (!(c >= 0.0)) c = 0.0;  // also NaN
    if (c > n_ - 1) c = n_ - 1;
    return static_cast<Mode>(c);
  };
  return cell(y) * static_cast<Mode>(n_) + cell(x);
}

std::size_t NavigationInstance::passages() const {
  std::size_t k = 0;
  for (const std::uint64_t w : open_) k += static_cast<std::size_t>(std::popcount(w));
  return k;
}

bool NavigationInstance::connected() const {
  const std::size_t count = terrains();
  std::vector<std::uint64_t> seen((count + 63) / 64, 0);
  std::vector<std::uint32_t> queue;
  queue.reserve(count);
  queue.push_back(0);
  seen[0] = 1;
  for (std::size_t head = 0; head < queue.size(); ++head) {
    const Mode q = queue[head];
    for (int k = 0; k < 4; ++k) {
      if (!open(q, side_of(k))) continue;
      const Mode r = neighbour(q, side_of(k));
      if (seen[r >> 6] >> (r & 63) & 1u) continue;
      seen[r >> 6] |= std::uint64_t{1} << (r & 63);
      queue.push_back(static_cast<std::uint32_t>(r));
    }
  }
  return queue.size() == count;
}

std::size_t NavigationInstance::memory_bytes() const {
  return (vehicles_.capacity() + open_.capacity()) * sizeof(std::uint64_t);
}

// --- drivers -------------------------------------------------------------------------------------

namespace {

struct Interval {
  double lo, hi;
};

// f(a, i, c, L, R) of seed 002 Sect. 4.1.2 with m = max_i; the bands are written with literal
// edges so that they partition [-1, 1] exactly in floating point.
//
// a is a normalized velocity, in [-1, 1] by the mode's invariant (|a| <= a_max). The stored
// state can lie a rounding error outside: one 2 s extension of SUni at full steering ends with
// ω = ω_max exactly in exact arithmetic, but RK4 stores 1.0000000000000007 ω_max (the invariant
// tolerates that, kBoundSlack). Read literally, such an a falls in no band and the driver would
// be Random there, admitting inputs that Student and Highway forbid. So f is evaluated at a
// clamped to the invariant's [-1, 1] (a NaN stays NaN and gets Random), and the interval is
// clamped to [-m, m] so that rounding in its products never leaves the input box.
Interval driver_f_bands(NavDriver d, double a, double m, double c, double L, double R) {
  const Interval any{-m, m};
  switch (d) {
    case NavDriver::random:
      return any;
    case NavDriver::student:
      if (a > 0.2 && a <= 1.0) return {-L * m + 0.0, R * (c - 1.0) * m + 0.0};
      if (a >= -1.0 && a < -0.2) return {R * (1.0 - c) * m + 0.0, L * m + 0.0};
      return any;
    case NavDriver::highway: {
      static constexpr double kEdge[5] = {0.2, 0.4, 0.6, 0.8, 1.0};  // b = kEdge[j + 1]
      for (int j = 0; j < 4; ++j)
        if (a > kEdge[j] && a <= kEdge[j + 1]) {
          const double b = kEdge[j + 1];
          return {-L * b * m + 0.0, R * (c - b) * m + 0.0};
        }
      for (int j = 0; j < 4; ++j)
        if (a >= -kEdge[j + 1] && a < -kEdge[j]) {
          const double b = kEdge[j + 1];
          return {R * (b - c) * m + 0.0, L * b * m + 0.0};
        }
      return any;
    }
  }
  return any;
}

Interval driver_f(NavDriver d, double a, double m, double c, double L, double R) {
  const double a_in = a > 1.0 ? 1.0 : a < -1.0 ? -1.0 : a;  // NaN passes through
  const Interval f = driver_f_bands(d, a_in, m, c, L, R);
  return {std::clamp(f.lo, -m, m), std::clamp(f.hi, -m, m)};
}

}  // namespace

DriverInterval navigation_driver_interval(NavDriver driver, NavVehicle vehicle, std::span<const double> x,
                                          NavWheelUnit unit) {
  const NavVehicleLimits lim = navigation_limits(vehicle, unit);
  Interval u0{}, u1{};
  switch (vehicle) {
    case NavVehicle::scar:
      u0 = driver_f(driver, x[3] / lim.a_max, lim.u0_max, 0.2, 1.0, 1.0);
      u1 = driver_f(NavDriver::random, 0.0, lim.u1_max, 0.0, 0.0, 0.0);
      break;
    case NavVehicle::suni:
      u0 = driver_f(driver, x[3] / lim.a_max, lim.u0_max, 0.2, 1.0, 1.0);
      u1 = driver_f(driver, x[4] / lim.b_max, lim.u1_max, 0.2, 1.0, 1.0);
      break;
    case NavVehicle::sddrive: {
      const double a = (x[3] + x[4]) / (2.0 * lim.a_max);
      u0 = driver_f(driver, a, lim.u0_max, 1.2, 0.0, 0.25);
      const Interval f1 = driver_f(driver, a, lim.u1_max, 1.2, 0.0, 0.25);
      u1 = {-f1.hi + 0.0, -f1.lo + 0.0};  // u1 = -f(...)
      break;
    }
  }
  return {{u0.lo, u1.lo}, {u0.hi, u1.hi}};
}

// --- the model ---------------------------------------------------------------------------------

namespace {

// The HyDICE decomposition (seed 002 Sect. 3.2.1): each terrain is a g x g grid of regions
// (g = kRegionGrid), region id = q g^2 + r_in g + c_in; G_D edges: the 8-neighbourhood inside a
// terrain, and across each open side of a terrain to the region straight across and its two
// diagonal neighbours there (REGIONTRANS; walls are known, so no edge crosses a wall). A region
// is unsafe when it lies in the unsafe terrain. Projection (x, y); coverage cells of side
// s / (g kCellsPerRegion).
constexpr int kRegionGrid = 2;
constexpr int kCellsPerRegion = 8;

class NavigationDecomposition final : public Decomposition {
 public:
  // `unsafe_place`: a property's unsafe place (a terrain; for n = 1 a quarter of terrain 0).
  NavigationDecomposition(std::shared_ptr<const NavigationInstance> maze, std::uint32_t unsafe_place)
      : maze_(std::move(maze)), unsafe_(maze_->place_mode(unsafe_place)), unsafe_place_(unsafe_place),
        hops_(maze_->terrains(), kFar) {
    // hops_to_unsafe(r) = the fewest G_D edges from region r to a region of the unsafe place:
    // a breadth-first search over the regions, level by level, from the unsafe place's regions
    // (G_D is symmetric: the 8-neighbourhood, and an edge across an open side has its reverse).
    // The exact region distance, not the terrain distance: a lead crosses a terrain in one or
    // two region edges (two where it enters and leaves on opposite sides), so the terrain hop
    // count underestimates a lead's length on unreached ground by up to 2x, and the A* of the
    // lead search (core/planners/hydice) then expanded every region with dist + h below the
    // lead's cost: 41 k regions a lead at 1024² against 1.2 k with the region distance.
    // Storage: the four regions of a terrain are mutually adjacent, so their distances differ
    // by at most 1; one word per terrain holds the smallest (kHopBits bits) and a 4-bit mask of
    // the regions one farther (4 MB at n = 1024, as the terrain distances took). The search
    // keeps only the current and the next level, and 4 bits a terrain marking the regions seen.
    std::vector<std::uint8_t> seen(maze_->terrains(), 0);
    std::vector<RegionId> level, next, nb;
    auto visit = [&](RegionId r, std::uint32_t d) {
      const Mode q = static_cast<Mode>(r / kG2);
      const std::uint8_t bit = static_cast<std::uint8_t>(1u << (r % kG2));
      if (seen[q] & bit) return false;
      seen[q] |= bit;
      if (hops_[q] == kFar) hops_[q] = d;  // the terrain's first region seen: the smallest
      else if (d > (hops_[q] & kHopMask)) hops_[q] |= std::uint32_t{bit} << kHopBits;
      return true;
    };
    if (maze_->n() == 1) {
      visit(unsafe_place_, 0);
      level.push_back(unsafe_place_);
    } else {
      for (RegionId c = 0; c < kG2; ++c) {
        visit(unsafe_ * kG2 + c, 0);
        level.push_back(unsafe_ * kG2 + c);
      }
    }
    for (std::uint32_t d = 1; !level.empty(); ++d) {
      if (d > kHopMask) throw std::length_error("navigation: region distances exceed the hop word");
      next.clear();
      for (RegionId r : level) {
        neighbors(r, nb);
        for (RegionId s : nb)
          if (visit(s, d)) next.push_back(s);
      }
      level.swap(next);
    }
  }
  RegionId region_of(Mode q, std::span<const double> x) const override {
    const auto lo = maze_->corner(q);
    const double side = maze_->terrain_size() / kRegionGrid;
    auto index = [&](double v) {
      double c = std::floor(v / side);
      if (!(c >= 0.0)) c = 0.0;
      if (c > kRegionGrid - 1) c = kRegionGrid - 1;
      return static_cast<RegionId>(c);
    };
    return q * kG2 + index(x[1] - lo[1]) * kRegionGrid + index(x[0] - lo[0]);
  }
  double volume(RegionId) const override {
    const double side = maze_->terrain_size() / kRegionGrid;
    return side * side;
  }
  void neighbors(RegionId r, std::vector<RegionId>& out) const override {
    out.clear();
    const Mode q = r / kG2;
    if constexpr (kRegionGrid == 2) {
      // The general loops below, unrolled for 2 x 2 regions a terrain, in the same order (the
      // lead search's tie-breaking follows it): the other three regions of the terrain, then
      // across the east, west, north and south sides the two regions of the adjoining column or
      // row (for g = 2 the region straight across and its diagonal neighbour are both of them).
      // The lead search calls this for every region it expands (10 % of a search at 1024²).
      const int cell = static_cast<int>(r % kG2), ri = cell / 2, ci = cell % 2;
      for (int c = 0; c < 4; ++c)
        if (c != cell) out.push_back(q * kG2 + static_cast<RegionId>(c));
      if (ci == 1 && maze_->open(q, NavSide::east)) {
        const RegionId b = maze_->neighbour(q, NavSide::east) * kG2;
        out.push_back(b + 0);
        out.push_back(b + 2);
      }
      if (ci == 0 && maze_->open(q, NavSide::west)) {
        const RegionId b = maze_->neighbour(q, NavSide::west) * kG2;
        out.push_back(b + 1);
        out.push_back(b + 3);
      }
      if (ri == 1 && maze_->open(q, NavSide::north)) {
        const RegionId b = maze_->neighbour(q, NavSide::north) * kG2;
        out.push_back(b + 0);
        out.push_back(b + 1);
      }
      if (ri == 0 && maze_->open(q, NavSide::south)) {
        const RegionId b = maze_->neighbour(q, NavSide::south) * kG2;
        out.push_back(b + 2);
        out.push_back(b + 3);
      }
      return;
    }
    const int ri = static_cast<int>(r % kG2) / kRegionGrid, ci = static_cast<int>(r % kG2) % kRegionGrid;
    const int g = kRegionGrid;
    for (int dr = -1; dr <= 1; ++dr)
      for (int dc = -1; dc <= 1; ++dc) {
        if (dr == 0 && dc == 0) continue;
        const int rr = ri + dr, cc = ci + dc;
        if (rr >= 0 && rr < g && cc >= 0 && cc < g) out.push_back(q * kG2 + static_cast<RegionId>(rr * g + cc));
      }
    auto across = [&](NavSide side, int edge_index, bool row_fixed, int fixed) {
      if (edge_index != (side == NavSide::east || side == NavSide::north ? g - 1 : 0)) return;
      if (!maze_->open(q, side)) return;
      const Mode q2 = maze_->neighbour(q, side);
      const int along = row_fixed ? ci : ri;
      for (int d = -1; d <= 1; ++d) {
        const int a = along + d;
        if (a < 0 || a >= g) continue;
        const int rr = row_fixed ? fixed : a, cc = row_fixed ? a : fixed;
        out.push_back(q2 * kG2 + static_cast<RegionId>(rr * g + cc));
      }
    };
    across(NavSide::east, ci, false, 0);
    across(NavSide::west, ci, false, g - 1);
    across(NavSide::north, ri, true, 0);
    across(NavSide::south, ri, true, g - 1);
  }
  // n = 1: the unsafe place is a quarter, i.e. region `unsafe_place_` of terrain 0 (regions are
  // the terrain's quarters, row-major, as the places).
  bool is_unsafe(RegionId r) const override { return maze_->n() == 1 ? r == unsafe_place_ : r / kG2 == unsafe_; }
  void project(Mode, std::span<const double> x, std::span<double, 2> out) const override {
    out[0] = x[0];
    out[1] = x[1];
  }
  double cell_size() const override { return maze_->terrain_size() / (kRegionGrid * kCellsPerRegion); }
  std::array<double, 2> centre(RegionId r) const override {
    const auto lo = maze_->corner(r / kG2);
    const double side = maze_->terrain_size() / kRegionGrid;
    const int ri = static_cast<int>(r % kG2) / kRegionGrid, ci = static_cast<int>(r % kG2) % kRegionGrid;
    return {lo[0] + (ci + 0.5) * side, lo[1] + (ri + 0.5) * side};
  }
  double hops_to_unsafe(RegionId r) const override {
    const std::uint32_t h = hops_[r / kG2];
    if (h == kFar) return std::numeric_limits<double>::infinity();
    return static_cast<double>((h & kHopMask) + ((h >> (kHopBits + r % kG2)) & 1u));
  }
  // Ids q g^2 + cell are dense over all modes: the planner's per-region data live in arrays.
  std::uint64_t dense_size() const override { return static_cast<std::uint64_t>(maze_->terrains()) * kG2; }
  std::uint64_t dense_index(RegionId r) const override { return r; }
  // The grid of terrains over (x, y) (each terrain's regions lie in its cell): OMPL's Syclop.
  std::optional<StateGrid> state_grid() const override {
    return StateGrid{{0, 1}, maze_->n(), {0.0, 0.0}, {maze_->extent(), maze_->extent()}};
  }

 private:
  static constexpr RegionId kG2 = static_cast<RegionId>(kRegionGrid) * kRegionGrid;
  static constexpr std::uint32_t kFar = std::numeric_limits<std::uint32_t>::max();
  static constexpr unsigned kHopBits = 28;  // 2^28 - 1 >= every distance up to n = 8192 (2^28 regions)
  static constexpr std::uint32_t kHopMask = (std::uint32_t{1} << kHopBits) - 1;
  std::shared_ptr<const NavigationInstance> maze_;
  Mode unsafe_;                 // the unsafe terrain
  std::uint32_t unsafe_place_;  // the property's unsafe place
  std::vector<std::uint32_t> hops_;  // per terrain: its regions' distances (see the constructor; kFar: unreachable)
};

class Navigation {
 public:
  static constexpr bool input_affine = true;  // a' = u0, b' = u1

  Navigation(std::shared_ptr<const NavigationInstance> maze, NavigationProperty property, NavDriver driver,
             NavWheelUnit unit, int levels)
      : maze_(std::move(maze)), property_(property), driver_(driver), unit_(unit), decomposition_(std::make_shared<NavigationDecomposition>(maze_, property.unsafe)) {
    static_assert(kRegionGrid == 2, "n = 1 places are the quarters = the regions of the one terrain");
    for (int v = 0; v < 3; ++v) {
      const NavVehicleLimits l = limits_[v] = navigation_limits(static_cast<NavVehicle>(v), unit);
      inputs_[v] = InputSet::grid({{-l.u0_max, -l.u1_max}, {l.u0_max, l.u1_max}}, levels);
    }
    unsafe_ = maze_->place_box(property.unsafe);
  }

  int dim() const { return 5; }
  void flow(Mode q, const double* x, const double* u, const double*, double* dx) const {
    const double c = std::cos(x[2]), s = std::sin(x[2]);
    switch (maze_->vehicle(q)) {
      case NavVehicle::scar:
        dx[0] = x[3] * c;
        dx[1] = x[3] * s;
        dx[2] = x[3] * std::tan(x[4]) / kCarL;
        break;
      case NavVehicle::suni:
        dx[0] = x[3] * c;
        dx[1] = x[3] * s;
        dx[2] = x[4];
        break;
      case NavVehicle::sddrive: {
        const double v = 0.5 * kWheelR * (x[3] + x[4]);
        dx[0] = v * c;
        dx[1] = v * s;
        dx[2] = kWheelR * (x[4] - x[3]) / kAxleL;
        break;
      }
    }
    dx[3] = u[0];
    dx[4] = u[1];
  }
  bool valid_mode(Mode q) const { return q < maze_->terrains(); }  // a terrain index
  int guard_count(Mode) const { return 4; }
  double guard(Mode q, int k, const double* x, const double*) const {
    return maze_->open(q, side_of(k)) ? beyond(q, k, x) - kHysteresis : -1.0;
  }
  Mode jump(Mode q, int k, double* x, const double*) const {
    x[3] = 0.0;
    x[4] = 0.0;
    return maze_->neighbour(q, side_of(k));
  }
  bool invariant(Mode q, const double* x, const double*) const {
    const NavVehicleLimits& l = limits_[static_cast<int>(maze_->vehicle(q))];
    // kBoundSlack: a bound is often met exactly (constant inputs from a grid, exact RK4 on the
    // linear a, b), where the rounding of two integrations (tree vs. validator) would decide.
    if (!(std::abs(x[3]) <= l.a_max * kBoundSlack && std::abs(x[4]) <= l.b_max * kBoundSlack)) return false;
    for (int k = 0; k < 4; ++k)
      if (!(beyond(q, k, x) < 0.0) && !maze_->open(q, side_of(k))) return false;
    return true;
  }
  double spec(Mode, const double* x, const double*) const { return navigation_box_spec(unsafe_, x); }
  // Signals for STL requirements: the position and the terrain (the mode).
  void outputs(Mode q, const double* x, const double*, const double*, double* y) const {
    y[0] = x[0];
    y[1] = x[1];
    y[2] = static_cast<double>(q);
  }
  bool outside_unsafe(Mode, const double* x, const double*) const { return navigation_outside_box(unsafe_, x); }
  const InputSet& inputs(Mode q) const { return inputs_[static_cast<int>(maze_->vehicle(q))]; }
  // The driver (seed 002 Sect. 4.1.2): u is drawn from a state-dependent interval. RandomDriver's
  // interval is U itself.
  bool state_dependent_inputs() const { return driver_ != NavDriver::random; }
  void input_bounds(Mode q, const double* x, double* lo, double* hi) const {
    const DriverInterval d = navigation_driver_interval(driver_, maze_->vehicle(q), std::span<const double>(x, 5), unit_);
    lo[0] = d.lo[0];
    lo[1] = d.lo[1];
    hi[0] = d.hi[0];
    hi[1] = d.hi[1];
  }
  std::string mode_name(Mode q) const {
    return fmt::format("{}(r{}c{} {})", q, maze_->row(q), maze_->col(q), navigation_vehicle_name(maze_->vehicle(q)));
  }
  const std::shared_ptr<const NavigationInstance>& maze() const { return maze_; }
  const Decomposition* decomposition() const { return decomposition_.get(); }

 private:
  // Signed distance of (x, y) beyond side k of terrain q (> 0: across it).
  double beyond(Mode q, int k, const double* x) const {
    const double s = maze_->terrain_size();
    const auto lo = maze_->corner(q);
    switch (k) {
      case 0: return x[0] - (lo[0] + s);
      case 1: return x[1] - (lo[1] + s);
      case 2: return lo[0] - x[0];
      default: return lo[1] - x[1];
    }
  }

  std::shared_ptr<const NavigationInstance> maze_;
  NavigationProperty property_;
  NavDriver driver_;
  NavWheelUnit unit_;
  NavVehicleLimits limits_[3];
  std::array<double, 4> unsafe_{};  // x_lo, y_lo, x_hi, y_hi
  std::shared_ptr<const NavigationDecomposition> decomposition_;
  InputSet inputs_[3];
};

using NavigationSystem = ModelSystem<Navigation>;

struct Parsed {
  int n = 0;
  std::uint64_t seed = 0;
  NavDriver driver = NavDriver::random;
  int property = 0;
  double terrain_size = 1.0, step = 1.0, integration_step = 0.01;
  int levels = 3;
  bool driver_draws = true;  // inputs=driver
  int draws = 1;             // driver_draws: inputs drawn per extension by the RRT-family methods
  NavWheelUnit wheel_unit = NavWheelUnit::radians;
};

Parsed parse(const Json& instance) {
  Parsed p;
  p.n = instance.at("n").get<int>();
  p.seed = static_cast<std::uint64_t>(instance.at("seed").get<std::int64_t>());
  p.driver = navigation_driver_from_name(instance.at("driver").get<std::string>());
  p.property = instance.at("property").get<int>();
  p.terrain_size = instance.at("terrain_size").get<double>();
  p.step = instance.at("step").get<double>();
  p.integration_step = instance.at("integration_step").get<double>();
  p.levels = instance.at("input_levels").get<int>();
  const std::string inputs = instance.at("inputs").get<std::string>();
  if (inputs != "driver" && inputs != "grid")
    throw std::invalid_argument(fmt::format("navigation: inputs must be driver or grid, not '{}'", inputs));
  p.driver_draws = inputs == "driver";
  p.draws = instance.at("driver_draws").get<int>();
  if (p.draws < 1 || p.draws > 441) throw std::invalid_argument("navigation: driver_draws must be in [1, 441]");
  const std::string unit = instance.at("sddrive_wheel_unit").get<std::string>();
  if (unit == "deg")
    p.wheel_unit = NavWheelUnit::degrees;
  else if (unit != "rad")
    throw std::invalid_argument(fmt::format("navigation: sddrive_wheel_unit must be rad or deg, not '{}'", unit));
  if (p.n < 1 || p.n > 4096) throw std::invalid_argument("navigation: n must be in [1, 4096]");
  if (p.property < 0 || p.property >= NavigationInstance::kProperties)
    throw std::invalid_argument("navigation: property must be in [0, 39]");
  if (!(p.terrain_size > 0.0)) throw std::invalid_argument("navigation: terrain_size must be > 0");
  if (!(p.step > 0.0)) throw std::invalid_argument("navigation: step must be > 0");
  if (!(p.integration_step > 0.0 && p.integration_step <= p.step))
    throw std::invalid_argument("navigation: integration_step must be in (0, step]");
  // Bounds the integration work of one propagation (a tiny integration_step must not make one
  // extension take minutes).
  if (p.step / p.integration_step > 1e4)
    throw std::invalid_argument("navigation: step / integration_step must be <= 10000");
  if (p.levels < 2 || p.levels > 21) throw std::invalid_argument("navigation: input_levels must be in [2, 21]");
  return p;
}

// STL requirements (ours; the instance's terrains are written into them): N1 the paper's property;
// N2 "the unsafe terrain is not reached before the vehicle has passed through a checkpoint
// terrain", the checkpoint being the unsafe terrain of the next property (or of the one after, if
// that is this property's start or unsafe terrain): `not (A until B)` with A = not in the
// checkpoint, B = unsafe (until: B at some sample, A from the start through it); N3 the property
// over the first 20 s only.
std::vector<DeclaredRequirement> navigation_requirements(const NavigationInstance& maze, int property) {
  const auto& all = maze.properties();
  const NavigationProperty& mine = all[property];
  Mode checkpoint = maze.place_mode(mine.unsafe);
  for (int k = 1; k < NavigationInstance::kProperties; ++k) {
    checkpoint = maze.place_mode(all[(property + k) % NavigationInstance::kProperties].unsafe);
    if (checkpoint != maze.place_mode(mine.unsafe) && checkpoint != maze.place_mode(mine.start)) break;
  }
  return {{"N1", "always (safety > 0)", "the paper's property: never in the unsafe terrain"},
          {"N2", fmt::format("not ((terrain != {}) until (safety <= 0))", checkpoint),
           fmt::format("the unsafe terrain is not reached before passing through terrain {}", checkpoint)},
          {"N3", "always[0,20] (safety > 0)", "not in the unsafe terrain within the first 20 s"}};
}

std::shared_ptr<const System> make_navigation(const Json& instance) {
  const Parsed p = parse(instance);
  auto maze = std::make_shared<const NavigationInstance>(NavigationInstance::generate(p.n, p.seed, p.terrain_size));
  const NavigationProperty prop = maze->properties()[p.property];
  const double s = p.terrain_size, extent = maze->extent();
  const double phi_max = kLimits[0].b_max, v_max = kLimits[0].a_max;

  SystemInfo info;
  info.suite = "navigation";
  info.instance = instance;
  info.state_names = {"x", "y", "theta", "a", "b"};
  info.input_names = {"u0", "u1"};
  info.outputs = {{"x", "m", "position"}, {"y", "m", "position"}, {"terrain", "", "the terrain's index, row * n + col (the mode)"}};
  info.requirements = navigation_requirements(*maze, p.property);
  info.initial_mode = maze->place_mode(prop.start);
  const auto b0 = maze->place_box(prop.start);
  info.initial_state = {0.5 * (b0[0] + b0[2]), 0.5 * (b0[1] + b0[3]), 0.0, 0.0, 0.0};
  info.sampling_box = {{0.0, 0.0, -std::numbers::pi, -v_max, -phi_max},
                       {extent, extent, std::numbers::pi, v_max, phi_max}};
  const double tenth = 0.1 * s;
  info.metric_weights = {1.0, 1.0, tenth * tenth, (tenth / v_max) * (tenth / v_max),
                         (tenth / phi_max) * (tenth / phi_max)};
  const auto bu = maze->place_box(prop.unsafe);
  info.goal_point = {0.5 * (bu[0] + bu[2]), 0.5 * (bu[1] + bu[3]), 0.0, 0.0, 0.0};
  info.coverage = {{0, 1}, {{0.0, 0.0}, {extent, extent}}, extent / std::min(4 * p.n, 1024)};
  info.step_duration = p.step;
  info.continuous_random_inputs = p.driver_draws;  // inputs=driver: see "Input policy" in the header
  info.random_inputs_per_extension = p.draws;
  info.integrator.kind = IntegratorKind::rk4;
  info.integrator.step = p.integration_step;
  info.integrator.max_step = p.integration_step;
  info.witness_tolerance = 1e-6;
  return std::make_shared<NavigationSystem>(Navigation(std::move(maze), prop, p.driver, p.wheel_unit, p.levels), std::move(info));
}

}  // namespace

std::shared_ptr<const NavigationInstance> navigation_instance(const System& system) {
  const auto* nav = dynamic_cast<const NavigationSystem*>(&system);
  return nav ? nav->model().maze() : nullptr;
}

Json navigation_instance_json(const Json& instance) {
  const Parsed p = parse(instance);
  const NavigationInstance maze = NavigationInstance::generate(p.n, p.seed, p.terrain_size);
  const Mode count = maze.terrains();
  std::string dynamics(count, '?');
  static constexpr char kCode[3] = {'C', 'U', 'D'};
  Json passages = Json::array();
  for (Mode q = 0; q < count; ++q) {
    dynamics[q] = kCode[static_cast<int>(maze.vehicle(q))];
    if (maze.open(q, NavSide::east)) passages.push_back({q, q + 1});
    if (maze.open(q, NavSide::north)) passages.push_back({q, q + p.n});
  }
  Json properties = Json::array();
  for (const auto& pr : maze.properties()) properties.push_back({pr.start, pr.unsafe});
  Json constants = Json::object();
  for (int v = 0; v < 3; ++v) {
    const NavVehicleLimits l = navigation_limits(static_cast<NavVehicle>(v), p.wheel_unit);
    constants[std::string(navigation_vehicle_name(static_cast<NavVehicle>(v)))] = {
        {"a_max", l.a_max}, {"b_max", l.b_max}, {"u0_max", l.u0_max}, {"u1_max", l.u1_max}};
  }
  constants["SCar"]["L"] = kCarL;
  constants["SDDrive"]["r"] = kWheelR;
  constants["SDDrive"]["L"] = kAxleL;
  constants["wall_keep_probability"] = NavigationInstance::kKeepWall;
  constants["transition_hysteresis"] = kHysteresis;
  return {{"format", "hyfal-navigation/1"},
          {"suite", "navigation"},
          {"instance", instance},
          {"n", p.n},
          {"seed", instance.at("seed")},
          {"terrain_size", p.terrain_size},
          {"driver", std::string(navigation_driver_name(p.driver))},
          {"property", p.property},
          {"layout", "terrain q = row * n + col covers [col s, (col+1) s] x [row s, (row+1) s]; "
                     "state (x, y, theta, a, b): SCar (a, b) = (v, phi), SUni (v, omega), "
                     "SDDrive (omega_l, omega_r)"},
          {"vehicles", {{"C", "SCar"}, {"U", "SUni"}, {"D", "SDDrive"}}},
          {"dynamics", std::move(dynamics)},
          {"passages", std::move(passages)},
          {"properties", std::move(properties)},
          {"property_places", p.n == 1 ? "quarters" : "terrains"},
          {"constants", std::move(constants)}};
}

SuiteEntry navigation_suite() {
  return {"navigation",
          "seed 002 Sect. 4.1: n x n terrains (SCar/SUni/SDDrive), Kruskal maze walls; reach the unsafe terrain",
          {{"n", 4, "terrains per side (|Q| = n^2 modes), 1..4096 (n = 1: start and unsafe are quarters of the one terrain)", "[1, 4096]"},
           {"seed", 1, "instance seed: dynamics per terrain, walls, the 40 properties", "[0, inf)"},
           {"driver", "random", "driver model: random | student | highway (for planners that use it)", "random|student|highway"},
           {"property", 0, "which of the instance's 40 (start, unsafe) properties, 0..39", "[0, 39]"},
           {"terrain_size", 1.0, "side of one terrain, m", "[0.01, 1000]"},
           {"step", 2.0, "duration T of one tree extension, s", "[0.01, 100]"},
           {"integration_step", 0.01, "RK4 step ε, s", "[1e-5, 10]"},
           {"input_levels", 3, "points per input dimension in Ū (grid over U, endpoints included), used with inputs=grid", "[2, 21]"},
           {"driver_draws", 1, "with inputs=driver: controls drawn per extension by the methods that keep the best of several (rrt, rrt-dstar, rrft, enhanced-rrt); HyDICE draws one", "[1, 441]"},
           {"inputs", "driver", "input policy of every method: driver (u drawn uniformly from the driver's interval, Sect. 4.1.2) or grid (Ū mapped onto it)", "driver|grid"},
           {"sddrive_wheel_unit", "rad", "SDDrive's wheel limits 5 and 10 read as rad/s, rad/s² (rad) or as printed, °/s, °/s² (deg)", "rad|deg"}},
          make_navigation,
          navigation_instance_json};
}

}  // namespace hyfal
