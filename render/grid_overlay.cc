#include "render/grid_overlay.h"

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace dt {

void AppendGridLines(const Terrain& terrain, double spacing_m, int samples_per_square, Rgba colour,
                     Mesh& mesh) {
  if (!(spacing_m > 0.0) || !std::isfinite(spacing_m) || samples_per_square < 1) {
    throw std::invalid_argument(
        fmt::format("grid overlay spacing {} m must be positive and samples per square {} >= 1",
                    spacing_m, samples_per_square));
  }
  const double size = terrain.ground().size_m();
  const int steps = terrain.ground().squares_per_side() * samples_per_square;
  const double step_m = size / steps;
  const long lines = static_cast<long>(std::floor(size / spacing_m));
  auto point = [&](double x, double z) {
    return Eigen::Vector3d(x, terrain.ElevationAt(x, z) + kGridLiftM, z);
  };
  for (long k = 0; k <= lines; ++k) {
    const double c = std::min(static_cast<double>(k) * spacing_m, size);
    for (int s = 0; s < steps; ++s) {
      const double t0 = s * step_m, t1 = std::min((s + 1) * step_m, size);
      mesh.AddLine(point(c, t0), point(c, t1), colour);  // north-south line
      mesh.AddLine(point(t0, c), point(t1, c), colour);  // east-west line
    }
  }
}

}  // namespace dt
