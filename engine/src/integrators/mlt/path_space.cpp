// Explicit paths: sampling them from either end, their contribution f and the
// densities of every vertex (path_space.h), and Veach's bidirectional mutation.
#include "integrators/mlt/path_space.h"
#include <algorithm>
#include <cmath>
#include "core/ray_offset.h"
#include "core/sampling.h"
#include "integrators/mlt/free_flights.h"
#include "lights/light.h"
#include "lights/sphere_lamp.h"
#include "lights/volume_light.h"
#include "media/medium_stack.h"
#include "scene/motion.h"

namespace rdv::mlt {

using bdpt::PathVertex;
using bdpt::VertexType;

void ExplicitPath::reserve(int max_vertices) {
  const size_t n = size_t(max_vertices);
  if (x.size() >= n) return;
  x.resize(n);
  fwd.assign(n, 0.0);
  rev.assign(n, 0.0);
  rev_area.assign(n, 0.0);
  fwd_area.assign(n, 0.0);
}

namespace {

float cosine_at(const PathVertex &v, Vec3 w) { return v.on_surface() ? absdot(v.ng, w) : 1.0f; }

// An orthographic camera without depth of field: its direction is a delta along the view
// axis and x_0 is x_1's foot (with depth of field x_0 is a point of its own, as a lens's).
bool orthographic_pinhole(const Camera &camera) {
  return camera.type == Camera::Type::Orthographic && !(camera.aperture_radius > 0);
}

// A point inside a medium: a scattering vertex, or a point of an emissive medium that is
// a volume light (its light vertex, medium set).
bool in_medium(const PathVertex &v) {
  return v.type == VertexType::Medium || (v.type == VertexType::Light && v.medium >= 0);
}

// The direction from a toward b: a light at infinity is a direction (the state holds it,
// not a point), the same from wherever its neighbour is.
Vec3 toward(const ExplicitVertex &a, const ExplicitVertex &b) {
  return b.v.infinite ? b.v.dir : normalize(b.v.p - a.v.p);
}

// How far a vertex's position may be from where the ray that found its neighbour (or the
// neighbour itself) took it: a surface point's spawn offset along its normal
// (core/ray_offset.h) plus a few roundings of its coordinates.
float position_uncertainty(const PathVertex &v) {
  const float offset = std::fabs(v.ng.x) * v.error.x + std::fabs(v.ng.y) * v.error.y + std::fabs(v.ng.z) * v.error.z;
  return offset + 4 * kUlp * max_abs_component(v.p);
}

// Whether an edge at a specular vertex is too short for its direction to be read from the
// two positions: Bsdf::delta_eval matches an event to about 4.5e-3 rad, and an edge of
// length d is known to (uncertainty / d) rad. A walk's free flight that stops 3e-5 from the
// glass it left (about 1e-6 of spawn offset) points 0.03 rad off the event it sampled, so
// f (the event checked from the camera side) and the light-side density (checked from the
// other) disagreed: a path sampled with density ~1 / d^2 was scored as if sampled only by
// its other splits (q too small by 1e10 on the volume caustic with a lamp sphere: b 13,800
// where it is 290). Path space leaves such paths out (f = 0): within 1024 uncertainties
// (1.2-1.6 mm on the volume caustic's ball) the direction is known to 1e-3 rad, beyond it the
// walks and the densities agree.
bool too_short_at_specular(const PathVertex &a, const PathVertex &b, float distance) {
  if (!a.delta && !b.delta) return false;
  return distance < 1024.0f * (position_uncertainty(a) + position_uncertainty(b));
}

// Veach's preference for short deletions (1997, sec. 11.4.2): one vertex (kd = 2 edges)
// most, one edge half as much, then halving with every edge more.
double deletion_weight(int kd) { return kd == 1 ? 0.5 : std::ldexp(1.0, -(kd - 2)); }
// Valid positions of a deletion of kd edges on a path of nv vertices: l in -1 .. nv - kd,
// but never the edge before the camera or after the light alone (kd = 1 at the ends).
int deletion_positions(int nv, int kd) { return nv - kd + 2 - (kd == 1 ? 2 : 0); }

// A kept distance (Pauly's retrace) measured from a vertex, re-measured from its ray's
// origin `offset` further along (a spawn offset, a lens point, a medium boundary crossed).
// One shorter than that offset (a vertex within it of the one before, which equiangular
// distances toward a lamp next to a scattering point make often) cannot be kept: the
// proposal fails rather than draw a new distance, which its ratio would not account for.
constexpr float kNotKeepable = -2.0f;
float kept_past(float kept_flight, float offset) {
  if (kept_flight < 0) return kept_flight;
  return kept_flight >= offset ? kept_flight - offset : kNotKeepable;
}

// Veach's E S* D: the index of x's first vertex after the camera that is not specular.
// Pauly's retrace (PathSpace: keep_distances): the distance a retraced medium vertex x_i keeps
// from its neighbour on the side the retrace comes from; -1 (a free flight is drawn) when the
// proposal does not keep distances or x_i is no medium vertex.
float kept_distance(const ExplicitPath &x, int i, int from, bool keep) {
  const ExplicitVertex &v = x.x[size_t(i)];
  return keep && v.v.type == VertexType::Medium ? length(v.v.p - x.x[size_t(from)].v.p) : -1.0f;
}

// Never NaN, Inf or a negative value into a splat or the acceptance ratio.
Color finite_or_black(Color c) { return is_finite(c) && c.x >= 0 && c.y >= 0 && c.z >= 0 ? c : Color(0.0f); }

int first_non_specular(const ExplicitPath &x) {
  int c = 1;
  while (c < x.n - 1 && x.x[size_t(c)].v.delta) ++c;
  return c;
}

// A direction turned from w by theta ~ 1 / theta on [lo, hi] and a uniform azimuth: a
// density in solid angle that depends on the angle between the two only (symmetric).
Vec3 turned(Vec3 w, float lo, float hi, float u_size, float u_azimuth) {
  const float theta = lo * std::pow(hi / lo, u_size), phi = 2 * kPi * u_azimuth;
  return normalize(Frame(w).to_world(
      Vec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta))));
}

}  // namespace

double split_sum(const ExplicitPath &y, int lo, int count) {
  // A split connects vertices lo + j - 1 and lo + j; none can at a specular vertex.
  auto connectible = [&](int k) {
    const bool a = k - 1 >= 0 && y.x[size_t(k - 1)].v.delta, b = k < y.n && y.x[size_t(k)].v.delta;
    return !a && !b;
  };
  // A_(j+1) = A_j rev_j + prod_(i <= j) fwd_i: the sum over the splits of the first j vertices.
  const double *fwd = y.fwd.data(), *rev = y.rev.data();
  double a = connectible(lo) ? 1 : 0, prefix = 1;
  for (int i = 0; i < count; ++i) {
    prefix *= fwd[lo + i];
    a = a * rev[lo + i] + (connectible(lo + i + 1) ? prefix : 0.0);
  }
  return a;
}

PathSpace::PathSpace(const Scene &scene, int max_bounces, Vec2 sample_origin, Vec2 sample_size, float image_area,
                     float large_step_probability, const MutationSettings &mutations,
                     const LightPathLimits &limits)
    : scene_(scene),
      max_vertices_(max_bounces + 2),
      min_vertices_(mutations.min_vertices),
      sample_origin_(sample_origin),
      sample_size_(sample_size),
      image_area_(image_area),
      region_area_(sample_size.x * sample_size.y),
      large_step_probability_(large_step_probability),
      mutations_(mutations),
      limits_(limits),
      filter_(limits.filter_glossy),
      media_(scene.has_media()),
      layers_(scene.has_transparency()),
      motion_(scene.has_motion()),
      visibility_(scene.has_ray_visibility()),
      mixed_visibility_(scene.has_mixed_visibility()) {
  for (uint32_t i = 0; i < uint32_t(scene.lights().size()); ++i) {
    const Light &light = scene.lights()[i];
    if (is_sphere_lamp(light) || light.type == LightType::Area) hittable_lamps_.push_back(i);
    if (light.is_infinite() && !light_is_delta_direction(light)) {
      if (infinite_light_ < 0) infinite_light_ = int(i);
      infinite_lights_.push_back(i);
    }
  }
  // Without media the medium perturbations could only fail (a property of the scene, not
  // of a state: the mutation probabilities stay fixed).
  if (!media_) mutations_.weights[2] = mutations_.weights[3] = 0;
  if (media_ && mutations_.equiangular > 0) {
    bool scattering = false;
    for (int m = 0; m < scene.num_media(); ++m) scattering |= medium_scatters(scene.medium(m));
    for (uint32_t i = 0; scattering && i < uint32_t(scene.lights().size()); ++i) {
      const Light &light = scene.lights()[i];
      if (light.type == LightType::Point || light.type == LightType::Spot)
        equiangular_.add(light.position, double(scene.light_distribution().pmf(i)));
    }
    equiangular_.finish(mutations_.equiangular);
  }
  caustic_weight_ = mutations_.weights[4];
  multi_chain_weight_ = mutations_.weights[5];
  set_specular_paths(true);
}

void PathSpace::set_specular_paths(bool found) {
  mutations_.weights[4] = found ? caustic_weight_ : 0.0f;
  mutations_.weights[5] = found ? multi_chain_weight_ : 0.0f;
  float sum = 0;
  for (float w : mutations_.weights) sum += w;
  if (!(sum > 0)) mutations_.weights[0] = 1;  // only mutations that could not apply: the bidirectional one
}

std::string PathSpace::unsupported(const Scene &scene, const RenderSettings &settings) {
  // A clamp caps one sample's estimate (f / p of one strategy, MIS-weighted), which depends
  // on how the path was sampled; a Metropolis chain's f is a function of the path alone,
  // with no estimate to cap (docs/mlt.md). pssmlt / mmlt clamp BDPT's estimates.
  if (settings.limits.clamps)
    return "Light Paths clamps (clamp_direct / clamp_indirect) cap one sample's estimate, which a path-space chain "
           "does not have (its f is a function of the path alone); switch them off (0) or use bdpt, pssmlt or mmlt";
  for (size_t i = 0; i < scene.lights().size(); ++i) {
    const Light &l = scene.lights()[i];
    const std::string which = "light " + std::to_string(i);
    // Ray visibility elsewhere in the scene is f's and the walks' (each edge by its kind of
    // ray); an emissive volume's own object hidden from some kinds is not modelled.
    if (l.type == LightType::Volume && scene.has_ray_visibility() && l.visibility != visibility::kAll)
      return which + " (medium '" + l.volume->medium().name +
             "') is an emissive volume whose object has ray visibility settings; mlt does not apply those to volume "
             "emission (use bdpt or pssmlt, or make the object visible to every kind of ray)";
  }
  for (int m = 0; m < scene.num_media(); ++m) {
    const Medium &medium = scene.medium(m);
    // Emission outside any mesh (the world's volume) is no light source: BDPT gathers it
    // from camera paths only, and a path-space state needs a light vertex to end at.
    if (medium.is_emissive() && medium.light < 0)
      return "medium '" + medium.name +
             "' emits light outside any mesh (the world's volume); mlt samples emissive media inside meshes only "
             "(use bdpt or pssmlt, or give the emission to a mesh's volume)";
  }
  return "";
}

// ---- Sampling ----

int PathSpace::first_lamp(Vec3 o, Vec3 d, float tmax, float &t, uint32_t mask) const {
  int first = -1;
  for (uint32_t index : hittable_lamps_) {
    const Light &light = scene_.lights()[index];
    if (!(light.visibility & mask)) continue;  // hidden from this kind of ray
    float t_lamp;
    Color radiance;  // emitted() evaluates it
    if (is_sphere_lamp(light) ? intersect_sphere_lamp(light, o, d, tmax, t_lamp)
                              : intersect_light(light, Ray{o, d, tmax}, tmax, t_lamp, radiance)) {
      first = int(index);
      tmax = t = t_lamp;
    }
  }
  return first;
}

float PathSpace::sample_distance(const Medium &medium, const Ray &ray, float segment, Side side, Pcg32 &rng) const {
  if (side == Side::Light || !equiangular_.on() || !medium_scatters(medium))
    return sample_free_flight(medium, ray.o, ray.d, segment, rng);
  if (rng.next_float() >= float(equiangular_.share())) return sample_free_flight(medium, ray.o, ray.d, segment, rng);
  const float u_lamp = rng.next_float(), u = rng.next_float();
  const float t = equiangular_.sample(ray.o, ray.d, u_lamp, u);
  return t < segment ? t : -1.0f;
}

