// PhysicalVehicle: a rigid body on spring-damper contacts, driven within the grip of the ground.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "base/feature_id.h"
#include "base/result.h"
#include "terrain/terrain.h"
#include "vehicle/belly_grid.h"
#include "vehicle/bridge_solids.h"
#include "vehicle/contact_surface.h"
#include "vehicle/physical_type.h"

namespace dt {

// The fixed internal step: every Advance runs whole steps of this length, whatever the caller's
// tick, and keeps the remainder for the next call (docs/vehicles.md "Time step").
inline constexpr int64_t kPhysicsStepNs = 10'000'000;
inline constexpr double kPhysicsStepS = 0.010;
inline constexpr double kGravityMps2 = 9.81;
// Static sag of the running gear under the vehicle's weight; the springs follow from it.
inline constexpr double kStaticSagM = 0.05;
// Largest compression of a running-gear contact before it bottoms out (a hard stop).
inline constexpr double kGearTravelM = 0.2;
// The most a body point moves in one (sub)step: half the thinnest solid (deck slab 0.5 m).
inline constexpr double kMaxMovePerStepM = 0.2;
// A contact that was clear of the ground this long and touches again is a landing. The latches
// add up the (sub)steps' lengths, so they hold the same time whatever the step.
inline constexpr double kLandingAirS = 0.020;
// Sums of steps under a latch's duration by no more than this (rounding) reach it.
inline constexpr double kLatchSlackS = 1e-6;

// A vehicle with no command that stays within kRestDriftM and kRestTurnRad of one pose for
// kSleepAfterS, never faster than kRestSpeedMps or kRestRateRadS, is at rest: it sleeps, taking
// steps without computing them, until it is commanded or the terrain changes under it
// (docs/vehicles.md "Rest"). The springs' settling jitters on for ever in some resting places.
inline constexpr double kRestDriftM = 0.005;
inline constexpr double kRestTurnRad = 0.005;
inline constexpr double kRestSpeedMps = 0.05;
inline constexpr double kRestRateRadS = 0.05;
inline constexpr double kSleepAfterS = 1.0;

enum class Damage : uint8_t { kNone = 0, kImmobilised = 1, kDestroyed = 2 };
std::string_view DamageName(Damage damage);  // "none", "immobilised", "destroyed"

// What happened during one Advance.
struct PhysicalReport {
  int steps = 0;
  FeatureId mounted;    // got onto this bridge's deck (number 0: no)
  FeatureId drove_off;  // drove off this bridge's deck onto the ground
  FeatureId fell_off;   // fell off this bridge's deck (reported once per fall)
  // Leaving a deck (0.1 s without it under the running gear) alive with the centre of mass in the
  // outer part of a hot spot (beyond a ramp's foot) is driving off; anything else is falling off.
  double max_landing_mps = 0.0;  // fastest landing (normal speed of a contact touching down)
  // Fastest impact with a bridge solid: the speed the hull lost along the face's normal. Judged
  // against the landing thresholds, as a landing is.
  double max_impact_mps = 0.0;
  bool blocked = false;               // the hull met a solid and was stopped against it
  bool sliding = false;               // the grip needed exceeded static friction at some step
  Damage damage_now = Damage::kNone;  // damage that happened in this call
  std::string cause;                  // why, when damage_now is not kNone
};

// Axes: world x east, y up, z north (docs/conventions.md). The body frame is (ahead, up, left) so
// that it is a proper rotation of the world frame in these coordinates; a heading d (counter-
// clockwise from +x) is the rotation by -d about +y. Position and velocity are the centre of
// mass's. Not thread-safe; deterministic: the same inputs give the same bits in the same build.
class PhysicalVehicle {
 public:
  // Places the vehicle level at rest on the ground and earthworks under its running gear, with the
  // gear's static sag. Refused for an invalid type, a non-finite pose, a footprint off the
  // terrain, or a hull that would start inside a bridge solid.
  static Result<PhysicalVehicle> Make(const PhysicalVehicleType& type, const Terrain& terrain,
                                      double x_m, double z_m, double heading_rad);
  // The same with the bottom of the running gear at `gear_bottom_m` (a deck, or in the air).
  static Result<PhysicalVehicle> MakeAt(const PhysicalVehicleType& type, const Terrain& terrain,
                                        double x_m, double z_m, double heading_rad,
                                        double gear_bottom_m);

