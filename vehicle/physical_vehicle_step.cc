// PhysicalVehicle::Step, one fixed step: contacts, grip, integration, hard stops, bridge tag,
// damage (docs/vehicles.md).
#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <span>

#include <fmt/format.h>

#include "terrain/bridge.h"
#include "vehicle/contact_surface.h"
#include "vehicle/physical_vehicle.h"
#include "vehicle/physical_vehicle_internal.h"

namespace dt {
namespace {

using Eigen::Matrix3d;
using Eigen::Quaterniond;
using Eigen::Vector3d;
using physical_internal::kBellyTravelM;
using physical_internal::kLevelBottomMinCos;
using physical_internal::Rotate;

// The tag leaves after 0.1 s without the deck; a fall stays latched for 1 s.
constexpr double kLeaveDeckS = 0.1;
constexpr double kFallLatchS = 1.0;
// Latch times stop growing here, so that adding a step still changes them.
constexpr double kLatchCapS = 1e3;
// A belly grid point this close to the surface also samples half-way to its neighbours: a crease
// of an earthwork (a crater ring, a berm's top edge) between two grid points can rise above the
// line joining them by a quarter of the spacing times the slopes' sum, more than the 0.1 m the
// hull may enter on a tilted hull; half-way points bring that under 0.04 m.
constexpr double kBellyRefineGapM = 0.1;
// Points along a solid's top edge under the belly are at most this far apart, and this far inside
// the edge.
constexpr double kEdgeSampleSpacingM = 0.25;
constexpr double kEdgeInsetM = 0.01;
// An edge under the belly supports it only if the solid's top there is at most this far below
// the belly (farther, the belly is clear of it; above, the hull meets a side: ResolveHull).
constexpr double kEdgeSupportGapM = 0.1;

// The part of segment a..b (plan x, z) inside the convex quadrilateral q (counter-clockwise or
// clockwise), as parameters [t0, t1] of a + t (b - a); false if none.
bool ClipToQuad(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                const std::array<Eigen::Vector2d, 4>& q, double& t0, double& t1) {
  const Eigen::Vector2d d = b - a;
  // The quad's orientation: the sign of its area.
  double area2 = 0.0;
  for (size_t i = 0; i < 4; ++i) {
    const Eigen::Vector2d& p = q[i];
    const Eigen::Vector2d& n = q[(i + 1) % 4];
    area2 += p.x() * n.y() - n.x() * p.y();
  }
  const double sign = area2 >= 0.0 ? 1.0 : -1.0;
  t0 = 0.0;
  t1 = 1.0;
  for (size_t i = 0; i < 4; ++i) {
    const Eigen::Vector2d e = q[(i + 1) % 4] - q[i];
    // Inside is where sign * cross(e, p - q[i]) >= 0.
    const double at_a = sign * (e.x() * (a.y() - q[i].y()) - e.y() * (a.x() - q[i].x()));
    const double rate = sign * (e.x() * d.y() - e.y() * d.x());
    if (std::abs(rate) < 1e-12) {
      if (at_a < 0.0) return false;
      continue;
    }
    const double t = -at_a / rate;
    if (rate > 0.0) {
      t0 = std::max(t0, t);
    } else {
      t1 = std::min(t1, t);
    }
    if (t0 > t1) return false;
  }
  return true;
}

// Far above the rounding of a contact's depth, its move in a step and the rotation matrix.
constexpr double kHardStopSlackM = 1e-6;

// Below this speed the engine's force is taken at this speed (P / v is unbounded at rest).
constexpr double kEngineFloorSpeedMps = 1.0;

}  // namespace

void PhysicalVehicle::Step(const Terrain& terrain, std::span<const Solid> solids, double h,
                           PhysicalReport& report) {
  const Vector3d x0 = x_, v0 = v_;
  const Quaterniond q0 = q_;
  const Matrix3d R = Rotation();
  std::array<Touch, kMaxTouches> touches;
  StepForces forces;
  forces.F = Vector3d(0.0, -kGravityMps2 * type_.mass_kg, 0.0);
  size_t count = GatherTouches(terrain, solids, R, h, touches, forces, report);
  count = GatherRefinedBellyTouches(terrain, solids, R, touches, count, forces);
  if (!alive()) count = GatherWreckTouches(terrain, solids, R, touches, count, forces);
  if (!solids.empty()) count = GatherSolidEdgeTouches(terrain, solids, R, touches, count, forces);
  const std::span<const Touch> touched(touches.data(), count);
  if (forces.total_n > 0.0) ApplyGrip(R, h, touched, forces, report);
  Integrate(forces, R, h);
  ApplyHardStops(touched, x0, h);

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
  UpdateBridgeTag(terrain, forces, h, report);
  CheckDamage(report);
}

// Inlined: the gatherers call it per touch, and the call with its eleven arguments cost more
// than its body.
[[gnu::always_inline]] inline double PhysicalVehicle::AddTouch(
    const Vector3d& r, const Vector3d& p, const Vector3d& body, const SurfaceSample& s,
    double depth_m, double vn_mps, bool gear, StepForces& forces, std::span<Touch> touches,
    size_t& count, double stiffness) {
  const double normal_n =
      stiffness * std::max(0.0, spring_n_per_m_ * depth_m - damper_n_s_per_m_ * vn_mps);
  forces.F += normal_n * s.normal;
  forces.tau += r.cross(normal_n * s.normal);
  forces.total_n += normal_n;
  if (!gear && s.bridge.number != 0) forces.hull_deck = s.bridge;
  const size_t material = static_cast<size_t>(s.material);
  const SoilGrip& grip = type_.grip[material];
  // What ApplyGrip sums over the touches, summed here in the same order.
  forces.normal_sum += normal_n * s.normal;
  forces.static_n += grip.static_friction * normal_n;
  forces.dynamic_n += grip.dynamic_friction * normal_n;
  if (gear) {
    forces.rolling_n += grip.rolling_resistance * normal_n;
    // A face steeper than the grip's angle (tan > static friction) is a wall to the running
    // gear: pressing into it gives no drive up it.
    if (s.normal.y() * grip_wall_factor_[material] >= 1.0)
      forces.climb_n += grip.static_friction * normal_n;
  }
  touches[count++] = {r,    s.normal, Vector3d(p.x(), s.height_m, p.z()), depth_m, normal_n,
                      gear, body};
  return normal_n;
}

size_t PhysicalVehicle::GatherTouches(const Terrain& terrain, std::span<const Solid> solids,
                                      const Matrix3d& R, double h, std::span<Touch> touches,
                                      StepForces& forces, PhysicalReport& report) {
  size_t count = 0;
  // The belly is sampled only where a crater, a berm or a bridge solid is near the footprint:
  // elsewhere the ground's triangles, far wider than the gear's spacing, cannot rise into it.
  const double half_diagonal = half_diagonal_m_;
  forces.sampled =
      !solids.empty() ||
              AnyOverlaps(earthworks_, Rect{x_.x(), x_.z(), x_.x(), x_.z()}.Expanded(half_diagonal))
          ? contacts_.size()
          : always_count_;
  // Without solids, a grid point outside every earthwork's bounds meets nothing.
  const bool grid_marked = solids.empty() && forces.sampled > always_count_;
  if (grid_marked) {
    std::fill(grid_over_earthwork_.begin(), grid_over_earthwork_.end(), 0);
    belly_grid_.MarkUnder(x_, R, earthworks_, grid_over_earthwork_);
  }
  // A contact clear of the surface adds to its time in the air; the grid's points share the belly
  // clock instead (below), so those no earthwork's bounds can hold are not visited.
  auto clear = [&](Contact& c) {
    if (!c.dense) c.air_s = std::min(c.air_s + h, kLatchCapS);
  };
  // Inlined for the reason AddTouch is.
  auto visit = [&](size_t k) __attribute__((always_inline)) {
    if (count >= touches.size()) return;
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
      if (solids.empty() && (!over || e <= p.y())) return;
    }
    if (c.ground.stamp != terrain.stamp()) {
      c.ground.valid = false;
      c.ground.stamp = terrain.stamp();
    }
    SurfaceSample s;
    if (solids.empty() && c.ground.Holds(p.x(), p.z())) {
      // SampleSurface's answer from the kept plane, asked here first: most contacts are clear of
      // it, and they need no sample.
      s.height_m = c.ground.HeightAt(p.x(), p.z());
      if ((s.height_m - p.y()) * c.ground.normal.y() <= 0.0) return clear(c);
      s.normal = c.ground.normal;
      s.material = c.ground.material;
    } else {
      s = SampleSurface(terrain, solids, {near_earthworks_, near_area_}, p.x(), p.z(),
                        p.y() + c.reach_m, c.ground);
    }
    const double depth = (s.height_m - p.y()) * s.normal.y();
    if (depth <= 0.0) return clear(c);
    const double vn = (v_ + w_.cross(r)).dot(s.normal);
    const double air_s = c.dense ? belly_clock_s_ - grid_touched_until_s_[k] : c.air_s;
    if (air_s >= kLandingAirS - kLatchSlackS)
      report.max_landing_mps = std::max(report.max_landing_mps, -vn);
    if (c.dense) {
      grid_touched_until_s_[k] = belly_clock_s_ + h;
    } else {
      c.air_s = 0.0;
    }
    const double normal_n = AddTouch(r, p, c.body, s, depth, vn, c.gear, forces, touches, count);
    if (c.gear) {
      forces.gear_touching = true;
      if (s.bridge.number != 0 && normal_n >= forces.deck_n) {
        forces.deck = s.bridge;
        forces.deck_n = normal_n;
      }
    }
  };
  const size_t first_grid =
      std::min(forces.sampled, always_count_ + static_cast<size_t>(per_side_));
  for (size_t k = 0; k < first_grid; ++k) visit(k);
  if (forces.sampled > always_count_) {
    std::fill(grid_near_.begin(), grid_near_.end(), 0);
    for (size_t k = first_grid; k < forces.sampled; ++k) {
      if (!grid_marked || grid_over_earthwork_[k]) visit(k);
    }
    // The belly clock runs in the steps that sample the belly, as a point's time in the air did
    // when each point counted its own.
    belly_clock_s_ += h;
  }
  return count;
}

