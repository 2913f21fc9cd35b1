// The navigation benchmark of seed 002 Sect. 4.1 (Plaku, Kavraki & Vardi, HyDICE): a robotic
// vehicle on an n x n grid of square terrains, one mode per terrain, each terrain with its own
// second-order dynamics (SCar, SUni or SDDrive), walls from a randomized Kruskal maze.
//
// This header is for the code that needs more than the System interface: the HyDICE planner
// (the terrain graph for its discrete search, the driver models for its input choice), the
// instance export, and tests. The constants and every modelling choice are documented in one
// place, at the top of suites/navigation/navigation.cpp.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/model/system.hpp"
#include "core/simulate/model_system.hpp"

namespace hyfal {

// The three second-order vehicles of seed 002 Sect. 4.1.1. The common state layout is
// x = (x, y, θ, a, b); (a, b) are the velocity-like components:
//   SCar:    a = v  [m/s]  (speed),            b = φ   [rad]   (steering angle)
//   SUni:    a = v  [m/s]  (speed),            b = ω   [rad/s] (turn rate)
//   SDDrive: a = ω_l [rad/s] (left wheel),     b = ω_r [rad/s] (right wheel)
// and u = (u0, u1) drives them: a' = u0, b' = u1 for all three.
enum class NavVehicle : std::uint8_t { scar = 0, suni = 1, sddrive = 2 };
enum class NavDriver : std::uint8_t { random = 0, student = 1, highway = 2 };
// Sides of a terrain; also the guard index k of the transition across that side.
enum class NavSide : int { east = 0, north = 1, west = 2, south = 3 };

struct NavVehicleLimits {
  double a_max, b_max;    // |a| <= a_max, |b| <= b_max (part of the mode's invariant)
  double u0_max, u1_max;  // U = [-u0_max, u0_max] x [-u1_max, u1_max]
};
// How SDDrive's printed wheel limits "5°/s, 10°/s²" are read (see suites/navigation/navigation.cpp).
enum class NavWheelUnit : std::uint8_t { radians = 0, degrees = 1 };
NavVehicleLimits navigation_limits(NavVehicle v, NavWheelUnit unit = NavWheelUnit::radians);
std::string_view navigation_vehicle_name(NavVehicle v);  // "SCar", "SUni", "SDDrive"
std::string_view navigation_driver_name(NavDriver d);    // "random", "student", "highway"
NavDriver navigation_driver_from_name(std::string_view name);  // throws std::invalid_argument

// One safety property: start at the centre of place `start` (heading 0, at rest); unsafe =
// inside place `unsafe` (start != unsafe). The places are the terrains, except for n = 1, where
// they are the one terrain's four quarters (NavigationInstance::place_box).
struct NavigationProperty {
  std::uint32_t start = 0, unsafe = 0;
};

// One generated instance: the terrain grid, its dynamics and walls, and its 40 properties.
// Compact: 2 bits per terrain for the vehicle and 2 bits per terrain for the passages through
// its east and north sides (the west/south ones are the neighbours' east/north), so n = 1024
// takes 512 KiB; every lookup is O(1) bit arithmetic. Terrain q = row * n + col covers
// [col s, (col+1) s] x [row s, (row+1) s], s = terrain_size.
class NavigationInstance {
 public:
  static constexpr int kProperties = 40;
  static constexpr double kKeepWall = 0.9;  // seed 002 Sect. 4.1.3

  // Vehicles, Kruskal maze, then each wall the maze kept is kept with probability
  // keep_probability (the paper's p = 0.9; 1.0 gives the bare spanning tree), then the
  // properties; all drawn from `seed` with platform-independent generators (SplitMix64
  // streams), so an instance is the same on every compiler and machine. 1 <= n <= 4096.
  static NavigationInstance generate(int n, std::uint64_t seed, double terrain_size,
                                     double keep_probability = kKeepWall);

  int n() const { return n_; }
  std::uint64_t seed() const { return seed_; }
  double terrain_size() const { return size_; }
  double extent() const { return size_ * n_; }  // the environment is [0, extent]^2
  std::size_t terrains() const { return static_cast<std::size_t>(n_) * n_; }
  int row(Mode q) const { return static_cast<int>(q / n_); }
  int col(Mode q) const { return static_cast<int>(q % n_); }

  NavVehicle vehicle(Mode q) const {
    return static_cast<NavVehicle>((vehicles_[q >> 5] >> ((q & 31) * 2)) & 3u);
  }
  // True when the side is an open passage (a transition both ways); false for a wall,
  // including the outer boundary of the environment.
  bool open(Mode q, NavSide s) const {
    switch (s) {
      case NavSide::east: return bit(q, 0);
      case NavSide::north: return bit(q, 1);
      case NavSide::west: return col(q) > 0 && bit(q - 1, 0);
      case NavSide::south: return row(q) > 0 && bit(q - n_, 1);
    }
    return false;
  }
  // The terrain across side s (precondition: it exists, e.g. open(q, s)).
  Mode neighbour(Mode q, NavSide s) const {
    switch (s) {
      case NavSide::east: return q + 1;
      case NavSide::north: return q + n_;
      case NavSide::west: return q - 1;
      case NavSide::south: return q - n_;
    }
    return q;
  }
  // The terrain containing (x, y) (points on a shared side go to the east/north terrain;
  // points outside the environment are clamped to the nearest terrain). O(1).
  Mode terrain_at(double x, double y) const;
  // Lower-left corner and centre of terrain q.
  std::array<double, 2> corner(Mode q) const { return {col(q) * size_, row(q) * size_}; }
  std::array<double, 2> centre(Mode q) const { return {(col(q) + 0.5) * size_, (row(q) + 0.5) * size_}; }