  // The driver's demand: forward speed (negative reverses) and heading rate (positive counter-
  // clockwise), clamped to the type's limits; the vehicle gets there as engine and grip allow.
  // Refused for non-finite values and for an immobilised or destroyed vehicle.
  Status Command(double speed_mps, double heading_rate_rad_s);

  // Runs as many fixed steps as dt_s and the remainder kept from earlier calls make. Refused,
  // changing nothing, for a non-finite or negative dt_s or one over 60 s.
  Result<PhysicalReport> Advance(const Terrain& terrain, double dt_s);

  const PhysicalVehicleType& type() const { return type_; }
  const Eigen::Vector3d& position_m() const { return x_; }
  const Eigen::Vector3d& velocity_mps() const { return v_; }
  const Eigen::Quaterniond& orientation() const { return q_; }
  const Eigen::Vector3d& angular_velocity_rad_s() const { return w_; }
  double x_m() const { return x_.x(); }
  double z_m() const { return x_.z(); }
  double heading_rad() const;
  double pitch_rad() const;  // nose up positive
  double roll_rad() const;   // right side down positive
  // Height of the bottom of the running gear under the centre, plus its static sag: the surface
  // it rests on (the thesis's vehicle elevation).
  double elevation_m() const;
  // Forward speed along the heading (negative reversing).
  double speed_mps() const;
  double commanded_speed_mps() const { return cmd_speed_mps_; }
  double commanded_rate_rad_s() const { return cmd_rate_rad_s_; }

  Damage damage() const { return damage_; }
  bool alive() const { return damage_ != Damage::kDestroyed; }
  bool mobile() const { return damage_ == Damage::kNone; }
  // The deck the running gear stands on (number 0: none).
  FeatureId bridge() const { return bridge_; }
  bool on_bridge() const { return bridge_.number != 0; }
  bool airborne() const { return air_s_ > 0.0; }
  // At rest and not computed (kSleepAfterS): a command that moves it, or a change of the terrain
  // under its hull, wakes it.
  bool asleep() const { return asleep_; }

  // World points of the hull box's bottom face on a grid at most `spacing_m` apart, and the
  // bottom of the running gear at its contacts: for checks of penetration.
  std::vector<Eigen::Vector3d> HullBottomPoints(double spacing_m) const;
  std::vector<Eigen::Vector3d> GearPoints() const;

 private:
  struct Contact {
    Eigen::Vector3d body;     // from the centre of mass, body frame
    bool gear = true;         // running gear (drives) or belly (slides)
    double reach_m = 0.0;     // a solid top this far above the point still carries it
    double air_s = 0.0;       // time clear of the ground (the grid's points: grid_touched_until_s_)
    bool dense = false;       // belly grid: only sampled where features lie under the footprint
    GroundPlaneCache ground;  // valid while the terrain's stamp is the one it was filled under
  };

  // A contact that touches the surface in this step.
  struct Touch {
    Eigen::Vector3d r, n, plane_point;  // arm from the centre of mass (world), normal, surface
    double depth_m;                     // below the surface along n, when gathered
    double normal_n;
    bool gear;
    Eigen::Vector3d body;  // the contact's point, body frame
  };
  static constexpr size_t kMaxTouches = 512;
  // What the contacts of one step add up to.
  struct StepForces {
    Eigen::Vector3d F = Eigen::Vector3d::Zero(), tau = Eigen::Vector3d::Zero();  // N, N m
    double total_n = 0.0;
    // Over the touches: the normal forces as vectors; static and dynamic friction, rolling
    // resistance and the grip up faces the running gear can climb, each times normal force (N).
    Eigen::Vector3d normal_sum = Eigen::Vector3d::Zero();
    double static_n = 0.0, dynamic_n = 0.0, rolling_n = 0.0, climb_n = 0.0;
    bool gear_touching = false;
    FeatureId deck;  // the deck that carries the running gear hardest
    double deck_n = 0.0;
    FeatureId hull_deck;  // a deck the belly rests on
    size_t sampled = 0;   // contacts sampled: the running gear, or all with the belly
  };

