// Aircraft conflict resolution — seed 003 Sect. 6.1 (Esposito, Kim & Kumar, RRFT: Example 1, eqs.
// 5-8, Fig. 5) and seed 002 Sect. 4.2 (Plaku, Kavraki & Vardi, HyDICE: the protocol, the safer
// protocol 4.2.1, random instances 4.2.2, Table 2). N aircraft fly from their starts to their
// goals under a conflict-resolution protocol; the wind is the adversarial input; unsafe = two
// aircraft closer than d. Units: km, s, rad.
//
// Dynamics (seed 003 eqs. 5-7), aircraft i:
//   x_i' = v cos θ_i + (−d1 sin θ_i + d2 cos θ_i)(−sin θ_i)
//   y_i' = v sin θ_i + (−d1 sin θ_i + d2 cos θ_i)( cos θ_i)      θ_i' = ω(q_i)
// i.e. the wind's component normal to the heading pushes the aircraft sideways; it never changes
// the along-track speed v. Seed 002 prints cos θ in y' — a typo (nothing could fly north).
// The wind u = (d1, d2) ∈ [−w, w]² is ONE vector for all aircraft: seed 003 counts 15 states for
// 5 aircraft and one input u(t) = [d1 d2]ᵀ, seed 002 writes "u1, u2 ∈ [−w, w] is the wind
// disturbance". Aircraft with different headings still drift differently (their normals differ);
// two aircraft on parallel or antiparallel headings drift alike. Ū = input_levels² grid over
// [−w, w]² (default 3 x 3: {−w, 0, w}²). input_affine = true.
// Constants (both papers): v = 0.3 km/s, c = 0.03 rad/s (half circle of radius v/c = 10 km, π/c
// = 104.7 s), d = 1 km, p = 5.25 km. w: seed 003's "‖u‖ ≤ 0.03 km/s" is read as the box
// [−0.03, 0.03]² of its u ∈ [−w, w] × [−w, w] (esposito5); seed 002 has w = 0.1 (random).
//
// State: per aircraft (x, y, θ, τ, partner), then the global time t (dim 5N + 1).
//   τ: clock of the current half circle (runs only in avoid, reset to 0 at each turn);
//   partner: 1 + index of the aircraft whose conflict started the current avoid (0: none);
//   t: time since the start (the decomposition's coverage axis; readable witnesses).
// Modes: per aircraft 3 bits (ModePacking{3}; N <= 21): H heading (ω = θ_goal − θ wrapped into
// [−π, π], θ_goal = direction from the aircraft to its goal: seed 002's "directed angle between
// the x-axis and (x_goal, y_goal)" read relative to the aircraft), C cruise (ω = 0), R avoid
// after a −90° turn (ω = +c: a right turn, then a left half circle — the papers' protocol), L
// avoid after a +90° turn (ω = −c; safer protocol only), G arrived (at rest, out of the protocol
// and out of the specification). mode_name: one letter per aircraft, e.g. "CRRCG".
// Transitions (all guards, urgent and localized; guard index k):
//   k = i < N, the aircraft's own:  H -> C when |θ_goal − θ| < 1e-3 (heading reached);
//     C -> H when |θ_goal − θ| > 0.05 (retargeting, ours: with ω = 0 the crosswind, up to 0.14
//     km/s sideways at w = 0.1, drifts a cruising aircraft off its bearing and it would miss its
//     goal by tens of km; the 1e-3 / 0.05 hysteresis means H and C cannot chatter);
//     R/L -> C when τ = π/c (half circle done): instantaneous turn θ := θ_goal (both papers), τ
//     and partner := 0.
//   k = N + i: arrival, |goal_i − (x_i, y_i)| < 0.5 km -> G (a point is never hit exactly; 0.5 km
//     is 1.7 s of flight, well inside every separation that matters).
//   k = 2N + pair index, pairs (i, j), i < j, in lexicographic order: the conflict guard
//       g = min(p − |(x_i, y_i) − (x_j, y_j)|,  τ_i − 5 s if i avoids,  τ_j − 5 s if j avoids)
//     while the pair is ARMED (both fly and neither's partner is the other), else −1. Jump: both
//     turn (original protocol: −90°, −90°; safer: the rule below), τ := 0, partners := each
//     other, modes R/L by the turn's sign.
//   Why: transitions fire at the last instant before g > 0, so the pair that just turned is on
//   the boundary of its p-disc; it must not re-trigger while its half circles keep it inside (the
//   papers' collisions are exactly such pairs "bumping into each other as they followed the
//   respective half-circles", seed 002) — the partner memory. Any other aircraft k within p of an
//   avoiding i triggers (i, k) (both papers: "another aircraft k comes within p distance to i"),
//   i turns again and its partner becomes k — but not within 5 s of i's last turn (the refractory
//   time τ − 5 in g, ours): with three aircraft within p of one another the partner memory alone
//   cannot disarm all three pairs, and they would turn each other forever at zero time (a Zeno
//   chain). Any refractory time > 0 prevents that; 1, 5 and 10 s gave the same collision rates
//   under random wind on random N = 10 instances (5 s = 1.5 km of flight, 5 % of a half circle).
//   The partner check also orders ties: two partners end their half circles at the same instant,
//   the one of lower index becomes C first, and the other must not be turned again before its
//   own circle ends. A pair still within p when both are back in cruise triggers at once.
//   (An earlier variant in which two avoiding aircraft ignored each other altogether made the
//   safer protocol 5-10 times likelier to collide under random wind; we keep the literal rule.)
// Safer protocol (seed 002 Sect. 4.2.1): the pair's turns (a_i, a_j) ∈ {−90°, +90°}² maximize
// the minimum distance along the two predicted half circles (closed-form circles, no wind, ω =
// −sign(a) c, over [0, π/c]), computed exactly: the difference of two such circles is a rotating
// vector (equal turns) or a point moving on a line (opposite turns), whose stationary points are
// closed forms (aircraft_halfcircle_min_distance). It was sampled before (64 intervals, then a
// golden section), which missed narrow dips and could choose the wrong turns (issue 11).
// Candidates in the order (−,−), (−,+), (+,−), (+,+); a later one replaces the best only when
// larger by more than 1 m, so ties keep the original protocol's turns, and the validator's
// re-simulated state (which differs from the tree's by ~1e-9) cannot flip a near-tie.
// Specification: s = min over pairs of flying aircraft of the distance − d (1000 km when fewer
// than two fly). Arrived aircraft are ignored: they have left the airspace (an aircraft crossing
// another's goal would otherwise "collide" with it without the protocol ever reacting).
// Invariant: none. P: one parameter, p (the protect radius).
// STL requirements (ours, `--set requirement=A2`): A1 `always (safety > 0)` (the papers' property);
// A2 `always (separation >= 2)` (twice d); A3 `always[0,600] (avoiding > 0 -> eventually[0,150]
// avoiding == 0)`: every conflict resolved within 150 s (a half circle takes 104.7 s, so A3 fails
// only when a manoeuvre is re-triggered). Signals: separation (km), avoiding, arrived, d1, d2, safety.
//
// Instances (`example`):
//  - esposito5 (seed 003 Example 1; the paper shows only a figure): five aircraft on a circle of
//    radius 40 km at 90° + 72° k, each bound for the diametrically opposite point and pointing at
//    it (heading mode ends at t = 0): all five converge on the centre at once, a symmetric
//    roundabout. P = [4.5, 5.5] (seed 003), default p = 5.25. Without wind it is safe: adjacent
//    pairs trigger at ~118 s, a second round of triggers follows 5 s later, minimum separation
//    3.7 km at p = 5.25 (3.1 at 4.5, 3.9 at 5.5), every aircraft arrives. With wind the triggers
//    come in an order the wind chooses and ~130 s later pairs meet again on their way home;
//    collisions come from such second encounters, a pair bumping on its half circles (t ≈ 250 s).
//    Collisions are reachable over the whole of P, and a larger p makes them rarer: random wind
//    (a new input of Ū every 5 s, 1000 runs) collides in 17 % of runs at p = 4.5, 14 % at 4.75,
//    7.4 % at 5.0, 3.3 % at 5.25, 0.9 % at 5.5; the planners need more nodes toward p = 5.5 too
//    (numbers below). So the upper end of P is the hard part, the paper's p = 5.25 in between.
//    We tried to make p = 4.5 safe and p = 5.25 unsafe (radius 30-50 km, goals at 30-60 km, goals
//    rotated by ±2-8° or displaced sideways by ±1-6 km; 400 random-wind runs per p): each variant
//    was safe at every p (rotated −5°: 0/400 everywhere), or rarer toward large p like this one,
//    or commoner toward large p but still easy at 4.5 (goals 2 km sideways: 7.5 % at 4.5, 17 % at
//    5.25), and 1-2° changes flipped the trend — the wind (up to 0.042 km/s sideways) moves the
//    encounters by kilometres, so no geometry gives a sharp threshold in p. We kept the plain
//    symmetric crossing.
//  - random (seed 002 Sect. 4.2.2, formulas exact): h = floor(N/2) aircraft start at the top,
//    the rest at the bottom (the paper's "i = h, ..., N" read as h+1..N); gap = (2.85 + 0.04 (N −
//    10)) p; top aircraft i = 1..h: x_init ~ U[init_i, init_i + p], init_i = −500 + (i − 1) gap,
//    y_init ~ U[250, 350], x_goal ~ U[goal_i, goal_i + p], goal_i = −420 + (i − 1) gap, y_goal ~
//    U[−350, −250]; bottom aircraft i = h+1..N: the same with i − h − 1 for i − 1 and the y
//    ranges swapped. Draws in the order x_init, y_init, x_goal, y_goal per aircraft, from a
//    SplitMix64 stream of `seed` (platform-independent). Initial headings point at the goals.
//    P = {p}. The papers use the safer protocol here (`--set protocol=safer`).
//
// Choices for the planners (none in the papers; kept here, in one place):
//  - δt (`step`) = 20 s (6 km of flight). The wind acts through its persistence: HyDICE draws one
//    input per extension. Tuning (HyDICE, random N = 10 safer, with the earlier conflict rule
//    above): δt = 5 s timed out (60 s) on each of seeds 1-3, 10 s solved 6 of seeds 2-9 within
//    30 s, 20 s all 8 (median 0.35 s), 40 s 6 of 8. On esposito5 (p = 5.25, 10 trials, 1M nodes)
//    HyDICE solved 8/10 at δt = 5 s, 10/10 at 10 s and 20 s; RRT solves it at any of them.
//  - Integration: Dormand-Prince (the heading mode's θ' = θ_goal − θ has a 1 s time constant,
//    fixed-step RK4 would need 0.1 s everywhere), tolerances 1e-10, max_step 0.5 s. Guards are
//    evaluated at step ends, and each also has a peak function (guard_peak, model.hpp): the
//    heading error for the 1e-3 band (a wind change flips the bearing's drift and the error
//    crosses the band in ~0.1 s, inside one step: issue 27 found a witness that missed it), and
//    the closest approach for the arrival and conflict discs; a sign change of it inside a step
//    makes the integrator look at the guard at the peak, so neither a crossed band nor a grazed
//    disc goes unseen. Witness tolerance 1e-6.
//  - x_rand: positions in the bounding box of starts and goals widened by 40 km (two half-circle
//    diameters), θ in [−π, π], τ in [0, π/c], partner in [0, N], t in [0, horizon] (horizon = the
//    longest start-goal distance / v + 2π/c).
//  - Metric (eq. 8, ρ = d + w_a |Δθ|, as a weighted Euclidean metric): weight 1 on every x_i, y_i,
//    w_a² = 1 (w_a = 1 km per rad) on θ_i, 0 on τ, partner and t.
//  - goal_point: every aircraft at the centre of the scene (s = −d); coverage grid (enhanced-rrt):
//    aircraft 0's position over the sampling box, spacing extent / 40.
//  - HyDICE decomposition (AircraftDecomposition; the paper gives none): regions are bands of the
//    PREDICTED closest approach between flying aircraft, [r d, (r + 1) d) for r = 0..15 (the last
//    open above): the smallest distance of any pair over the next `lookahead` = 20 s (= δt) if
//    both flew straight on at v along their headings (no wind, no turns); lookahead = 0 is the
//    current separation. The same in every mode (a jump does not move the aircraft, so no
//    REGIONTRANS edges are needed). G_D is the chain of bands, hops_to_unsafe(r) = r; band 0
//    (< d) is unsafe; every band has volume 1. Projection (t / δt · d / 8, predicted separation)
//    with coverage cells of d / 8: one cell per δt of time and 125 m of separation, so that the
//    motion planner spreads its selections over time and pushes the frontier (the conflicts of
//    random instances come after ~900 s, 45 extensions deep). Leads are thus "go down the bands";
//    HyDICE expands the least covered states among the closest approaches found so far.
//    Why predicted: in δt = 20 s two aircraft close by up to 12 km, so the separation at the end
//    states of the tree misses the near misses in between, and a state just before a crossing
//    looks far from unsafe. Measured (HyDICE, random safer, instance seeds 0-4, 30 s, one thread
//    each, two at a time; falsified count and times): N = 20, current separation (lookahead = 0):
//    3/5 (1.0, 1.4, 9.7 s); lookahead 20 s: 5/5 (0.85-3.8 s, median 1.5 s); 60 s: 4/5. N = 10
//    and 15 at 20 s: 3/5 and 4/5 (instance seed 1 is solved by no method at N = 10, 15 in 30 s).
//    A grid over (t, separation) was tried first: its leads ran through unreachable regions
//    (small separations at early times) and HyDICE timed out on random N = 10.
//
// Measured (this machine, 2 cores, one thread per trial, two trials at a time; `hyfal reproduce
// plaku-table2 --profile quick`, 2026-11-22): median time over instance seeds 0-4, 30 s limit —
// HyDICE 0.86 s [3/5] / 0.51 s [4/5] / 1.49 s [5/5] for N = 10 / 15 / 20 (paper 30.35 / 42.67 /
// 77.61 s), RRT ≥ 17.9 [3/5] / 7.2 [4/5] / ≥ 11.7 [3/5], RRT[D*] ≥ 30 [2/5] / 8.3 [4/5] / ≥ 30
// [2/5]; the 5-aircraft crossing: every method in 0.04-0.1 s. RRFT on esposito5 (10 trials):
// median 639 nodes, 4 seeds (the first Halton seeds already succeed), 0.12 s.
#include "suites/aircraft/aircraft.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>