// A wreck's whole box meets the ground and the solids' tops, so it falls, tumbles and comes to
// rest on any face.
size_t PhysicalVehicle::GatherWreckTouches(const Terrain& terrain, std::span<const Solid> solids,
                                           const Matrix3d& R, std::span<Touch> touches,
                                           size_t count, StepForces& forces) {
  for (Contact& c : wreck_contacts_) {
    if (count >= touches.size()) break;
    const Vector3d r = R * c.body;
    const Vector3d p = x_ + r;
    if (c.ground.stamp != terrain.stamp()) {
      c.ground.valid = false;
      c.ground.stamp = terrain.stamp();
    }
    // Most of the box is clear of the surface: the kept ground plane tells, before a sample.
    if (solids.empty()) {
      if (c.ground.Holds(p.x(), p.z())) {
        if ((c.ground.HeightAt(p.x(), p.z()) - p.y()) * c.ground.normal.y() <= 0.0) continue;
      } else {
        // Over an earthwork no plane is kept, and a sample takes three heights and the soil; the
        // height alone (the sample's, bit for bit) clears most of the box, as for the belly grid.
        double e = 0.0;
        if (EarthworkElevationAt(terrain, earthworks_, p.x(), p.z(), e) && e <= p.y()) continue;
      }
    }
    const SurfaceSample s = SampleSurface(terrain, solids, {near_earthworks_, near_area_}, p.x(),
                                          p.z(), p.y() + c.reach_m, c.ground);
    const double depth = (s.height_m - p.y()) * s.normal.y();
    if (depth <= 0.0) continue;
    AddTouch(r, p, c.body, s, depth, (v_ + w_.cross(r)).dot(s.normal), false, forces, touches,
             count, wreck_stiffness_);
  }
  return count;
}

