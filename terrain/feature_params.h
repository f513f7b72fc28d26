// FeatureType and FeatureParams: the parameters that fully define a dynamic feature.
#pragma once

#include <array>
#include <cstdint>
#include <numbers>
#include <string>
#include <string_view>
#include <vector>

#include "terrain/bytes.h"
#include "terrain/material.h"
#include "terrain/result.h"

namespace dt {

// Values are part of the PDU and save-file formats: append, never renumber.
enum class FeatureType : uint16_t {
  kCrater = 1,
  kBerm = 2,
  kBridge = 3,
};

std::string_view FeatureTypeName(FeatureType type);  // "crater", "berm", "bridge"
inline bool IsValidFeatureType(uint16_t raw) { return raw >= 1 && raw <= 3; }

// Bridge status (thesis table 1 "Status").
enum class BridgeStatus : int32_t { kIntact = 0, kDestroyed = 1 };

// One crater vertex set away from the standard profile (erosion, breach of the rim).
struct CraterVertexEdit {
  uint8_t spoke = 0;      // 0..15, spoke k points along direction k * 22.5 deg
  uint8_t ring = 0;       // 0..3, innermost first
  double offset_m = 0.0;  // height of this vertex above the bare ground
  auto operator<=>(const CraterVertexEdit&) const = default;
};

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
inline constexpr int kCraterSpokes = 16;
inline constexpr int kCraterRings = 4;

// The fields of thesis table 1 that define a feature, plus width (berms and bridges need one; the
// thesis table has none) and crater vertex edits. Units: metres and radians, with the coordinate
// convention of docs/conventions.md (x east, z north, y up; direction 0 = +x, counter-clockwise).
//   crater: length_m[0] = radius.
//   berm:   length_m[0] = length, height_m[0] = height, width_m, direction_rad.
//   bridge: length_m[0] = span, length_m[1] = ramp 1, length_m[2] = ramp 2, height_m[0] = deck
//           height above ground where ramp 1 meets the span, height_m[1] = where the span meets
//           ramp 2, width_m, direction_rad, status. (x_m, z_m) is the joint of ramp 1 and span.
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
};

// Checks types, finiteness and the documented ranges above; the error names the field and its
// value. Does not check bounds against a terrain: Terrain::Add does.
Status ValidateFeatureParams(const FeatureParams& params);

// Canonical little-endian encoding: equal params give equal bytes on every machine.
void EncodeFeatureParams(const FeatureParams& params, ByteWriter& out);
// Decodes what EncodeFeatureParams wrote and validates it.
Result<FeatureParams> DecodeFeatureParams(ByteReader& in);

}  // namespace dt
