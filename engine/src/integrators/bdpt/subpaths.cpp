// Camera and light subpaths: random walks that record each vertex with its forward
// density and, once the next direction is chosen, the reverse density of the vertex
// before it (pbrt-v3's RandomWalk), plus Russian roulette.
#include "core/ray_offset.h"
#include "integrators/bdpt/bdpt.h"
#include "lights/rectangle_lamp.h"
#include "lights/sphere_lamp.h"
#include "integrators/filter_glossy.h"
#include "integrators/visibility_clear.h"
#include "media/emission_gather.h"
#include "samplers/dimension_layout.h"

namespace rdv::bdpt {

bool PathVertex::connectible(const Scene &scene) const {
  switch (type) {
    case VertexType::Camera: return !delta;
    case VertexType::Light: return infinite || !light_is_delta_direction(scene.lights()[light]);
    case VertexType::Surface: return surface_connectible;
    case VertexType::Medium: return true;
  }
  return false;
}

// What turns a solid-angle density at a vertex into an area density at `to` (volume
// density at a volume light's point): scale (the cosine at a surface, or the gather
// rate of a volume light's point), given the unit direction d between them.
static float density_scale(const PathVertex &to, Vec3 d) {
  float scale = to.on_surface() ? absdot(to.ng, d) : 1.0f;
  return to.gather_rate > 0 ? scale * to.gather_rate : scale;
}

float PathVertex::convert_density(float pdf, const PathVertex &next) const {
  if (next.infinite) return pdf;
  Vec3 w = next.p - p;
  float d2 = length_squared(w);
  if (!(d2 > 0)) return 0;
  float inv_d2 = 1.0f / d2;
  return pdf * density_scale(next, w * std::sqrt(inv_d2)) * inv_d2;
}

void PathVertex::link_to_prev(const PathVertex &prev, float pdf_dir) {
  // One distance for both directions: prev -> this (pdf_fwd) and this -> prev.
  Vec3 w = p - prev.p;
  float d2 = length_squared(w);
  if (!(d2 > 0)) {
    pdf_fwd = 0;
    prev_scale = prev_inv_d2 = prev.infinite ? 1.0f : 0.0f;
    return;
  }
  float inv_d2 = 1.0f / d2;
  Vec3 d = w * std::sqrt(inv_d2);
  pdf_fwd = pdf_dir * density_scale(*this, d) * inv_d2;
  prev_scale = prev.infinite ? 1.0f : density_scale(prev, -d);
  prev_inv_d2 = prev.infinite ? 1.0f : inv_d2;
}

template <bool kMedia>
int Bdpt::random_walk(Ray ray, Sampler &sampler, RayStats &stats, Color beta, float pdf_fwd, int max_vertices,
                      TransportMode mode, PathVertex *path, Color *emitted, RayCone cone, DataPassSample *data,
                      bool see_through_only, bool catcher_copy) const {
  if (max_vertices <= 0) return 0;
  const float beta_start = std::max(max_component(beta), 1e-30f);
  MediumStack media = path[0].media;
  int n = 0, boundary_crossings = 0;
  // Lamps are transparent (Scene::nearest_lamp): past one, the ray goes on from the lamp's
  // point, not into the lamp it passed.
  int lamp_passed = -1;
  // Where each decision draws (samplers/dimension_layout.h): bounce k (the segment
  // leaving vertex k and the vertex k + 1 it reaches) draws from its block of the walk's
  // stream; its segments after `crossings` boundaries, lamps or plain layers from crossing
  // blocks, and once a layer has passed (layer_passed) its scattering decisions do too.
  const bool camera = mode == TransportMode::Radiance;
  const SampleStream stream = camera ? SampleStream::Camera : SampleStream::Light;
  const uint32_t layout_vertices = uint32_t(settings_.max_bounces) + 2;
  uint32_t k = 0, crossings = 0;
  bool layer_passed = false;
  auto start_scatter = [&](uint32_t offset) {
    const dims::SegmentDims d = layer_passed ? dims::segment(camera, k, crossings, layout_vertices, offset)
                                             : dims::SegmentDims{stream, dims::bounce(k, offset)};
    sampler.start_stream(d.stream, d.position);
  };
  // Plain transparent layers (Scene::is_plain_layer) are no path vertices: the walk passes
  // them as the path tracer does (a pass is no bounce) and connections see through them, so
  // every strategy makes the same paths, next-event estimation and connections included
  // (a point lamp or the sun behind an alpha-mapped leaf). `layers`: those passed since
  // path[n]. `colors_open`: the camera has not scattered yet; the colour passes take every
  // surface it meets until then (vertex or not), as the path tracer's camera ray does.
  int layers = 0;
  bool colors_open = camera && data;
  // Cycles' Light Paths: once a vertex's subpath is over a bounce limit (or breaks a
  // caustics switch), no longer subpath makes a path the limits keep, except, on camera
  // paths, the one more vertex where an emitter may be found (light_path_limits.cpp).
  const bool classify = settings_.limits.classify;
  // Filter Glossy (filter_glossy.h): camera walks blur each BSDF by the smallest density
  // so far, as the path tracer does; light walks sample unblurred and record what a
  // connection needs to tell whether the blur would have changed their vertices.
  FilterGlossy filter(settings_.limits.filter_glossy);
  // Transparent film: whether the camera still sees through (film_alpha.h).
  // The data passes (film/data_passes.h) follow the same chain.
  // A shadow catcher splits camera paths where that chain first meets one (shadow_catcher.cpp).
  bool see_through = camera && (settings_.alpha.tracked() || data || see_through_only || catchers_);
  // A catcher copy's rays meet shadow catchers only: a light walk's from its start, a
  // camera walk's from its split on.
  bool catcher_only = catcher_copy && !camera;
  // Ray visibility (scene/ray_visibility.h): camera paths trace each ray as the kind of
  // the scattering it leaves; light paths as any kind after a scattering (without mixed
  // visibility every instance is seen by all of them or by none).
  const bool classify_rays = scene_.has_ray_visibility();
  const bool instance_bits = classify_rays;
  auto ray_kind = [&](ScatterKind kind) {
    return !camera ? visibility::kNonCamera : classify_rays ? visibility::after(kind) : visibility::kAnyRay;
  };
  // Mixed visibility (bdpt.h): a camera walk tests each segment after its first for a
  // surface of mixed visibility, which no light walk passes (segment_cut: on an earlier
  // piece of it; the vertex it reaches takes it as light_cut); a light walk ends where it
  // would pass one, or where the vertex before is hidden from the kind of scattering found
  // at the new one.
  const bool test_cuts = mixed_ && camera;
  bool segment_cut = false;
  auto light_segment_hidden = [&](Vec3 wi) { return !camera && mixed_ && !light_walk_seen(path, n, wi); };
  // Transparent max bounces (light_path_limits.h): a walk stops where no path through its
  // passes could count; a camera walk that has only passed through, one past the limit,
  // goes on for one more vertex, an emitter the camera may see.
  const bool limited_passes = settings_.limits.transparent < LightPathLimits::kNoLimit;
  auto passes_end_walk = [&](int passes, bool scattered) {
    if (!settings_.limits.transparent_within(passes, !camera || scattered)) return true;
    if (passes > settings_.limits.transparent) max_vertices = std::min(max_vertices, n + 1);  // an emitter next
    return false;
  };
  // A new vertex's counts: the passes and scatterings on the walk before it.
  auto count_before = [&](PathVertex &v, const PathVertex &before) {
    v.passes = uint16_t(before.passes_after() + layers);
    v.scatterings = uint16_t(before.scatterings_after());
  };
  auto limits_end_walk = [&](Vec3 wi, bool delta) {
    if (record_kind(path, n, wi, camera, delta)) return false;
    if (camera) max_vertices = std::min(max_vertices, n + 1);
    return !camera;
  };
  auto russian_roulette = [&]() {
    if (n < 3) return true;
    float q = std::max(0.05f, 1.0f - max_component(beta) / beta_start);
    sampler.start_stream(stream, dims::bounce(k, dims::kRoulette));
    if (sampler.get_1d() < q) return false;
    beta *= 1.0f / (1.0f - q);
    return true;
  };
  while (true) {
    if (uint32_t(n) != k) {  // a new bounce (not a segment after a boundary or layer)
      k = uint32_t(n);
      crossings = 0;
      layer_passed = false;
      layers = 0;
      segment_cut = false;
    }
    PathVertex &prev = path[n];
    PathVertex &v = path[n + 1];
    SurfaceHit hit;
    CoincidentBoundary boundary;  // media: a medium boundary lying in the surface hit
    ++stats.rays;
    bool found;
    if (catcher_only) {
      Ray q = ray;
      q.mask = visibility::catcher_rays(ray.mask);
      found = kMedia ? scene_.intersect_media(q, hit, boundary) : scene_.intersect(q, hit);
    } else {
      found = kMedia ? scene_.intersect_media(ray, hit, boundary) : scene_.intersect(ray, hit);
    }
    float tmax = found ? hit.t : ray.tmax;
    // The nearest surface of mixed visibility on this piece before the surface met
    // (mixed_t), and whether that surface is one (hit_mixed: the segment ends there unless
    // the walk passes it). cut_before(t): the segment so far, up to distance t on this
    // piece, has one.
    float mixed_t = kInf;
    bool hit_mixed = false;
    if (test_cuts && n >= 1) {
      uint32_t instance = 0, prim = 0;
      float t = kInf;
      ++stats.rays;
      const uint32_t mixed_mask = catcher_only ? visibility::catcher_rays(visibility::kMixed) : visibility::kMixed;
      if (scene_.nearest_mixed(Ray{ray.o, ray.d, tmax, mixed_mask}, t, instance, prim)) {
        if (found && instance == hit.instance && prim == hit.prim) hit_mixed = true;
        else mixed_t = t;
      }
    }
    // A camera walk's segment leaving a look copy of mixed visibility: no light walk makes it
    // (it would have to make a vertex there, which light walks never do: below).
    const bool leaves_copy = test_cuts && prev.look_copy;
    auto cut_before = [&](float t) { return segment_cut || leaves_copy || mixed_t < t; };
    // Lamps a camera path passes (they are not in the BVH; light paths ignore them, as
    // lamps neither reflect nor block).
    // The denoising data (film/denoising_passes.h) take the emission the camera path finds
    // while their features are active, unweighted (as Cycles' path tracing finds it
    // through near-specular surfaces).
    DenoisingSample *const denoising = camera && data && data->denoising.active ? &data->denoising : nullptr;
    Color lamp_L;
    int lamp = mode == TransportMode::Radiance && (emitted || denoising)
                   ? scene_.nearest_lamp(ray, lamp_passed, tmax, lamp_L, catcher_only)
                   : -1;
    if constexpr (kMedia) {
      int m = media.current(scene_);
      if (m >= 0) {
        const Medium &medium = scene_.medium(m);
        if (emitted && medium.is_emissive()) {
          dims::SegmentDims g = dims::segment(camera, k, crossings, layout_vertices, dims::kGather);
          SampleRun gather_run(sampler, g.stream, g.position, dims::kGatherRun);
          gather_volume_emission(medium, ray, tmax, gather_run, beta, path, n, layers, pdf_fwd,
                                 segment_cut ? 0.0f : mixed_t, emitted[n]);
        }
        // The denoising albedo takes the segment's share before the path flies through it.
        if (denoising) scene_.add_denoising_volume(medium, ray.o, ray.d, tmax, beta, *denoising);
        dims::SegmentDims f = dims::segment(camera, k, crossings, layout_vertices, dims::kMedium);
        SampleRun run(sampler, f.stream, f.position, dims::kMediumRun);
        MediumSample ms = medium.sample_distance(ray.o, ray.d, tmax, run);
        beta *= ms.weight;
        if (is_black(beta)) return n;
        if (ms.scattered) {
          fresh_vertex(v);
          v.type = VertexType::Medium;
          count_before(v, prev);
          v.p = ray.o + ray.d * ms.t;
          v.wo = -ray.d;
          v.beta = beta;
          v.medium = m;
          v.light_cut = cut_before(ms.t);
          v.specularity = std::fabs(medium.phase.g);  // forward (or back) scattering: specular-like
          v.media = media;
          v.link_to_prev(prev, pdf_fwd);
          if (camera) v.filter_pdf = filter.min_pdf;
          see_through = false;
          colors_open = false;
          if (denoising) denoising->end_at_volume_scatter();
          ++n;
          if (n >= max_vertices || see_through_only) return n;
          start_scatter(dims::kScatterDirection);
          Vec3 wi = medium.phase.sample(v.wo, sampler.get_2d());
          pdf_fwd = medium.phase.pdf(v.wo, wi);  // the phase function is symmetric
          if (filter.on()) {
            if (camera) filter.scattered(pdf_fwd);
            else v.filter_pdf = pdf_fwd;
          }
          if (classify && limits_end_walk(wi, false)) return n;
          if (light_segment_hidden(wi)) return n;
          prev.pdf_rev = v.to_prev_density(pdf_fwd);
          if (mode == TransportMode::Radiance && n >= 2) set_mis_sum(path, n - 1, path[n - 2].delta, balance());
          ray = Ray{v.p, wi, kInf, ray_kind(ScatterKind::Volume)};
          v.out_mask = ray.mask;
          lamp_passed = -1;
          if (mode == TransportMode::Radiance) cone = cone.after(ms.t).scattered(kRoughConeSpread);
          if (!russian_roulette()) return n;
          continue;
        }
      }
    }
    if (lamp >= 0) {
      // The path that ends on the lamp (s = 0), weighted here; the walk goes on past it.
      Vec3 q = ray.o + ray.d * tmax;
      if (emitted)
        emitted[n] += lamp_emission(lamp, q, -ray.d, lamp_L, beta, path, n, layers, pdf_fwd, cut_before(tmax), stats,
                                    catcher_only);
      segment_cut = cut_before(tmax);
      if (denoising) denoising->add_emission(beta * lamp_L);
      if (++boundary_crossings > 256) return n;
      ++crossings;
      cone = cone.after(tmax);
      ray = Ray{q, ray.d, kInf, ray.mask};
      lamp_passed = lamp;
      continue;
    }
    if (!found) {
      // The world; with a transparent film, also where there is none (the alpha it leaves).
      const bool transparent_world = see_through && settings_.alpha.film_transparent;
      if (see_through && data) scene_.add_world_data_passes(ray.d, *data);
      if (mode == TransportMode::Radiance && (!scene_.infinite_lights().empty() || transparent_world)) {
        fresh_vertex(v);
        v.type = VertexType::Light;
        v.infinite = true;
        v.light_cut = cut_before(kInf);
        count_before(v, prev);
        v.see_through = see_through;
        v.dir = ray.d;
        v.wo = -ray.d;
        v.beta = beta;
        v.pdf_fwd = pdf_fwd;  // infinite lights keep solid-angle densities
        if (denoising) denoising->add_emission(beta * Le(v, prev, stats));
        ++n;
      }
      return n;
    }
    if constexpr (kMedia) {
      if (scene_.is_boundary_only(hit.material)) {  // an index-matched boundary: no vertex
        media.cross(scene_, hit, boundary, ray.d);
        segment_cut = cut_before(kInf);
        ray = Ray{spawn_origin(hit.p, hit.ng, hit.error, ray.d), ray.d, kInf, ray.mask};
        lamp_passed = -1;
        if (++boundary_crossings > 256) return n;
        ++crossings;
        continue;
      }
    }
    // A light walk ends at a look copy of mixed visibility: which kind of ray the segment
    // reaching it is, and so whether it meets this copy or another of the object's on the
    // same spot, is known only once the walk has scattered on; a vertex here would be on the
    // copy the BVH happened to report.
    const bool on_look_copy = mixed_ && scene_.ends_light_walks(hit.instance);
    if (on_look_copy && !camera) return n;
    const Material &material = scene_.material(hit.material);
    fresh_surface_vertex(v, hit, ray.d, boundary, media);  // boundary: none without media
    v.look_copy = on_look_copy;
    count_before(v, prev);
    v.beta = beta;
    v.light_cut = cut_before(kInf);
    v.see_through = see_through;
    if (settings_.alpha.holdouts) v.holdout = scene_.holdout_weight(hit);
    if (instance_bits) v.visibility = scene_.instance_visibility(hit.instance);
    v.bsdf = scene_.bsdf(hit, v.wo, cone.width_at(hit.t), &v.emitted);
    cone = cone.after(hit.t);
    if (material.emits()) v.light = int(scene_.triangle_light(hit.instance, hit.prim));
    if (catchers_ && scene_.is_shadow_catcher(hit.instance) && !scene_.is_holdout_instance(hit.instance)) {
      v.catcher = true;
      if (catcher_copy && see_through) catcher_only = true;  // a copy's split: catchers only from here on
    }
    if (see_through && v.holdout >= 1) {  // all held out where the camera sees it: nothing of it is seen
      v.bsdf = Bsdf(hit.ng, hit.ns, v.wo);
      v.emitted = Color(0.0f);
      v.light = -1;
    } else if (see_through && data) {
      scene_.add_data_passes(hit, beta, settings_.alpha.pass_alpha_threshold, *data);
    }
    if (filter.on()) {
      if (camera) {
        v.filter_pdf = filter.min_pdf;
        const float alpha = filter.alpha();
        if (v.bsdf.blur_changes(alpha)) {
          v.bsdf.blur(alpha);
          v.blurred = true;
        }
      } else {
        v.blur_threshold = v.bsdf.blur_threshold();
      }
    }
    if (colors_open) {
      Color colors[kColorKinds];
      v.bsdf.kind_colors(v.wo, colors);
      for (int c = 0; c < kColorKinds; ++c) data->colors[c] += beta * colors[c];
    }
    if (denoising) {
      if (v.light >= 0) denoising->add_emission(beta * Le(v, prev, stats));
      scene_.add_denoising_surface(v.bsdf, v.wo, hit.t, *denoising);
    }
    // A plain layer decides first whether the walk passes it (even where a vertex would
    // be the walk's last: the path tracer passes it there too).
    BsdfSample bs;
    bool sampled = false;
    if (scene_.is_plain_layer(hit) && v.bsdf.has_lobes()) {
      start_scatter(dims::kScatterLobe);
      const float u_lobe = sampler.get_1d();
      sampled = v.bsdf.sample(v.wo, u_lobe, sampler.get_2d(), mode, bs);
      if (sampled && bs.pass_through) {
        if (mixed_ && !camera && visibility::is_mixed(scene_.instance_visibility(hit.instance))) return n;
        segment_cut = cut_before(kInf) || hit_mixed;
        beta *= bs.weight;
        if constexpr (kMedia) media.cross(scene_, hit, boundary, ray.d);
        ray = Ray{spawn_origin(hit.p, hit.ng, hit.error, ray.d), ray.d, kInf, ray.mask};
        lamp_passed = -1;
        if (++boundary_crossings > 256 || is_black(beta)) return n;
        ++crossings;
        ++layers;
        layer_passed = true;
        if (limited_passes && passes_end_walk(prev.passes_after() + layers, prev.scatterings_after() > 0)) return n;
        continue;
      }
      // Kept as a vertex only when the walk does not pass: what the vertex itself adds
      // (its connections) is divided by that probability.
      const float pass = v.bsdf.pass_probability(v.wo);
      if (pass > 0 && pass < 1) v.beta = v.beta / (1 - pass);
    }
    v.link_to_prev(prev, pdf_fwd);
    v.surface_connectible = v.bsdf.has_lobes() && !v.bsdf.is_delta();
    if (settings_.mis == MisHeuristic::LafortuneWillems) v.specularity = v.bsdf.specularity();
    ++n;
    if (n >= max_vertices || !v.bsdf.has_lobes()) return n;

    if (!sampled) {
      start_scatter(dims::kScatterLobe);
      const float u_lobe = sampler.get_1d();
      if (!v.bsdf.sample(v.wo, u_lobe, sampler.get_2d(), mode, bs)) return n;
    }
    if (classify && limits_end_walk(bs.wi, bs.is_delta)) return n;
    if (light_segment_hidden(bs.wi)) return n;
    // A vertex passed through (not a plain layer).
    if (limited_passes && bs.pass_through && passes_end_walk(v.passes + 1, v.scatterings > 0)) return n;
    if (!bs.pass_through) colors_open = false;
    beta *= bs.weight;
    if (see_through) see_through = settings_.alpha.keeps_seeing_through(bs);
    // The first-hit pass (see_through_only) goes on while the denoising data look for
    // their surface.
    if (see_through_only && !see_through && !(data && data->denoising.active)) return n;
    float pdf_rev;
    if (bs.is_delta) {
      v.delta = true;
      v.passed_through = bs.pass_through;
      if (camera) v.one_way = !v.bsdf.same_frame_both_ways(v.wo, bs.wi);
      pdf_fwd = pdf_rev = 0;
    } else {
      pdf_fwd = bs.pdf;
      pdf_rev = v.bsdf.pdf(bs.wi, v.wo);
      if (filter.on()) {
        if (camera) filter.scattered(bs.pdf);
        else v.filter_pdf = pdf_rev;
      }
    }
    prev.pdf_rev = v.to_prev_density(pdf_rev);
    // Camera subpaths: the MIS sum up to prev (the camera vertex itself is no strategy);
    // light subpaths sum theirs once complete (light_subpath).
    if (mode == TransportMode::Radiance && n >= 2) set_mis_sum(path, n - 1, path[n - 2].delta, balance());
    if constexpr (kMedia) {
      if (dot(bs.wi, hit.ng) * dot(ray.d, hit.ng) > 0) media.cross(scene_, hit, boundary, bs.wi);  // refracted through
    }
    // A pass through a transparent surface keeps the ray's kind.
    ray = Ray{spawn_origin(hit.p, hit.ng, hit.error, bs.wi), bs.wi, kInf,
              bs.pass_through                ? ray.mask
              : camera && classify_rays ? ray_kind(v.bsdf.scatter_kind(v.wo, bs.wi))
                                        : ray_kind(ScatterKind::Transparent)};
    v.out_mask = ray.mask;
    lamp_passed = -1;
    // Camera paths: wider after a rough bounce, as in the path tracer. Light paths
    // carry no cone (unfiltered lookups).
    if (mode == TransportMode::Radiance) cone = cone.scattered(bs.cone_spread);

    // Russian roulette on the throughput relative to the subpath's start. The MIS
    // densities leave it out, as is usual: the weights still sum to one.
    if (!russian_roulette() || is_black(beta)) return n;
  }
}

// A lamp the camera path passes at q (toward wo): the path that ends there (s = 0,
// t = n + 2), MIS-weighted against the strategies that start a light subpath there. The
// lamp point stands in for the next vertex while its weight is computed; the walk then
// goes on through the lamp, so the vertex is overwritten.
Color Bdpt::lamp_emission(int lamp, Vec3 q, Vec3 wo, Color Le, Color beta, PathVertex *path, int n, int layers,
                          float pdf_dir, bool light_cut, RayStats &stats, bool catcher_only) const {
  const Light &light = scene_.lights()[lamp];
  const PathVertex &prev = path[n];
  PathVertex &point = fresh_vertex(path[n + 1]);
  point.type = VertexType::Light;
  point.light = lamp;
  point.p = q;
  point.ng = point.ns = light.type == LightType::Area ? light.axis
                        : is_sphere_lamp(light)        ? normalize(q - light.position)
                                                       : Vec3(0.0f);
  point.wo = wo;
  point.beta = beta;
  point.emitted = Le;
  point.pdf_fwd = prev.convert_density(pdf_dir, point);
  point.light_cut = light_cut;
  Color c = beta * Le;
  if (n == 0) return c;  // seen straight from the camera: s = 0, t = 2 is the only strategy
  // Mixed visibility: the segment from the scattering vertex is blocked by shadow casters.
  const uint32_t occluders = catcher_only ? visibility::catcher_rays(light.occluders()) : light.occluders();
  if (mixed_ && !visibility_clear(scene_, shadow_ray(prev.p, prev.ng, prev.error, q, Vec3(0.0f), Vec3(0.0f)),
                                             occluders, false, stats.rays))
    return Color(0.0f);
  const LightPathLimits &limits = settings_.limits;
  constexpr ScatterKind kNone = ScatterKind::Transparent;
  const Color kept = limits.classify ? limits_share(path, path, 0, n + 2, kNone, kNone) : Color(1.0f);
  if (is_black(kept)) return Color(0.0f);
  c *= kept;
  const int scatterings = path[n].scatterings_after();
  if (!limits.transparent_within(path[n].passes_after() + layers, scatterings > 0)) return Color(0.0f);
  bool one_strategy = settings_.strategy_s >= 0;
  if (one_strategy && (settings_.strategy_s != 0 || settings_.strategy_t != n + 2)) return Color(0.0f);
  ConnectionDensities d;
  light_densities(point, prev, d.pt_rev, d.pt_minus_rev);
  float w = mis_weight(path, path, point, 0, n + 2, d);  // s = 0 reads no light vertex
  if (one_strategy && settings_.strategy_unweighted) return c;
  return limits.clamps ? limits.clamp(c * w, scatterings) : c * w;
}

// Emission of the medium along a camera path's segment (s = 0 strategies ending inside
// a volume): each gathered point is a path ending at a volume light's point, MIS-weighted
// against the strategies that sample that point from the light. The point stands in
// for the next vertex while its weight is computed.
void Bdpt::gather_volume_emission(const Medium &medium, const Ray &ray, float tmax, SampleRun &rng, Color beta,
                                  PathVertex *path, int n, int layers, float pdf_dir, float cut_from,
                                  Color &emitted) const {
  const PathVertex &prev = path[n];
  PathVertex &point = path[n + 1];
  const LightPathLimits &limits = settings_.limits;
  const Color kept = limits.classify && n > 0
                         ? limits_share(path, path, 0, n + 2, ScatterKind::Transparent, ScatterKind::Transparent)
                         : Color(1.0f);
  if (is_black(kept)) return;
  beta *= kept;
  const int scatterings = path[n].scatterings_after();
  if (!limits.transparent_within(path[n].passes_after() + layers, scatterings > 0)) return;
  const bool one_strategy = settings_.strategy_s >= 0;  // the debug view of one strategy (s, t)
  if (one_strategy && (settings_.strategy_s != 0 || settings_.strategy_t != n + 2)) return;
  gather_emission(medium, ray.o, ray.d, tmax, rng, [&](Vec3 x, Color c, float rate) {
    float w = 1;
    if (rate > 0 && n > 0) {  // seen straight from the camera: s = 0, t = 2 is the only strategy
      point.type = VertexType::Light;
      point.light = medium.light;
      point.infinite = false;
      point.p = x;
      point.ng = point.ns = Vec3(0.0f);
      point.gather_rate = rate;
      point.pdf_fwd = prev.convert_density(pdf_dir, point);
      point.light_cut = !(length(x - ray.o) < cut_from);
      ConnectionDensities d;
      light_densities(point, prev, d.pt_rev, d.pt_minus_rev);
      w = mis_weight(path, path, point, 0, n + 2, d);  // s = 0 reads no light vertex
      if (one_strategy && settings_.strategy_unweighted) w = 1;
    }
    emitted += limits.clamps ? limits.clamp(beta * c * w, scatterings) : beta * c * w;
  });
}

template <bool kMedia>
int Bdpt::camera_subpath(const CameraRay &cr, Sampler &sampler, RayStats &stats, PathVertex *path,
                         Color *emitted, int max_vertices, DataPassSample *data, bool see_through_only,
                         bool catcher_copy) const {
  const Camera &camera = scene_.camera_now();
  PathVertex &v = path[0];
  fresh_vertex(v);
  v.type = VertexType::Camera;
  v.p = cr.lens_point;
  v.beta = Color(1.0f);
  if constexpr (kMedia) v.media = MediumStack::for_camera(scene_);
  float pdf_pos = 0, pdf_dir = 0;
  camera.importance_pdf(Ray{cr.lens_point, cr.ray.d, kInf}, pdf_pos, pdf_dir);
  // Light paths cannot reach an orthographic camera, nor a ray leaving the image
  // (the pixel filter reaches 1.5 px past the border): no t = 1 strategy there.
  v.delta = pdf_dir == 0;
  if (pdf_dir == 0) pdf_dir = 1;
  int walk = max_vertices >= 0 ? max_vertices - 1 : settings_.max_bounces + 1;
  Ray ray = cr.ray;
  ray.mask = v.out_mask = visibility::kCamera;  // camera rays see what is visible to the camera
  return 1 + random_walk<kMedia>(ray, sampler, stats, Color(1.0f), pdf_dir, walk, TransportMode::Radiance, path,
                                 emitted, cr.cone, data, see_through_only, catcher_copy);
}

template <bool kMedia>
int Bdpt::light_subpath(Sampler &sampler, RayStats &stats, PathVertex *path, int max_vertices,
                        bool catcher_copy) const {
  const Distribution1D &dist = scene_.light_distribution();
  sampler.start_stream(SampleStream::Light, dims::kLightChoice);
  float u_light = sampler.get_1d();
  Vec2 u_pos = sampler.get_2d(), u_dir = sampler.get_2d();
  if (dist.size() == 0 || dist.total() <= 0) return 0;
  float pmf;
  uint32_t index = uint32_t(dist.sample_discrete(u_light, &pmf));
  Light moved;
  const Light &light = scene_.light_now(index, moved);  // a moving emitter at the sample's time
  if (catcher_copy && !light.shadow_catcher) return 0;  // the synthetic objects' light: not the catcher pass's
  Vec3 u_volume(0.0f);
  if (light.type == LightType::Volume)
    u_volume = dims::volume_point(sampler, SampleStream::Light, dims::kLightVolumePoint);
  EmissionSample es;
  if (!scene_.sample_emission(index, u_pos, u_dir, u_volume, es)) return 0;
  if (!(es.pdf_pos > 0) || !(es.pdf_dir > 0) || (is_black(es.Le) && !light.by_distance)) return 0;
  // Emissive triangles are in the BVH: leave them as any surface is left.
  Ray ray = es.ray;
  ray.mask = visibility::kNonCamera;
  if (light.type == LightType::Triangle) ray.o = spawn_origin(ray.o, light.axis, light.error, ray.d);
  PathVertex &v = path[0];
  fresh_vertex(v);
  v.type = VertexType::Light;
  v.light = int(index);
  v.p = es.ray.o;
  v.ng = v.ns = es.n;
  if (light.type == LightType::Triangle) v.error = light.error;
  v.beta = es.Le;
  v.pdf_fwd = pmf * es.pdf_pos;
  v.infinite = light.is_infinite();
  if (v.infinite) {
    v.dir = -es.ray.d;
    v.ng = v.ns = Vec3(0.0f);
  }
  if constexpr (kMedia) {
    // The media the lamp sits in (infinite lights shine from outside everything).
    // Found once per commit unless a medium boundary passes through the lamp.
    if (!v.infinite) {
      if (const std::vector<int> *media = scene_.light_media(index)) v.media = MediumStack::from(*media);
      else v.media = MediumStack::from(scene_.media_along(ray.o, ray.d));
    }
    // A volume light's point emits only inside its medium.
    if (light.type == LightType::Volume) {
      const int m = light.volume->medium_index();
      if (v.media.current(scene_) != m) return 0;
      v.gather_rate = 1.0f / scene_.medium(m).emission_step;
    }
  }
  float cos_emit = is_black(es.n) ? 1.0f : absdot(es.n, es.ray.d);
  // A light whose emission depends on the distance its light travels (Light Falloff) walks
  // without it; the walk's vertices take it once the first segment is known (Russian
  // roulette is relative to the start, so its decisions do not change).
  Color beta = (light.by_distance ? Color(1.0f) : es.Le) * (cos_emit / (pmf * es.pdf_pos * es.pdf_dir));
  int walk = max_vertices >= 0 ? max_vertices - 1 : settings_.max_bounces;
  int n = random_walk<kMedia>(ray, sampler, stats, beta, es.pdf_dir, walk, TransportMode::Importance, path, nullptr,
                              {}, nullptr, false, catcher_copy);
  if (light.by_distance && n > 0) {
    const Color Le = scene_.light_radiance(light, v.p, es.n, es.ray.d, path[1].p);
    for (int k = 1; k <= n; ++k) path[k].beta *= Le;
  }
  if (v.infinite) {
    // Infinite lights: the first hit's density is the planar one of the emission disk,
    // and the light vertex's own density is directional.
    if (n > 0) {
      path[1].pdf_fwd = es.pdf_pos;
      if (path[1].on_surface()) path[1].pdf_fwd *= absdot(es.ray.d, path[1].ng);
    }
    v.pdf_fwd = infinite_light_density(v.dir);
  } else if (n > 0 && (is_sphere_lamp(light) || is_rectangle_lamp(light))) {
    // A lamp's sphere, a square or rectangle: next-event estimation's density for its
    // point, the rest moved to the first vertex, as every strategy reckons it
    // (Bdpt::split_next_event_density).
    split_next_event_density(light, v, path[1].p, v.pdf_fwd, path[1].pdf_fwd);
  }
  // The MIS sums, now that every density is final (the last vertex's is never read).
  set_mis_sum(path, 0, light_start_is_delta(path[0]), balance());
  for (int k = 1; k < n; ++k) set_mis_sum(path, k, path[k - 1].delta, balance());
  return n + 1;
}

template int Bdpt::camera_subpath<false>(const CameraRay &, Sampler &, RayStats &, PathVertex *, Color *, int,
                                         DataPassSample *, bool, bool) const;
template int Bdpt::camera_subpath<true>(const CameraRay &, Sampler &, RayStats &, PathVertex *, Color *, int,
                                        DataPassSample *, bool, bool) const;
template int Bdpt::light_subpath<false>(Sampler &, RayStats &, PathVertex *, int, bool) const;
template int Bdpt::light_subpath<true>(Sampler &, RayStats &, PathVertex *, int, bool) const;

}  // namespace rdv::bdpt