  PhysicalVehicle(const PhysicalVehicleType& type, double x_m, double z_m, double heading_rad,
                  double gear_bottom_m);
  // One fixed step (physical_vehicle_step.cc), in the order of these phases.
  void Step(const Terrain& terrain, std::span<const Solid> solids, double h_s,
            PhysicalReport& report);
  // A contact at depth_m below the surface s, its point moving at vn_mps along the normal: its
  // spring-damper force joins `forces` and it joins `touches`. Returns its normal force, N.
  double AddTouch(const Eigen::Vector3d& r, const Eigen::Vector3d& p, const Eigen::Vector3d& body,
                  const SurfaceSample& s, double depth_m, double vn_mps, bool gear,
                  StepForces& forces, std::span<Touch> touches, size_t& count,
                  double stiffness = 1.0);
  size_t GatherTouches(const Terrain& terrain, std::span<const Solid> solids,
                       const Eigen::Matrix3d& R, double h, std::span<Touch> touches,
                       StepForces& forces, PhysicalReport& report);
  // A destroyed vehicle's box: every face meets the ground and the solids' tops.
  size_t GatherWreckTouches(const Terrain& terrain, std::span<const Solid> solids,
                            const Eigen::Matrix3d& R, std::span<Touch> touches, size_t count,
                            StepForces& forces);
  size_t GatherRefinedBellyTouches(const Terrain& terrain, std::span<const Solid> solids,
                                   const Eigen::Matrix3d& R, std::span<Touch> touches, size_t count,
                                   StepForces& forces);
  size_t GatherSolidEdgeTouches(const Terrain& terrain, std::span<const Solid> solids,
                                const Eigen::Matrix3d& R, std::span<Touch> touches, size_t count,
                                StepForces& forces);
  void ApplyGrip(const Eigen::Matrix3d& R, double h_s, std::span<const Touch> touches,
                 StepForces& forces, PhysicalReport& report);
  void Integrate(const StepForces& forces, const Eigen::Matrix3d& R, double h_s);
  // `x_before` is the centre of mass before Integrate moved it by a step of h_s.
  void ApplyHardStops(std::span<const Touch> touches, const Eigen::Vector3d& x_before, double h_s);
  void UpdateBridgeTag(const Terrain& terrain, const StepForces& forces, double h,
                       PhysicalReport& report);
  void CheckDamage(PhysicalReport& report);
  // The hull against bridge solids (physical_vehicle_hull.cc).
  void ResolveHull(std::span<const Solid> solids, PhysicalReport& report);
  bool OnTerrain(const Terrain& terrain) const;
  // The corners of the box from the gear's bottom to the roof over the footprint, world.
  std::array<Eigen::Vector3d, 8> HullBoxCorners() const;
  Status CheckClearOfSolids(const Terrain& terrain) const;
  // True if the centre of mass is in the outer part of one of the bridge's hot spots (beyond a
  // ramp's foot by at most half a hot spot, within the bridge's width): leaving the deck there is
  // driving off, anywhere else falling off (thesis IV.B.3).
  bool InOuterHotSpot(const Terrain& terrain, FeatureId bridge) const;
  void Damaged(Damage damage, std::string cause, PhysicalReport& report);
  // After a step: counts the time at rest, and falls asleep once it is long enough.
  void CountRest(const Terrain& terrain);
  // Asleep: true if nothing changed under the hull since the terrain's stamp last seen.
  bool StaysAsleep(const Terrain& terrain);
  Eigen::Matrix3d WorldInverseInertia(const Eigen::Matrix3d& r) const;
  // q_.toRotationMatrix(), computed again only once q_'s bits have changed: the phases of a step
  // ask it three times and the orientation mostly changes once.
  const Eigen::Matrix3d& Rotation();

