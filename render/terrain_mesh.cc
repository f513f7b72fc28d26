#include "render/terrain_mesh.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

#include <fmt/format.h>

#include "render/palette.h"

namespace dt {
namespace {

bool IsEarthwork(const Feature& f) {
  return f.type() == FeatureType::kCrater || f.type() == FeatureType::kBerm ||
         f.type() == FeatureType::kDitch || f.type() == FeatureType::kBermLine;
}

// Squares holding an earthwork or an area are sampled finely: an area changes the colour (and
// water the height drawn) along its outline.
bool IsRefined(const Feature& f) { return IsEarthwork(f) || f.type() == FeatureType::kArea; }

// The smallest length an earthwork's shape varies over, which sampling must resolve.
double DetailLengthM(const Feature& f) {
  const FeatureParams p = f.params();
  switch (p.type) {
    case FeatureType::kCrater:
      return 0.1 * p.length_m[0];  // rings lie 0.2 radius apart
    case FeatureType::kBerm:
      return p.width_m / 6.0;  // each side slope runs a third of the width
    case FeatureType::kDitch: {
      double d = p.length_m[0];  // a side slope
      for (const FeaturePoint& q : p.points) d = std::min(d, (q.width_m - 2 * p.length_m[0]) / 2);
      if (p.length_m[1] > 0.0) d = std::min(d, p.length_m[1] / 6.0);
      return std::max(d, p.length_m[0] / 2);
    }
    case FeatureType::kBermLine: {
      double d = std::numeric_limits<double>::infinity();
      for (const FeaturePoint& q : p.points) d = std::min(d, q.width_m / 6.0);
      return d;
    }
    case FeatureType::kArea:
      return 1.0;  // outlines drawn to a metre
    case FeatureType::kBridge:
    case FeatureType::kEarthMove:  // its work is in the ground posts, drawn with them
      break;
  }
  return std::numeric_limits<double>::infinity();
}

bool SquareHasEarthwork(const Terrain& terrain, SquareIndex square) {
  if (terrain.SquareBits(square) == 0) return false;
  for (const Feature* f : terrain.FeaturesInSquare(square)) {
    if (IsRefined(*f)) return true;
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

// The soil the composition rule gives (Terrain::SoilAt: water, areas, earthworks, ground),
// tinted as earth where an earthwork makes the surface.
Colour SurfaceColour(const Terrain& terrain, SquareIndex sq, double x_m, double z_m) {
  const Material soil = terrain.SoilAt(x_m, z_m);
  if (soil != Material::kWater && TopEarthworkAt(terrain, sq, x_m, z_m) != nullptr) {
    return EarthworkColour(soil);
  }
  return MaterialColour(soil);
}

// Sample point of global sub-index (gi, gj) at k sub-squares per grid square. Grid corners
// (multiples of k) get exactly the post positions; the far edge is clamped onto the terrain.
// Every square that uses a point computes it the same way, so shared vertices are bit-identical.
Eigen::Vector3d SamplePoint(const Terrain& terrain, int k, long gi, long gj) {
  const HeightGrid& g = terrain.ground();
  const double s = g.spacing_m(), sub = s / k;
  auto coord = [&](long idx, double size_m) {
    const double c =
        idx % k == 0 ? static_cast<double>(idx / k) * s : static_cast<double>(idx) * sub;
    return std::min(c, size_m);
  };
  const double x = coord(gi, g.size_x_m()), z = coord(gj, g.size_z_m());
  // Water is drawn as its own level surface over the ground it floods.
  const std::optional<double> water = terrain.WaterLevelAt(x, z);
  return Eigen::Vector3d(x, water ? *water : terrain.ElevationAt(x, z), z);
}

void EmitRefinedSquare(const Terrain& terrain, SquareIndex sq, int k, const ElevationRange& range,
                       Mesh& mesh) {
  std::vector<Eigen::Vector3d> v(static_cast<size_t>(k + 1) * (k + 1));
  for (int b = 0; b <= k; ++b) {
    for (int a = 0; a <= k; ++a) {
      v[static_cast<size_t>(b) * (k + 1) + a] =
          SamplePoint(terrain, k, static_cast<long>(sq.i) * k + a, static_cast<long>(sq.j) * k + b);
    }
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

// One grid triangle whose edges may carry the extra vertices of refined neighbours. `loop` runs
// round its boundary; a fan from the centroid keeps every piece in the triangle's plane, so the
// picture is that of the coarse triangle but without T-junctions (which leave pinholes).
void EmitGridTriangle(const std::vector<Eigen::Vector3d>& loop, const Eigen::Vector3d& a,
                      const Eigen::Vector3d& b, const Eigen::Vector3d& c, const Colour& base,
                      const ElevationRange& range, Mesh& mesh) {
  if (loop.size() == 3) {
    EmitTriangle(a, b, c, base, range, mesh);
    return;
  }
  const double shade = ShadeFactor(UpwardNormal(a, b, c));
  const Eigen::Vector3d centre = (a + b + c) / 3.0;
  auto colour = [&](const Eigen::Vector3d& p) {
    return ToRgba(base, shade * ElevationFactor(p.y(), range.lowest_m, range.highest_m));
  };
  for (size_t n = 0; n < loop.size(); ++n) {
    const Eigen::Vector3d& p = loop[n];
    const Eigen::Vector3d& q = loop[(n + 1) % loop.size()];
    mesh.AddVertex(centre, colour(centre));
    mesh.AddVertex(p, colour(p));
    mesh.AddVertex(q, colour(q));
  }
}

// A square without earthworks: its grid triangles, coloured by their soil. Edges shared with a
// refined square (k > 1) take that square's edge vertices.
void EmitPlainSquare(const Terrain& terrain, SquareIndex sq, int k, const ElevationRange& range,
                     Mesh& mesh) {
  const HeightGrid& g = terrain.ground();
  const int mx = g.squares_x(), mz = g.squares_z();
  auto refined = [&](int i, int j) {
    return k > 1 && i >= 0 && j >= 0 && i < mx && j < mz && SquareHasEarthwork(terrain, {i, j});
  };
  const bool south = refined(sq.i, sq.j - 1), north = refined(sq.i, sq.j + 1);
  const bool west = refined(sq.i - 1, sq.j), east = refined(sq.i + 1, sq.j);
  const Colour lower = MaterialColour(g.soil(sq, TriangleHalf::kLower));
  const Colour upper = MaterialColour(g.soil(sq, TriangleHalf::kUpper));
  const double s = g.spacing_m();
  if (!south && !north && !west && !east) {
    const double x0 = sq.i * s, x1 = (sq.i + 1) * s, z0 = sq.j * s, z1 = (sq.j + 1) * s;
    const Eigen::Vector3d p00(x0, g.post(sq.i, sq.j), z0), p10(x1, g.post(sq.i + 1, sq.j), z0),
        p01(x0, g.post(sq.i, sq.j + 1), z1), p11(x1, g.post(sq.i + 1, sq.j + 1), z1);
    // The diagonal runs from (x0, z1) to (x1, z0) (docs/conventions.md).
    EmitTriangle(p00, p10, p01, lower, range, mesh);
    EmitTriangle(p11, p01, p10, upper, range, mesh);
    return;
  }
  const long gi = static_cast<long>(sq.i) * k, gj = static_cast<long>(sq.j) * k;
  auto pt = [&](long a, long b) { return SamplePoint(terrain, k, gi + a, gj + b); };
  const Eigen::Vector3d p00 = pt(0, 0), p10 = pt(k, 0), p01 = pt(0, k), p11 = pt(k, k);
  std::vector<Eigen::Vector3d> loop;
  // Lower triangle: south edge west to east, the diagonal, west edge north to south.
  loop.push_back(p00);
  for (int a = 1; south && a < k; ++a) loop.push_back(pt(a, 0));
  loop.push_back(p10);
  loop.push_back(p01);
  for (int b = k - 1; west && b > 0; --b) loop.push_back(pt(0, b));
  EmitGridTriangle(loop, p00, p10, p01, lower, range, mesh);
  // Upper triangle: north edge east to west, the diagonal, east edge south to north.
  loop.clear();
  loop.push_back(p11);
  for (int a = k - 1; north && a > 0; --a) loop.push_back(pt(a, k));
  loop.push_back(p01);
  loop.push_back(p10);
  for (int b = 1; east && b < k; ++b) loop.push_back(pt(k, b));
  EmitGridTriangle(loop, p11, p01, p10, upper, range, mesh);
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

void AppendTerrainSquares(const Terrain& terrain, SquareIndex first, SquareIndex end,
                          int subdivisions, const ElevationRange& range, Mesh& mesh) {
  const int mx = terrain.ground().squares_x(), mz = terrain.ground().squares_z();
  if (first.i < 0 || first.j < 0 || end.i > mx || end.j > mz || first.i > end.i ||
      first.j > end.j || subdivisions < 1) {
    throw std::invalid_argument(
        fmt::format("terrain mesh: squares [{}, {}) x [{}, {}) of {} x {} with {} subdivisions",
                    first.i, end.i, first.j, end.j, mx, mz, subdivisions));
  }
  for (int j = first.j; j < end.j; ++j) {
    for (int i = first.i; i < end.i; ++i) {
      const SquareIndex sq{i, j};
      if (SquareHasEarthwork(terrain, sq)) {
        EmitRefinedSquare(terrain, sq, subdivisions, range, mesh);
      } else {
        EmitPlainSquare(terrain, sq, subdivisions, range, mesh);
      }
    }
  }
}

}  // namespace dt