size_t PhysicalVehicle::GatherRefinedBellyTouches(const Terrain& terrain,
                                                  std::span<const Solid> solids, const Matrix3d& R,
                                                  std::span<Touch> touches, size_t count,
                                                  StepForces& forces) {
  // Half-way points of the belly grid near the surface (kBellyRefineGapM): each edge of the grid
  // once, owned by the point towards +ahead / +left unless that neighbour is not near.
  if (forces.sampled <= always_count_) return count;
  const double L2 = type_.base.length_m / 2.0 + 1e-9, W2 = type_.base.width_m / 2.0 + 1e-9;
  const double ahead = belly_grid_.station_step_m(), left = belly_grid_.line_step_m();
  const Vector3d steps[] = {
      {ahead, 0.0, 0.0}, {-ahead, 0.0, 0.0}, {0.0, 0.0, left}, {0.0, 0.0, -left}};
  for (size_t k = always_count_ + static_cast<size_t>(per_side_); k < forces.sampled; ++k) {
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
      if (solids.empty()) {
        // The height alone first (the sample's, bit for bit): most half-way points are clear.
        double e = 0.0;
        if (!EarthworkElevationAt(terrain, earthworks_, p.x(), p.z(), e))
          e = terrain.GroundElevationAt(p.x(), p.z());
        if (e <= p.y()) continue;
      }
      GroundPlaneCache cache;
      const SurfaceSample s = SampleSurface(terrain, solids, {near_earthworks_, near_area_}, p.x(),
                                            p.z(), p.y() + c.reach_m, cache);
      const double depth = (s.height_m - p.y()) * s.normal.y();
      if (depth <= 0.0) continue;
      AddTouch(r, p, mid, s, depth, (v_ + w_.cross(r)).dot(s.normal), false, forces, touches,
               count);
    }
  }
  return count;
}

