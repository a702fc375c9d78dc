// What texture nodes ask of the scene: rays traced from a shading point, the Ambient
// Occlusion node's (textures/ambient_occlusion.h) and the Bevel node's (textures/bevel.h), and
// where the camera is (the Camera Data node). The scene answers (textures sit below the scene);
// Scene::shading_point hands it over in ShadingPoint::rays.
//
// Cycles draws such a node's directions at random at every evaluation. Here they are a
// stratified set shifted by a hash of the point's position (PointSampleSet): a fixed
// function of the point, since a path's contribution must be one function of its vertices
// (BDPT's strategies, MLT's mutations, docs/mlt.md); the same distribution per evaluation,
// so images agree with Cycles' in expectation.
#pragma once
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include "core/hash.h"
#include "core/math.h"

namespace rdv {

struct ShadingPoint;

// A surface of the shading point's own object met by a local ray (Bevel).
struct LocalHit {
  Vec3 p;   // world position
  Vec3 ng;  // geometric normal, world
  Vec3 ns;  // interpolated (smooth) normal, world
};

class TextureRays {
 public:
  virtual ~TextureRays() = default;
  // Whether a ray leaving the shading point along d meets a surface within tmax (only_local:
  // a surface of the point's own object; else any that shadow rays meet).
  virtual bool texture_ray_occluded(const ShadingPoint &sp, Vec3 d, float tmax, bool only_local) const = 0;
  // The surfaces of the shading point's own object along the segment o + t d, 0 <= t <= tmax,
  // whatever lies between (Cycles' local intersection). Returns how many there are; hits
  // receives min(that, max_hits) of them, a uniform choice by `seed` when there are more.
  virtual int texture_ray_local_hits(const ShadingPoint &sp, Vec3 o, Vec3 d, float tmax, LocalHit *hits,
                                     int max_hits, uint32_t seed) const = 0;
  // A world point in the space of the camera at its frame (x right, y up, looking down -z).
  virtual Vec3 texture_camera_space(Vec3 p) const = 0;
};

// `count` points in [0, 1)^2: a Hammersley set shifted (Cranley-Patterson) by a hash of a
// position, remixed by a per-node salt (0: none, the Ambient Occlusion node's) so two nodes at
// one point do not share their directions.
class PointSampleSet {
 public:
  PointSampleSet(Vec3 p, uint32_t salt, int count) : count_(count) {
    p = p + Vec3(0.0f);  // -0 is 0
    hash_ = hash3(std::bit_cast<uint32_t>(p.x), std::bit_cast<uint32_t>(p.y), std::bit_cast<uint32_t>(p.z));
    if (salt) hash_ = hash_u32(hash_ ^ salt);
    shift_u_ = u32_to_unit_float(hash_);
    shift_v_ = u32_to_unit_float(hash_u32(hash_ ^ 0x68e31da4u));
  }
  Vec2 operator[](int i) const {
    float u = (float(i) + 0.5f) / float(count_) + shift_u_, v = u32_to_unit_float(reverse_bits(uint32_t(i))) + shift_v_;
    u -= std::floor(u);
    v -= std::floor(v);
    return {std::min(u, 0.99999994f), std::min(v, 0.99999994f)};
  }
  uint32_t hash() const { return hash_; }  // for further choices at the point

 private:
  int count_;
  uint32_t hash_;
  float shift_u_, shift_v_;
};

}  // namespace rdv
