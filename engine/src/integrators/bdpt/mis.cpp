// Multiple importance sampling over every strategy that could have made the path
// (Veach 1997, sec. 10.2; pbrt-v3's MISWeight), with the power heuristic. The weight
// is 1 / sum_i (p_i / p_s)^2, built from running products of reverse/forward density
// ratios along each subpath, so no product of densities ever overflows.
#include "integrators/bdpt/bdpt.h"

namespace rdv::bdpt {

float Bdpt::infinite_light_density(Vec3 dir) const {
  const Distribution1D &dist = scene_.light_distribution();
  float pdf = 0;
  for (uint32_t li : scene_.infinite_lights()) pdf += dist.pmf(li) * light_pdf(scene_.lights()[li], Vec3(0.0f), dir, kInf);
  return pdf;
}

// The densities of light vertex lv as the start of a light subpath that goes to v:
// of choosing it (light choice x position; for infinite lights, of the direction) and
// of emitting toward v (area measure at v).
void Bdpt::light_densities(const PathVertex &lv, const PathVertex &v, float &origin, float &toward) const {
  float radius = scene_.bounding_radius();
  if (lv.infinite) {
    origin = infinite_light_density(lv.dir);
    toward = 1.0f / (kPi * radius * radius);
    if (v.on_surface()) toward *= absdot(v.ng, -lv.dir);
    return;
  }
  Vec3 w = v.p - lv.p;
  float d2 = length_squared(w);
  w = w / std::sqrt(d2);
  float pdf_pos, pdf_dir;
  emission_pdf(scene_.lights()[lv.light], lv.p, lv.ng, w, radius, pdf_pos, pdf_dir);
  origin = pdf_pos * scene_.light_distribution().pmf(lv.light);
  toward = 0;
  if (!(d2 > 0)) return;
  toward = pdf_dir / d2;
  if (v.on_surface()) toward *= absdot(v.ng, w);
}

namespace {
float remap0(float f) { return f != 0 ? f : 1.0f; }
}  // namespace

// Whether a light subpath starting at light vertex v starts with a delta distribution
// (a point, spot or sun lamp): no strategy can hit it.
bool Bdpt::light_start_is_delta(const PathVertex &v) const {
  if (v.light < 0) return false;
  const Light &light = scene_.lights()[v.light];
  return (!v.infinite && light_is_delta_position(light)) || light_is_delta_direction(light);
}

// One term of the sums below: a strategy that moves the connection down past vertex v
// multiplies the ratio p_i / p_s by remap0(rev) / remap0(v.pdf_fwd). In double: a sum
// from far down a subpath times the ratios near the connection can overflow (or a
// ratio underflow) in float where their product is moderate (dense forward-scattering
// media: test_media_grid_render's extremes).
static double ratio(float rev, const PathVertex &v) { return double(remap0(rev)) / remap0(v.pdf_fwd); }

void set_mis_sum(PathVertex *path, int k, bool delta_before) {
  double r = ratio(path[k].pdf_rev, path[k]);
  double below = k > 0 ? path[k - 1].mis_sum : 0.0;
  path[k].mis_sum = r * r * ((!path[k].delta && !delta_before ? 1.0 : 0.0) + below);
}

float Bdpt::mis_weight(const PathVertex *light_path, const PathVertex *camera_path, const PathVertex &sampled, int s,
                       int t, const ConnectionDensities &c) const {
  if (s + t == 2) return 1.0f;
  // Nothing is copied or modified: the densities this strategy changes are overrides
  // (c), read for the two vertices nearest the connection on each side; the strategies
  // further down each subpath are summed once per subpath (mis_sum). The connection
  // vertices are connectible by construction (never delta here).
  double sum = 0;
  // Camera side: strategies with fewer camera vertices (i = t - 1 down to 1).
  if (t >= 2) {
    const PathVertex &pt_minus = camera_path[t - 2];
    double r = ratio(c.pt_rev, camera_path[t - 1]);
    if (!pt_minus.delta) sum += r * r;
    if (t >= 3) {
      const PathVertex &below = camera_path[t - 3];
      r *= ratio(c.pt_minus_rev, pt_minus);
      sum += r * r * ((!pt_minus.delta && !below.delta ? 1.0 : 0.0) + below.mis_sum);
    }
  }
  // Light side: strategies with fewer light vertices (i = s - 1 down to 0). The light
  // point an s = 1 strategy sampled afresh stands in for the subpath's first vertex.
  if (s >= 1) {
    const PathVertex &qs = s == 1 ? sampled : light_path[s - 1];
    double r = ratio(c.qs_rev, qs);
    bool delta_before = s >= 2 ? light_path[s - 2].delta : light_start_is_delta(qs);
    if (!delta_before) sum += r * r;
    if (s >= 2) {
      const PathVertex &qs_minus = light_path[s - 2];
      r *= ratio(c.qs_minus_rev, qs_minus);
      bool delta_below = s >= 3 ? light_path[s - 3].delta : light_start_is_delta(qs_minus);
      double below = s >= 3 ? light_path[s - 3].mis_sum : 0.0;
      sum += r * r * ((!qs_minus.delta && !delta_below ? 1.0 : 0.0) + below);
    }
  }
  // A sum that overflowed (or met 0 x inf) even so: weight 0, as for any overflow.
  return sum < HUGE_VAL ? float(1.0 / (1.0 + sum)) : 0.0f;
}

}  // namespace rdv::bdpt
