// Random-offset ray marching (Pauly, Kollig & Keller 2000, section 4): the part of the
// ray inside the grid box is cut into equal steps of about `step_size`; each step's
// extinction is taken at the same random offset within every step, so the optical
// depth is a quadrature that is deterministic along the ray but decorrelated between
// rays (no banding). It is fast and approximate: the density is treated as constant
// over each step, so results are biased where it changes within a step (use tracking
// for reference images). Distances are sampled by inverting the marched optical depth
// of one channel chosen uniformly, weighted with the one-sample MIS over channels, as
// in the homogeneous case. Emission is gathered separately (media/emission_gather.h).
#include "media/medium.h"

namespace rdv {

namespace {

constexpr int kMaxMarchingSteps = 1 << 16;

// Calls f(a, h, density) for each step [a, a + h] of the ray inside the grid box up
// to tmax, with the density at the step's random offset; f returns false to stop.
// Returns the box exit (or 0 if the ray misses it).
template <class F>
float march(const DensityGrid &g, Vec3 o, Vec3 d, float tmax, float step_size, SampleRun &rng, float &t_enter, F &&f) {
  Vec3 go = g.world_to_grid().point(o), gd = g.world_to_grid().vector(d);
  float t_exit;
  if (!g.clip(go, gd, tmax, t_enter, t_exit)) { t_enter = t_exit = 0; return 0; }
  float length = t_exit - t_enter;
  int n = int(std::min(std::ceil(length / step_size), float(kMaxMarchingSteps)));
  n = std::max(n, 1);
  float h = length / n, offset = rng.next_float();
  for (int k = 0; k < n; ++k) {
    float a = t_enter + k * h;
    if (!f(a, h, g.density(go + gd * (a + offset * h)))) break;
  }
  return t_exit;
}

Color exp_neg(Color tau) { return {std::exp(-tau.x), std::exp(-tau.y), std::exp(-tau.z)}; }

}  // namespace

MediumSample Medium::ray_marched_distance(Vec3 o, Vec3 d, float tmax, SampleRun &rng) const {
  MediumSample s;
  s.t = tmax;
  const bool scatters = max_component(sigma_s) > 0;
  int channel = std::min(int(rng.next_float() * 3.0f), 2);
  float target = -std::log(1.0f - rng.next_float());  // optical depth of the event
  Color tau(0.0f);
  float t_enter;
  march(*grid, o, d, tmax, step_size, rng, t_enter, [&](float a, float h, float density) {
    Color st = sigma_t * density;
    if (scatters && !s.scattered && st[channel] > 0 && tau[channel] + st[channel] * h >= target) {
      float t = a + (target - tau[channel]) / st[channel];
      Color tr = exp_neg(tau + st * (t - a));
      float pdf = average(st * tr);  // the marched distance densities of the channels
      if (pdf > 0) {
        s.scattered = true;
        s.t = t;
        s.weight = sigma_s * density * tr / pdf;
      }
      return false;
    }
    tau += st * h;
    return true;
  });
  if (!s.scattered) {
    Color tr = exp_neg(tau);
    float p_pass = average(tr);
    s.weight = !scatters ? tr : p_pass > 0 ? tr / p_pass : Color(0.0f);
  }
  return s;
}

Color Medium::ray_marched_transmittance(Vec3 o, Vec3 d, float distance, SampleRun &rng) const {
  Color tau(0.0f);
  float t_enter;
  march(*grid, o, d, distance, step_size, rng, t_enter, [&](float, float h, float density) {
    tau += sigma_t * (density * h);
    return true;
  });
  return exp_neg(tau);
}

}  // namespace rdv
