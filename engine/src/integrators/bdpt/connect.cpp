// Connecting a light subpath prefix of s vertices to a camera subpath prefix of t
// vertices (pbrt-v3's ConnectBDPT), with the vertex quantities the connection needs.
#include "bsdfs/transparency.h"
#include "core/ray_offset.h"
#include "lights/sphere_lamp.h"
#include "lights/volume_light.h"
#include "media/medium_stack.h"
#include "samplers/dimension_layout.h"
#include "integrators/bdpt/bdpt.h"
#include "integrators/filter_glossy.h"
#include "integrators/visibility_clear.h"

namespace rdv::bdpt {

static Vec3 direction_to(const PathVertex &from, const PathVertex &to) {
  return to.infinite ? to.dir : normalize(to.p - from.p);
}

Scattering Bdpt::scatter(const PathVertex &v, Vec3 wi, TransportMode mode, const Bsdf *bsdf) const {
  Scattering sc;
  if (v.type == VertexType::Medium) {
    const HenyeyGreenstein &phase = scene_.medium(v.medium).phase;
    sc.f = Color(phase.eval(v.wo, wi));
    sc.pdf_fwd = sc.pdf_rev = phase.pdf(v.wo, wi);  // symmetric, and sampled exactly
  } else if (v.type == VertexType::Surface) {
    sc.f = (bsdf ? *bsdf : v.bsdf).f_and_pdfs(v.wo, wi, mode, sc.pdf_fwd, sc.pdf_rev);
  }
  return sc;
}

// Radiance a light vertex (or an emissive surface) sends toward `toward`, a camera-path
// vertex (its out_mask: the kind of ray that found v).
Color Bdpt::Le(const PathVertex &v, const PathVertex &toward, RayStats &stats, bool catcher_only,
              int scatterings) const {
  if (!v.is_light()) return Color(0.0f);
  // A catcher copy's shadow rays meet shadow catchers only.
  auto occluders = [catcher_only](const Light &light) {
    return catcher_only ? visibility::catcher_rays(light.occluders()) : light.occluders();
  };
  // Mixed visibility: the segment from a scattering vertex is blocked by shadow casters.
  const bool test_shadows = mixed_ && toward.type != VertexType::Camera;
  if (v.infinite) {
    // The world seen through a transparent film is not there (film_alpha.h).
    const bool transparent_world = v.see_through && settings_.alpha.film_transparent;
    const ShadowRay s = shadow_ray_to_infinity(toward.p, toward.ng, toward.error, v.dir);
    Color L(0.0f);
    for (uint32_t li : scene_.infinite_lights()) {
      const Light &light = scene_.lights()[li];
      if (!(light.visibility & toward.out_mask)) continue;  // camera rays: suns are not seen
      if (transparent_world && light.type == LightType::Background) continue;
      if (catcher_only && !light.shadow_catcher) continue;
      if (scatterings >= 0 && !light.lights_path(scatterings)) continue;
      if (test_shadows && !visibility_clear(scene_, s, occluders(light), true, stats.rays, true)) continue;
      L += infinite_light_radiance(light, v.dir);
    }
    return L;
  }
  if (catcher_only && v.light >= 0 && !scene_.lights()[v.light].shadow_catcher) return Color(0.0f);
  if (scatterings >= 0 && v.light >= 0 && !scene_.lights()[v.light].lights_path(scatterings)) return Color(0.0f);
  if (test_shadows && v.light >= 0 &&
      !visibility_clear(scene_, shadow_ray(toward.p, toward.ng, toward.error, v.p, v.ng, v.error),
                        occluders(scene_.lights()[v.light]), true, stats.rays, true))
    return Color(0.0f);
  return v.emitted;  // lamps, and emissive surfaces (both sides; textures evaluated at the hit)
}

bool Bdpt::light_walk_unblurred(const PathVertex *light_path, int s, float min_pdf) const {
  const FilterGlossy filter(settings_.limits.filter_glossy);
  for (int j = s - 2; j >= 1; --j) {
    const PathVertex &v = light_path[j];
    const float alpha = filter.alpha_after(min_pdf);
    if (Bsdf::blur_acts(alpha) && alpha > v.blur_threshold) return false;
    min_pdf = std::min(min_pdf, v.filter_pdf);
  }
  return true;
}

bool Bdpt::light_walk_seen(const PathVertex *light_path, int last, Vec3 wi) const {
  const ScatterKind kind = kind_toward(light_path[last], wi);
  if (kind == ScatterKind::Transparent) return true;  // a pass keeps the kind: the next scattering checks
  const uint32_t ray = visibility::after(kind);
  // Back to the light walk's scattering before (a pass lets the same ray on); the light
  // itself is light_start_visible's.
  for (int m = last - 1; m >= 1; --m) {
    const PathVertex &before = light_path[m];
    if (before.on_surface() && !(before.visibility & ray)) return false;
    if (!before.passed_through) break;
  }
  return true;
}

bool Bdpt::light_start_visible(const PathVertex *light_path, int s, Vec3 wi) const {
  if (!scene_.has_ray_visibility() || s < 2) return true;
  if (mixed_ && s >= 3 && !light_walk_seen(light_path, s - 1, wi)) return false;
  if (light_path[0].light < 0) return true;
  const uint32_t v = scene_.lights()[light_path[0].light].visibility;
  if ((v & visibility::kNonCamera) == visibility::kNonCamera) return true;
  if (s >= 3) wi = -light_path[2].wo;
  return v & visibility::after(kind_toward(light_path[1], wi));
}

template <bool kMedia>
Color Bdpt::transmittance(const PathVertex &a, const PathVertex &b, Sampler &sampler, SampleStream stream,
                          uint32_t position, RayStats &stats, uint32_t mask, int layers) const {
  Vec3 d = b.p - a.p;
  float dist = length(d);
  if (!(dist > 0)) return Color(0.0f);
  d = d / dist;
  // Both ends leave the geometry they lie on (error > 0: surfaces and emissive triangles).
  ShadowRay shadow = shadow_ray(a.p, a.ng, a.error, b.p, b.ng, b.error);
  if constexpr (kMedia) {
    SampleRun run(sampler, stream, position, dims::kMediumRun);
    return medium_transmittance(scene_, shadow, a.media_toward(scene_, d), stats.rays, run, layers, nullptr, mask, true);
  } else {
    ++stats.rays;
    if (!scene_.occluded(shadow.o, shadow.d, shadow.tmax, mask)) return Color(1.0f);
    if (!scene_.has_transparency()) return Color(0.0f);
    return transparent_shadow(scene_, shadow.o, shadow.d, shadow.tmax, stats.rays, mask, layers, true);
  }
}

template <bool kMedia>
Color Bdpt::connect(PathVertex *light_path, PathVertex *camera_path, int s, int t, Sampler &sampler,
                    RayStats &stats, Vec2 *raster, float *mis_weight_out, Vec3 *connection_dir,
                    bool catcher_copy) const {
  Color L(0.0f);
  const LightPathLimits &limits = settings_.limits;
  // A catcher copy's connections meet shadow catchers only (shadow_catcher.cpp).
  auto rays = [catcher_copy](uint32_t mask) { return catcher_copy ? visibility::catcher_rays(mask) : mask; };
  PathVertex &pt = camera_path[t - 1];
  // s = 0 needs a camera path that ended on an emitter; one that ended on a lamp (or
  // the world) counts only as s = 0.
  if (s == 0 ? !pt.is_light() : t > 1 && pt.type == VertexType::Light) return L;
  // Transparent max bounces: the subpaths' passes, and what is left for the connection to
  // pass (plain layers; a connection's path always scatters). The clamps count scatterings.
  const int passes = path_passes(light_path, camera_path, s, t);
  const int scatterings = path_scatterings(light_path, camera_path, s, t);
  if (!limits.transparent_within(passes, scatterings > 0)) return L;
  const int layers = limits.layers_left(passes, kShadowLayers);
  // A light subpath's light, by its Max Bounces (next-event estimation checks its own
  // light below, the camera path's emitter in Le).
  if (s >= 2 && light_path[0].light >= 0 && !scene_.lights()[light_path[0].light].lights_path(scatterings)) return L;
  PathVertex sampled;
  ConnectionDensities densities;
  constexpr ScatterKind kNone = ScatterKind::Transparent;
  Color kept(1.0f);  // the share of the path Cycles' Light Paths limits keep
  if (s == 0) {
    if (limits.classify && is_black(kept = limits_share(light_path, camera_path, 0, t, kNone, kNone))) return L;
    L = Le(pt, camera_path[t - 2], stats, catcher_copy, scatterings) * pt.beta;
    if (!is_black(L) && t > 2) {
      light_densities(pt, camera_path[t - 2], densities.pt_rev, densities.pt_minus_rev);
    }
  } else if (t == 1) {
    // Light tracing: connect the light subpath to a point on the lens.
    PathVertex &qs = light_path[s - 1];
    if (!qs.connectible(scene_) || (qs.type != VertexType::Surface && qs.type != VertexType::Medium)) return L;
    if (qs.holdout >= 1) return L;  // a holdout object seen by the camera is not there (film_alpha.h)
    // A catcher copy's path splits at a catcher the camera sees: its prefix, the camera ray,
    // is in the whole scene (the transmittance below checks it against every object).
    if (catcher_copy && !qs.catcher) return L;
    if (!(qs.visibility & visibility::kCamera)) return L;  // hidden from the camera
    const Camera &camera = scene_.camera_now();
    Camera::ImportanceSample is;
    sampler.start_stream(SampleStream::Lens, dims::lens(uint32_t(s) - 1, dims::kLensPoint));
    Vec2 u = sampler.get_2d();
    if (!camera.can_be_connected() || !camera.sample_importance(qs.p, u, is) || !(is.pdf > 0)) return L;
    if (limits.classify &&
        is_black(kept = limits_share(light_path, camera_path, s, 1, kNone, kind_toward(qs, is.wi), -is.wi)))
      return L;
    if (!light_start_visible(light_path, s, is.wi)) return L;
    sampled.type = VertexType::Camera;
    sampled.p = is.lens_point;
    sampled.ng = sampled.ns = camera.forward();
    sampled.beta = Color(is.We / is.pdf);
    if constexpr (kMedia) sampled.media = MediumStack::for_camera(scene_);
    if (connection_dir) *connection_dir = direction_to(qs, sampled);
    Scattering sq = scatter(qs, direction_to(qs, sampled), TransportMode::Importance);
    // Filter Glossy: seen straight from the camera, qs is never blurred; the light walk's
    // vertices before it must not be (filter_glossy.h).
    if (limits.filter_glossy > 0 && s >= 3 && !light_walk_unblurred(light_path, s, sq.pdf_rev)) return L;
    L = qs.beta * sq.f * sampled.beta;
    if (qs.on_surface()) L *= absdot(is.wi, qs.bsdf.shading_normal(is.wi));
    if (!is_black(L))
      L *= transmittance<kMedia>(qs, sampled, sampler, SampleStream::Lens, dims::lens(uint32_t(s) - 1, dims::kLensMedia),
                                 stats, visibility::kCamera, layers);
    *raster = is.raster;
    densities.pt_rev = qs.convert_density(sq.pdf_fwd, sampled);
    densities.qs_rev = sampled.convert_density(is.pdf_dir, qs);
    densities.qs_minus_rev = qs.to_prev_density(sq.pdf_rev);
  } else if (s == 1) {
    // Next-event estimation: a fresh point on a light chosen by power.
    if (!pt.connectible(scene_)) return L;
    const uint32_t vertex = uint32_t(t) - 1;
    sampler.start_stream(SampleStream::LightPoint, dims::next_event(vertex, dims::kNeeLightChoice));
    float u_light = sampler.get_1d();
    Vec2 u = sampler.get_2d();
    const Distribution1D &dist = scene_.light_distribution();
    if (dist.size() == 0 || dist.total() <= 0) return L;
    float pmf;
    uint32_t index = uint32_t(dist.sample_discrete(u_light, &pmf));
    const Light &light = scene_.lights()[index];
    if (catcher_copy && !light.shadow_catcher) return L;  // the synthetic objects' light
    if (!light.lights_path(scatterings)) return L;  // its Max Bounces
    Vec3 u_volume(0.0f);
    if (light.type == LightType::Volume)
      u_volume = dims::volume_point(sampler, SampleStream::LightPoint, dims::next_event(vertex, dims::kNeeVolumePoint));
    LightSample ls;
    if (!scene_.sample_light(index, pt.p, u, u_volume, ls) || !(ls.pdf > 0)) return L;
    sampled.type = VertexType::Light;
    sampled.light = int(index);
    sampled.beta = ls.L / (ls.pdf * pmf);
    if (light.is_infinite()) {
      sampled.infinite = true;
      sampled.dir = ls.wi;
    } else {
      sampled.p = ls.p;
      sampled.error = ls.error;
      if (light.type == LightType::Area || light.type == LightType::Triangle) sampled.ng = sampled.ns = light.axis;
      if (is_sphere_lamp(light)) sampled.ng = sampled.ns = normalize(ls.p - light.position);
      if (light.type == LightType::Volume) sampled.gather_rate = 1.0f / light.volume->medium().emission_step;
    }
    if (limits.classify) {
      const Vec3 to_light = direction_to(pt, sampled);
      kept = limits_share(light_path, camera_path, 1, t, kind_toward(pt, to_light), kNone, to_light);
      if (is_black(kept)) return L;
    }
    // Ray visibility: the light must be visible to the kind of the scattering toward it.
    uint32_t kind = visibility::kAnyRay;
    if (scene_.has_ray_visibility()) {
      kind = visibility::after(kind_toward(pt, direction_to(pt, sampled)));
      if (!(light.visibility & kind)) return L;
    }
    if (connection_dir) *connection_dir = direction_to(pt, sampled);
    light_densities(sampled, pt, sampled.pdf_fwd, densities.pt_rev, ls.pdf);
    Scattering sp = scatter(pt, direction_to(pt, sampled), TransportMode::Radiance);
    L = pt.beta * sp.f * sampled.beta;
    densities.pt_minus_rev = pt.to_prev_density(sp.pdf_rev);
    densities.qs_rev = pt.convert_density(sp.pdf_fwd, sampled);
    if (pt.on_surface()) L *= absdot(ls.wi, pt.bsdf.shading_normal(pt.wo));
    if (!is_black(L)) {
      ShadowRay shadow = std::isinf(ls.dist) ? shadow_ray_to_infinity(pt.p, pt.ng, pt.error, ls.wi)
                                             : shadow_ray(pt.p, pt.ng, pt.error, ls.p, ls.n, ls.error);
      if constexpr (kMedia) {
        MediumStack end;
        SampleRun run(sampler, SampleStream::LightPoint, dims::next_event(vertex, dims::kNeeMedia), dims::kMediumRun);
        L *= medium_transmittance(scene_, shadow, pt.media_toward(scene_, ls.wi), stats.rays, run, layers, &end,
                                  rays(light.occluders()), true);
        if (ls.medium >= 0 && !is_black(L) && end.current(scene_) != ls.medium) L = Color(0.0f);  // outside its medium
      } else if (const uint32_t occluders = rays(light.occluders())) {
        ++stats.rays;
        if (scene_.occluded(shadow.o, shadow.d, shadow.tmax, occluders))
          L = scene_.has_transparency()
                  ? L * transparent_shadow(scene_, shadow.o, shadow.d, shadow.tmax, stats.rays, occluders, layers, true)
                  : Color(0.0f);
      }
      // Mixed visibility: could the camera path have found the light along this segment?
      // Could a light walk have made it? It passes no surface of mixed visibility, and
      // from a lamp that casts no shadows (nothing blocks this segment) no surface at all.
      if (mixed_ && !is_black(L)) {
        densities.s0_impossible = !visibility_clear(scene_, shadow, rays(kind), true, stats.rays, true);
        ++stats.rays;
        const uint32_t passed = light.occluders() ? visibility::kMixed : visibility::kNonCamera;
        densities.light_cut = ends_light_walks(pt) || scene_.occluded(shadow.o, shadow.d, shadow.tmax, rays(passed));
      }
    }
  } else {
    // Both ends are surface or medium vertices (finite points).
    PathVertex &qs = light_path[s - 1];
    // Filter Glossy (filter_glossy.h): qs may be blurred (a smooth one made connectible).
    const bool filter = limits.filter_glossy > 0;
    if ((!filter && !qs.connectible(scene_)) || !pt.connectible(scene_)) return L;
    Vec3 dir = normalize(pt.p - qs.p);
    if (connection_dir) *connection_dir = -dir;
    if (limits.classify &&
        is_black(kept = limits_share(light_path, camera_path, s, t, kind_toward(pt, -dir), kind_toward(qs, dir), -dir)))
      return L;
    if (!light_start_visible(light_path, s, dir)) return L;
    Scattering sq, sp;
    if (filter) {
      // qs's BSDF as the path has it: blurred by the camera side's smallest density,
      // pt's scattering toward qs included.
      sp = scatter(pt, -dir, TransportMode::Radiance);
      if (is_black(sp.f)) return L;
      float min_pdf = std::min(pt.filter_pdf, sp.pdf_fwd);
      const float alpha = FilterGlossy(limits.filter_glossy).alpha_after(min_pdf);
      Bsdf blurred;
      if (qs.type == VertexType::Surface && qs.bsdf.blur_changes(alpha)) {
        blurred = qs.bsdf;
        blurred.blur(alpha);
        if (!blurred.has_lobes() || blurred.is_delta()) return L;
        densities.qs_blurred = true;
      } else if (!qs.connectible(scene_)) {
        return L;
      }
      sq = scatter(qs, dir, TransportMode::Importance, densities.qs_blurred ? &blurred : nullptr);
      if (is_black(sq.f)) return L;
      if (s >= 3 && !light_walk_unblurred(light_path, s, std::min(min_pdf, sq.pdf_rev))) return L;
    } else {
      sq = scatter(qs, dir, TransportMode::Importance);
      if (is_black(sq.f)) return L;  // nothing to trace a shadow ray for
      sp = scatter(pt, -dir, TransportMode::Radiance);
    }
    L = qs.beta * sq.f * sp.f * pt.beta;
    if (is_black(L)) return L;
    // The geometry term and the two area-measure conversions share one distance.
    Vec3 w = pt.p - qs.p;
    float d2 = length_squared(w);
    if (!(d2 > 0)) return Color(0.0f);
    float inv_d2 = 1.0f / d2;
    Vec3 d = w * std::sqrt(inv_d2);
    float g = inv_d2, cos_qs = 1, cos_pt = 1;  // geometric cosines, for the densities
    // The shading cosines of f's frames (Bsdf::shading_normal: normal maps, the terminator).
    if (qs.on_surface()) { g *= absdot(qs.bsdf.shading_normal(dir), d); cos_qs = absdot(qs.ng, d); }
    if (pt.on_surface()) { g *= absdot(pt.bsdf.shading_normal(pt.wo), d); cos_pt = absdot(pt.ng, d); }
    if (!(g > 0)) return Color(0.0f);
    // Without mixed visibility every instance is seen by all kinds after a scattering or
    // by none: one mask stands for them. With it, the segment is the kind of pt's
    // scattering, which must see qs, and no light walk makes it past a surface of mixed
    // visibility.
    uint32_t kind = visibility::kNonCamera;
    if (mixed_) {
      kind = visibility::after(kind_toward(pt, -dir));
      if (qs.on_surface() && !(qs.visibility & kind)) return Color(0.0f);
    }
    L *= transmittance<kMedia>(qs, pt, sampler, SampleStream::Connection, dims::connection(uint32_t(s), uint32_t(t)),
                               stats, rays(kind), layers) * g;
    if (is_black(L)) return L;
    if (mixed_) {
      const ShadowRay segment = shadow_ray(qs.p, qs.ng, qs.error, pt.p, pt.ng, pt.error);
      ++stats.rays;
      densities.light_cut =
          ends_light_walks(pt) || scene_.occluded(segment.o, segment.d, segment.tmax, rays(visibility::kMixed));
    }
    densities.pt_rev = sq.pdf_fwd * cos_pt * inv_d2;  // qs.convert_density(sq.pdf_fwd, pt)
    densities.pt_minus_rev = pt.to_prev_density(sp.pdf_rev);
    densities.qs_rev = sp.pdf_fwd * cos_qs * inv_d2;  // pt.convert_density(sp.pdf_fwd, qs)
    densities.qs_minus_rev = qs.to_prev_density(sq.pdf_rev);
  }
  float w = is_black(L) ? 0.0f : mis_weight(light_path, camera_path, sampled, s, t, densities);
  if (mis_weight_out) *mis_weight_out = w;
  L *= kept;
  return limits.clamps ? limits.clamp(L * w, scatterings) : L * w;
}

template Color Bdpt::connect<false>(PathVertex *, PathVertex *, int, int, Sampler &, RayStats &, Vec2 *, float *,
                                    Vec3 *, bool) const;
template Color Bdpt::connect<true>(PathVertex *, PathVertex *, int, int, Sampler &, RayStats &, Vec2 *, float *,
                                   Vec3 *, bool) const;

}  // namespace rdv::bdpt
