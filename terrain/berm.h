// Berm: a straight earth bank of trapezoidal cross-section draped on the bare ground (thesis
// III.A.2).
#pragma once

#include <memory>

#include "terrain/feature.h"

namespace dt {

// Mesh lines of a berm (thesis appendix B: 11 XLINES x 4 ZLINES).
inline constexpr int kBermLengthLines = 11;
inline constexpr int kBermWidthLines = 4;
// Width of the flat top as a fraction of the base width (docs/terrain.md "Berms"). Each side
// slope, and each end piece, runs over (1 - kBermTopWidthFraction) / 2 of the width.
inline constexpr double kBermTopWidthFraction = 1.0 / 3.0;

// A vertex of a berm's mesh: its ground position and its offset above the bare ground.
struct BermVertex {
  double x_m = 0.0;
  double z_m = 0.0;
  double offset_m = 0.0;
};

// The berm's crest runs from the placement point (the centre of the starting end) along its
// direction for its length. A standard end piece slopes down beyond each end of the crest over
// the side-slope run, so two berms whose crest ends meet join at full height at any angle.
class Berm final : public Feature {
 public:
  FeatureType type() const override { return FeatureType::kBerm; }
  FeatureParams params() const override;
  Material material() const override { return resolved_material_; }

  Rect Bounds() const override;
  bool Covers(double x_m, double z_m) const override;
  bool MayCover(const Rect& rect) const override;
  double OffsetOrNotCovered(double x_m, double z_m) const override;

  double x_m() const { return x_m_; }
  double z_m() const { return z_m_; }
  double direction_rad() const { return direction_rad_; }
  double length_m() const { return length_m_; }
  double width_m() const { return width_m_; }
  double height_m() const { return height_m_; }
  // How far each side slope and each end piece runs on the ground.
  double slope_run_m() const { return slope_run_m_; }

  // Mesh vertex: length line 0..10 at length_line / 10 of the crest from the placement point,
  // width line 0..3 from the right-hand edge to the left-hand edge (facing along the direction).
  // Throws std::out_of_range for indices outside 11 x 4.
  BermVertex Vertex(int length_line, int width_line) const;

 private:
  Berm(FeatureId id, const FeatureParams& params, Material resolved);
  // Along-crest and leftward coordinates of a ground point relative to the placement point.
  void Local(double x_m, double z_m, double& along_m, double& left_m) const;
  bool InFootprint(double along_m, double left_m) const;

  double x_m_;
  double z_m_;
  double direction_rad_;
  double length_m_;
  double width_m_;
  double height_m_;
  double cos_;  // unit vector of the direction
  double sin_;
  double half_width_m_;
  double slope_run_m_;
  double inverse_run_;  // 1 / slope_run_m_, per metre
  Material given_material_;
  Material resolved_material_;

  friend Result<std::unique_ptr<Feature>> MakeBerm(FeatureId, const FeatureParams&,
                                                   const HeightGrid&);
};

// Builds a berm. Refuses parameters ValidateFeatureParams refuses, a type other than berm,
// fields a berm does not use set to non-zero (they could not be given back by params()), and a
// placement point off the ground.
Result<std::unique_ptr<Feature>> MakeBerm(FeatureId id, const FeatureParams& params,
                                          const HeightGrid& ground);

}  // namespace dt
