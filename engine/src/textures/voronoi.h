// Blender's Voronoi Texture (Cycles 3.4), 1D to 4D: one jittered feature point per unit
// cell (Worley), its position and colour from the cell's hash (textures/hash.h), so cells
// have Blender's shapes and colours. Features F1, F2, Smooth F1, Distance to Edge and
// N-Sphere Radius; Euclidean, Manhattan, Chebychev and Minkowski distances.
#pragma once
#include "core/math.h"

namespace rdv {

enum class VoronoiFeature : uint8_t { F1, F2, SmoothF1, DistanceToEdge, NSphereRadius };
enum class VoronoiMetric : uint8_t { Euclidean, Manhattan, Chebychev, Minkowski };

struct VoronoiParams {
  VoronoiFeature feature = VoronoiFeature::F1;
  VoronoiMetric metric = VoronoiMetric::Euclidean;
  float scale = 5, smoothness = 1, exponent = 0.5f, randomness = 1;
};

// The node's five outputs at the Vector (p) and W inputs.
struct VoronoiResult {
  float distance = 0;
  Color color{0.0f};
  Vec3 position{0.0f};
  float w = 0;
  float radius = 0;
};

VoronoiResult voronoi_texture(Vec3 p, float w, int dims, VoronoiParams v);

}  // namespace rdv
