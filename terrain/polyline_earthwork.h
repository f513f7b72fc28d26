// PolylineEarthwork: a ditch or a multi-segment berm along a polyline, each point with its own
// cross-section, joints bevelled (docs/terrain.md "Ditches and berm lines").
#pragma once

#include <memory>
#include <vector>

#include "terrain/feature.h"

namespace dt {

// Built from FeatureParams of type kDitch or kBermLine (feature_params.h). The cross-section
// varies linearly along each segment between its two points. Beyond the first and last points an
// end piece tapers the section to nothing; at an interior point the outside of the joint is
// bevelled (the section is measured from a straight chord across the corner, not from the
// point), and the inside is where the two segments overlap. Where pieces of one feature overlap
// they combine like features do (Terrain::ElevationAt): the highest raise plus the deepest cut.
class PolylineEarthwork final : public Feature {
 public:
  FeatureType type() const override { return params_.type; }
  FeatureParams params() const override { return params_; }
  Material material() const override { return resolved_material_; }

  Rect Bounds() const override { return bounds_; }
  bool Covers(double x_m, double z_m) const override {
    return OffsetOrNotCovered(x_m, z_m) != kNotCovered;
  }
  bool MayCover(const Rect& rect) const override;
  double OffsetOrNotCovered(double x_m, double z_m) const override;

  // Length of the centre line (sum of the segments), metres.
  double length_m() const { return length_m_; }

 private:
  struct Segment {
    double ax, az;     // start point
    double ux, uz;     // unit direction
    double length_m;   // > 0
    double h0, h1;     // height (berm) or depth (ditch) at start and end
    double w0, w1;     // base (berm) or top (ditch) width at start and end
    double start_run;  // end piece before the start (first segment only), else 0
    double end_run;    // end piece after the end (last segment only), else 0
  };
  struct Joint {
    double vx, vz;       // the point
    double t1x, t1z;     // unit direction of the segment arriving
    double t2x, t2z;     // unit direction of the segment leaving
    double nbx, nbz;     // unit normal of the bevel chord, pointing out of the corner
    double inverse_cos;  // 1 / cos(half the turn)
    double outer_sign;   // +1 when the outside of the corner is on the left, -1 on the right
    double h, w;         // the point's cross-section
  };

  PolylineEarthwork(FeatureId id, FeatureParams params, Material resolved);
  // The cross-section at signed lateral distance u (positive to the left of the direction of
  // travel), for height or depth h and width w; kNotCovered outside it.
  double Section(double u, double h, double w) const;
  // Greatest lateral reach of the section from the centre line for width w, either side.
  double Reach(double w) const;
  double EndRun(double w) const;

  FeatureParams params_;
  Material resolved_material_;
  bool is_ditch_;
  double side_run_m_ = 0.0;      // ditch
  double spoil_height_m_ = 0.0;  // ditch; 0 for none
  double spoil_width_m_ = 0.0;
  std::vector<Segment> segments_;
  std::vector<Joint> joints_;
  Rect bounds_;
  double length_m_ = 0.0;

  friend Result<std::unique_ptr<Feature>> MakePolylineEarthwork(FeatureId, const FeatureParams&,
                                                                const HeightGrid&);
};

// Builds a ditch or berm line. Refuses what ValidateFeatureParams refuses and a placement point
// off the ground; Terrain::Add checks that the whole feature lies on the terrain.
Result<std::unique_ptr<Feature>> MakePolylineEarthwork(FeatureId id, const FeatureParams& params,
                                                       const HeightGrid& ground);

// The distance along the centre line at which each point stands (0 for the first).
std::vector<double> PolylineStations(const FeatureParams& params);

// Cuts a gap gap_width_m wide centred gap_centre_m along the centre line of a ditch or berm line,
// as BreachBerm does for a berm: the piece before the gap ends so that its end piece reaches the
// gap's edge, the piece after it starts likewise; pieces shorter than kMinFeatureSizeM are
// dropped. Points at the cuts take the interpolated cross-section. Refused: a gap centre outside
// [0, length], a gap width not finite and > 0, or parameters that are not a valid polyline.
Result<std::vector<FeatureParams>> BreachPolyline(const FeatureParams& params, double gap_centre_m,
                                                  double gap_width_m);

}  // namespace dt
