#include "terrain/berm.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace dt {
namespace {

// Points this far outside the footprint still count as covered, so mesh vertices computed in
// floating point (and points on the outline) are covered however they round.
constexpr double kEdgeToleranceM = 1e-9;

Status CheckUnused(const FeatureParams& p) {
  for (auto [name, v] : {std::pair{"height_m[1]", p.height_m[1]},
                         {"length_m[1]", p.length_m[1]},
                         {"length_m[2]", p.length_m[2]}}) {
    if (v != 0.0)
      return Error{fmt::format("a berm does not use {}; it must be 0, not {}", name, v)};
  }
  return Status::Ok();
}

}  // namespace

Berm::Berm(FeatureId id, const FeatureParams& p, Material resolved)
    : Feature(id),
      x_m_(p.x_m),
      z_m_(p.z_m),
      direction_rad_(p.direction_rad),
      length_m_(p.length_m[0]),
      width_m_(p.width_m),
      height_m_(p.height_m[0]),
      cos_(std::cos(p.direction_rad)),
      sin_(std::sin(p.direction_rad)),
      half_width_m_(0.5 * p.width_m),
      slope_run_m_(0.5 * (1.0 - kBermTopWidthFraction) * p.width_m),
      inverse_run_(1.0 / slope_run_m_),
      given_material_(p.material),
      resolved_material_(resolved) {}

FeatureParams Berm::params() const {
  return FeatureParams::Berm(x_m_, z_m_, direction_rad_, length_m_, width_m_, height_m_,
                             given_material_);
}

void Berm::Local(double x_m, double z_m, double& along_m, double& left_m) const {
  const double dx = x_m - x_m_, dz = z_m - z_m_;
  along_m = dx * cos_ + dz * sin_;
  left_m = dz * cos_ - dx * sin_;
}

Rect Berm::Bounds() const {
  // The footprint is the rectangle along [-run, length + run] x left [-w/2, w/2].
  const double half_along = 0.5 * length_m_ + slope_run_m_;
  const double cx = x_m_ + 0.5 * length_m_ * cos_;
  const double cz = z_m_ + 0.5 * length_m_ * sin_;
  const double ex = std::abs(cos_) * half_along + std::abs(sin_) * half_width_m_;
  const double ez = std::abs(sin_) * half_along + std::abs(cos_) * half_width_m_;
  return {cx - ex, cz - ez, cx + ex, cz + ez};
}

bool Berm::InFootprint(double along_m, double left_m) const {
  // Written so that NaN fails every test.
  const double reach = slope_run_m_ + kEdgeToleranceM;
  return std::abs(left_m) <= half_width_m_ + kEdgeToleranceM && along_m >= -reach &&
         along_m <= length_m_ + reach;
}

bool Berm::Covers(double x_m, double z_m) const {
  double along, left;
  Local(x_m, z_m, along, left);
  return InFootprint(along, left);
}

bool Berm::MayCover(const Rect& rect) const {
  // Separating-axis test of the footprint against the rectangle, on the four edge directions.
  const double half_along = 0.5 * length_m_ + slope_run_m_ + kEdgeToleranceM;
  const double half_across = half_width_m_ + kEdgeToleranceM;
  const double hx = 0.5 * (rect.max_x - rect.min_x), hz = 0.5 * (rect.max_z - rect.min_z);
  const double dx = x_m_ + 0.5 * length_m_ * cos_ - 0.5 * (rect.min_x + rect.max_x);
  const double dz = z_m_ + 0.5 * length_m_ * sin_ - 0.5 * (rect.min_z + rect.max_z);
  const double ac = std::abs(cos_), as = std::abs(sin_);
  if (std::abs(dx) > hx + ac * half_along + as * half_across) return false;
  if (std::abs(dz) > hz + as * half_along + ac * half_across) return false;
  if (std::abs(dx * cos_ + dz * sin_) > half_along + hx * ac + hz * as) return false;
  if (std::abs(dz * cos_ - dx * sin_) > half_across + hx * as + hz * ac) return false;
  return true;
}

double Berm::OffsetOrNotCovered(double x_m, double z_m) const {
  double along, left;
  Local(x_m, z_m, along, left);
  if (!InFootprint(along, left)) return kNotCovered;
  // Bilinear over the mesh: the cross-section times the end-piece factor, each a fraction of the
  // height clamped to [0, 1]. Branch-free, as query points fall anywhere on the berm.
  const double side = (half_width_m_ - std::abs(left)) * inverse_run_;
  const double end =
      std::min(along + slope_run_m_, length_m_ + slope_run_m_ - along) * inverse_run_;
  return height_m_ * std::clamp(side, 0.0, 1.0) * std::clamp(end, 0.0, 1.0);
}

BermVertex Berm::Vertex(int length_line, int width_line) const {
  if (length_line < 0 || length_line >= kBermLengthLines || width_line < 0 ||
      width_line >= kBermWidthLines) {
    throw std::out_of_range(
        fmt::format("berm vertex (length line {}, width line {}) is outside "
                    "11 x 4",
                    length_line, width_line));
  }
  const double along = length_m_ * length_line / (kBermLengthLines - 1);
  constexpr double kLeftFractions[kBermWidthLines] = {-1.0, -kBermTopWidthFraction,
                                                      kBermTopWidthFraction, 1.0};
  const double left = half_width_m_ * kLeftFractions[width_line];
  const bool top = width_line == 1 || width_line == 2;
  return {x_m_ + along * cos_ - left * sin_, z_m_ + along * sin_ + left * cos_,
          top ? height_m_ : 0.0};
}

Result<std::unique_ptr<Feature>> MakeBerm(FeatureId id, const FeatureParams& params,
                                          const HeightGrid& ground) {
  Result<Material> resolved = CheckPlacementBasics(id, params, FeatureType::kBerm, ground);
  if (!resolved) return resolved.error();
  if (auto s = CheckUnused(params); !s) {
    return Error{fmt::format("berm {}: {}", id.ToString(), s.error().message)};
  }
  return std::unique_ptr<Feature>(new Berm(id, params, resolved.value()));
}

}  // namespace dt