bool PathSpace::trace_step(Ray ray, MediumStack media, Side side, Pcg32 &rng, RayStats &stats, ExplicitVertex &z,
                           bool to_light, float kept_flight) const {
  if (!is_finite(ray.o) || !is_finite(ray.d) || !(length_squared(ray.d) > 0)) return false;
  if (kept_flight == kNotKeepable || (kept_flight >= 0 && !media_)) return false;
  // On past a surface that makes no vertex (an index-matched boundary, a plain layer
  // passed): the ray goes on from it, a kept distance measured from its new origin (false:
  // that distance lies before it).
  auto go_past = [&](const SurfaceHit &hit, const CoincidentBoundary &boundary) {
    if (media_) media.cross(scene_, hit, boundary, ray.d);
    const float tmax = std::isinf(ray.tmax) ? kInf : ray.tmax - hit.t;
    const Vec3 o = spawn_origin(hit.p, hit.ng, hit.error, ray.d);
    kept_flight = kept_past(kept_flight, dot(o - ray.o, ray.d));
    ray = Ray{o, ray.d, tmax, ray.mask};
    return kept_flight != kNotKeepable;
  };
  for (int guard = 0; guard < 256; ++guard) {
    SurfaceHit hit;
    CoincidentBoundary boundary;
    ++stats.rays;
    bool found = media_ ? scene_.intersect_media(ray, hit, boundary) : scene_.intersect(ray, hit);
    float segment = found ? hit.t : ray.tmax;
    // The last vertex from the camera side: a lamp's sphere or an area lamp in front of the surface.
    float t_lamp = 0;
    const int lamp = to_light ? first_lamp(ray.o, ray.d, segment, t_lamp, ray.mask) : -1;
    if (lamp >= 0) segment = t_lamp;
    if (media_) {
      int m = media.current(scene_);
      if (kept_flight >= 0) {
        if (kept_flight < segment) {  // nothing the ray meets before the kept distance
          if (m < 0) return false;
          PathVertex &v = bdpt::fresh_vertex(z.v);
          v.type = VertexType::Medium;
          v.p = ray.o + ray.d * kept_flight;
          v.wo = -ray.d;
          v.medium = m;
          v.media = media;
          return true;
        }
      } else if (m >= 0) {
        const Medium &medium = scene_.medium(m);
        float t = sample_distance(medium, ray, segment, side, rng);
        if (t == 0) return false;  // on the vertex it left (probability 0): no new vertex
        if (t > 0) {
          PathVertex &v = bdpt::fresh_vertex(z.v);
          v.type = VertexType::Medium;
          // The last step from the camera side reaches a volume light where its free
          // flight stops in the emissive medium: the point is the light vertex.
          if (to_light && medium.light >= 0) {
            v.type = VertexType::Light;
            v.light = medium.light;
          }
          v.p = ray.o + ray.d * t;
          v.wo = -ray.d;
          v.medium = m;
          v.media = media;
          return true;
        }
      }
      if (found && lamp < 0 && scene_.is_boundary_only(hit.material)) {  // an index-matched boundary: no vertex
        if (!go_past(hit, boundary)) return false;
        continue;
      }
    }
    if (found && lamp < 0 && layers_ && scene_.is_plain_layer(hit)) {
      // A plain layer: the walk's lobe choice there decides first whether it passes (BDPT's
      // walks); a pass is no vertex, the edge crosses the layer (trace_edge). Pauly's
      // retrace passes without a choice: its ratio takes the edge's passes out with the
      // kept vertex's free flight (camera_side_flight, light_side_flight).
      bool pass = kept_flight >= 0;
      if (!pass) pass = rng.next_float() < scene_.bsdf(hit, -ray.d).pass_probability(-ray.d);
      if (pass) {
        if (!go_past(hit, boundary)) return false;
        continue;
      }
    }
    if (kept_flight >= 0) return false;  // a surface or a lamp before the kept distance, or the ray escaped
    if (lamp >= 0) {
      const Light &light = scene_.lights()[size_t(lamp)];
      PathVertex &v = bdpt::fresh_vertex(z.v);
      v.type = VertexType::Light;
      v.light = lamp;
      if (light.type == LightType::Area) {  // a point on the rectangle or disk, its emitting side toward the ray
        v.ng = v.ns = light.axis;
        v.p = ray.o + ray.d * t_lamp;
      } else {
        v.ng = v.ns = normalize(ray.o + ray.d * t_lamp - light.position);
        v.p = light.position + v.ng * light.radius;
      }
      v.wo = -ray.d;
      v.media = media;
      return true;
    }
    if (!found) {
      // Escaped: the last vertex from the camera side may be the lights at infinity
      // (all of them but suns without an angle, which no direction sampled at random hits).
      if (!to_light || infinite_light_ < 0) return false;
      PathVertex &v = bdpt::fresh_vertex(z.v);
      v.type = VertexType::Light;
      v.light = infinite_light_;
      v.infinite = true;
      v.dir = normalize(ray.d);
      v.p = ray.o;
      v.wo = -v.dir;
      v.media = media;
      return true;
    }
    PathVertex &v = bdpt::fresh_surface_vertex(z.v, hit, ray.d, boundary, media);
    if (scene_.material(hit.material).emits()) v.light = int(scene_.triangle_light(hit.instance, hit.prim));
    z.hit = hit;
    return true;
  }
  return false;
}

bool PathSpace::first_camera_step(Vec2 raster, Pcg32 &rng, RayStats &stats, ExplicitVertex &x0,
                                  ExplicitVertex &x1) const {
  return camera_vertex(rng, x0) && trace_step(camera_ray(x0, raster), x0.v.media, Side::Camera, rng, stats, x1);
}

bool PathSpace::camera_vertex(Pcg32 &rng, ExplicitVertex &z) const {
  const Camera &camera = scene_.camera_now();
  PathVertex &v = bdpt::fresh_vertex(z.v);
  v.type = VertexType::Camera;
  v.p = camera.position();  // orthographic: moved to x_1's foot on the image plane by evaluate()
  if (camera.aperture_radius > 0) {
    Vec2 u{rng.next_float(), rng.next_float()};
    if (camera.type == Camera::Type::Orthographic) {
      Vec2 a, b;
      lens_region(camera, a, b);
      v.p = camera.lens_to_world(Vec2(a.x + u.x * (b.x - a.x), a.y + u.y * (b.y - a.y)));
    } else {
      v.p = camera.lens_to_world(camera.lens_sample(u));
    }
  }
  if (media_) v.media = MediumStack::for_camera(scene_);
  return true;
}

void PathSpace::lens_region(const Camera &camera, Vec2 &lo, Vec2 &hi) const {
  // Every point of the plane some ray into the sample region can start from.
  const Vec2 a = camera.plane_of_raster(sample_origin_), b = camera.plane_of_raster(sample_origin_ + sample_size_);
  const float r = camera.aperture_radius;
  lo = Vec2(std::min(a.x, b.x) - r, std::min(a.y, b.y) - r);
  hi = Vec2(std::max(a.x, b.x) + r, std::max(a.y, b.y) + r);
}

double PathSpace::lens_region_area(const Camera &camera) const {
  Vec2 lo, hi;
  lens_region(camera, lo, hi);
  return (double(hi.x) - lo.x) * (double(hi.y) - lo.y);
}

Ray PathSpace::camera_ray(const ExplicitVertex &camera_vertex, Vec2 raster) const {
  const Camera &camera = scene_.camera_now();
  Ray ray;
  if (!(camera.aperture_radius > 0))
    ray = camera.generate_ray(raster, Vec2(0.5f, 0.5f));
  else if (camera.type == Camera::Type::Orthographic)  // the lens offset: x_0 from the raster point's foot
    ray = camera.generate_ray_from_lens(raster, camera.lens_of_point(camera_vertex.v.p) - camera.plane_of_raster(raster));
  else
    ray = camera.generate_ray_from_lens(raster, camera.lens_of_point(camera_vertex.v.p));
  ray.mask = visibility::kCamera;  // it passes the lamps the camera does not see (ray_mask)
  return ray;
}

bool PathSpace::light_vertex(Pcg32 &rng, ExplicitVertex &z, Vec3 &dir) const {
  const Distribution1D &dist = scene_.light_distribution();
  float u_light = rng.next_float();
  Vec2 u_pos{rng.next_float(), rng.next_float()}, u_dir{rng.next_float(), rng.next_float()};
  if (dist.size() == 0 || dist.total() <= 0) return false;
  uint32_t index = uint32_t(dist.sample_discrete(u_light, nullptr));
  Light moved;
  const Light &light = scene_.light_now(index, moved);  // a moving emitter where it is at the path's time
  // Where the light's rays start, and one direction (for the vertex's media).
  Ray ray;
  Vec3 n(0.0f);
  if (is_sphere_lamp(light)) {  // a point on the lamp's sphere (lights/sphere_lamp.h), facing out
    Vec3 p;
    sample_sphere_lamp_point(light, u_pos, p, n);
    ray = Ray{p, n, kInf};
  } else if (light.type == LightType::Volume) {  // a point of the emissive medium by power
    const Vec3 u_point{rng.next_float(), rng.next_float(), rng.next_float()};
    float pdf = 0;
    ray = Ray{light.volume->sample(u_pos, u_point, &pdf), Vec3(0, 0, 1), kInf};
    if (!(pdf > 0)) return false;
  } else {
    EmissionSample es;
    if (!scene_.sample_emission(index, u_pos, u_dir, Vec3(0.5f), es)) return false;
    ray = es.ray;
    if (light.type == LightType::Area || light.type == LightType::Triangle) n = light.axis;
  }
  PathVertex &v = bdpt::fresh_vertex(z.v);
  v.type = VertexType::Light;
  v.light = int(index);
  v.p = ray.o;
  dir = ray.d;
  if (light.is_infinite()) {
    // A direction (the point on the disk it starts from is sampled with the next vertex,
    // extend_from_light_side); the lights at infinity but a sun without an angle are one
    // vertex whose density sums theirs (light_position_density).
    v.infinite = true;
    v.dir = -ray.d;
    v.wo = ray.d;
    if (!light_is_delta_direction(light)) v.light = infinite_light_;
    return true;
  }
  v.ng = v.ns = n;
  if (light.type == LightType::Triangle) v.error = light.error;
  if (light.type == LightType::Volume) v.medium = light.volume->medium_index();
  if (media_) {
    if (const std::vector<int> *media = scene_.light_media(index)) v.media = MediumStack::from(*media);
    else v.media = MediumStack::from(scene_.media_along(ray.o, ray.d));
  }
  return true;
}

uint32_t PathSpace::ray_mask(const ExplicitPath &y, int i, Vec3 w) const {
  // Without ray visibility settings every instance meets every kind, but lamps are hidden
  // from camera rays (Cycles never shows them there): a camera ray that met one would end on
  // it, so the world or a surface behind a lamp in view could only be sampled from the light
  // side (one E W path of the Blender shadow-catcher scene weighed 186 times the others).
  if (!visibility_) return i == 0 ? visibility::kCamera : visibility::kAnyRay;
  uint32_t mask = visibility::kCamera;
  for (int j = 1; j <= i; ++j) {
    const PathVertex &v = y.x[size_t(j)].v;
    const Vec3 wj = j == i ? w : normalize(y.x[size_t(j + 1)].v.p - v.p);
    const ScatterKind kind = v.type == VertexType::Medium ? ScatterKind::Volume : v.bsdf.scatter_kind(v.wo, wj);
    if (kind != ScatterKind::Transparent) mask = visibility::after(kind);
  }
  return mask;
}

MediumStack PathSpace::stack_toward(const ExplicitVertex &z, Vec3 w) const {
  if (!media_) return MediumStack();
  // A lamp that a medium boundary passes through (Scene::light_media has no one stack for
  // it): its media depend on the direction a ray leaves by, not on the one light_vertex()
  // found them along (a point lamp on a fog box's face counted the fog twice on rays into
  // the box, and saw fog outside it).
  if (z.v.type == VertexType::Light && !z.v.infinite && z.v.light >= 0) {
    const Light &light = scene_.lights()[size_t(z.v.light)];
    const bool lamp = light.type == LightType::Point || light.type == LightType::Spot || light.type == LightType::Area;
    if (lamp && !scene_.light_media(uint32_t(z.v.light))) return MediumStack::from(scene_.media_along(z.v.p, w));
  }
  return z.v.media_toward(scene_, w);
}

// z's camera-side neighbour is now `camera_side`: its wo, its media on that side and
// (surfaces) its BSDF follow (path_space.h: f's rule).
void PathSpace::settle(ExplicitVertex &z, const ExplicitVertex &camera_side) const {
  if (z.v.infinite) return;  // a direction: it stays whatever its neighbour does
  const Camera &camera = scene_.camera_now();
  // An orthographic camera sees x_1 along its view axis, wherever x_1 is (without depth of field).
  Vec3 w = camera_side.v.type == VertexType::Camera && orthographic_pinhole(camera)
               ? -camera.forward()
               : normalize(camera_side.v.p - z.v.p);
  if (z.v.type == VertexType::Surface) {
    if (media_) z.v.media = z.v.media_toward(scene_, w);
    z.v.bsdf = scene_.bsdf(z.hit, w, 0);
    z.blur = 0;
  }
  z.v.wo = w;
}

void PathSpace::blur_by_prefix(ExplicitVertex &z) const {
  if (z.v.type != VertexType::Surface) return;
  float alpha = filter_.alpha_after(z.v.filter_pdf);
  if (!Bsdf::blur_acts(alpha)) alpha = 0;
  if (alpha == z.blur) return;
  if (z.blur > 0) z.v.bsdf = scene_.bsdf(z.hit, z.v.wo, 0);  // blurred by another prefix: as built
  if (alpha > 0) z.v.bsdf.blur(alpha);
  z.blur = alpha;
}

bool PathSpace::light_walk_made(const ExplicitPath &y, int lo, int hi) {
  for (int i = lo; i <= hi; ++i)
    if (!(y.rev[size_t(i)] > 0)) return false;
  return true;
}

