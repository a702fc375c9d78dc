// Blender's Musgrave Texture (Cycles 3.4), 1D to 4D: F. K. Musgrave's fractal sums of the
// Noise Texture's signed noise (fBM, multifractal, heterogeneous terrain, hybrid and ridged
// multifractal), octave for octave as Blender sums them, so the same inputs give Blender's
// heights.
#pragma once
#include "textures/noise.h"

namespace rdv {

enum class MusgraveType : uint8_t { Multifractal, RidgedMultifractal, HybridMultifractal, Fbm, HeteroTerrain };

struct MusgraveParams {
  MusgraveType type = MusgraveType::Fbm;
  float detail = 2;      // octaves, clamped to [0, 15]
  float dimension = 2;   // H: each octave's weight falls by lacunarity^-H
  float lacunarity = 2;  // frequency ratio of successive octaves
  float offset = 0;      // hetero terrain, hybrid and ridged
  float gain = 1;        // hybrid and ridged
};

// The node's Fac at q (the Vector and W inputs times Scale) in dims dimensions.
float musgrave_texture(const NoisePoint &q, int dims, MusgraveParams m);

}  // namespace rdv
