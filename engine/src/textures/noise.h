// Blender's Noise Texture (Cycles 3.4), 1D to 4D: Perlin's gradient noise on the integer lattice with
// each corner's gradient picked by a hash of its coordinates (Bob Jenkins' lookup3, as Cycles),
// scaled by 0.982 to about [-1, 1]; its fractal sum of octaves mapped to [0, 1]; distortion and
// the Color output from the same noise at Cycles' fixed offsets. The same pattern as Blender's
// for the same coordinates (a bump from it then bends the normals Cycles bends).
#pragma once
#include "core/math.h"

namespace rdv {
// Signed Perlin noise at p, about [-1, 1] (Cycles' snoise_3d).
float signed_noise(Vec3 p);
// The fractal sum of detail + 1 octaves (the last one fractional), in about [0, 1].
float fractal_noise(Vec3 p, float detail, float roughness);
// The node's Fac (color == false) or Color output at p and w (the Vector and W inputs times
// Scale) in dims dimensions: 1 (w), 2 (p.x, p.y), 3 (p) or 4 (p, w).
Color noise_texture(Vec3 p, float w, int dims, float detail, float roughness, float distortion, bool color);
}  // namespace rdv