size_t PhysicalVehicle::GatherSolidEdgeTouches(const Terrain& terrain,
                                               std::span<const Solid> solids, const Matrix3d& R,
                                               std::span<Touch> touches, size_t count,
                                               StepForces& forces) {
  // A deck's edge under the belly carries the hull at the edge itself, not at the nearest belly
  // grid point inside it (up to a grid spacing short): a vehicle with one side's wheels off a
  // deck rests on its bottom at the edge while its centre of mass is over the deck.
  // Tilted further, the hull's side meets the edge instead (ResolveHull), and slides off it.
  if (R(1, 1) <= kLevelBottomMinCos) return count;
  const double L2 = type_.base.length_m / 2.0, W2 = type_.base.width_m / 2.0;
  const double bottom_up = type_.clearance_m - type_.cg_height_m;  // body frame
  std::array<Eigen::Vector2d, 4> quad;
  const double corners[4][2] = {{L2, W2}, {-L2, W2}, {-L2, -W2}, {L2, -W2}};
  double lowest = INFINITY;
  for (size_t i = 0; i < 4; ++i) {
    const Vector3d p = x_ + R * Vector3d(corners[i][0], bottom_up, corners[i][1]);
    quad[i] = {p.x(), p.z()};
    lowest = std::min(lowest, p.y());
  }
  // Plan x, z of body (ahead, left) on the bottom face, for the inverse map.
  Eigen::Matrix2d plan;
  plan << R(0, 0), R(0, 2), R(2, 0), R(2, 2);
  const Eigen::Matrix2d to_body = plan.inverse();
  const Eigen::Vector2d offset(x_.x() + R(0, 1) * bottom_up, x_.z() + R(2, 1) * bottom_up);
  for (const Solid& s : solids) {
    const double top_max = std::max(s.top0_m, s.top1_m);
    if (top_max < lowest - kEdgeSupportGapM) continue;
    // The four edges of the solid's plan, in its frame: (a, r) from and to.
    const double edges[4][4] = {{s.a0_m, s.r0_m, s.a1_m, s.r0_m},
                                {s.a0_m, s.r1_m, s.a1_m, s.r1_m},
                                {s.a0_m, s.r0_m, s.a0_m, s.r1_m},
                                {s.a1_m, s.r0_m, s.a1_m, s.r1_m}};
    const double mid_a = 0.5 * (s.a0_m + s.a1_m), mid_r = 0.5 * (s.r0_m + s.r1_m);
    for (const auto& e : edges) {
      // Bridge frame to world plan: x = origin + a u + r (uz, -ux).
      auto world = [&](double a, double r) {
        return Eigen::Vector2d(s.origin_x_m + a * s.ux + r * s.uz,
                               s.origin_z_m + a * s.uz - r * s.ux);
      };
      // Inset towards the solid's middle, so the samples lie on its top.
      const double ia = e[0] == e[2] ? (mid_a > e[0] ? kEdgeInsetM : -kEdgeInsetM) : 0.0;
      const double ir = e[1] == e[3] ? (mid_r > e[1] ? kEdgeInsetM : -kEdgeInsetM) : 0.0;
      const Eigen::Vector2d a = world(e[0] + ia, e[1] + ir), b = world(e[2] + ia, e[3] + ir);
      double t0 = 0.0, t1 = 0.0;
      if (!ClipToQuad(a, b, quad, t0, t1)) continue;
      const double length = (b - a).norm() * (t1 - t0);
      const int n = std::max(1, static_cast<int>(std::ceil(length / kEdgeSampleSpacingM))) + 1;
      for (int k = 0; k < n && count < touches.size(); ++k) {
        const double t = t0 + (t1 - t0) * k / (n - 1);
        const Eigen::Vector2d at = a + t * (b - a);
        const Eigen::Vector2d ahead_left = to_body * (at - offset);
        const Vector3d body(ahead_left.x(), bottom_up, ahead_left.y());
        const Vector3d r = R * body;
        const Vector3d p = x_ + r;
        double along = 0.0, right = 0.0;
        s.ToLocal(p.x(), p.z(), along, right);
        const double top = s.TopAt(std::clamp(along, s.a0_m, s.a1_m));
        // Clear of the belly, or a side the hull meets (not a top it rests on).
        if (top <= p.y() - kEdgeSupportGapM || top > p.y() + kBellyTravelM) continue;
        GroundPlaneCache cache;
        const SurfaceSample sample =
            SampleSurface(terrain, solids, p.x(), p.z(), p.y() + kBellyTravelM, cache);
        const double depth = (sample.height_m - p.y()) * sample.normal.y();
        if (depth <= 0.0) continue;
        AddTouch(r, p, body, sample, depth, (v_ + w_.cross(r)).dot(sample.normal), false, forces,
                 touches, count);
      }
    }
  }
  return count;
}

