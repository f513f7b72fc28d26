#include "runtime/feature_edit.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

namespace dt {
namespace {

constexpr double kDegToRad = std::numbers::pi / 180.0;

// Sets one key; false if the key does not belong to the type.
bool SetKey(FeatureParams& p, std::string_view key, double v) {
  if (key == "x_m") {
    p.x_m = v;
    return true;
  }
  if (key == "z_m") {
    p.z_m = v;
    return true;
  }
  switch (p.type) {
    case FeatureType::kCrater:
      if (key == "radius_m")
        p.length_m[0] = v;
      else
        return false;
      return true;
    case FeatureType::kBerm:
      if (key == "direction_deg")
        p.direction_rad = v * kDegToRad;
      else if (key == "length_m")
        p.length_m[0] = v;
      else if (key == "width_m")
        p.width_m = v;
      else if (key == "height_m")
        p.height_m[0] = v;
      else
        return false;
      return true;
    case FeatureType::kBridge:
      if (key == "direction_deg")
        p.direction_rad = v * kDegToRad;
      else if (key == "width_m")
        p.width_m = v;
      else if (key == "span_m")
        p.length_m[0] = v;
      else if (key == "ramp1_m")
        p.length_m[1] = v;
      else if (key == "ramp2_m")
        p.length_m[2] = v;
      else if (key == "height1_m")
        p.height_m[0] = v;
      else if (key == "height2_m")
        p.height_m[1] = v;
      else if (key == "status" && (v == 0.0 || v == 1.0))
        p.status = static_cast<BridgeStatus>(v);
      else
        return false;
      return true;
  }
  return false;
}

std::string KeyList(const std::vector<std::string_view>& keys) {
  std::string out;
  for (std::string_view k : keys) {
    if (!out.empty()) out += ", ";
    out += k;
  }
  return out;
}

}  // namespace

std::vector<std::string_view> FeatureKeys(FeatureType type) {
  switch (type) {
    case FeatureType::kCrater:
      return {"x_m", "z_m", "radius_m"};
    case FeatureType::kBerm:
      return {"x_m", "z_m", "direction_deg", "length_m", "width_m", "height_m"};
    case FeatureType::kBridge:
      return {"x_m",    "z_m",     "direction_deg", "width_m",   "ramp1_m",
              "span_m", "ramp2_m", "height1_m",     "height2_m", "status"};
  }
  return {};
}

std::vector<std::string_view> RequiredFeatureKeys(FeatureType type) {
  std::vector<std::string_view> keys = FeatureKeys(type);
  std::erase(keys, std::string_view("status"));
  return keys;
}

Result<FeatureParams> ApplyFeatureEdit(const FeatureParams& params, const FeatureEdit& edit) {
  FeatureParams p = params;
  for (const auto& [key, value] : edit.values) {
    if (!std::isfinite(value)) {
      return Error{fmt::format("{}={} is not a finite number", key, value)};
    }
    // Validation allows one turn either way (kMaxDirectionRad); say so in the key's own unit.
    if (key == "direction_deg" && std::abs(value) > 360.0) {
      return Error{
          fmt::format("direction_deg={} is outside [-360, 360] (one turn either way)", value)};
    }
    if (!SetKey(p, key, value)) {
      if (key == "status") {
        return Error{fmt::format("status={} must be 0 (intact) or 1 (destroyed)", value)};
      }
      return Error{fmt::format("{} is not a key of a {} (keys: {})", key, FeatureTypeName(p.type),
                               KeyList(FeatureKeys(p.type)))};
    }
  }
  if (Status s = ValidateFeatureParams(p); !s) return s.error();
  return p;
}

Result<FeatureParams> MakeFeature(FeatureType type, const FeatureEdit& edit) {
  for (std::string_view key : RequiredFeatureKeys(type)) {
    const bool given = std::any_of(edit.values.begin(), edit.values.end(),
                                   [&](const auto& kv) { return kv.first == key; });
    if (!given) {
      return Error{fmt::format("a new {} needs {} (keys: {})", FeatureTypeName(type), key,
                               KeyList(RequiredFeatureKeys(type)))};
    }
  }
  FeatureParams base;
  base.type = type;
  if (type == FeatureType::kBridge) base.material = Material::kConcrete;
  return ApplyFeatureEdit(base, edit);
}

Result<FeatureType> ParseFeatureType(std::string_view name) {
  for (FeatureType t : {FeatureType::kCrater, FeatureType::kBerm, FeatureType::kBridge}) {
    if (FeatureTypeName(t) == name) return t;
  }
  return Error{fmt::format("unknown feature type \"{}\" (crater, berm, bridge)", name)};
}

}  // namespace dt
