#include "terrain/crater.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace dt {
namespace {

// Unit vectors of the 16 spokes, spoke k along direction k * pi / 8. Written out so no
// trigonometry runs at start-up or per query.
constexpr double kC1 = 0.92387953251128674;  // cos(pi / 8)
constexpr double kS1 = 0.38268343236508978;  // sin(pi / 8)
constexpr double kH = 0.70710678118654757;   // cos(pi / 4)
constexpr std::array<std::array<double, 2>, kCraterSpokes> kSpokes = {{
    {1.0, 0.0},
    {kC1, kS1},
    {kH, kH},
    {kS1, kC1},
    {0.0, 1.0},
    {-kS1, kC1},
    {-kH, kH},
    {-kC1, kS1},
    {-1.0, 0.0},
    {-kC1, -kS1},
    {-kH, -kH},
    {-kS1, -kC1},
    {0.0, -1.0},
    {kS1, -kC1},
    {kH, -kH},
    {kC1, -kS1},
}};

// Points this far outside the rim still count as covered, so mesh vertices computed in floating
// point (and points on the outline) are covered however they round.
constexpr double kEdgeToleranceM = 1e-9;

// Finds the sector [spoke k, spoke k + 1) holding the non-zero offset (dx, dz) by halving the
// turn four times (half, quarter, eighth, sixteenth), each a comparison and a select, never
// atan2. Returns k and turns (dx, dz) back by k * pi / 8, into the first sector.
int SectorOf(double& dx, double& dz) {
  // [pi, 2 pi): turn by pi.
  const bool lower = dz < 0.0 || (dz == 0.0 && dx < 0.0);
  dx = lower ? -dx : dx;
  dz = lower ? -dz : dz;
  // [pi/2, pi): turn by -pi/2.
  const bool second = dx <= 0.0;
  const double x2 = second ? dz : dx, z2 = second ? -dx : dz;
  // [pi/4, pi/2): turn by -pi/4.
  const bool upper_eighth = z2 >= x2;
  const double x3 = upper_eighth ? kH * (x2 + z2) : x2;
  const double z3 = upper_eighth ? kH * (z2 - x2) : z2;
  // [pi/8, pi/4): turn by -pi/8.
  const bool upper_sixteenth = kC1 * z3 - kS1 * x3 >= 0.0;
  dx = upper_sixteenth ? kC1 * x3 + kS1 * z3 : x3;
  dz = upper_sixteenth ? kC1 * z3 - kS1 * x3 : z3;
  return 8 * lower + 4 * second + 2 * upper_eighth + upper_sixteenth;
}

// The standard profile: a flat floor depth_m below the ground inside ring 0 (at the ground for
// the thesis crater), rising linearly to the rim (rings 1 and 2), falling linearly to the ground
// at ring 3. Tested on the squared distance first so the floor and the rim top need no square
// root, and written in metres so no division is needed for the thesis crater.
double StandardProfile(double d2, double radius_m, double depth_m) {
  constexpr auto& f = kCraterRingFractions;
  constexpr double kSlope = kCraterRimHeightFraction / (f[1] - f[0]);  // rise per metre
  static_assert(f[1] - f[0] == f[3] - f[2], "inner and outer rim slopes are equally steep");
  const double r0 = f[0] * radius_m, r1 = f[1] * radius_m, r2 = f[2] * radius_m;
  if (d2 <= r0 * r0) return -depth_m;
  if (d2 < r1 * r1) {
    const double t = (std::sqrt(d2) - r0) / (r1 - r0);
    return depth_m == 0.0 ? kSlope * (std::sqrt(d2) - r0)
                          : -depth_m + t * (kCraterRimHeightFraction * radius_m + depth_m);
  }
  if (d2 <= r2 * r2) return kCraterRimHeightFraction * radius_m;
  return std::max(0.0, kSlope * (radius_m - std::sqrt(d2)));
}

Status CheckUnused(const FeatureParams& p) {
  for (auto [name, v] : {std::pair{"direction_rad", p.direction_rad},
                         {"height_m[1]", p.height_m[1]},
                         {"length_m[1]", p.length_m[1]},
                         {"length_m[2]", p.length_m[2]},
                         {"width_m", p.width_m}}) {
    if (v != 0.0)
      return Error{fmt::format("a crater does not use {}; it must be 0, not {}", name, v)};
  }
  return Status::Ok();
}

}  // namespace

