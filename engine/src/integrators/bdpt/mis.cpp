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

// Density with which the camera sends a ray from its vertex toward v (area measure at v).
float Bdpt::pdf_camera(const PathVertex &camera, const PathVertex &v) const {
  float pdf_pos, pdf_dir;
  scene_.camera().importance_pdf(Ray{camera.p, normalize(v.p - camera.p), kInf}, pdf_pos, pdf_dir);
  return camera.convert_density(pdf_dir, v);
}

// Density with which a light vertex emits toward v (area measure at v).
float Bdpt::pdf_light(const PathVertex &lv, const PathVertex &v) const {
  float radius = scene_.bounding_radius();
  Vec3 w;
  float p;
  if (lv.infinite) {
    w = -lv.dir;
    p = 1.0f / (kPi * radius * radius);
  } else {
    w = v.p - lv.p;
    float d2 = length_squared(w);
    if (!(d2 > 0)) return 0;
    w = w / std::sqrt(d2);
    float pdf_pos, pdf_dir;
    emission_pdf(scene_.lights()[lv.light], lv.p, lv.ng, w, radius, pdf_pos, pdf_dir);
    p = pdf_dir / d2;
  }
  if (v.on_surface()) p *= absdot(v.ng, w);
  return p;
}

// Density of choosing lv as the start of a light subpath.
float Bdpt::pdf_light_origin(const PathVertex &lv, const PathVertex &v) const {
  if (lv.infinite) return infinite_light_density(lv.dir);
  Vec3 w = normalize(v.p - lv.p);
  float pdf_pos, pdf_dir;
  emission_pdf(scene_.lights()[lv.light], lv.p, lv.ng, w, scene_.bounding_radius(), pdf_pos, pdf_dir);
  return pdf_pos * scene_.light_distribution().pmf(lv.light);
}

namespace {
float remap0(float f) { return f != 0 ? f : 1.0f; }
}  // namespace

float Bdpt::mis_weight(const PathVertex *light_path, const PathVertex *camera_path, const PathVertex &sampled, int s,
                       int t, const ConnectionDensities &c) const {
  if (s + t == 2) return 1.0f;
  // Nothing is copied or modified: the densities this strategy changes are overrides
  // (c) read by the sums below.
  // Camera side: strategies with fewer camera vertices. The connection vertices are
  // connectible by construction (never delta here).
  float sum = 0, ri = 1;
  for (int i = t - 1; i > 0; --i) {
    float rev = i == t - 1 ? c.pt_rev : i == t - 2 ? c.pt_minus_rev : camera_path[i].pdf_rev;
    ri *= remap0(rev) / remap0(camera_path[i].pdf_fwd);
    bool delta = i != t - 1 && camera_path[i].delta;
    if (!delta && !camera_path[i - 1].delta) sum += ri * ri;
  }
  // Light side: strategies with fewer light vertices. The light point an s = 1
  // strategy sampled afresh stands in for the subpath's first vertex.
  const PathVertex &light_start = s == 1 ? sampled : light_path[0];
  const bool delta_light =
      s > 0 && light_start.light >= 0 &&
      ((!light_start.infinite && light_is_delta_position(scene_.lights()[light_start.light])) ||
       light_is_delta_direction(scene_.lights()[light_start.light]));
  ri = 1;
  for (int i = s - 1; i >= 0; --i) {
    const PathVertex &v = i == 0 ? light_start : light_path[i];
    float rev = i == s - 1 ? c.qs_rev : i == s - 2 ? c.qs_minus_rev : v.pdf_rev;
    ri *= remap0(rev) / remap0(v.pdf_fwd);
    bool delta = i != s - 1 && v.delta;
    bool delta_before = i > 0 ? light_path[i - 1].delta : delta_light;
    if (!delta && !delta_before) sum += ri * ri;
  }
  return 1.0f / (1.0f + sum);
}

}  // namespace rdv::bdpt
