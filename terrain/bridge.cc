#include "terrain/bridge.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include <fmt/format.h>

namespace dt {
namespace {

using Quad = std::array<Eigen::Vector2d, 4>;

// Separating-axis test for two convex quadrilaterals: they overlap when their projections
// overlap by more than `min_overlap_m` on every edge normal of both.
bool QuadsOverlap(const Quad& a, const Quad& b, double min_overlap_m) {
  for (const Quad* q : {&a, &b}) {
    for (size_t k = 0; k < 4; ++k) {
      const Eigen::Vector2d edge = (*q)[(k + 1) % 4] - (*q)[k];
      const Eigen::Vector2d axis(-edge.y(), edge.x());
      const double norm = axis.norm();
      if (norm == 0.0) continue;
      double a_lo = INFINITY, a_hi = -INFINITY, b_lo = INFINITY, b_hi = -INFINITY;
      for (const auto& p : a) {
        const double d = p.dot(axis) / norm;
        a_lo = std::min(a_lo, d);
        a_hi = std::max(a_hi, d);
      }
      for (const auto& p : b) {
        const double d = p.dot(axis) / norm;
        b_lo = std::min(b_lo, d);
        b_hi = std::max(b_hi, d);
      }
      if (std::min(a_hi, b_hi) - std::max(a_lo, b_lo) <= min_overlap_m) return false;
    }
  }
  return true;
}

Quad RectQuad(const Rect& r) {
  return {Eigen::Vector2d(r.min_x, r.min_z), Eigen::Vector2d(r.max_x, r.min_z),
          Eigen::Vector2d(r.max_x, r.max_z), Eigen::Vector2d(r.min_x, r.max_z)};
}

// Decks that share only an edge, up to this rounding, may coexist (bridges end to end).
constexpr double kTouchToleranceM = 1e-6;

}  // namespace

Bridge::Bridge(FeatureId id, const FeatureParams& params, Material resolved)
    : Feature(id),
      params_(params),
      resolved_material_(resolved),
      ux_(std::cos(params.direction_rad)),
      uz_(std::sin(params.direction_rad)) {}

Eigen::Vector2d Bridge::AtBridge(double along_m, double right_m) const {
  // Right of direction d is d - pi/2: (sin d, -cos d) = (uz, -ux).
  return {params_.x_m + along_m * ux_ + right_m * uz_, params_.z_m + along_m * uz_ - right_m * ux_};
}

BridgeCoords Bridge::ToBridge(double x_m, double z_m) const {
  const double dx = x_m - params_.x_m;
  const double dz = z_m - params_.z_m;
  return {dx * ux_ + dz * uz_, dx * uz_ - dz * ux_};
}

void Bridge::OnGroundChanged(const HeightGrid& ground) {
  auto at = [&](double along_m) {
    const Eigen::Vector2d p = AtBridge(along_m, 0.0);
    return ground.ElevationAt(p.x(), p.y());
  };
  ground_foot1_m_ = at(start_along_m());
  ground_joint1_m_ = at(0.0);
  ground_joint2_m_ = at(span_length_m());
  ground_foot2_m_ = at(end_along_m());
  ground_middle_m_ = at(span_length_m() / 2.0);
}

std::array<Eigen::Vector2d, 4> Bridge::DeckCorners() const {
  const double r = width_m() / 2.0;
  return {AtBridge(start_along_m(), r), AtBridge(end_along_m(), r), AtBridge(end_along_m(), -r),
          AtBridge(start_along_m(), -r)};
}

Rect Bridge::Bounds() const {
  const double r = width_m() / 2.0;
  const double h = kBridgeHotSpotLengthM / 2.0;
  Rect b{INFINITY, INFINITY, -INFINITY, -INFINITY};
  for (double a : {start_along_m() - h, end_along_m() + h}) {
    for (double s : {-r, r}) {
      const Eigen::Vector2d p = AtBridge(a, s);
      b = b.Union({p.x(), p.y(), p.x(), p.y()});
    }
  }
  return b;
}

bool Bridge::OverDeck(double x_m, double z_m) const {
  const BridgeCoords c = ToBridge(x_m, z_m);
  return std::abs(c.right_m) <= width_m() / 2.0 && c.along_m >= start_along_m() &&
         c.along_m <= end_along_m();
}

bool Bridge::Covers(double x_m, double z_m) const { return OverDeck(x_m, z_m); }

bool Bridge::MayCover(const Rect& rect) const {
  const double r = width_m() / 2.0;
  const double h = kBridgeHotSpotLengthM / 2.0;
  const Quad footprint = {AtBridge(start_along_m() - h, r), AtBridge(end_along_m() + h, r),
                          AtBridge(end_along_m() + h, -r), AtBridge(start_along_m() - h, -r)};
  // Conservative: touching counts.
  return QuadsOverlap(footprint, RectQuad(rect), -kTouchToleranceM);
}

bool Bridge::ConflictsWith(const Feature& other) const {
  const auto* b = dynamic_cast<const Bridge*>(&other);
  if (b == nullptr || b == this) return false;
  return QuadsOverlap(DeckCorners(), b->DeckCorners(), kTouchToleranceM);
}

double Bridge::IntactDeckAt(double a) const {
  const double top1 = ground_joint1_m_ + params_.height_m[0];
  const double top2 = ground_joint2_m_ + params_.height_m[1];
  if (a <= 0.0) {
    const double t = (a - start_along_m()) / ramp1_length_m();
    return ground_foot1_m_ + t * (top1 - ground_foot1_m_);
  }
  if (a <= span_length_m()) return top1 + a / span_length_m() * (top2 - top1);
  const double t = (a - span_length_m()) / ramp2_length_m();
  return top2 + t * (ground_foot2_m_ - top2);
}

std::optional<double> Bridge::DeckElevationAt(double x_m, double z_m) const {
  const BridgeCoords c = ToBridge(x_m, z_m);
  if (!(std::abs(c.right_m) <= width_m() / 2.0) || c.along_m < start_along_m() ||
      c.along_m > end_along_m()) {
    return std::nullopt;
  }
  if (destroyed() && c.along_m > 0.0 && c.along_m < span_length_m()) return std::nullopt;
  return IntactDeckAt(c.along_m);
}

BridgeHotSpot Bridge::HotSpotAt(double x_m, double z_m) const {
  const BridgeCoords c = ToBridge(x_m, z_m);
  if (!(std::abs(c.right_m) <= width_m() / 2.0)) return BridgeHotSpot::kNone;
  const double h = kBridgeHotSpotLengthM / 2.0;
  if (std::abs(c.along_m - start_along_m()) <= h) return BridgeHotSpot::kRamp1;
  if (std::abs(c.along_m - end_along_m()) <= h) return BridgeHotSpot::kRamp2;
  return BridgeHotSpot::kNone;
}

bool Bridge::InOuterHotSpot(double x_m, double z_m) const {
  const BridgeCoords c = ToBridge(x_m, z_m);
  if (!(std::abs(c.right_m) <= width_m() / 2.0)) return false;
  const double h = kBridgeHotSpotLengthM / 2.0;
  return (c.along_m < start_along_m() && c.along_m >= start_along_m() - h) ||
         (c.along_m > end_along_m() && c.along_m <= end_along_m() + h);
}

double Bridge::OntoDirectionRad(BridgeHotSpot spot) const {
  switch (spot) {
    case BridgeHotSpot::kRamp1:
      return params_.direction_rad;
    case BridgeHotSpot::kRamp2:
      return params_.direction_rad + std::numbers::pi;
    case BridgeHotSpot::kNone:
      break;
  }
  throw std::invalid_argument("OntoDirectionRad needs a hot spot, not kNone");
}

std::vector<DeckSection> Bridge::DeckProfile() const {
  std::vector<DeckSection> out;
  out.push_back({start_along_m(), ground_foot1_m_});
  out.push_back({0.0, IntactDeckAt(0.0)});
  if (destroyed()) {
    // The broken halves meet the ground at the span's middle: thesis IV.C's four extra points.
    out.push_back({span_length_m() / 2.0, ground_middle_m_});
    out.push_back({span_length_m() / 2.0, ground_middle_m_});
  }
  out.push_back({span_length_m(), IntactDeckAt(span_length_m())});
  out.push_back({end_along_m(), ground_foot2_m_});
  return out;
}

Result<std::unique_ptr<Feature>> MakeBridge(FeatureId id, const FeatureParams& params,
                                            const HeightGrid& ground) {
  Result<Material> resolved = CheckPlacementBasics(id, params, FeatureType::kBridge, ground);
  if (!resolved) return resolved.error();
  // The ground is sampled along the deck only once the whole footprint is known to be on it.
  std::unique_ptr<Bridge> bridge(new Bridge(id, params, resolved.value()));
  const Rect b = bridge->Bounds();
  if (!ground.Contains(b.min_x, b.min_z) || !ground.Contains(b.max_x, b.max_z)) {
    return Error{fmt::format(
        "bridge {}: deck and hot spots cover x [{}, {}] z [{}, {}] m, which leaves the terrain "
        "[0, {}] x [0, {}] m",
        id.ToString(), b.min_x, b.max_x, b.min_z, b.max_z, ground.size_x_m(), ground.size_z_m())};
  }
  bridge->OnGroundChanged(ground);
  return std::unique_ptr<Feature>(std::move(bridge));
}

}  // namespace dt
