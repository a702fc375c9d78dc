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

// Density with which vertex v, reached from prev, scatters toward next (area measure at next).
float Bdpt::pdf(const PathVertex &v, const PathVertex *prev, const PathVertex &next) const {
  if (v.type == VertexType::Light) return pdf_light(v, next);
  Vec3 wn = next.infinite ? next.dir : normalize(next.p - v.p);
  float p;
  if (v.type == VertexType::Camera) {
    float pdf_pos;
    scene_.camera().importance_pdf(Ray{v.p, wn, kInf}, pdf_pos, p);
  } else if (v.type == VertexType::Medium) {
    Vec3 wp = prev ? (prev->infinite ? prev->dir : normalize(prev->p - v.p)) : v.wo;
    p = scene_.medium(v.medium).phase.pdf(wp, wn);
  } else {
    Vec3 wp = prev ? (prev->infinite ? prev->dir : normalize(prev->p - v.p)) : v.wo;
    p = v.bsdf.pdf(wp, wn);
  }
  return v.convert_density(p, next);
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
                       int t) const {
  if (s + t == 2) return 1.0f;
  // The vertex a strategy sampled afresh (s = 1: the light point; t = 1: the lens
  // point) stands in for the subpath's own. Nothing is copied or modified: the few
  // densities that differ for this strategy are overrides read by the sums below.
  const PathVertex *qs = s == 1 ? &sampled : s > 1 ? &light_path[s - 1] : nullptr;
  const PathVertex *pt = t == 1 ? &sampled : &camera_path[t - 1];
  const PathVertex *qs_minus = s > 1 ? &light_path[s - 2] : nullptr;
  const PathVertex *pt_minus = t > 1 ? &camera_path[t - 2] : nullptr;

  // Reverse densities at the connection and its neighbours.
  const float pt_rev = s > 0 ? pdf(*qs, qs_minus, *pt) : pdf_light_origin(*pt, *pt_minus);
  const float pt_minus_rev = pt_minus ? (s > 0 ? pdf(*pt, qs, *pt_minus) : pdf_light(*pt, *pt_minus)) : 0.0f;
  const float qs_rev = qs ? pdf(*pt, pt_minus, *qs) : 0.0f;
  const float qs_minus_rev = qs_minus ? pdf(*qs, pt, *qs_minus) : 0.0f;

  // Camera side: strategies with fewer camera vertices. The connection vertices are
  // connectible by construction (never delta here).
  float sum = 0, ri = 1;
  for (int i = t - 1; i > 0; --i) {
    float rev = i == t - 1 ? pt_rev : i == t - 2 ? pt_minus_rev : camera_path[i].pdf_rev;
    ri *= remap0(rev) / remap0(camera_path[i].pdf_fwd);
    bool delta = i != t - 1 && camera_path[i].delta;
    if (!delta && !camera_path[i - 1].delta) sum += ri * ri;
  }
  // Light side: strategies with fewer light vertices.
  const PathVertex &light_start = s == 1 ? sampled : light_path[0];
  const bool delta_light =
      s > 0 && light_start.light >= 0 &&
      ((!light_start.infinite && light_is_delta_position(scene_.lights()[light_start.light])) ||
       light_is_delta_direction(scene_.lights()[light_start.light]));
  ri = 1;
  for (int i = s - 1; i >= 0; --i) {
    const PathVertex &v = i == 0 ? light_start : light_path[i];
    float rev = i == s - 1 ? qs_rev : i == s - 2 ? qs_minus_rev : v.pdf_rev;
    ri *= remap0(rev) / remap0(v.pdf_fwd);
    bool delta = i != s - 1 && v.delta;
    bool delta_before = i > 0 ? light_path[i - 1].delta : delta_light;
    if (!delta && !delta_before) sum += ri * ri;
  }
  return 1.0f / (1.0f + sum);
}

}  // namespace rdv::bdpt
