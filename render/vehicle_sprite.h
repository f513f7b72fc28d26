// VehicleSprite: what the renderer needs of a vehicle, and its oriented box.
#pragma once

#include "render/image.h"
#include "render/mesh.h"
#include "vehicle/vehicle.h"

namespace dt {

// A vehicle as drawn: an oriented box. (x_m, y_m, z_m) is the centre of the box's underside,
// where the vehicle meets the ground. Heading, pitch and roll follow docs/conventions.md:
// heading 0 = +x, counter-clockwise; pitch > 0 nose up; roll > 0 right side down.
struct VehicleSprite {
  double x_m = 0.0;
  double y_m = 0.0;
  double z_m = 0.0;
  double heading_rad = 0.0;
  double pitch_rad = 0.0;
  double roll_rad = 0.0;
  double length_m = 7.0;
  double width_m = 3.5;
  double height_m = 2.5;
  Rgba colour = {200, 40, 40, 255};
};

// The front third of the roof is drawn this much lighter (towards white) so the heading shows
// from above.
inline constexpr double kVehicleFrontHighlight = 0.5;

// Vehicle types give no height: sprites are this fraction of the width tall (tank 2.2 m, truck
// 1.4 m, jeep 1.3 m).
inline constexpr double kSpriteHeightPerWidth = 0.6;
// Dead vehicles are drawn in this colour whatever colour they were given.
inline constexpr Rgba kDeadVehicleColour = {60, 60, 60, 255};

// The sprite of a simulated vehicle: its position, elevation, heading, pitch, roll and size.
VehicleSprite SpriteOf(const Vehicle& vehicle, Rgba colour = VehicleSprite{}.colour);

// Appends the box (roof, four sides; the underside is never seen), each face flat-shaded by its
// own normal, so pitch and roll show as different brightness as well as shape. Throws
// std::invalid_argument for non-finite values or non-positive sizes.
void AppendVehicle(const VehicleSprite& vehicle, Mesh& mesh);

}  // namespace dt
