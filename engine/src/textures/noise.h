// Blender's Noise Texture (Cycles 3.4), 1D to 4D: Perlin's gradient noise on the integer lattice with
// each corner's gradient picked by a hash of its coordinates (Bob Jenkins' lookup3, as Cycles),
// scaled by 0.982 to about [-1, 1]; its fractal sum of octaves mapped to [0, 1]; distortion and
// the Color output from the same noise at Cycles' fixed offsets. The same pattern as Blender's
// for the same coordinates (a bump from it then bends the normals Cycles bends).
#pragma once
#include "core/math.h"

namespace rdv {
// A point of the noise's one to four dimensions: 1D keeps its coordinate in w, 2D in p.x
// and p.y, 3D in p, 4D in p and w.
struct NoisePoint {
  Vec3 p;
  float w;
  NoisePoint operator+(const NoisePoint &o) const { return {p + o.p, w + o.w}; }
  NoisePoint operator*(float k) const { return {p * k, w * k}; }
};
// The node's Vector (p) and W inputs as a point of dims dimensions.
inline NoisePoint noise_point(Vec3 p, float w, int dims) {
  return {dims == 1 ? Vec3(0.0f) : dims == 2 ? Vec3(p.x, p.y, 0.0f) : p, dims == 1 || dims == 4 ? w : 0.0f};
}
// Signed Perlin noise of dims dimensions at q, scaled to about [-1, 1] by Cycles' factors
// (its snoise_1d .. snoise_4d).
float signed_noise(int dims, const NoisePoint &q);
// Signed Perlin noise at p, about [-1, 1] (Cycles' snoise_3d).
float signed_noise(Vec3 p);
// The fractal sum of detail + 1 octaves (the last one fractional), in about [0, 1].
float fractal_noise(Vec3 p, float detail, float roughness);
// The node's Fac (color == false) or Color output at p and w (the Vector and W inputs times
// Scale) in dims dimensions: 1 (w), 2 (p.x, p.y), 3 (p) or 4 (p, w).
Color noise_texture(Vec3 p, float w, int dims, float detail, float roughness, float distortion, bool color);
}  // namespace rdv
