// The relative target's importance map (integrators/mlt/importance_map.h): the weight of
// a block is the image mean over the block's luminance, never above 1; a block whose own
// pilot hits are too few takes its estimate from the smallest enclosing square that has
// enough. Exact arithmetic on constructed pilots: no randomness.
#include <gtest/gtest.h>
#include "integrators/mlt/importance_map.h"

namespace test_importance_map {

using rdv::Vec2;
using rdv::mlt::ImportanceMap;

namespace {

constexpr int kW = 8, kH = 8;  // blocks
constexpr float kPixels = ImportanceMap::kBlock * ImportanceMap::kBlock;

Vec2 centre_of(int bx, int by) {
  return {(bx + 0.5f) * ImportanceMap::kBlock, (by + 0.5f) * ImportanceMap::kBlock};
}

}  // namespace

TEST(ImportanceMap, EvenImageWeighsOneEverywhere) {
  std::vector<float> lum(kW * kH, 2.0f * kPixels), hits(kW * kH, 100.0f);
  ImportanceMap map(lum, hits, kW, kH, {0, 0}, 1.0);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) EXPECT_FLOAT_EQ(map.weight(centre_of(x, y)), 1.0f);
  EXPECT_EQ(map.relative_share(), 0.0f);
}

TEST(ImportanceMap, BlocksBrighterThanTheMeanFollowRelativeError) {
  // One block 64x brighter than the other 63 (each of luminance 1 per pixel).
  std::vector<float> lum(kW * kH, kPixels), hits(kW * kH, 100.0f);
  lum[3 * kW + 5] = 64 * kPixels;
  ImportanceMap map(lum, hits, kW, kH, {0, 0}, 1.0);
  const float mean = (63.0f + 64.0f) / 64.0f;
  EXPECT_FLOAT_EQ(map.weight(centre_of(5, 3)), mean / 64.0f);
  EXPECT_FLOAT_EQ(map.weight(centre_of(0, 0)), 1.0f);  // below the mean: the luminance target
  EXPECT_FLOAT_EQ(map.relative_share(), 1.0f / 64.0f);
  // Positions past the edge take the edge block's weight.
  EXPECT_FLOAT_EQ(map.weight({-3.0f, -3.0f}), 1.0f);
  EXPECT_FLOAT_EQ(map.weight({1e6f, 1e6f}), 1.0f);
}

TEST(ImportanceMap, SparseHitsTakeTheEnclosingSquaresEstimate) {
  // Light is rare: each block has 1 hit, except one block of 4 x 4 (blocks 4..7 in both
  // axes) that is much brighter. A block alone has too few hits, so each takes the
  // mean of the smallest square that has kMinHits (16): the 4 x 4 quadrant.
  std::vector<float> lum(kW * kH, kPixels), hits(kW * kH, 1.0f);
  lum[6 * kW + 6] = 1601 * kPixels;  // a single noisy hit in the bright quadrant
  ImportanceMap map(lum, hits, kW, kH, {0, 0}, 1.0);
  // The bright quadrant's mean: (15 + 1601) / 16 = 101 per pixel; the others 1.
  const float mean = (48 * 1.0f + 16 * 101.0f) / 64.0f;
  for (int y = 4; y < 8; ++y)
    for (int x = 4; x < 8; ++x) EXPECT_FLOAT_EQ(map.weight(centre_of(x, y)), mean / 101.0f) << x << " " << y;
  EXPECT_FLOAT_EQ(map.weight(centre_of(0, 0)), 1.0f);
  EXPECT_FLOAT_EQ(map.weight(centre_of(7, 0)), 1.0f);
}

TEST(ImportanceMap, NoLightAtAllGivesFiniteEvenWeights) {
  std::vector<float> lum(kW * kH, 0.0f), hits(kW * kH, 0.0f);
  ImportanceMap map(lum, hits, kW, kH, {0, 0}, 1.0);
  EXPECT_FLOAT_EQ(map.weight(centre_of(2, 2)), 1.0f);
}

}  // namespace test_importance_map