#include <fmt/format.h>

#include "core/model/decomposition.hpp"
#include "core/run/paper_table.hpp"
#include "core/util/rng.hpp"
#include "suites/registry.hpp"

namespace hyfal {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kHalfPi = std::numbers::pi / 2;
constexpr int kStride = kAircraftStride;
constexpr double kFar = 1e3;  // s when fewer than two aircraft fly, km

double wrap(double a) { return std::remainder(a, 2 * kPi); }  // into [−π, π]


// Position at time t on the half circle that starts at (x, y) with heading th and turn rate om.
std::array<double, 2> on_circle(const std::array<double, 3>& s, double th, double om, double v, double t) {
  const double r = v / om;
  return {s[0] + r * (std::sin(th + om * t) - std::sin(th)), s[1] - r * (std::cos(th + om * t) - std::cos(th))};
}

}  // namespace

// --- scenarios ---------------------------------------------------------------------------------

AircraftScenario aircraft_random_scenario(int n, double p, std::uint64_t seed) {
  if (n < 2 || n > kMaxAircraft) throw std::invalid_argument(fmt::format("aircraft: N must be in [2, {}]", kMaxAircraft));
  if (!(p > 0.0) || !std::isfinite(p)) throw std::invalid_argument("aircraft: p must be > 0");
  AircraftScenario s;
  const int h = n / 2;
  const double gap = (2.85 + 0.04 * (n - 10)) * p;
  InstanceStream rng(seed, "aircraft/random-instance");
  for (int i = 1; i <= n; ++i) {
    const bool top = i <= h;
    const int slot = top ? i - 1 : i - h - 1;
    const double init = -500.0 + slot * gap, goal = -420.0 + slot * gap;
    const double xi = rng.uniform(init, init + p);
    const double yi = top ? rng.uniform(250.0, 350.0) : rng.uniform(-350.0, -250.0);
    const double xg = rng.uniform(goal, goal + p);
    const double yg = top ? rng.uniform(-350.0, -250.0) : rng.uniform(250.0, 350.0);
    s.start.push_back({xi, yi});
    s.goal.push_back({xg, yg});
    s.heading.push_back(std::atan2(yg - yi, xg - xi));
  }
  return s;
}