  PhysicalVehicleType type_;
  std::vector<Contact> contacts_;
  std::vector<Eigen::Vector3d> hull_points_;  // body frame, perimeter at three heights
  // A wreck's contacts: the surface of the box from the gear's bottom to the roof, each face's
  // springs together as stiff as the running gear's at least (the smallest face's).
  std::vector<Contact> wreck_contacts_;
  double wreck_stiffness_ = 1.0;     // each wreck contact's spring and damper ÷ a gear contact's
  Eigen::Vector3d inertia_;          // principal moments, body frame (ahead, up, left)
  Eigen::Vector3d inverse_inertia_;  // their inverses
  double spring_n_per_m_ = 0.0;      // per contact
  double damper_n_s_per_m_ = 0.0;    // per contact
  int gear_count_ = 0;
  int per_side_ = 0;  // gear points per side; as many belly centre-line points
  BellyGrid belly_grid_;
  size_t always_count_ = 0;       // the running gear; the belly (centre line, then grid) follows
  double half_diagonal_m_ = 0.0;  // of the footprint
  double box_radius_m_ = 0.0;     // bounds the hull box's corners' distance from the centre
  // Per material: sqrt(1 + static friction^2), the grip's wall test (ApplyGrip).
  std::array<double, kMaterialCount> grip_wall_factor_{};

  Eigen::Vector3d x_;
  Eigen::Vector3d v_ = Eigen::Vector3d::Zero();
  Eigen::Quaterniond q_;
  Eigen::Vector3d w_ = Eigen::Vector3d::Zero();
  Eigen::Quaterniond rotation_of_;  // the q_ that rotation_ was computed from
  Eigen::Matrix3d rotation_;
  double cmd_speed_mps_ = 0.0;
  double cmd_rate_rad_s_ = 0.0;
  int64_t pending_ns_ = 0;
  // Bridge solids and earthworks over an area around the vehicle, kept between Advance calls
  // while the terrain's stamp is the one they were gathered under and every chunk of steps
  // stays inside the area: the terrain's index reaches into scattered memory.
  uint64_t near_stamp_ = 0;  // 0: nothing gathered (stamps start at 1)
  Rect near_area_;
  std::vector<Solid> near_solids_;
  std::vector<Rect> near_solid_bounds_;
  std::vector<NearEarthwork> near_earthworks_;
  // Those of them that the vehicle can reach in the current chunk of steps.
  std::vector<Solid> solids_;
  std::vector<NearEarthwork> earthworks_;
  // Belly grid: each point's neighbours towards +ahead, -ahead, +left, -left (contact index, -1
  // where there is no grid point), and whether the point is near the surface this step.
  std::vector<std::array<int, 4>> grid_neighbours_;
  std::vector<uint8_t> grid_near_;
  // Grid points that may lie inside the bounds of an earthwork this step (BellyGrid::MarkUnder).
  std::vector<uint8_t> grid_over_earthwork_;
  // The time the belly has been sampled for (steps with features near the footprint), and per
  // grid point the belly clock after it last touched: its time in the air is the difference.
  double belly_clock_s_ = 0.0;
  std::vector<double> grid_touched_until_s_;
  Damage damage_ = Damage::kNone;
  double sin_pitch_limit_ = 0.0, tan_roll_limit_ = 0.0;
  FeatureId bridge_;
  FeatureId fell_from_;  // a fall from this bridge was reported; cleared on the ground
  double air_s_ = 0.0;   // time since the running gear last touched anything
  double rest_s_ = 0.0;  // time at rest with no command, near the pose below (kRestDriftM)
  Eigen::Vector3d rest_x_ = Eigen::Vector3d::Zero();
  Eigen::Quaterniond rest_q_ = Eigen::Quaterniond::Identity();
  bool asleep_ = false;
  const Terrain* asleep_terrain_ = nullptr;  // the terrain it fell asleep on
  uint64_t asleep_stamp_ = 0;  // that terrain's stamp when last seen unchanged under the hull
  double off_deck_s_ = 0.0;    // time since a deck last carried the running gear
};

}  // namespace dt
