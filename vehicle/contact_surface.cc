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
  const int cx = std::min(static_cast<int>(at.u * kBitgridCellsPerSide), kBitgridCellsPerSide - 1);
  const int cz = std::min(static_cast<int>(at.v * kBitgridCellsPerSide), kBitgridCellsPerSide - 1);
  if (((terrain.SquareBits(at.square) >> (cz * kBitgridCellsPerSide + cx)) & 1u) == 0) {
    // No feature may cover this cell: one ground triangle gives height, normal and soil.
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

bool FeatureCellsIn(const Terrain& terrain, const Rect& area) {
  const HeightGrid& g = terrain.ground();
  const double size = g.size_m(), cell = g.spacing_m() / kBitgridCellsPerSide;
  const double x0 = std::clamp(area.min_x, 0.0, size), x1 = std::clamp(area.max_x, 0.0, size);
  const double z0 = std::clamp(area.min_z, 0.0, size), z1 = std::clamp(area.max_z, 0.0, size);
  const int cells = g.squares_per_side() * kBitgridCellsPerSide;
  const int ci0 = std::min(static_cast<int>(x0 / cell), cells - 1);
  const int ci1 = std::min(static_cast<int>(x1 / cell), cells - 1);
  const int cj0 = std::min(static_cast<int>(z0 / cell), cells - 1);
  const int cj1 = std::min(static_cast<int>(z1 / cell), cells - 1);
  for (int sj = cj0 / kBitgridCellsPerSide; sj <= cj1 / kBitgridCellsPerSide; ++sj) {
    for (int si = ci0 / kBitgridCellsPerSide; si <= ci1 / kBitgridCellsPerSide; ++si) {
      const uint16_t bits = terrain.SquareBits({si, sj});
      if (bits == 0) continue;
      for (int cz = 0; cz < kBitgridCellsPerSide; ++cz) {
        const int cj = sj * kBitgridCellsPerSide + cz;
        if (cj < cj0 || cj > cj1) continue;
        for (int cx = 0; cx < kBitgridCellsPerSide; ++cx) {
          const int ci = si * kBitgridCellsPerSide + cx;
          if (ci < ci0 || ci > ci1) continue;
          if ((bits >> (cz * kBitgridCellsPerSide + cx)) & 1u) return true;
        }
      }
    }
  }
  return false;
}

}  // namespace dt
