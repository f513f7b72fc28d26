#include "render/camera.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include <fmt/format.h>
#include <Eigen/Geometry>

#include "render/image.h"

namespace dt {
namespace {

void CheckSize(int width_px, int height_px) {
  if (width_px < 1 || height_px < 1 || width_px > Image::kMaxSidePx ||
      height_px > Image::kMaxSidePx) {
    throw std::invalid_argument(fmt::format("camera image {} x {} px is outside 1..{}", width_px,
                                            height_px, Image::kMaxSidePx));
  }
}

bool Finite(const Eigen::Vector3d& v) { return v.allFinite(); }

// gluLookAt in a right-handed frame.
Eigen::Matrix4d LookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target,
                       const Eigen::Vector3d& up) {
  const Eigen::Vector3d f = (target - eye).normalized();
  const Eigen::Vector3d s = f.cross(up).normalized();
  const Eigen::Vector3d u = s.cross(f);
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.block<1, 3>(0, 0) = s.transpose();
  m.block<1, 3>(1, 0) = u.transpose();
  m.block<1, 3>(2, 0) = -f.transpose();
  m(0, 3) = -s.dot(eye);
  m(1, 3) = -u.dot(eye);
  m(2, 3) = f.dot(eye);
  return m;
}

}  // namespace

Camera Camera::Map(double center_x_m, double center_z_m, double metres_per_pixel, int width_px,
                   int height_px) {
  CheckSize(width_px, height_px);
  if (!std::isfinite(center_x_m) || !std::isfinite(center_z_m) ||
      !std::isfinite(metres_per_pixel) || metres_per_pixel <= 0.0) {
    throw std::invalid_argument(fmt::format(
        "map camera centre ({}, {}) m and {} m per pixel must be finite, with a positive scale",
        center_x_m, center_z_m, metres_per_pixel));
  }
  Camera c;
  c.kind_ = CameraKind::kMap;
  c.width_px_ = width_px;
  c.height_px_ = height_px;
  c.metres_per_pixel_ = metres_per_pixel;
  c.pixel_footprint_m_ = metres_per_pixel;
  c.center_x_m_ = center_x_m;
  c.center_z_m_ = center_z_m;
  // Eye coordinates: X = east, Y = north, looking down -Z from y = kMapDepthRangeM.
  Eigen::Matrix4d v = Eigen::Matrix4d::Zero();
  v(0, 0) = 1.0;
  v(0, 3) = -center_x_m;
  v(1, 2) = 1.0;
  v(1, 3) = -center_z_m;
  v(2, 1) = 1.0;
  v(2, 3) = -kMapDepthRangeM;
  v(3, 3) = 1.0;
  c.view_ = v;
  // glOrtho(-w/2, w/2, -h/2, h/2, 0, 2 * range).
  const double half_w = 0.5 * width_px * metres_per_pixel;
  const double half_h = 0.5 * height_px * metres_per_pixel;
  const double near_m = 0.0, far_m = 2.0 * kMapDepthRangeM;
  Eigen::Matrix4d p = Eigen::Matrix4d::Identity();
  p(0, 0) = 1.0 / half_w;
  p(1, 1) = 1.0 / half_h;
  p(2, 2) = -2.0 / (far_m - near_m);
  p(2, 3) = -(far_m + near_m) / (far_m - near_m);
  c.projection_ = p;
  return c;
}

Camera Camera::MapOf(const Rect& area, int width_px) {
  const double dx = area.max_x - area.min_x;
  const double dz = area.max_z - area.min_z;
  if (!(dx > 0.0) || !(dz > 0.0) || !std::isfinite(dx) || !std::isfinite(dz)) {
    throw std::invalid_argument(fmt::format("map area x [{}, {}] z [{}, {}] m is empty", area.min_x,
                                            area.max_x, area.min_z, area.max_z));
  }
  CheckSize(width_px, 1);
  const double mpp = dx / width_px;
  const double rows = std::ceil(dz / mpp - 1e-9);
  if (rows > Image::kMaxSidePx) {
    throw std::invalid_argument(
        fmt::format("map of {} x {} m at {} px wide needs {} rows", dx, dz, width_px, rows));
  }
  const int height_px = std::max(1, static_cast<int>(rows));
  // Keep the area's west and south edges on the image's left and bottom edges.
  return Map(area.min_x + 0.5 * width_px * mpp, area.min_z + 0.5 * height_px * mpp, mpp, width_px,
             height_px);
}

