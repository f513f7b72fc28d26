// FeatureType and FeatureParams: the parameters that fully define a dynamic feature.
#pragma once

#include <array>
#include <cstdint>
#include <numbers>
#include <string>
#include <string_view>
#include <vector>

#include "base/bytes.h"
#include "base/enum_list.h"
#include "base/result.h"
#include "terrain/material.h"

namespace dt {

// One X(enumerator, value, name) per feature type (base/enum_list.h); the name is lower case, as
// used in messages and commands. Values are part of the PDU and save-file formats: append, never
// renumber.
#define DT_FEATURE_TYPES(X)                                                         \
  X(kCrater, 1, "crater")                                                           \
  X(kBerm, 2, "berm")                                                               \
  X(kBridge, 3, "bridge")                                                           \
  /* a polyline cut below the ground, optional spoil berm (polyline_earthwork.h) */ \
  X(kDitch, 4, "ditch")                                                             \
  /* a multi-segment berm (polyline_earthwork.h) */                                 \
  X(kBermLine, 5, "berm_line")                                                      \
  /* an areal feature: a polygon of other soil or water (area_feature.h) */         \
  X(kArea, 6, "area")                                                               \
  /* blade work: additive height changes of grid posts (earth_move.h) */            \
  X(kEarthMove, 7, "earth_move")

enum class FeatureType : uint16_t { DT_FEATURE_TYPES(DT_ENUM_ENUMERATOR) };

inline constexpr uint16_t kFeatureTypeCount = 0 DT_FEATURE_TYPES(DT_ENUM_PLUS_ONE);
// Values run 1, 2, 3, ... in the list's order: 0 is no type, and value - 1 indexes the names.
static_assert(EnumValuesRunOn({DT_FEATURE_TYPES(DT_ENUM_VALUE)}, 1));

// "crater", "berm", "bridge", "ditch", "berm_line", "area", "earth_move"
std::string_view FeatureTypeName(FeatureType type);
inline bool IsValidFeatureType(uint16_t raw) { return raw >= 1 && raw <= kFeatureTypeCount; }
// True for the types whose parameters carry a list of points (FeatureParams::points).
inline bool HasFeaturePoints(FeatureType type) {
  return type == FeatureType::kDitch || type == FeatureType::kBermLine ||
         type == FeatureType::kArea;
}

// Bridge status (thesis table 1 "Status").
enum class BridgeStatus : int32_t { kIntact = 0, kDestroyed = 1 };

// One crater vertex set away from the standard profile (erosion, breach of the rim).
struct CraterVertexEdit {
  uint8_t spoke = 0;      // 0..15, spoke k points along direction k * 22.5 deg
  uint8_t ring = 0;       // 0..3, innermost first
  double offset_m = 0.0;  // height of this vertex above the bare ground
  auto operator<=>(const CraterVertexEdit&) const = default;
};

// One point of a polyline earthwork or of an area's polygon, in terrain coordinates. For a
// berm line, height_m is the crest height and width_m the base width there; for a ditch, height_m
// is the depth below the ground and width_m the top width there; an area's points use neither
// (both 0).
struct FeaturePoint {
  double x_m = 0.0;
  double z_m = 0.0;
  double height_m = 0.0;
  double width_m = 0.0;
  bool operator==(const FeaturePoint&) const = default;
};

// One post's height change in an earth move: post (i, j) of the grid rises by delta_mm
// millimetres (negative: lowered). Integer millimetres, so the sum of any set of earth moves over
// a post is exact and the same in every order of arrival (docs/terrain.md "Blade work").
struct PostDelta {
  uint16_t i = 0;  // post column, along x
  uint16_t j = 0;  // post row, along z
  int32_t delta_mm = 0;
  auto operator<=>(const PostDelta&) const = default;
};
// Metres per unit of PostDelta::delta_mm.
inline constexpr double kPostDeltaUnitM = 0.001;
// Largest change of one post in one earth move (10 m): a blade moves far less in a tick.
inline constexpr int32_t kMaxPostDeltaMm = 10000;
// Most posts one earth move changes, and the largest side of the rectangle they lie in (posts):
// with its bit mask and two bytes per post, an earth move of a full 48 x 48 rectangle would not
// fit a datagram, so the author splits its work into pieces that do (pdu/conversion.h).
inline constexpr int kMaxEarthMovePosts = 400;
inline constexpr int kMaxEarthMoveSpanPosts = 48;

// Documented ranges (docs/terrain.md "Parameter ranges"); values outside are refused as bad
// input. Every size (radius, lengths, widths, heights) is at least kMinFeatureSizeM, the finest
// post spacing an exercise allows: smaller is no earthwork, and a subnormal or vanishing size
// would only overflow the geometry's divisions.
inline constexpr double kMinFeatureSizeM = 0.01;
// Placement coordinates: far beyond any terrain (kMaxPostsPerSide posts at the exercise file's
// largest spacing, 10 km, span 41 000 km), so sums and differences of them stay exact to well
// under a millimetre. Whether the feature lies on the terrain is Terrain::Add's check.
inline constexpr double kMaxFeatureCoordinateM = 1e8;
// Directions: one turn either way, so both the [0, 2 pi) and the (-pi, pi] conventions (and
// -360 .. 360 degrees) are accepted; a larger magnitude is a unit mistake or garbage.
inline constexpr double kMaxDirectionRad = 2.0 * std::numbers::pi;
inline constexpr double kMaxCraterRadiusM = 200.0;
inline constexpr double kMaxBermLengthM = 2000.0;
inline constexpr double kMaxBermWidthM = 100.0;
inline constexpr double kMaxBermHeightM = 50.0;
inline constexpr double kMaxBridgeLengthM = 2000.0;
inline constexpr double kMaxBridgeWidthM = 100.0;
inline constexpr double kMaxBridgeHeightM = 200.0;
// A crater's depth below the original surface (height_m[0]; 0 is the thesis crater).
inline constexpr double kMaxCraterDepthM = 100.0;
inline constexpr double kMaxDitchDepthM = 50.0;
inline constexpr double kMaxDitchWidthM = 100.0;
// Points of a polyline or polygon: enough for any earthwork drawn by hand, and a Construct with
// 32 points (32 bytes each) and its authentication trailer stays under kMaxPduBytes (1400).
inline constexpr int kMaxFeaturePoints = 32;
// The sharpest turn a polyline may make at a joint: the bevel of a sharper joint would reach far
// beyond the cross-section (its width grows as 1 / cos(turn / 2)).
inline constexpr double kMaxPolylineTurnRad = 150.0 * std::numbers::pi / 180.0;
// A water level (absolute elevation, metres): far beyond any ground on Earth.
inline constexpr double kMaxWaterLevelM = 1e4;
inline constexpr int kCraterSpokes = 16;
inline constexpr int kCraterRings = 4;

// The fields of thesis table 1 that define a feature, plus width (berms and bridges need one; the
// thesis table has none) and crater vertex edits. Units: metres and radians, with the coordinate
// convention of docs/conventions.md (x east, z north, y up; direction 0 = +x, counter-clockwise).
//   crater: length_m[0] = radius, height_m[0] = depth of the floor below the bare ground (0 for
//           the thesis crater, whose floor is the ground).
//   berm:   length_m[0] = length, height_m[0] = height, width_m, direction_rad.
//   bridge: length_m[0] = span, length_m[1] = ramp 1, length_m[2] = ramp 2, height_m[0] = deck
//           height above ground where ramp 1 meets the span, height_m[1] = where the span meets
//           ramp 2, width_m, direction_rad, status. (x_m, z_m) is the joint of ramp 1 and span.
//   ditch:  points (2..32, per point depth and top width), length_m[0] = side run (horizontal
//           width of each sloping side), height_m[1] and length_m[1] = spoil berm height and
//           base width on the right of the line (both 0: no spoil). (x_m, z_m) = points[0].
//   berm_line: points (2..32, per point crest height and base width). (x_m, z_m) = points[0].
//   area:   points (3..32, a polygon), material = the soil inside (water: flooded), height_m[0] =
//           the water level (absolute elevation) for water, else 0. (x_m, z_m) = points[0].
//   earth_move: post_deltas (1..400, sorted by (j, i), unique, each nonzero and within
//           +-10 000 mm, all inside a 48 x 48 post rectangle); every other field 0 and material
//           from_ground. Whether the posts are on the grid is Terrain::Add's check.
struct FeatureParams {
  FeatureType type = FeatureType::kCrater;
  double x_m = 0.0;
  double z_m = 0.0;
  double direction_rad = 0.0;
  std::array<double, 2> height_m = {0.0, 0.0};
  std::array<double, 3> length_m = {0.0, 0.0, 0.0};
  double width_m = 0.0;
  Material material = Material::kFromGround;
  BridgeStatus status = BridgeStatus::kIntact;
  std::vector<CraterVertexEdit> vertex_edits;  // crater only; sorted by (spoke, ring), unique
  std::vector<FeaturePoint> points;            // ditch, berm_line, area only
  std::vector<PostDelta> post_deltas;          // earth_move only