AircraftScenario aircraft_esposito5_scenario() {
  AircraftScenario s;
  constexpr double kRadius = 40.0;  // km
  for (int k = 0; k < 5; ++k) {
    const double phi = kHalfPi + 2 * kPi / 5 * k;
    s.start.push_back({kRadius * std::cos(phi), kRadius * std::sin(phi)});
    s.goal.push_back({-s.start.back()[0], -s.start.back()[1]});
    s.heading.push_back(std::atan2(s.goal.back()[1] - s.start.back()[1], s.goal.back()[0] - s.start.back()[0]));
  }
  return s;
}

// --- the safer protocol's rule ----------------------------------------------------------------

// Exact closest approach of the two predicted half circles. With φ = c t in [0, π], σ = +1 for a
// right avoidance (ω = +c) and −1 for a left one, R = v / c and e(α) = (sin α, −cos α), aircraft k
// flies P_k(φ) = C_k + σ_k R e(θ_k + σ_k φ) about its centre C_k = (x_k, y_k) − σ_k R e(θ_k), so
// D(φ) = P_i − P_j is one of two closed forms:
//   σ_i = σ_j = σ:  D = ΔC + Rot(σ φ) w with w = σ R (e(θ_i) − e(θ_j)), so |D|² = const +
//                   2 |ΔC| |w| cos(σ φ − β): a sinusoid, stationary where σ φ ≡ β (mod π);
//   σ_i = −σ_j:     D = ΔC + λ(φ) u with u = e((θ_i + θ_j)/2), λ = 2 σ_i R cos((θ_i − θ_j)/2 + σ_i φ)
//                   (sum-to-product), so D runs along a line and |D|² = |ΔC|² + 2 λ ΔC·u + λ² is
//                   stationary where λ = −ΔC·u or λ' = 0 (cos = ±1).
// A minimum over [0, π] lies at an endpoint or a stationary point; all of them are enumerated in
// closed form and |D| is evaluated there on the positions themselves (not through the expanded
// squares, which would cancel). So the result is the global minimum up to rounding (~1e-12 km):
// no sampling that a narrow dip could slip through (the former 64-interval grid with a golden
// section scored a pair of random N = 10, instance seed 3, 0.5624 km for a true 0.5238 km).
double aircraft_halfcircle_min_distance(const std::array<double, 3>& i, double turn_i,
                                        const std::array<double, 3>& j, double turn_j, double v, double c) {
  const double thi = i[2] + turn_i, thj = j[2] + turn_j;
  const double si = turn_i < 0 ? 1.0 : -1.0, sj = turn_j < 0 ? 1.0 : -1.0;
  const double omi = si * c, omj = sj * c;
  auto dist = [&](double phi) {
    const double t = phi / c;
    const auto a = on_circle(i, thi, omi, v, t), b = on_circle(j, thj, omj, v, t);
    return std::hypot(a[0] - b[0], a[1] - b[1]);
  };
  const double R = v / c;
  auto e = [](double alpha) { return std::array<double, 2>{std::sin(alpha), -std::cos(alpha)}; };
  const auto ei = e(thi), ej = e(thj);
  const double dC[2] = {(i[0] - si * R * ei[0]) - (j[0] - sj * R * ej[0]), (i[1] - si * R * ei[1]) - (j[1] - sj * R * ej[1])};

  double best = std::min(dist(0.0), dist(kPi));
  // φ with σ φ ≡ alpha (mod 2π), if it lies in [0, π].
  auto at_angle = [&](double sigma, double alpha) {
    double phi = std::fmod(sigma * alpha, 2 * kPi);
    if (phi < 0) phi += 2 * kPi;
    if (phi <= kPi) best = std::min(best, dist(phi));
  };
  if (si == sj) {
    const double w[2] = {si * R * (ei[0] - ej[0]), si * R * (ei[1] - ej[1])};
    // ΔC · Rot(α) w = p cos α + q sin α = |(p, q)| cos(α − β).
    const double pc = dC[0] * w[0] + dC[1] * w[1], qc = dC[1] * w[0] - dC[0] * w[1];
    const double beta = std::atan2(qc, pc);
    at_angle(si, beta);
    at_angle(si, beta + kPi);
  } else {
    const double kappa = (thi - thj) / 2;
    const auto u = e((thi + thj) / 2);
    const double target = -(dC[0] * u[0] + dC[1] * u[1]);  // the λ nearest the origin
    // λ = 2 σ_i R cos(κ + σ_i φ): the extremes (cos = ±1) and where λ = target.
    at_angle(si, -kappa);
    at_angle(si, kPi - kappa);
    const double g = target / (2 * si * R);
    if (g >= -1.0 && g <= 1.0) {
      const double a = std::acos(g);
      at_angle(si, a - kappa);
      at_angle(si, -a - kappa);
    }
  }
  return best;
}

