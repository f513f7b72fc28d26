#include "runtime/feature_edit.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

namespace dt {
namespace {

constexpr double kDegToRad = std::numbers::pi / 180.0;

// Sets points[i].field; false if the key is not of that form, the index skips a point or the
// list is full.
bool SetPointKey(FeatureParams& p, std::string_view key, double v) {
  constexpr std::string_view kPrefix = "points[";
  if (!key.starts_with(kPrefix)) return false;
  const size_t close = key.find("].", kPrefix.size());
  if (close == std::string_view::npos) return false;
  const std::string_view digits = key.substr(kPrefix.size(), close - kPrefix.size());
  if (digits.empty() || digits.size() > 3 ||
      !std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; })) {
    return false;
  }
  const size_t index = static_cast<size_t>(std::stoi(std::string(digits)));
  if (index > p.points.size() || index >= static_cast<size_t>(kMaxFeaturePoints)) return false;
  const std::string_view field = key.substr(close + 2);
  double FeaturePoint::*member = nullptr;
  if (field == "x_m") member = &FeaturePoint::x_m;
  if (field == "z_m") member = &FeaturePoint::z_m;
  if (field == "height_m") member = &FeaturePoint::height_m;
  if (field == "width_m") member = &FeaturePoint::width_m;
  if (member == nullptr) return false;
  if (index == p.points.size()) p.points.emplace_back();
  p.points[index].*member = v;
  return true;
}

// Sets one key; false if the key does not belong to the type.
bool SetKey(FeatureParams& p, std::string_view key, double v) {
  if (HasFeaturePoints(p.type)) {
    if (SetPointKey(p, key, v)) return true;
    if (p.type == FeatureType::kDitch) {
      if (key == "side_run_m")
        p.length_m[0] = v;
      else if (key == "spoil_height_m")
        p.height_m[1] = v;
      else if (key == "spoil_width_m")
        p.length_m[1] = v;
      else
        return false;
      return true;
    }
    if (p.type == FeatureType::kArea && key == "level_m") {
      p.height_m[0] = v;
      return true;
    }
    return false;
  }
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
      else if (key == "depth_m")
        p.height_m[0] = v;
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
    case FeatureType::kDitch:
    case FeatureType::kBermLine:
    case FeatureType::kArea:
      break;  // handled above
    case FeatureType::kEarthMove:
      break;  // blade work has no keys: it is added once and never updated
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
      return {"x_m", "z_m", "radius_m", "depth_m"};
    case FeatureType::kBerm:
      return {"x_m", "z_m", "direction_deg", "length_m", "width_m", "height_m"};
    case FeatureType::kBridge:
      return {"x_m",    "z_m",     "direction_deg", "width_m",   "ramp1_m",
              "span_m", "ramp2_m", "height1_m",     "height2_m", "status"};
    case FeatureType::kDitch:
      return {"side_run_m",    "spoil_height_m",     "spoil_width_m",    "points[i].x_m",
              "points[i].z_m", "points[i].height_m", "points[i].width_m"};
    case FeatureType::kBermLine:
      return {"points[i].x_m", "points[i].z_m", "points[i].height_m", "points[i].width_m"};
    case FeatureType::kArea:
      return {"level_m", "points[i].x_m", "points[i].z_m"};
    case FeatureType::kEarthMove:
      return {};  // made by a blade (docs/vehicles.md "Bulldozer"), never by keys
  }
  return {};
}

std::vector<std::string_view> RequiredFeatureKeys(FeatureType type) {
  std::vector<std::string_view> keys = FeatureKeys(type);
  // Optional keys, and the point keys (MakeFeature checks the points through validation).
  std::erase_if(keys, [](std::string_view k) {
    return k == "status" || k == "depth_m" || k == "spoil_height_m" || k == "spoil_width_m" ||
           k == "level_m" || k.starts_with("points[");
  });
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
      if (key.starts_with("points[")) {
        return Error{
            fmt::format("{} is not a point key of this {} (points[i].x_m, z_m, height_m or "
                        "width_m, with i at most {}, the next point)",
                        key, FeatureTypeName(p.type), p.points.size())};
      }
      if (key == "status") {
        return Error{fmt::format("status={} must be 0 (intact) or 1 (destroyed)", value)};
      }
      return Error{fmt::format("{} is not a key of a {} (keys: {})", key, FeatureTypeName(p.type),
                               KeyList(FeatureKeys(p.type)))};
    }
  }
  if (edit.soil) {
    if (p.type != FeatureType::kArea) {
      return Error{fmt::format("soil={} is not a key of a {} (only an area has a soil)",
                               MaterialName(*edit.soil), FeatureTypeName(p.type))};
    }
    // A level stays as given: an area turned from water to another soil must also set
    // level_m=0, or validation refuses it (nothing is dropped silently).
    p.material = *edit.soil;
  }
  // The types with points stand at their first point.
  if (HasFeaturePoints(p.type) && !p.points.empty()) {
    p.x_m = p.points.front().x_m;
    p.z_m = p.points.front().z_m;
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
  for (FeatureType t : {FeatureType::kCrater, FeatureType::kBerm, FeatureType::kBridge,
                        FeatureType::kDitch, FeatureType::kBermLine, FeatureType::kArea}) {
    if (FeatureTypeName(t) == name) return t;
  }
  return Error{fmt::format(
      "unknown feature type \"{}\" (crater, berm, bridge, ditch, berm_line, area)", name)};
}

}  // namespace dt
