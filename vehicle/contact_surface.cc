#include "vehicle/contact_surface.h"

#include <algorithm>
#include <cmath>

namespace dt {
namespace {

// Step of the central differences that give the normal over earthworks.
constexpr double kNormalStepM = 0.1;

}  // namespace

SurfaceSample SampleSurface(const Terrain& terrain, std::span<const Solid> solids, double x_m,
                            double z_m, double reach_m) {
  const HeightGrid& g = terrain.ground();
  const HeightGrid::Location at = g.Locate(x_m, z_m);
  SurfaceSample out;
  if (terrain.SquareBits(at.square) == 0) {
    // Bare square: one triangle gives height, normal and soil.
    const SquareIndex& s = at.square;
    const double h01 = g.post(s.i, s.j + 1), h10 = g.post(s.i + 1, s.j);
    double dh_du, dh_dv;
    TriangleHalf half;
    if (at.u + at.v >= 1.0) {
      const double h11 = g.post(s.i + 1, s.j + 1);
      dh_du = h11 - h01;
      dh_dv = h11 - h10;
      half = TriangleHalf::kUpper;
    } else {
      const double h00 = g.post(s.i, s.j);
      dh_du = h10 - h00;
      dh_dv = h01 - h00;
      half = TriangleHalf::kLower;
    }
    out.height_m = g.ElevationAt(at);
    const double inv = 1.0 / g.spacing_m();
    out.normal = Eigen::Vector3d(-dh_du * inv, 1.0, -dh_dv * inv).normalized();
    out.material = g.soil(s, half);
  } else {
    const double size = g.size_m();
    const double x0 = std::max(0.0, x_m - kNormalStepM), x1 = std::min(size, x_m + kNormalStepM);
    const double z0 = std::max(0.0, z_m - kNormalStepM), z1 = std::min(size, z_m + kNormalStepM);
    out.height_m = terrain.ElevationAt(x_m, z_m);
    const double dx = (terrain.ElevationAt(x1, z_m) - terrain.ElevationAt(x0, z_m)) / (x1 - x0);
    const double dz = (terrain.ElevationAt(x_m, z1) - terrain.ElevationAt(x_m, z0)) / (z1 - z0);
    out.normal = Eigen::Vector3d(-dx, 1.0, -dz).normalized();
    out.material = terrain.SoilAt(x_m, z_m);
  }
  for (const Solid& s : solids) {
    double a, r;
    s.ToLocal(x_m, z_m, a, r);
    if (!s.InPlan(a, r)) continue;
    const double top = s.TopAt(a);
    if (top > reach_m || top <= out.height_m) continue;
    out.height_m = top;
    const double slope = s.TopSlope();
    out.normal = Eigen::Vector3d(-slope * s.ux, 1.0, -slope * s.uz).normalized();
    out.material = s.material;
    out.bridge = s.deck ? s.bridge : FeatureId{};
  }
  return out;
}

}  // namespace dt