std::array<double, 2> aircraft_safer_turns(const std::array<double, 3>& i, const std::array<double, 3>& j,
                                           const AircraftConstants& k) {
  static constexpr double kTurns[4][2] = {{-kHalfPi, -kHalfPi}, {-kHalfPi, kHalfPi}, {kHalfPi, -kHalfPi}, {kHalfPi, kHalfPi}};
  std::array<double, 2> best{kTurns[0][0], kTurns[0][1]};
  double best_d = aircraft_halfcircle_min_distance(i, kTurns[0][0], j, kTurns[0][1], k.v, k.c);
  for (int t = 1; t < 4; ++t) {
    const double dt = aircraft_halfcircle_min_distance(i, kTurns[t][0], j, kTurns[t][1], k.v, k.c);
    if (dt > best_d + k.tie_margin) best = {kTurns[t][0], kTurns[t][1]}, best_d = dt;
  }
  return best;
}

// --- the model ---------------------------------------------------------------------------------

namespace {

struct Pair {
  int i, j;
};

// The HyDICE decomposition (see the header comment): region r = the band
// [r d, (r + 1) d) of the minimum separation of the flying aircraft (the last band open above),
// mode-independent; G_D is the chain of bands; band 0 (separation < d) is unsafe. Projection
// (t / seconds_per_cell · d / 8, separation), so that coverage cells are δt by d / 8.
class AircraftDecomposition final : public Decomposition {
 public:
  static constexpr int kBands = 16;
  static constexpr double kCellsPerBand = 8.0;
  // horizon: the look-ahead of the predicted closest approach, s (0: the current separation).
  AircraftDecomposition(int n, double d, double v, double seconds_per_cell, double horizon)
      : n_(n), d_(d), v_(v), horizon_(horizon), time_scale_(d / kCellsPerBand / seconds_per_cell) {}
  RegionId region_of(Mode q, std::span<const double> x) const override {
    const int band = static_cast<int>(std::floor(predicted_separation(q, x) / d_));
    return static_cast<RegionId>(std::clamp(band, 0, kBands - 1));
  }
  double volume(RegionId) const override { return 1.0; }
  void neighbors(RegionId r, std::vector<RegionId>& out) const override {
    out.clear();
    if (r > 0) out.push_back(r - 1);
    if (r + 1 < kBands) out.push_back(r + 1);
  }
  bool is_unsafe(RegionId r) const override { return r == 0; }
  double hops_to_unsafe(RegionId r) const override { return static_cast<double>(r); }
  void project(Mode q, std::span<const double> x, std::span<double, 2> out) const override {
    out[0] = x[kStride * n_] * time_scale_;
    out[1] = std::min(predicted_separation(q, x), kBands * d_ * (1 - 1e-12));
  }
  double cell_size() const override { return d_ / kCellsPerBand; }