  const std::array<NavigationProperty, kProperties>& properties() const { return properties_; }
  // The places a property's start and unsafe set are drawn from: the n² terrains; for n = 1 (the
  // paper's 1² column: one terrain has no other terrain to be unsafe) its 2 x 2 quarters, place
  // i = (row, col) = (i / 2, i % 2), each the square of side s/2 (and, for HyDICE, exactly one
  // decomposition region). Where n >= 2 a place is a terrain.
  std::uint32_t places() const { return n_ == 1 ? 4u : static_cast<std::uint32_t>(terrains()); }
  Mode place_mode(std::uint32_t place) const { return n_ == 1 ? 0 : place; }
  std::array<double, 4> place_box(std::uint32_t place) const {  // x_lo, y_lo, x_hi, y_hi
    if (n_ != 1) return {corner(place)[0], corner(place)[1], corner(place)[0] + size_, corner(place)[1] + size_};
    const double h = 0.5 * size_, x = (place % 2) * h, y = (place / 2) * h;
    return {x, y, x + h, y + h};
  }

  std::size_t passages() const;          // number of open passages (undirected)
  bool connected() const;                // every terrain reachable through open passages (BFS)
  std::size_t memory_bytes() const;      // heap bytes held by this object

 private:
  bool bit(Mode q, int which) const { return (open_[q >> 5] >> ((q & 31) * 2 + which)) & 1u; }
  int n_ = 0;
  std::uint64_t seed_ = 0;
  double size_ = 1.0;
  std::vector<std::uint64_t> vehicles_;  // 2 bits per terrain, 32 terrains per word
  std::vector<std::uint64_t> open_;      // bit 0: east side open, bit 1: north side open
  std::array<NavigationProperty, kProperties> properties_{};
};

// The Kruskal spanning tree alone (the instance before the p = 0.9 step): every terrain is
// connected, and it has exactly n^2 - 1 passages. The full instance's passages contain it.
NavigationInstance navigation_kruskal_tree(int n, std::uint64_t seed, double terrain_size = 1.0);

// The driver models of seed 002 Sect. 4.1.2 as intervals: the driver draws u_i uniformly
// from [lo[i], hi[i]], which depends on the vehicle and the state x = (x, y, θ, a, b). Always
// inside the vehicle's input box U.
struct DriverInterval {
  std::array<double, 2> lo{}, hi{};
};
DriverInterval navigation_driver_interval(NavDriver driver, NavVehicle vehicle, std::span<const double> state,
                                          NavWheelUnit unit = NavWheelUnit::radians);

// The navigation spec (seed 002 Sect. 4.1.4): the signed Euclidean distance from (x[0], x[1]) to
// the closed square box = {x_lo, y_lo, x_hi, y_hi} (<= 0 inside). navigation_outside_box is
// exactly navigation_box_spec > 0, without the hypot: outside the closed square the distance
// of a positive offset is > 0, inside it -min(...) <= 0 (the integrator tests every step with
// it, core/model/system.hpp).
inline double navigation_box_spec(const std::array<double, 4>& box, const double* x) {
  const double dx = std::max({box[0] - x[0], 0.0, x[0] - box[2]});
  const double dy = std::max({box[1] - x[1], 0.0, x[1] - box[3]});
  if (dx > 0.0 || dy > 0.0) return std::hypot(dx, dy);
  return -std::min({x[0] - box[0], box[2] - x[0], x[1] - box[1], box[3] - x[1]});
}
inline bool navigation_outside_box(const std::array<double, 4>& box, const double* x) {
  return box[0] - x[0] > 0.0 || x[0] - box[2] > 0.0 || box[1] - x[1] > 0.0 || x[1] - box[3] > 0.0;
}

// The instance of a navigation System (nullptr for any other System): for planners and tools
// that need the terrain graph.
std::shared_ptr<const NavigationInstance> navigation_instance(const System& system);

// The instance as JSON, for `hyfal instance export --suite navigation`: `instance` is the
// resolved instance key (resolve_options of the suite's parameters). Fields:
//   format "hyfal-navigation/1", instance (the key), n, seed, terrain_size, driver, property,
//   vehicles {"C": "SCar", "U": "SUni", "D": "SDDrive"}, dynamics (a string of n^2 letters
//   C/U/D, terrain q = row * n + col at index q), passages ([[q, q'], ...], q < q', sorted),
//   properties ([[start, unsafe], ...], 40 of them; places: terrains, or for n = 1 the quarters 0..3 = 2 row + col,
//   property_places says which), constants (per vehicle limits, L, r).
// Throws std::invalid_argument on bad values, as the suite does.
Json navigation_instance_json(const Json& instance);

}  // namespace hyfal
