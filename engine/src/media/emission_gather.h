// Gathering the emission of a medium along a ray segment: the radiance
//     integral over [0, tmax) of T(0, t) e(o + t d) dt
// that the segment sends back to its origin, for camera paths.
//
// A volume light (Medium::light >= 0) is also sampled by next-event estimation and by
// light subpaths, so each gathered point needs its own MIS weight. It is gathered at
// points every `emission_step` along the ray with one random offset (Pauly et al.'s
// random-offset quadrature, unbiased for the integral), with the transmittance to each
// point estimated piece by piece (ratio tracking for grids, unbiased; closed form for
// homogeneous media). Those points form a point process of density 1 / emission_step
// per unit length: that is the density the MIS weights compare with the light's (see
// integrators). f(x, contribution, rate) receives each point, its contribution
// (T e step) and that rate.
// Any other emissive medium (the world's fog) is integrated in closed form and
// reported once with rate 0: no other strategy samples it.
#pragma once
#include "media/medium.h"

namespace rdv {

template <class F>
void gather_emission(const Medium &m, Vec3 o, Vec3 d, float tmax, SampleRun &rng, F &&f) {
  if (m.light < 0) {
    if (m.is_heterogeneous()) return;  // grid media are always inside meshes: volume lights
    Color e = m.uniform_emission(), tr = m.transmittance(tmax), sum;
    for (int c = 0; c < 3; ++c)
      sum[c] = m.sigma_t[c] > 0 ? e[c] * (1.0f - tr[c]) / m.sigma_t[c] : (e[c] > 0 ? e[c] * tmax : 0.0f);
    if (!is_black(sum) && is_finite(sum)) f(o, sum, 0.0f);
    return;
  }
  // The part of the ray inside the light's bounds: the medium emits nowhere else.
  Vec3 lo = m.light_lo, hi = m.light_hi;
  float a = 0, b = tmax;
  for (int axis = 0; axis < 3; ++axis) {
    float inv = 1.0f / d[axis];
    float t0 = (lo[axis] - o[axis]) * inv, t1 = (hi[axis] - o[axis]) * inv;
    if (t0 > t1) std::swap(t0, t1);
    if (std::isnan(t0) || std::isnan(t1)) {  // parallel to the slab
      if (o[axis] < lo[axis] || o[axis] > hi[axis]) return;
      continue;
    }
    a = std::max(a, t0);
    b = std::min(b, t1);
  }
  if (!(b > a)) return;
  const float step = m.emission_step, rate = 1.0f / step;
  constexpr int kMaxPoints = 1 << 16;
  if ((b - a) * rate > kMaxPoints) return;  // a degenerate (unbounded) segment: nothing sane to gather
  Color tr(1.0f);
  float t_prev = 0;
  for (float t = a + rng.next_float() * step; t < b; t += step) {
    tr *= m.transmittance(o + d * t_prev, d, t - t_prev, rng);
    t_prev = t;
    if (is_black(tr)) return;
    Vec3 x = o + d * t;
    Color e = m.emission_at(x);
    if (!is_black(e)) f(x, tr * e * step, rate);
  }
}

}  // namespace rdv