  // The smallest distance between two flying aircraft over [0, horizon] if every one flew straight
  // on at speed v along its heading from x (no wind, no turns; arrived aircraft do not count).
  double predicted_separation(Mode q, std::span<const double> x) const {
    double m = std::numeric_limits<double>::infinity();
    for (int i = 0; i < n_; ++i) {
      if (aircraft_mode(q, i) == AircraftMode::arrived) continue;
      const double vxi = v_ * std::cos(x[kStride * i + 2]), vyi = v_ * std::sin(x[kStride * i + 2]);
      for (int j = i + 1; j < n_; ++j) {
        if (aircraft_mode(q, j) == AircraftMode::arrived) continue;
        const double rx = x[kStride * j] - x[kStride * i], ry = x[kStride * j + 1] - x[kStride * i + 1];
        const double r2 = rx * rx + ry * ry;
        if (r2 - m > 0.0 && r2 > (2 * v_ * horizon_ + std::sqrt(m)) * (2 * v_ * horizon_ + std::sqrt(m)))
          continue;  // too far apart to come closer than m within the horizon
        const double wx = v_ * std::cos(x[kStride * j + 2]) - vxi, wy = v_ * std::sin(x[kStride * j + 2]) - vyi;
        const double w2 = wx * wx + wy * wy;
        const double t = w2 > 0.0 ? std::clamp(-(rx * wx + ry * wy) / w2, 0.0, horizon_) : 0.0;
        const double cx = rx + wx * t, cy = ry + wy * t;
        m = std::min(m, cx * cx + cy * cy);
      }
    }
    return std::sqrt(m);  // +inf when fewer than two fly: the top band
  }

 private:
  int n_;
  double d_, v_, horizon_, time_scale_;
};

class Aircraft {
 public:
  static constexpr bool input_affine = true;  // x', y' are linear in the wind

  Aircraft(const AircraftScenario& s, AircraftProtocol protocol, const AircraftConstants& k, int levels,
           double max_step, std::shared_ptr<const AircraftDecomposition> dec)
      : n_(s.size()), protocol_(protocol), k_(k), goal_(s.goal),
        reach_((k.v + std::sqrt(2.0) * k.w) * max_step), pair_change_(std::max(2.0 * reach_, max_step)),
        decomposition_(std::move(dec)),
        u_(InputSet::grid({{-k.w, -k.w}, {k.w, k.w}}, levels)) {
    for (int i = 0; i < n_; ++i)
      for (int j = i + 1; j < n_; ++j) pairs_.push_back({i, j});
  }

  int dim() const { return kStride * n_ + 1; }

  // Every aircraft's 3-bit field holds one of H, C, R, G (and L only under the safer protocol,
  // the only one that turns left), and the bits above the N fields are zero.
  bool valid_mode(Mode q) const {
    if ((q >> (3 * n_)) != 0) return false;  // 3 N <= 63 (kMaxAircraft)
    for (int i = 0; i < n_; ++i) {
      const auto m = static_cast<Mode>(aircraft_mode(q, i));
      if (m > static_cast<Mode>(AircraftMode::arrived)) return false;
      if (m == static_cast<Mode>(AircraftMode::avoid_left) && protocol_ != AircraftProtocol::safer) return false;
    }
    return true;
  }

  void flow(Mode q, const double* x, const double* u, const double*, double* dx) const {
    for (int i = 0; i < n_; ++i) {
      const double* a = x + kStride * i;
      double* da = dx + kStride * i;
      const AircraftMode m = aircraft_mode(q, i);
      da[4] = 0.0;
      if (m == AircraftMode::arrived) {
        da[0] = da[1] = da[2] = da[3] = 0.0;
        continue;
      }
      velocity(i, a, u, da[0], da[1]);
      switch (m) {
        case AircraftMode::heading: da[2] = heading_error(i, a); break;
        case AircraftMode::cruise: da[2] = 0.0; break;
        case AircraftMode::avoid_right: da[2] = k_.c; break;
        default: da[2] = -k_.c; break;
      }
      da[3] = avoiding(q, i) ? 1.0 : 0.0;
    }
    dx[kStride * n_] = 1.0;
  }

  int guard_count(Mode) const { return 2 * n_ + static_cast<int>(pairs_.size()); }

  double guard(Mode q, int k, const double* x, const double* p) const {
    if (k < n_) {  // the aircraft's own transition
      const double* a = x + kStride * k;
      switch (aircraft_mode(q, k)) {
        case AircraftMode::heading: return k_.heading_tolerance - std::abs(heading_error(k, a));
        case AircraftMode::cruise: return std::abs(heading_error(k, a)) - k_.retarget;
        case AircraftMode::avoid_right:
        case AircraftMode::avoid_left: return a[3] - kPi / k_.c;
        default: return -1.0;
      }
    }
    if (k < 2 * n_) {  // arrival
      const int i = k - n_;
      if (aircraft_mode(q, i) == AircraftMode::arrived) return -1.0;
      const double* a = x + kStride * i;
      const double gx = goal_[i][0] - a[0], gy = goal_[i][1] - a[1];
      return k_.goal_radius - std::sqrt(gx * gx + gy * gy);
    }
    const Pair& pr = pairs_[k - 2 * n_];  // conflict: two aircraft within p
    if (!armed(q, x, pr)) return -1.0;
    double g = p[0] - distance(x, pr.i, pr.j);
    if (avoiding(q, pr.i)) g = std::min(g, x[kStride * pr.i + 3] - k_.refractory);
    if (avoiding(q, pr.j)) g = std::min(g, x[kStride * pr.j + 3] - k_.refractory);
    return g;
  }

  // Where each guard peaks (model.hpp): the heading band |θ_goal − θ| < tol at e = 0 (a change of
  // wind flips the bearing's drift and e crosses the 2e-3 rad band in a fraction of a second, inside
  // one 0.5 s step); the arrival and conflict discs at the closest approach (relative position ·
  // relative velocity), where a grazing pass would otherwise go unseen between step ends. 0: no
  // peak to watch (cruise's retargeting fires outside a band, avoid's clock only rises).
  double guard_peak(Mode q, int k, const double* x, const double* u, const double*) const {
    if (k < n_) {
      if (aircraft_mode(q, k) != AircraftMode::heading) return 0.0;
      return heading_error(k, x + kStride * k);
    }
    if (k < 2 * n_) {
      const int i = k - n_;
      if (aircraft_mode(q, i) == AircraftMode::arrived) return 0.0;
      const double* a = x + kStride * i;
      const double gx = a[0] - goal_[i][0], gy = a[1] - goal_[i][1];
      double vx, vy;
      velocity(i, a, u, vx, vy);
      return gx * vx + gy * vy;
    }
    const Pair& pr = pairs_[k - 2 * n_];
    if (!armed(q, x, pr)) return 0.0;
    const double* a = x + kStride * pr.i;
    const double* b = x + kStride * pr.j;
    double vxa, vya, vxb, vyb;
    velocity(pr.i, a, u, vxa, vya);
    velocity(pr.j, b, u, vxb, vyb);
    return (a[0] - b[0]) * (vxa - vxb) + (a[1] - b[1]) * (vya - vyb);
  }

