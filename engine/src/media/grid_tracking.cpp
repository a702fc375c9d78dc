// Unbiased estimators for grid media (Novak et al. 2018, "Monte Carlo methods for
// volumetric light transport simulation"): tentative collisions are sampled against
// the majorant sigma_bar = (majorant density) x max_c sigma_t,c of each cell of the
// majorant grid, which the ray crosses with a DDA (empty cells cost one step).
//
// Distance sampling is delta tracking in its null-collision form, made chromatic as
// spectral tracking (Kutz et al. 2017): at a tentative collision the path scatters
// with probability P_s = avg(w sigma_t) / (avg(w sigma_t) + avg(w sigma_n)) (w: the
// running RGB weight, sigma_n = sigma_bar - sigma_t) and the weight is multiplied by
// sigma_s / (sigma_bar P_s) or sigma_n / (sigma_bar (1 - P_s)). Every channel stays
// unbiased, and avg(w) never grows, so chromatic weights stay bounded. For one
// channel this is plain delta tracking with weight albedo.
// Transmittance is ratio tracking: the product of sigma_n / sigma_bar.
// Emission is gathered separately (media/emission_gather.h).
#include "media/medium.h"

namespace rdv {

namespace {

// A bound on the work per call: a pathological grid ends the walk (weight 0) instead
// of running away. Real scenes stay far below (tens of steps).
constexpr int kMaxTrackingSteps = 1 << 20;

struct GridRay {
  Vec3 o, d;  // in grid coordinates; t stays the world distance along the ray
};

GridRay to_grid(const DensityGrid &grid, Vec3 o, Vec3 d) {
  return {grid.world_to_grid().point(o), grid.world_to_grid().vector(d)};
}

float exponential(SampleRun &rng, float rate) { return -std::log(1.0f - rng.next_float()) / rate; }

// Russian roulette on a ratio-tracking weight once little is left: unbiased, and dense
// media end after a few steps instead of thousands. False: the walk ends (w = 0).
bool survives_roulette(Color &w, SampleRun &rng) {
  float m = max_component(w);
  if (m >= 0.1f) return true;
  if (m == 0 || rng.next_float() < 0.5f) { w = Color(0.0f); return false; }
  w *= 2.0f;
  return true;
}

}  // namespace

MediumSample Medium::delta_tracking(Vec3 o, Vec3 d, float tmax, SampleRun &rng) const {
  MediumSample s;
  s.t = tmax;
  const DensityGrid &g = *grid;
  const GridRay r = to_grid(g, o, d);
  const float sigma_t_max = max_component(sigma_t);
  const bool scatters = max_component(sigma_s) > 0;
  Color w(1.0f);
  int steps = 0;
  g.for_each_majorant_segment(r.o, r.d, tmax, [&](float t0, float t1, float majorant) {
    float sigma_bar = majorant * sigma_t_max;
    if (!(sigma_bar > 0)) return true;  // nothing here
    for (float t = t0 + exponential(rng, sigma_bar); t < t1; t += exponential(rng, sigma_bar)) {
      if (++steps > kMaxTrackingSteps) { w = Color(0.0f); return false; }
      float density = g.density(r.o + r.d * t);
      Color st = sigma_t * density, sn = vmax(Color(sigma_bar) - st, Color(0.0f));
      if (!scatters) {  // ratio tracking: always a null collision
        w *= sn * (1.0f / sigma_bar);
        if (!survives_roulette(w, rng)) return false;
        continue;
      }
      float w_avg = average(w), p_real = average(w * st), p_null = average(w * sn);
      if (!(p_real + p_null > 0)) { w = Color(0.0f); return false; }
      if (rng.next_float() * (p_real + p_null) < p_real) {
        s.scattered = true;
        s.t = t;
        w *= sigma_s * (density * w_avg / p_real);
        return false;
      }
      w *= sn * (w_avg / p_null);
    }
    return true;
  });
  s.weight = w;
  return s;
}

Color Medium::ratio_tracking(Vec3 o, Vec3 d, float distance, SampleRun &rng) const {
  const DensityGrid &g = *grid;
  const GridRay r = to_grid(g, o, d);
  const float sigma_t_max = max_component(sigma_t);
  Color tr(1.0f);
  int steps = 0;
  g.for_each_majorant_segment(r.o, r.d, distance, [&](float t0, float t1, float majorant) {
    float sigma_bar = majorant * sigma_t_max;
    if (!(sigma_bar > 0)) return true;
    for (float t = t0 + exponential(rng, sigma_bar); t < t1; t += exponential(rng, sigma_bar)) {
      if (++steps > kMaxTrackingSteps) { tr = Color(0.0f); return false; }
      Color st = sigma_t * g.density(r.o + r.d * t);
      tr *= vmax(Color(1.0f) - st * (1.0f / sigma_bar), Color(0.0f));
      if (!survives_roulette(tr, rng)) return false;
    }
    return true;
  });
  return tr;
}

}  // namespace rdv