bool PathSpace::extend_from_camera_side(ExplicitPath &y, int at, Pcg32 &rng, RayStats &stats, int to_light,
                                        float kept_flight) const {
  ExplicitVertex &prev = y.x[size_t(at - 1)];
  Ray ray;
  MediumStack media;
  float scattered_pdf = kInf;  // Filter Glossy: the density prev sampled the direction with
  if (prev.v.type == VertexType::Camera) {
    // A raster point uniform over the sample region, through the pinhole. Orthographic with
    // depth of field: the raster point whose foot is x_0 less an offset uniform on the
    // aperture (its rays into the region start anywhere on the plane: camera_vertex).
    const Vec2 u{rng.next_float(), rng.next_float()};
    Vec2 raster{sample_origin_.x + u.x * sample_size_.x, sample_origin_.y + u.y * sample_size_.y};
    const Camera &camera = scene_.camera_now();
    if (camera.type == Camera::Type::Orthographic && camera.aperture_radius > 0) {
      raster = camera.raster_of_plane(camera.lens_of_point(prev.v.p) - camera.lens_sample(u));
      if (!in_sample_region(raster)) return false;
    }
    ray = camera_ray(prev, raster);
    media = prev.v.media;
  } else {
    Vec3 wi;
    if (prev.v.type == VertexType::Medium) {
      Vec2 u{rng.next_float(), rng.next_float()};
      const auto &phase = scene_.medium(prev.v.medium).phase;
      wi = phase.sample(prev.v.wo, u);
      if (filter_.on()) scattered_pdf = phase.pdf(prev.v.wo, wi);
    } else if (prev.v.type == VertexType::Surface) {
      float u_lobe = rng.next_float();
      Vec2 u{rng.next_float(), rng.next_float()};
      if (filter_.on()) blur_by_prefix(prev);  // the camera side samples f's (blurred) BSDF
      // On a plain layer the walk has chosen not to pass (trace_step): it scatters.
      const bool layer = on_plain_layer(prev);
      if (layer) u_lobe = prev.v.bsdf.scattering_lobe_u(prev.v.wo, u_lobe);
      BsdfSample bs;
      if (!prev.v.bsdf.has_lobes() || !prev.v.bsdf.sample(prev.v.wo, u_lobe, u, TransportMode::Radiance, bs) ||
          (layer && bs.pass_through))
        return false;
      prev.v.delta = bs.is_delta;  // the path's specular vertices are part of its state
      if (!bs.is_delta) scattered_pdf = bs.pdf;
      wi = bs.wi;
    } else {
      return false;  // lights do not scatter
    }
    return trace_from(y, at - 1, wi, scattered_pdf, rng, stats, to_light, kept_flight);
  }
  ExplicitVertex &z = y.x[size_t(at)];
  kept_flight = kept_past(kept_flight, dot(ray.o - prev.v.p, ray.d));  // a thin lens's ray starts at its lens point
  if (!trace_step(ray, media, Side::Camera, rng, stats, z, to_light < 0 ? at == y.n - 1 : to_light > 0, kept_flight)) return false;
  settle(z, prev);
  if (filter_.on()) z.v.filter_pdf = std::min(prev.v.filter_pdf, scattered_pdf);  // x_1: none before it
  return true;
}

bool PathSpace::trace_from(ExplicitPath &y, int at, Vec3 wi, float scattered_pdf, Pcg32 &rng, RayStats &stats,
                           int to_light, float kept_flight) const {
  ExplicitVertex &prev = y.x[size_t(at)], &z = y.x[size_t(at + 1)];
  const Ray ray{prev.v.on_surface() ? spawn_origin(prev.v.p, prev.v.ng, prev.v.error, wi) : prev.v.p, wi, kInf,
                ray_mask(y, at, wi)};
  const bool last = to_light < 0 ? at + 1 == y.n - 1 : to_light > 0;
  kept_flight = kept_past(kept_flight, dot(ray.o - prev.v.p, wi));  // measured from prev, not the spawn offset
  if (!trace_step(ray, stack_toward(prev, wi), Side::Camera, rng, stats, z, last, kept_flight)) return false;
  settle(z, prev);
  if (filter_.on()) z.v.filter_pdf = std::min(prev.v.filter_pdf, scattered_pdf);
  return true;
}

bool PathSpace::extend_from_light_side(ExplicitPath &y, int at, Pcg32 &rng, RayStats &stats, float kept_flight) const {
  ExplicitVertex &next = y.x[size_t(at + 1)];
  Vec3 wi;
  if (next.v.infinite) {
    if (kept_flight >= 0) return false;  // its rays start on a disk drawn afresh: no distance to keep
    // From a light at infinity along its direction: the ray starts at a point uniform on
    // the disk perpendicular to it that covers the scene (sample_emission's; the density
    // of the vertex it reaches is the disk's times the cosine there, evaluate()).
    Vec2 u_pos{rng.next_float(), rng.next_float()};
    const float radius = scene_.bounding_radius();
    const Frame frame(next.v.dir);
    const Vec2 q = concentric_disk(u_pos) * radius;
    const Vec3 o = scene_.bounding_center() + next.v.dir * radius + frame.s * q.x + frame.t * q.y;
    const MediumStack media = media_ ? MediumStack::from(scene_.media_along(o, -next.v.dir)) : MediumStack();
    return trace_step(Ray{o, -next.v.dir, kInf, light_walk_mask()}, media, Side::Light, rng, stats, y.x[size_t(at)]);
  }
  if (at + 1 == y.n - 1) {
    // Leaving the light: its emission direction (sample_emission's, whatever point it
    // picks; a sphere lamp's from its point).
    EmissionSample es;
    Vec2 u_pos{rng.next_float(), rng.next_float()}, u_dir{rng.next_float(), rng.next_float()};
    if (next.v.light < 0) return false;
    const Light &light = scene_.lights()[size_t(next.v.light)];
    if (is_sphere_lamp(light)) {
      if (!sample_sphere_lamp_direction(light, next.v.ng, u_dir, wi)) return false;
    } else if (light.type == LightType::Volume) {
      wi = uniform_sphere(u_dir);  // isotropic emission (emission_pdf's direction density)
    } else {
      if (!scene_.sample_emission(uint32_t(next.v.light), u_pos, u_dir, Vec3(0.5f), es)) return false;
      wi = es.ray.d;
    }
  } else {
    Vec3 w_light = toward(next, y.x[size_t(at + 2)]);
    if (next.v.type == VertexType::Medium) {
      Vec2 u{rng.next_float(), rng.next_float()};
      wi = scene_.medium(next.v.medium).phase.sample(w_light, u);
    } else if (next.v.type == VertexType::Surface) {
      float u_lobe = rng.next_float();
      Vec2 u{rng.next_float(), rng.next_float()};
      Bsdf bsdf = scene_.bsdf(next.hit, w_light, 0);
      const bool layer = on_plain_layer(next);  // chosen not to pass: it scatters (as above)
      if (layer) u_lobe = bsdf.scattering_lobe_u(w_light, u_lobe);
      BsdfSample bs;
      if (!bsdf.has_lobes() || !bsdf.sample(w_light, u_lobe, u, TransportMode::Importance, bs) ||
          (layer && bs.pass_through))
        return false;
      next.v.delta = bs.is_delta;
      wi = bs.wi;
    } else {
      return false;
    }
  }
  MediumStack media = stack_toward(next, wi);
  Ray ray{next.v.on_surface() ? spawn_origin(next.v.p, next.v.ng, next.v.error, wi) : next.v.p, wi, kInf,
          light_walk_mask()};
  kept_flight = kept_past(kept_flight, dot(ray.o - next.v.p, wi));
  return trace_step(ray, media, Side::Light, rng, stats, y.x[size_t(at)], false, kept_flight);
}

double PathSpace::camera_side_flight(const ExplicitPath &p, int i) const {
  // fwd_area[i] = cos / d^2 x the free flight; a medium vertex has no cosine, and an
  // orthographic camera's x_1 no d^2 (evaluate()).
  if (i == 1 && orthographic_pinhole(scene_.camera_now())) return p.fwd_area[1];
  return p.fwd_area[size_t(i)] * double(length_squared(p.x[size_t(i)].v.p - p.x[size_t(i - 1)].v.p));
}

double PathSpace::light_side_flight(const ExplicitPath &p, int i) {
  return p.rev_area[size_t(i)] * double(length_squared(p.x[size_t(i)].v.p - p.x[size_t(i + 1)].v.p));
}

// y's vertices 0 .. l and l + na + 1 .. n - 1 are in place; the na between are sampled:
// j from the camera side, the rest from the light side, then joined.
bool PathSpace::regenerate(ExplicitPath &y, int l, int na, int j, Pcg32 &rng, RayStats &stats) const {
  for (int i = 0; i < j; ++i) {
    int at = l + 1 + i;
    if (at == 0) camera_vertex(rng, y.x[0]);
    else if (!extend_from_camera_side(y, at, rng, stats)) return false;
  }
  if (l + j + 1 == 0) return false;  // the camera cannot be reached from the light side
  const int last = y.n - 1;
  for (int i = 0; i < na - j; ++i) {
    int at = l + na - i;
    Vec3 dir;
    if (at == last) {
      if (!light_vertex(rng, y.x[size_t(at)], dir)) return false;
    } else if (!extend_from_light_side(y, at, rng, stats)) {
      return false;
    }
  }
  // The connection's ends scatter by their non-delta lobes (a kept vertex may have been
  // specular in x); a pure delta BSDF there makes f 0.
  if (l + j >= 0) y.x[size_t(l + j)].v.delta = false;
  if (l + j + 1 <= last) y.x[size_t(l + j + 1)].v.delta = false;
  // The light-side vertices and the kept vertex after them face their new camera side.
  for (int i = l + j + 1; i <= std::min(l + na + 1, last); ++i) settle(y.x[size_t(i)], y.x[size_t(i - 1)]);
  return true;
}

// ---- f and the densities ----

Color PathSpace::emitted(const ExplicitVertex &light_vertex, Vec3 w, uint32_t ray_kind, bool background,
                         int scatterings, Vec3 receiver) const {
  Light moved;
  const Light &l = scene_.light_now(uint32_t(light_vertex.v.light), moved);
  if (!l.lights_path(scatterings) && !(light_vertex.v.infinite && !light_is_delta_direction(l)))
    return Color(0.0f);  // its Max Bounces (lights at infinity: each below)
  if (light_vertex.v.infinite) {
    // A sun without an angle: its irradiance (a delta in direction, as a point lamp's
    // intensity is one in position; no camera ray meets it). The others: the sum of the
    // radiance along the direction of those the kind of ray that reaches them sees.
    if (light_is_delta_direction(l))
      return ray_kind != visibility::kCamera && (l.visibility & ray_kind) ? l.radiance : Color(0.0f);
    Color L(0.0f);
    for (uint32_t index : infinite_lights_) {
      const Light &light = scene_.lights()[index];
      if (!background && light.type == LightType::Background) continue;
      if (!light.lights_path(scatterings)) continue;
      if (light.visibility & ray_kind) L += infinite_light_radiance(light, light_vertex.v.dir);
    }
    return L;
  }
  // Textured emission: the texture where the vertex is, unfiltered (f's rule). A volume's:
  // per unit length at the point (the edge's column weighs the medium's own absorption on
  // the way out; a point outside the medium has f = 0 from trace_edge).
  return scene_.light_radiance(l, light_vertex.v.p, light_vertex.v.ng, w, receiver);
}

double PathSpace::light_position_density(const ExplicitVertex &light_vertex) const {
  Light moved;
  const Light &l = scene_.light_now(uint32_t(light_vertex.v.light), moved);
  const Distribution1D &choice = scene_.light_distribution();
  if (light_vertex.v.infinite) {
    // The direction's density in solid angle (a sun without an angle: 1, its delta's).
    if (light_is_delta_direction(l)) return double(choice.pmf(size_t(light_vertex.v.light)));
    double pdf = 0;
    for (uint32_t index : infinite_lights_)
      pdf += double(choice.pmf(index)) * light_pdf(scene_.lights()[index], Vec3(0.0f), light_vertex.v.dir, kInf);
    return pdf;
  }
  // Light choice by power (a textured mesh triangle's by its material's mean emission
  // times its area, Scene::commit), a point uniform on it.
  // A volume light: a point by emitted power, density in volume measure.
  const double area_pdf = is_sphere_lamp(l)                ? sphere_lamp_point_pdf(l, light_vertex.v.ng)
                          : l.type == LightType::Volume ? double(l.volume->pdf(light_vertex.v.p))
                                                           : double(l.inv_area);
  return double(choice.pmf(size_t(light_vertex.v.light))) * area_pdf;
}

double PathSpace::see_through_share(const ExplicitVertex &v, Vec3 w) const {
  if (v.v.type != VertexType::Surface) return 0;
  if (v.v.delta) {
    if (v.v.bsdf.passes_straight_through(v.v.wo, w)) return 1;
    return transparent_glass_ && dot(v.v.wo, v.v.ng) * dot(w, v.v.ng) < 0 ? 1 : 0;  // a smooth refraction
  }
  if (!transparent_glass_ || catchers_) return 0;
  return v.v.bsdf.share_refracted_below(v.v.wo, w, glass_alpha2_);
}