Camera Camera::MapFitting(const Rect& area, int longest_side_px) {
  const double dx = area.max_x - area.min_x;
  const double dz = area.max_z - area.min_z;
  if (!(dz > dx)) return MapOf(area, longest_side_px);  // also an empty or non-finite area
  CheckSize(longest_side_px, 1);
  const double width = std::max(1.0, std::round(longest_side_px * (dx / dz)));
  return MapOf(area, static_cast<int>(width));
}

Camera Camera::Perspective(const Eigen::Vector3d& eye, const Eigen::Vector3d& target,
                           double fov_y_rad, int width_px, int height_px, double near_m,
                           double far_m) {
  CheckSize(width_px, height_px);
  if (!Finite(eye) || !Finite(target) || (target - eye).norm() <= 0.0) {
    throw std::invalid_argument(fmt::format(
        "perspective eye ({}, {}, {}) and target ({}, {}, {}) m must be finite and distinct",
        eye.x(), eye.y(), eye.z(), target.x(), target.y(), target.z()));
  }
  if (!(fov_y_rad > 0.0 && fov_y_rad < std::numbers::pi) || !(near_m > 0.0) || !(far_m > near_m) ||
      !std::isfinite(far_m)) {
    throw std::invalid_argument(
        fmt::format("perspective fov {} rad must be in (0, pi) and 0 < near {} m < far {} m",
                    fov_y_rad, near_m, far_m));
  }
  Camera c;
  c.kind_ = CameraKind::kPerspective;
  c.width_px_ = width_px;
  c.height_px_ = height_px;
  c.pixel_footprint_m_ = 2.0 * (target - eye).norm() * std::tan(0.5 * fov_y_rad) / height_px;
  // The world frame (x east, y up, z north) is left-handed; OpenGL's is right-handed. Mirror z
  // first so the image is not mirrored: east stays right of north.
  Eigen::Matrix4d mirror = Eigen::Matrix4d::Identity();
  mirror(2, 2) = -1.0;
  const Eigen::Vector3d e(eye.x(), eye.y(), -eye.z());
  const Eigen::Vector3d t(target.x(), target.y(), -target.z());
  const Eigen::Vector3d dir = (t - e).normalized();
  // Looking (almost) straight up or down: use north as the image's up.
  Eigen::Vector3d up(0.0, 1.0, 0.0);
  if (std::abs(dir.y()) > 0.999) up = Eigen::Vector3d(0.0, 0.0, -1.0);
  c.view_ = LookAt(e, t, up) * mirror;
  const double f = 1.0 / std::tan(0.5 * fov_y_rad);
  const double aspect = static_cast<double>(width_px) / height_px;
  Eigen::Matrix4d p = Eigen::Matrix4d::Zero();
  p(0, 0) = f / aspect;
  p(1, 1) = f;
  p(2, 2) = (far_m + near_m) / (near_m - far_m);
  p(2, 3) = 2.0 * far_m * near_m / (near_m - far_m);
  p(3, 2) = -1.0;
  c.projection_ = p;
  return c;
}

Rect Camera::map_area() const {
  const double half_w = 0.5 * width_px_ * metres_per_pixel_;
  const double half_h = 0.5 * height_px_ * metres_per_pixel_;
  return {center_x_m_ - half_w, center_z_m_ - half_h, center_x_m_ + half_w, center_z_m_ + half_h};
}

std::optional<Eigen::Vector2d> Camera::WorldToPixel(const Eigen::Vector3d& world) const {
  const Eigen::Vector4d clip = projection_ * view_ * world.homogeneous();
  if (!(clip.w() > 0.0)) return std::nullopt;
  const double ndc_x = clip.x() / clip.w();
  const double ndc_y = clip.y() / clip.w();
  return Eigen::Vector2d((ndc_x + 1.0) * 0.5 * width_px_, (1.0 - ndc_y) * 0.5 * height_px_);
}

}  // namespace dt
