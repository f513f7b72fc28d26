// FeatureType and FeatureParams: the parameters that fully define a dynamic feature.
#pragma once

#include <array>
#include <cstdint>
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

// Documented maxima (docs/terrain.md): bigger values are refused as bad input.
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

// Checks types, finiteness and documented ranges; the error names the field and its value.
// Does not check bounds against a terrain: Terrain::Add does.
Status ValidateFeatureParams(const FeatureParams& params);

// Canonical little-endian encoding: equal params give equal bytes on every machine.
void EncodeFeatureParams(const FeatureParams& params, ByteWriter& out);
// Decodes what EncodeFeatureParams wrote and validates it.
Result<FeatureParams> DecodeFeatureParams(ByteReader& in);

}  // namespace dt