double PathSpace::escape_weight(const ExplicitVertex &v, Vec3 w) const {
  const Distribution1D &dist = scene_.light_distribution();
  for (uint32_t index : infinite_lights_) {
    const Light &light = scene_.lights()[index];
    if (light.type == LightType::Background)
      return power_heuristic(v.v.bsdf.pdf(v.v.wo, w), dist.pmf(index) * light_pdf(light, v.v.p, w, kInf));
  }
  return 1;
}

bool PathSpace::on_catcher(const ExplicitVertex &v) const {
  if (v.v.type == VertexType::Surface)
    return scene_.is_shadow_catcher(v.hit.instance) && !scene_.is_holdout_instance(v.hit.instance);
  // An emitting triangle of a catcher (Light::shadow_catcher), where the path ends on it.
  if (v.v.type != VertexType::Light || v.v.infinite || v.v.light < 0) return false;
  const Light &light = scene_.lights()[size_t(v.v.light)];
  return light.type == LightType::Triangle && light.shadow_catcher;
}

bool PathSpace::trace_edge(const ExplicitVertex &a, const ExplicitVertex &b, Vec3 w, const EdgeMasks &masks,
                           EdgeTrace &e, RayStats &stats) const {
  e = EdgeTrace();
  Vec3 from = a.v.p;
  if (a.v.type == VertexType::Camera) {  // camera rays start at the near clip plane
    const Camera &camera = scene_.camera_now();
    from = from + w * (camera.clip_start / dot(w, camera.forward()));
  }
  ShadowRay s = b.v.infinite ? shadow_ray_to_infinity(from, a.v.ng, a.v.error, w)
                             : shadow_ray(from, a.v.ng, a.v.error, b.v.p, b.v.ng, b.v.error);
  // A point in a medium lies on no surface: the edge runs to it, not the shadow ray's relative
  // margin short of it, so a layer (or wall) the walk met just before stopping there is on
  // the edge too (0.5 mm before a medium vertex 3 m away was left out of f and the densities).
  if (!b.v.infinite && in_medium(b.v)) s.tmax = length(b.v.p - s.o);
  if (!media_) {
    if (layers_ && masks.f) {
      e.visible = layers_along(s, w, masks.f, e.layers, stats);
    } else {
      ++stats.rays;
      e.visible = !masks.f || !scene_.occluded(s.o, s.d, s.tmax, masks.f);
    }
    if (e.visible) walks_along(s, w, masks, e, stats);
    return e.visible;
  }
  // Mask 0 (the last edge to a lamp that casts no shadows): nothing blocks, the medium
  // boundaries still count.
  const uint32_t trace_mask = masks.f ? masks.f : visibility::kAnyRay;
  MediumStack stack = a.v.type == VertexType::Camera ? a.v.media : a.v.media_toward(scene_, w);
  Vec3 o = s.o;
  float remaining = s.tmax;
  // Free-flight densities along the edge's segments: all passed, but the one at a
  // medium end, where the flight stops instead.
  // A segment's column (free_flights.h): its length in homogeneous media, the integral of
  // the density in grid media.
  // The camera side's walk draws from the equiangular mixture: its passes and its stop at b
  // by equiangular_, along the edge's own line from + t w (a segment starts at its start's
  // foot on it): the spawn offsets move a ray sideways, and the equiangular density at a
  // point varies at the scale of its distance h from the lamp's centre, so f's densities
  // read it from the vertices alone (a walk samples along its offset ray: a relative
  // difference of about offset / h, 1e-3 where a ray passes within a millimetre).
  int first_medium = -2, last_medium = -1;
  double first_column = 0, last_column = 0;
  double pass_all = 1, pass_but_first = 1;
  double camera_pass_all = 1, camera_pass_but_last = 1;
  float last_start = 0;  // along w from `from'
  auto on_line = [&](Vec3 p) { return from + w * dot(p - from, w); };
  for (int guard = 0;; ++guard) {
    if (guard == 64) return false;
    SurfaceHit hit;
    CoincidentBoundary boundary;
    ++stats.rays;
    bool found = scene_.intersect_media(Ray{o, s.d, remaining, trace_mask}, hit, boundary);
    float segment = found ? hit.t : remaining;
    // The last segment's media run to b itself: the shadow ray stops 2e-4 of the edge short
    // of it (core/ray_offset.h), which would be an error of that order in the column.
    if (!found && !b.v.infinite) segment = length(b.v.p - o);
    int m = stack.current(scene_);
    double pass = 1, camera_pass = 1, column = 0;
    if (m >= 0 && !(segment < kInf)) return false;  // no light comes through an unbounded medium
    if (m >= 0) {
      const Medium &medium = scene_.medium(m);
      column = medium_column(medium, o, s.d, segment);
      e.tr *= column_transmittance(medium, column);
      pass = camera_pass = pass_probability(medium, column);
      // (Not where the segment ends at b inside the medium: its stop density replaces it.)
      if (equiangular_.on() && medium_scatters(medium) && (found || !in_medium(b.v)))
        camera_pass = equiangular_.pass_probability(on_line(o), w, segment, pass);
    }
    camera_pass_but_last = camera_pass_all;
    camera_pass_all *= camera_pass;
    last_start = dot(o - from, w);
    if (first_medium == -2) {
      first_medium = m;
      first_column = column;
    } else {
      pass_but_first *= pass;
    }
    pass_all *= pass;
    last_medium = m;
    last_column = column;
    if (!found) break;
    if (layers_ && masks.f && scene_.is_plain_layer(hit)) {
      add_layer(hit, w, e.layers);
      stack.cross(scene_, hit, boundary, s.d);
    } else if (!scene_.is_boundary_only(hit.material)) {
      if (masks.f) return false;  // blocked
    } else {
      stack.cross(scene_, hit, boundary, s.d);
    }
    o = spawn_origin(hit.p, hit.ng, hit.error, s.d);
    remaining -= hit.t;
    if (remaining <= 0) break;
  }
  e.fwd = camera_pass_all;
  e.rev = pass_all;
  if (in_medium(b.v)) {
    if (last_medium != b.v.medium) return false;  // not inside its own medium
    const Medium &medium = scene_.medium(last_medium);
    const double stop = stop_density(medium, last_column, medium_density(medium, b.v.p));
    e.fwd = camera_pass_but_last * (equiangular_.on() && medium_scatters(medium)
                                        ? equiangular_.stop_density(from + w * last_start, w,
                                                                    dot(b.v.p - from, w) - last_start, stop)
                                        : stop);
  }
  if (a.v.type == VertexType::Medium) {
    if (first_medium != a.v.medium) return false;
    const Medium &medium = scene_.medium(first_medium);
    e.rev = pass_but_first * stop_density(medium, first_column, medium_density(medium, a.v.p));
  }
  e.visible = true;
  walks_along(s, w, masks, e, stats);
  return true;
}

void PathSpace::walks_along(const ShadowRay &s, Vec3 w, const EdgeMasks &masks, EdgeTrace &e, RayStats &stats) const {
  // Ray visibility where the walks' kinds of ray differ from f's: a walk stops at what its
  // own kind meets (real surfaces; medium boundaries are crossed as f crosses them) and
  // passes the plain layers its kind meets.
  double layers_fwd = e.layers.fwd, layers_rev = e.layers.rev;
  auto walk = [&](uint32_t mask, bool camera) {
    if (!layers_) {
      ++stats.rays;
      return scene_.occluded(s.o, s.d, s.tmax, mask) ? 0.0 : 1.0;
    }
    LayerPasses l;
    if (!layers_along(s, w, mask, l, stats)) return 0.0;
    return camera ? l.fwd : l.rev;
  };
  if (masks.camera_walk != masks.f) layers_fwd = walk(masks.camera_walk, true);
  if (masks.light_walk != masks.f && e.rev > 0) layers_rev = walk(masks.light_walk, false);
  e.fwd *= layers_fwd;
  e.rev *= layers_rev;
}

void PathSpace::add_layer(const SurfaceHit &hit, Vec3 w, LayerPasses &l) const {
  // f: the coefficient of the layer's straight-through delta, seen from the camera side (the
  // BSDF built toward it, as at a vertex); the walks: their lobe choice's pass from each side.
  const Bsdf camera_side = scene_.bsdf(hit, -w), light_side = scene_.bsdf(hit, w);
  float pdf, jacobian;
  l.tr *= camera_side.delta_eval(-w, w, TransportMode::Radiance, pdf, jacobian);
  l.fwd *= double(camera_side.pass_probability(-w));
  l.rev *= double(light_side.pass_probability(w));
  ++l.count;
}

bool PathSpace::layers_along(const ShadowRay &s, Vec3 w, uint32_t mask, LayerPasses &l, RayStats &stats) const {
  Vec3 o = s.o;
  float remaining = s.tmax;
  for (int guard = 0; guard < 256; ++guard) {
    SurfaceHit hit;
    ++stats.rays;
    if (!scene_.intersect(Ray{o, s.d, remaining, mask}, hit) || !(hit.t < remaining)) return true;
    if (!scene_.is_plain_layer(hit)) return false;
    add_layer(hit, w, l);
    if (is_black(l.tr) && !(l.fwd > 0) && !(l.rev > 0)) return false;  // an opaque part of a layer
    o = spawn_origin(hit.p, hit.ng, hit.error, s.d);
    remaining -= hit.t;
    if (!(remaining > 0)) return true;
  }
  return false;
}

