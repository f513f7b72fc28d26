#include "terrain/polyline_earthwork.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include <fmt/format.h>

#include "terrain/berm.h"

namespace dt {
namespace {

// The berm cross-section (berm.h): a crest kBermTopWidthFraction of the width, straight sides.
double BermSection(double a, double h, double w) {
  const double half = 0.5 * w;
  if (a > half) return Feature::kNotCovered;
  const double crest_half = 0.5 * kBermTopWidthFraction * w;
  if (a <= crest_half) return h;
  return h * (half - a) / (half - crest_half);
}

// True if the oriented rectangle (origin, unit direction u, along [s0, s1], across [-r, r])
// may meet the axis-aligned rectangle: a separating-axis test on the four axes.
bool OrientedMeetsRect(double ox, double oz, double ux, double uz, double s0, double s1, double r,
                       const Rect& rect) {
  const double cx = ox + ux * 0.5 * (s0 + s1), cz = oz + uz * 0.5 * (s0 + s1);
  const double half_len = 0.5 * (s1 - s0);
  const double nx = -uz, nz = ux;
  // Axes x and z: the oriented rectangle's extents.
  const double ex = std::abs(ux) * half_len + std::abs(nx) * r;
  const double ez = std::abs(uz) * half_len + std::abs(nz) * r;
  if (cx + ex < rect.min_x || cx - ex > rect.max_x) return false;
  if (cz + ez < rect.min_z || cz - ez > rect.max_z) return false;
  // Axes u and n: the rectangle's projection.
  const double rx = 0.5 * (rect.max_x - rect.min_x), rz = 0.5 * (rect.max_z - rect.min_z);
  const double mx = 0.5 * (rect.max_x + rect.min_x) - cx, mz = 0.5 * (rect.max_z + rect.min_z) - cz;
  if (std::abs(mx * ux + mz * uz) > half_len + rx * std::abs(ux) + rz * std::abs(uz)) return false;
  if (std::abs(mx * nx + mz * nz) > r + rx * std::abs(nx) + rz * std::abs(nz)) return false;
  return true;
}

}  // namespace

PolylineEarthwork::PolylineEarthwork(FeatureId id, FeatureParams params, Material resolved)
    : Feature(id),
      params_(std::move(params)),
      resolved_material_(resolved),
      is_ditch_(params_.type == FeatureType::kDitch) {
  if (is_ditch_) {
    side_run_m_ = params_.length_m[0];
    spoil_height_m_ = params_.height_m[1];
    spoil_width_m_ = params_.length_m[1];
  }
  const auto& pts = params_.points;
  for (size_t i = 0; i + 1 < pts.size(); ++i) {
    const FeaturePoint& a = pts[i];
    const FeaturePoint& b = pts[i + 1];
    const double dx = b.x_m - a.x_m, dz = b.z_m - a.z_m;
    const double len = std::sqrt(dx * dx + dz * dz);
    Segment s{a.x_m,      a.z_m,     dx / len,  dz / len, len, a.height_m,
              b.height_m, a.width_m, b.width_m, 0.0,      0.0};
    if (i == 0) s.start_run = EndRun(a.width_m);
    if (i + 2 == pts.size()) s.end_run = EndRun(b.width_m);
    segments_.push_back(s);
    length_m_ += len;
  }
  for (size_t i = 1; i < segments_.size(); ++i) {
    const Segment& s1 = segments_[i - 1];
    const Segment& s2 = segments_[i];
    const double cross = s1.ux * s2.uz - s1.uz * s2.ux;  // > 0: a left turn
    if (std::abs(cross) < 1e-12 && s1.ux * s2.ux + s1.uz * s2.uz > 0.0) continue;  // straight
    // Left normals; their sum points into the left side of the corner.
    const double n1x = -s1.uz, n1z = s1.ux, n2x = -s2.uz, n2z = s2.ux;
    const double sx = n1x + n2x, sz = n1z + n2z;
    const double len = std::sqrt(sx * sx + sz * sz);  // 2 cos(turn / 2), > 0.5 (turn <= 150 deg)
    const double outer_sign = cross > 0.0 ? -1.0 : 1.0;
    const FeaturePoint& v = pts[i];
    joints_.push_back({v.x_m, v.z_m, s1.ux, s1.uz, s2.ux, s2.uz, outer_sign * sx / len,
                       outer_sign * sz / len, 2.0 / len, outer_sign, v.height_m, v.width_m});
  }
  // The box of each segment's rectangle (end pieces included) and of each joint's reach.
  bool first = true;
  auto add = [&](const Rect& r) {
    bounds_ = first ? r : bounds_.Union(r);
    first = false;
  };
  for (const Segment& s : segments_) {
    const double r = std::max(Reach(s.w0), Reach(s.w1));
    const double s0 = -s.start_run, s1 = s.length_m + s.end_run;
    const double cx = s.ax + s.ux * 0.5 * (s0 + s1), cz = s.az + s.uz * 0.5 * (s0 + s1);
    const double half = 0.5 * (s1 - s0);
    const double ex = std::abs(s.ux) * half + std::abs(s.uz) * r;
    const double ez = std::abs(s.uz) * half + std::abs(s.ux) * r;
    add({cx - ex, cz - ez, cx + ex, cz + ez});
  }
  for (const Joint& j : joints_) add(Rect{j.vx, j.vz, j.vx, j.vz}.Expanded(Reach(j.w)));
}

double PolylineEarthwork::Reach(double w) const {
  return 0.5 * w + (is_ditch_ ? spoil_width_m_ : 0.0);
}

double PolylineEarthwork::EndRun(double w) const {
  return is_ditch_ ? side_run_m_ : 0.5 * (1.0 - kBermTopWidthFraction) * w;
}

double PolylineEarthwork::Section(double u, double h, double w) const {
  const double a = std::abs(u);
  if (!is_ditch_) return BermSection(a, h, w);
  const double half = 0.5 * w;
  if (a <= half - side_run_m_) return -h;
  if (a <= half) return -h * (half - a) / side_run_m_;
  // The spoil berm lies on the right (u < 0), its inner foot at the ditch's edge.
  if (spoil_height_m_ > 0.0 && u < 0.0) {
    return BermSection(std::abs(a - half - 0.5 * spoil_width_m_), spoil_height_m_, spoil_width_m_);
  }
  return kNotCovered;
}

double PolylineEarthwork::OffsetOrNotCovered(double x_m, double z_m) const {
  if (!bounds_.Contains(x_m, z_m)) return kNotCovered;  // also refuses NaN
  bool covered = false;
  double raise = 0.0, cut = 0.0;
  auto take = [&](double v) {
    if (v == kNotCovered) return;
    covered = true;
    raise = std::max(raise, v);
    cut = std::min(cut, v);
  };
  for (const Segment& s : segments_) {
    const double dx = x_m - s.ax, dz = z_m - s.az;
    const double along = dx * s.ux + dz * s.uz;
    if (along < -s.start_run || along > s.length_m + s.end_run) continue;
    const double across = dz * s.ux - dx * s.uz;  // positive to the left
    const double t = std::clamp(along / s.length_m, 0.0, 1.0);
    double v = Section(across, s.h0 + t * (s.h1 - s.h0), s.w0 + t * (s.w1 - s.w0));
    if (v == kNotCovered) continue;
    if (along < 0.0) v *= 1.0 + along / s.start_run;
    if (along > s.length_m) v *= 1.0 - (along - s.length_m) / s.end_run;
    take(v);
  }
  for (const Joint& j : joints_) {
    const double dx = x_m - j.vx, dz = z_m - j.vz;
    // The wedge outside the corner: past the end of the arriving segment and before the start
    // of the leaving one.
    if (!(dx * j.t1x + dz * j.t1z > 0.0) || !(dx * j.t2x + dz * j.t2z < 0.0)) continue;
    const double bevel = (dx * j.nbx + dz * j.nbz) * j.inverse_cos;
    take(Section(j.outer_sign * bevel, j.h, j.w));
  }
  if (!covered) return kNotCovered;
  return raise + cut;
}

bool PolylineEarthwork::MayCover(const Rect& rect) const {
  if (!bounds_.Intersects(rect)) return false;
  for (const Segment& s : segments_) {
    const double r = std::max(Reach(s.w0), Reach(s.w1));
    if (OrientedMeetsRect(s.ax, s.az, s.ux, s.uz, -s.start_run, s.length_m + s.end_run, r, rect)) {
      return true;
    }
  }
  for (const Joint& j : joints_) {
    // The bevelled wedge lies within the section's reach of the point.
    const Rect around = Rect{j.vx, j.vz, j.vx, j.vz}.Expanded(Reach(j.w));
    if (around.Intersects(rect)) return true;
  }
  return false;
}

Result<std::unique_ptr<Feature>> MakePolylineEarthwork(FeatureId id, const FeatureParams& params,
                                                       const HeightGrid& ground) {
  if (params.type != FeatureType::kDitch && params.type != FeatureType::kBermLine) {
    return Error{fmt::format("feature {}: a polyline earthwork maker given a {}", id.ToString(),
                             FeatureTypeName(params.type))};
  }
  Result<Material> resolved = CheckPlacementBasics(id, params, params.type, ground);
  if (!resolved) return resolved.error();
  return std::unique_ptr<Feature>(new PolylineEarthwork(id, params, resolved.value()));
}

std::vector<double> PolylineStations(const FeatureParams& params) {
  std::vector<double> out;
  double along = 0.0;
  for (size_t i = 0; i < params.points.size(); ++i) {
    if (i > 0) {
      const double dx = params.points[i].x_m - params.points[i - 1].x_m;
      const double dz = params.points[i].z_m - params.points[i - 1].z_m;
      along += std::sqrt(dx * dx + dz * dz);
    }
    out.push_back(along);
  }
  return out;
}

namespace {

// The point at distance `at` along the line, with the interpolated cross-section.
FeaturePoint PointAt(const FeatureParams& p, const std::vector<double>& stations, double at) {
  size_t i = 1;
  while (i + 1 < stations.size() && stations[i] < at) ++i;
  const FeaturePoint& a = p.points[i - 1];
  const FeaturePoint& b = p.points[i];
  const double t = std::clamp((at - stations[i - 1]) / (stations[i] - stations[i - 1]), 0.0, 1.0);
  return {a.x_m + t * (b.x_m - a.x_m), a.z_m + t * (b.z_m - a.z_m),
          a.height_m + t * (b.height_m - a.height_m), a.width_m + t * (b.width_m - a.width_m)};
}

// The part of the line between distances from and to, or nullopt if shorter than the smallest
// feature.
std::optional<FeatureParams> Piece(const FeatureParams& p, const std::vector<double>& stations,
                                   double from, double to) {
  if (!(to - from >= kMinFeatureSizeM)) return std::nullopt;
  FeatureParams out = p;
  out.points.clear();
  out.points.push_back(PointAt(p, stations, from));
  for (size_t i = 0; i < stations.size(); ++i) {
    // Points closer than the smallest feature to a cut are dropped, so no segment is too short.
    if (stations[i] > from + kMinFeatureSizeM && stations[i] < to - kMinFeatureSizeM) {
      out.points.push_back(p.points[i]);
    }
  }
  out.points.push_back(PointAt(p, stations, to));
  out.x_m = out.points.front().x_m;
  out.z_m = out.points.front().z_m;
  if (!ValidateFeatureParams(out)) return std::nullopt;  // a joint made too sharp: drop it
  return out;
}

}  // namespace

Result<std::vector<FeatureParams>> BreachPolyline(const FeatureParams& params, double gap_centre_m,
                                                  double gap_width_m) {
  if (params.type != FeatureType::kDitch && params.type != FeatureType::kBermLine) {
    return Error{fmt::format("cannot breach a {} as a polyline", FeatureTypeName(params.type))};
  }
  if (auto s = ValidateFeatureParams(params); !s) return s.error();
  const std::vector<double> stations = PolylineStations(params);
  const double length = stations.back();
  if (!(gap_centre_m >= 0.0 && gap_centre_m <= length)) {
    return Error{
        fmt::format("gap centre {} m is outside the line [0, {}] m", gap_centre_m, length)};
  }
  if (!std::isfinite(gap_width_m) || !(gap_width_m > 0.0)) {
    return Error{fmt::format("gap width {} m must be finite and > 0", gap_width_m)};
  }
  auto end_run = [&](double at) {
    const FeaturePoint q = PointAt(params, stations, std::clamp(at, 0.0, length));
    return params.type == FeatureType::kDitch ? params.length_m[0]
                                              : 0.5 * (1.0 - kBermTopWidthFraction) * q.width_m;
  };
  const double gap_start = gap_centre_m - 0.5 * gap_width_m;
  const double gap_end = gap_centre_m + 0.5 * gap_width_m;
  std::vector<FeatureParams> pieces;
  if (auto before = Piece(params, stations, 0.0, gap_start - end_run(gap_start))) {
    pieces.push_back(*before);
  }
  if (auto after = Piece(params, stations, gap_end + end_run(gap_end), length)) {
    pieces.push_back(*after);
  }
  return pieces;
}

}  // namespace dt
