// HeightGrid: the bare ground, nx x nz elevation posts with a soil type per triangle.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "terrain/material.h"

namespace dt {

// Which triangle of a grid square. The diagonal runs from the top-left (x0, z1) to the
// bottom-right (x1, z0) corner (thesis fig. 2): kUpper holds (x1, z1), kLower holds (x0, z0).
enum class TriangleHalf : uint8_t { kLower = 0, kUpper = 1 };

// A grid square, by its lower-left post: square (i, j) spans [i, i+1] x [j, j+1] posts.
struct SquareIndex {
  int i = 0;  // along x
  int j = 0;  // along z
  bool operator==(const SquareIndex&) const = default;
};

// The most posts a grid may have along either side (docs/terrain.md "Grid size"): at most 4097 x
// 4097 posts, 40 km a side at 10 m spacing. A Terrain over it holds about 34 bytes per square
// (elevation, two soils, the square's feature list and bits), some 570 MB; the next power-of-two
// size, 8193, would need 2.3 GB per process. A rectangular grid within the bound takes less.
inline constexpr int kMaxPostsPerSide = 4097;

// posts_x posts along x (east) by posts_z along z (north). Post (i, j) stands at
// x = i * spacing_m, z = j * spacing_m; the grid covers [0, size_x_m()] x [0, size_z_m()].
// Elevations are y, up (docs/conventions.md).
class HeightGrid {
 public:
  // Flat ground. Throws std::invalid_argument, before allocating anything, unless posts_x and
  // posts_z are each in [2, kMaxPostsPerSide] and spacing_m is finite and > 0.
  HeightGrid(int posts_x, int posts_z, double spacing_m, float elevation_m = 0.0f,
             Material soil = Material::kGrass);
  // Posts given row by row along x: index = j * posts_x + i. Throws as above, on a size mismatch
  // or on a non-finite elevation.
  HeightGrid(int posts_x, int posts_z, double spacing_m, std::vector<float> posts_m,
             Material soil = Material::kGrass);
  // Square conveniences: posts_per_side posts along both x and z. A bad posts_per_side is named
  // so in the message.
  HeightGrid(int posts_per_side, double spacing_m, float elevation_m = 0.0f,
             Material soil = Material::kGrass);
  HeightGrid(int posts_per_side, double spacing_m, std::vector<float> posts_m,
             Material soil = Material::kGrass);

  int posts_x() const { return nx_; }
  int posts_z() const { return nz_; }
  int squares_x() const { return nx_ - 1; }
  int squares_z() const { return nz_ - 1; }
  double spacing_m() const { return spacing_m_; }
  double size_x_m() const { return spacing_m_ * (nx_ - 1); }
  double size_z_m() const { return spacing_m_ * (nz_ - 1); }
  bool is_square() const { return nx_ == nz_; }

  // True if (x, z) is finite and inside [0, size_x_m()] x [0, size_z_m()].
  bool Contains(double x_m, double z_m) const;

  float post(int i, int j) const { return posts_[Index(i, j)]; }
  // Throws std::out_of_range for a post outside the grid, std::invalid_argument for non-finite.
  void set_post(int i, int j, float elevation_m);
  const std::vector<float>& posts() const { return posts_; }

  // Bare-ground elevation by linear interpolation in the point's triangle.
  // Throws std::out_of_range if !Contains(x_m, z_m).
  double ElevationAt(double x_m, double z_m) const;
  // Unit upward normal of the point's triangle. Throws like ElevationAt.
  Eigen::Vector3d NormalAt(double x_m, double z_m) const;

  // Where a point lies: its square and local coordinates u, v in [0, 1] along x and z.
  struct Location {
    SquareIndex square;
    double u = 0.0;
    double v = 0.0;
  };
  // Throws std::out_of_range if !Contains(x_m, z_m).
  Location Locate(double x_m, double z_m) const;
  // Bare-ground elevation at a located point (one grid look-up serves square and height).
  double ElevationAt(const Location& at) const;

  // The square holding (x, z); points on the far edge belong to the last square.
  // Throws std::out_of_range if !Contains(x_m, z_m).
  SquareIndex SquareAt(double x_m, double z_m) const;
  TriangleHalf HalfAt(double x_m, double z_m) const;

  Material soil(SquareIndex square, TriangleHalf half) const {
    return soil_[SoilIndex(square, half)];
  }
  void set_soil(SquareIndex square, TriangleHalf half, Material soil);
  const std::vector<Material>& soils() const { return soil_; }

 private:
  // Returns posts_per_side; throws std::invalid_argument naming it unless it is in
  // [2, kMaxPostsPerSide].
  static int CheckPostsPerSide(int posts_per_side);
  size_t Index(int i, int j) const { return static_cast<size_t>(j) * nx_ + i; }
  size_t SoilIndex(SquareIndex s, TriangleHalf h) const {
    return (static_cast<size_t>(s.j) * (nx_ - 1) + s.i) * 2 + static_cast<size_t>(h);
  }

  int nx_;
  int nz_;
  double spacing_m_;
  std::vector<float> posts_;
  std::vector<Material> soil_;  // two per square: lower, upper
};

}  // namespace dt