double StandardCraterRingOffset(double radius_m, int ring, double depth_m) {
  if (ring < 0 || ring >= kCraterRings) {
    throw std::out_of_range(fmt::format("crater ring {} is outside 0..{}", ring, kCraterRings - 1));
  }
  if (ring == 0) return -depth_m;
  return (ring == 1 || ring == 2) ? kCraterRimHeightFraction * radius_m : 0.0;
}

Crater::Crater(FeatureId id, double x_m, double z_m, double radius_m, Material given,
               Material resolved, std::unique_ptr<const Edits> edits)
    : Feature(id),
      x_m_(x_m),
      z_m_(z_m),
      radius_m_(radius_m),
      edits_(std::move(edits)),
      given_material_(given),
      resolved_material_(resolved) {}

FeatureParams Crater::params() const {
  FeatureParams p = FeatureParams::DeepCrater(x_m_, z_m_, radius_m_, depth_m(), given_material_);
  if (edits_) p.vertex_edits = edits_->list;
  return p;
}

Rect Crater::Bounds() const {
  return {x_m_ - radius_m_, z_m_ - radius_m_, x_m_ + radius_m_, z_m_ + radius_m_};
}

double Crater::CoveredRadiusSquared() const {
  const double r = radius_m_ + kEdgeToleranceM;
  return r * r;
}

bool Crater::Covers(double x_m, double z_m) const {
  const double dx = x_m - x_m_, dz = z_m - z_m_;
  return dx * dx + dz * dz <= CoveredRadiusSquared();
}

bool Crater::MayCover(const Rect& rect) const {
  // Distance from the centre to the nearest point of the rectangle.
  const double dx = x_m_ - std::clamp(x_m_, rect.min_x, rect.max_x);
  const double dz = z_m_ - std::clamp(z_m_, rect.min_z, rect.max_z);
  return dx * dx + dz * dz <= CoveredRadiusSquared();
}

double Crater::OffsetOrNotCovered(double x_m, double z_m) const {
  const double dx = x_m - x_m_, dz = z_m - z_m_;
  const double d2 = dx * dx + dz * dz;
  if (!(d2 <= CoveredRadiusSquared())) return kNotCovered;  // also refuses NaN
  if (!edits_) return StandardProfile(d2, radius_m_, 0.0);
  if (edits_->list.empty()) return StandardProfile(d2, radius_m_, edits_->depth_m);
  if (d2 == 0.0) return -edits_->depth_m;  // the centre: the floor
  const double q = std::min(1.0, std::sqrt(d2) * edits_->inverse_radius_per_m);
  double sx = dx, sz = dz;
  const int k = SectorOf(sx, sz);
  // Fraction of the way from spoke k to spoke k + 1, from the perpendicular distances to both
  // (monotone, 0 on spoke k, 1 on spoke k + 1; within 0.0025 of the angular fraction).
  const double a = std::max(0.0, sz);
  const double b = std::max(0.0, kS1 * sx - kC1 * sz);
  const double t = a + b > 0.0 ? a / (a + b) : 0.0;
  return EditedOffset(k, t, q);
}