void PhysicalVehicle::ApplyGrip(const Matrix3d& R, double h, std::span<const Touch> touches,
                                StepForces& forces, PhysicalReport& report) {
  // Grip: the driver's demand, limited by engine and by friction x normal force (docs/vehicles.md
  // "Drive and grip").
  const Matrix3d Iinv = WorldInverseInertia(R);
  const double m = type_.mass_kg;
  Vector3d& F = forces.F;
  Vector3d& tau = forces.tau;
  Vector3d nbar = forces.normal_sum;
  const double cs = forces.static_n, cd = forces.dynamic_n, cg = forces.climb_n;
  const double rr = forces.rolling_n;
  nbar.normalize();
  Vector3d f = R.col(0) - R.col(0).dot(nbar) * nbar;
  if (f.norm() <= 1e-6) return;
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
  // A beached hull has nothing to push with; a wreck brakes on whatever it touches.
  if (!forces.gear_touching && drive) v_cmd = vf;
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
  for (const Touch& t : touches) {
    const Vector3d fi = ft * (t.normal_n / forces.total_n);
    F += fi;
    tau += t.r.cross(fi);
  }
  tau += yaw_axis * (moment * scale);
}

void PhysicalVehicle::Integrate(const StepForces& forces, const Matrix3d& R, double h) {
  // Semi-implicit Euler; the angular part in the body frame with the gyroscopic term.
  v_ += forces.F / type_.mass_kg * h;
  Vector3d wb = R.transpose() * w_;
  const Vector3d tb = R.transpose() * forces.tau;
  wb += (tb - wb.cross(inertia_.cwiseProduct(wb))).cwiseQuotient(inertia_) * h;
  w_ = R * wb;
  x_ += v_ * h;
  Rotate(q_, w_ * h);
}

void PhysicalVehicle::ApplyHardStops(std::span<const Touch> touches, const Vector3d& x_before,
                                     double h) {
  // Hard stops: a contact compressed beyond its travel is pushed back onto it (positions and
  // velocities, with the contact's effective mass), up to four times over for the coupled
  // contacts.
  // Most steps have none, and that is known without the new rotation: a contact's depth grew in
  // Integrate by at most the centre of mass's move plus its point's move in the turn, which
  // Rotate makes at most |w| h radians, about a point within box_radius_m_.
  const double move_m = (x_ - x_before).norm() + w_.norm() * h * box_radius_m_ + kHardStopSlackM;
  if (std::none_of(touches.begin(), touches.end(), [&](const Touch& t) {
        return t.depth_m + move_m > (t.gear ? kGearTravelM : kBellyTravelM);
      }))
    return;
  const double m = type_.mass_kg;
  for (int pass = 0; pass < 4; ++pass) {
    bool corrected = false;
    Matrix3d Rn = Rotation();
    for (const Touch& t : touches) {
      const Vector3d r = Rn * t.body;
      const double travel = t.gear ? kGearTravelM : kBellyTravelM;
      const double depth = (t.plane_point - (x_ + r)).dot(t.n);
      if (depth <= travel) continue;
      corrected = true;
      // Only for a contact beyond its travel (most steps have none); the rotation changes below.
      const Matrix3d Iw = WorldInverseInertia(Rn);
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
      Rn = Rotation();
    }
    if (!corrected) break;
  }
}

