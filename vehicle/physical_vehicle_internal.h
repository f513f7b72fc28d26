// Constants and small helpers shared by the physical vehicle's source files (not a public API).
#pragma once

#include <Eigen/Geometry>

namespace dt::physical_internal {

// Belly contacts bottom out almost at once: the hull is rigid.
inline constexpr double kBellyTravelM = 0.03;

// Adds a small rotation (world axis-angle vector) to q.
inline void Rotate(Eigen::Quaterniond& q, const Eigen::Vector3d& angle) {
  const Eigen::Quaterniond dq(0.0, angle.x(), angle.y(), angle.z());
  q.coeffs() += 0.5 * (dq * q).coeffs();
  q.normalize();
}

}  // namespace dt::physical_internal
