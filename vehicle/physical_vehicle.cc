#include "vehicle/physical_vehicle.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

#include <numbers>

#include <fmt/format.h>

#include "terrain/bridge.h"
#include "vehicle/contact_surface.h"
#include "vehicle/hull_collision.h"
#include "vehicle/physical_vehicle_internal.h"

namespace dt {
namespace {

using Eigen::Matrix3d;
using Eigen::Quaterniond;
using Eigen::Vector3d;
using physical_internal::kBellyTravelM;

// Damping ratio of the running gear's vertical bounce.
constexpr double kDampingRatio = 0.6;
// Belly grid points are at most this far apart.
constexpr double kBellyGridSpacingM = 0.5;
// A wreck's box is sampled at points at most this far apart, as the belly's grid.
constexpr double kWreckSampleSpacingM = 0.5;
// A solid's top this far above a wreck's point still carries it: a wreck rolling over a deck's
// or the rubble's edge rides up onto its top rather than into it (half a deck slab's thickness,
// so never up through a slab from below).
constexpr double kWreckReachM = 0.25;
// Hull perimeter points are at most this far apart.
constexpr double kHullSampleSpacingM = 0.5;
// Contacts per side of a tracked vehicle: one every this many metres of track, at least three.
constexpr double kTrackContactSpacingM = 2.0;
// Features are gathered this far around the area a chunk of steps can reach, and gathered again
// once a chunk reaches outside (or the terrain changed).
constexpr double kNearCacheMarginM = 24.0;

// A sleeping vehicle wakes for changes this close to its hull box's plan.
constexpr double kSleepAreaMarginM = 0.5;
const double kRestTurnHalfCos = std::cos(kRestTurnRad / 2.0);
// A wreck's window is ten times wider: lying on a side or an edge on uneven ground, its contacts
// let it creep at 1-2 cm/s and rad/s for minutes, an artefact of the springs a wreck, which no
// one drives, need not be computed for (a real slide speeds up past kRestSpeedMps).
constexpr double kWreckRestDriftM = 10.0 * kRestDriftM;
const double kWreckRestTurnHalfCos = std::cos(10.0 * kRestTurnRad / 2.0);

Quaterniond HeadingQuaternion(double heading_rad) {
  return Quaterniond(Eigen::AngleAxisd(-heading_rad, Vector3d::UnitY()));
}

}  // namespace

std::string_view DamageName(Damage d) {
  switch (d) {
    case Damage::kNone:
      return "none";
    case Damage::kImmobilised:
      return "immobilised";
    case Damage::kDestroyed:
      return "destroyed";
  }
  return "?";
}

PhysicalVehicle::PhysicalVehicle(const PhysicalVehicleType& type, double x_m, double z_m,
                                 double heading_rad, double gear_bottom_m)
    : type_(type),
      x_(x_m, gear_bottom_m + type.cg_height_m, z_m),
      q_(HeadingQuaternion(heading_rad)),
      rotation_of_(q_),
      rotation_(q_.toRotationMatrix()) {
  const double L = type.base.length_m, W = type.base.width_m, H = type.hull_height_m;
  const double cg = type.cg_height_m;
  const int per_side = type.gear == RunningGear::kTracked
                           ? std::max(3, static_cast<int>(std::ceil(L / kTrackContactSpacingM)) + 1)
                           : 3;
  // Running gear: per_side points along each side (the six orientation points when 3), then the
  // belly's centre line at the same stations.
  for (const double left : {W / 2.0, -W / 2.0}) {
    for (int k = 0; k < per_side; ++k) {
      const double ahead = L / 2.0 - L * k / (per_side - 1);
      contacts_.push_back({Vector3d(ahead, -cg, left), true, type.clearance_m, 0, false, {}});
    }
  }
  gear_count_ = static_cast<int>(contacts_.size());
  per_side_ = per_side;
  always_count_ = contacts_.size();
  for (int k = 0; k < per_side; ++k) {
    const double ahead = L / 2.0 - L * k / (per_side - 1);
    contacts_.push_back(
        {Vector3d(ahead, type.clearance_m - cg, 0.0), false, kBellyTravelM, 0, false, {}});
  }
  // The belly grid, at most kBellyGridSpacingM apart, so an earthwork narrower than the gear's
  // spacing cannot rise into the hull between contacts.
  belly_grid_ = BellyGrid(L, W, kBellyGridSpacingM, type.clearance_m - cg);
  const int ga = belly_grid_.stations(), gl = belly_grid_.lines();
  for (int i = 0; i < ga; ++i) {
    for (int j = 0; j < gl; ++j) {
      if (belly_grid_.OnCentreLine(j)) continue;  // the centre line is above
      belly_grid_.SetContact(i, j, static_cast<int>(contacts_.size()));
      contacts_.push_back({belly_grid_.Body(i, j), false, kBellyTravelM, 0, true, {}});
    }
  }
  grid_neighbours_.assign(contacts_.size(), {-1, -1, -1, -1});
  grid_near_.assign(contacts_.size(), 0);
  grid_over_earthwork_.assign(contacts_.size(), 0);
  grid_touched_until_s_.assign(contacts_.size(), 0.0);
  for (int i = 0; i < ga; ++i) {
    for (int j = 0; j < gl; ++j) {
      const int k = belly_grid_.ContactAt(i, j);
      if (k < 0) continue;
      grid_neighbours_[static_cast<size_t>(k)] = {
          belly_grid_.ContactAt(i + 1, j), belly_grid_.ContactAt(i - 1, j),
          belly_grid_.ContactAt(i, j + 1), belly_grid_.ContactAt(i, j - 1)};
    }
  }
  // Hull perimeter from the belly to the roof, in rows close enough that no deck slab fits
  // between two of them.
  const int na = std::max(2, static_cast<int>(std::ceil(L / kHullSampleSpacingM)) + 1);
  const int nl = std::max(2, static_cast<int>(std::ceil(W / kHullSampleSpacingM)) + 1);
  const double rise = H - type.clearance_m;
  const int rows = std::max(2, static_cast<int>(std::ceil(rise / (0.8 * kDeckThicknessM))) + 1);
  for (int row = 0; row < rows; ++row) {
    const double up = type.clearance_m + rise * row / (rows - 1);
    for (int i = 0; i < na; ++i) {
      const double ahead = -L / 2.0 + L * i / (na - 1);
      hull_points_.emplace_back(ahead, up - cg, W / 2.0);
      hull_points_.emplace_back(ahead, up - cg, -W / 2.0);
    }
    for (int i = 1; i + 1 < nl; ++i) {
      const double left = -W / 2.0 + W * i / (nl - 1);
      hull_points_.emplace_back(L / 2.0, up - cg, left);
      hull_points_.emplace_back(-L / 2.0, up - cg, left);
    }
  }
  // A wreck's box surface, from the gear's bottom to the roof.
  {
    const int wa = static_cast<int>(std::ceil(L / kWreckSampleSpacingM)) + 1;
    const int wl = static_cast<int>(std::ceil(W / kWreckSampleSpacingM)) + 1;
    const int wh = static_cast<int>(std::ceil(H / kWreckSampleSpacingM)) + 1;
    for (int i = 0; i < wa; ++i) {
      for (int j = 0; j < wl; ++j) {
        for (int k = 0; k < wh; ++k) {
          if (i != 0 && i != wa - 1 && j != 0 && j != wl - 1 && k != 0 && k != wh - 1) continue;
          const Vector3d b(-L / 2.0 + L * i / (wa - 1), -cg + H * k / (wh - 1),
                           -W / 2.0 + W * j / (wl - 1));
          wreck_contacts_.push_back({b, false, kWreckReachM, 0, false, {}});
        }
      }
    }
    wreck_stiffness_ = static_cast<double>(2 * per_side) / (wl * wh);
  }
  half_diagonal_m_ = 0.5 * std::hypot(L, W);
  for (size_t k = 0; k < grip_wall_factor_.size(); ++k) {
    const double mu = type.grip[k].static_friction;
    grip_wall_factor_[k] = std::sqrt(1.0 + mu * mu);
  }
  // The farthest box corner from the centre of mass, with a margin far above the rounding of a
  // rotated corner's coordinates.
  const double tall = std::max(cg, H - cg);
  box_radius_m_ = std::sqrt(L * L / 4.0 + W * W / 4.0 + tall * tall) * (1.0 + 1e-9) + 1e-6;
  const double m = type.mass_kg;
  inertia_ =
      Vector3d(m * (H * H + W * W) / 12.0, m * (L * L + W * W) / 12.0, m * (L * L + H * H) / 12.0);
  inverse_inertia_ = inertia_.cwiseInverse();
  const double k_total = m * kGravityMps2 / kStaticSagM;
  spring_n_per_m_ = k_total / gear_count_;
  sin_pitch_limit_ = std::sin(type.StaticPitchLimitRad());
  tan_roll_limit_ = std::tan(type.StaticRollLimitRad());
  damper_n_s_per_m_ = 2.0 * kDampingRatio * std::sqrt(k_total * m) / gear_count_;
}

Result<PhysicalVehicle> PhysicalVehicle::MakeAt(const PhysicalVehicleType& type,
                                                const Terrain& terrain, double x_m, double z_m,
                                                double heading_rad, double gear_bottom_m) {
  if (Status s = ValidatePhysicalType(type); !s) return s.error();
  if (!std::isfinite(x_m) || !std::isfinite(z_m) || !std::isfinite(heading_rad) ||
      !std::isfinite(gear_bottom_m)) {
    return Error{fmt::format("the {} pose (x {}, z {}, heading {}, gear bottom {}) is not finite",
                             type.base.name, x_m, z_m, heading_rad, gear_bottom_m)};
  }
  PhysicalVehicle v(type, x_m, z_m, heading_rad, gear_bottom_m);
  if (!v.OnTerrain(terrain)) {
    return Error{
        fmt::format("the {} at (x {}, z {}) m heading {} rad reaches off the terrain "
                    "[0, {}] x [0, {}] m",
                    type.base.name, x_m, z_m, heading_rad, terrain.ground().size_x_m(),
                    terrain.ground().size_z_m())};
  }
  if (Status s = v.CheckClearOfSolids(terrain); !s) return s.error();
  return v;
}

Result<PhysicalVehicle> PhysicalVehicle::Make(const PhysicalVehicleType& type,
                                              const Terrain& terrain, double x_m, double z_m,
                                              double heading_rad) {
  Result<PhysicalVehicle> v = MakeAt(type, terrain, x_m, z_m, heading_rad, 0.0);
  if (!v) return v;
  PhysicalVehicle& p = v.value();
  const Matrix3d r = p.q_.toRotationMatrix();
  double top = -INFINITY;
  for (int k = 0; k < p.gear_count_; ++k) {
    const Vector3d at = p.x_ + r * p.contacts_[static_cast<size_t>(k)].body;
    top = std::max(top, terrain.ElevationAt(at.x(), at.z()));
  }
  p.x_.y() = top - kStaticSagM + type.cg_height_m;
  if (Status s = p.CheckClearOfSolids(terrain); !s) return s.error();
  return v;
}

Status PhysicalVehicle::CheckClearOfSolids(const Terrain& terrain) const {
  const double reach = std::hypot(type_.base.length_m, type_.base.width_m);
  const std::vector<Solid> solids =
      SolidsNear(terrain, Rect{x_.x(), x_.z(), x_.x(), x_.z()}.Expanded(reach));
  if (solids.empty()) return Status::Ok();
  const Matrix3d r = q_.toRotationMatrix();
  std::vector<Vector3d> world;
  for (const Vector3d& b : hull_points_) world.push_back(x_ + r * b);
  const HullPenetration in = DeepestPenetration(world, solids, 0.0);
  if (!in.hit) return Status::Ok();
  return Error{fmt::format(
      "the {} at (x {}, z {}) m, elevation {} m, would start {:.2f} m inside "
      "bridge {}",
      type_.base.name, x_.x(), x_.z(), elevation_m(), in.depth_m, in.bridge.ToString())};
}

Status PhysicalVehicle::Command(double speed_mps, double heading_rate_rad_s) {
  if (!std::isfinite(speed_mps) || !std::isfinite(heading_rate_rad_s)) {
    return Error{fmt::format("drive command (speed {} m/s, heading rate {} rad/s) is not finite",
                             speed_mps, heading_rate_rad_s)};
  }
  if (!mobile()) {
    return Error{
        fmt::format("the {} is {} and cannot be driven", type_.base.name, DamageName(damage_))};
  }
  const VehicleType& b = type_.base;
  cmd_speed_mps_ = std::clamp(speed_mps, -b.max_reverse_speed_mps, b.max_speed_mps);
  cmd_rate_rad_s_ = std::clamp(heading_rate_rad_s, -b.max_turn_rate_rad_s, b.max_turn_rate_rad_s);
  if (cmd_speed_mps_ != 0.0 || cmd_rate_rad_s_ != 0.0) {
    asleep_ = false;
    rest_s_ = 0.0;
  }
  return Status::Ok();
}

double PhysicalVehicle::heading_rad() const {
  const Vector3d f = q_ * Vector3d::UnitX();
  return std::atan2(f.z(), f.x());
}
double PhysicalVehicle::pitch_rad() const {
  const Vector3d f = q_ * Vector3d::UnitX();
  return std::atan2(f.y(), std::hypot(f.x(), f.z()));
}
double PhysicalVehicle::roll_rad() const {
  const Vector3d up = q_ * Vector3d::UnitY();
  const Vector3d left = q_ * Vector3d::UnitZ();
  return std::atan2(left.y(), up.y());
}
double PhysicalVehicle::elevation_m() const {
  return (x_ + q_ * Vector3d(0.0, -type_.cg_height_m, 0.0)).y() + kStaticSagM;
}
double PhysicalVehicle::speed_mps() const { return v_.dot(q_ * Vector3d::UnitX()); }

std::vector<Vector3d> PhysicalVehicle::GearPoints() const {
  std::vector<Vector3d> out;
  const Matrix3d r = q_.toRotationMatrix();
  for (int k = 0; k < gear_count_; ++k)
    out.push_back(x_ + r * contacts_[static_cast<size_t>(k)].body);
  return out;
}

std::vector<Vector3d> PhysicalVehicle::HullBottomPoints(double spacing_m) const {
  const double L = type_.base.length_m, W = type_.base.width_m;
  const int na = std::max(2, static_cast<int>(std::ceil(L / spacing_m)) + 1);
  const int nl = std::max(2, static_cast<int>(std::ceil(W / spacing_m)) + 1);
  const Matrix3d r = q_.toRotationMatrix();
  std::vector<Vector3d> out;
  for (int i = 0; i < na; ++i) {
    for (int j = 0; j < nl; ++j) {
      const Vector3d b(-L / 2.0 + L * i / (na - 1), type_.clearance_m - type_.cg_height_m,
                       -W / 2.0 + W * j / (nl - 1));
      out.push_back(x_ + r * b);
    }
  }
  return out;
}

bool PhysicalVehicle::OnTerrain(const Terrain& terrain) const {
  // Every contact and hull point lies in the box from the gear's bottom to the roof over the
  // footprint; the terrain is convex, so the box's eight corners decide. They all lie within
  // box_radius_m_ of the centre of mass: a centre that far inside every edge needs no corner
  // (the answer is the same; this is asked every step).
  if (x_.x() - box_radius_m_ >= 0.0 && x_.x() + box_radius_m_ <= terrain.ground().size_x_m() &&
      x_.z() - box_radius_m_ >= 0.0 && x_.z() + box_radius_m_ <= terrain.ground().size_z_m())
    return true;
  for (const Vector3d& p : HullBoxCorners()) {
    if (!terrain.Contains(p.x(), p.z())) return false;
  }
  return true;
}

std::array<Vector3d, 8> PhysicalVehicle::HullBoxCorners() const {
  const double L = type_.base.length_m / 2.0, W = type_.base.width_m / 2.0;
  const double lo = -type_.cg_height_m, hi = type_.hull_height_m - type_.cg_height_m;
  const Matrix3d r = q_.toRotationMatrix();
  std::array<Vector3d, 8> out;
  size_t k = 0;
  for (const double a : {-L, L}) {
    for (const double l : {-W, W}) {
      for (const double u : {lo, hi}) out[k++] = x_ + r * Vector3d(a, u, l);
    }
  }
  return out;
}

const Matrix3d& PhysicalVehicle::Rotation() {
  if (std::memcmp(rotation_of_.coeffs().data(), q_.coeffs().data(), 4 * sizeof(double)) != 0) {
    rotation_of_ = q_;
    rotation_ = q_.toRotationMatrix();
  }
  return rotation_;
}

void PhysicalVehicle::CountRest(const Terrain& terrain) {
  // |q . rest_q| is the cosine of half the turn between the two orientations.
  const bool wreck = !alive();
  const bool quiet = cmd_speed_mps_ == 0.0 && cmd_rate_rad_s_ == 0.0 && v_.norm() < kRestSpeedMps &&
                     w_.norm() < kRestRateRadS &&
                     (x_ - rest_x_).norm() < (wreck ? kWreckRestDriftM : kRestDriftM) &&
                     std::abs(q_.dot(rest_q_)) > (wreck ? kWreckRestTurnHalfCos : kRestTurnHalfCos);
  if (!quiet) {
    rest_s_ = 0.0;
    rest_x_ = x_;
    rest_q_ = q_;
    return;
  }
  rest_s_ = std::min(rest_s_ + kPhysicsStepS, kSleepAfterS);
  if (rest_s_ < kSleepAfterS - kLatchSlackS) return;
  // At rest: what is left of its speed is the springs' settling.
  asleep_ = true;
  asleep_terrain_ = &terrain;
  asleep_stamp_ = terrain.stamp();
  v_ = Vector3d::Zero();
  w_ = Vector3d::Zero();
}

bool PhysicalVehicle::StaysAsleep(const Terrain& terrain) {
  if (terrain.stamp() == asleep_stamp_) return true;
  // Another terrain's squares may carry stamps older than the one it fell asleep under.
  if (&terrain != asleep_terrain_) return false;
  // A resting vehicle touches only what lies under its hull box: ground, earthworks and solids
  // whose squares the box's plan touches (with a margin for the springs' sag and the edges).
  Rect plan{x_.x(), x_.z(), x_.x(), x_.z()};
  for (const Vector3d& p : HullBoxCorners()) plan = plan.Union(Rect{p.x(), p.z(), p.x(), p.z()});
  if (terrain.AreaStamp(plan.Expanded(kSleepAreaMarginM)) > asleep_stamp_) return false;
  asleep_stamp_ = terrain.stamp();
  return true;
}

Matrix3d PhysicalVehicle::WorldInverseInertia(const Matrix3d& r) const {
  return r * inverse_inertia_.asDiagonal() * r.transpose();
}

void PhysicalVehicle::Damaged(Damage damage, std::string cause, PhysicalReport& report) {
  if (damage <= damage_) return;
  damage_ = damage;
  report.damage_now = damage;
  report.cause = std::move(cause);
  cmd_speed_mps_ = 0.0;
  cmd_rate_rad_s_ = 0.0;
}

Result<PhysicalReport> PhysicalVehicle::Advance(const Terrain& terrain, double dt_s) {
  if (!std::isfinite(dt_s) || dt_s < 0.0 || dt_s > 60.0) {
    return Error{fmt::format("time step {} s is not a finite number in [0, 60]", dt_s)};
  }
  if (!OnTerrain(terrain)) {
    return Error{fmt::format("the {} at (x {}, z {}) m is not on this terrain [0, {}] x [0, {}] m",
                             type_.base.name, x_.x(), x_.z(), terrain.ground().size_x_m(),
                             terrain.ground().size_z_m())};
  }
  PhysicalReport report;
  pending_ns_ += std::llround(dt_s * 1e9);
  const int64_t steps = pending_ns_ / kPhysicsStepNs;
  pending_ns_ -= steps * kPhysicsStepNs;
  if (asleep_ && !StaysAsleep(terrain)) {
    asleep_ = false;
    rest_s_ = 0.0;
  }
  if (asleep_) {
    report.steps = static_cast<int>(steps);
    return report;
  }
  // The running gear's contacts are read in every step: fetched now, their misses (a fleet's
  // vehicles do not stay in the cache between ticks) overlap the gathering of features below.
  // The belly's centre line is read only near features: fetched when the last chunk had some.
  {
    const bool belly = !solids_.empty() || !earthworks_.empty();
    const char* begin = reinterpret_cast<const char*>(contacts_.data());
    const char* end = reinterpret_cast<const char*>(contacts_.data() + always_count_ +
                                                    (belly ? static_cast<size_t>(per_side_) : 0));
    for (const char* p = begin; p < end; p += 64) __builtin_prefetch(p);
  }
  const double reach = half_diagonal_m_ + type_.hull_height_m + 2.0;
  // Solids are gathered for chunks of steps, over the area the vehicle can reach in one.
  constexpr int64_t kChunkSteps = 40;
  for (int64_t done = 0; done < steps && !asleep_;) {
    const int64_t n = std::min(kChunkSteps, steps - done);
    const double margin = reach + (v_.norm() + 20.0) * kPhysicsStepS * static_cast<double>(n);
    const Rect area = Rect{x_.x(), x_.z(), x_.x(), x_.z()}.Expanded(margin);
    if (near_stamp_ != terrain.stamp() || area.min_x < near_area_.min_x ||
        area.min_z < near_area_.min_z || area.max_x > near_area_.max_x ||
        area.max_z > near_area_.max_z) {
      near_area_ = area.Expanded(kNearCacheMarginM);
      SolidsNear(terrain, near_area_, near_solids_);
      near_solid_bounds_.clear();
      for (const Solid& s : near_solids_) near_solid_bounds_.push_back(PlanBounds(s));
      EarthworksNear(terrain, near_area_, near_earthworks_);
      near_stamp_ = terrain.stamp();
    }
    solids_.clear();
    for (size_t i = 0; i < near_solids_.size(); ++i) {
      if (near_solid_bounds_[i].Intersects(area)) solids_.push_back(near_solids_[i]);
    }
    earthworks_.clear();
    for (const NearEarthwork& e : near_earthworks_) {
      if (e.bounds.Intersects(area)) earthworks_.push_back(e);
    }
    for (int64_t k = 0; k < n; ++k) {
      // Substeps keep every move under kMaxMovePerStepM, so no solid is tunnelled through.
      const double fastest = v_.norm() + w_.norm() * reach;
      const int sub =
          std::max(1, static_cast<int>(std::ceil(fastest * kPhysicsStepS / kMaxMovePerStepM)));
      for (int s = 0; s < sub; ++s) Step(terrain, solids_, kPhysicsStepS / sub, report);
      ++report.steps;
      CountRest(terrain);
      if (asleep_) break;
    }
    done += n;
  }
  if (asleep_) report.steps = static_cast<int>(steps);  // the rest asleep
  return report;
}

}  // namespace dt
