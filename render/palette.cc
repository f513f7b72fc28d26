#include "render/palette.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

namespace dt {

Colour MaterialColour(Material material) {
  switch (material) {
    case Material::kFromGround:
      return {1.0, 0.0, 1.0};
    case Material::kGrass:
      return {0.42, 0.60, 0.30};
    case Material::kDirt:
      return {0.55, 0.42, 0.28};
    case Material::kSand:
      return {0.86, 0.78, 0.56};
    case Material::kRock:
      return {0.55, 0.53, 0.50};
    case Material::kMud:
      return {0.36, 0.28, 0.20};
    case Material::kGravel:
      return {0.68, 0.66, 0.62};
    case Material::kConcrete:
      return {0.80, 0.80, 0.78};
    case Material::kAsphalt:
      return {0.25, 0.25, 0.27};
    case Material::kSteel:
      return {0.45, 0.50, 0.58};
    case Material::kWater:
      return {0.20, 0.42, 0.72};
    case Material::kBurnt:
      return {0.16, 0.14, 0.12};
    case Material::kOil:
      return {0.08, 0.07, 0.10};
  }
  return {1.0, 0.0, 1.0};
}

Colour EarthworkColour(Material material) {
  const Colour earth(0.50, 0.36, 0.22);
  return (1.0 - kEarthworkTint) * MaterialColour(material) + kEarthworkTint * earth;
}

Eigen::Vector3d SunDirection() { return Eigen::Vector3d(-1.0, std::sqrt(2.0), 1.0).normalized(); }

double ShadeFactor(const Eigen::Vector3d& normal) {
  constexpr double kAmbient = 0.35, kDiffuse = 0.65;
  const Eigen::Vector3d sun = SunDirection();
  return (kAmbient + kDiffuse * std::max(0.0, normal.dot(sun))) / (kAmbient + kDiffuse * sun.y());
}

double ElevationFactor(double elevation_m, double lowest_m, double highest_m) {
  if (!(highest_m > lowest_m)) return 1.0;
  const double t = std::clamp((elevation_m - lowest_m) / (highest_m - lowest_m), 0.0, 1.0);
  return 0.85 + 0.30 * t;
}

Rgba ToRgba(const Colour& colour, double factor) {
  Rgba out{0, 0, 0, 255};
  for (int k = 0; k < 3; ++k) {
    const double v = std::clamp(colour[k] * factor, 0.0, 1.0);
    out[k] = static_cast<uint8_t>(v * 255.0 + 0.5);  // v >= 0: rounds half up, like lround
  }
  return out;
}

}  // namespace dt