void PhysicalVehicle::UpdateBridgeTag(const Terrain& terrain, const StepForces& forces, double h,
                                      PhysicalReport& report) {
  // Bridge tag: the deck carrying the running gear (docs/vehicles.md "Bridge events"). The tag
  // goes only after kLeaveDeckS without the deck, so a vehicle bouncing or tipping on a deck
  // edge leaves once; after a fall, touching the same deck again is not getting on it until the
  // vehicle has been off it for kFallLatchS.
  air_s_ = forces.gear_touching ? 0.0 : std::min(air_s_ + h, kLatchCapS);
  const FeatureId deck = forces.deck;
  if (deck.number != 0) {
    off_deck_s_ = 0.0;
    if (deck != bridge_) {
      if (on_bridge() && bridge_ != fell_from_) report.drove_off = bridge_;
      if (deck != fell_from_) report.mounted = deck;
      bridge_ = deck;
    }
  } else if (on_bridge() && forces.hull_deck == bridge_) {
    // The running gear lifted (a bounce) while the hull rests on the deck: still on it.
    off_deck_s_ = 0.0;
  } else {
    off_deck_s_ = std::min(off_deck_s_ + h, kLatchCapS);
    if (on_bridge() && off_deck_s_ >= kLeaveDeckS - kLatchSlackS) {
      if (bridge_ != fell_from_) {
        if (alive() && InOuterHotSpot(terrain, bridge_)) {
          report.drove_off = bridge_;
        } else {
          report.fell_off = bridge_;
          fell_from_ = bridge_;
        }
      }
      bridge_ = FeatureId{};
    }
    if (off_deck_s_ >= kFallLatchS - kLatchSlackS) fell_from_ = FeatureId{};
  }
}

void PhysicalVehicle::CheckDamage(PhysicalReport& report) {
  // Damage: landing speed or impact speed (both the speed lost along the contact's normal),
  // then static stability.
  if (alive()) {
    const bool impact = report.max_impact_mps > report.max_landing_mps;
    const double speed = std::max(report.max_landing_mps, report.max_impact_mps);
    const char* what = impact ? "hit a bridge solid" : "landed";
    if (speed >= type_.land_kill_mps) {
      Damaged(
          Damage::kDestroyed,
          fmt::format("{} at {:.2f} m/s (kill threshold {} m/s)", what, speed, type_.land_kill_mps),
          report);
    } else if (speed >= type_.land_immobilise_mps) {
      Damaged(Damage::kImmobilised,
              fmt::format("{} at {:.2f} m/s (immobilise threshold {} m/s)", what, speed,
                          type_.land_immobilise_mps),
              report);
    }
  }
  // Static stability: past it the vehicle is destroyed, and its wreck goes on as a box under
  // gravity (GatherWreckTouches) until it comes to rest on what is below it.
  // |pitch| > limit is |forward.y| > sin(limit); |roll| > limit is |left.y| > tan(limit) up.y.
  // A wreck is past caring: its message would be formatted, and dropped, every step it lies
  // tipped.
  if (!alive()) return;
  const Matrix3d& Rn = Rotation();
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
  }
}

bool PhysicalVehicle::InOuterHotSpot(const Terrain& terrain, FeatureId id) const {
  const Feature* f = terrain.Find(id);
  if (f == nullptr || f->type() != FeatureType::kBridge) return false;
  const auto* b = static_cast<const Bridge*>(f);
  // Thesis IV.B.3: only the part of a hot spot beyond the bridge is used to get off it.
  const BridgeCoords c = b->ToBridge(x_.x(), x_.z());
  if (std::abs(c.right_m) > b->width_m() / 2.0) return false;
  const double h = kBridgeHotSpotLengthM / 2.0;
  return (c.along_m <= b->start_along_m() && c.along_m >= b->start_along_m() - h) ||
         (c.along_m >= b->end_along_m() && c.along_m <= b->end_along_m() + h);
}

}  // namespace dt
