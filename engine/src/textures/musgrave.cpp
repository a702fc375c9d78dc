#include "textures/musgrave.h"
#include <cmath>

namespace rdv {

namespace {

// Each sum runs over the whole octaves, then adds the fractional one's share (rmd), as
// Cycles does; ridged multifractal has no fractional octave.
struct Octaves {
  int whole;
  float fraction;
  explicit Octaves(float detail) : whole(int(detail)), fraction(detail - std::floor(detail)) {}
};

float fbm(NoisePoint p, int dims, float H, float lacunarity, Octaves o) {
  float value = 0, pwr = 1;
  const float pwHL = std::pow(lacunarity, -H);
  for (int i = 0; i < o.whole; ++i) {
    value += signed_noise(dims, p) * pwr;
    pwr *= pwHL;
    p = p * lacunarity;
  }
  if (o.fraction != 0.0f) value += o.fraction * signed_noise(dims, p) * pwr;
  return value;
}

float multifractal(NoisePoint p, int dims, float H, float lacunarity, Octaves o) {
  float value = 1, pwr = 1;
  const float pwHL = std::pow(lacunarity, -H);
  for (int i = 0; i < o.whole; ++i) {
    value *= pwr * signed_noise(dims, p) + 1.0f;
    pwr *= pwHL;
    p = p * lacunarity;
  }
  if (o.fraction != 0.0f) value *= o.fraction * pwr * signed_noise(dims, p) + 1.0f;
  return value;
}

float hetero_terrain(NoisePoint p, int dims, float H, float lacunarity, Octaves o, float offset) {
  const float pwHL = std::pow(lacunarity, -H);
  float pwr = pwHL;
  float value = offset + signed_noise(dims, p);  // the first octave unscaled
  p = p * lacunarity;
  for (int i = 1; i < o.whole; ++i) {
    value += (signed_noise(dims, p) + offset) * pwr * value;
    pwr *= pwHL;
    p = p * lacunarity;
  }
  if (o.fraction != 0.0f) value += o.fraction * ((signed_noise(dims, p) + offset) * pwr * value);
  return value;
}

float hybrid_multifractal(NoisePoint p, int dims, float H, float lacunarity, Octaves o, float offset, float gain) {
  const float pwHL = std::pow(lacunarity, -H);
  float pwr = 1, value = 0, weight = 1;
  for (int i = 0; weight > 0.001f && i < o.whole; ++i) {
    weight = std::min(weight, 1.0f);
    const float signal = (signed_noise(dims, p) + offset) * pwr;
    pwr *= pwHL;
    value += weight * signal;
    weight *= gain * signal;
    p = p * lacunarity;
  }
  if (o.fraction != 0.0f && weight > 0.001f) {
    weight = std::min(weight, 1.0f);
    value += o.fraction * weight * ((signed_noise(dims, p) + offset) * pwr);
  }
  return value;
}

float ridged_multifractal(NoisePoint p, int dims, float H, float lacunarity, Octaves o, float offset, float gain) {
  const float pwHL = std::pow(lacunarity, -H);
  float pwr = pwHL;
  float signal = offset - std::fabs(signed_noise(dims, p));
  signal *= signal;
  float value = signal;
  for (int i = 1; i < o.whole; ++i) {
    p = p * lacunarity;
    const float weight = clampf(signal * gain, 0.0f, 1.0f);
    signal = offset - std::fabs(signed_noise(dims, p));
    signal *= signal;
    signal *= weight;
    value += signal * pwr;
    pwr *= pwHL;
  }
  return value;
}

}  // namespace

float musgrave_texture(const NoisePoint &q, int dims, MusgraveParams m) {
  const float H = std::max(m.dimension, 1e-5f), lacunarity = std::max(m.lacunarity, 1e-5f);
  const Octaves o(clampf(m.detail, 0.0f, 15.0f));
  float fac = 0;
  switch (m.type) {
    case MusgraveType::Multifractal: fac = multifractal(q, dims, H, lacunarity, o); break;
    case MusgraveType::RidgedMultifractal: fac = ridged_multifractal(q, dims, H, lacunarity, o, m.offset, m.gain); break;
    case MusgraveType::HybridMultifractal: fac = hybrid_multifractal(q, dims, H, lacunarity, o, m.offset, m.gain); break;
    case MusgraveType::Fbm: fac = fbm(q, dims, H, lacunarity, o); break;
    case MusgraveType::HeteroTerrain: fac = hetero_terrain(q, dims, H, lacunarity, o, m.offset); break;
  }
  return std::isfinite(fac) ? fac : 0.0f;
}

}  // namespace rdv
