// The aircraft conflict-resolution suite (seed 003 Sect. 6.1, seed 002 Sect. 4.2): what the tests
// and tools need beyond the System interface — the scenarios (hand-made 5-aircraft crossing,
// seed 002's random generator), the protocol's modes and state layout, the safer protocol's
// turn rule, and a System over any scenario. The constants and every modelling choice are
// documented in one place, at the top of suites/aircraft/aircraft.cpp.
#pragma once
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/model/system.hpp"
#include "core/simulate/model_system.hpp"

namespace hyfal {

// Per-aircraft protocol modes, packed 3 bits per aircraft into the Mode (ModePacking{3}).
//   heading:     ω = wrap(θ_goal − θ) (proportional turn toward the goal direction)
//   cruise:      ω = 0
//   avoid_right: after a −90° instantaneous turn, half circle with ω = +c (the original protocol)
//   avoid_left:  after a +90° instantaneous turn, half circle with ω = −c (safer protocol only)
//   arrived:     at the goal: stopped, out of the protocol and out of the specification
enum class AircraftMode : std::uint8_t { heading = 0, cruise = 1, avoid_right = 2, avoid_left = 3, arrived = 4 };
enum class AircraftProtocol : std::uint8_t { original = 0, safer = 1 };

// State layout: aircraft i owns x[kAircraftStride i .. +5) = (x, y, θ, τ, partner); the last
// state variable is the global time t. τ: clock of the current half circle (0 outside avoid);
// partner: 1 + the index of the aircraft this one is avoiding (0: none).
inline constexpr int kAircraftStride = 5;
inline constexpr int kMaxAircraft = 21;  // 3 bits per aircraft in a 64-bit Mode

struct AircraftScenario {
  std::vector<std::array<double, 2>> start, goal;  // km
  std::vector<double> heading;                     // initial θ, rad
  int size() const { return static_cast<int>(start.size()); }
};

struct AircraftConstants {
  double v = 0.3;              // forward speed, km/s
  double c = 0.03;             // turn rate of the half circle, rad/s
  double d = 1.0;              // collision distance, km
  double w = 0.03;             // wind bound: u = (d1, d2) in [−w, w]², km/s
  double goal_radius = 0.5;    // arrival: within this distance of the goal, km
  double heading_tolerance = 1e-3;  // heading -> cruise when |θ_goal − θ| < this, rad
  double retarget = 0.05;           // cruise -> heading when |θ_goal − θ| > this, rad
  double tie_margin = 1e-3;         // safer protocol: a turn pair must beat the earlier ones by this, km
  double refractory = 5.0;          // an avoiding aircraft ignores new conflicts this long after a turn, s
};

// Seed 002 Sect. 4.2.2, exact formulas (h = floor(N/2) top aircraft), drawn from `seed` with a
// platform-independent SplitMix64 stream. Initial headings point at the goals.
AircraftScenario aircraft_random_scenario(int n, double p, std::uint64_t seed);
// The hand-made 5-aircraft crossing for seed 003 Example 1 (see suites/aircraft/aircraft.cpp).
AircraftScenario aircraft_esposito5_scenario();

// Minimum distance between aircraft i at (x_i, y_i, θ_i) and j at (x_j, y_j, θ_j) when i turns
// instantaneously by turn_i (±π/2) and j by turn_j and both then fly half circles at speed v with
// ω = −sign(turn) c for π/c (no wind): the safer protocol's prediction (seed 002 Sect. 4.2.1).
double aircraft_halfcircle_min_distance(const std::array<double, 3>& i, double turn_i,
                                        const std::array<double, 3>& j, double turn_j, double v, double c);
// The safer rule: the pair (turn_i, turn_j) in {−π/2, +π/2}² with the largest predicted minimum
// distance; candidates in the order (−,−), (−,+), (+,−), (+,+), a later one replacing the best so
// far only when larger by more than tie_margin (so ties keep the original protocol's −90°/−90°).
std::array<double, 2> aircraft_safer_turns(const std::array<double, 3>& i, const std::array<double, 3>& j,
                                           const AircraftConstants& k);

// A System for `scenario`: all aircraft start in heading mode at global time 0; parameter p (the
// protect radius) has P = [p_lo, p_hi] and default p_default. step: δt; max_step: the
// integrator's largest step; input_levels: Ū = grid over [−w, w]².
struct AircraftSystemOptions {
  AircraftProtocol protocol = AircraftProtocol::original;
  AircraftConstants constants;
  double p_default = 5.25, p_lo = 5.25, p_hi = 5.25;
  double step = 20.0;
  double max_step = 0.5;
  int input_levels = 3;
  double lookahead = 20.0;  // HyDICE decomposition: horizon of the predicted closest approach, s
  Json instance = Json::object();  // SystemInfo::instance
};
std::shared_ptr<const System> make_aircraft_system(const AircraftScenario& scenario, const AircraftSystemOptions& o);

inline AircraftMode aircraft_mode(Mode q, int i) {
  return static_cast<AircraftMode>((q >> (3 * i)) & 7u);
}

// The resolved instance key of the suite -> the scenario it describes (throws
// std::invalid_argument on bad values).
AircraftScenario aircraft_scenario(const Json& instance);

}  // namespace hyfal