  // How far a guard can move in one integration step (of at most max_step): the arrival disc by
  // one aircraft's flight (reach_: v + |wind| over max_step), a conflict disc by two, or by the
  // refractory clock (rate 1). The aircraft's own guard: watched, without a bound, in heading mode
  // only (a few seconds at a time); in the other modes it has no peak (0: never watched).
  double guard_step_change(Mode q, int k) const {
    if (k < n_) return aircraft_mode(q, k) == AircraftMode::heading ? std::numeric_limits<double>::infinity() : 0.0;
    if (k < 2 * n_) return reach_;
    return pair_change_;
  }

  Mode jump(Mode q, int k, double* x, const double*) const {
    if (k < n_) {
      double* a = x + kStride * k;
      switch (aircraft_mode(q, k)) {
        case AircraftMode::heading: return set(q, k, AircraftMode::cruise);
        case AircraftMode::cruise: return set(q, k, AircraftMode::heading);
        default:  // end of the half circle: instantaneous turn toward the goal, cruise
          a[2] = bearing(k, a);
          a[3] = 0.0;
          a[4] = 0.0;
          return set(q, k, AircraftMode::cruise);
      }
    }
    if (k < 2 * n_) {
      double* a = x + kStride * (k - n_);
      a[3] = 0.0;
      a[4] = 0.0;
      return set(q, k - n_, AircraftMode::arrived);
    }
    const Pair& pr = pairs_[k - 2 * n_];
    std::array<double, 2> turn{-kHalfPi, -kHalfPi};
    if (protocol_ == AircraftProtocol::safer) {
      const double* a = x + kStride * pr.i;
      const double* b = x + kStride * pr.j;
      turn = aircraft_safer_turns({a[0], a[1], a[2]}, {b[0], b[1], b[2]}, k_);
    }
    const int who[2] = {pr.i, pr.j};
    for (int e = 0; e < 2; ++e) {
      double* a = x + kStride * who[e];
      a[2] = wrap(a[2] + turn[e]);
      a[3] = 0.0;
      a[4] = 1.0 + who[1 - e];
      q = set(q, who[e], turn[e] < 0 ? AircraftMode::avoid_right : AircraftMode::avoid_left);
    }
    return q;
  }

  bool invariant(Mode, const double*, const double*) const { return true; }

  double spec(Mode q, const double* x, const double*) const {
    double m2 = std::numeric_limits<double>::infinity();
    for (const Pair& pr : pairs_) {
      if (aircraft_mode(q, pr.i) == AircraftMode::arrived || aircraft_mode(q, pr.j) == AircraftMode::arrived) continue;
      m2 = std::min(m2, distance2(x, pr.i, pr.j));
    }
    return m2 == std::numeric_limits<double>::infinity() ? kFar : std::sqrt(m2) - k_.d;
  }

  const InputSet& inputs(Mode) const { return u_; }

  // Signals for STL requirements: the separation (the distance of the closest pair of flying
  // aircraft; kFar + d when fewer than two fly), and how many aircraft avoid and have arrived.
  void outputs(Mode q, const double* x, const double* u, const double* p, double* y) const {
    y[0] = spec(q, x, p) + k_.d;
    int avoiding = 0, arrived = 0;
    for (int i = 0; i < n_; ++i) {
      const AircraftMode m = aircraft_mode(q, i);
      avoiding += m == AircraftMode::avoid_right || m == AircraftMode::avoid_left;
      arrived += m == AircraftMode::arrived;
    }
    y[1] = avoiding;
    y[2] = arrived;
  }

  std::string mode_name(Mode q) const {
    static constexpr char kLetter[8] = {'H', 'C', 'R', 'L', 'G', '?', '?', '?'};
    std::string s;
    for (int i = 0; i < n_; ++i) s += kLetter[static_cast<int>(aircraft_mode(q, i))];
    return s;
  }

  const Decomposition* decomposition() const { return decomposition_.get(); }

 private:
  static Mode set(Mode q, int i, AircraftMode m) { return ModePacking{3}.set(q, i, static_cast<Mode>(m)); }
  double bearing(int i, const double* a) const { return std::atan2(goal_[i][1] - a[1], goal_[i][0] - a[0]); }
  // θ_goal − θ wrapped into [−π, π]: the angle from the heading to the goal direction.
  double heading_error(int i, const double* a) const {
    double cs, sn;
    trig(i, a[2], cs, sn);
    const double gx = goal_[i][0] - a[0], gy = goal_[i][1] - a[1];
    return std::atan2(cs * gy - sn * gx, cs * gx + sn * gy);
  }
  // Ground velocity of flying aircraft i (seed 003 eqs. 5-6): v along the heading plus the wind's
  // component normal to it.
  void velocity(int i, const double* a, const double* u, double& vx, double& vy) const {
    double cs, sn;
    trig(i, a[2], cs, sn);
    const double normal = -u[0] * sn + u[1] * cs;
    vx = k_.v * cs - normal * sn;
    vy = k_.v * sn + normal * cs;
  }
  static double distance(const double* x, int i, int j) {
    return std::sqrt(distance2(x, i, j));
  }
  static double distance2(const double* x, int i, int j) {
    const double dx = x[kStride * i] - x[kStride * j], dy = x[kStride * i + 1] - x[kStride * j + 1];
    return dx * dx + dy * dy;
  }
  // cos θ, sin θ of aircraft i, remembered per thread: a cruising or arrived aircraft keeps its
  // heading through a whole propagation, so most calls hit (the values are those of std::cos and
  // std::sin, bit for bit).
  static void trig(int i, double th, double& cs, double& sn) {
    struct Entry {
      double th = std::numeric_limits<double>::quiet_NaN(), c = 0.0, s = 0.0;
    };
    thread_local std::array<Entry, kMaxAircraft> cache;
    Entry& e = cache[i];
    if (e.th != th) e = {th, std::cos(th), std::sin(th)};
    cs = e.c;
    sn = e.s;
  }
  static bool avoiding(Mode q, int i) {
    const AircraftMode m = aircraft_mode(q, i);
    return m == AircraftMode::avoid_right || m == AircraftMode::avoid_left;
  }
  // A pair can trigger when both fly and neither is avoiding the other (see the header comment:
  // no re-trigger of a pair on its half circles, ties at the end of the half circles resolved
  // independently of the indices). The refractory time is part of the guard value (above).
  static bool armed(Mode q, const double* x, const Pair& pr) {
    if (aircraft_mode(q, pr.i) == AircraftMode::arrived || aircraft_mode(q, pr.j) == AircraftMode::arrived) return false;
    return std::abs(x[kStride * pr.i + 4] - (1.0 + pr.j)) > 0.5 && std::abs(x[kStride * pr.j + 4] - (1.0 + pr.i)) > 0.5;
  }

