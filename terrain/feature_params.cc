#include "terrain/feature_params.h"

#include "terrain/height_grid.h"

#include <fmt/format.h>
#include <algorithm>
#include <array>
#include <cmath>
#include <initializer_list>
#include <iterator>
#include <span>

namespace dt {
namespace {

Status RangeError(std::string_view field, double value, double min_inclusive,
                  double max_inclusive) {
  if (!std::isfinite(value)) {
    return Error{fmt::format("{} is not finite ({})", field, value)};
  }
  return Error{
      fmt::format("{} = {} is outside [{}, {}]", field, value, min_inclusive, max_inclusive)};
}

// The checks below name the field only when they fail: every feature received is checked, and
// measuring a name (strlen) for each field of each one was a visible part of applying it.
template <typename Name>
Status CheckRange(const Name& field, double value, double min_inclusive, double max_inclusive) {
  if (std::isfinite(value) && value >= min_inclusive && value <= max_inclusive) {
    return Status::Ok();
  }
  return RangeError(field, value, min_inclusive, max_inclusive);
}

// A size: at least kMinFeatureSizeM, at most the type's maximum.
template <typename Name>
Status CheckSize(const Name& field, double value, double max_inclusive) {
  return CheckRange(field, value, kMinFeatureSizeM, max_inclusive);
}

template <typename Name>
Status CheckFinite(const Name& field, double value) {
  if (std::isfinite(value)) return Status::Ok();
  return Error{fmt::format("{} is not finite ({})", std::string_view(field), value)};
}

}  // namespace

std::string_view FeatureTypeName(FeatureType type) {
  static constexpr std::string_view kNames[] = {DT_FEATURE_TYPES(DT_ENUM_NAME)};
  static_assert(std::size(kNames) == kFeatureTypeCount);
  const auto raw = static_cast<uint16_t>(type);
  return IsValidFeatureType(raw) ? kNames[raw - 1] : "unknown";
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

FeatureParams FeatureParams::DeepCrater(double x_m, double z_m, double radius_m, double depth_m,
                                        Material material) {
  FeatureParams p = Crater(x_m, z_m, radius_m, material);
  p.height_m[0] = depth_m;
  return p;
}

namespace {
FeatureParams WithPoints(FeatureType type, std::vector<FeaturePoint> points, Material material) {
  FeatureParams p;
  p.type = type;
  if (!points.empty()) {
    p.x_m = points.front().x_m;
    p.z_m = points.front().z_m;
  }
  p.points = std::move(points);
  p.material = material;
  return p;
}
}  // namespace

FeatureParams FeatureParams::Ditch(std::vector<FeaturePoint> points, double side_run_m,
                                   double spoil_height_m, double spoil_width_m, Material material) {
  FeatureParams p = WithPoints(FeatureType::kDitch, std::move(points), material);
  p.length_m[0] = side_run_m;
  p.height_m[1] = spoil_height_m;
  p.length_m[1] = spoil_width_m;
  return p;
}

FeatureParams FeatureParams::BermLine(std::vector<FeaturePoint> points, Material material) {
  return WithPoints(FeatureType::kBermLine, std::move(points), material);
}

FeatureParams FeatureParams::Area(std::vector<FeaturePoint> points, Material material,
                                  double water_level_m) {
  FeatureParams p = WithPoints(FeatureType::kArea, std::move(points), material);
  if (material == Material::kWater) p.height_m[0] = water_level_m;
  return p;
}

namespace {

// The fields a type leaves unused must be 0, so params() gives back exactly what was sent.
using NamedField = std::pair<const char*, double>;

// Every scalar field of a feature by its name (validation names the field it refuses).
std::array<NamedField, 9> ScalarFields(const FeatureParams& p) {
  return {{{"x_m", p.x_m},
           {"z_m", p.z_m},
           {"direction_rad", p.direction_rad},
           {"height_m[0]", p.height_m[0]},
           {"height_m[1]", p.height_m[1]},
           {"length_m[0]", p.length_m[0]},
           {"length_m[1]", p.length_m[1]},
           {"length_m[2]", p.length_m[2]},
           {"width_m", p.width_m}}};
}

Status CheckZero(FeatureType type, std::span<const NamedField> fields) {
  for (auto [name, v] : fields) {
    if (v != 0.0) {
      return Error{fmt::format("a {} does not use {}; it must be 0, not {}", FeatureTypeName(type),
                               name, v)};
    }
  }
  return Status::Ok();
}

Status CheckZero(FeatureType type, std::initializer_list<NamedField> fields) {
  return CheckZero(type, std::span(fields.begin(), fields.size()));
}

// The point list of a polyline (open) or polygon (closed): count, finite coordinates in range,
// (x_m, z_m) at the first point, consecutive points apart, and for a polyline no joint sharper
// than kMaxPolylineTurnRad.
Status CheckPoints(const FeatureParams& p, size_t min_points, bool polyline) {
  const std::string_view type = FeatureTypeName(p.type);
  if (p.points.size() < min_points || p.points.size() > kMaxFeaturePoints) {
    return Error{fmt::format("{} points: {} given, needs {} to {}", type, p.points.size(),
                             min_points, kMaxFeaturePoints)};
  }
  for (size_t i = 0; i < p.points.size(); ++i) {
    const FeaturePoint& q = p.points[i];
    for (auto [name, v] : {std::pair{"x_m", q.x_m}, std::pair{"z_m", q.z_m}}) {
      if (auto s = CheckRange(fmt::format("{} points[{}].{}", type, i, name), v,
                              -kMaxFeatureCoordinateM, kMaxFeatureCoordinateM);
          !s) {
        return s;
      }
    }
    if (!std::isfinite(q.height_m) || !std::isfinite(q.width_m)) {
      return Error{fmt::format("{} points[{}] height_m {} or width_m {} is not finite", type, i,
                               q.height_m, q.width_m)};
    }
    if (i > 0) {
      const FeaturePoint& prev = p.points[i - 1];
      const double dx = q.x_m - prev.x_m, dz = q.z_m - prev.z_m;
      if (!(std::sqrt(dx * dx + dz * dz) >= kMinFeatureSizeM)) {
        return Error{fmt::format("{} points[{}] ({}, {}) is within {} m of points[{}]", type, i,
                                 q.x_m, q.z_m, kMinFeatureSizeM, i - 1)};
      }
    }
    if (polyline && i >= 2) {
      const FeaturePoint& a = p.points[i - 2];
      const FeaturePoint& b = p.points[i - 1];
      const double ux = b.x_m - a.x_m, uz = b.z_m - a.z_m;
      const double vx = q.x_m - b.x_m, vz = q.z_m - b.z_m;
      const double cos_turn =
          (ux * vx + uz * vz) / (std::sqrt(ux * ux + uz * uz) * std::sqrt(vx * vx + vz * vz));
      if (!(cos_turn >= std::cos(kMaxPolylineTurnRad))) {
        return Error{fmt::format(
            "{} points[{}]: the line turns by {:.1f} deg there, more than {} "
            "deg",
            type, i - 1, std::acos(std::clamp(cos_turn, -1.0, 1.0)) * 180.0 / std::numbers::pi,
            kMaxPolylineTurnRad * 180.0 / std::numbers::pi)};
      }
    }
  }
  if (p.x_m != p.points.front().x_m || p.z_m != p.points.front().z_m) {
    return Error{fmt::format("{} x_m, z_m ({}, {}) must be points[0] ({}, {})", type, p.x_m, p.z_m,
                             p.points.front().x_m, p.points.front().z_m)};
  }
  return Status::Ok();
}

Status CheckPointSizes(const FeatureParams& p, double max_height_m, double max_width_m) {
  const std::string_view type = FeatureTypeName(p.type);
  for (size_t i = 0; i < p.points.size(); ++i) {
    const FeaturePoint& q = p.points[i];
    if (auto s =
            CheckSize(fmt::format("{} points[{}].height_m", type, i), q.height_m, max_height_m);
        !s) {
      return s;
    }
    if (auto s = CheckSize(fmt::format("{} points[{}].width_m", type, i), q.width_m, max_width_m);
        !s) {
      return s;
    }
  }
  return Status::Ok();
}

Status ValidateDitch(const FeatureParams& p) {
  if (auto s = CheckPoints(p, 2, true); !s) return s;
  if (auto s = CheckPointSizes(p, kMaxDitchDepthM, kMaxDitchWidthM); !s) return s;
  if (auto s = CheckSize("ditch side run length_m[0]", p.length_m[0], kMaxDitchWidthM / 2); !s) {
    return s;
  }
  for (size_t i = 0; i < p.points.size(); ++i) {
    if (p.points[i].width_m < 2.0 * p.length_m[0]) {
      return Error{
          fmt::format("ditch points[{}].width_m = {} is less than twice the side run "
                      "length_m[0] = {} (the sides would cross)",
                      i, p.points[i].width_m, p.length_m[0])};
    }
  }
  if (p.height_m[1] != 0.0 || p.length_m[1] != 0.0) {
    if (auto s = CheckSize("ditch spoil height_m[1]", p.height_m[1], kMaxBermHeightM); !s) {
      return s;
    }
    if (auto s = CheckSize("ditch spoil width_m length_m[1]", p.length_m[1], kMaxBermWidthM); !s) {
      return s;
    }
  }
  return CheckZero(p.type, {{"direction_rad", p.direction_rad},
                            {"height_m[0]", p.height_m[0]},
                            {"length_m[2]", p.length_m[2]},
                            {"width_m", p.width_m}});
}

Status ValidateBermLine(const FeatureParams& p) {
  if (auto s = CheckPoints(p, 2, true); !s) return s;
  if (auto s = CheckPointSizes(p, kMaxBermHeightM, kMaxBermWidthM); !s) return s;
  return CheckZero(p.type, {{"direction_rad", p.direction_rad},
                            {"height_m[0]", p.height_m[0]},
                            {"height_m[1]", p.height_m[1]},
                            {"length_m[0]", p.length_m[0]},
                            {"length_m[1]", p.length_m[1]},
                            {"length_m[2]", p.length_m[2]},
                            {"width_m", p.width_m}});
}

Status ValidateArea(const FeatureParams& p) {
  if (auto s = CheckPoints(p, 3, false); !s) return s;
  for (size_t i = 0; i < p.points.size(); ++i) {
    if (p.points[i].height_m != 0.0 || p.points[i].width_m != 0.0) {
      return Error{fmt::format("area points[{}] height_m {} and width_m {} must be 0", i,
                               p.points[i].height_m, p.points[i].width_m)};
    }
  }
  if (p.material == Material::kFromGround) {
    return Error{"area material must be a soil (water, burnt, mud, oil, ...), not from_ground"};
  }
  if (p.material == Material::kWater) {
    if (auto s = CheckRange("area water level height_m[0]", p.height_m[0], -kMaxWaterLevelM,
                            kMaxWaterLevelM);
        !s) {
      return s;
    }
  } else if (auto s = CheckZero(p.type, {{"height_m[0] (a water level; the material is not water)",
                                          p.height_m[0]}});
             !s) {
    return s;
  }
  return CheckZero(p.type, {{"direction_rad", p.direction_rad},
                            {"height_m[1]", p.height_m[1]},
                            {"length_m[0]", p.length_m[0]},
                            {"length_m[1]", p.length_m[1]},
                            {"length_m[2]", p.length_m[2]},
                            {"width_m", p.width_m}});
}

}  // namespace

FeatureParams FeatureParams::EarthMove(std::vector<PostDelta> post_deltas) {
  FeatureParams p;
  p.type = FeatureType::kEarthMove;
  std::sort(post_deltas.begin(), post_deltas.end(), [](const PostDelta& a, const PostDelta& b) {
    return std::pair(a.j, a.i) < std::pair(b.j, b.i);
  });
  p.post_deltas = std::move(post_deltas);
  return p;
}

namespace {

// Post indices of an earth move are below the largest grid's side (an elevation ground's).
constexpr int kMaxEarthMovePostIndex = kMaxGridPostsPerSide;

Status ValidateEarthMove(const FeatureParams& p) {
  if (auto s = CheckZero(FeatureType::kEarthMove, ScalarFields(p)); !s) {
    return s;
  }
  if (p.material != Material::kFromGround) {
    return Error{fmt::format("earth_move material {} must be from_ground (0)",
                             static_cast<uint16_t>(p.material))};
  }
  if (p.post_deltas.empty() || p.post_deltas.size() > kMaxEarthMovePosts) {
    return Error{fmt::format("earth_move post_deltas: {} given, needs 1 to {}",
                             p.post_deltas.size(), kMaxEarthMovePosts)};
  }
  int min_i = kMaxEarthMovePostIndex, max_i = -1;
  int min_j = kMaxEarthMovePostIndex, max_j = -1;
  for (size_t k = 0; k < p.post_deltas.size(); ++k) {
    const PostDelta& d = p.post_deltas[k];
    if (d.i >= kMaxEarthMovePostIndex || d.j >= kMaxEarthMovePostIndex) {
      return Error{
          fmt::format("earth_move post_deltas[{}] post ({}, {}) is beyond any grid ({} posts "
                      "a side)",
                      k, d.i, d.j, kMaxEarthMovePostIndex)};
    }
    if (d.delta_mm == 0 || d.delta_mm > kMaxPostDeltaMm || d.delta_mm < -kMaxPostDeltaMm) {
      return Error{fmt::format("earth_move post_deltas[{}].delta_mm = {} is 0 or outside [-{}, {}]",
                               k, d.delta_mm, kMaxPostDeltaMm, kMaxPostDeltaMm)};
    }
    if (k > 0) {
      const PostDelta& prev = p.post_deltas[k - 1];
      if (std::pair(prev.j, prev.i) >= std::pair(d.j, d.i)) {
        return Error{
            fmt::format("earth_move post_deltas[{}] post ({}, {}) is not after post ({}, "
                        "{}): posts must be sorted by (j, i) without repeats",
                        k, d.i, d.j, prev.i, prev.j)};
      }
    }
    min_i = std::min<int>(min_i, d.i);
    max_i = std::max<int>(max_i, d.i);
    min_j = std::min<int>(min_j, d.j);
    max_j = std::max<int>(max_j, d.j);
  }
  if (max_i - min_i + 1 > kMaxEarthMoveSpanPosts || max_j - min_j + 1 > kMaxEarthMoveSpanPosts) {
    return Error{fmt::format("earth_move post_deltas span {} x {} posts, more than {} x {}",
                             max_i - min_i + 1, max_j - min_j + 1, kMaxEarthMoveSpanPosts,
                             kMaxEarthMoveSpanPosts)};
  }
  return Status::Ok();
}

}  // namespace

Status ValidateFeatureParams(const FeatureParams& p) {
  if (!IsValidFeatureType(static_cast<uint16_t>(p.type))) {
    return Error{fmt::format("unknown feature type {}", static_cast<uint16_t>(p.type))};
  }
  if (!IsValidMaterial(static_cast<uint16_t>(p.material))) {
    return Error{fmt::format("unknown material {}", static_cast<uint16_t>(p.material))};
  }
  // Every feature received passes here, twice (MakeFeature, then its maker): the fields are
  // named one by one only when one of them is not finite.
  const bool all_finite = std::isfinite(p.x_m) && std::isfinite(p.z_m) &&
                          std::isfinite(p.direction_rad) && std::isfinite(p.height_m[0]) &&
                          std::isfinite(p.height_m[1]) && std::isfinite(p.length_m[0]) &&
                          std::isfinite(p.length_m[1]) && std::isfinite(p.length_m[2]) &&
                          std::isfinite(p.width_m);
  if (!all_finite) {
    for (auto [name, v] : ScalarFields(p)) {
      if (auto s = CheckFinite(name, v); !s) return s;
    }
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
  if (!HasFeaturePoints(p.type) && !p.points.empty()) {
    return Error{fmt::format("{} cannot carry points", FeatureTypeName(p.type))};
  }
  if (p.type != FeatureType::kEarthMove && !p.post_deltas.empty()) {
    return Error{fmt::format("{} cannot carry post deltas", FeatureTypeName(p.type))};
  }
  if (p.type != FeatureType::kBridge && p.status != BridgeStatus::kIntact) {
    return Error{fmt::format("{} cannot have status {}", FeatureTypeName(p.type),
                             static_cast<int32_t>(p.status))};
  }
  switch (p.type) {
    case FeatureType::kCrater: {
      if (auto s = CheckSize("crater radius_m", p.length_m[0], kMaxCraterRadiusM); !s) return s;
      if (auto s = CheckRange("crater depth_m height_m[0]", p.height_m[0], 0.0, kMaxCraterDepthM);
          !s) {
        return s;
      }
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
    case FeatureType::kDitch:
      return ValidateDitch(p);
    case FeatureType::kBermLine:
      return ValidateBermLine(p);
    case FeatureType::kArea:
      return ValidateArea(p);
    case FeatureType::kEarthMove:
      return ValidateEarthMove(p);
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
  if (p.type == FeatureType::kEarthMove) {
    out.U16(static_cast<uint16_t>(p.post_deltas.size()));
    for (const auto& d : p.post_deltas) {
      out.U16(d.i);
      out.U16(d.j);
      out.I32(d.delta_mm);
    }
    return;
  }
  if (!HasFeaturePoints(p.type)) return;
  out.U16(static_cast<uint16_t>(p.points.size()));
  for (const auto& q : p.points) {
    out.F64(q.x_m);
    out.F64(q.z_m);
    out.F64(q.height_m);
    out.F64(q.width_m);
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
  if (HasFeaturePoints(p.type)) {
    auto count = in.U16();
    if (!count) return truncated();
    if (*count > kMaxFeaturePoints) {
      return Error{fmt::format("feature record at byte {} claims {} points (max {})", start, *count,
                               kMaxFeaturePoints)};
    }
    p.points.resize(*count);
    for (auto& q : p.points) {
      for (double* field : {&q.x_m, &q.z_m, &q.height_m, &q.width_m}) {
        auto v = in.F64();
        if (!v) return truncated();
        *field = *v;
      }
    }
  }
  if (p.type == FeatureType::kEarthMove) {
    auto count = in.U16();
    if (!count) return truncated();
    if (*count > kMaxEarthMovePosts) {
      return Error{fmt::format("feature record at byte {} claims {} post deltas (max {})", start,
                               *count, kMaxEarthMovePosts)};
    }
    p.post_deltas.resize(*count);
    for (auto& d : p.post_deltas) {
      auto i = in.U16();
      auto j = in.U16();
      auto delta = in.I32();
      if (!i || !j || !delta) return truncated();
      d = {*i, *j, *delta};
    }
  }
  if (auto s = ValidateFeatureParams(p); !s) {
    return Error{fmt::format("feature record at byte {}: {}", start, s.error().message)};
  }
  return p;
}

}  // namespace dt
