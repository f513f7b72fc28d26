#include "vehicle/contact_surface.h"

#include <algorithm>
#include <cmath>

namespace dt {
namespace {

// Step of the central differences that give the normal over earthworks.
constexpr double kNormalStepM = 0.1;
// Earthworks cover points up to 1e-9 m outside their bounds (their edge tolerance).
constexpr double kBoundsSlackM = 1e-6;

}  // namespace

namespace {

// Terrain::ElevationAt's composition (docs/terrain.md "Composing the surface") over `near`, those
// earthworks whose bounds hold (x, z): the highest raise and the deepest cut, which the caller
// adds to the ground as `ground + raise + cut`, the order Terrain::ElevationAt sums them in, so
// the same bits. False where no bounds hold the point.
bool KnownRaiseAndCut(std::span<const NearEarthwork> near, double x_m, double z_m, double& raise_m,
                      double& cut_m) {
  raise_m = 0.0;
  cut_m = 0.0;
  bool over = false;
  for (const NearEarthwork& e : near) {
    if (!e.bounds.Contains(x_m, z_m)) continue;
    over = true;
    const double offset_m = e.feature->OffsetOrNotCovered(x_m, z_m);
    raise_m = std::max(raise_m, offset_m);
    cut_m = std::min(cut_m, offset_m == Feature::kNotCovered ? 0.0 : offset_m);
  }
  return over;
}

void RaiseToSolids(std::span<const Solid> solids, double x_m, double z_m, double reach_m,
                   SurfaceSample& out) {
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
}

// True if (x, z) lies where `known` says no feature raises or cuts the ground.
bool KnownBare(const KnownEarthworks* known, double x_m, double z_m) {
  if (known == nullptr || !known->area.Contains(x_m, z_m)) return false;
  for (const NearEarthwork& e : known->near) {
    if (e.bounds.Contains(x_m, z_m)) return false;
  }
  return true;
}

// A rectangle of `cell` around (x, z), a point that KnownBare holds, inside the area whose
// earthworks `known` holds all of and clear of each one's bounds: there no feature raises or
// cuts the ground. Each earthwork in the way is cut off on the side the point is not on (of the
// sides that leave the point, the one that leaves the most). Bridges do not count: their solids
// are added to the ground afterwards (RaiseToSolids).
Rect KnownBarePart(const KnownEarthworks& known, const Rect& cell, double x_m, double z_m) {
  Rect part{std::max(cell.min_x, known.area.min_x), std::max(cell.min_z, known.area.min_z),
            std::min(cell.max_x, known.area.max_x), std::min(cell.max_z, known.area.max_z)};
  for (const NearEarthwork& e : known.near) {
    const Rect& b = e.bounds;
    if (!b.Intersects(part)) continue;
    const Rect options[4] = {
        {part.min_x, part.min_z, std::min(part.max_x, b.min_x), part.max_z},  // point west
        {std::max(part.min_x, b.max_x), part.min_z, part.max_x, part.max_z},  // point east
        {part.min_x, part.min_z, part.max_x, std::min(part.max_z, b.min_z)},  // point south
        {part.min_x, std::max(part.min_z, b.max_z), part.max_x, part.max_z},  // point north
    };
    const bool keeps[4] = {x_m<b.min_x, x_m> b.max_x, z_m<b.min_z, z_m> b.max_z};
    double best_area = -1.0;
    for (int k = 0; k < 4; ++k) {
      const double area =
          (options[k].max_x - options[k].min_x) * (options[k].max_z - options[k].min_z);
      if (keeps[k] && area > best_area) {
        best_area = area;
        part = options[k];
      }
    }
  }
  return part;
}

SurfaceSample Sample(const Terrain& terrain, double x_m, double z_m, GroundPlaneCache* cache,
                     const KnownEarthworks* known = nullptr) {
  const HeightGrid& g = terrain.ground();
  const HeightGrid::Location at = g.Locate(x_m, z_m);
  SurfaceSample out;
  const int cx = std::min(static_cast<int>(at.u * kBitgridCellsPerSide), kBitgridCellsPerSide - 1);
  const int cz = std::min(static_cast<int>(at.v * kBitgridCellsPerSide), kBitgridCellsPerSide - 1);
  const bool feature_cell =
      ((terrain.SquareBits(at.square) >> (cz * kBitgridCellsPerSide + cx)) & 1u) != 0;
  // Where no earthwork raises the surface (no feature in the cell, or none covering the point
  // above the ground) one ground triangle gives height, normal and soil.
  const double ground = g.ElevationAt(at);
  // No feature covering the point, Terrain::ElevationAt would be the ground (plus zeros).
  const bool known_bare = feature_cell && KnownBare(known, x_m, z_m);
  // The surface over an earthwork from the earthworks gathered near the vehicle where they hold
  // all of them, else from the terrain's index (which reaches into scattered feature memory).
  auto surface_at = [&](double x, double z) {
    double raise_m, cut_m;
    if (known == nullptr || !known->area.Contains(x, z)) return terrain.ElevationAt(x, z);
    const double ground_m = terrain.GroundElevationAt(x, z);
    if (!KnownRaiseAndCut(known->near, x, z, raise_m, cut_m)) return ground_m;
    return ground_m + raise_m + cut_m;
  };
  const double surface = feature_cell && !known_bare ? surface_at(x_m, z_m) : ground;
  if (surface == ground) {
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
    out.height_m = ground;
    const double inv = 1.0 / g.spacing_m();
    out.normal = Eigen::Vector3d(-dh_du * inv, 1.0, -dh_dv * inv).normalized();
    out.material = g.soil(s, half);
    const double sp = g.spacing_m(), cell = sp / kBitgridCellsPerSide;
    const double cell_x0 = s.i * sp + cx * cell, cell_z0 = s.j * sp + cz * cell;
    Rect plane{cell_x0, cell_z0, cell_x0 + cell, cell_z0 + cell};
    // In a cell that features cover, the ground plane holds where the earthworks gathered near
    // the vehicle show that none of them reaches (most of a feature's bitgrid cells).
    if (cache != nullptr && (!feature_cell || known_bare)) {
      if (feature_cell) plane = KnownBarePart(*known, plane, x_m, z_m);
      GroundPlaneCache& c = *cache;
      c.valid = true;
      c.square_x0 = s.i * sp;
      c.square_z0 = s.j * sp;
      c.inverse_spacing = inv;
      c.x0 = plane.min_x;
      c.z0 = plane.min_z;
      c.x1 = plane.max_x;
      c.z1 = plane.max_z;
      c.upper = half == TriangleHalf::kUpper;
      c.slope_x = dh_du * inv;
      c.slope_z = dh_dv * inv;
      c.h0 = ground - c.slope_x * (x_m - c.x0) - c.slope_z * (z_m - c.z0);
      c.normal = out.normal;
      c.material = out.material;
    }
  } else {
    // On an earthwork: forward differences (backward at the terrain's far edges) for the normal.
    const double dx = x_m + kNormalStepM <= g.size_x_m() ? kNormalStepM : -kNormalStepM;
    const double dz = z_m + kNormalStepM <= g.size_z_m() ? kNormalStepM : -kNormalStepM;
    out.height_m = surface;
    const double sx = (surface_at(x_m + dx, z_m) - surface) / dx;
    const double sz = (surface_at(x_m, z_m + dz) - surface) / dz;
    out.normal = Eigen::Vector3d(-sx, 1.0, -sz).normalized();
    out.material = terrain.SoilAt(x_m, z_m);
  }
  return out;
}

}  // namespace

SurfaceSample SampleSurface(const Terrain& terrain, std::span<const Solid> solids, double x_m,
                            double z_m, double reach_m) {
  SurfaceSample out = Sample(terrain, x_m, z_m, nullptr);
  RaiseToSolids(solids, x_m, z_m, reach_m, out);
  return out;
}

SurfaceSample SampleSurface(const Terrain& terrain, std::span<const Solid> solids, double x_m,
                            double z_m, double reach_m, GroundPlaneCache& c) {
  return SampleSurface(terrain, solids, KnownEarthworks{{}, Rect{1.0, 1.0, 0.0, 0.0}}, x_m, z_m,
                       reach_m, c);
}

SurfaceSample SampleSurface(const Terrain& terrain, std::span<const Solid> solids,
                            const KnownEarthworks& known, double x_m, double z_m, double reach_m,
                            GroundPlaneCache& c) {
  SurfaceSample out;
  if (c.Holds(x_m, z_m)) {
    out.height_m = c.HeightAt(x_m, z_m);
    out.normal = c.normal;
    out.material = c.material;
  } else {
    c.valid = false;
    out = Sample(terrain, x_m, z_m, &c, &known);
  }
  RaiseToSolids(solids, x_m, z_m, reach_m, out);
  return out;
}

bool EarthworkNear(const Terrain& terrain, const Rect& area) {
  const HeightGrid& g = terrain.ground();
  const double sx = g.size_x_m(), sz = g.size_z_m();
  const SquareIndex lo =
      g.SquareAt(std::clamp(area.min_x, 0.0, sx), std::clamp(area.min_z, 0.0, sz));
  const SquareIndex hi =
      g.SquareAt(std::clamp(area.max_x, 0.0, sx), std::clamp(area.max_z, 0.0, sz));
  for (int j = lo.j; j <= hi.j; ++j) {
    for (int i = lo.i; i <= hi.i; ++i) {
      if (terrain.SquareBits({i, j}) == 0) continue;
      for (const Feature* f : terrain.FeaturesInSquare({i, j})) {
        if (f->type() != FeatureType::kBridge && f->Bounds().Intersects(area)) return true;
      }
    }
  }
  return false;
}

void EarthworksNear(const Terrain& terrain, const Rect& area, std::vector<NearEarthwork>& out) {
  out.clear();
  const HeightGrid& g = terrain.ground();
  const double sx = g.size_x_m(), sz = g.size_z_m();
  const SquareIndex lo =
      g.SquareAt(std::clamp(area.min_x, 0.0, sx), std::clamp(area.min_z, 0.0, sz));
  const SquareIndex hi =
      g.SquareAt(std::clamp(area.max_x, 0.0, sx), std::clamp(area.max_z, 0.0, sz));
  for (int j = lo.j; j <= hi.j; ++j) {
    for (int i = lo.i; i <= hi.i; ++i) {
      if (terrain.SquareBits({i, j}) == 0) continue;
      for (const Feature* f : terrain.FeaturesInSquare({i, j})) {
        if (f->type() == FeatureType::kBridge) continue;
        // Features cover their bounds' edges within a tolerance (1e-9 m): widened past it, the
        // bounds hold every point a feature covers.
        const Rect b = f->Bounds().Expanded(kBoundsSlackM);
        if (!b.Intersects(area)) continue;
        if (std::any_of(out.begin(), out.end(),
                        [f](const NearEarthwork& e) { return e.feature == f; }))
          continue;
        out.push_back({f, b});
      }
    }
  }
}

bool AnyOverlaps(std::span<const NearEarthwork> near, const Rect& area) {
  for (const NearEarthwork& e : near) {
    if (e.bounds.Intersects(area)) return true;
  }
  return false;
}

bool EarthworkElevationAt(const Terrain& terrain, std::span<const NearEarthwork> near, double x_m,
                          double z_m, double& elevation_m) {
  double raise_m, cut_m;
  if (!KnownRaiseAndCut(near, x_m, z_m, raise_m, cut_m)) return false;
  elevation_m = terrain.GroundElevationAt(x_m, z_m) + raise_m + cut_m;
  return true;
}

}  // namespace dt