  int n_;
  AircraftProtocol protocol_;
  AircraftConstants k_;
  std::vector<std::array<double, 2>> goal_;
  std::vector<Pair> pairs_;
  double reach_;     // the farthest an aircraft flies in one integration step (guard_step_change), km
  double pair_change_;  // a conflict guard's largest change in one step: 2 reach_ or the refractory clock's
  std::shared_ptr<const AircraftDecomposition> decomposition_;
  InputSet u_;
};

}  // namespace

std::shared_ptr<const System> make_aircraft_system(const AircraftScenario& s, const AircraftSystemOptions& o) {
  const int n = s.size();
  if (n < 2 || n > kMaxAircraft) throw std::invalid_argument(fmt::format("aircraft: N must be in [2, {}]", kMaxAircraft));
  if (s.goal.size() != s.start.size() || s.heading.size() != s.start.size())
    throw std::invalid_argument("aircraft: scenario with inconsistent sizes");
  const AircraftConstants& k = o.constants;
  if (!(k.v > 0.0) || !(k.c > 0.0) || !(k.d > 0.0) || !(k.w >= 0.0))
    throw std::invalid_argument("aircraft: v, c, d must be > 0 and w >= 0");
  if (!(o.p_lo <= o.p_default && o.p_default <= o.p_hi && o.p_lo > k.d))
    throw std::invalid_argument("aircraft: need d < p_lo <= p <= p_hi");
  if (!(o.step > 0.0)) throw std::invalid_argument("aircraft: step must be > 0");
  if (!(o.max_step > 0.0 && o.max_step <= o.step)) throw std::invalid_argument("aircraft: max_step must be in (0, step]");
  if (o.input_levels < 2 || o.input_levels > 11) throw std::invalid_argument("aircraft: input_levels must be in [2, 11]");

  // The scene: bounding box of starts and goals, with a margin of two half-circle diameters.
  double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300}, longest = 0.0;
  for (int i = 0; i < n; ++i) {
    for (int a = 0; a < 2; ++a) {
      lo[a] = std::min({lo[a], s.start[i][a], s.goal[i][a]});
      hi[a] = std::max({hi[a], s.start[i][a], s.goal[i][a]});
    }
    longest = std::max(longest, std::hypot(s.goal[i][0] - s.start[i][0], s.goal[i][1] - s.start[i][1]));
  }
  const double margin = 4 * k.v / k.c;
  const double horizon = longest / k.v + 2 * kPi / k.c;  // the longest flight plus two half circles

  SystemInfo info;
  info.suite = "aircraft";
  info.instance = o.instance;
  std::vector<double> slo, shi, w;
  for (int i = 0; i < n; ++i) {
    for (const char* v : {"x", "y", "theta", "tau", "partner"}) info.state_names.push_back(fmt::format("a{}_{}", i, v));
    info.initial_state.insert(info.initial_state.end(), {s.start[i][0], s.start[i][1], s.heading[i], 0.0, 0.0});
    slo.insert(slo.end(), {lo[0] - margin, lo[1] - margin, -kPi, 0.0, 0.0});
    shi.insert(shi.end(), {hi[0] + margin, hi[1] + margin, kPi, kPi / k.c, static_cast<double>(n)});
    w.insert(w.end(), {1.0, 1.0, 1.0, 0.0, 0.0});
  }
  info.state_names.push_back("t");
  info.initial_state.push_back(0.0);
  slo.push_back(0.0);
  shi.push_back(horizon);
  w.push_back(0.0);
  info.input_names = {"d1", "d2"};
  info.input_units = {"km/s", "km/s"};
  info.outputs = {{"separation", "km", "distance of the closest pair of flying aircraft"},
                  {"avoiding", "", "aircraft in an avoidance half circle"},
                  {"arrived", "", "aircraft at their goals"}};
  info.requirements = {
      {"A1", "always (safety > 0)", "the papers' property: no two flying aircraft closer than d"},
      {"A2", "always (separation >= 2)", "separation of at least 2 km (twice d) at all times"},
      {"A3", "always[0,600] (avoiding > 0 -> eventually[0,150] avoiding == 0)",
       "every conflict is resolved (no aircraft avoiding) within 150 s"}};
  info.parameter_names = {"p"};
  info.parameter_box = {{o.p_lo}, {o.p_hi}};
  info.parameters = {o.p_default};
  info.initial_mode = 0;  // every aircraft in heading mode
  info.sampling_box = {slo, shi};
  info.metric_weights = w;
  const double cx = (lo[0] + hi[0]) / 2, cy = (lo[1] + hi[1]) / 2;
  for (int i = 0; i < n; ++i) info.goal_point.insert(info.goal_point.end(), {cx, cy, 0.0, 0.0, 0.0});
  info.goal_point.push_back(0.0);
  const double extent = std::max(hi[0] - lo[0], hi[1] - lo[1]) + 2 * margin;
  info.coverage = {{0, 1}, {{lo[0] - margin, lo[1] - margin}, {hi[0] + margin, hi[1] + margin}}, extent / 40};
  info.step_duration = o.step;
  info.integrator.kind = IntegratorKind::dopri5;
  info.integrator.step = std::min(0.1, o.max_step);
  info.integrator.max_step = o.max_step;
  info.integrator.abs_tol = 1e-10;
  info.integrator.rel_tol = 1e-10;
  info.witness_tolerance = 1e-6;
  auto dec = std::make_shared<const AircraftDecomposition>(n, k.d, k.v, o.step, o.lookahead);
  return std::make_shared<ModelSystem<Aircraft>>(Aircraft(s, o.protocol, k, o.input_levels, o.max_step, std::move(dec)),
                                                 std::move(info));
}

// --- the suite ---------------------------------------------------------------------------------

