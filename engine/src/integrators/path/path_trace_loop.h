// The path tracer's loop (PathTracer::trace) and its next-event estimation, as templates:
// path_tracer.cpp compiles them for scenes without shadow catchers, shadow_catcher.cpp
// for scenes with one, each in its own translation unit so that neither changes how the
// compiler inlines the other (the loop without catchers is the one every other scene runs).
#pragma once
#include "integrators/path/path_tracer.h"
#include "bsdfs/transparency.h"
#include "core/ray_offset.h"
#include "core/sampling.h"
#include "integrators/caustics_switches.h"
#include "integrators/filter_glossy.h"
#include "integrators/visibility_clear.h"
#include "media/emission_gather.h"
#include "media/medium_stack.h"
#include "samplers/dimension_layout.h"

namespace rdv {


// Next-event estimation: one light chosen by power, one point on it, MIS-weighted
// against the scattering function having sampled the same direction.
//   scatter(wi, &pdf) returns f * |cos| (surfaces) or the phase function (media).
//   ng, p_error: geometric normal and rounding error at p (zero inside a medium).
//   media_toward(wi) gives the media a shadow ray along wi starts in.
// With media, the shadow ray carries transmittance through media and index-matched
// boundaries; without, it is a plain occlusion query.
// vertex: the path vertex p is (its next-event block, samplers/dimension_layout.h).
// kind_toward(wi): the kind of ray (scene/ray_visibility.h) the scattering toward wi
// sends, asked only in scenes with ray visibility: a light hidden from it gives nothing.
// The shadow ray is blocked by what the light's shadows are cast by (Light::occluders).
// In scenes with mixed visibility, scattering toward the light could only have found it
// if nothing visible to that kind lies between (visibility_clear): else this estimate
// is the path's only one and takes all its weight.
// catcher_only: the catcher pass's copy of a path (shadow_catcher.h): shadow rays meet
// shadow catchers only, and emitting objects that are not catchers give no light; only
// in the loop compiled for scenes with a catcher (kCatcher).
// shadow_layers: the transparent layers the shadow ray may pass (Transparent max bounces
// less the path's passes so far, light_path_limits.h).
template <bool kMedia, bool kCatcher, class Scatter, class MediaToward, class KindToward>
static Color sample_direct_light(const Scene &scene, uint32_t vertex, Vec3 p, Vec3 ng, Vec3 p_error,
                                 const Scatter &scatter, const MediaToward &media_toward,
                                 const KindToward &kind_toward, Sampler &sampler, RayStats &stats,
                                 bool catcher_only, int shadow_layers) {
  catcher_only = kCatcher && catcher_only;
  sampler.start_stream(SampleStream::LightPoint, dims::next_event(vertex, dims::kNeeLightChoice));
  float u_light = sampler.get_1d();
  Vec2 u = sampler.get_2d();
  const Distribution1D &dist = scene.light_distribution();
  if (dist.size() == 0 || dist.total() <= 0) return Color(0.0f);
  float pmf;
  uint32_t index = uint32_t(dist.sample_discrete(u_light, &pmf));
  const Light &light = scene.lights()[index];
  if (catcher_only && !light.shadow_catcher) return Color(0.0f);  // a synthetic object's light
  if (!light.lights_path(int(vertex))) return Color(0.0f);  // its Max Bounces (vertex: the path's scatterings)
  Vec3 u_volume(0.0f);
  if (light.type == LightType::Volume)
    u_volume = dims::volume_point(sampler, SampleStream::LightPoint, dims::next_event(vertex, dims::kNeeVolumePoint));
  LightSample ls;
  if (!scene.sample_light(index, p, u, u_volume, ls) || !(ls.pdf > 0)) return Color(0.0f);
  uint32_t kind = visibility::kAnyRay;
  if (scene.has_ray_visibility()) {
    kind = kind_toward(ls.wi);
    if (!(light.visibility & kind)) return Color(0.0f);
  }
  float scatter_pdf;
  Color f = scatter(ls.wi, &scatter_pdf);
  if (is_black(f)) return Color(0.0f);
  Color tr(1.0f);
  ShadowRay shadow = std::isinf(ls.dist) ? shadow_ray_to_infinity(p, ng, p_error, ls.wi)
                                         : shadow_ray(p, ng, p_error, ls.p, ls.n, ls.error);
  // The rays' masks: a catcher copy's meet shadow catchers only.
  auto rays = [catcher_only](uint32_t mask) { return catcher_only ? visibility::catcher_rays(mask) : mask; };
  const uint32_t occluders = rays(light.occluders());
  if constexpr (kMedia) {
    SampleRun run(sampler, SampleStream::LightPoint, dims::next_event(vertex, dims::kNeeMedia), dims::kMediumRun);
    MediumStack end;
    tr = medium_transmittance(scene, shadow, media_toward(ls.wi), stats.rays, run, shadow_layers, &end, occluders);
    if (is_black(tr)) return Color(0.0f);
    if (ls.medium >= 0 && end.current(scene) != ls.medium) return Color(0.0f);  // outside the emitting medium
  } else if (occluders) {
    ++stats.rays;
    if (scene.occluded(shadow.o, shadow.d, shadow.tmax, occluders)) {
      // Transparent shadows (alpha, Transparent BSDF): look through what blocked the ray.
      if (!scene.has_transparency()) return Color(0.0f);
      tr = transparent_shadow(scene, shadow.o, shadow.d, shadow.tmax, stats.rays, occluders, shadow_layers);
      if (is_black(tr)) return Color(0.0f);
    }
  }
  float light_pdf = pmf * ls.pdf;
  // Volume lights: camera paths gather their emission at 1 / emission_step points per
  // unit length along the sampled direction (media/emission_gather.h).
  if (light.type == LightType::Volume) scatter_pdf /= light.volume->medium().emission_step;
  const bool scattering_finds_it =
      !scene.has_mixed_visibility() || visibility_clear(scene, shadow, rays(kind), true, stats.rays);
  float weight = light.is_delta() || !scattering_finds_it ? 1.0f : power_heuristic(light_pdf, scatter_pdf);
  return f * ls.L * tr * (weight / light_pdf);
}

template <bool kMedia, shadow_catcher::Role kRole>
Color PathTracer::trace(const CameraRay &camera_ray, Sampler &sampler, RayStats &stats, FirstHit *first_hit) const {
  using shadow_catcher::Role;
  constexpr bool kCatcher = kRole != Role::None;
  Color L(0.0f), beta(1.0f);
  Ray ray = camera_ray.ray;
  ray.mask = visibility::kCamera;  // camera rays see what is visible to the camera
  RayCone cone = camera_ray.cone;  // the footprint, for filtered texture lookups
  bool specular_bounce = true;  // camera rays count as specular: no MIS on what they see
  float prev_pdf = 0;
  Vec3 prev_p = ray.o;
  // Ray visibility (scene/ray_visibility.h): rays leaving a scattering of a kind meet only
  // what is visible to it. With mixed visibility the last segment of a path to a light
  // is blocked by what casts that light's shadows, as next-event estimation's is:
  // emission found by scattering counts only when that segment is clear too.
  const bool classify_rays = scene_.has_ray_visibility();
  const bool mixed = scene_.has_mixed_visibility();
  Vec3 prev_ng(0.0f), prev_error(0.0f);  // the last scattering vertex's surface (zero in a medium)
  const Distribution1D &dist = scene_.light_distribution();
  MediumStack stack;
  if constexpr (kMedia) stack = MediumStack::for_camera(scene_);
  int boundary_crossings = 0;
  // Lamps are transparent (Scene::nearest_lamp): past one, the ray goes on from the lamp's
  // point, not into the lamp it passed.
  int lamp_passed = -1;
  auto new_ray = [&](const Ray &r) {
    ray = r;
    lamp_passed = -1;
  };
  // Where each decision draws (samplers/dimension_layout.h): bounce `depth`'s block;
  // its segments after `crossings` boundaries, lamps or transparent layers have crossing
  // blocks, and once a layer has passed through (layer_passed) its scattering
  // decisions do too, so no dimension serves two decisions.
  const uint32_t max_vertices = uint32_t(max_bounces_) + 2;
  int segment_depth = -1;
  uint32_t crossings = 0;
  bool layer_passed = false;
  auto segment_dims = [&](uint32_t offset) {
    return dims::segment(true, uint32_t(segment_depth), crossings, max_vertices, offset);
  };
  auto start_scatter = [&](uint32_t offset) {
    dims::SegmentDims d = layer_passed ? segment_dims(offset)
                                       : dims::SegmentDims{SampleStream::Camera, dims::bounce(uint32_t(segment_depth), offset)};
    sampler.start_stream(d.stream, d.position);
  };
  // Shadow catchers (shadow_catcher.h): whether the path has met its catcher; a copy
  // adds only what it finds from there on (catcher_only: its rays meet catchers only).
  CatcherSample *const catcher = kRole == Role::Main ? first_hit->catcher : nullptr;
  bool split = false, catcher_only = false;  // stay false without kCatcher
  // Segments from the camera are not last segments from a scattering vertex.
  auto shadows_allow = [&](const Light &light, const ShadowRay &s) {
    if (!mixed || segment_depth == 0) return true;
    const uint32_t occluders =
        kCatcher && catcher_only ? visibility::catcher_rays(light.occluders()) : light.occluders();
    return visibility_clear(scene_, s, occluders, true, stats.rays);
  };

  // MIS weight for emission found by BSDF sampling, given that light's solid-angle pdf.
  auto emission_weight = [&](uint32_t light, float pdf_light_sa) {
    if (specular_bounce) return 1.0f;
    return power_heuristic(prev_pdf, dist.pmf(light) * pdf_light_sa);
  };
  // Cycles' Light Paths (light_path_limits.h): the bounces of each kind so far; once one
  // is over its limit the path still collects emission at its next vertex, then ends
  // (stop_after). kept: the share of the path the limits keep with every scattering so
  // far counted (what next-event estimation from the current vertex carries); kept_found:
  // without the last one (what emission found by the segment leaving it carries). Below 1
  // only where mixed reflections (a Principled BSDF) were diffuse or glossy by Cycles' odds.
  // caustic: the caustics switches' chain (caustics_switches.h) past the last scattering;
  // caustic_found: the weight it gives emission found by the segment leaving it.
  BounceCounts counts;
  float kept = 1, kept_found = 1;
  FilterGlossy filter(limits_.filter_glossy);  // Filter Glossy (filter_glossy.h)
  // Transparent max bounces (light_path_limits.h): the path's passes through transparent
  // layers so far. A scattering vertex needs at most the limit behind it, shadow rays pass only
  // what is left of it, and the path stops where nothing it finds could count any more.
  const int max_passes = limits_.transparent;
  int transparent_passes = 0;
  auto shadow_layers = [&]() { return limits_.layers_left(transparent_passes, kShadowLayers); };
  bool stop_after = false;
  CausticState caustic;
  Color caustic_found(1.0f);
  auto count_bounce = [&](ScatterKind kind, float glossy_odds, const CausticStep &step) {
    counts.add(kind, glossy_odds);
    kept_found = kept;
    kept = limits_.kept_share(counts);
    if (!(kept > 0)) stop_after = true;
    if (limits_.caustics) {
      caustic_found = caustic.at_last(step.kept);
      caustic = caustic.after(step);
      if (caustic.none()) stop_after = true;
    }
  };
  // Light passes (film/light_passes.h), when the film keeps them: each contribution's
  // share by the first scattering vertex, split as first_split (at depth 0 set for the
  // direction next-event estimation samples, then for the one the path goes on in).
  LightPassSample *const passes = first_hit ? first_hit->passes : nullptr;
  KindSplit first_split;
  // A contribution of a path with `vertices` scattering vertices (clamped if asked);
  // background: the world's background (the Environment pass when seen directly).
  auto add_to_passes = [&](const Color &c, int vertices, bool background) {
    Color v = limits_.clamps ? limits_.clamp(c, vertices) : c;
    if (kRole == Role::Copy && !catcher_only) return v;  // the main path's part
    L += v;
    if (passes && !(kCatcher && split)) passes->add(v, vertices, first_split, background);  // none after a split, as Cycles
    return v;
  };
  auto add = [&](const Color &c, int vertices) { add_to_passes(c * kept, vertices, false); };
  // Emission the path itself finds (not next-event estimation's): the denoising albedo
  // takes it too while its features are active (film/denoising_passes.h).
  DenoisingSample *const denoising = first_hit ? &first_hit->data.denoising : nullptr;
  auto add_found = [&](const Color &c, int vertices, bool background = false) {
    const Color kept_c = limits_.caustics ? caustic_found * kept_found : Color(kept_found);
    const Color v = add_to_passes(c * kept_c, vertices, background);
    if (denoising && denoising->active) denoising->add_emission(v);
    return v;
  };
  // Transparent film (film_alpha.h): whether the camera still sees through to the
  // background, and what of the sample did. The data passes (film/data_passes.h) follow
  // the same chain of surfaces, so it is tracked whenever they are asked for.
  bool see_through = alpha_.tracked() || first_hit || kCatcher;
  DataPassSample *const data = first_hit ? &first_hit->data : nullptr;
  float transparency = 0;
  auto russian_roulette = [&](int depth) {
    if (depth < 3) return true;
    float q = std::max(0.05f, 1.0f - max_component(beta));
    sampler.start_stream(SampleStream::Camera, dims::bounce(uint32_t(depth), dims::kRoulette));
    if (sampler.get_1d() < q) return false;
    beta *= 1.0f / (1.0f - q);
    return true;
  };

  for (int depth = 0;; ++depth) {
    if (depth != segment_depth) {  // a new bounce (not a segment after a crossing)
      segment_depth = depth;
      crossings = 0;
      layer_passed = false;
    }
    SurfaceHit hit;
    CoincidentBoundary boundary;  // media: a medium boundary lying in the surface hit
    ++stats.rays;
    bool found;
    if (kCatcher && catcher_only) {  // the catcher pass's copy meets shadow catchers only
      Ray q = ray;
      q.mask = visibility::catcher_rays(ray.mask);
      found = kMedia ? scene_.intersect_media(q, hit, boundary) : scene_.intersect(q, hit);
    } else {
      found = kMedia ? scene_.intersect_media(ray, hit, boundary) : scene_.intersect(ray, hit);
    }
    float tmax = found ? hit.t : ray.tmax;

    // Analytic lights (disks, rectangles) in front of the surface.
    Color light_L;
    int hit_light = scene_.nearest_lamp(ray, lamp_passed, tmax, light_L, kCatcher && catcher_only);

    if constexpr (kMedia) {
      int m = stack.current(scene_);
      if (m >= 0) {
        const Medium &medium = scene_.medium(m);
        if (medium.is_emissive()) {
          // Emission along the segment, each point weighted against next-event
          // estimation having sampled it from the volume light (densities per volume,
          // both times the squared distance).
          dims::SegmentDims g = segment_dims(dims::kGather);
          SampleRun rng(sampler, g.stream, g.position, dims::kGatherRun);
          const Light *light = medium.light >= 0 ? &scene_.lights()[medium.light] : nullptr;
          gather_emission(medium, ray.o, ray.d, tmax, rng, [&](Vec3 x, Color c, float rate) {
            float w = 1;
            if (light && rate > 0 && !specular_bounce) {
              float pdf_light = dist.pmf(medium.light) * light->volume->pdf(x) * length_squared(x - prev_p);
              w = power_heuristic(prev_pdf * rate, pdf_light);
            }
            add_found(beta * c * w, depth);
          });
        }
        // The denoising albedo takes the segment's share before the path flies through it.
        if (denoising && denoising->active) scene_.add_denoising_volume(medium, ray.o, ray.d, tmax, beta, *denoising);
        dims::SegmentDims f = segment_dims(dims::kMedium);
        SampleRun run(sampler, f.stream, f.position, dims::kMediumRun);
        MediumSample ms = medium.sample_distance(ray.o, ray.d, tmax, run);
        beta *= ms.weight;
        if (ms.scattered) {
          // A scattering event in the medium: next-event estimation with the phase
          // function, then a new direction from it.
          Vec3 p = ray.o + ray.d * ms.t;
          Vec3 wo = -ray.d;
          if (denoising && denoising->active) denoising->end_at_volume_scatter();
          if (depth >= max_bounces_ || stop_after || transparent_passes > max_passes) break;
          auto phase = [&](Vec3 wi, float *pdf) {
            *pdf = medium.phase.pdf(wo, wi);
            return Color(medium.phase.eval(wo, wi));
          };
          auto same_medium = [&](Vec3) { return stack; };
          if (passes && depth == 0) first_split = KindSplit::only(3);  // a volume scattering
          auto scatter_kind = [](Vec3) { return visibility::after(ScatterKind::Volume); };
          const Color caustic_weight = limits_.caustics ? caustic.at_last(Color(1.0f)) : Color(1.0f);
          add(beta * caustic_weight *
                  sample_direct_light<true, kCatcher>(scene_, uint32_t(depth) + 1, p, Vec3(0.0f), Vec3(0.0f), phase,
                                                      same_medium, scatter_kind, sampler, stats, catcher_only,
                                                      shadow_layers()),
              depth + 1);
          start_scatter(dims::kScatterDirection);
          Vec3 wi = medium.phase.sample(wo, sampler.get_2d());
          specular_bounce = false;
          see_through = false;
          prev_pdf = medium.phase.pdf(wo, wi);
          filter.scattered(prev_pdf);
          prev_p = p;
          prev_ng = prev_error = Vec3(0.0f);
          if (limits_.classify)
            count_bounce(ScatterKind::Volume, -1, caustic_step(limits_, ScatterKind::Volume, -1, Color(1.0f)));
          new_ray(Ray{p, wi, kInf, classify_rays ? visibility::after(ScatterKind::Volume) : visibility::kAnyRay});
          cone = cone.after(ms.t).scattered(kRoughConeSpread);
          if (!russian_roulette(depth) || is_black(beta)) break;
          continue;
        }
      }
    }

    if (hit_light >= 0) {
      Vec3 q = ray.o + ray.d * tmax;
      const Light &lamp = scene_.lights()[hit_light];
      float pdf = light_pdf(lamp, prev_p, ray.d, length(q - prev_p));
      if (lamp.lights_path(depth) &&
          shadows_allow(lamp, shadow_ray(prev_p, prev_ng, prev_error, q, Vec3(0.0f), Vec3(0.0f))))
        add_found(beta * light_L * emission_weight(hit_light, pdf), depth);
      // Not a bounce: on from the lamp's point to what lies behind it.
      if (++boundary_crossings > 256) break;
      ++crossings;
      cone = cone.after(tmax);
      ray = Ray{q, ray.d, kInf, ray.mask};
      lamp_passed = hit_light;
      --depth;
      continue;
    }
    if (!found) {
      // The world seen through a transparent film is not there: only its alpha is.
      const bool transparent_world = see_through && alpha_.film_transparent;
      if (transparent_world) transparency += average(beta);
      if (see_through && data) scene_.add_world_data_passes(ray.d, *data);
      for (uint32_t li : scene_.infinite_lights()) {  // the world, beyond clip_end too
        const Light &light = scene_.lights()[li];
        if (!(light.visibility & ray.mask)) continue;  // camera rays: suns are not seen, the world is unless hidden
        if (transparent_world && light.type == LightType::Background) continue;
        if (kCatcher && catcher_only && !light.shadow_catcher) continue;
        if (!light.lights_path(depth)) continue;  // its Max Bounces
        if (!shadows_allow(light, shadow_ray_to_infinity(prev_p, prev_ng, prev_error, ray.d))) continue;
        Color Le = infinite_light_radiance(light, ray.d);
        if (!is_black(Le)) {
          const Color v = add_found(beta * Le * emission_weight(li, light_pdf(light, prev_p, ray.d, kInf)), depth,
                                    light.type == LightType::Background);
          // Cycles' background pass: the world seen directly, behind a catcher's matte.
          if (kCatcher && catcher && see_through && !split && light.type == LightType::Background)
            catcher->background += v;
        }
      }
      break;
    }

    if constexpr (kMedia) {
      // An index-matched medium boundary: change medium and carry straight on.
      if (scene_.is_boundary_only(hit.material)) {
        stack.cross(scene_, hit, boundary, ray.d);
        new_ray(Ray{spawn_origin(hit.p, hit.ng, hit.error, ray.d), ray.d, kInf, ray.mask});
        cone = cone.after(hit.t);
        if (++boundary_crossings > 256) break;
        ++crossings;
        --depth;  // not a bounce
        continue;
      }
    }

    // The first shadow catcher the camera sees through to (not a holdout object): the
    // split (shadow_catcher.h).
    if (kCatcher && !split && see_through && scene_.is_shadow_catcher(hit.instance) &&
        !scene_.is_holdout_instance(hit.instance)) {
      split = true;
      if constexpr (kRole == Role::Copy) {
        catcher_only = true;
      } else {
        catcher->split = true;
        catcher->matte = L;
        catcher->matte_transparency = transparency + average(beta);
        if (!alpha_.film_transparent)  // the world behind the catcher, seen along this ray
          for (uint32_t li : scene_.infinite_lights()) {
            const Light &light = scene_.lights()[li];
            if (light.type == LightType::Background && (light.visibility & ray.mask))
              catcher->background += beta * infinite_light_radiance(light, ray.d);
          }
      }
    }

    const Material &material = scene_.material(hit.material);
    Vec3 wo = -ray.d;
    Color Le;
    Bsdf bsdf = scene_.bsdf(hit, wo, cone.width_at(hit.t), &Le);
    if (filter.on()) bsdf.blur(filter.alpha());
    cone = cone.after(hit.t);
    if (see_through && alpha_.holdouts) {  // as Cycles: only where the camera sees through
      const float h = scene_.holdout_weight(hit);
      transparency += h * average(beta);
      if (h >= 1) break;  // all held out: nothing of it is seen
    }
    if (see_through && data) scene_.add_data_passes(hit, beta, alpha_.pass_alpha_threshold, *data);
    if (passes && depth == 0) {  // the colour passes: every layer the camera sees, by what reaches it
      Color colors[kColorKinds];
      bsdf.kind_colors(wo, colors);
      for (int k = 0; k < kColorKinds; ++k) passes->color[k] += beta * colors[k];
    }
    if (material.emits()) {
      uint32_t li = scene_.triangle_light(hit.instance, hit.prim);
      Light moved;
      const Light &light = scene_.light_now(li, moved);  // where the ray met it
      float pdf = light_pdf(light, prev_p, ray.d, length(hit.p - prev_p));
      if (shadows_allow(light, shadow_ray(prev_p, prev_ng, prev_error, hit.p, hit.ng, hit.error)))
        add_found(beta * Le * emission_weight(li, pdf), depth);
    }
    if (denoising && denoising->active) scene_.add_denoising_surface(bsdf, wo, hit.t, *denoising);
    if (depth == 0 && first_hit) {
      const Camera &cam = scene_.camera_now();
      first_hit->valid = true;
      first_hit->depth = dot(hit.p - cam.position(), cam.forward());
      first_hit->normal = bsdf.shading_normal(wo);  // a normal map's or bump's, as Cycles' Normal pass
      first_hit->albedo = bsdf.albedo(wo);
    }
    // Where the path may not scatter any more (a bounce limit), a plain transparent layer
    // (Scene::is_plain_layer) may still be passed: the lobe decides, as in BDPT's walks.
    const bool last = depth >= max_bounces_ || stop_after || transparent_passes > max_passes;
    if (!bsdf.has_lobes() || (last && !scene_.is_plain_layer(hit))) break;

    if (!last && !bsdf.is_delta()) {
      // With a caustics switch off, after a diffuse bounce only the share of f the switches
      // keep scatters (caustics_switches.h).
      const bool caustic_filter = limits_.caustics && !is_black(caustic.diffuse);
      auto surface = [&](Vec3 wi, float *pdf) {
        if (passes && depth == 0) first_split = bsdf.kind_split(wo, wi, false);
        const Color f = bsdf.eval_and_pdf(wo, wi, TransportMode::Radiance, *pdf);
        if (!limits_.caustics) return f;
        if (!caustic_filter) return f * caustic.other;
        const ScatterKind kind = bsdf.scatter_kind(wo, wi);
        return f * caustic.at_last(caustic_step(limits_, bsdf, wo, wi, false, kind, -1).kept);
      };
      auto scatter_kind = [&](Vec3 wi) { return visibility::after(bsdf.scatter_kind(wo, wi)); };
      if constexpr (kMedia) {
        // The shadow ray starts in the medium on wi's side: reflection stays in the
        // current one, transmission crosses into the other.
        auto media_toward = [&](Vec3 wi) {
          MediumStack s = stack;
          if (dot(wi, hit.ng) * dot(ray.d, hit.ng) > 0) s.cross(scene_, hit, boundary, wi);
          return s;
        };
        add(beta * sample_direct_light<true, kCatcher>(scene_, uint32_t(depth) + 1, hit.p, hit.ng, hit.error, surface,
                                             media_toward, scatter_kind, sampler, stats, catcher_only, shadow_layers()),
            depth + 1);
      } else {
        auto unused = [](Vec3) { return 0; };
        add(beta * sample_direct_light<false, kCatcher>(scene_, uint32_t(depth) + 1, hit.p, hit.ng, hit.error, surface, unused,
                                              scatter_kind, sampler, stats, catcher_only, shadow_layers()),
            depth + 1);
      }
    }

    BsdfSample bs;
    start_scatter(dims::kScatterLobe);
    float u_lobe = sampler.get_1d();
    Vec2 u = sampler.get_2d();
    // Under bounce limits the sample brings Cycles' odds that this bounce was glossy; its
    // defensive sampling floors the closures' weights at a camera path's first scattering
    // (no bounce or transparent pass before it).
    const Bsdf::Odds odds = !limits_.classify ? Bsdf::Odds::None
                            : depth == 0 && transparent_passes == 0 ? Bsdf::Odds::Defensive
                                                                    : Bsdf::Odds::Plain;
    if (!bsdf.sample(wo, u_lobe, u, TransportMode::Radiance, bs, odds) || (last && !bs.pass_through)) break;
    beta *= bs.weight;
    if (see_through) see_through = alpha_.keeps_seeing_through(bs);
    if (bs.pass_through) {
      // Straight through a transparent surface: not a bounce, and the MIS state of the
      // last scattering vertex stays (transparent shadows give NEE the same paths).
      if constexpr (kMedia) stack.cross(scene_, hit, boundary, ray.d);
      new_ray(Ray{spawn_origin(hit.p, hit.ng, hit.error, ray.d), ray.d, kInf, ray.mask});
      if (++boundary_crossings > 256 || is_black(beta)) break;
      if (!limits_.transparent_within(++transparent_passes, depth > 0)) break;  // nothing further counts
      ++crossings;
      layer_passed = true;
      --depth;
      continue;
    }
    if (passes && depth == 0) first_split = bsdf.kind_split(wo, bs.wi, bs.is_delta);
    uint32_t next_mask = visibility::kAnyRay;
    if (limits_.classify || classify_rays) {
      ScatterKind kind = bsdf.scatter_kind(wo, bs.wi);
      if (classify_rays) next_mask = visibility::after(kind);
      if (limits_.classify) {
        count_bounce(kind, bs.glossy_odds,
                     limits_.caustics ? caustic_step(limits_, bsdf, wo, bs.wi, bs.is_delta, kind, bs.glossy_odds,
                                                     !is_black(caustic.diffuse))
                                      : CausticStep{});
        if (limits_.caustics && is_black(caustic_found) && caustic.none()) break;
      }
    }
    specular_bounce = bs.is_delta;
    cone = cone.scattered(bs.cone_spread);  // wider after a rough bounce
    prev_pdf = bs.pdf;
    if (!bs.is_delta) filter.scattered(bs.pdf);
    prev_p = hit.p;
    prev_ng = hit.ng;
    prev_error = hit.error;
    if constexpr (kMedia) {
      if (dot(bs.wi, hit.ng) * dot(ray.d, hit.ng) > 0) stack.cross(scene_, hit, boundary, bs.wi);  // refracted through
    }
    new_ray(Ray{spawn_origin(hit.p, hit.ng, hit.error, bs.wi), bs.wi, kInf, next_mask});
    if (!russian_roulette(depth) || is_black(beta)) break;
  }
  if (first_hit) first_hit->transparency = transparency;
  if (kCatcher && catcher && !split) {  // no catcher met: all of it is the matte's
    catcher->matte = L;
    catcher->matte_transparency = transparency;
  }
  return L;
}

}  // namespace rdv
