#include "terrain/height_grid.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include <fmt/format.h>

#include "base/demand.h"

namespace dt {
namespace {

// Checks the shape and returns the number of posts, so a constructor can check before it
// allocates.
size_t CheckShape(int posts_x, int posts_z, double spacing_m) {
  for (const auto& [name, n] : {std::pair{"posts_x", posts_x}, std::pair{"posts_z", posts_z}}) {
    if (n < 2 || n > kMaxGridPostsPerSide) {
      throw std::invalid_argument(
          fmt::format("{} = {} must be in [2, {}]", name, n, kMaxGridPostsPerSide));
    }
  }
  if (!std::isfinite(spacing_m) || spacing_m <= 0.0) {
    throw std::invalid_argument(fmt::format("spacing_m = {} must be finite and > 0", spacing_m));
  }
  return static_cast<size_t>(posts_x) * static_cast<size_t>(posts_z);
}

}  // namespace

int HeightGrid::CheckPostsPerSide(int posts_per_side) {
  if (posts_per_side < 2 || posts_per_side > kMaxGridPostsPerSide) {
    throw std::invalid_argument(fmt::format("posts_per_side = {} must be in [2, {}]",
                                            posts_per_side, kMaxGridPostsPerSide));
  }
  return posts_per_side;
}

HeightGrid::HeightGrid(int posts_per_side, double spacing_m, float elevation_m, Material soil)
    : HeightGrid(CheckPostsPerSide(posts_per_side), posts_per_side, spacing_m, elevation_m, soil) {}

HeightGrid::HeightGrid(int posts_per_side, double spacing_m, std::vector<float> posts_m,
                       Material soil)
    : HeightGrid(CheckPostsPerSide(posts_per_side), posts_per_side, spacing_m, std::move(posts_m),
                 soil) {}

HeightGrid::HeightGrid(int posts_x, int posts_z, double spacing_m, float elevation_m, Material soil)
    : HeightGrid(posts_x, posts_z, spacing_m,
                 std::vector<float>(CheckShape(posts_x, posts_z, spacing_m), elevation_m), soil) {}

HeightGrid::HeightGrid(int posts_x, int posts_z, double spacing_m, std::vector<float> posts_m,
                       Material soil)
    : nx_(posts_x), nz_(posts_z), spacing_m_(spacing_m), owned_posts_(std::move(posts_m)) {
  const size_t expected = CheckShape(posts_x, posts_z, spacing_m);
  if (owned_posts_.size() != expected) {
    throw std::invalid_argument(fmt::format("{} posts given for a {} x {} grid (expected {})",
                                            owned_posts_.size(), nx_, nz_, expected));
  }
  for (size_t k = 0; k < owned_posts_.size(); ++k) {
    if (!std::isfinite(owned_posts_[k])) {
      throw std::invalid_argument(
          fmt::format("post ({}, {}) is not finite ({})", k % nx_, k / nx_, owned_posts_[k]));
    }
  }
  if (!IsValidMaterial(static_cast<uint16_t>(soil)) || soil == Material::kFromGround) {
    throw std::invalid_argument(fmt::format("{} is not a soil", static_cast<uint16_t>(soil)));
  }
  owned_soil_.assign(soil_count(), soil);
  posts_ = owned_posts_.data();
  soil_ = owned_soil_.data();
}

GroundFileSource::~GroundFileSource() {
  if (fd >= 0) close(fd);
}

HeightGrid HeightGrid::Mapped(int posts_x, int posts_z, double spacing_m,
                              std::shared_ptr<const GroundFileSource> file) {
  CheckShape(posts_x, posts_z, spacing_m);
  DT_DEMAND(file != nullptr);
  HeightGrid g;
  g.nx_ = posts_x;
  g.nz_ = posts_z;
  g.spacing_m_ = spacing_m;
  if (file->posts_offset + g.post_count() * sizeof(float) > file->file_size ||
      file->soils_offset + g.soil_count() * sizeof(Material) > file->file_size) {
    throw std::invalid_argument(fmt::format(
        "a ground file of {} bytes cannot hold {} x {} posts at offset {} and soils at {}",
        file->file_size, posts_x, posts_z, file->posts_offset, file->soils_offset));
  }
  g.file_ = std::move(file);
  g.MapFile();
  return g;
}

void HeightGrid::MapFile() {
  Result<MappedMemory> m = MappedMemory::MapFilePrivate(file_->fd, file_->file_size);
  if (!m) throw std::runtime_error("mapping the ground file: " + m.error().message);
  mapping_ = std::move(m).value();
  posts_ = reinterpret_cast<float*>(mapping_.data() + file_->posts_offset);
  soil_ = reinterpret_cast<Material*>(mapping_.data() + file_->soils_offset);
}

HeightGrid::HeightGrid(const HeightGrid& other)
    : nx_(other.nx_),
      nz_(other.nz_),
      spacing_m_(other.spacing_m_),
      owned_posts_(other.owned_posts_),
      owned_soil_(other.owned_soil_),
      file_(other.file_) {
  if (!file_) {
    posts_ = owned_posts_.empty() ? nullptr : owned_posts_.data();
    soil_ = owned_soil_.empty() ? nullptr : owned_soil_.data();
    return;
  }
  MapFile();
  // Only the pages the other grid wrote differ from the file: copying just those keeps every
  // other page shared.
  constexpr size_t kChunk = 4096;
  const std::byte* from = other.mapping_.data();
  std::byte* to = mapping_.data();
  for (size_t at = 0; at < mapping_.size(); at += kChunk) {
    const size_t n = std::min(kChunk, mapping_.size() - at);
    if (std::memcmp(from + at, to + at, n) != 0) std::memcpy(to + at, from + at, n);
  }
}

HeightGrid& HeightGrid::operator=(const HeightGrid& other) {
  if (this != &other) *this = HeightGrid(other);
  return *this;
}

bool HeightGrid::Contains(double x_m, double z_m) const {
  // Written so that NaN fails every comparison.
  return x_m >= 0.0 && x_m <= size_x_m() && z_m >= 0.0 && z_m <= size_z_m();
}

void HeightGrid::set_post(int i, int j, float elevation_m) {
  if (i < 0 || j < 0 || i >= nx_ || j >= nz_) {
    throw std::out_of_range(
        fmt::format("post ({}, {}) is outside the {} x {} grid", i, j, nx_, nz_));
  }
  if (!std::isfinite(elevation_m)) {
    throw std::invalid_argument(
        fmt::format("post ({}, {}) elevation {} is not finite", i, j, elevation_m));
  }
  posts_[Index(i, j)] = elevation_m;
}

HeightGrid::Location HeightGrid::Locate(double x_m, double z_m) const {
  if (!Contains(x_m, z_m)) {
    throw std::out_of_range(
        fmt::format("position (x {}, z {}) m is outside the terrain [0, {}] x [0, {}] m", x_m, z_m,
                    size_x_m(), size_z_m()));
  }
  const double gx = x_m / spacing_m_;
  const double gz = z_m / spacing_m_;
  Location at;
  at.square.i = std::min(static_cast<int>(gx), nx_ - 2);
  at.square.j = std::min(static_cast<int>(gz), nz_ - 2);
  at.u = gx - at.square.i;
  at.v = gz - at.square.j;
  return at;
}

SquareIndex HeightGrid::SquareAt(double x_m, double z_m) const { return Locate(x_m, z_m).square; }

TriangleHalf HeightGrid::HalfAt(double x_m, double z_m) const {
  const Location at = Locate(x_m, z_m);
  return at.u + at.v >= 1.0 ? TriangleHalf::kUpper : TriangleHalf::kLower;
}

double HeightGrid::ElevationAt(double x_m, double z_m) const {
  return ElevationAt(Locate(x_m, z_m));
}

double HeightGrid::ElevationAt(const Location& at) const {
  const SquareIndex& s = at.square;
  const double u = at.u, v = at.v;
  const double h01 = post(s.i, s.j + 1);
  const double h10 = post(s.i + 1, s.j);
  if (u + v >= 1.0) {
    const double h11 = post(s.i + 1, s.j + 1);
    return h11 + (1.0 - u) * (h01 - h11) + (1.0 - v) * (h10 - h11);
  }
  const double h00 = post(s.i, s.j);
  return h00 + u * (h10 - h00) + v * (h01 - h00);
}

Eigen::Vector3d HeightGrid::NormalAt(double x_m, double z_m) const {
  const auto [s, u, v] = Locate(x_m, z_m);
  const double h01 = post(s.i, s.j + 1);
  const double h10 = post(s.i + 1, s.j);
  double dh_du, dh_dv;
  if (u + v >= 1.0) {
    const double h11 = post(s.i + 1, s.j + 1);
    dh_du = h11 - h01;
    dh_dv = h11 - h10;
  } else {
    const double h00 = post(s.i, s.j);
    dh_du = h10 - h00;
    dh_dv = h01 - h00;
  }
  // Surface y = h(x, z): the upward normal is (-dh/dx, 1, -dh/dz), normalised.
  return Eigen::Vector3d(-dh_du / spacing_m_, 1.0, -dh_dv / spacing_m_).normalized();
}

void HeightGrid::set_soil(SquareIndex square, TriangleHalf half, Material soil) {
  if (square.i < 0 || square.j < 0 || square.i >= nx_ - 1 || square.j >= nz_ - 1) {
    throw std::out_of_range(fmt::format("square ({}, {}) is outside the {} x {} squares", square.i,
                                        square.j, nx_ - 1, nz_ - 1));
  }
  if (!IsValidMaterial(static_cast<uint16_t>(soil)) || soil == Material::kFromGround) {
    throw std::invalid_argument(fmt::format("{} is not a soil", static_cast<uint16_t>(soil)));
  }
  soil_[SoilIndex(square, half)] = soil;
}

}  // namespace dt
