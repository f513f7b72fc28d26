#include "render/grid_overlay.h"

#include <algorithm>
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
  const HeightGrid& g = terrain.ground();
  auto point = [&](double x, double z) {
    return Eigen::Vector3d(x, terrain.ElevationAt(x, z) + kGridLiftM, z);
  };
  // North-south lines at x = k * spacing_m, followed along z in samples_per_square steps per grid
  // square, and east-west lines likewise; emitted interleaved, line k of each then segment s of
  // each, in the order a square grid always had.
  const double size_x = g.size_x_m(), size_z = g.size_z_m();
  const int steps_x = g.squares_x() * samples_per_square;
  const int steps_z = g.squares_z() * samples_per_square;
  const double step_x_m = size_x / steps_x, step_z_m = size_z / steps_z;
  const long lines_x = static_cast<long>(std::floor(size_x / spacing_m));
  const long lines_z = static_cast<long>(std::floor(size_z / spacing_m));
  for (long k = 0; k <= std::max(lines_x, lines_z); ++k) {
    const double cx = std::min(static_cast<double>(k) * spacing_m, size_x);
    const double cz = std::min(static_cast<double>(k) * spacing_m, size_z);
    for (int s = 0; s < std::max(steps_x, steps_z); ++s) {
      if (k <= lines_x && s < steps_z) {  // north-south line
        const double t0 = s * step_z_m, t1 = std::min((s + 1) * step_z_m, size_z);
        mesh.AddLine(point(cx, t0), point(cx, t1), colour);
      }
      if (k <= lines_z && s < steps_x) {  // east-west line
        const double t0 = s * step_x_m, t1 = std::min((s + 1) * step_x_m, size_x);
        mesh.AddLine(point(t0, cz), point(t1, cz), colour);
      }
    }
  }
}

}  // namespace dt
