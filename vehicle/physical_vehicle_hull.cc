// PhysicalVehicle's hull against bridge solids and the ground: the collision response.
#include <algorithm>
#include <array>
#include <cmath>
#include <span>

#include "vehicle/hull_collision.h"
#include "vehicle/physical_vehicle.h"
#include "vehicle/physical_vehicle_internal.h"

namespace dt {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;
using physical_internal::kBellyTravelM;
using physical_internal::kLevelBottomMinCos;
using physical_internal::Rotate;

// A wedge's level exit is at most the way a substep drives in near a solid (kMaxMovePerStepM)
// with margin; a deeper one is a roof pushed up into a flat ceiling, left to the impulse below.
constexpr double kWedgeLevelExitMaxM = 0.3;

}  // namespace

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
  // A wreck may lie on any face: its whole box is tested.
  const size_t n_hull = std::min(world.size(), hull_points_.size());
  const size_t n =
      alive() ? n_hull : std::min(world.size(), hull_points_.size() + wreck_contacts_.size());
  for (int pass = 0; pass < 4; ++pass) {
    const Matrix3d R = q_.toRotationMatrix();
    const bool level_bottom = (R * Vector3d::UnitY()).y() > kLevelBottomMinCos;
    for (size_t i = 0; i < n_hull; ++i) world[i] = x_ + R * hull_points_[i];
    for (size_t i = n_hull; i < n; ++i) world[i] = x_ + R * wreck_contacts_[i - n_hull].body;
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
      if (into < 0.0) {
        v_ -= into * face;
        report.max_impact_mps = std::max(report.max_impact_mps, -into);
      }
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
        if (com_into < 0.0) {
          v_ -= com_into * back;
          report.max_impact_mps = std::max(report.max_impact_mps, -com_into);
        }
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
      report.max_impact_mps = std::max(report.max_impact_mps, -vn);
    }
  }
}

}  // namespace dt