void PathSpace::evaluate(ExplicitPath &y, RayStats &stats) const {
  shutter::SampleTime at(y.time);  // every ray, the camera and the lights at the path's time
  const int n = y.n;
  y.f = y.f_catcher = Color(0.0f);
  y.split = -1;
  std::fill(y.fwd.begin(), y.fwd.begin() + n, 0.0);
  std::fill(y.rev.begin(), y.rev.begin() + n, 0.0);
  std::fill(y.rev_area.begin(), y.rev_area.begin() + n, 0.0);
  std::fill(y.fwd_area.begin(), y.fwd_area.begin() + n, 0.0);
  if (n < min_vertices_ || n > max_vertices_) return;
  const ExplicitVertex &last = y.x[size_t(n - 1)];
  if (y.x[0].v.type != VertexType::Camera || last.v.light < 0) return;
  for (int i = 1; i < n - 1; ++i)
    if (y.x[size_t(i)].v.type == VertexType::Camera || y.x[size_t(i)].v.type == VertexType::Light) return;
  // Two neighbours at one point (a walk that met the surface it left, at float precision)
  // have no direction between them: such a path has measure 0. Checked up front, as the
  // edge loop reads the light-side direction at b toward the vertex after it.
  for (int i = 1; i + 1 < n; ++i)
    if (!y.x[size_t(i + 1)].v.infinite && !(length_squared(y.x[size_t(i + 1)].v.p - y.x[size_t(i)].v.p) > 0)) return;
  Light moved_light;
  const Light &light = scene_.light_now(uint32_t(last.v.light), moved_light);
  // Lamps: not in the BVH, no walk reaches them (a volume light is a medium the walks enter).
  const bool lamp = light.type != LightType::Triangle && light.type != LightType::Volume;
  // Cycles never shows lamps to the camera (lights at infinity: emitted() keeps those the
  // ray that reaches them sees); with ray visibility the edge loop checks every light
  // against its ray's kind.
  if (n == 2 && lamp && !last.v.infinite && !light.visible_camera()) return;

  // The camera, for a raster point in the sample region (pbrt's We). A pinhole or a thin
  // lens: We = 1 / (A A_lens cos^4), A the image's area at unit distance, x_0 on the
  // aperture (a pinhole: A_lens = 1), the raster point where the ray from x_0 to x_1
  // crosses the focal plane. Orthographic: x_0 is x_1's foot on the image plane (the
  // direction is a delta along the view axis), We = 1 / A_plane per unit of plane area,
  // and the first edge has no 1 / d^2 (dA_plane = cos_1 dA_1). Orthographic with depth of
  // field: the camera's rays start at a raster point's foot plus a lens offset (uniform on
  // the aperture) and aim at the foot's point on the focal plane, at distance d along the
  // axis, so We cos_0 = d^2 / (A_plane A_lens cos^3), a thin lens's with A = A_plane / d^2
  // (the image's area seen from x_0 at unit distance), where x_0 lies on the aperture around
  // the foot of the ray's focal-plane point (Camera::raster_through_lens). Its walk: x_0
  // uniform on the plane around the sample region (camera_vertex), then an offset uniform on
  // the aperture: x_1 per solid angle d^2 / (A_lens cos^3).
  const Camera &camera = scene_.camera_now();
  const bool ortho = orthographic_pinhole(camera);
  Vec2 raster;
  Vec3 w0;
  float cos0 = 1;
  double pdf_x1_dir;  // camera side: x_1's density per unit solid angle (ortho: per plane area)
  Color f;
  if (ortho) {
    // The world seen along the view axis (x_1 at infinity): the camera walk keeps its ray's
    // origin in the vertex, a point of the line whose foot is x_0. Only the camera's own ray
    // has the axis' direction (bit for bit); a direction from the light side never does.
    const ExplicitVertex &x1 = y.x[1];
    if (!camera.raster_of_point(x1.v.infinite ? x1.v.p + x1.v.dir : x1.v.p, raster, y.x[0].v.p)) return;
    if (x1.v.infinite && !(x1.v.dir == normalize(camera_ray(y.x[0], raster).d))) return;
    w0 = camera.forward();
    f = Color(float(1.0 / camera.image_plane_area()));
    pdf_x1_dir = (double(image_area_) / region_area_) / camera.image_plane_area();
  } else {
    w0 = toward(y.x[0], y.x[1]);
    if (!camera.raster_through_lens(y.x[0].v.p, w0, raster, cos0)) return;
    const double d = camera.focus_distance, c2 = double(cos0) * cos0;
    const bool perspective = camera.type == Camera::Type::Perspective;
    const double area = perspective ? camera.viewplane_area() : camera.viewplane_area() / (d * d);
    f = Color(float(1.0 / (area * camera.aperture_area() * c2 * c2) * cos0));
    // Orthographic with depth of field: the direction from x_0 by a lens offset uniform on
    // the aperture, whose focal-plane point moves d^2 / cos^3 per unit solid angle.
    pdf_x1_dir = perspective ? (double(image_area_) / region_area_) / (area * c2 * cos0)
                             : d * d / (camera.aperture_area() * c2 * cos0);
  }
  if (!in_sample_region(raster)) return;
  if (!y.x[1].v.infinite) {  // the world beyond the clip end is seen: Cycles' camera rays end there
    float depth = dot(y.x[1].v.p - camera.position(), camera.forward());
    if (depth < camera.clip_start || depth > camera.clip_end) return;
  }

  // Cycles' Light Paths limits: each scattering vertex's kind, as the path tracer labels it
  // (its BSDF built toward the camera, the direction toward the light), counted over every
  // scattering vertex but the one that meets the light (integrators/light_path_limits.h);
  // the caustics switches' chain from the camera (integrators/caustics_switches.h), whose
  // weight at the last scattering vertex is f's share.
  BounceCounts counts;
  CausticState caustic;
  Color caustic_weight(1.0f);
  // Ray visibility (scene/ray_visibility.h): the kind of ray each edge stands for, camera
  // rays from x_0, then each scattering's kind (a pass-through keeps the kind it had).
  uint32_t ray_kind = visibility_ ? visibility::kCamera : visibility::kAnyRay;

  // Filter Glossy: the smallest camera-side scattering density so far (filter_glossy.h).
  float filter_min = kInf;
  // The passes straight through (Transparent BSDF, alpha): no scattering. Plain layers are
  // on edges (trace_edge); the transparent surfaces that emit, hold out or catch shadows are
  // vertices passed through (vertex_passes).
  int passes = 0, vertex_passes = 0;
  // Plain layers (on_plain_layer) as vertices: the probability that the walk that reached
  // one did not pass it, from the camera side (keep_camera, a's) and the light side
  // (keep_light, a's: found when a was b).
  double keep_camera = 1, keep_light = 1;

  // How much the camera still sees through (Film > Transparent, holdouts, shadow catchers):
  // from x_1 on, past Transparent BSDFs and, with Transparent Glass, refractions
  // (see_through_share: 1, 0 or a share in between after a rough one).
  double seen_through = catchers_ || film_transparent_ || holdouts_ ? 1.0 : 0.0;
  // A holdout object the camera sees through to shows nothing there: f keeps the share that
  // does not see through (false: nothing is left).
  auto hold_out = [&]() {
    f = f * float(1 - seen_through);
    seen_through = 0;
    return !is_black(f);
  };
  // Shadow catchers: f and f_catcher share every factor but the visibility of the edges past
  // the split, which vertices past it may be, and the light's emission; whether each lives.
  bool image = true, copy = catchers_;
  Color layers_past_split(1.0f);  // in f, not in f_catcher

  // Edge by edge: transmittance, geometry, the scattering at its camera-side end, and
  // the densities of its two ends as the other end's walk would reach them.
  for (int i = 0; i + 1 < n; ++i) {
    if (filter_.on() && i >= 1) {  // a's BSDF in f: blurred by its camera-side prefix
      y.x[size_t(i)].v.filter_pdf = filter_min;
      blur_by_prefix(y.x[size_t(i)]);
    }
    const ExplicitVertex &a = y.x[size_t(i)], &b = y.x[size_t(i + 1)];
    // An edge to a light at infinity: no geometry term (its vertex is in solid angle).
    Vec3 w = b.v.dir;
    float d2 = 1;
    if (!b.v.infinite) {
      Vec3 d = b.v.p - a.v.p;
      d2 = length_squared(d);
      if (!(d2 > 0)) return;
      w = i == 0 ? w0 : d / std::sqrt(d2);
      if (too_short_at_specular(a.v, b.v, std::sqrt(d2))) return;
    }
    if (seen_through > 0 && i >= 1) {  // the split: the first catcher the camera sees through to
      // A holdout object where the camera sees it shows nothing (its alpha: the first-hit
      // pass); the share of f that does not see through to it goes on.
      if (holdouts_ && a.v.type == VertexType::Surface && scene_.is_holdout_instance(a.hit.instance)) {
        if (!hold_out()) return;
      } else if (catchers_ && on_catcher(a)) {
        y.split = i;
        seen_through = 0;
      } else {
        seen_through *= see_through_share(a, w);
        if (!(seen_through > 0)) copy = false;
      }
    }
    const bool past_split = y.split >= 0 && i >= y.split;
    if (past_split && b.v.type == VertexType::Surface && !on_catcher(b)) {
      copy = false;  // the catcher pass's rays meet catchers only
      if (!image) return;
    }
    if (i >= 1 && (limits_.classify || visibility_)) {
      // The kind of scattering at a toward b, as the path tracer labels it (its BSDF built
      // toward the camera): Cycles' Light Paths limits count it over every scattering
      // vertex but the one that meets the light, the caustics switches weigh each vertex by
      // the chain's state (integrators/light_path_limits.h); it sets the kind of ray toward b.
      const ScatterKind kind =
          a.v.type == VertexType::Medium ? ScatterKind::Volume : a.v.bsdf.scatter_kind(a.v.wo, w);
      if (limits_.classify) {
        const bool last_scattering = i + 1 == n - 1;  // the vertex that meets the light
        // A mixed reflection by Cycles' odds (BounceCounts): at x_1 with no pass before it,
        // with its defensive sampling.
        const float glossy = a.v.type == VertexType::Surface && (!last_scattering || limits_.caustics)
                                 ? a.v.bsdf.glossy_odds(a.v.wo, w, a.v.delta, i == 1 && passes + vertex_passes == 0)
                                 : -1.0f;
        if (limits_.caustics) {
          const CausticStep step = a.v.type == VertexType::Surface
                                       ? caustic_step(limits_, a.v.bsdf, a.v.wo, w, a.v.delta, kind, glossy,
                                                      !is_black(caustic.diffuse))
                                       : caustic_step(limits_, kind, -1, Color(1.0f));
          if (last_scattering) {
            caustic_weight = caustic.at_last(step.kept);
            if (is_black(caustic_weight)) return;
          } else {
            caustic = caustic.after(step);
            if (caustic.none()) return;
          }
        }
        if (!last_scattering) {
          counts.add(kind, glossy);
          if (!limits_.within(counts)) return;
        }
      }
      if (visibility_ && kind != ScatterKind::Transparent) ray_kind = visibility::after(kind);
    }
    EdgeMasks masks{ray_kind, ray_kind, ray_kind};
    if (visibility_) {
      // b must be visible to the kind of ray that reaches it; the light walk (which cannot
      // know the kind) meets what any ray but the camera's meets.
      if (i + 1 == n - 1) {
        if (!last.v.infinite && !(light.visibility & ray_kind)) return;  // infinite: emitted()
      } else if (b.v.on_surface() && !(scene_.instance_visibility(b.hit.instance) & ray_kind)) {
        return;
      }
      if (i >= 1 && mixed_visibility_) masks.light_walk = visibility::kNonCamera;
      // The last segment from a scattering vertex to the light is blocked by what casts
      // the light's shadows, whichever strategy made it (integrators/visibility_clear.h);
      // the camera walk reaches the light only where nothing its kind meets lies between.
      if (i >= 1 && i + 1 == n - 1) {
        masks.f = light.occluders();
        if (!mixed_visibility_) masks.camera_walk = masks.f;
      }
    }
    EdgeTrace e;
    if (!trace_edge(a, b, w, masks, e, stats)) {
      // Blocked in the image. Past the split the catcher pass's copy sees through what is not
      // a catcher; the walks do not (e keeps the scene's walk densities: 0 on this edge).
      if (!copy || !past_split || !masks.f) return;
      const EdgeMasks copy_masks{visibility::catcher_rays(masks.f), masks.camera_walk, masks.light_walk};
      if (!trace_edge(a, b, w, copy_masks, e, stats)) return;
      image = false;
    }
    if (visibility_ && i >= 1 && a.v.on_surface() &&
        !(scene_.instance_visibility(a.hit.instance) & visibility::kNonCamera))
      e.rev = 0;  // light walks pass what only the camera sees
    const float cos_b = cosine_at(b.v, w), cos_a = cosine_at(a.v, w);
    const float geometry = i == 0 && ortho ? cos_b : cos_b / d2;
    f *= e.tr * geometry;
    // The layers on the edge: the catcher pass's rays past the split meet catchers only.
    if (past_split) layers_past_split *= e.layers.tr;
    else f *= e.layers.tr;
    // Scattering at a (interior vertices), toward b. A specular vertex: the coefficient
    // of its Dirac delta (about the direction toward b), which its densities share.
    float pdf_delta = 0, jacobian = 1;
    if (i >= 1) {
      if (a.v.type == VertexType::Surface) {
        f *= a.v.delta ? a.v.bsdf.delta_eval(a.v.wo, w, TransportMode::Radiance, pdf_delta, jacobian)
                       : a.v.bsdf.eval(a.v.wo, w, TransportMode::Radiance);
      } else {
        const Medium &medium = scene_.medium(a.v.medium);
        f *= medium.sigma_s * (medium_density(medium, a.v.p) * medium.phase.eval(a.v.wo, w));
      }
    }
    if (is_black(f)) return;
    if (i >= 1 && a.v.delta && a.v.bsdf.passes_straight_through(a.v.wo, w)) {
      if (on_plain_layer(a)) return;  // a pass there is part of an edge, no vertex
      ++vertex_passes;
    }
    passes += e.layers.count;
    // Density of b from the camera side (a scattered toward it) and of a from the light
    // side (b scattered toward it): area measure, times the free flight.
    double pdf_b = 0;
    if (i == 0) {
      pdf_b = pdf_x1_dir;
    } else if (a.v.type == VertexType::Surface) {
      pdf_b = a.v.delta ? pdf_delta : a.v.bsdf.pdf(a.v.wo, w);
    } else {
      pdf_b = scene_.medium(a.v.medium).phase.pdf(a.v.wo, w);
    }
    if (i >= 1 && !a.v.delta) filter_min = std::min(filter_min, float(pdf_b));
    // A walk scatters from a plain layer only where it did not pass it: its density there
    // is the rest of the layer's sampling.
    if (i >= 1 && keep_camera < 1) pdf_b = keep_camera > 0 ? pdf_b / keep_camera : 0.0;
    keep_camera = i + 1 < n - 1 ? keeps(b, b.v.bsdf, b.v.wo) : 1.0;
    y.fwd_area[size_t(i + 1)] = (i == 0 && ortho ? cos_b * e.fwd : cos_b / d2 * e.fwd) * keep_camera;
    y.fwd[size_t(i + 1)] = pdf_b * y.fwd_area[size_t(i + 1)];
    double pdf_a = 0, b_keep_light = 1;
    if (i == 0) {
      pdf_a = 0;  // the camera vertex is always sampled from the camera side
      if (n > 2 && on_plain_layer(b)) {  // (below: where b scatters toward a)
        const Vec3 w_light = toward(b, y.x[2]);
        b_keep_light = keeps(b, scene_.bsdf(b.hit, w_light, 0), w_light);
      }
    } else if (b.v.infinite) {
      // From a light at infinity: a point uniform on the disk of the scene's bounding
      // radius perpendicular to the direction (BDPT's light tracing), the ray along it
      // reaching a (the cosine there below). a is inside the bounding sphere.
      const float radius = scene_.bounding_radius();
      const Vec3 offset = a.v.p - scene_.bounding_center();
      const bool covered = length_squared(offset - b.v.dir * dot(offset, b.v.dir)) <= radius * radius;
      pdf_a = covered ? 1.0 / (double(kPi) * radius * radius) : 0.0;
    } else if (i + 1 == n - 1) {
      if (is_sphere_lamp(light)) {
        pdf_a = sphere_lamp_direction_pdf(light, b.v.ng, -w);
      } else {
        float pdf_pos, pdf_dir;
        emission_pdf(light, b.v.p, b.v.ng, -w, scene_.bounding_radius(), pdf_pos, pdf_dir);
        pdf_a = pdf_dir;
      }
    } else if (b.v.type == VertexType::Surface) {
      Vec3 w_light = toward(b, y.x[size_t(i + 2)]);
      Bsdf light_side = scene_.bsdf(b.hit, w_light, 0);
      b_keep_light = keeps(b, light_side, w_light);
      if (filter_.on() && light_side.blur_changes(filter_.alpha_after(filter_min))) {
        pdf_a = 0;  // the light walk samples b unblurred: it cannot make f's blurred b
      } else if (b.v.delta) {
        // Sampled from the light side, b's delta is about the direction toward a: in
        // units of f's (about the direction toward the light) it is divided by the
        // light-side event's d omega_a / d omega_light.
        float pdf_rev, jacobian_rev;
        light_side.delta_eval(w_light, -w, TransportMode::Importance, pdf_rev, jacobian_rev);
        pdf_a = jacobian_rev > 0 ? double(pdf_rev) / jacobian_rev : 0.0;
      } else {
        pdf_a = light_side.pdf(w_light, -w);
      }
    } else {
      pdf_a = scene_.medium(b.v.medium).phase.pdf(toward(b, y.x[size_t(i + 2)]), -w);
    }
    if (b_keep_light < 1) pdf_a = b_keep_light > 0 ? pdf_a / b_keep_light : 0.0;
    y.rev_area[size_t(i)] = cos_a / d2 * e.rev * keep_light;
    y.rev[size_t(i)] = pdf_a * y.rev_area[size_t(i)];
    keep_light = b_keep_light;
  }
  // Of the n - 2 inner vertices, those not passed through scatter: the chains' paths have at
  // least min_vertices_ - 2 of them (the direct light left to the path tracer is every path
  // of at most one, however many layers it passes, as the path tracer counts), and Transparent
  // max bounces (light_path_limits.h) bounds the passes.
  if (n - vertex_passes < min_vertices_ || !limits_.transparent_within(passes, n - 2 > vertex_passes)) return;
  // The kind of ray that meets the light (without ray visibility: the camera's for the camera
  // ray alone, lamps' default visibility, else any other kind).
  const uint32_t kind_at_light = visibility_ ? ray_kind : n == 2 ? visibility::kCamera : visibility::kNonCamera;
  // An emitting holdout object seen through to shows nothing either.
  if (seen_through > 0 && holdouts_ && light.type == LightType::Triangle &&
      scene_.is_holdout_instance(light.instance) && !hold_out())
    return;
  if (seen_through > 0 && catchers_ && on_catcher(last)) y.split = n - 1;  // an emitting catcher seen through to
  // The world seen through a transparent film is not in the image (its alpha: the first-hit
  // pass). Past a rough refraction the camera sees through by a share (see_through_share),
  // and the path tracer's rule (Cycles') depends on sampling there: the ray that escapes
  // leaves the world out, next-event estimation adds it whatever the camera sees; f takes
  // the expectation, the world less seen_through x the escape's MIS weight.
  double world_left_out = 0;
  if (film_transparent_ && seen_through > 0 && last.v.infinite) {
    world_left_out = seen_through;
    const ExplicitVertex &v = y.x[size_t(n - 2)];
    if (n > 2 && v.v.type == VertexType::Surface && !v.v.delta) world_left_out *= escape_weight(v, last.v.dir);
  }
  const Vec3 w_light = -toward(y.x[size_t(n - 2)], last);
  const int scatterings = n - 2 - vertex_passes;
  const Vec3 receiver = y.x[size_t(n - 2)].v.p;
  Color emission = emitted(last, w_light, kind_at_light, world_left_out < 1, scatterings, receiver);
  if (world_left_out > 0 && world_left_out < 1) {
    const Color without_world = emitted(last, w_light, kind_at_light, false, scatterings, receiver);
    emission = emission - (emission - without_world) * float(world_left_out);
  }
  f *= emission;
  if (limits_.classify) f *= limits_.kept_share(counts) * caustic_weight;  // below 1 with mixed reflections
  Color f_catcher = copy && y.split >= 0 && light.shadow_catcher ? f : Color(0.0f);
  f *= layers_past_split;
  if (!image) f = Color(0.0f);
  // A point uniform on the aperture (pinhole, orthographic: 1), or with an orthographic
  // camera's depth of field on the plane around the sample region (camera_vertex).
  y.fwd[0] = orthographic_pinhole(camera) || camera.type == Camera::Type::Perspective ? 1.0 / camera.aperture_area()
                                                                                       : 1.0 / lens_region_area(camera);
  // The camera side reaches the light where its last ray meets it first: a lamp's sphere
  // where the ray enters it (emitted() is 0 from inside), an area lamp from its emitting
  // side (E S+ L through a mirror or glass has no other strategy), another lamp on the way
  // takes the ray instead; point and spot lamps without a radius and suns without an
  // angle are never reached; the other lights at infinity where the ray escapes.
  // A volume light where the last step's free flight stops in its medium: only if it scatters.
  const bool reachable = last.v.infinite                  ? !light_is_delta_direction(light)
                         : light.type == LightType::Volume ? medium_scatters(scene_.medium(last.v.medium))
                                                           : !lamp || is_sphere_lamp(light) || light.type == LightType::Area;
  if (!reachable) {
    y.fwd[size_t(n - 1)] = 0;
  } else if (!hittable_lamps_.empty()) {
    Vec3 from = y.x[size_t(n - 2)].v.p;
    if (n == 2) from = from + w0 * (camera.clip_start / dot(w0, camera.forward()));
    float t, length_d = kInf;
    Vec3 w_last = last.v.dir;
    if (!last.v.infinite) {
      const Vec3 d = last.v.p - from;
      length_d = length(d);
      w_last = d / length_d;
    }
    const uint32_t kind = visibility_ || n > 2 ? ray_kind : visibility::kCamera;  // n = 2: the camera ray (ray_mask)
    const int first = first_lamp(from, w_last, length_d * (1 - 1e-4f), t, kind);
    if (first >= 0 && (last.v.infinite || first != last.v.light)) y.fwd[size_t(n - 1)] = 0;
  }
  // The light side samples a direction in solid angle; an orthographic camera sees the world
  // along its axis only (a delta), so E W has no light-side way there.
  y.rev[size_t(n - 1)] = ortho && n == 2 && last.v.infinite ? 0.0 : light_position_density(last);
  f *= image_area_;
  f_catcher *= image_area_;
  y.f = finite_or_black(f);
  y.f_catcher = finite_or_black(f_catcher);
  y.raster = raster;
}

