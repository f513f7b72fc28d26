#include "vehicle/physical_vehicle.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <numbers>

#include <fmt/format.h>

#include "terrain/bridge.h"
#include "vehicle/contact_surface.h"
#include "vehicle/hull_collision.h"

namespace dt {
namespace {

using Eigen::Matrix3d;
using Eigen::Quaterniond;
using Eigen::Vector3d;

// Damping ratio of the running gear's vertical bounce.
constexpr double kDampingRatio = 0.6;
// Belly contacts bottom out almost at once: the hull is rigid.
constexpr double kBellyTravelM = 0.03;
// A wedge's level exit is at most the way a step drives in at top speed (25 m/s x 10 ms) with
// margin; a deeper one is a roof pushed up into a flat ceiling, left to the impulse below.
constexpr double kWedgeLevelExitMaxM = 0.3;
// A hull tilted less than this (cos 30 degrees) meets a deck's edge with its bottom, which rests
// on the edge; tilted further, its side meets it and slides off.
constexpr double kLevelBottomMinCos = 0.866;
// The tag leaves after this many steps without the deck (0.1 s); a fall stays latched for 1 s.
constexpr int kLeaveDeckSteps = static_cast<int>(100'000'000 / kPhysicsStepNs);
constexpr int kFallLatchSteps = static_cast<int>(1'000'000'000 / kPhysicsStepNs);
// Belly grid points are at most this far apart.
constexpr double kBellyGridSpacingM = 0.5;
// A belly grid point this close to the surface also samples half-way to its neighbours: a crease
// of an earthwork (a crater ring, a berm's top edge) between two grid points can rise above the
// line joining them by a quarter of the spacing times the slopes' sum, more than the 0.1 m the
// hull may enter on a tilted hull; half-way points bring that under 0.04 m.
constexpr double kBellyRefineGapM = 0.1;
// Hull perimeter points are at most this far apart.
constexpr double kHullSampleSpacingM = 0.5;
// Contacts per side of a tracked vehicle: one every this many metres of track, at least three.
constexpr double kTrackContactSpacingM = 2.0;
// Below this speed the engine's force is taken at this speed (P / v is unbounded at rest).
constexpr double kEngineFloorSpeedMps = 1.0;
// Features are gathered this far around the area a chunk of steps can reach, and gathered again
// once a chunk reaches outside (or the terrain changed).
constexpr double kNearCacheMarginM = 24.0;

Quaterniond HeadingQuaternion(double heading_rad) {
  return Quaterniond(Eigen::AngleAxisd(-heading_rad, Vector3d::UnitY()));
}

// Adds a small rotation (world axis-angle vector) to q.
void Rotate(Quaterniond& q, const Vector3d& angle) {
  const Quaterniond dq(0.0, angle.x(), angle.y(), angle.z());
  q.coeffs() += 0.5 * (dq * q).coeffs();
  q.normalize();
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
      q_(HeadingQuaternion(heading_rad)) {
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
  const int ga = std::max(2, static_cast<int>(std::ceil(L / kBellyGridSpacingM)) + 1);
  const int gl = std::max(3, static_cast<int>(std::ceil(W / kBellyGridSpacingM)) + 1);
  grid_step_ahead_m_ = L / (ga - 1);
  grid_step_left_m_ = W / (gl - 1);
  std::vector<int> grid_index(static_cast<size_t>(ga * gl), -1);
  for (int i = 0; i < ga; ++i) {
    for (int j = 0; j < gl; ++j) {
      const double left = -W / 2.0 + W * j / (gl - 1);
      if (std::abs(left) < 1e-9) continue;  // the centre line is above
      const double ahead = -L / 2.0 + L * i / (ga - 1);
      grid_index[static_cast<size_t>(i * gl + j)] = static_cast<int>(contacts_.size());
      contacts_.push_back(
          {Vector3d(ahead, type.clearance_m - cg, left), false, kBellyTravelM, 0, true, {}});
    }
  }
  grid_neighbours_.assign(contacts_.size(), {-1, -1, -1, -1});
  grid_near_.assign(contacts_.size(), 0);
  auto grid_at = [&](int i, int j) {
    return i < 0 || i >= ga || j < 0 || j >= gl ? -1 : grid_index[static_cast<size_t>(i * gl + j)];
  };
  for (int i = 0; i < ga; ++i) {
    for (int j = 0; j < gl; ++j) {
      const int k = grid_at(i, j);
      if (k < 0) continue;
      grid_neighbours_[static_cast<size_t>(k)] = {grid_at(i + 1, j), grid_at(i - 1, j),
                                                  grid_at(i, j + 1), grid_at(i, j - 1)};
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
  const double m = type.mass_kg;
  inertia_ =
      Vector3d(m * (H * H + W * W) / 12.0, m * (L * L + W * W) / 12.0, m * (L * L + H * H) / 12.0);
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
                    "[0, {}]^2",
                    type.base.name, x_m, z_m, heading_rad, terrain.ground().size_m())};
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
  // footprint; the terrain is convex, so the box's eight corners decide.
  const double L = type_.base.length_m / 2.0, W = type_.base.width_m / 2.0;
  const double lo = -type_.cg_height_m, hi = type_.hull_height_m - type_.cg_height_m;
  const Matrix3d r = q_.toRotationMatrix();
  for (const double a : {-L, L}) {
    for (const double l : {-W, W}) {
      for (const double u : {lo, hi}) {
        const Vector3d p = x_ + r * Vector3d(a, u, l);
        if (!terrain.Contains(p.x(), p.z())) return false;
      }
    }
  }
  return true;
}

Matrix3d PhysicalVehicle::WorldInverseInertia(const Matrix3d& r) const {
  return r * inertia_.cwiseInverse().asDiagonal() * r.transpose();
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
    return Error{fmt::format("the {} at (x {}, z {}) m is not on this terrain [0, {}]^2",
                             type_.base.name, x_.x(), x_.z(), terrain.ground().size_m())};
  }
  PhysicalReport report;
  pending_ns_ += std::llround(dt_s * 1e9);
  const int64_t steps = pending_ns_ / kPhysicsStepNs;
  pending_ns_ -= steps * kPhysicsStepNs;
  if (frozen_) return report;
  // The running gear's contacts are read in every step: fetched now, their misses (a fleet's
  // vehicles do not stay in the cache between ticks) overlap the gathering of features below.
  {
    const char* begin = reinterpret_cast<const char*>(contacts_.data());
    const char* end = reinterpret_cast<const char*>(contacts_.data() + always_count_ + per_side_);
    for (const char* p = begin; p < end; p += 64) __builtin_prefetch(p);
  }
  const double reach =
      std::hypot(type_.base.length_m, type_.base.width_m) / 2.0 + type_.hull_height_m + 2.0;
  // Solids are gathered for chunks of steps, over the area the vehicle can reach in one.
  constexpr int64_t kChunkSteps = 40;
  for (int64_t done = 0; done < steps && !frozen_;) {
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
    for (int64_t k = 0; k < n && !frozen_; ++k) {
      // Substeps keep every move under kMaxMovePerStepM, so no solid is tunnelled through.
      const double fastest = v_.norm() + w_.norm() * reach;
      const int sub =
          std::max(1, static_cast<int>(std::ceil(fastest * kPhysicsStepS / kMaxMovePerStepM)));
      for (int s = 0; s < sub; ++s) Step(terrain, solids_, kPhysicsStepS / sub, report);
      ++report.steps;
    }
    done += n;
  }
  return report;
}

void PhysicalVehicle::Step(const Terrain& terrain, std::span<const Solid> solids, double h,
                           PhysicalReport& report) {
  const Vector3d x0 = x_, v0 = v_;
  const Quaterniond q0 = q_;
  const Matrix3d R = q_.toRotationMatrix();
  const Matrix3d Iinv = WorldInverseInertia(R);
  const double m = type_.mass_kg;

  struct Touch {
    Vector3d r, n, plane_point;
    double normal_n;
    const SoilGrip* grip;
    bool gear;
    Vector3d body;  // the contact's point, body frame
  };
  std::array<Touch, 512> touches;
  size_t count = 0;
  Vector3d F(0.0, -kGravityMps2 * m, 0.0), tau = Vector3d::Zero();
  double total_n = 0.0;
  bool gear_touching = false;
  FeatureId deck;
  double deck_n = 0.0;
  Vector3d deck_point = Vector3d::Zero();
  // The belly is sampled only where a crater, a berm or a bridge solid is near the footprint:
  // elsewhere the ground's triangles, far wider than the gear's spacing, cannot rise into it.
  const double half_diagonal = 0.5 * std::hypot(type_.base.length_m, type_.base.width_m);
  const size_t sampled =
      !solids.empty() ||
              AnyOverlaps(earthworks_, Rect{x_.x(), x_.z(), x_.x(), x_.z()}.Expanded(half_diagonal))
          ? contacts_.size()
          : always_count_;
  for (size_t k = 0; k < sampled && count < touches.size(); ++k) {
    Contact& c = contacts_[k];
    const Vector3d r = R * c.body;
    const Vector3d p = x_ + r;
    if (c.dense) {
      // Only over an earthwork can the ground rise into the belly between the running gear (the
      // bare ground's triangles are far wider than the gear's spacing), and belly grid points
      // rarely touch even there: a height alone tells, before the normal and soil. It also tells
      // whether the point is near enough to refine around (below).
      double e = 0.0;
      const bool over = EarthworkElevationAt(terrain, earthworks_, p.x(), p.z(), e);
      grid_near_[k] = over && e > p.y() - kBellyRefineGapM;
      if (solids.empty() && (!over || e <= p.y())) {
        c.air_steps = std::min(c.air_steps + 1, 1 << 20);
        continue;
      }
    }
    if (c.ground.stamp != terrain.stamp()) {
      c.ground.valid = false;
      c.ground.stamp = terrain.stamp();
    }
    const SurfaceSample s =
        SampleSurface(terrain, solids, p.x(), p.z(), p.y() + c.reach_m, c.ground);
    const double depth = (s.height_m - p.y()) * s.normal.y();
    if (depth <= 0.0) {
      c.air_steps = std::min(c.air_steps + 1, 1 << 20);
      continue;
    }
    const double vn = (v_ + w_.cross(r)).dot(s.normal);
    if (c.air_steps >= kLandingAirSteps)
      report.max_landing_mps = std::max(report.max_landing_mps, -vn);
    c.air_steps = 0;
    const double normal_n = std::max(0.0, spring_n_per_m_ * depth - damper_n_s_per_m_ * vn);
    F += normal_n * s.normal;
    tau += r.cross(normal_n * s.normal);
    total_n += normal_n;
    if (c.gear) {
      gear_touching = true;
      if (s.bridge.number != 0 && normal_n >= deck_n) {
        deck = s.bridge;
        deck_n = normal_n;
        deck_point = p;
      }
    }
    touches[count++] = {r,
                        s.normal,
                        Vector3d(p.x(), s.height_m, p.z()),
                        normal_n,
                        &type_.grip[static_cast<size_t>(s.material)],
                        c.gear,
                        c.body};
  }
  // Half-way points of the belly grid near the surface (kBellyRefineGapM): each edge of the grid
  // once, owned by the point towards +ahead / +left unless that neighbour is not near.
  if (sampled > always_count_) {
    const double L2 = type_.base.length_m / 2.0 + 1e-9, W2 = type_.base.width_m / 2.0 + 1e-9;
    const Vector3d steps[] = {{grid_step_ahead_m_, 0.0, 0.0},
                              {-grid_step_ahead_m_, 0.0, 0.0},
                              {0.0, 0.0, grid_step_left_m_},
                              {0.0, 0.0, -grid_step_left_m_}};
    for (size_t k = always_count_ + static_cast<size_t>(per_side_); k < sampled; ++k) {
      const Contact& c = contacts_[k];
      if (!grid_near_[k]) continue;
      for (int d = 0; d < 4 && count < touches.size(); ++d) {
        const Vector3d mid = c.body + 0.5 * steps[d];
        if (std::abs(mid.x()) > L2 || std::abs(mid.z()) > W2) continue;
        const bool towards_plus = d == 0 || d == 2;
        const int q = grid_neighbours_[k][static_cast<size_t>(d)];
        // The neighbour owns this edge.
        if (q >= 0 && grid_near_[static_cast<size_t>(q)] && !towards_plus) continue;
        const Vector3d r = R * mid;
        const Vector3d p = x_ + r;
        GroundPlaneCache cache;
        const SurfaceSample s =
            SampleSurface(terrain, solids, p.x(), p.z(), p.y() + c.reach_m, cache);
        const double depth = (s.height_m - p.y()) * s.normal.y();
        if (depth <= 0.0) continue;
        const double vn = (v_ + w_.cross(r)).dot(s.normal);
        const double normal_n = std::max(0.0, spring_n_per_m_ * depth - damper_n_s_per_m_ * vn);
        F += normal_n * s.normal;
        tau += r.cross(normal_n * s.normal);
        total_n += normal_n;
        touches[count++] = {r,
                            s.normal,
                            Vector3d(p.x(), s.height_m, p.z()),
                            normal_n,
                            &type_.grip[static_cast<size_t>(s.material)],
                            false,
                            mid};
      }
    }
  }

  // Grip: the driver's demand, limited by engine and by friction x normal force (docs/vehicles.md
  // "Drive and grip").
  if (total_n > 0.0) {
    Vector3d nbar = Vector3d::Zero();
    double cs = 0.0, cd = 0.0, cg = 0.0, rr = 0.0;
    for (size_t i = 0; i < count; ++i) {
      const Touch& t = touches[i];
      nbar += t.normal_n * t.n;
      cs += t.grip->static_friction * t.normal_n;
      cd += t.grip->dynamic_friction * t.normal_n;
      if (t.gear) {
        rr += t.grip->rolling_resistance * t.normal_n;
        // A face steeper than the grip's angle (tan > static friction) is a wall to the running
        // gear: pressing into it gives no drive up it.
        const double mu = t.grip->static_friction;
        if (t.n.y() * std::sqrt(1.0 + mu * mu) >= 1.0) cg += mu * t.normal_n;
      }
    }
    nbar.normalize();
    Vector3d f = R.col(0) - R.col(0).dot(nbar) * nbar;
    if (f.norm() > 1e-6) {
      f.normalize();
      const Vector3d side = nbar.cross(f);
      const Vector3d vp = v_ + F / m * h;
      const Vector3d wp = w_ + Iinv * tau * h;
      // Heading grows counter-clockwise seen from above: about -y in these coordinates.
      const Vector3d yaw_axis = -nbar;
      const double vf = vp.dot(f), vs = vp.dot(side), yaw = wp.dot(yaw_axis);
      const bool drive = mobile();
      double v_cmd = drive ? cmd_speed_mps_ : 0.0;
      double r_cmd = drive ? cmd_rate_rad_s_ : 0.0;
      if (type_.min_turn_radius_m > 0.0) {
        const double limit = std::abs(vf) / type_.min_turn_radius_m;
        r_cmd = std::clamp(r_cmd, -limit, limit);
      }
      if (!gear_touching) v_cmd = vf;  // a beached hull has nothing to push with
      const double f_rr = (vf > 0 ? -1.0 : 1.0) * std::min(rr, m * std::abs(vf) / h);
      const double vf1 = vf + f_rr * h / m;
      double fw = m * (v_cmd - vf1) / h;
      const bool accelerating = v_cmd != 0.0 && fw * v_cmd > 0.0 && vf1 * v_cmd >= 0.0;
      const double fs = -m * vs / h;
      const Vector3d yaw_body = R.transpose() * yaw_axis;
      const double inertia_n = yaw_body.dot(inertia_.cwiseProduct(yaw_body));
      const double moment = inertia_n * (r_cmd - yaw) / h;
      const double arm = type_.base.length_m / 4.0;
      if (accelerating) {
        // The engine drives with what grip the side force and the turn leave: pressed against a
        // wall at an angle, the running gear holds sideways rather than spinning and sliding
        // along it at a speed that grew with the step.
        const double engine = type_.engine_power_w / std::max(std::abs(vf1), kEngineFloorSpeedMps);
        const double left = cs * cs - fs * fs - (moment / arm) * (moment / arm);
        const double limit = std::min({engine, cg, std::sqrt(std::max(0.0, left))});
        fw = std::clamp(fw, -limit, limit);
      }
      const double demand = std::sqrt(fw * fw + fs * fs + (moment / arm) * (moment / arm));
      double scale = 1.0;
      if (demand > cs) {
        scale = cd / demand;
        report.sliding = true;
      }
      const Vector3d ft = (fw * f + fs * side) * scale + f_rr * f;
      for (size_t i = 0; i < count; ++i) {
        const Vector3d fi = ft * (touches[i].normal_n / total_n);
        F += fi;
        tau += touches[i].r.cross(fi);
      }
      tau += yaw_axis * (moment * scale);
    }
  }

  // Semi-implicit Euler; the angular part in the body frame with the gyroscopic term.
  v_ += F / m * h;
  Vector3d wb = R.transpose() * w_;
  const Vector3d tb = R.transpose() * tau;
  wb += (tb - wb.cross(inertia_.cwiseProduct(wb))).cwiseQuotient(inertia_) * h;
  w_ = R * wb;
  x_ += v_ * h;
  Rotate(q_, w_ * h);

  // Hard stops: a contact compressed beyond its travel is pushed back onto it (positions and
  // velocities, with the contact's effective mass), up to four times over for the coupled
  // contacts.
  for (int pass = 0; pass < 4; ++pass) {
    bool corrected = false;
    Matrix3d Rn = q_.toRotationMatrix();
    Matrix3d Iw = WorldInverseInertia(Rn);
    for (size_t i = 0; i < count; ++i) {
      const Touch& t = touches[i];
      const Vector3d r = Rn * t.body;
      const double travel = t.gear ? kGearTravelM : kBellyTravelM;
      const double depth = (t.plane_point - (x_ + r)).dot(t.n);
      if (depth <= travel) continue;
      corrected = true;
      const Vector3d rn = r.cross(t.n);
      const double w = 1.0 / m + rn.dot(Iw * rn);
      const double p = (depth - travel) / w;
      x_ += t.n * (p / m);
      Rotate(q_, Iw * rn * p);
      const double vn = (v_ + w_.cross(r)).dot(t.n);
      if (vn < 0.0) {
        const double j = -vn / w;
        v_ += t.n * (j / m);
        w_ += Iw * rn * j;
      }
      Rn = q_.toRotationMatrix();
      Iw = WorldInverseInertia(Rn);
    }
    if (!corrected) break;
  }

  if (!solids.empty()) ResolveHull(solids, report);

  if (!OnTerrain(terrain)) {
    // Stop at the edge, as the kinematic vehicle does.
    x_ = x0;
    q_ = q0;
    v_ = Vector3d(0.0, v0.y(), 0.0);
    w_ = Vector3d::Zero();
    cmd_speed_mps_ = 0.0;
    cmd_rate_rad_s_ = 0.0;
  }

  // Bridge tag: the deck carrying the running gear (docs/vehicles.md "Bridge events"). The tag
  // goes only after kLeaveDeckSteps without the deck, so a vehicle bouncing or tipping on a deck
  // edge leaves once; after a fall, touching the same deck again is not getting on it until the
  // vehicle has been off it for kFallLatchSteps.
  air_steps_ = gear_touching ? 0 : air_steps_ + 1;
  if (deck.number != 0) {
    off_deck_steps_ = 0;
    if (deck != bridge_) {
      if (on_bridge() && bridge_ != fell_from_) report.drove_off = bridge_;
      if (deck != fell_from_) report.mounted = deck;
      bridge_ = deck;
    }
    last_deck_x_m_ = deck_point.x();
    last_deck_z_m_ = deck_point.z();
  } else {
    off_deck_steps_ = std::min(off_deck_steps_ + 1, 1 << 20);
    if (on_bridge() && off_deck_steps_ >= kLeaveDeckSteps) {
      if (bridge_ != fell_from_) {
        if (NearRampFoot(terrain, bridge_)) {
          report.drove_off = bridge_;
        } else {
          report.fell_off = bridge_;
          fell_from_ = bridge_;
        }
      }
      bridge_ = FeatureId{};
    }
    if (off_deck_steps_ >= kFallLatchSteps) fell_from_ = FeatureId{};
  }

  // Damage: landing speed, then static stability.
  if (alive()) {
    if (report.max_landing_mps >= type_.land_kill_mps) {
      Damaged(Damage::kDestroyed,
              fmt::format("landed at {:.2f} m/s (kill threshold {} m/s)", report.max_landing_mps,
                          type_.land_kill_mps),
              report);
    } else if (report.max_landing_mps >= type_.land_immobilise_mps) {
      Damaged(Damage::kImmobilised,
              fmt::format("landed at {:.2f} m/s (immobilise threshold {} m/s)",
                          report.max_landing_mps, type_.land_immobilise_mps),
              report);
    }
  }
  // Static stability, for a wreck too: the hull has no contacts on its sides and roof, so one
  // destroyed by a landing that then rolled over would sink into the ground on its side.
  // |pitch| > limit is |forward.y| > sin(limit); |roll| > limit is |left.y| > tan(limit) up.y.
  const Matrix3d Rn = q_.toRotationMatrix();
  const double up_y = Rn(1, 1);
  if (up_y <= 0.0 || std::abs(Rn(1, 0)) > sin_pitch_limit_ ||
      std::abs(Rn(1, 2)) > tan_roll_limit_ * up_y) {
    const double roll = roll_rad(), pitch = pitch_rad();
    Damaged(Damage::kDestroyed,
            fmt::format("tipped over (pitch {:.1f} deg, roll {:.1f} deg; static stability {:.1f} "
                        "/ {:.1f} deg)",
                        pitch * 180.0 / std::numbers::pi, roll * 180.0 / std::numbers::pi,
                        type_.StaticPitchLimitRad() * 180.0 / std::numbers::pi,
                        type_.StaticRollLimitRad() * 180.0 / std::numbers::pi),
            report);
    // The wreck stays where it came to lie: once it rests on something (a contact touched in
    // this step, or a hull corner is down at the ground). One that tips in the air falls on.
    if (count > 0 || HullCornerAtGround(terrain)) frozen_ = true;
  }
}

bool PhysicalVehicle::HullCornerAtGround(const Terrain& terrain) const {
  const double L = type_.base.length_m / 2.0, W = type_.base.width_m / 2.0;
  const double lo = -type_.cg_height_m, hi = type_.hull_height_m - type_.cg_height_m;
  const Matrix3d r = q_.toRotationMatrix();
  for (const double a : {-L, L}) {
    for (const double l : {-W, W}) {
      for (const double u : {lo, hi}) {
        const Vector3d p = x_ + r * Vector3d(a, u, l);
        if (p.y() <= terrain.ElevationAt(p.x(), p.z())) return true;
      }
    }
  }
  return false;
}

bool PhysicalVehicle::NearRampFoot(const Terrain& terrain, FeatureId id) const {
  const Feature* f = terrain.Find(id);
  if (f == nullptr || f->type() != FeatureType::kBridge) return false;
  const auto* b = static_cast<const Bridge*>(f);
  const double along = b->ToBridge(last_deck_x_m_, last_deck_z_m_).along_m;
  const double h = kBridgeHotSpotLengthM / 2.0;
  return std::abs(along - b->start_along_m()) <= h || std::abs(along - b->end_along_m()) <= h;
}

void PhysicalVehicle::ResolveHull(std::span<const Solid> solids, PhysicalReport& report) {
  // Only solids within the hull's bounding sphere are tested point by point.
  const double radius = 0.5 * std::sqrt(type_.base.length_m * type_.base.length_m +
                                        type_.base.width_m * type_.base.width_m +
                                        type_.hull_height_m * type_.hull_height_m) +
                        type_.cg_height_m;
  std::array<Solid, 32> near;
  size_t near_count = 0;
  for (const Solid& s : solids) {
    double a, r;
    s.ToLocal(x_.x(), x_.z(), a, r);
    const double da = std::max({s.a0_m - a, a - s.a1_m, 0.0});
    const double dr = std::max({s.r0_m - r, r - s.r1_m, 0.0});
    if (da * da + dr * dr > radius * radius) continue;
    const double top = std::max(s.top0_m, s.top1_m), bottom = std::min(s.bottom0_m, s.bottom1_m);
    if (x_.y() - radius > top || x_.y() + radius < bottom) continue;
    if (near_count < near.size()) near[near_count++] = s;
  }
  if (near_count == 0) return;
  std::array<Vector3d, 1024> world;
  const size_t n = std::min(world.size(), hull_points_.size());
  for (int pass = 0; pass < 4; ++pass) {
    const Matrix3d R = q_.toRotationMatrix();
    const bool level_bottom = (R * Vector3d::UnitY()).y() > kLevelBottomMinCos;
    for (size_t i = 0; i < n; ++i) world[i] = x_ + R * hull_points_[i];
    const HullPenetration hit = DeepestPenetration(std::span<const Vector3d>(world.data(), n),
                                                   std::span<const Solid>(near.data(), near_count),
                                                   kBellyTravelM, level_bottom);
    if (!hit.hit) return;
    report.blocked = true;
    const Vector3d& face = hit.normal;
    // A level bottom resting on a deck's edge turns as well as moves, as through an underside:
    // translated alone, the roll that brought the edge down went on.
    if (face.y() > -0.5 && !(level_bottom && face.y() > 0.5)) {
      // Through a side, the top, or level out from under a sloping face: the hull moves out and
      // loses its velocity into the face.
      x_ += hit.push_m;
      const double into = v_.dot(face);
      if (into < 0.0) v_ -= into * face;
      continue;
    }
    // Down through a slab's underside (a roof or corner grazing it): as the hard stops, the point
    // is moved out and its velocity into the face removed with the point's effective mass, so the
    // hull turns as well as moves. Moving it down alone left the angular velocity that had turned
    // the corner in, and the corner was pushed down through the springs step after step: a fall
    // with no speed, which the ground's hard stops then fought.
    const Vector3d r = hit.point_m - x_;
    // Driving on into a ceiling that comes down (a roof under a ramp's underside) is a wedge: the
    // slope turned the forward speed into a downward push that squeezed the hull down faster than
    // it could fall. The wedge stops the vehicle instead: the hull goes back level the way it
    // came in (out from under the slope, as far as it drove in) and loses its speed into the
    // wedge.
    const Vector3d level(face.x(), 0.0, face.z());
    const double level_norm = level.norm();
    if (level_norm > 1e-6) {
      const Vector3d back = level / level_norm;  // towards where the ceiling rises
      const double level_m = hit.depth_m * std::abs(face.y()) / level_norm;
      const double into = (v_ + w_.cross(r)).dot(back);
      if (into < 0.0 && level_m <= kWedgeLevelExitMaxM) {
        x_ += back * level_m;
        const double com_into = v_.dot(back);
        if (com_into < 0.0) v_ -= com_into * back;
        continue;
      }
    }
    const Matrix3d Iw = WorldInverseInertia(R);
    const Vector3d rn = r.cross(face);
    const double w = 1.0 / type_.mass_kg + rn.dot(Iw * rn);
    const double p = hit.depth_m / w;
    x_ += face * (p / type_.mass_kg);
    Rotate(q_, Iw * rn * p);
    const double vn = (v_ + w_.cross(r)).dot(face);
    if (vn < 0.0) {
      const double j = -vn / w;
      v_ += face * (j / type_.mass_kg);
      w_ += Iw * rn * j;
    }
  }
}

}  // namespace dt
