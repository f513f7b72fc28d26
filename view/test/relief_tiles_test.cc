// Tests of the relief tiles: a tile's sample of the terrain, and its drawing on the tiles' own
// thread when a page asks, again only when a change touched it.
#include "view/relief_tiles.h"

#include <unistd.h>

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <future>

#include "render/png_io.h"

namespace dt {
namespace {

// 769 x 513 posts 4 m apart (3072 x 2048 m), rolling: tiles of 3072, 1536 and 768 m.
Terrain Rolling() {
  std::vector<float> posts;
  for (int j = 0; j < 513; ++j) {
    for (int i = 0; i < 769; ++i)
      posts.push_back(static_cast<float>(20.0 + 8.0 * std::sin(i * 0.05) * std::cos(j * 0.04)));
  }
  return Terrain(HeightGrid(769, 513, 4.0, std::move(posts), Material::kGrass));
}

Image Decode(const std::string& png) {
  const auto path = std::filesystem::temp_directory_path() /
                    ("dt_relief_tiles_test_" + std::to_string(::getpid()) + ".png");
  std::ofstream(path, std::ios::binary) << png;
  Result<Image> image = ReadPng(path.string());
  std::filesystem::remove(path);
  EXPECT_TRUE(image.ok()) << image.error().message;
  return image.ok() ? image.value() : Image(1, 1);
}

// A page's request on its own thread while this thread plays the view's loop.
ReliefTiles::Answer Ask(ReliefTiles& tiles, const Terrain& t, TileKey key) {
  auto page = std::async(std::launch::async, [&] { return tiles.Get(key, 10000); });
  while (page.wait_for(std::chrono::milliseconds(2)) != std::future_status::ready)
    tiles.Serve(t, ReliefPyramid::kTilePx);
  return page.get();
}

TEST(ReliefTileTest, ASampleReadsAboutATilesPostsAtEveryLevel) {
  Terrain t = Rolling();
  ASSERT_TRUE(t.Add({1, 1, 1}, FeatureParams::Crater(200.0, 200.0, 20.0)).ok());
  ASSERT_TRUE(t.Add({1, 1, 2}, FeatureParams::Crater(2000.0, 1000.0, 2.0)).ok());  // small
  const ReliefPyramid p(t.ground().size_x_m(), t.ground().size_z_m(), t.ground().spacing_m());
  ASSERT_EQ(p.levels(), 3);
  for (int level = 0; level < p.levels(); ++level) {
    const ReliefTileJob job = SampleReliefTile(t, p, {level, 0, 0}, 7, {0.0, 30.0});
    EXPECT_EQ(job.version, 7);
    EXPECT_EQ(job.ground.spacing_m(), p.SampleStride(level) * 4.0);
    // At most two samples a pixel (the stride is whole posts), plus the edges' posts.
    EXPECT_LE(job.ground.posts_x(), 2 * ReliefPyramid::kTilePx + 2);
    EXPECT_LE(job.ground.posts_z(), 2 * ReliefPyramid::kTilePx + 2);
    // The big crater is in every level's tile 0, moved into the tile's grid.
    ASSERT_FALSE(job.features.empty());
    EXPECT_EQ(job.features.front().first, (FeatureId{1, 1, 1}));
    EXPECT_DOUBLE_EQ(job.features.front().second.x_m, 200.0 - job.first_i * 4.0);
    // The post (first_i + stride, first_j) of the tile's grid is the terrain's.
    const int stride = p.SampleStride(level);
    EXPECT_EQ(job.ground.post(1, 0), t.ground().post(job.first_i + stride, job.first_j));
  }
  // The 2 m crater is narrower than a pixel of level 0 (12 m) and left out there.
  const ReliefTileJob coarse = SampleReliefTile(t, p, {0, 0, 0}, 1, {0.0, 30.0});
  EXPECT_EQ(coarse.features.size(), 1u);
  const ReliefTileJob fine = SampleReliefTile(t, p, {2, 2, 1}, 1, {0.0, 30.0});
  ASSERT_EQ(fine.features.size(), 1u);
  EXPECT_EQ(fine.features.front().first, (FeatureId{1, 1, 2}));
  EXPECT_THROW((void)SampleReliefTile(t, p, {3, 0, 0}, 1, {0.0, 30.0}), std::invalid_argument);
}

TEST(ReliefTilesTest, ATileIsDrawnWhenAskedAndAgainOnlyWhenAChangeTouchedIt) {
  Terrain t = Rolling();
  ReliefTiles tiles(t.ground());
  (void)tiles.Track(t);
  const TileKey near{2, 0, 0}, far{2, 3, 2};
  const ReliefTiles::Answer first = Ask(tiles, t, near);
  ASSERT_EQ(first.status, 200) << first.why;
  const Image before = Decode(*first.png);
  EXPECT_EQ(before.width(), ReliefPyramid::kTilePx);
  EXPECT_EQ(before.height(), ReliefPyramid::kTilePx);
  EXPECT_EQ(tiles.rendered(), 1u);
  ASSERT_EQ(Ask(tiles, t, far).status, 200);
  EXPECT_EQ(tiles.rendered(), 2u);
  // Asked again unchanged: from the cache, not drawn again.
  ASSERT_EQ(Ask(tiles, t, near).status, 200);
  EXPECT_EQ(tiles.rendered(), 2u);
  EXPECT_GT(tiles.cache_bytes(), 0u);

  // A crater at (200, 200) m: tile 2/0/0 (0..768 m, 3 m a pixel) is drawn again and shows it;
  // tile 2/3/2 is not.
  ASSERT_TRUE(t.Add({1, 1, 1}, FeatureParams::DeepCrater(200.0, 200.0, 30.0, 6.0)).ok());
  ASSERT_FALSE(tiles.Track(t).is_null());
  const ReliefTiles::Answer again = Ask(tiles, t, near);
  ASSERT_EQ(again.status, 200) << again.why;
  EXPECT_EQ(tiles.rendered(), 3u);
  const Image after = Decode(*again.png);
  const int col = static_cast<int>(200.0 / 3.0), row = static_cast<int>((768.0 - 200.0) / 3.0);
  int changed_in = 0, changed_out = 0;
  for (int r = 0; r < after.height(); ++r) {
    for (int c = 0; c < after.width(); ++c) {
      if (after.at(c, r) == before.at(c, r)) continue;
      const double d =
          std::hypot(c - col, r - row) * 3.0;  // metres from the centre; rim within 2 r
      (d < 60.0 ? changed_in : changed_out) += 1;
    }
  }
  EXPECT_GT(changed_in, 100);  // the crater, 60 m across: about 300 pixels
  EXPECT_EQ(changed_out, 0);
  ASSERT_EQ(Ask(tiles, t, far).status, 200);
  EXPECT_EQ(tiles.rendered(), 3u);
}

// A page waiting for a tile nobody will draw (no loop serves it) is answered 503 when the tiles
// stop, not after its minute: the web server's stop is not held by it.
TEST(ReliefTilesTest, StopAnswersAWaitingPageAtOnce) {
  Terrain t = Rolling();
  ReliefTiles tiles(t.ground());
  (void)tiles.Track(t);
  auto page = std::async(std::launch::async, [&] { return tiles.Get({0, 0, 0}, 60000); });
  tiles.Stop();
  ASSERT_EQ(page.wait_for(std::chrono::seconds(10)), std::future_status::ready);
  EXPECT_EQ(page.get().status, 503);
  EXPECT_EQ(tiles.Get({0, 0, 0}, 60000).status, 503);
}

}  // namespace
}  // namespace dt