// ---- The transition densities ----

double PathSpace::deletion_probability(int nv, int l, int m) const {
  if (l == -1 && m == nv) return large_step_probability_;
  if (l < -1 || m > nv || m <= l || (l == -1 && m == 0) || (l == nv - 1 && m == nv)) return 0;
  double z = 0;
  for (int kd = 1; kd <= nv; ++kd) z += deletion_weight(kd) * deletion_positions(nv, kd);
  return (1.0 - large_step_probability_) * deletion_weight(m - l) / z;
}

namespace {
// The range of added vertex counts after deleting l+1 .. m-1 of nv (path_space.h).
void addition_range(int nv, int l, int m, int min_vertices, int max_vertices, int &lo, int &hi) {
  const int kept = nv - (m - l - 1);
  lo = std::max(int(l == -1) + int(m == nv), min_vertices - kept);
  hi = max_vertices - kept;
}
// Added vertices around the deleted count; never none for none (the path unchanged).
double addition_weight(int na, int nd) { return na == 0 && nd == 0 ? 0.0 : std::ldexp(1.0, -std::abs(na - nd)); }
}  // namespace

double PathSpace::addition_probability(int nv, int l, int m, int na) const {
  if (l == -1 && m == nv) return length_probability(na);
  int lo, hi;
  addition_range(nv, l, m, min_vertices_, max_vertices_, lo, hi);
  if (na < lo || na > hi) return 0;
  const int nd = m - l - 1;
  double z = 0;
  for (int k = lo; k <= hi; ++k) z += addition_weight(k, nd);
  return z > 0 ? addition_weight(na, nd) / z : 0.0;
}

double PathSpace::transition_density(int nv_x, int l, int m, const ExplicitPath &y, int na) const {
  double p = deletion_probability(nv_x, l, m) * addition_probability(nv_x, l, m, na);
  if (!(p > 0)) return 0;
  return p * split_sum(y, l + 1, na) / double(na + 1);
}

double PathSpace::independent_density(const ExplicitPath &y) const {
  return split_sum(y, 0, y.n) / double(y.n + 1) * length_probability(y.n);
}

void PathSpace::set_length_weights(const std::vector<double> &weights) {
  // A quarter of the large steps stay uniform over the lengths: a length whose few
  // bootstrap samples missed its light keeps its share of proposals (and b its samples).
  constexpr double kUniformShare = 0.25;
  std::vector<double> w(size_t(path_lengths()), 0.0);
  double sum = 0;
  for (size_t k = 0; k < w.size() && k < weights.size(); ++k) {
    if (std::isfinite(weights[k])) w[k] = std::max(0.0, weights[k]);
    sum += w[k];
  }
  length_pmf_.clear();
  if (!(sum > 0)) return;  // uniform
  for (double wk : w) length_pmf_.push_back(kUniformShare / path_lengths() + (1 - kUniformShare) * wk / sum);
}

int PathSpace::random_path_length(Pcg32 &rng) const {
  const float u = rng.next_float();
  if (length_pmf_.empty()) return min_vertices_ + std::min(int(u * float(path_lengths())), path_lengths() - 1);
  double below = 0;
  for (int k = 0; k + 1 < path_lengths(); ++k) {
    below += length_pmf_[size_t(k)];
    if (double(u) < below) return min_vertices_ + k;
  }
  return max_vertices_;
}

double PathSpace::sample_independent(Pcg32 &rng, RayStats &stats, ExplicitPath &y) const {
  y.reserve(max_vertices_);
  y.f = Color(0.0f);
  y.time = shutter_time(rng);
  shutter::SampleTime at(y.time);
  const int nv = random_path_length(rng);
  const int j = std::min(int(rng.next_float() * float(nv + 1)), nv);
  y.n = nv;
  if (!regenerate(y, -1, nv, j, rng, stats)) return 0;
  evaluate(y, stats);
  if (!(y.carried() > 0)) return 0;
  if (filter_.on() && !light_walk_made(y, j, nv - 1)) return 0;  // scattered where f blurs
  return independent_density(y);
}

void PathSpace::mutation_weights(const ExplicitPath &x, float w[kWeightedMutations]) const {
  const int n = x.n, c = first_non_specular(x);
  auto delta = [&](int i) { return x.x[size_t(i)].v.delta; };
  // Lens perturbation (lens_move): x_c joined to x_(c+1), which must not be specular.
  const bool joinable = c <= n - 2 && !delta(c + 1);
  // Medium vertices the propagation perturbation can move (after a non-specular camera-side
  // neighbour), and the scattering perturbation (a non-specular neighbour on both sides).
  bool propagation = false, scattering = false;
  for (int j = 1; j + 1 < n; ++j) {
    if (x.x[size_t(j)].v.type != VertexType::Medium || delta(j - 1)) continue;
    propagation = true;
    scattering = scattering || !delta(j + 1);
  }
  // Multi-chain perturbation: x_(c+1) specular, or E S* L. Where every vertex after x_c is
  // specular up to the light, its last chain must hit the light: never one the camera side
  // cannot reach (a point or spot lamp, a sun without an angle: fwd = 0 there).
  bool chain_to_light = true;
  for (int i = c + 1; i < n - 1; ++i) chain_to_light = chain_to_light && delta(i);
  const bool multi_chain = !joinable && (!chain_to_light || x.fwd[size_t(n - 1)] > 0);
  // Caustic perturbation: E D S+ (D|L) ...
  int k = 2;
  while (k < n - 1 && delta(k)) ++k;
  const bool caustic = n >= 4 && !delta(1) && k >= 3 && !delta(k);
  const bool applies[kWeightedMutations] = {
      true,                  // bidirectional
      joinable,              // lens
      propagation,           // propagation
      scattering,            // scattering
      caustic,               // caustic
      multi_chain,           // multi-chain
      joinable || c >= n - 2,  // lens subpath: x_(c+1) joinable, or a short path replaced whole
  };
  for (int t = 0; t < kWeightedMutations; ++t) w[t] = applies[t] ? mutations_.weights[t] : 0.0f;
}

Proposal PathSpace::mutate(const ExplicitPath &x, Pcg32 &rng, RayStats &stats, ExplicitPath &y,
                           ImageStrata *strata) const {
  // The small steps' types by weight among those that can apply to x (mutation_weights:
  // from x's vertex kinds alone), so a path that only two perturbations can move (a volume
  // caustic, E M S S L) spends no steps on the five that would propose nothing. The
  // choice's probability then depends on the state: the ratio takes P(type | y) /
  // P(type | x) (0 where the type cannot apply to y: the move could not be undone).
  // Every mutation but the large step keeps x's shutter time (path_space.h).
  y.time = x.time;
  shutter::SampleTime at(x.time);
  if (rng.next_float() < large_step_probability_) return bidirectional(x, true, rng, stats, y);
  float w[kWeightedMutations];
  mutation_weights(x, w);
  float total = 0;
  for (int k = 0; k < kWeightedMutations; ++k) total += w[k];
  float u = rng.next_float() * total;
  if (!(total > 0)) return Proposal{};  // no weighted type applies: nothing to propose
  int pick = 0;  // the last mutation with a weight takes what rounding leaves over
  for (int k = 0; k < kWeightedMutations; ++k) {
    if (!(w[k] > 0)) continue;
    pick = k;
    if (u < w[k]) break;
    u -= w[k];
  }
  Proposal proposal = small_step(MutationType(pick + 1), x, rng, stats, y, strata);
  if (proposal.ratio > 0) {
    float wy[kWeightedMutations];
    mutation_weights(y, wy);
    float total_y = 0;
    for (int k = 0; k < kWeightedMutations; ++k) total_y += wy[k];
    proposal.ratio *= (double(wy[pick]) / double(total_y)) / (double(w[pick]) / double(total));
  }
  return proposal;
}

