// Constants and small helpers shared by the physical vehicle's source files (not a public API).
#pragma once

#include <Eigen/Geometry>

namespace dt::physical_internal {

// Belly contacts bottom out almost at once: the hull is rigid.
inline constexpr double kBellyTravelM = 0.03;

// A hull tilted less than this (cos 30 degrees) meets a deck's edge with its bottom, which rests
// on the edge; tilted further, its side meets it and slides off.
inline constexpr double kLevelBottomMinCos = 0.866;

// Adds a small rotation (world axis-angle vector) to q.
inline void Rotate(Eigen::Quaterniond& q, const Eigen::Vector3d& angle) {
  const Eigen::Quaterniond dq(0.0, angle.x(), angle.y(), angle.z());
  q.coeffs() += 0.5 * (dq * q).coeffs();
  q.normalize();
}

}  // namespace dt::physical_internal
