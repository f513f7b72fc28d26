// Camera: the top-down map and the perspective view, with the world-to-pixel mapping both use.
#pragma once

#include <optional>

#include <Eigen/Core>

#include "base/rect.h"

namespace dt {

enum class CameraKind : uint8_t { kMap, kPerspective };

// A camera fixes the image size and the matrices handed to OpenGL. WorldToPixel applies the same
// matrices on the CPU, so tests and overlays find where a world point lands in the picture.
// World points are (x east, y up, z north) in metres (docs/conventions.md).
class Camera {
 public:
  // Orthographic, looking straight down: north is up and east is right in the image, each pixel
  // is metres_per_pixel on both axes, and the image centre is (center_x_m, center_z_m).
  // Elevations in [-kMapDepthRangeM, kMapDepthRangeM] are drawn. Throws std::invalid_argument
  // for non-finite values, metres_per_pixel <= 0 or sizes outside 1..Image::kMaxSidePx.
  static Camera Map(double center_x_m, double center_z_m, double metres_per_pixel, int width_px,
                    int height_px);
  // The map that shows `area` exactly across width_px; the height follows the area's aspect
  // (rounded up). Throws as Map does, or for an empty area.
  static Camera MapOf(const Rect& area, int width_px);
  // The map that shows `area` with its longer side across longest_side_px (at least one pixel
  // wide): MapOf(area, longest_side_px) unless the area is taller than wide. Throws as MapOf.
  static Camera MapFitting(const Rect& area, int longest_side_px);
  // Perspective from `eye` looking at `target`, world up is +y (north is up when looking
  // straight down). fov_y_rad is the vertical field of view. Throws std::invalid_argument for
  // eye == target, fov outside (0, pi), near_m <= 0, far_m <= near_m, or bad sizes.
  static Camera Perspective(const Eigen::Vector3d& eye, const Eigen::Vector3d& target,
                            double fov_y_rad, int width_px, int height_px, double near_m = 1.0,
                            double far_m = 50000.0);

  static constexpr double kMapDepthRangeM = 20000.0;

  CameraKind kind() const { return kind_; }
  int width_px() const { return width_px_; }
  int height_px() const { return height_px_; }
  // Map cameras: ground metres per pixel. 0 for perspective cameras.
  double metres_per_pixel() const { return metres_per_pixel_; }
  // The length one pixel spans: everywhere for a map, at the target's distance for a
  // perspective view (nearer things get more pixels, farther ones fewer). The renderer samples
  // earthworks no finer than this.
  double pixel_footprint_m() const { return pixel_footprint_m_; }
  // Map cameras: the ground rectangle the image covers.
  Rect map_area() const;

  // Where `world` lands: (col, row) in pixels, continuous, row 0 at the top; pixel (c, r) covers
  // [c, c + 1) x [r, r + 1). nullopt if the point is behind a perspective eye. Points off the
  // image are returned too (outside [0, width) x [0, height)).
  std::optional<Eigen::Vector2d> WorldToPixel(const Eigen::Vector3d& world) const;

  // Column-major matrices for glLoadMatrixd: eye-to-clip and world-to-eye.
  const Eigen::Matrix4d& projection() const { return projection_; }
  const Eigen::Matrix4d& view() const { return view_; }

 private:
  Camera() = default;

  CameraKind kind_ = CameraKind::kMap;
  int width_px_ = 0;
  int height_px_ = 0;
  double metres_per_pixel_ = 0.0;
  double pixel_footprint_m_ = 0.0;
  double center_x_m_ = 0.0;
  double center_z_m_ = 0.0;
  Eigen::Matrix4d projection_ = Eigen::Matrix4d::Identity();
  Eigen::Matrix4d view_ = Eigen::Matrix4d::Identity();
};

}  // namespace dt
