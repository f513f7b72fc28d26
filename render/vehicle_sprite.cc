#include "render/vehicle_sprite.h"

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "render/palette.h"

namespace dt {

VehicleSprite SpriteOf(const Vehicle& vehicle, Rgba colour) {
  VehicleSprite s;
  s.x_m = vehicle.x_m();
  s.y_m = vehicle.elevation_m();
  s.z_m = vehicle.z_m();
  s.heading_rad = vehicle.heading_rad();
  s.pitch_rad = vehicle.pitch_rad();
  s.roll_rad = vehicle.roll_rad();
  s.length_m = vehicle.type().length_m;
  s.width_m = vehicle.type().width_m;
  s.height_m = kSpriteHeightPerWidth * vehicle.type().width_m;
  s.colour = vehicle.alive() ? colour : kDeadVehicleColour;
  return s;
}

void AppendVehicle(const VehicleSprite& v, Mesh& mesh) {
  const double values[] = {v.x_m, v.y_m, v.z_m, v.heading_rad, v.pitch_rad, v.roll_rad};
  for (double value : values) {
    if (!std::isfinite(value)) {
      throw std::invalid_argument(fmt::format(
          "vehicle sprite at ({}, {}, {}) m heading {} pitch {} roll {} rad is not finite", v.x_m,
          v.y_m, v.z_m, v.heading_rad, v.pitch_rad, v.roll_rad));
    }
  }
  if (!(v.length_m > 0.0 && v.width_m > 0.0 && v.height_m > 0.0) || !std::isfinite(v.length_m) ||
      !std::isfinite(v.width_m) || !std::isfinite(v.height_m)) {
    throw std::invalid_argument(fmt::format("vehicle sprite size {} x {} x {} m must be positive",
                                            v.length_m, v.width_m, v.height_m));
  }
  const Eigen::Vector3d up(0.0, 1.0, 0.0);
  const Eigen::Vector3d fwd(std::cos(v.heading_rad), 0.0, std::sin(v.heading_rad));
  const Eigen::Vector3d right0(std::sin(v.heading_rad), 0.0, -std::cos(v.heading_rad));
  // Pitch turns the nose towards up; roll then turns the right side down about the new forward.
  const Eigen::Vector3d f = fwd * std::cos(v.pitch_rad) + up * std::sin(v.pitch_rad);
  const Eigen::Vector3d u1 = up * std::cos(v.pitch_rad) - fwd * std::sin(v.pitch_rad);
  const Eigen::Vector3d r = right0 * std::cos(v.roll_rad) - u1 * std::sin(v.roll_rad);
  const Eigen::Vector3d u = u1 * std::cos(v.roll_rad) + right0 * std::sin(v.roll_rad);

  const Eigen::Vector3d base(v.x_m, v.y_m, v.z_m);
  // a: -1 rear .. 1 front; b: -1 left .. 1 right; c: 0 underside, 1 roof.
  auto corner = [&](double a, double b, double c) -> Eigen::Vector3d {
    return base + a * 0.5 * v.length_m * f + b * 0.5 * v.width_m * r + c * v.height_m * u;
  };
  const Colour body(v.colour[0] / 255.0, v.colour[1] / 255.0, v.colour[2] / 255.0);
  const Colour front =
      (1.0 - kVehicleFrontHighlight) * body + kVehicleFrontHighlight * Colour(1.0, 1.0, 1.0);
  auto face = [&](const Colour& c, const Eigen::Vector3d& n, const Eigen::Vector3d& p0,
                  const Eigen::Vector3d& p1, const Eigen::Vector3d& p2, const Eigen::Vector3d& p3) {
    mesh.AddQuad(p0, p1, p2, p3, ToRgba(c, ShadeFactor(n)));
  };
  constexpr double kSplit = 1.0 / 3.0;  // the roof's front third starts here
  face(body, u, corner(-1, -1, 1), corner(-1, 1, 1), corner(kSplit, 1, 1), corner(kSplit, -1, 1));
  face(front, u, corner(kSplit, -1, 1), corner(kSplit, 1, 1), corner(1, 1, 1), corner(1, -1, 1));
  face(body, f, corner(1, -1, 0), corner(1, 1, 0), corner(1, 1, 1), corner(1, -1, 1));
  face(body, -f, corner(-1, -1, 0), corner(-1, 1, 0), corner(-1, 1, 1), corner(-1, -1, 1));
  face(body, r, corner(-1, 1, 0), corner(1, 1, 0), corner(1, 1, 1), corner(-1, 1, 1));
  face(body, -r, corner(-1, -1, 0), corner(1, -1, 0), corner(1, -1, 1), corner(-1, -1, 1));
}

}  // namespace dt