namespace {

struct Parsed {
  bool random = false;
  AircraftSystemOptions o;
  int n = 5;
  std::uint64_t seed = 1;
};

Parsed parse(const Json& instance) {
  Parsed r;
  const std::string example = instance.at("example").get<std::string>();
  const std::string protocol = instance.at("protocol").get<std::string>();
  if (example == "random")
    r.random = true;
  else if (example != "esposito5")
    throw std::invalid_argument(fmt::format("aircraft: example must be esposito5 or random, not '{}'", example));
  if (protocol == "safer")
    r.o.protocol = AircraftProtocol::safer;
  else if (protocol != "original")
    throw std::invalid_argument(fmt::format("aircraft: protocol must be original or safer, not '{}'", protocol));
  r.n = instance.at("N").get<int>();
  const std::int64_t seed = instance.at("seed").get<std::int64_t>();
  if (seed < 0) throw std::invalid_argument("aircraft: seed must be >= 0");
  r.seed = static_cast<std::uint64_t>(seed);
  const double p = instance.at("p").get<double>();
  AircraftConstants& k = r.o.constants;
  k.v = instance.at("v").get<double>();
  k.c = instance.at("c").get<double>();
  k.d = instance.at("d").get<double>();
  const double w = instance.at("w").get<double>();
  if (w < 0.0 && w != -1.0) throw std::invalid_argument("aircraft: w must be >= 0, or -1 for the example's wind bound");
  k.w = w >= 0.0 ? w : (r.random ? 0.1 : 0.03);
  r.o.step = instance.at("step").get<double>();
  r.o.max_step = instance.at("max_step").get<double>();
  r.o.lookahead = instance.at("lookahead").get<double>();
  if (!(r.o.lookahead >= 0.0)) throw std::invalid_argument("aircraft: lookahead must be >= 0");
  r.o.input_levels = instance.at("input_levels").get<int>();
  if (!(k.d > 0.0)) throw std::invalid_argument("aircraft: d must be > 0");
  if (r.random) {
    if (r.n < 2 || r.n > kMaxAircraft) throw std::invalid_argument(fmt::format("aircraft: N must be in [2, {}]", kMaxAircraft));
    if (!(p > k.d)) throw std::invalid_argument("aircraft: p must be > d");
    r.o.p_default = r.o.p_lo = r.o.p_hi = p;
  } else {
    r.n = 5;
    if (!(p >= 4.5 && p <= 5.5)) throw std::invalid_argument("aircraft: p must be in P = [4.5, 5.5] for esposito5");
    r.o.p_default = p;
    r.o.p_lo = 4.5;
    r.o.p_hi = 5.5;
  }
  r.o.instance = instance;
  return r;
}

std::shared_ptr<const System> make_aircraft(const Json& instance) {
  const Parsed r = parse(instance);
  return make_aircraft_system(aircraft_scenario(instance), r.o);
}

Json export_aircraft(const Json& instance) {
  const Parsed r = parse(instance);
  const AircraftScenario s = aircraft_scenario(instance);
  Json aircraft = Json::array();
  for (int i = 0; i < s.size(); ++i)
    aircraft.push_back({{"start", {s.start[i][0], s.start[i][1]}},
                        {"goal", {s.goal[i][0], s.goal[i][1]}},
                        {"heading", s.heading[i]}});
  const AircraftConstants& k = r.o.constants;
  return {{"format", "hyfal-aircraft/1"},
          {"suite", "aircraft"},
          {"instance", instance},
          {"protocol", r.o.protocol == AircraftProtocol::safer ? "safer" : "original"},
          {"N", s.size()},
          {"aircraft", std::move(aircraft)},
          {"P", {r.o.p_lo, r.o.p_hi}},
          {"p", r.o.p_default},
          {"constants",
           {{"v", k.v}, {"c", k.c}, {"d", k.d}, {"w", k.w}, {"goal_radius", k.goal_radius},
            {"heading_tolerance", k.heading_tolerance}, {"retarget", k.retarget}, {"tie_margin", k.tie_margin},
            {"refractory", k.refractory}, {"step", r.o.step}, {"max_step", r.o.max_step}}},
          {"units", "km, s, rad"}};
}

}  // namespace

AircraftScenario aircraft_scenario(const Json& instance) {
  const Parsed r = parse(instance);
  return r.random ? aircraft_random_scenario(r.n, r.o.p_default, r.seed) : aircraft_esposito5_scenario();
}

SuiteEntry aircraft_suite() {
  SuiteEntry e;
  e.name = "aircraft";
  e.description =
      "seed 003 Sect. 6.1 / seed 002 Sect. 4.2: N aircraft, conflict-resolution protocol (original or safer), "
      "wind input; unsafe = two aircraft within d";
  e.parameters = {
      {"example", "esposito5", "esposito5 (seed 003 Example 1, 5 aircraft) | random (seed 002 Sect. 4.2.2)", "esposito5|random"},
      {"protocol", "original", "original (always -90°) | safer (seed 002 Sect. 4.2.1)", "original|safer"},
      {"N", 10, "random: number of aircraft, 2..21", "[2, 21]"},
      {"seed", 1, "random: instance seed", "[0, inf)"},
      {"p", 5.25, "protect radius (avoid when closer), km; esposito5: the default of P = [4.5, 5.5]", "(0, 1000]"},
      {"d", 1.0, "collision distance, km", "(0, 1000]"},
      {"v", 0.3, "forward speed, km/s", "(0, 10]"},
      {"c", 0.03, "turn rate of the half circle, rad/s", "(0, 10]"},
      {"w", -1.0, "wind bound, u in [-w, w]^2 km/s; -1: the example's (esposito5 0.03, random 0.1)", "[-1, 10]"},
      {"step", 20.0, "duration δt of one tree extension, s", "[0.1, 1000]"},
      {"max_step", 0.5, "largest Dormand-Prince step (events shorter than this may be missed), s", "[0.0001, 100]"},
      {"input_levels", 3, "points per wind component in Ū (grid, endpoints included)", "[2, 11]"},
      {"lookahead", 20.0, "HyDICE regions: bands of the closest approach predicted this far ahead (straight flight), s", "[0, 1000]"}};
  e.make = make_aircraft;
  e.export_instance = export_aircraft;
  return e;
}

}  // namespace hyfal