Proposal PathSpace::small_step(MutationType type, const ExplicitPath &x, Pcg32 &rng, RayStats &stats,
                               ExplicitPath &y, ImageStrata *strata) const {
  switch (type) {
    case MutationType::Lens: return perturb_lens(x, rng, stats, y);
    case MutationType::Propagation:
    case MutationType::Scattering: return perturb_medium_vertex(x, type, rng, stats, y);
    case MutationType::Caustic: return perturb_caustic(x, rng, stats, y);
    case MutationType::MultiChain: return perturb_multi_chain(x, rng, stats, y);
    case MutationType::LensSubpath: {
      Vec2 raster;
      if (strata) {
        raster = strata->next(rng);
      } else {
        const float ux = rng.next_float(), uy = rng.next_float();
        raster = {sample_origin_.x + ux * sample_size_.x, sample_origin_.y + uy * sample_size_.y};
      }
      return lens_subpath(x, raster, rng, stats, y);
    }
    default: return bidirectional(x, false, rng, stats, y);
  }
}

Proposal PathSpace::bidirectional(const ExplicitPath &x, bool large, Pcg32 &rng, RayStats &stats,
                                  ExplicitPath &y) const {
  Proposal proposal;
  y.reserve(max_vertices_);
  y.f = Color(0.0f);
  const int nv = x.n;
  // The deletion: everything (a large step), or kd edges by Veach's weights, placed uniformly.
  int l, m;
  if (large) {
    proposal.type = MutationType::Large;
    l = -1;
    m = nv;
  } else {
    double z = 0;
    for (int kd = 1; kd <= nv; ++kd) z += deletion_weight(kd) * deletion_positions(nv, kd);
    double u = rng.next_float() * z;
    int kd = 1;
    for (; kd < nv; ++kd) {
      u -= deletion_weight(kd) * deletion_positions(nv, kd);
      if (u < 0) break;
    }
    const int positions = deletion_positions(nv, kd);
    const int first = kd == 1 ? 0 : -1;
    l = first + std::min(int(rng.next_float() * float(positions)), positions - 1);
    m = l + kd;
  }
  const int nd = m - l - 1, kept = nv - nd;
  // How many vertices to add, then how many of them from the camera side.
  int na;
  if (proposal.type == MutationType::Large) {
    na = random_path_length(rng);
  } else {
    int lo, hi;
    addition_range(nv, l, m, min_vertices_, max_vertices_, lo, hi);
    double z = 0;
    for (int k = lo; k <= hi; ++k) z += addition_weight(k, nd);
    if (!(z > 0)) return proposal;  // only the unchanged path: nothing to propose
    double u = rng.next_float() * z;
    na = lo;
    for (; na < hi; ++na) {
      u -= addition_weight(na, nd);
      if (u < 0) break;
    }
  }
  const int j = std::min(int(rng.next_float() * float(na + 1)), na);
  // A large step draws a new shutter time (density 1: q and T unchanged); the others keep x's.
  y.time = proposal.type == MutationType::Large ? shutter_time(rng) : x.time;
  shutter::SampleTime at(y.time);
  proposal.l = l;
  proposal.m = m;
  proposal.na = na;
  y.n = kept + na;
  for (int i = 0; i <= l; ++i) y.x[size_t(i)] = x.x[size_t(i)];
  for (int i = m; i < nv; ++i) y.x[size_t(i - m + l + na + 1)] = x.x[size_t(i)];
  if (!regenerate(y, l, na, j, rng, stats)) return proposal;
  evaluate(y, stats);
  const float fy = y.carried();
  if (!(fy > 0)) return proposal;
  if (filter_.on() && !light_walk_made(y, l + j + 1, l + na)) return proposal;  // scattered where f blurs
  const double t_xy = transition_density(nv, l, m, y, na);
  const double t_yx = transition_density(y.n, l, l + na + 1, x, nd);
  if (!(t_xy > 0) || !std::isfinite(t_yx)) return proposal;
  proposal.ratio = t_yx / t_xy;
  if (proposal.type == MutationType::Large) proposal.independent = double(fy) / independent_density(y);
  return proposal;
}

Proposal PathSpace::perturb_medium_vertex(const ExplicitPath &x, MutationType type, Pcg32 &rng, RayStats &stats,
                                          ExplicitPath &y) const {
  Proposal proposal;
  proposal.type = type;
  const float u_vertex = rng.next_float(), u_size = rng.next_float(), u_direction = rng.next_float();
  int media = 0;
  for (int i = 1; i + 1 < x.n; ++i) media += x.x[size_t(i)].v.type == VertexType::Medium;
  if (media == 0) return proposal;
  int pick = std::min(int(u_vertex * float(media)), media - 1), j = 1;
  for (;; ++j)
    if (x.x[size_t(j)].v.type == VertexType::Medium && pick-- == 0) break;
  // A specular neighbour fixes x_j's direction from it: moving x_j can keep its event
  // only along the line from a specular light-side neighbour (the propagation
  // perturbation), never off it or from a specular camera-side neighbour. Those moves
  // would have f = 0 exactly; they are not proposed, since the comparison of directions
  // that finds a delta's event allows about 4e-3 rad, and small moves inside it would be
  // taken for paths on the event.
  if (x.x[size_t(j - 1)].v.delta || (type == MutationType::Scattering && x.x[size_t(j + 1)].v.delta)) return proposal;
  const ExplicitVertex &light_side = x.x[size_t(j + 1)];
  if (light_side.v.infinite && type == MutationType::Scattering &&
      light_is_delta_direction(scene_.lights()[size_t(light_side.v.light)]))
    return proposal;  // a sun without an angle: its direction cannot turn
  y.reserve(max_vertices_);
  y.n = x.n;
  y.time = x.time;
  shutter::SampleTime at(y.time);
  for (int i = 0; i < x.n; ++i) y.x[size_t(i)] = x.x[size_t(i)];
  if (light_side.v.infinite) {
    // The light-side neighbour is a direction (a light at infinity): propagation moves x_j
    // along it (a translation: Jacobian 1), scattering turns the direction at x_j by theta
    // ~ 1 / theta, phi uniform (symmetric in solid angle, the measure of that vertex).
    if (type == MutationType::Propagation) {
      const float lo = mutations_.distance[0], hi = mutations_.distance[1];
      const float distance = lo * std::pow(hi / lo, u_size);
      y.x[size_t(j)].v.p = x.x[size_t(j)].v.p - light_side.v.dir * (u_direction < 0.5f ? distance : -distance);
      settle(y.x[size_t(j)], y.x[size_t(j - 1)]);
      proposal.l = j - 1;
      proposal.m = j + 1;
    } else {
      const float lo = mutations_.angle[0], hi = mutations_.angle[1];
      const float theta = lo * std::pow(hi / lo, u_size), phi = 2 * kPi * u_direction;
      const Vec3 turned = normalize(Frame(light_side.v.dir)
                                        .to_world(Vec3(std::sin(theta) * std::cos(phi),
                                                       std::sin(theta) * std::sin(phi), std::cos(theta))));
      y.x[size_t(j + 1)].v.dir = turned;
      y.x[size_t(j + 1)].v.wo = -turned;
      proposal.l = j;
      proposal.m = j + 2;
    }
    evaluate(y, stats);
    if (!(y.carried() > 0)) return proposal;
    proposal.ratio = 1;
    proposal.na = 1;
    return proposal;
  }
  // Spherical coordinates of x_j about its light-side neighbour c.
  const Vec3 c = x.x[size_t(j + 1)].v.p;
  const Vec3 d = x.x[size_t(j)].v.p - c;
  const float r = length(d);
  if (!(r > 0)) return proposal;
  const Vec3 w = d / r;
  Vec3 p;
  double jacobian = 1;
  if (type == MutationType::Propagation) {
    // D ~ 1 / D on [Dmin, Dmax], either way along the line from c (never past c).
    const float lo = mutations_.distance[0], hi = mutations_.distance[1];
    const float distance = lo * std::pow(hi / lo, u_size);
    const float r_new = u_direction < 0.5f ? r + distance : r - distance;
    if (!(r_new > 0)) return proposal;
    p = c + w * r_new;
    jacobian = (double(r_new) * r_new) / (double(r) * r);
  } else {
    // theta ~ 1 / theta on [theta_min, theta_max], phi uniform: a density in solid angle
    // that depends on the angle between the directions only.
    const float lo = mutations_.angle[0], hi = mutations_.angle[1];
    const float theta = lo * std::pow(hi / lo, u_size), phi = 2 * kPi * u_direction;
    Frame frame(w);
    p = c + frame.to_world(Vec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta))) * r;
  }
  y.x[size_t(j)].v.p = p;
  settle(y.x[size_t(j)], y.x[size_t(j - 1)]);
  settle(y.x[size_t(j + 1)], y.x[size_t(j)]);  // its camera-side neighbour moved
  evaluate(y, stats);
  if (!(y.carried() > 0)) return proposal;
  proposal.ratio = jacobian;
  proposal.l = j - 1;
  proposal.m = j + 1;
  proposal.na = 1;
  return proposal;
}

int PathSpace::retrace_lens(const ExplicitPath &x, Vec2 raster, bool keep, Pcg32 &rng, RayStats &stats,
                            ExplicitPath &y) const {
  const int c = first_non_specular(x);
  if (!in_sample_region(raster)) return 0;
  y.reserve(max_vertices_);
  y.n = x.n;
  y.time = x.time;  // the caller's shutter::SampleTime is at it
  for (int i = 0; i < x.n; ++i) y.x[size_t(i)] = x.x[size_t(i)];
  // Pauly's retrace: a medium x_c keeps its distance from x_(c-1).
  const float kept = kept_distance(x, c, c - 1, keep);
  Ray ray = camera_ray(y.x[0], raster);
  // (a thin lens's ray leaves its lens point, x_0)
  const float t = c == 1 ? kept_past(kept, dot(ray.o - y.x[0].v.p, ray.d)) : -1.0f;
  if (!trace_step(ray, y.x[0].v.media, Side::Camera, rng, stats, y.x[1], y.n == 2, t)) return 0;
  settle(y.x[1], y.x[0]);
  // Through the specular chain as the camera walk samples it: each of y_1 .. y_(c-1) must
  // scatter by a delta lobe (y's chain then has x's shape, so the move can be undone).
  for (int k = 1; k < c; ++k)
    if (!extend_from_camera_side(y, k + 1, rng, stats, -1, k + 1 == c ? kept : -1.0f) || !y.x[size_t(k)].v.delta)
      return 0;
  if (keep && y.x[size_t(c)].v.type != x.x[size_t(c)].v.type) return 0;  // the path's kinds are kept
  return c;
}

Proposal PathSpace::lens_move(const ExplicitPath &x, Vec2 raster, bool keep, MutationType type, Pcg32 &rng,
                              RayStats &stats, ExplicitPath &y) const {
  Proposal proposal;
  proposal.type = type;
  proposal.kept_distances = keep;
  const int c = first_non_specular(x);
  if (c > x.n - 2 || x.x[size_t(c + 1)].v.delta) return proposal;  // a delta cannot be joined
  shutter::SampleTime at(x.time);  // every mutation but the large step keeps x's shutter time
  if (retrace_lens(x, raster, keep, rng, stats, y) != c) return proposal;
  settle(y.x[size_t(c + 1)], y.x[size_t(c)]);
  evaluate(y, stats);
  if (!(y.carried() > 0)) return proposal;
  // The raster point's density is the same both ways (a symmetric offset, or uniform); the
  // rest is the camera walk's density of x_1 .. x_c (fwd[1] holds the uniform raster
  // density times the raster-to-area Jacobian), event probabilities included.
  double px = 1, py = 1;
  for (int k = 1; k <= c; ++k) {
    px *= x.fwd[size_t(k)];
    py *= y.fwd[size_t(k)];
  }
  if (keep && x.x[size_t(c)].v.type == VertexType::Medium) {  // no free flight drawn for y_c
    px /= camera_side_flight(x, c);
    py /= camera_side_flight(y, c);
  }
  if (!(py > 0) || !std::isfinite(px)) return proposal;
  proposal.ratio = px / py;
  proposal.l = 0;
  proposal.m = c + 1;
  proposal.na = c;
  return proposal;
}

Proposal PathSpace::perturb_lens(const ExplicitPath &x, Pcg32 &rng, RayStats &stats, ExplicitPath &y) const {
  const float u_radius = rng.next_float(), u_angle = rng.next_float();
  const float lo = mutations_.lens[0], hi = mutations_.lens[1];
  const float radius = lo * std::pow(hi / lo, u_radius), angle = 2 * kPi * u_angle;
  const Vec2 raster{x.raster.x + radius * std::cos(angle), x.raster.y + radius * std::sin(angle)};
  return lens_move(x, raster, keeps_distances(rng), MutationType::Lens, rng, stats, y);
}

