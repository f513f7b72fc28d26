#include "terrain/feature_params.h"

#include <fmt/format.h>
#include <cmath>

namespace dt {
namespace {

Status CheckRange(std::string_view field, double value, double min_inclusive,
                  double max_inclusive) {
  if (!std::isfinite(value)) {
    return Error{fmt::format("{} is not finite ({})", field, value)};
  }
  if (!(value >= min_inclusive) || value > max_inclusive) {
    return Error{
        fmt::format("{} = {} is outside [{}, {}]", field, value, min_inclusive, max_inclusive)};
  }
  return Status::Ok();
}

// A size: at least kMinFeatureSizeM, at most the type's maximum.
Status CheckSize(std::string_view field, double value, double max_inclusive) {
  return CheckRange(field, value, kMinFeatureSizeM, max_inclusive);
}

Status CheckFinite(std::string_view field, double value) {
  if (!std::isfinite(value)) return Error{fmt::format("{} is not finite ({})", field, value)};
  return Status::Ok();
}

}  // namespace

std::string_view FeatureTypeName(FeatureType type) {
  switch (type) {
    case FeatureType::kCrater:
      return "crater";
    case FeatureType::kBerm:
      return "berm";
    case FeatureType::kBridge:
      return "bridge";
  }
  return "unknown";
}

FeatureParams FeatureParams::Crater(double x_m, double z_m, double radius_m, Material material) {
  FeatureParams p;
  p.type = FeatureType::kCrater;
  p.x_m = x_m;
  p.z_m = z_m;
  p.length_m[0] = radius_m;
  p.material = material;
  return p;
}

FeatureParams FeatureParams::Berm(double x_m, double z_m, double direction_rad, double length_m,
                                  double width_m, double height_m, Material material) {
  FeatureParams p;
  p.type = FeatureType::kBerm;
  p.x_m = x_m;
  p.z_m = z_m;
  p.direction_rad = direction_rad;
  p.length_m[0] = length_m;
  p.width_m = width_m;
  p.height_m[0] = height_m;
  p.material = material;
  return p;
}

FeatureParams FeatureParams::Bridge(double x_m, double z_m, double direction_rad, double width_m,
                                    double ramp1_length_m, double span_length_m,
                                    double ramp2_length_m, double height1_m, double height2_m,
                                    Material material) {
  FeatureParams p;
  p.type = FeatureType::kBridge;
  p.x_m = x_m;
  p.z_m = z_m;
  p.direction_rad = direction_rad;
  p.width_m = width_m;
  p.length_m = {span_length_m, ramp1_length_m, ramp2_length_m};
  p.height_m = {height1_m, height2_m};
  p.material = material;
  return p;
}

Status ValidateFeatureParams(const FeatureParams& p) {
  if (!IsValidFeatureType(static_cast<uint16_t>(p.type))) {
    return Error{fmt::format("unknown feature type {}", static_cast<uint16_t>(p.type))};
  }
  if (!IsValidMaterial(static_cast<uint16_t>(p.material))) {
    return Error{fmt::format("unknown material {}", static_cast<uint16_t>(p.material))};
  }
  for (auto [name, v] : {std::pair{"x_m", p.x_m},
                         {"z_m", p.z_m},
                         {"direction_rad", p.direction_rad},
                         {"height_m[0]", p.height_m[0]},
                         {"height_m[1]", p.height_m[1]},
                         {"length_m[0]", p.length_m[0]},
                         {"length_m[1]", p.length_m[1]},
                         {"length_m[2]", p.length_m[2]},
                         {"width_m", p.width_m}}) {
    if (auto s = CheckFinite(name, v); !s) return s;
  }
  for (auto [name, v] : {std::pair{"x_m", p.x_m}, std::pair{"z_m", p.z_m}}) {
    if (auto s = CheckRange(name, v, -kMaxFeatureCoordinateM, kMaxFeatureCoordinateM); !s) {
      return s;
    }
  }
  if (!(std::abs(p.direction_rad) <= kMaxDirectionRad)) {
    return Error{fmt::format("{} direction_rad = {} is outside [-2 pi, 2 pi] (one turn either way)",
                             FeatureTypeName(p.type), p.direction_rad)};
  }
  if (p.type != FeatureType::kCrater && !p.vertex_edits.empty()) {
    return Error{fmt::format("{} cannot carry crater vertex edits", FeatureTypeName(p.type))};
  }
  if (p.type != FeatureType::kBridge && p.status != BridgeStatus::kIntact) {
    return Error{fmt::format("{} cannot have status {}", FeatureTypeName(p.type),
                             static_cast<int32_t>(p.status))};
  }
  switch (p.type) {
    case FeatureType::kCrater: {
      if (auto s = CheckSize("crater radius_m", p.length_m[0], kMaxCraterRadiusM); !s) return s;
      const CraterVertexEdit* previous = nullptr;
      for (const auto& e : p.vertex_edits) {
        if (e.spoke >= kCraterSpokes || e.ring >= kCraterRings) {
          return Error{fmt::format("crater vertex edit (spoke {}, ring {}) is outside 16 x 4",
                                   e.spoke, e.ring)};
        }
        if (auto s = CheckRange("crater vertex offset_m", e.offset_m, -kMaxCraterRadiusM,
                                kMaxCraterRadiusM);
            !s) {
          return s;
        }
        if (previous && std::pair(previous->spoke, previous->ring) >= std::pair(e.spoke, e.ring)) {
          return Error{"crater vertex edits must be sorted by (spoke, ring) without repeats"};
        }
        previous = &e;
      }
      break;
    }
    case FeatureType::kBerm:
      if (auto s = CheckSize("berm length_m", p.length_m[0], kMaxBermLengthM); !s) return s;
      if (auto s = CheckSize("berm width_m", p.width_m, kMaxBermWidthM); !s) return s;
      if (auto s = CheckSize("berm height_m", p.height_m[0], kMaxBermHeightM); !s) return s;
      break;
    case FeatureType::kBridge:
      if (auto s = CheckSize("bridge span length_m", p.length_m[0], kMaxBridgeLengthM); !s)
        return s;
      if (auto s = CheckSize("bridge ramp 1 length_m", p.length_m[1], kMaxBridgeLengthM); !s)
        return s;
      if (auto s = CheckSize("bridge ramp 2 length_m", p.length_m[2], kMaxBridgeLengthM); !s)
        return s;
      if (auto s = CheckSize("bridge width_m", p.width_m, kMaxBridgeWidthM); !s) return s;
      if (auto s = CheckSize("bridge height_m[0]", p.height_m[0], kMaxBridgeHeightM); !s) return s;
      if (auto s = CheckSize("bridge height_m[1]", p.height_m[1], kMaxBridgeHeightM); !s) return s;
      if (p.status != BridgeStatus::kIntact && p.status != BridgeStatus::kDestroyed) {
        return Error{fmt::format("unknown bridge status {}", static_cast<int32_t>(p.status))};
      }
      break;
  }
  return Status::Ok();
}

void EncodeFeatureParams(const FeatureParams& p, ByteWriter& out) {
  out.U16(static_cast<uint16_t>(p.type));
  out.F64(p.x_m);
  out.F64(p.z_m);
  out.F64(p.direction_rad);
  for (double h : p.height_m) out.F64(h);
  for (double l : p.length_m) out.F64(l);
  out.F64(p.width_m);
  out.U16(static_cast<uint16_t>(p.material));
  out.I32(static_cast<int32_t>(p.status));
  out.U16(static_cast<uint16_t>(p.vertex_edits.size()));
  for (const auto& e : p.vertex_edits) {
    out.U8(e.spoke);
    out.U8(e.ring);
    out.F64(e.offset_m);
  }
}

Result<FeatureParams> DecodeFeatureParams(ByteReader& in) {
  const size_t start = in.offset();
  auto truncated = [&] {
    return Error{fmt::format("feature parameters truncated at byte {} (record began at {})",
                             in.offset(), start)};
  };
  FeatureParams p;
  auto type = in.U16();
  if (!type) return truncated();
  p.type = static_cast<FeatureType>(*type);
  for (double* field : {&p.x_m, &p.z_m, &p.direction_rad, &p.height_m[0], &p.height_m[1],
                        &p.length_m[0], &p.length_m[1], &p.length_m[2], &p.width_m}) {
    auto v = in.F64();
    if (!v) return truncated();
    *field = *v;
  }
  auto material = in.U16();
  auto status = in.I32();
  auto edits = in.U16();
  if (!material || !status || !edits) return truncated();
  p.material = static_cast<Material>(*material);
  p.status = static_cast<BridgeStatus>(*status);
  if (*edits > kCraterSpokes * kCraterRings) {
    return Error{fmt::format("feature record at byte {} claims {} vertex edits (max {})", start,
                             *edits, kCraterSpokes * kCraterRings)};
  }
  p.vertex_edits.resize(*edits);
  for (auto& e : p.vertex_edits) {
    auto spoke = in.U8();
    auto ring = in.U8();
    auto offset = in.F64();
    if (!spoke || !ring || !offset) return truncated();
    e = {*spoke, *ring, *offset};
  }
  if (auto s = ValidateFeatureParams(p); !s) {
    return Error{fmt::format("feature record at byte {}: {}", start, s.error().message)};
  }
  return p;
}

}  // namespace dt
