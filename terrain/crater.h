// Crater: a ringed earthwork of 16 spokes x 4 rings draped on the bare ground (thesis III.A.1).
#pragma once

#include <array>
#include <memory>
#include <vector>

#include "terrain/feature.h"

namespace dt {

// Ring radii as fractions of the crater radius, innermost first (docs/terrain.md "Craters").
inline constexpr std::array<double, kCraterRings> kCraterRingFractions = {0.4, 0.6, 0.8, 1.0};
// Standard rim height (rings 1 and 2) as a fraction of the radius.
inline constexpr double kCraterRimHeightFraction = 0.15;

// A vertex of a crater's mesh: its ground position and its offset above the bare ground.
struct CraterVertex {
  double x_m = 0.0;
  double z_m = 0.0;
  double offset_m = 0.0;
};

// Keeps only what a query needs (placement, radius, materials, and the edited offsets when there
// are any) and computes vertex offsets on demand, so a million craters stay small.
class Crater final : public Feature {
 public:
  FeatureType type() const override { return FeatureType::kCrater; }
  FeatureParams params() const override;
  Material material() const override { return resolved_material_; }

  Rect Bounds() const override;
  bool Covers(double x_m, double z_m) const override;
  bool MayCover(const Rect& rect) const override;
  double OffsetOrNotCovered(double x_m, double z_m) const override;

  double x_m() const { return x_m_; }
  double z_m() const { return z_m_; }
  double radius_m() const { return radius_m_; }
  double rim_height_m() const { return kCraterRimHeightFraction * radius_m_; }
  // Depth of the floor below the bare ground (0: the thesis crater, floor at the ground).
  double depth_m() const { return edits_ ? edits_->depth_m : 0.0; }
  bool has_vertex_edits() const { return edits_ && !edits_->list.empty(); }

  // Vertex (spoke, ring): spoke 0..15 along direction spoke * pi / 8, ring 0..3 innermost
  // first. Throws std::out_of_range for indices outside 16 x 4.
  CraterVertex Vertex(int spoke, int ring) const;

 private:
  struct Edits {
    std::vector<CraterVertexEdit> list;                          // as given, for params()
    std::array<double, kCraterSpokes * kCraterRings> offsets_m;  // every vertex, spoke-major
    double inverse_radius_per_m;  // kept here: standard craters do without it
    double depth_m;               // below the ground; kept here so thesis craters stay small
  };

  Crater(FeatureId id, double x_m, double z_m, double radius_m, Material given, Material resolved,
         std::unique_ptr<const Edits> edits);
  double VertexOffset(int spoke, int ring) const;
  double CoveredRadiusSquared() const;
  // Offset for a point at distance fraction q = r / radius in the sector between spokes k and
  // k + 1, at fraction t of the way from spoke k.
  double EditedOffset(int k, double t, double q) const;

  double x_m_;
  double z_m_;
  double radius_m_;
  // Null for a thesis crater (no edits, at the ground); a crater below the ground without edits
  // holds an empty list and keeps the standard, circularly symmetric profile.
  std::unique_ptr<const Edits> edits_;
  Material given_material_;
  Material resolved_material_;

  friend Result<std::unique_ptr<Feature>> MakeCrater(FeatureId, const FeatureParams&,
                                                     const HeightGrid&);
};

// The standard offset of ring `ring` (0..3) for a crater of the given radius and depth: -depth
// for ring 0 (the edge of the floor), the rim height for rings 1 and 2, 0 for ring 3. Throws
// std::out_of_range for a ring outside 0..3.
double StandardCraterRingOffset(double radius_m, int ring, double depth_m = 0.0);

// Builds a crater. Refuses parameters ValidateFeatureParams refuses, a type other than crater,
// fields a crater does not use set to non-zero (they could not be given back by params()), and a
// placement point off the ground.
Result<std::unique_ptr<Feature>> MakeCrater(FeatureId id, const FeatureParams& params,
                                            const HeightGrid& ground);

// The parameters with vertex (edit.spoke, edit.ring) set to edit.offset_m, replacing any earlier
// edit of that vertex and keeping the edits sorted. Throws std::invalid_argument if `params` is
// not a crater or the vertex is outside 16 x 4; the offset itself is checked when the result is
// applied (Terrain::Update).
FeatureParams WithCraterVertexEdit(const FeatureParams& params, const CraterVertexEdit& edit);

}  // namespace dt
