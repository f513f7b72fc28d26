// Wanderer: the seeded steering of an autonomous vehicle that roams an area and turns back before
// the terrain's edge (docs/vehicles.md "Autonomous groups").
#pragma once

#include <cstdint>

#include "base/rect.h"
#include "terrain/terrain.h"
#include "vehicle/simulated_vehicle.h"
#include "vehicle/vehicle_type.h"

namespace dt {

// A rectangle of the terrain's plane (docs/conventions.md: x east, z north, metres from the
// terrain's south-west corner).
struct WanderArea {
  double x_min_m = 0.0, x_max_m = 0.0;
  double z_min_m = 0.0, z_max_m = 0.0;
};

// A deterministic stream of numbers from a seed (SplitMix64), the same on every platform and
// build: std::uniform_real_distribution is not.
class WanderRandom {
 public:
  explicit WanderRandom(uint64_t seed) : state_(seed) {}
  uint64_t Next();
  double Uniform(double lo, double hi);  // [lo, hi)

 private:
  uint64_t state_;
};

// The seed of vehicle `index` of a group seeded `group_seed`.
uint64_t WanderSeed(uint64_t group_seed, uint64_t index);

// Where a group's vehicle starts: a point of `clear` (a Wanderer's clear_area()) and a heading,
// drawn from `random`.
struct WanderStart {
  double x_m = 0.0, z_m = 0.0, heading_rad = 0.0;
};
WanderStart DrawWanderStart(const WanderArea& clear, WanderRandom& random);

// What a wanderer asks of its vehicle this tick.
struct WanderCommand {
  double speed_mps = 0.0;
  double heading_rate_rad_s = 0.0;
};

// Drives in legs of 3-10 s, each a speed of 25-60 % of the type's top speed and, one leg in two,
// a turn of up to half its turn rate either way; the commanded speed moves towards the leg's by
// 2 m/s^2 (the light model would otherwise jump to it in one tick). Every tick it looks ahead along
// its heading
// (`lookahead_m()`: room to turn round at the turning-back speed plus the vehicle's length); if
// that point leaves the area, or comes within `edge_margin_m()` (a turning circle and a length) of
// the terrain's edge, it turns towards the area's centre, on the side it first turned to, at the
// type's full turn rate and 30 % of its top speed until it faces
// inwards again, then starts a new leg.
//
// It also looks at the terrain ahead, as a driver would: an earthwork (crater, berm, ditch), taken
// as a disc (a crater's own, else the one round its bounds), that comes within half its width and
// a metre of its path within `avoid_ahead_m()` is an obstacle; it slows to 30 % of its top speed
// (less where its full turn rate's circle would not pass the nearest one) and turns at its full
// rate away from it, on the side first chosen, until the path is clear. One already under it
// is not avoided (it drives out), and after kAvoidGiveUpS of turning it crawls on straight at
// 10 % of its top speed until the path clears. Bridges are not obstacles: they are driven over.
// A clear path is looked at every 0.2 s, a blocked one every tick.
// The same seed, type, area, terrain and sequence of poses and time steps give the same commands.
class Wanderer {
 public:
  // `area` must lie inside [0, terrain_size_x_m] x [0, terrain_size_z_m] (the exercise file's
  // validation checks it).
  Wanderer(const VehicleType& type, const WanderArea& area, double terrain_size_x_m,
           double terrain_size_z_m, uint64_t seed);

  // The command for the tick of dt_s that starts at `pose` on `terrain`.
  WanderCommand Next(const VehiclePose& pose, double dt_s, const Terrain& terrain);

  // Only the clear part of the area is wandered: the area less edge_margin_m() at the terrain's
  // edge (a point at its centre if nothing is left).
  const WanderArea& clear_area() const { return clear_; }
  double lookahead_m() const { return lookahead_m_; }
  double edge_margin_m() const { return edge_margin_m_; }
  bool turning_back() const { return turning_back_; }
  // True while the last Next steered around an obstacle (or crawled on after giving up).
  bool avoiding() const { return avoid_s_ > 0.0; }
  // How far ahead of its centre it looks for obstacles at `speed_mps`.
  double avoid_ahead_m(double speed_mps) const;

 private:
  void NewLeg();
  bool Inside(double x_m, double z_m) const;
  // The nearest obstacle across the path ahead (false: none): its centre, and the radius of the
  // widest turn that passes it.
  bool ObstacleAhead(const VehiclePose& pose, double ahead_m, const Terrain& terrain,
                     double& at_x_m, double& at_z_m, double& turn_radius_m) const;

  double max_speed_mps_, max_rate_rad_s_;
  double length_m_, half_width_m_, turn_radius_m_;
  double lookahead_m_, edge_margin_m_;
  WanderArea clear_;
  WanderRandom random_;
  WanderCommand leg_;
  double leg_left_s_ = 0.0;
  bool turning_back_ = false;
  double turn_sign_ = 1.0;  // of the turn back: +1 counter-clockwise
  double speed_mps_ = 0.0;  // commanded last, ramped at 2 m/s^2 except when slowing down
  double avoid_s_ = 0.0;    // time spent avoiding the obstacles ahead (0: the path is clear)
  double avoid_sign_ = 1.0;
  double look_in_s_ = 0.0;  // until the path ahead is looked at again
};

}  // namespace dt