double Crater::EditedOffset(int k, double t, double q) const {
  const double* here = &edits_->offsets_m[static_cast<size_t>(k * kCraterRings)];
  const int k1 = k + 1 == kCraterSpokes ? 0 : k + 1;
  const double* next = &edits_->offsets_m[static_cast<size_t>(k1 * kCraterRings)];
  auto at_ring = [&](int ring) { return (1.0 - t) * here[ring] + t * next[ring]; };
  constexpr auto& f = kCraterRingFractions;
  constexpr double kInverseRing0 = 1.0 / f[0];
  if (q <= f[0]) {  // the floor: linear from the centre (at -depth) to ring 0
    const double depth = edits_->depth_m;
    return -depth + (at_ring(0) + depth) * (q * kInverseRing0);
  }
  static_assert(f[2] - f[1] - (f[1] - f[0]) < 1e-12 && f[1] - f[0] - (f[2] - f[1]) < 1e-12 &&
                    f[3] - f[2] - (f[1] - f[0]) < 1e-12 && f[1] - f[0] - (f[3] - f[2]) < 1e-12,
                "the rings are equally spaced");
  constexpr double kRingsPerUnit = 1.0 / (f[1] - f[0]);
  const int ring = (q > f[1]) + (q > f[2]);
  const double s = std::min(1.0, (q - f[ring]) * kRingsPerUnit);
  return (1.0 - s) * at_ring(ring) + s * at_ring(ring + 1);
}

double Crater::VertexOffset(int spoke, int ring) const {
  if (edits_) return edits_->offsets_m[static_cast<size_t>(spoke * kCraterRings + ring)];
  return StandardCraterRingOffset(radius_m_, ring);
}

CraterVertex Crater::Vertex(int spoke, int ring) const {
  if (spoke < 0 || spoke >= kCraterSpokes || ring < 0 || ring >= kCraterRings) {
    throw std::out_of_range(
        fmt::format("crater vertex (spoke {}, ring {}) is outside 16 x 4", spoke, ring));
  }
  const double r = kCraterRingFractions[static_cast<size_t>(ring)] * radius_m_;
  return {x_m_ + r * kSpokes[spoke][0], z_m_ + r * kSpokes[spoke][1], VertexOffset(spoke, ring)};
}

Result<std::unique_ptr<Feature>> MakeCrater(FeatureId id, const FeatureParams& params,
                                            const HeightGrid& ground) {
  Result<Material> resolved = CheckPlacementBasics(id, params, FeatureType::kCrater, ground);
  if (!resolved) return resolved.error();
  if (auto s = CheckUnused(params); !s) {
    return Error{fmt::format("crater {}: {}", id.ToString(), s.error().message)};
  }
  std::unique_ptr<Crater::Edits> edits;
  if (!params.vertex_edits.empty() || params.height_m[0] != 0.0) {
    edits = std::make_unique<Crater::Edits>();
    edits->depth_m = params.height_m[0];
    edits->list = params.vertex_edits;
    edits->inverse_radius_per_m = 1.0 / params.length_m[0];
    for (int spoke = 0; spoke < kCraterSpokes; ++spoke) {
      for (int ring = 0; ring < kCraterRings; ++ring) {
        edits->offsets_m[static_cast<size_t>(spoke * kCraterRings + ring)] =
            StandardCraterRingOffset(params.length_m[0], ring, params.height_m[0]);
      }
    }
    for (const auto& e : params.vertex_edits) {
      edits->offsets_m[static_cast<size_t>(e.spoke * kCraterRings + e.ring)] = e.offset_m;
    }
  }
  return std::unique_ptr<Feature>(new Crater(id, params.x_m, params.z_m, params.length_m[0],
                                             params.material, resolved.value(), std::move(edits)));
}

FeatureParams WithCraterVertexEdit(const FeatureParams& params, const CraterVertexEdit& edit) {
  if (params.type != FeatureType::kCrater) {
    throw std::invalid_argument(
        fmt::format("cannot edit a crater vertex of a {}", FeatureTypeName(params.type)));
  }
  if (edit.spoke >= kCraterSpokes || edit.ring >= kCraterRings) {
    throw std::invalid_argument(
        fmt::format("crater vertex (spoke {}, ring {}) is outside 16 x 4", edit.spoke, edit.ring));
  }
  FeatureParams out = params;
  auto& edits = out.vertex_edits;
  auto key = [](const CraterVertexEdit& e) { return std::pair(e.spoke, e.ring); };
  auto it = std::lower_bound(edits.begin(), edits.end(), edit,
                             [&](const auto& a, const auto& b) { return key(a) < key(b); });
  if (it != edits.end() && key(*it) == key(edit)) {
    it->offset_m = edit.offset_m;
  } else {
    edits.insert(it, edit);
  }
  return out;
}

}  // namespace dt
