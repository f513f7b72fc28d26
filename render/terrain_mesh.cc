#include "render/terrain_mesh.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

#include "render/palette.h"

namespace dt {
namespace {

bool IsEarthwork(const Feature& f) {
  return f.type() == FeatureType::kCrater || f.type() == FeatureType::kBerm;
}

// The smallest length an earthwork's shape varies over, which sampling must resolve.
double DetailLengthM(const Feature& f) {
  const FeatureParams p = f.params();
  switch (p.type) {
    case FeatureType::kCrater:
      return 0.1 * p.length_m[0];  // rings lie 0.2 radius apart
    case FeatureType::kBerm:
      return p.width_m / 6.0;  // each side slope runs a third of the width
    case FeatureType::kBridge:
      break;
  }
  return std::numeric_limits<double>::infinity();
}

bool SquareHasEarthwork(const Terrain& terrain, SquareIndex square) {
  if (terrain.SquareBits(square) == 0) return false;
  for (const Feature* f : terrain.FeaturesInSquare(square)) {
    if (IsEarthwork(*f)) return true;
  }
  return false;
}

// Emits triangle a-b-c flat-shaded, each vertex tinted by its own elevation.
void EmitTriangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                  const Colour& base, const ElevationRange& range, Mesh& mesh) {
  const double shade = ShadeFactor(UpwardNormal(a, b, c));
  for (const Eigen::Vector3d* p : {&a, &b, &c}) {
    mesh.AddVertex(*p,
                   ToRgba(base, shade * ElevationFactor(p->y(), range.lowest_m, range.highest_m)));
  }
}

void EmitPlainSquare(const Terrain& terrain, SquareIndex sq, const ElevationRange& range,
                     Mesh& mesh) {
  const HeightGrid& g = terrain.ground();
  const double s = g.spacing_m();
  const double x0 = sq.i * s, x1 = (sq.i + 1) * s, z0 = sq.j * s, z1 = (sq.j + 1) * s;
  const Eigen::Vector3d p00(x0, g.post(sq.i, sq.j), z0), p10(x1, g.post(sq.i + 1, sq.j), z0),
      p01(x0, g.post(sq.i, sq.j + 1), z1), p11(x1, g.post(sq.i + 1, sq.j + 1), z1);
  // The diagonal runs from (x0, z1) to (x1, z0) (docs/conventions.md).
  EmitTriangle(p00, p10, p01, MaterialColour(g.soil(sq, TriangleHalf::kLower)), range, mesh);
  EmitTriangle(p11, p01, p10, MaterialColour(g.soil(sq, TriangleHalf::kUpper)), range, mesh);
}

Colour SurfaceColour(const Terrain& terrain, SquareIndex sq, double x_m, double z_m) {
  if (const Feature* top = TopEarthworkAt(terrain, sq, x_m, z_m)) {
    return EarthworkColour(top->material());
  }
  const HeightGrid& g = terrain.ground();
  return MaterialColour(g.soil(sq, g.HalfAt(x_m, z_m)));
}

void EmitRefinedSquare(const Terrain& terrain, SquareIndex sq, int k, const ElevationRange& range,
                       Mesh& mesh) {
  const HeightGrid& g = terrain.ground();
  const double sub = g.spacing_m() / k;
  const double size = g.size_m();
  // Positions from global sub-indices, so a shared edge gives bit-identical vertices in both
  // squares; the far edge is clamped onto the terrain.
  auto vertex = [&](int a, int b) {
    const double x = std::min(static_cast<double>(sq.i * k + a) * sub, size);
    const double z = std::min(static_cast<double>(sq.j * k + b) * sub, size);
    return Eigen::Vector3d(x, terrain.ElevationAt(x, z), z);
  };
  std::vector<Eigen::Vector3d> v(static_cast<size_t>(k + 1) * (k + 1));
  for (int b = 0; b <= k; ++b) {
    for (int a = 0; a <= k; ++a) v[static_cast<size_t>(b) * (k + 1) + a] = vertex(a, b);
  }
  auto at = [&](int a, int b) -> const Eigen::Vector3d& {
    return v[static_cast<size_t>(b) * (k + 1) + a];
  };
  for (int b = 0; b < k; ++b) {
    for (int a = 0; a < k; ++a) {
      const Eigen::Vector3d &p00 = at(a, b), &p10 = at(a + 1, b), &p01 = at(a, b + 1),
                            &p11 = at(a + 1, b + 1);
      // Same diagonal as the grid: the bare parts coincide with the coarse triangles.
      const Eigen::Vector3d lower_c = (p00 + p10 + p01) / 3.0;
      const Eigen::Vector3d upper_c = (p11 + p01 + p10) / 3.0;
      EmitTriangle(p00, p10, p01, SurfaceColour(terrain, sq, lower_c.x(), lower_c.z()), range,
                   mesh);
      EmitTriangle(p11, p01, p10, SurfaceColour(terrain, sq, upper_c.x(), upper_c.z()), range,
                   mesh);
    }
  }
}

}  // namespace

int EarthworkSubdivisions(const Terrain& terrain, const TerrainMeshOptions& options) {
  if (options.max_subdivisions < 1 || !(options.min_sample_m >= 0.0)) {
    throw std::invalid_argument(
        fmt::format("terrain mesh: max_subdivisions {} must be >= 1 and min_sample_m {} >= 0",
                    options.max_subdivisions, options.min_sample_m));
  }
  double detail = std::numeric_limits<double>::infinity();
  for (const Feature* f : terrain.FeaturesById()) detail = std::min(detail, DetailLengthM(*f));
  if (!std::isfinite(detail)) return 1;
  const double target = std::max(detail, options.min_sample_m);
  const double wanted = std::ceil(terrain.ground().spacing_m() / target);
  return static_cast<int>(std::clamp(wanted, 1.0, static_cast<double>(options.max_subdivisions)));
}

ElevationRange GroundElevationRange(const HeightGrid& ground) {
  const auto [lo, hi] = std::minmax_element(ground.posts().begin(), ground.posts().end());
  return {*lo, *hi};
}

const Feature* TopEarthworkAt(const Terrain& terrain, SquareIndex square, double x_m, double z_m) {
  const Feature* top = nullptr;
  double highest = 0.0;
  for (const Feature* f : terrain.FeaturesInSquare(square)) {
    if (!IsEarthwork(*f)) continue;
    const std::optional<double> offset = f->OffsetAboveGround(x_m, z_m);
    if (!offset) continue;
    if (!top || *offset > highest || (*offset == highest && f->id() < top->id())) {
      top = f;
      highest = *offset;
    }
  }
  return top;
}

void AppendTerrainRows(const Terrain& terrain, int row_begin, int row_end, int subdivisions,
                       const ElevationRange& range, Mesh& mesh) {
  const int m = terrain.ground().squares_per_side();
  if (row_begin < 0 || row_end > m || row_begin > row_end || subdivisions < 1) {
    throw std::invalid_argument(
        fmt::format("terrain mesh: rows [{}, {}) of {} with {} subdivisions", row_begin, row_end, m,
                    subdivisions));
  }
  for (int j = row_begin; j < row_end; ++j) {
    for (int i = 0; i < m; ++i) {
      const SquareIndex sq{i, j};
      if (SquareHasEarthwork(terrain, sq)) {
        EmitRefinedSquare(terrain, sq, subdivisions, range, mesh);
      } else {
        EmitPlainSquare(terrain, sq, range, mesh);
      }
    }
  }
}

}  // namespace dt
