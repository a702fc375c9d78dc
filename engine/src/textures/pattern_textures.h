// Blender's smaller procedural textures (Cycles 3.4), each as Blender computes it so a
// material shows Blender's pattern: Wave (bands or rings, optionally distorted by the
// Noise Texture's fractal noise), Magic (nested sines), Brick (rows of bricks, each tinted
// by an integer hash) and White Noise (a hash of the coordinates).
#pragma once
#include "core/math.h"

namespace rdv {

enum class WaveType : uint8_t { Bands, Rings };
enum class WaveProfile : uint8_t { Sine, Saw, Triangle };
struct WaveParams {
  WaveType type = WaveType::Bands;
  uint8_t direction = 0;  // bands: X, Y, Z, diagonal; rings: X, Y, Z, spherical
  WaveProfile profile = WaveProfile::Sine;
  float distortion = 0, detail = 2, detail_scale = 1, detail_roughness = 0.5f, phase = 0;
};
// The Fac at p (the Vector input times Scale), in [0, 1].
float wave_texture(Vec3 p, const WaveParams &w);

// The Color at p (the Vector input), of `depth` nested turns (0..10); Fac is its average.
Color magic_texture(Vec3 p, float scale, int depth, float distortion);

struct BrickParams {
  float mortar_size = 0.02f, mortar_smooth = 0, bias = 0, brick_width = 0.5f, row_height = 0.25f;
  float offset = 0.5f, squash = 1;   // every offset_frequency-th row shifted, every squash_frequency-th squashed
  int offset_frequency = 2, squash_frequency = 2;
};
// At p (the Vector input times Scale): the brick's tint in [0, 1] (mixes Color1 to Color2)
// and the mortar's weight (1 in the mortar).
struct BrickSample { float tint, mortar; };
BrickSample brick_texture(Vec3 p, const BrickParams &b);

// White Noise's Value (color false: grey) or Color at p and w in dims dimensions.
Color white_noise_texture(Vec3 p, float w, int dims, bool color);

}  // namespace rdv