int PathSpace::walk_lens_subpath(const ExplicitPath &x, Vec2 raster, bool to_light, int after, Pcg32 &rng,
                                 RayStats &stats, ExplicitPath &y) const {
  if (!in_sample_region(raster)) return 0;
  y.reserve(max_vertices_);
  y.time = x.time;  // the caller's shutter::SampleTime is at it
  y.x[0] = x.x[0];
  Ray ray = camera_ray(y.x[0], raster);
  if (!trace_step(ray, y.x[0].v.media, Side::Camera, rng, stats, y.x[1], to_light)) return 0;
  settle(y.x[1], y.x[0]);
  for (int k = 1; k < max_vertices_; ++k) {
    const PathVertex &z = y.x[size_t(k)].v;
    if (to_light && (z.type == VertexType::Light || z.light >= 0)) return k;  // a light: the path's end
    if (z.type != VertexType::Surface || !z.bsdf.is_delta()) return k + after < max_vertices_ ? k : 0;
    if (k + 1 == max_vertices_ || !extend_from_camera_side(y, k + 1, rng, stats, to_light ? 1 : 0) || !z.delta)
      return 0;
  }
  return 0;
}

double PathSpace::lens_subpath_density(const ExplicitPath &p, int c, bool short_path) const {
  double density = 1;
  for (int k = 1; k <= c; ++k) density *= p.fwd[size_t(k)];
  if (!(density > 0)) return 0;
  for (int k = 1; k < c; ++k) {
    const PathVertex &z = p.x[size_t(k)].v;
    if (z.type != VertexType::Surface || !z.bsdf.is_delta() || !z.delta) return 0;
    if (short_path && z.light >= 0) return 0;  // the walk would have ended at this mesh lamp
  }
  if (!short_path) return density;
  // A short path's walk ends at the first light it meets: E S* D L needs a D that is none (no
  // mesh lamp, no free flight stopped in a volume light), and then a light vertex of the
  // light side's density.
  const bool to_d = c == p.n - 2;
  if (to_d) {
    const PathVertex &d = p.x[size_t(c)].v;
    if (d.light >= 0 || (d.type == VertexType::Medium && scene_.medium(d.medium).light >= 0)) return 0;
    density *= p.rev[size_t(p.n - 1)];
  }
  if (!hittable_lamps_.empty()) {
    // Each step could end at a lamp in front of what it reaches (the last step to the light:
    // fwd[c]'s business, evaluate()).
    const Camera &camera = scene_.camera_now();
    for (int k = 0; k + 1 < c || (to_d && k < c); ++k) {
      Vec3 from = p.x[size_t(k)].v.p;
      const Vec3 d = p.x[size_t(k + 1)].v.p - from;
      const float length_d = length(d);
      const Vec3 w = d / length_d;
      if (k == 0) from = from + w * (camera.clip_start / dot(w, camera.forward()));  // camera rays start at the clip plane
      float t;
      if (first_lamp(from, w, length_d * (1 - 1e-4f), t, ray_mask(p, k, w)) >= 0) return 0;
    }
  }
  return density;
}

Proposal PathSpace::lens_subpath(const ExplicitPath &x, Vec2 raster, Pcg32 &rng, RayStats &stats,
                                 ExplicitPath &y) const {
  Proposal proposal;
  proposal.type = MutationType::LensSubpath;
  const int c = first_non_specular(x);
  // A short path (E S* L, E S* D L): the whole path anew, a walk to the first light it meets
  // or to a non-specular vertex joined to a light vertex from the light side. Else x_(c+1) ..
  // are kept and the walk's end joined to x_(c+1).
  const bool short_path = c >= x.n - 2;
  if (!short_path && x.x[size_t(c + 1)].v.delta) return proposal;  // a delta cannot be joined
  shutter::SampleTime at(x.time);  // every mutation but the large step keeps x's shutter time
  const int after = short_path ? 1 : x.n - 1 - c;  // room after the walk's non-specular end
  const int cy = walk_lens_subpath(x, raster, short_path, after, rng, stats, y);
  if (cy == 0) return proposal;
  if (short_path) {
    const ExplicitVertex &end = y.x[size_t(cy)];
    if (end.v.type == VertexType::Light || end.v.light >= 0) {
      y.n = cy + 1;
    } else {
      Vec3 dir;
      if (!light_vertex(rng, y.x[size_t(cy + 1)], dir)) return proposal;
      y.n = cy + 2;
      settle(y.x[size_t(cy + 1)], y.x[size_t(cy)]);
    }
  } else {
    y.n = cy + 1 + after;
    for (int i = c + 1; i < x.n; ++i) y.x[size_t(i - c + cy)] = x.x[size_t(i)];
    settle(y.x[size_t(cy + 1)], y.x[size_t(cy)]);
  }
  evaluate(y, stats);
  if (!(y.carried() > 0)) return proposal;
  const double px = lens_subpath_density(x, c, short_path), py = lens_subpath_density(y, cy, short_path);
  if (!(py > 0) || !std::isfinite(px)) return proposal;
  proposal.ratio = px / py;
  proposal.l = 0;
  proposal.m = short_path ? x.n : c + 1;
  proposal.na = y.n - 1 - (short_path ? 0 : after);
  return proposal;
}

Proposal PathSpace::perturb_multi_chain(const ExplicitPath &x, Pcg32 &rng, RayStats &stats, ExplicitPath &y) const {
  Proposal proposal;
  proposal.type = MutationType::MultiChain;
  const float u_radius = rng.next_float(), u_angle = rng.next_float();
  // x_c on the light (E S* L: the camera's chain must hit it again), or followed by a
  // specular vertex; else the path is the lens perturbation's.
  const int c = first_non_specular(x);
  if (c < x.n - 1 && !x.x[size_t(c + 1)].v.delta) return proposal;
  const float lo = mutations_.lens[0], hi = mutations_.lens[1];
  const float radius = lo * std::pow(hi / lo, u_radius), angle = 2 * kPi * u_angle;
  const Vec2 raster{x.raster.x + radius * std::cos(angle), x.raster.y + radius * std::sin(angle)};
  const bool keep = proposal.kept_distances = keeps_distances(rng);
  shutter::SampleTime at(x.time);  // every mutation but the large step keeps x's shutter time
  if (retrace_lens(x, raster, keep, rng, stats, y) != c) return proposal;
  // Chain by chain: x_a not specular, x_(a+1) .. x_(b-1) specular, x_b not (or the light).
  int kept = c + 1;  // the first vertex y keeps
  for (int a = c; a < x.n - 1 && x.x[size_t(a + 1)].v.delta;) {
    int b = a + 1;
    while (b < x.n - 1 && x.x[size_t(b)].v.delta) ++b;
    const float u_size = rng.next_float(), u_azimuth = rng.next_float();
    const Vec3 w = turned(toward(x.x[size_t(a)], x.x[size_t(a + 1)]), mutations_.caustic[0], mutations_.caustic[1],
                          u_size, u_azimuth);
    // Filter Glossy: the vertices after y_a are blurred by a prefix that includes y_a's
    // density of the turned direction (f's rule, evaluate()), which the walk on samples.
    float turned_pdf = kInf;
    if (filter_.on()) {
      ExplicitVertex &end = y.x[size_t(a)];
      if (end.v.type == VertexType::Medium) {
        turned_pdf = scene_.medium(end.v.medium).phase.pdf(end.v.wo, w);
      } else {
        blur_by_prefix(end);
        turned_pdf = end.v.bsdf.pdf(end.v.wo, w);
      }
    }
    if (!trace_from(y, a, w, turned_pdf, rng, stats)) return proposal;
    const ExplicitVertex &x_b = x.x[size_t(b)];
    const float flight = kept_distance(x, b, b - 1, keep);
    for (int k = a + 1; k < b; ++k)
      if (!extend_from_camera_side(y, k + 1, rng, stats, -1, k + 1 == b ? flight : -1.0f) || !y.x[size_t(k)].v.delta)
        return proposal;
    if (keep && y.x[size_t(b)].v.type != x_b.v.type) return proposal;
    a = b;
    kept = b + 1;
  }
  if (kept < x.n) settle(y.x[size_t(kept)], y.x[size_t(kept - 1)]);
  evaluate(y, stats);
  if (!(y.carried() > 0)) return proposal;
  // The raster offset's and the turns' densities are symmetric: what is left is the camera
  // walk's density of the moved vertices, each turned direction's vertex without its
  // directional part, and with Pauly's retrace each medium end of a chain (x_c, the x_b)
  // without its free flight.
  auto walk_density = [&](const ExplicitPath &p) {
    double d = 1;
    for (int k = 1; k < kept; ++k) {
      const bool turned_to = k - 1 >= c && !x.x[size_t(k - 1)].v.delta && x.x[size_t(k)].v.delta;
      d *= turned_to ? p.fwd_area[size_t(k)] : p.fwd[size_t(k)];
      if (keep && x.x[size_t(k)].v.type == VertexType::Medium) d /= camera_side_flight(p, k);
    }
    return d;
  };
  const double px = walk_density(x), py = walk_density(y);
  if (!(py > 0) || !std::isfinite(px)) return proposal;
  proposal.ratio = px / py;
  proposal.l = 0;
  proposal.m = kept;
  proposal.na = kept - 1;
  return proposal;
}

Proposal PathSpace::perturb_caustic(const ExplicitPath &x, Pcg32 &rng, RayStats &stats, ExplicitPath &y) const {
  Proposal proposal;
  proposal.type = MutationType::Caustic;
  const float u_size = rng.next_float(), u_azimuth = rng.next_float();
  if (x.n < 4 || x.x[1].v.delta) return proposal;
  int k = 2;
  while (k < x.n - 1 && x.x[size_t(k)].v.delta) ++k;
  if (k < 3 || x.x[size_t(k)].v.delta) return proposal;  // no specular chain before a non-specular x_k
  const float lo = mutations_.caustic[0], hi = mutations_.caustic[1];
  const float theta = lo * std::pow(hi / lo, u_size), phi = 2 * kPi * u_azimuth;
  const Vec3 local(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
  // Pauly's retrace: a medium x_1 keeps its distance from x_2.
  const bool keep = proposal.kept_distances = keeps_distances(rng);
  const bool kept_x1 = keep && x.x[1].v.type == VertexType::Medium;
  y.reserve(max_vertices_);
  y.n = x.n;
  y.time = x.time;
  shutter::SampleTime at(y.time);
  for (int i = 0; i < x.n; ++i) y.x[size_t(i)] = x.x[size_t(i)];
  const ExplicitVertex &end = y.x[size_t(k)];
  Ray ray;
  MediumStack media;
  if (end.v.infinite) {
    // A light at infinity: its rays are parallel; the one through x_(k-1) moved across
    // the direction by R theta (R the scene's bounding radius; theta as below, phi uniform:
    // a density over the disk the light side samples that depends on the offset's length
    // only), traced from that disk. rev_area[k - 1] is then the disk-to-area factor.
    const Vec3 dir = end.v.dir;
    const Frame frame(dir);
    const float radius = scene_.bounding_radius(), shift = radius * theta;
    const Vec3 through = x.x[size_t(k - 1)].v.p + (frame.s * std::cos(phi) + frame.t * std::sin(phi)) * shift;
    const Vec3 o = through + dir * (radius - dot(through - scene_.bounding_center(), dir));
    ray = Ray{o, -dir, kInf, light_walk_mask()};
    media = media_ ? MediumStack::from(scene_.media_along(o, -dir)) : MediumStack();
  } else {
    const Vec3 from = x.x[size_t(k)].v.p;
    const Vec3 d = x.x[size_t(k - 1)].v.p - from;
    if (!(length_squared(d) > 0)) return proposal;
    const Vec3 w = Frame(normalize(d)).to_world(local);
    ray = Ray{end.v.on_surface() ? spawn_origin(end.v.p, end.v.ng, end.v.error, w) : end.v.p, w, kInf,
              light_walk_mask()};
    media = stack_toward(end, w);
  }
  if (!trace_step(ray, media, Side::Light, rng, stats, y.x[size_t(k - 1)])) return proposal;
  const float kept = kept_distance(x, 1, 2, keep);
  for (int at = k - 2; at >= 1; --at)
    if (!extend_from_light_side(y, at, rng, stats, at == 1 ? kept : -1.0f) || !y.x[size_t(at + 1)].v.delta)
      return proposal;
  if (keep && y.x[1].v.type != x.x[1].v.type) return proposal;  // the path's kinds are kept
  for (int i = 1; i <= k; ++i) settle(y.x[size_t(i)], y.x[size_t(i - 1)]);
  evaluate(y, stats);
  if (!(y.carried() > 0)) return proposal;
  double px = x.rev_area[size_t(k - 1)], py = y.rev_area[size_t(k - 1)];
  for (int i = 1; i <= k - 2; ++i) {
    px *= x.rev[size_t(i)];
    py *= y.rev[size_t(i)];
  }
  if (kept_x1) {  // no free flight drawn for y_1
    px /= light_side_flight(x, 1);
    py /= light_side_flight(y, 1);
  }
  if (!(py > 0) || !std::isfinite(px)) return proposal;
  proposal.ratio = px / py;
  proposal.l = 0;
  proposal.m = k;
  proposal.na = k - 1;
  return proposal;
}

}  // namespace rdv::mlt
