// Palette: the colours of materials and the shading rule shared by every drawn surface.
#pragma once

#include <Eigen/Core>

#include "render/image.h"
#include "terrain/material.h"

namespace dt {

// Linear colour, each channel in [0, 1].
using Colour = Eigen::Vector3d;

// The base colour of a material (kFromGround, which never reaches the renderer, is bright pink).
Colour MaterialColour(Material material);

// Earthworks (crater, berm) are tinted towards freshly moved earth by this fraction so that they
// stand out from the undisturbed ground of the same material.
inline constexpr double kEarthworkTint = 0.35;
Colour EarthworkColour(Material material);

// Sun from the north-west, 45 degrees above the horizon (the cartographic convention), in
// world coordinates (x east, y up, z north).
Eigen::Vector3d SunDirection();

// Flat-shading factor for a surface with unit normal `normal`: ambient plus diffuse, scaled so
// level ground gets exactly 1.
double ShadeFactor(const Eigen::Vector3d& normal);

// Elevation tint: 0.85 at `lowest_m`, 1.15 at `highest_m`, linear between and clamped; 1 when
// the range is empty.
double ElevationFactor(double elevation_m, double lowest_m, double highest_m);

// Rounds colour * factor to 8 bits (opaque), clamping at 255.
Rgba ToRgba(const Colour& colour, double factor = 1.0);

}  // namespace dt
