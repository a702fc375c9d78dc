#include "integrators/path/path_tracer.h"
#include "core/ray_offset.h"
#include "core/sampling.h"

namespace rdv {

// Next-event estimation: one light chosen by power, one point on it, MIS-weighted
// against the BSDF having sampled the same direction.
Color PathTracer::sample_direct_light(const SurfaceHit &hit, const Bsdf &bsdf, Vec3 wo, Sampler &sampler,
                                      RayStats &stats) const {
  float u_light = sampler.get_1d();
  Vec2 u = sampler.get_2d();
  const Distribution1D &dist = scene_.light_distribution();
  if (dist.size() == 0 || dist.total() <= 0) return Color(0.0f);
  float pmf;
  const Light &light = scene_.lights()[dist.sample_discrete(u_light, &pmf)];
  LightSample ls;
  if (!sample_light(light, hit.p, u, ls) || !(ls.pdf > 0)) return Color(0.0f);
  Color f = bsdf.eval(wo, ls.wi, TransportMode::Radiance);
  if (is_black(f)) return Color(0.0f);
  Vec3 o = spawn_origin(hit.p, hit.ng, ls.wi);
  float tmax = std::isinf(ls.dist) ? kInf : shadow_tmax(length(ls.p - o));
  ++stats.rays;
  if (scene_.occluded(o, ls.wi, tmax)) return Color(0.0f);
  float light_pdf = pmf * ls.pdf;
  float weight = light.is_delta() ? 1.0f : power_heuristic(light_pdf, bsdf.pdf(wo, ls.wi));
  return f * ls.L * (weight / light_pdf);
}

Color PathTracer::Li(const CameraRay &camera_ray, Sampler &sampler, RayStats &stats, FirstHit *first_hit,
                     std::vector<Splat> &) const {
  Color L(0.0f), beta(1.0f);
  Ray ray = camera_ray.ray;
  bool specular_bounce = true;  // camera rays count as specular: no MIS on what they see
  float prev_pdf = 0;
  Vec3 prev_p = ray.o;
  const Distribution1D &dist = scene_.light_distribution();

  // MIS weight for emission found by BSDF sampling, given that light's solid-angle pdf.
  auto emission_weight = [&](uint32_t light, float pdf_light_sa) {
    if (specular_bounce) return 1.0f;
    return power_heuristic(prev_pdf, dist.pmf(light) * pdf_light_sa);
  };

  for (int depth = 0;; ++depth) {
    SurfaceHit hit;
    ++stats.rays;
    bool found = scene_.intersect(ray, hit);
    float tmax = found ? hit.t : ray.tmax;

    // Analytic lights (disks, rectangles) in front of the surface.
    int hit_light = -1;
    Color light_L;
    for (uint32_t li : scene_.hittable_lights()) {
      if (depth == 0 && !scene_.lights()[li].visible_camera) continue;
      float t;
      Color Le;
      if (intersect_light(scene_.lights()[li], ray, tmax, t, Le)) { tmax = t; hit_light = int(li); light_L = Le; }
    }
    if (hit_light >= 0) {
      float pdf = light_pdf(scene_.lights()[hit_light], prev_p, ray.d, tmax);
      L += beta * light_L * emission_weight(hit_light, pdf);
      break;
    }
    if (!found) {
      for (uint32_t li : scene_.infinite_lights()) {  // the world, beyond clip_end too
        const Light &light = scene_.lights()[li];
        if (depth == 0 && !light.visible_camera) continue;
        Color Le = infinite_light_radiance(light, ray.d);
        if (!is_black(Le)) L += beta * Le * emission_weight(li, light_pdf(light, prev_p, ray.d, kInf));
      }
      break;
    }

    const Material &material = scene_.material(hit.material);
    Vec3 wo = -ray.d;
    if (material.emits()) {
      uint32_t li = scene_.triangle_light(hit.instance, hit.prim);
      float pdf = light_pdf(scene_.lights()[li], prev_p, ray.d, hit.t);
      L += beta * material.emission * emission_weight(li, pdf);
    }
    Bsdf bsdf = material.make_bsdf(scene_.shading_point(hit), wo);
    if (depth == 0 && first_hit) {
      const Camera &cam = scene_.camera();
      first_hit->valid = true;
      first_hit->depth = dot(hit.p - cam.position(), cam.forward());
      first_hit->normal = dot(hit.ns, wo) < 0 ? -hit.ns : hit.ns;
      first_hit->albedo = bsdf.albedo();
    }
    if (depth >= max_bounces_ || !bsdf.has_lobes()) break;

    if (!bsdf.is_delta()) L += beta * sample_direct_light(hit, bsdf, wo, sampler, stats);

    BsdfSample bs;
    float u_lobe = sampler.get_1d();
    Vec2 u = sampler.get_2d();
    if (!bsdf.sample(wo, u_lobe, u, TransportMode::Radiance, bs)) break;
    beta *= bs.weight;
    specular_bounce = bs.is_delta;
    prev_pdf = bs.pdf;
    prev_p = hit.p;
    ray = Ray{spawn_origin(hit.p, hit.ng, bs.wi), bs.wi, kInf};

    // Russian roulette once the path has had a few bounces to pick up light.
    if (depth >= 3) {
      float q = std::max(0.05f, 1.0f - max_component(beta));
      if (sampler.get_1d() < q) break;
      beta *= 1.0f / (1.0f - q);
    }
    if (is_black(beta)) break;
  }
  return L;
}

}  // namespace rdv
