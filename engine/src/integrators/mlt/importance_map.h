// What a Metropolis chain targets, per image position (Hoberock and Hart 2010,
// "Arbitrary importance functions for Metropolis light transport"). The luminance target
// puts the mutations where the image is bright: a small bright region (a lit room seen
// through a door gap) takes most of them while the dim rest, where the error of the
// image is, starves. The relative target divides each splat's luminance by a coarse
// estimate of the image there, from a pilot of independent samples, but never by less
// than the image's mean: regions brighter than the mean get mutations in proportion to
// their relative error, the rest stay in proportion to luminance. The estimator stays
// unbiased for any positive target: splats are weighted by 1 / target and the image is
// scaled by b, the target's integral, which the bootstrap measures with the same map.
#pragma once
#include <algorithm>
#include <vector>
#include "core/math.h"

namespace rdv::mlt {

class ImportanceMap {
 public:
  // Pixels per block side of the finest level. A block's estimate comes from the
  // smallest square of blocks around it (2, 4, 8, ... pixels wide) in which the pilot
  // found light kMinHits times, so the map is sharp where light is common (a lit room
  // seen through a gap) and smooth where the pilot's hits are rare (a room lit through
  // a slit), instead of following its noise.
  static constexpr int kBlock = 2;
  static constexpr float kMinHits = 16;

  ImportanceMap() = default;  // empty: the luminance target
  // From the pilot's luminance summed per block and its light-carrying splats per block
  // (blocks_x x blocks_y, row-major, block (0, 0) at `origin` in raster space) over
  // `samples` samples, each of whose splats estimates the whole image.
  ImportanceMap(const std::vector<float> &block_luminance, const std::vector<float> &block_hits, int blocks_x,
                int blocks_y, Vec2 origin, double samples);

  // The block a raster position falls in (positions past the edge: the edge block).
  static size_t block_of(Vec2 raster, Vec2 origin, int blocks_x, int blocks_y) {
    int bx = std::clamp(int((raster.x - origin.x) * (1.0f / kBlock)), 0, blocks_x - 1);
    int by = std::clamp(int((raster.y - origin.y) * (1.0f / kBlock)), 0, blocks_y - 1);
    return size_t(by) * size_t(blocks_x) + size_t(bx);
  }

  bool empty() const { return weights_.empty(); }
  // 1 / importance at a raster position.
  float weight(Vec2 raster) const { return weights_[block_of(raster, origin_, blocks_x_, blocks_y_)]; }
  // Share of the blocks brighter than the image's mean (followed by relative error).
  float relative_share() const { return relative_share_; }

 private:
  std::vector<float> weights_;
  int blocks_x_ = 0, blocks_y_ = 0;
  Vec2 origin_{0, 0};
  float relative_share_ = 0;
};

}  // namespace rdv::mlt
