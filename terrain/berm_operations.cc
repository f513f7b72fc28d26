#include "terrain/berm_operations.h"

#include <cmath>
#include <numbers>

#include <fmt/format.h>

namespace dt {
namespace {

// Direction in [-pi, pi], so generated parameters stay small and readable.
double NormalisedDirection(double direction_rad) {
  return std::remainder(direction_rad, 2.0 * std::numbers::pi);
}

}  // namespace

Result<std::vector<FeatureParams>> BreachBerm(const FeatureParams& berm, double gap_centre_m,
                                              double gap_width_m) {
  if (berm.type != FeatureType::kBerm) {
    return Error{
        fmt::format("cannot breach a {}: only berms are breached", FeatureTypeName(berm.type))};
  }
  if (auto s = ValidateFeatureParams(berm); !s) {
    return Error{fmt::format("cannot breach an invalid berm: {}", s.error().message)};
  }
  if (!std::isfinite(gap_width_m) || !(gap_width_m > 0.0)) {
    return Error{fmt::format("breach gap width {} m must be finite and > 0", gap_width_m)};
  }
  const double length = berm.length_m[0];
  if (!(gap_centre_m >= 0.0 && gap_centre_m <= length)) {
    return Error{fmt::format("breach gap centre {} m is outside the berm's crest [0, {}] m",
                             gap_centre_m, length)};
  }
  const double run = 0.5 * (1.0 - kBermTopWidthFraction) * berm.width_m;
  const double c = std::cos(berm.direction_rad), s = std::sin(berm.direction_rad);
  std::vector<FeatureParams> pieces;
  // Before the gap: same start, crest shortened so its end piece ends at the gap's edge.
  const double first_length = gap_centre_m - 0.5 * gap_width_m - run;
  // A piece shorter than the smallest feature is no berm: dropped, so the breach stays valid.
  if (first_length >= kMinFeatureSizeM) {
    FeatureParams p = berm;
    p.length_m[0] = first_length;
    pieces.push_back(p);
  }
  // After the gap: starts where its end piece clears the gap, ends where the berm ended.
  const double second_start = gap_centre_m + 0.5 * gap_width_m + run;
  if (length - second_start >= kMinFeatureSizeM) {
    FeatureParams p = berm;
    p.x_m = berm.x_m + second_start * c;
    p.z_m = berm.z_m + second_start * s;
    p.length_m[0] = length - second_start;
    pieces.push_back(p);
  }
  return pieces;
}

Result<std::vector<FeatureParams>> BreachBerm(const Berm& berm, double gap_centre_m,
                                              double gap_width_m) {
  auto pieces = BreachBerm(berm.params(), gap_centre_m, gap_width_m);
  if (!pieces) return pieces;
  for (auto& p : pieces.value()) p.material = berm.material();
  return pieces;
}

Result<std::array<FeatureParams, 3>> EmplacementBerms(const EmplacementSpec& spec) {
  if (!std::isfinite(spec.facing_rad)) {
    return Error{fmt::format("emplacement facing {} rad is not finite", spec.facing_rad)};
  }
  const double half = 0.5 * spec.size_m;
  const double fx = std::cos(spec.facing_rad), fz = std::sin(spec.facing_rad);  // forward
  const double lx = -fz, lz = fx;                                               // left
  const double front_left_x = spec.centre_x_m + half * (fx + lx);
  const double front_left_z = spec.centre_z_m + half * (fz + lz);
  const double front_right_x = spec.centre_x_m + half * (fx - lx);
  const double front_right_z = spec.centre_z_m + half * (fz - lz);
  const double left_dir = NormalisedDirection(spec.facing_rad + 0.5 * std::numbers::pi);
  const double back_dir = NormalisedDirection(spec.facing_rad + std::numbers::pi);
  std::array<FeatureParams, 3> berms = {
      FeatureParams::Berm(front_right_x, front_right_z, left_dir, spec.size_m, spec.width_m,
                          spec.height_m, spec.material),
      FeatureParams::Berm(front_left_x, front_left_z, back_dir, spec.size_m, spec.width_m,
                          spec.height_m, spec.material),
      FeatureParams::Berm(front_right_x, front_right_z, back_dir, spec.size_m, spec.width_m,
                          spec.height_m, spec.material),
  };
  constexpr const char* kNames[] = {"front", "left", "right"};
  for (size_t k = 0; k < berms.size(); ++k) {
    if (auto s = ValidateFeatureParams(berms[k]); !s) {
      return Error{fmt::format("emplacement {} berm: {}", kNames[k], s.error().message)};
    }
  }
  return berms;
}

}  // namespace dt