  bool operator==(const FeatureParams&) const = default;

  static FeatureParams Crater(double x_m, double z_m, double radius_m,
                              Material material = Material::kFromGround);
  static FeatureParams Berm(double x_m, double z_m, double direction_rad, double length_m,
                            double width_m, double height_m,
                            Material material = Material::kFromGround);
  static FeatureParams Bridge(double x_m, double z_m, double direction_rad, double width_m,
                              double ramp1_length_m, double span_length_m, double ramp2_length_m,
                              double height1_m, double height2_m,
                              Material material = Material::kConcrete);
  // A crater whose floor lies depth_m below the bare ground.
  static FeatureParams DeepCrater(double x_m, double z_m, double radius_m, double depth_m,
                                  Material material = Material::kFromGround);
  static FeatureParams Ditch(std::vector<FeaturePoint> points, double side_run_m,
                             double spoil_height_m = 0.0, double spoil_width_m = 0.0,
                             Material material = Material::kFromGround);
  static FeatureParams BermLine(std::vector<FeaturePoint> points,
                                Material material = Material::kFromGround);
  // water_level_m is used only for Material::kWater.
  static FeatureParams Area(std::vector<FeaturePoint> points, Material material,
                            double water_level_m = 0.0);
  // Sorts the deltas by (j, i); does not merge repeats (validation refuses them).
  static FeatureParams EarthMove(std::vector<PostDelta> post_deltas);
};

// Checks types, finiteness and the documented ranges above; the error names the field and its
// value. Does not check bounds against a terrain: Terrain::Add does.
Status ValidateFeatureParams(const FeatureParams& params);

// Canonical little-endian encoding: equal params give equal bytes on every machine. The point
// list is written only for the types that have one (HasFeaturePoints), and the post deltas only
// for earth moves, so the bytes of craters, berms and bridges are those of the first encoding.
void EncodeFeatureParams(const FeatureParams& params, ByteWriter& out);
// Decodes what EncodeFeatureParams wrote and validates it.
Result<FeatureParams> DecodeFeatureParams(ByteReader& in);

}  // namespace dt
