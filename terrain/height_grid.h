// HeightGrid: the bare ground, nx x nz elevation posts with a soil type per triangle.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "base/mapped_memory.h"
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

// The most posts a side of ground every process makes for itself may have (docs/terrain.md "Grid
// size"): random ground and imported grids, at most 4097 x 4097 posts, 40 km a side at 10 m
// spacing, 8 bytes a post (elevation, two soils per square) held by each process.
inline constexpr int kMaxPostsPerSide = 4097;
// The most posts a side of any grid may have: an elevation file's ground beyond kMaxPostsPerSide
// or a terrain file's (ground_file) is read once per host into a ground cache file
// (terrain/ground_cache.h) that every process maps and shares (docs/real-ground.md "Large
// worlds"); 16385 posts, 16 km a side at 1 m.
inline constexpr int kMaxGridPostsPerSide = 16385;

// An open file holding a grid's posts (float, row by row) at posts_offset and its soils (u16, two
// per square) at soils_offset, both page aligned, as a ground cache file does. Closes the file
// when the last grid mapping it is gone.
struct GroundFileSource {
  int fd = -1;
  size_t file_size = 0;
  size_t posts_offset = 0;
  size_t soils_offset = 0;
  GroundFileSource() = default;
  GroundFileSource(const GroundFileSource&) = delete;
  GroundFileSource& operator=(const GroundFileSource&) = delete;
  ~GroundFileSource();
};

// posts_x posts along x (east) by posts_z along z (north). Post (i, j) stands at
// x = i * spacing_m, z = j * spacing_m; the grid covers [0, size_x_m()] x [0, size_z_m()].
// Elevations are y, up (docs/conventions.md).
class HeightGrid {
 public:
  // Flat ground. Throws std::invalid_argument, before allocating anything, unless posts_x and
  // posts_z are each in [2, kMaxGridPostsPerSide] and spacing_m is finite and > 0.
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
  // The posts and soils of a ground cache file, mapped privately: the pages stay shared with
  // every other process mapping the file until this grid writes one (set_post, set_soil), which
  // copies that page alone. The file's contents are trusted (the cache checked them); throws
  // std::invalid_argument for a bad shape or a file too short for it, std::runtime_error if the
  // mapping fails.
  static HeightGrid Mapped(int posts_x, int posts_z, double spacing_m,
                           std::shared_ptr<const GroundFileSource> file);

  // A copy of a mapped grid maps the file again and copies only the pages that differ from it.
  HeightGrid(const HeightGrid& other);
  HeightGrid& operator=(const HeightGrid& other);
  HeightGrid(HeightGrid&& other) noexcept = default;
  HeightGrid& operator=(HeightGrid&& other) noexcept = default;
  ~HeightGrid() = default;

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
  size_t post_count() const { return static_cast<size_t>(nx_) * static_cast<size_t>(nz_); }
  // Throws std::out_of_range for a post outside the grid, std::invalid_argument for non-finite.
  void set_post(int i, int j, float elevation_m);
  std::span<const float> posts() const { return {posts_, post_count()}; }
  // True if the posts and soils are a ground cache file's pages (Mapped).
  bool is_mapped() const { return file_ != nullptr; }

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
  std::span<const Material> soils() const { return {soil_, soil_count()}; }

 private:
  HeightGrid() = default;
  // Returns posts_per_side; throws std::invalid_argument naming it unless it is in
  // [2, kMaxGridPostsPerSide].
  static int CheckPostsPerSide(int posts_per_side);
  size_t Index(int i, int j) const { return static_cast<size_t>(j) * nx_ + i; }
  size_t SoilIndex(SquareIndex s, TriangleHalf h) const {
    return (static_cast<size_t>(s.j) * (nx_ - 1) + s.i) * 2 + static_cast<size_t>(h);
  }

  size_t soil_count() const {
    return static_cast<size_t>(nx_ - 1) * static_cast<size_t>(nz_ - 1) * 2;
  }
  // Maps file_ into mapping_ and points posts_ and soil_ into it.
  void MapFile();

  int nx_ = 0;
  int nz_ = 0;
  double spacing_m_ = 0.0;
  // Owned storage (file_ null) or the mapped file's: posts_ and soil_ point into one of them.
  std::vector<float> owned_posts_;
  std::vector<Material> owned_soil_;
  std::shared_ptr<const GroundFileSource> file_;
  MappedMemory mapping_;
  float* posts_ = nullptr;
  Material* soil_ = nullptr;  // two per square: lower, upper
};

}  // namespace dt
