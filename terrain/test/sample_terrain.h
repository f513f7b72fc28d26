// SampleTerrain: a small terrain with every kind of feature, shared by the state tests, and the
// sloped ground the terrain tests build on.
#pragma once

#include <memory>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "terrain/random_terrain.h"
#include "terrain/terrain.h"

namespace dt::test {

// 101 x 101 posts, 2 m apart (200 m square), rising 0.25 m per metre toward +x and 0.1 toward +z,
// so "follows the ground" is visible.
inline HeightGrid SlopedGround() {
  const int n = 101;
  std::vector<float> posts(n * n);
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) posts[j * n + i] = static_cast<float>(0.5 * i + 0.2 * j);
  }
  return HeightGrid(n, 2.0, std::move(posts), Material::kGrass);
}

using Placement = std::pair<FeatureId, FeatureParams>;

// 9 x 9 posts, 10 m apart: an 80 m square with a few metres of relief.
inline HeightGrid SampleGround() {
  return MakeRandomTerrain(
      {.posts_x = 9, .posts_z = 9, .spacing_m = 10.0, .relief_m = 12.0, .seed = 5});
}

// Three craters (one with edited vertices), a berm and a bridge, from three nodes.
inline std::vector<Placement> SampleFeatures() {
  FeatureParams edited = FeatureParams::Crater(15.0, 65.0, 4.0, Material::kDirt);
  edited.vertex_edits = {{3, 1, 0.25}, {7, 2, -0.5}};
  return {
      {{1, 1, 1}, FeatureParams::Crater(10.0, 10.0, 3.0)},
      {{1, 1, 2}, edited},
      {{1, 2, 1}, FeatureParams::Crater(70.0, 12.0, 5.0, Material::kSand)},
      {{2, 1, 7}, FeatureParams::Berm(60.0, 65.0, 0.3, 12.0, 3.0, 1.5)},
      {{1, 1, 9}, FeatureParams::Bridge(30.0, 40.0, 0.0, 4.0, 10.0, 20.0, 10.0, 3.0, 3.5)},
  };
}

// The sample ground with the features added in the given order; a refused feature fails the test.
inline std::unique_ptr<Terrain> BuildSample(const std::vector<Placement>& features) {
  auto t = std::make_unique<Terrain>(SampleGround());
  for (const auto& [id, params] : features) {
    const Status s = t->Add(id, params);
    EXPECT_TRUE(s.ok()) << id.ToString() << ": " << (s.ok() ? "" : s.error().message);
  }
  return t;
}

}  // namespace dt::test
