// Path-space MLT's acceptance ratio T(y -> x) / T(x -> y) of the bidirectional mutation and
// the lens perturbation against a brute-force
// evaluation. For random paths mlt really makes (Cornell box: surfaces and a mesh lamp;
// fog through a door gap: medium vertices and an area lamp), each proposal's ratio is
// recomputed here from scratch in double precision: every vertex density from the
// BSDFs rebuilt from the hits (not the vertices' stored ones), the phase function, the
// camera's and the lamp's emission densities and the closed-form free flights through
// the fog measured between the vertices; the deletion and addition probabilities by
// enumerating every deletion; the sum over the splits of the new vertices as an explicit
// double loop. Also: f is a function of the vertices (re-building every BSDF by the
// rule gives the same f), and a proposal never touches the state it mutates (rejected
// proposals leave it bit-identical). Deterministic (fixed seeds): nothing fails by chance.
// Lamps with a radius: their sphere's point and direction densities (lights/sphere_lamp.h)
// written out here from the point's offset from the lamp's centre.
// Specular vertices (the glass ball and the mirror of mirror_caustic, its lamp made a
// point): their densities are the event's probability from a Fresnel term written out here
// in double precision (1 for the mirror), the light side's divided by the refraction's
// d omega_camera / d omega_light = cos_l / (eta^2 cos_c) (the delta about the direction
// toward the light that f carries), and splits that would connect at one are left out.
#include <gtest/gtest.h>
#include <cmath>
#include <cstring>
#include <nlohmann/json.hpp>
#include "api/handles.h"
#include "integrators/mlt/path_space.h"
#include "integrators/filter_glossy.h"
#include "lights/light.h"
#include "lights/sphere_lamp.h"
#include "scene/motion.h"
#include "lights/volume_light.h"
#include "chi_square.h"
#include "media_grids.h"
#include "render_helpers.h"

namespace test_path_mlt_densities {

using namespace rdv;
using namespace rdv::mlt;
using bdpt::VertexType;

namespace {

constexpr int kWidth = 32, kHeight = 32, kMaxBounces = 6;
constexpr float kLargeStep = 0.3f;
// Equiangular distances toward point and spot lamps (off by default) are on in these
// checks, at the share whose random sequence found the kept-distance defect (kept_past).
MutationSettings checked_mutations() {
  MutationSettings m;
  m.equiangular = 0.25f;
  return m;
}

struct LoadedScene {
  rdv_scene *handle = nullptr;
  ~LoadedScene() { rdv_scene_destroy(handle); }
  const Scene &scene() const { return *handle->scene; }
};

void load(LoadedScene &s, const nlohmann::json &j) {
  rdv_scene_create(&s.handle);
  rdv_tools::load_scene_json(j.dump(), test::source_path("scenes"), s.handle);
  ASSERT_EQ(rdv_scene_commit(s.handle), RDV_OK);
  s.handle->scene->camera().set_resolution(kWidth, kHeight);
}

// The sample region of a kWidth x kHeight image with the default 1.5 px filter.
constexpr float kFilterRadius = 1.5f;
const Vec2 kOrigin{-kFilterRadius, -kFilterRadius};
const Vec2 kSize{kWidth + 2 * kFilterRadius, kHeight + 2 * kFilterRadius};

struct BruteForce {
  const Scene &scene;
  int max_vertices = kMaxBounces + 2;
  // Or a box of homogeneous medium (axis-aligned, medium 0) in a scene without a world one.
  bool box = false;
  Vec3 box_lo{0.0f}, box_hi{0.0f};
  // The large steps' vertex counts 2 .. max_vertices by these weights (PathSpace::
  // set_length_weights: a quarter uniform, the rest in proportion), or uniform if empty.
  std::vector<double> length_weights;

  // The length of the line a + t d, t in [0, tmax], inside the box (slabs).
  double inside_box(Vec3 a, Vec3 d, double tmax) const {
    double t0 = 0, t1 = tmax;
    for (int k = 0; k < 3; ++k) {
      const double o = (&a.x)[k], dk = (&d.x)[k], lo = (&box_lo.x)[k], hi = (&box_hi.x)[k];
      if (dk == 0) {
        if (o < lo || o > hi) return 0;
        continue;
      }
      double ta = (lo - o) / dk, tb = (hi - o) / dk;
      if (ta > tb) std::swap(ta, tb);
      t0 = std::max(t0, ta);
      t1 = std::min(t1, tb);
    }
    return t1 > t0 ? t1 - t0 : 0.0;
  }
  // Grid fog (the box's medium a grid, box = true): the column of a -> b (the density's
  // integral along it) by composite Simpson on 8,192 intervals of the part inside the box,
  // in double; the density where a flight stops read at b.
  bool grid = false;
  double grid_flight(Vec3 a, Vec3 b, bool stops) const {
    const Medium &m = scene.medium(0);
    if (max_component(m.sigma_s) == 0) return stops ? 0.0 : 1.0;  // never stops, Tr is in f
    const DensityGrid &g = *m.grid;
    const Vec3 d = normalize(b - a);
    const double length_ab = length(b - a);
    double t0 = 0, t1 = length_ab;
    for (int k = 0; k < 3; ++k) {
      const double o = (&a.x)[k], dk = (&d.x)[k], lo = (&box_lo.x)[k], hi = (&box_hi.x)[k];
      if (dk == 0) {
        if (o < lo || o > hi) t1 = t0;
        continue;
      }
      double ta = (lo - o) / dk, tb = (hi - o) / dk;
      if (ta > tb) std::swap(ta, tb);
      t0 = std::max(t0, ta);
      t1 = std::min(t1, tb);
    }
    double column = 0;
    if (t1 > t0) {
      constexpr int kIntervals = 8192;
      const double h = (t1 - t0) / kIntervals;
      for (int i = 0; i <= kIntervals; ++i) {
        const double t = t0 + i * h, w = i == 0 || i == kIntervals ? 1 : (i % 2 ? 4 : 2);
        column += w * g.density(g.world_to_grid().point(a + d * float(t)));
      }
      column *= h / 3;
    }
    const double end_density = g.density(g.world_to_grid().point(b));
    double s = 0;
    for (int c = 0; c < 3; ++c) {
      const double st = m.sigma_t[c], tr = std::exp(-st * column);
      s += stops ? st * end_density * tr : tr;
    }
    return s / 3;
  }
  double box_flight(double length_inside, bool stops) const {
    const Medium &m = scene.medium(0);
    double s = 0;
    for (int c = 0; c < 3; ++c) {
      double st = m.sigma_t[c], tr = std::exp(-st * length_inside);
      s += stops ? st * tr : tr;
    }
    return s / 3;
  }

  // Free flight over the straight segment a -> b in the world medium (the only medium of
  // these scenes): stopping in it at b, or passing it.
  double free_flight(Vec3 a, Vec3 b, bool stops) const {
    if (box && grid) return grid_flight(a, b, stops);
    if (box) return box_flight(inside_box(a, normalize(b - a), length(b - a)), stops);
    const int wm = scene.world_medium();
    const double d = length(b - a);
    if (wm < 0) return stops ? 0.0 : 1.0;
    const Medium &m = scene.medium(wm);
    if (max_component(m.sigma_s) == 0) return stops ? 0.0 : 1.0;
    double s = 0;
    for (int c = 0; c < 3; ++c) {
      double st = m.sigma_t[c], tr = std::exp(-st * d);
      s += stops ? st * tr : tr;
    }
    return s / 3;
  }
  // Camera-side walks in a scattering medium draw each distance from the mixture (1 -
  // share) x free flight + share x an equiangular distance toward a point or spot lamp
  // chosen by power (mlt/equiangular.h), over [0, inf) from where the ray enters the medium:
  // here in Kulla and Fajardo's angles theta in [atan(-delta / h), pi / 2), in double.
  double equiangular_share = 0;
  std::vector<std::pair<Vec3, double>> lamps;  // centre, probability
  double equiangular(Vec3 o, Vec3 d, double t, bool stops) const {
    double sum = 0;
    for (const auto &[c, weight] : lamps) {
      const double x[3] = {double(c.x) - o.x, double(c.y) - o.y, double(c.z) - o.z}, e[3] = {d.x, d.y, d.z};
      const double delta = x[0] * e[0] + x[1] * e[1] + x[2] * e[2];
      double h2 = 0;  // |x - delta e|^2
      for (int k = 0; k < 3; ++k) h2 += (x[k] - delta * e[k]) * (x[k] - delta * e[k]);
      const double h = std::sqrt(h2);
      const double theta_a = std::atan(-delta / h), theta_b = kPi / 2.0;
      sum += weight * (stops ? h / ((theta_b - theta_a) * (h * h + (t - delta) * (t - delta)))
                             : (theta_b - std::atan((t - delta) / h)) / (theta_b - theta_a));
    }
    return sum;
  }
  // The camera side's flight over a -> b: the free flight mixed with the equiangular one
  // over the part of the segment inside the medium.
  // A walk draws its distances afresh after each plain layer it passes, as after a medium
  // boundary: the mixture is taken piece by piece between the layers on the segment.
  // stops: b is a point in the medium; a_in_medium: so is a (no surface at that end: the
  // pieces run to it, as the walks' rays do).
  double camera_flight(Vec3 a, Vec3 b, bool stops, bool a_in_medium = false) const {
    if (!layers) return camera_flight_piece(a, b, stops);
    const Vec3 d = normalize(b - a);
    double product = 1;
    Vec3 start = a;
    for (bool first = true;; first = false) {
      const float left = length(b - start);
      const float gap_start = first ? end_gap(a_in_medium) : 1e-4f, gap_end = end_gap(stops);
      SurfaceHit hit;
      if (!(left > gap_start + gap_end) || !scene.intersect(Ray{start + d * gap_start, d, left - gap_start - gap_end}, hit))
        break;
      product *= camera_flight_piece(start, hit.p, false);
      start = hit.p;
    }
    return product * camera_flight_piece(start, b, stops);
  }
  double camera_flight_piece(Vec3 a, Vec3 b, bool stops) const {
    const double free = free_flight(a, b, stops);
    const Medium *m = box ? &scene.medium(0) : scene.world_medium() >= 0 ? &scene.medium(scene.world_medium()) : nullptr;
    if (equiangular_share == 0 || !m || max_component(m->sigma_s) == 0) return free;
    const Vec3 d = normalize(b - a);
    const double length_ab = length(b - a);
    double t0 = 0, t1 = length_ab;
    if (box) {
      for (int k = 0; k < 3; ++k) {
        const double o = (&a.x)[k], dk = (&d.x)[k], lo = (&box_lo.x)[k], hi = (&box_hi.x)[k];
        if (dk == 0) continue;
        double ta = (lo - o) / dk, tb = (hi - o) / dk;
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
      }
      if (!(t1 > t0)) return free;  // the segment misses the medium
    }
    const Vec3 o = a + d * float(t0);
    return (1 - equiangular_share) * free + equiangular_share * equiangular(o, d, stops ? length_ab - t0 : t1 - t0, stops);
  }
  // Lights at infinity: their vertex is the direction toward the light.
  static Vec3 dir(const ExplicitPath &p, int from, int to) {
    if (p.x[size_t(to)].v.infinite) return p.x[size_t(to)].v.dir;
    if (p.x[size_t(from)].v.infinite) return -p.x[size_t(from)].v.dir;
    return normalize(p.x[size_t(to)].v.p - p.x[size_t(from)].v.p);
  }
  // An edge to a light at infinity: these scenes have no world medium there.
  double free_flight(const ExplicitPath &p, int a, int b, bool stops) const {
    const bdpt::PathVertex &va = p.x[size_t(a)].v, &vb = p.x[size_t(b)].v;
    if (box && (va.infinite || vb.infinite)) {
      const bdpt::PathVertex &finite = va.infinite ? vb : va, &light = va.infinite ? va : vb;
      return box_flight(inside_box(finite.p, light.dir, 1e30), stops);
    }
    if (va.infinite || vb.infinite) return scene.world_medium() < 0 ? 1.0 : 0.0;
    return free_flight(p.x[size_t(a)].v.p, p.x[size_t(b)].v.p, stops);
  }
  // The camera walk's last step (to the light) ends at the first lamp it meets: where it
  // enters the sphere of a point or spot lamp with a radius (area lamps: none in the scenes
  // that mix them with others). Another lamp's sphere on the last edge makes the path's
  // camera-side density 0 there.
  bool other_lamp_on_last_edge(const ExplicitPath &p) const {
    const int n = p.n;
    const bdpt::PathVertex &last = p.x[size_t(n - 1)].v;
    Vec3 from = p.x[size_t(n - 2)].v.p;
    const Vec3 w = last.infinite ? last.dir : normalize(last.p - from);
    if (n == 2) from = from + w * float(scene.camera_now().clip_start / dot(w, scene.camera_now().forward()));
    const double length_d = last.infinite ? 1e30 : double(length(last.p - from)) * (1 - 1e-4);
    for (size_t k = 0; k < scene.lights().size(); ++k) {
      const Light &l = scene.lights()[k];
      if (int(k) == last.light || !(l.type == LightType::Point || l.type == LightType::Spot) || !(l.radius > 0)) continue;
      const double oc[3] = {double(from.x) - l.position.x, double(from.y) - l.position.y, double(from.z) - l.position.z};
      const double b = oc[0] * w.x + oc[1] * w.y + oc[2] * w.z;
      const double disc = b * b - (oc[0] * oc[0] + oc[1] * oc[1] + oc[2] * oc[2] - double(l.radius) * l.radius);
      if (disc < 0) continue;
      const double t_enter = -b - std::sqrt(disc);
      if (t_enter > 0 && t_enter < length_d) return true;
    }
    return false;
  }
  // The camera side's flight over the edge a -> b (b may be a light at infinity).
  double camera_flight(const ExplicitPath &p, int a, int b, bool stops) const {
    const bdpt::PathVertex &va = p.x[size_t(a)].v, &vb = p.x[size_t(b)].v;
    if (vb.infinite) return box ? camera_flight(va.p, va.p + vb.dir * 1e4f, stops) : free_flight(p, a, b, stops);
    return camera_flight(va.p, vb.p, stops, va.type == VertexType::Medium);
  }
  // A specular vertex's event from wo to wi (smooth glass of IOR 1.5, or a mirror): its
  // probability and d omega_wi / d omega_wo; 0 when wi is not where the event sends wo.
  double specular_event(const ExplicitVertex &v, Vec3 wo, Vec3 wi, double &jacobian) const {
    jacobian = 1;
    const Material &material = scene.material(v.hit.material);
    Vec3 n = v.hit.ns;
    if (dot(n, v.hit.ng) < 0) n = -n;
    const bool front = dot(wo, v.hit.ng) > 0;
    if (!front) n = -n;  // the side wo is on
    const double ci = dot(wo, n);
    if (!(ci > 0)) return 0;
    const bool reflection = dot(wo, v.hit.ng) * dot(wi, v.hit.ng) > 0;
    if (material.type != MaterialType::Glass) {
      if (!reflection) return 0;
      Vec3 r = n * float(2 * ci) - wo;
      // A mirror on a plain layer (alpha): the event is the mirror's pick, the rest passes.
      const double pick = layers && scene.is_plain_layer(v.hit) ? 1 - pass_probability(v.hit, wo) : 1.0;
      return dot(r, wi) > 1 - 1e-5 ? pick : 0.0;
    }
    const double eta = front ? 1.5 : 1 / 1.5;  // the far side's IOR over the near side's
    const double sin2_t = (1 - ci * ci) / (eta * eta);
    double F = 1, ct = 0;
    if (sin2_t < 1) {
      ct = std::sqrt(1 - sin2_t);
      const double rs = (ci - eta * ct) / (ci + eta * ct), rp = (eta * ci - ct) / (eta * ci + ct);
      F = 0.5 * (rs * rs + rp * rp);
    }
    if (reflection) {
      Vec3 r = n * float(2 * ci) - wo;
      return dot(r, wi) > 1 - 1e-5 ? F : 0.0;
    }
    if (F >= 1) return 0;
    const double ax = -wo.x / eta + n.x * (ci / eta - ct), ay = -wo.y / eta + n.y * (ci / eta - ct),
                 az = -wo.z / eta + n.z * (ci / eta - ct);
    if (ax * wi.x + ay * wi.y + az * wi.z < 1 - 1e-5) return 0;
    jacobian = ci / (eta * eta * ct);
    return 1 - F;
  }
  // The density of scattering at vertex v from direction wo into wi, v's BSDF rebuilt
  // from its hit with wo as the direction it is built from. Specular vertices: the
  // event's probability (a delta about wi); toward_camera: sampled from the light side,
  // converted to the delta about wo. blur: the BSDF blurred so (Filter Glossy).
  double scatter_pdf(const ExplicitVertex &v, Vec3 wo, Vec3 wi, bool toward_camera = false, float blur = 0) const {
    if (v.v.type == VertexType::Medium) return scene.medium(v.v.medium).phase.pdf(wo, wi);
    if (v.v.delta) {
      double jacobian;
      double p = specular_event(v, wo, wi, jacobian);
      return toward_camera ? p / jacobian : p;
    }
    Bsdf bsdf = scene.bsdf(v.hit, wo, 0);
    bsdf.blur(blur);
    return bsdf.pdf(wo, wi);
  }
  // Filter Glossy (filter_glossy.h), written out: the roughness vertex k's BSDF is blurred
  // with in f, from the smallest camera-side scattering density before it, each of those
  // from the BSDF rebuilt from its hit and blurred by its own prefix in turn.
  FilterGlossy filter{0};
  float blur_alpha(const ExplicitPath &p, int k) const {
    if (!filter.on()) return 0;
    float min_pdf = kInf, alpha = 0;
    for (int j = 1; j <= k; ++j) {
      alpha = filter.alpha_after(min_pdf);  // vertex j's
      if (j < k && !p.x[size_t(j)].v.delta)
        min_pdf = std::min(min_pdf, float(scatter_pdf(p.x[size_t(j)], dir(p, j, j - 1), dir(p, j, j + 1), false, alpha)));
    }
    return alpha;
  }
  // Solid angle at `from` to area at i; from a light at infinity: its disk to area at i (the
  // cosine there); to one: none (its vertex is in solid angle).
  double to_area(const ExplicitPath &p, int from, int i) const {
    const bdpt::PathVertex &v = p.x[size_t(i)].v;
    if (v.infinite) return 1;
    if (p.x[size_t(from)].v.infinite) return v.on_surface() ? std::fabs(dot(v.ng, p.x[size_t(from)].v.dir)) : 1.0;
    Vec3 d = v.p - p.x[size_t(from)].v.p;
    double cos = v.on_surface() ? std::fabs(dot(v.ng, normalize(d))) : 1.0;
    return cos / double(length_squared(d));
  }
  // An orthographic camera without depth of field: x_0 is x_1's foot, the direction a delta.
  bool orthographic_pinhole() const {
    return scene.camera_now().type == Camera::Type::Orthographic && !(scene.camera_now().aperture_radius > 0);
  }
  bool orthographic_lens() const {
    return scene.camera_now().type == Camera::Type::Orthographic && scene.camera_now().aperture_radius > 0;
  }
  // Orthographic with depth of field: x_0 uniform over the plane under the sample region
  // (kOrigin, kSize in pixels) widened by the aperture's radius on every side; x_1 by an
  // offset uniform on the aperture, the ray from x_0 aimed at the focal-plane point of the
  // raster point x_0 less that offset: per solid angle d^2 / (A_lens cos^3), d the focus
  // distance (the focal-plane point moves d / cos^2 per radian across, d / cos along).
  double orthographic_lens_region() const {
    const Camera &camera = scene.camera_now();
    const double px = double(camera.right - camera.left) / kWidth, py = double(camera.top - camera.bottom) / kHeight;
    const double r = camera.aperture_radius;
    return (kSize.x * px + 2 * r) * (kSize.y * py + 2 * r);
  }
  double orthographic_lens_direction(Vec3 w) const {
    const Camera &camera = scene.camera_now();
    const double c = dot(w, camera.forward()), d = camera.focus_distance;
    return d * d / (aperture_area() * c * c * c);
  }
  // The aperture's area: a disk, or a regular polygon of `blades` corners on its circle.
  double aperture_area() const {
    const Camera &camera = scene.camera_now();
    const double r = camera.aperture_radius;
    if (!(r > 0)) return 1;
    return camera.blades >= 3 ? 0.5 * camera.blades * std::sin(2 * kPi / camera.blades) * r * r : kPi * r * r;
  }
  // Motion blur: the camera, the lights and the hits of a path at its shutter time.
  // Plain transparent layers (Scene::is_plain_layer: alpha, Transparent BSDF) are no path
  // vertices: an edge crosses them. A walk along an edge passes each by the probability that
  // its lobe choice there passes (the BSDF rebuilt toward the side the walk comes from); a
  // walk that reached a vertex on a layer did not pass it, and scatters there by the rest.
  // Each layer found here by intersecting the edge anew.
  bool layers = false;
  double pass_probability(const SurfaceHit &hit, Vec3 wo) const {
    return scene.bsdf(hit, wo, 0).pass_probability(wo);
  }
  // The layers on the segment from o along d (unit) for `distance`, passed by a walk
  // travelling along `travel` (d or -d); 0 where something else lies on it. An end in a
  // medium lies on no surface: the segment runs to it (a walk may stop microns past a layer).
  static float end_gap(bool in_medium) { return in_medium ? 1e-6f : 1e-4f; }
  double layer_passes(Vec3 o, Vec3 d, double distance, Vec3 travel, bool start_in_medium = false,
                      bool end_in_medium = false) const {
    double product = 1;
    constexpr float kGap = 1e-4f;  // beside a surface vertex or a layer just passed
    const float end = end_gap(end_in_medium);
    double left = distance - end_gap(start_in_medium);
    o = o + d * end_gap(start_in_medium);
    while (layers && left > end) {
      SurfaceHit hit;
      if (!scene.intersect(Ray{o, d, float(left)}, hit) || !(hit.t < left - end)) break;
      if (!scene.is_plain_layer(hit)) return 0;
      product *= pass_probability(hit, -travel);
      o = hit.p + d * kGap;
      left -= hit.t + kGap;
    }
    return product;
  }
  // The plain layers on the segment a -> b farther than a millimetre from its ends (where
  // the vertices' own surfaces are), other surfaces passed over.
  int layers_on(Vec3 a, Vec3 b) const {
    const Vec3 d = normalize(b - a);
    constexpr float kEnd = 1e-3f;
    int count = 0;
    Vec3 o = a + d * kEnd;
    float left = length(b - a) - 2 * kEnd;
    for (int guard = 0; guard < 64 && left > 0; ++guard) {
      SurfaceHit hit;
      if (!scene.intersect(Ray{o, d, left}, hit)) break;
      count += scene.is_plain_layer(hit);
      o = o + d * (hit.t + 1e-5f);
      left -= hit.t + 1e-5f;
    }
    return count;
  }
  // Whether an edge of p passes within ~10 microns of a layer's edge: the engine's rays
  // restart from each crossing's offset point (core/ray_offset.h), microns off the straight
  // line traced here, so there the two may see the layer or not (a measure-zero set that a
  // finite test still meets: the Cornell box sheet's front edge). Such proposals are left out.
  bool grazes_layer(const ExplicitPath &p) const {
    if (!layers) return false;
    for (int i = 1; i < p.n; ++i) {
      const bdpt::PathVertex &a = p.x[size_t(i - 1)].v, &b = p.x[size_t(i)].v;
      if (a.infinite || b.infinite) continue;
      const Vec3 d = normalize(b.p - a.p);
      const Frame f(d);
      const int straight = layers_on(a.p, b.p);
      for (Vec3 shift : {f.s, -f.s, f.t, -f.t}) {
        const Vec3 e = shift * 1e-5f;
        if (layers_on(a.p + e, b.p + e) != straight) return true;
      }
    }
    return false;
  }
  // Whether p's vertex i lies on a plain layer, and then the probability that a walk from
  // its camera (or light) side neighbour did not pass it.
  double keeps(const ExplicitPath &p, int i, bool from_camera) const {
    const ExplicitVertex &v = p.x[size_t(i)];
    if (!layers || i == 0 || i == p.n - 1 || v.v.type != VertexType::Surface || !scene.is_plain_layer(v.hit)) return 1;
    return 1 - pass_probability(v.hit, dir(p, i, from_camera ? i - 1 : i + 1));
  }
  // The layers on the edge x_(i-1) -> x_i (camera side; from_camera false: x_(i+1) -> x_i)
  // as the walk toward x_i passes them.
  double edge_layers(const ExplicitPath &p, int i, bool from_camera) const {
    const int j = from_camera ? i - 1 : i + 1;
    const bdpt::PathVertex &a = p.x[size_t(j)].v, &b = p.x[size_t(i)].v;
    if (b.infinite) return layer_passes(a.p, b.dir, 1e30, b.dir);
    if (a.infinite) return layer_passes(b.p, a.dir, 1e30, -a.dir);  // from the light's disk, along -dir
    Vec3 from = a.p;
    if (from_camera && i == 1 && orthographic_pinhole()) {
      const Camera &camera = scene.camera_now();
      from = b.p - camera.forward() * dot(b.p - camera.position(), camera.forward());
    }
    const Vec3 d = normalize(b.p - from);
    return layer_passes(from, d, length(b.p - from), d, a.type == VertexType::Medium, b.type == VertexType::Medium);
  }
  // What a walk's density of x_i takes from the layers: the edge's passes, not passing x_i,
  // and the scattering at the neighbour it came from out of the rest of its sampling.
  double layer_walk(const ExplicitPath &p, int i, bool from_camera) const {
    if (!layers) return 1;
    const int j = from_camera ? i - 1 : i + 1;
    return edge_layers(p, i, from_camera) * keeps(p, i, from_camera) / keeps(p, j, from_camera);
  }
  double camera_side(const ExplicitPath &p, int i) const {
    if (i == 0) return camera_walk(p, i);
    shutter::SampleTime at(p.time);
    return camera_walk(p, i) * layer_walk(p, i, true);
  }
  double light_side(const ExplicitPath &p, int i) const {
    if (i == p.n - 1) return light_walk(p, i);
    shutter::SampleTime at(p.time);
    return light_walk(p, i) * layer_walk(p, i, false);
  }
  // The camera side's density of x_i without the layers.
  double camera_walk(const ExplicitPath &p, int i) const {
    shutter::SampleTime at(p.time);
    const int n = p.n;
    if (i == 0) return orthographic_lens() ? 1 / orthographic_lens_region() : 1 / aperture_area();  // (a pinhole: 1)
    const bdpt::PathVertex &v = p.x[size_t(i)].v;
    if (v.infinite) {
      // Escaped: the density of the direction at x_(n-2) (a sun without an angle: never).
      const Light &light = scene.lights()[size_t(v.light)];
      if (light.type == LightType::Sun && light.radius == 0) return 0;
      double pdf;
      if (i == 1 && orthographic_pinhole()) {
        // The world along the view axis: a raster point uniform, per unit of plane area.
        const Camera &camera = scene.camera_now();
        pdf = (double(kWidth) * kHeight / (double(kSize.x) * kSize.y)) /
              (double(camera.right - camera.left) * (camera.top - camera.bottom));
      } else if (i == 1 && orthographic_lens()) {
        pdf = orthographic_lens_direction(v.dir);
      } else if (i == 1) {
        const double cos0 = dot(v.dir, scene.camera_now().forward());
        pdf = (double(kWidth) * kHeight / (double(kSize.x) * kSize.y)) /
              (scene.camera_now().viewplane_area() * cos0 * cos0 * cos0);
      } else {
        pdf = scatter_pdf(p.x[size_t(i - 1)], dir(p, i - 1, i - 2), v.dir, false, blur_alpha(p, i - 1));
      }
      if (other_lamp_on_last_edge(p)) return 0;
      return pdf * camera_flight(p, i - 1, i, false);
    }
    const LightType end_type = scene.lights()[size_t(p.x[size_t(n - 1)].v.light)].type;
    if (i == n - 1 && end_type != LightType::Triangle && end_type != LightType::Volume) {
      // Lamps: no walk hits them, but for the spheres of lamps with a radius (another's
      // sphere on the way: other_lamp_on_last_edge), where the ray enters: the cosine
      // at the sphere from the point's offset from the centre; and area lamps, from their
      // emitting side: the cosine to their axis.
      const Light &light = scene.lights()[size_t(v.light)];
      if (light.type != LightType::Area && light.radius == 0) return 0;
      Vec3 w = dir(p, i - 1, i);
      const double cos_lamp = -dot(light.type == LightType::Area ? light.axis : sphere_normal(light, v.p), w);
      if (!(cos_lamp > 0) || other_lamp_on_last_edge(p)) return 0;
      const Vec3 from = p.x[size_t(i - 1)].v.p;
      return scatter_pdf(p.x[size_t(i - 1)], dir(p, i - 1, i - 2), w, false, blur_alpha(p, i - 1)) * cos_lamp / double(length_squared(v.p - from)) *
             camera_flight(from, v.p, false);
    }
    Vec3 w = dir(p, i - 1, i);
    double pdf;
    Vec3 from = p.x[size_t(i - 1)].v.p;
    const double raster_density = double(kWidth) * kHeight / (double(kSize.x) * kSize.y);
    if (i == 1 && orthographic_pinhole()) {
      // A raster point uniform, its ray along the view axis from the image plane (scene
      // units, the camera unscaled): density per plane area, dA_plane = |cos| dA at x_1.
      const Camera &camera = scene.camera_now();
      const double plane_area = double(camera.right - camera.left) * (camera.top - camera.bottom);
      const double cos1 = v.on_surface() ? std::fabs(dot(v.ng, camera.forward())) : 1.0;
      const Vec3 foot = v.p - camera.forward() * dot(v.p - camera.position(), camera.forward());
      return raster_density / plane_area * cos1 *
             camera_flight(foot + camera.forward() * camera.clip_start, v.p, v.type == VertexType::Medium);
    }
    if (i == 1) {
      const Camera &camera = scene.camera_now();
      double cos0 = dot(w, camera.forward());
      pdf = orthographic_lens() ? orthographic_lens_direction(w)
                                : raster_density / (camera.viewplane_area() * cos0 * cos0 * cos0);
      from = from + w * float(camera.clip_start / cos0);
    } else {
      pdf = scatter_pdf(p.x[size_t(i - 1)], dir(p, i - 1, i - 2), w, false, blur_alpha(p, i - 1));
    }
    if (i == n - 1 && other_lamp_on_last_edge(p)) return 0;
    // A volume light's point: where the last step's free flight stops in its medium.
    const bool stops = v.type == VertexType::Medium || (i == n - 1 && end_type == LightType::Volume);
    return pdf * to_area(p, i - 1, i) *
           camera_flight(from, v.p, stops, i > 1 && p.x[size_t(i - 1)].v.type == VertexType::Medium);  // finite: as before
  }
  // The free flight that stops at medium vertex i from the camera side: from x_(i-1), the
  // camera's rays from the clip start (camera_side's).
  double camera_side_stop(const ExplicitPath &p, int i) const {
    Vec3 from = p.x[size_t(i - 1)].v.p;
    const Vec3 to = p.x[size_t(i)].v.p;
    if (i == 1) {
      const Camera &camera = scene.camera_now();
      if (orthographic_pinhole()) {
        from = to - camera.forward() * (dot(to - camera.position(), camera.forward()) - camera.clip_start);
      } else {
        const Vec3 w = normalize(to - from);
        from = from + w * float(camera.clip_start / dot(w, camera.forward()));
      }
    }
    return camera_flight(from, to, true, i > 1 && p.x[size_t(i - 1)].v.type == VertexType::Medium) *
           edge_layers(p, i, true);  // a kept distance's retrace draws neither
  }
  // A lamp with a radius is a sphere (lights/sphere_lamp.h): its point uniform over the
  // sphere (a point lamp) or over the cap of points whose normal is within pi/2 + the
  // cone's half angle of the spot's axis; the direction cosine-distributed about the
  // normal (point) or uniform in the cone (spot), never below the point's horizon. The
  // normal here is the point's offset from the centre, not the vertex's stored one.
  static Vec3 sphere_normal(const Light &light, Vec3 p) { return normalize(p - light.position); }
  static double sphere_point_pdf(const Light &light, Vec3 p) {
    const double r = light.radius;
    double cap = kPi;  // the cap's angular radius
    if (light.type == LightType::Spot) cap = std::min(double(kPi), kPi / 2 + std::acos(double(light.cos_half_spot)));
    if (std::acos(std::clamp(double(dot(sphere_normal(light, p), light.axis)), -1.0, 1.0)) > cap) return 0;
    return 1 / (2 * kPi * (1 - std::cos(cap)) * r * r);
  }
  static double sphere_direction_pdf(const Light &light, Vec3 p, Vec3 d) {
    const double c = dot(sphere_normal(light, p), d);
    if (!(c > 0)) return 0;
    if (light.type != LightType::Spot) return c / kPi;
    const double cos_cone = light.cos_half_spot;
    return dot(light.axis, d) > cos_cone ? 1 / (2 * kPi * (1 - cos_cone)) : 0.0;
  }
  // The light side's density of x_i without the layers.
  double light_walk(const ExplicitPath &p, int i) const {
    shutter::SampleTime at(p.time);
    const int n = p.n;
    const bdpt::PathVertex &light_vertex = p.x[size_t(n - 1)].v;
    Light moved;
    const Light &light = scene.light_now(uint32_t(light_vertex.light), moved);
    const bool sphere = (light.type == LightType::Point || light.type == LightType::Spot) && light.radius > 0;
    if (light_vertex.infinite) {
      // A direction by each light's power and direction density (a sun without an angle:
      // its delta, 1), summed over the lights at infinity it stands for; then a point
      // uniform on the disk of the bounding radius perpendicular to it, at the cosine.
      if (i == n - 1) {
        // Seen by an orthographic camera: only along its axis, a direction no light samples.
        if (n == 2 && orthographic_pinhole()) return 0;
        if (light.type == LightType::Sun && light.radius == 0)
          return double(scene.light_distribution().pmf(size_t(light_vertex.light)));
        double pdf = 0;
        for (size_t k = 0; k < scene.lights().size(); ++k) {
          const Light &l = scene.lights()[k];
          if (l.is_infinite() && !(l.type == LightType::Sun && l.radius == 0))
            pdf += double(scene.light_distribution().pmf(k)) * light_pdf(l, Vec3(0.0f), light_vertex.dir, kInf);
        }
        return pdf;
      }
      if (i == n - 2 && i > 0) {
        const double r = scene.bounding_radius();
        return to_area(p, n - 1, i) * free_flight(p, n - 1, i, p.x[size_t(i)].v.type == VertexType::Medium) /
               (kPi * r * r);
      }
    }
    if (i == n - 1)
      return double(scene.light_distribution().pmf(size_t(light_vertex.light))) *
             (sphere                               ? sphere_point_pdf(light, light_vertex.p)
              : light.type == LightType::Volume ? double(light.volume->pdf(light_vertex.p))
                                                   : double(light.inv_area));
    if (i == 0) return 0;
    Vec3 w = dir(p, i + 1, i);
    double pdf;
    if (i == n - 2 && sphere) {
      pdf = sphere_direction_pdf(light, light_vertex.p, w);
    } else if (i == n - 2) {
      float pdf_pos, pdf_dir;
      emission_pdf(light, light_vertex.p, light_vertex.ng, w, scene.bounding_radius(), pdf_pos, pdf_dir);
      pdf = pdf_dir;
    } else {
      pdf = scatter_pdf(p.x[size_t(i + 1)], dir(p, i + 1, i + 2), w, true);
      // Filter Glossy: the light walk samples x_(i+1) unblurred; where the blur changes that
      // BSDF it cannot make the path.
      const ExplicitVertex &next = p.x[size_t(i + 1)];
      if (filter.on() && next.v.type == VertexType::Surface &&
          scene.bsdf(next.hit, dir(p, i + 1, i + 2), 0).blur_changes(blur_alpha(p, i + 1)))
        pdf = 0;
    }
    const bdpt::PathVertex &v = p.x[size_t(i)].v;
    return pdf * to_area(p, i + 1, i) * free_flight(p, i + 1, i, v.type == VertexType::Medium);
  }
  // The lens subpath mutation's walk from the camera (path_space.h) makes p's vertices
  // 1 .. c with the product of their camera-side densities, but only through surfaces whose
  // BSDF (rebuilt here) is all delta. A short path (E S* L, E S* D L) is made whole: its walk
  // passes no emitting surface and no lamp (each lamp intersected here), where it would have
  // ended, and E S* D L's D is no light (an emitting surface, a point of an emissive medium),
  // its light vertex then sampled by the light side.
  double lens_walk(const ExplicitPath &p, int c) const {
    shutter::SampleTime at(p.time);
    const bool short_path = c >= p.n - 2, to_d = c == p.n - 2;
    double density = 1;
    for (int i = 1; i <= c; ++i) density *= camera_side(p, i);
    for (int i = 1; i < c; ++i) {
      const ExplicitVertex &v = p.x[size_t(i)];
      if (v.v.type != VertexType::Surface || !scene.bsdf(v.hit, dir(p, i, i - 1), 0).is_delta()) return 0;
      if (short_path && scene.material(v.hit.material).emits()) return 0;
    }
    if (!short_path) return density;
    if (to_d) {
      const ExplicitVertex &d = p.x[size_t(c)];
      if (d.v.type == VertexType::Surface && scene.material(d.hit.material).emits()) return 0;
      if (d.v.type == VertexType::Medium && scene.medium(d.v.medium).is_emissive()) return 0;
      density *= light_side(p, p.n - 1);
    }
    for (int i = 0; i + 1 < c || (to_d && i < c); ++i) {
      Vec3 a = p.x[size_t(i)].v.p;
      const Vec3 w = dir(p, i, i + 1);
      if (i == 0) a = a + w * float(scene.camera_now().clip_start / dot(w, scene.camera_now().forward()));
      const float d = length(p.x[size_t(i + 1)].v.p - a);
      for (const Light &light : scene.lights()) {
        if (i == 0 && !light.visible_camera()) continue;  // camera rays pass the lamps the camera does not see
        float t;
        Color radiance;
        if (light.type == LightType::Area && intersect_light(light, Ray{a, w, d}, d, t, radiance)) return 0;
        if (is_sphere_lamp(light) && intersect_sphere_lamp(light, a, w, d, t)) return 0;
      }
    }
    return density;
  }
  // Deletions: every (l, m) of a path of nv vertices but the edges before the camera
  // and after the light alone, and the whole path (a large step).
  double deletion(int nv, int l, int m) const {
    if (l == -1 && m == nv) return kLargeStep;
    double z = 0, w = 0;
    for (int a = -1; a < nv; ++a)
      for (int b = a + 1; b <= nv; ++b) {
        if ((a == -1 && b == 0) || (a == nv - 1 && b == nv) || (a == -1 && b == nv)) continue;
        const int kd = b - a;
        double weight = kd == 1 ? 0.5 : std::pow(0.5, kd - 2);
        z += weight;
        if (a == l && b == m) w = weight;
      }
    return (1 - kLargeStep) * w / z;
  }
  double addition(int nv, int l, int m, int na) const {
    if (l == -1 && m == nv) {
      const double uniform = 1.0 / (max_vertices - 1);
      if (length_weights.empty()) return uniform;
      double sum = 0;
      for (double w : length_weights) sum += w;
      return 0.25 * uniform + 0.75 * length_weights[size_t(na - 2)] / sum;
    }
    const int nd = m - l - 1, kept = nv - nd;
    double z = 0, w = 0;
    for (int k = 0; kept + k <= max_vertices; ++k) {
      if (kept + k < 2 || (l == -1 && k < 1) || (m == nv && k < 1) || (k == 0 && nd == 0)) continue;
      double weight = std::pow(0.5, std::abs(k - nd));
      z += weight;
      if (k == na) w = weight;
    }
    return z > 0 ? w / z : 0.0;
  }
  // T(from -> to): from's vertices l+1 .. m-1 replaced by to's l+1 .. l+na.
  double transition(int nv_from, int l, int m, const ExplicitPath &to, int na) const {
    double sum = 0;
    for (int j = 0; j <= na; ++j) {
      const int a = l + j, b = l + j + 1;  // the connection
      if ((a >= 0 && to.x[size_t(a)].v.delta) || (b < to.n && to.x[size_t(b)].v.delta)) continue;
      double product = 1;
      for (int i = l + 1; i <= l + na; ++i) product *= i <= l + j ? camera_side(to, i) : light_side(to, i);
      sum += product;
    }
    return deletion(nv_from, l, m) * addition(nv_from, l, m, na) * sum / (na + 1);
  }
};

// The bytes a state is made of (positions, directions, types, densities, f).
std::vector<unsigned char> digest(const ExplicitPath &p) {
  std::vector<unsigned char> bytes;
  auto add = [&](const void *data, size_t size) {
    const unsigned char *c = static_cast<const unsigned char *>(data);
    bytes.insert(bytes.end(), c, c + size);
  };
  add(&p.n, sizeof p.n);
  add(&p.f, sizeof p.f);
  add(&p.raster, sizeof p.raster);
  add(&p.time, sizeof p.time);
  for (int i = 0; i < p.n; ++i) {
    const bdpt::PathVertex &v = p.x[size_t(i)].v;
    add(&v.type, sizeof v.type);
    add(&v.p, sizeof v.p);
    add(&v.ng, sizeof v.ng);
    add(&v.wo, sizeof v.wo);
    add(&v.light, sizeof v.light);
    add(&v.medium, sizeof v.medium);
    add(&v.delta, sizeof v.delta);
    add(&v.dir, sizeof v.dir);
    add(&p.fwd[size_t(i)], sizeof(double));
    add(&p.rev[size_t(i)], sizeof(double));
  }
  return bytes;
}

// Whether a perturbation retraced as Pauly's (MutationSettings::keep_distances) and kept
// medium vertex i's distance from the vertex before it (x's and y's equal, kinds kept).
// Such a vertex had no free flight drawn: the brute-force ratio loses that factor
// (path_space.h), and the distance must be x's.
bool kept_flight(const Proposal &p, const ExplicitPath &x, const ExplicitPath &y, int i) {
  if (!p.kept_distances || x.x[size_t(i)].v.type != VertexType::Medium) return false;
  EXPECT_EQ(int(y.x[size_t(i)].v.type), int(VertexType::Medium)) << "a kept medium vertex changed its kind";
  const int before = p.type == MutationType::Caustic ? i + 1 : i - 1;  // the caustic retraces from the light side
  const float rx = length(x.x[size_t(i)].v.p - x.x[size_t(before)].v.p);
  const float ry = length(y.x[size_t(i)].v.p - y.x[size_t(before)].v.p);
  EXPECT_NEAR(ry / rx, 1.0f, 1e-4f) << "a kept medium vertex's distance changed";
  return true;
}

int specular_vertices(const ExplicitPath &p) {
  int k = 0;
  for (int i = 1; i + 1 < p.n; ++i) k += p.x[size_t(i)].v.delta;
  return k;
}

// min_specular: how many checked proposals must have specular vertices in x or y.
// box_lo, box_hi: the scene's one medium is in that axis-aligned box (BruteForce::box).
// filter_glossy: Cycles' Filter Glossy (0: off). grid: the box's medium is a grid
// (BruteForce::grid_flight).
// Returns how many lens subpath proposals made a path E S* L with a specular vertex in it or
// in the path it came from.
int check_scene(const std::string &name, const nlohmann::json &json, int starts, int mutations_per_start,
                int min_specular = 0, const Vec3 *box_lo = nullptr, const Vec3 *box_hi = nullptr,
                float filter_glossy = 0, bool grid = false, const std::vector<double> &length_weights = {}) {
  LoadedScene loaded;
  load(loaded, json);
  const Scene &scene = loaded.scene();
  LightPathLimits limits;
  limits.filter_glossy = filter_glossy;
  PathSpace space(scene, kMaxBounces, kOrigin, kSize, float(kWidth * kHeight), kLargeStep, checked_mutations(), limits);
  BruteForce brute{scene};
  bool scattering = false;  // a medium that scatters: camera-side distances toward point and spot lamps
  for (int m = 0; m < scene.num_media(); ++m) scattering |= max_component(scene.medium(m).sigma_s) > 0;
  double lamp_power = 0;
  for (size_t k = 0; scattering && k < scene.lights().size(); ++k) {
    const Light &light = scene.lights()[k];
    if (light.type != LightType::Point && light.type != LightType::Spot) continue;
    brute.lamps.push_back({light.position, double(scene.light_distribution().pmf(k))});
    lamp_power += brute.lamps.back().second;
  }
  for (auto &lamp : brute.lamps) lamp.second /= lamp_power;
  if (!brute.lamps.empty()) brute.equiangular_share = checked_mutations().equiangular;
  if (!length_weights.empty()) {
    space.set_length_weights(length_weights);
    brute.length_weights = length_weights;
  }
  brute.filter = FilterGlossy(filter_glossy);
  brute.layers = scene.has_transparency();
  if (box_lo) {
    brute.box = true;
    brute.box_lo = *box_lo;
    brute.box_hi = *box_hi;
    brute.grid = grid;
  }
  Pcg32 rng(7, 11);
  RayStats stats;
  ExplicitPath x, y, z;
  int grazing = 0;  // proposals left out: an edge grazes a layer's edge (BruteForce::grazes_layer)
  int checked = 0, worse = 0, medium_paths = 0, large = 0, lens = 0, specular = 0, lens_specular = 0, caustic = 0;
  int lens_subpaths = 0, multi_chain = 0, multi_chain_chains = 0, multi_chain_to_light = 0;
  int lens_subpath_new_shape = 0, lens_subpath_to_light = 0;  // another specular count; E S* L to E S* L
  int lens_subpath_to_light_specular = 0, lens_subpath_short = 0;  // E S* L to E S* D L or back
  int off_sphere = 0, infinite = 0, delta_sun = 0, volume_light = 0, volume_light_camera_side = 0;
  int time_moved = 0, time_lost = 0;
  int kept_medium = 0;  // perturbations that kept a medium vertex's distance (Pauly's retrace)
  int layered = 0;  // bidirectional proposals whose y crosses a plain layer or scatters on one
  int blurred = 0;  // Filter Glossy: proposals with a vertex the blur changed  // motion blur: large steps that drew a new time; others that changed it
  double worst = 0, worst_f = 0;
  for (int s = 0; s < starts; ++s) {
    if (!(space.sample_independent(rng, stats, x) > 0)) continue;
    const Light &light = scene.lights()[size_t(x.x[size_t(x.n - 1)].v.light)];
    if (light.radius > 0 && (light.type == LightType::Point || light.type == LightType::Spot))
      off_sphere += !(std::fabs(length(x.x[size_t(x.n - 1)].v.p - light.position) / light.radius - 1) < 1e-4);
    // f is a function of the vertices: every BSDF rebuilt by the rule gives the same f.
    z = x;
    shutter::SampleTime at(x.time);
    for (int i = 1; i + 1 < z.n; ++i)
      if (z.x[size_t(i)].v.type == VertexType::Surface) {
        Vec3 wo = normalize(z.x[size_t(i - 1)].v.p - z.x[size_t(i)].v.p);
        z.x[size_t(i)].v.bsdf = scene.bsdf(z.x[size_t(i)].hit, wo, 0);
        z.x[size_t(i)].v.wo = wo;
        z.x[size_t(i)].blur = 0;  // as built: evaluate blurs it by the rule
      }
    space.evaluate(z, stats);
    worst_f = std::max(worst_f, double(std::fabs(luminance(z.f) / luminance(x.f) - 1)));
    const std::vector<unsigned char> before = digest(x);
    for (int k = 0; k < mutations_per_start; ++k) {
      const bool whole = rng.next_float() < kLargeStep;
      Proposal p = space.bidirectional(x, whole, rng, stats, y);
      if (!(p.ratio > 0)) continue;
      if (brute.grazes_layer(x) || brute.grazes_layer(y)) {
        ++grazing;
        continue;
      }
      const int nd = p.m - p.l - 1;
      double t_xy = brute.transition(x.n, p.l, p.m, y, p.na);
      double t_yx = brute.transition(y.n, p.l, p.l + p.na + 1, x, nd);
      double error = std::fabs(std::log(p.ratio / (t_yx / t_xy)));
      if (!(error < 1e-3)) {
        ++worse;
        if (worse <= 3)
          ADD_FAILURE() << name << ": ratio " << p.ratio << " vs brute force " << t_yx / t_xy << " (l " << p.l << ", m "
                        << p.m << ", na " << p.na << ", nv " << x.n << " -> " << y.n << ")";
      }
      if (std::isfinite(error)) worst = std::max(worst, error);
      ++checked;
      for (int i = 1; i + 1 < y.n; ++i)
        if (y.x[size_t(i)].blur > 0 && scene.bsdf(y.x[size_t(i)].hit, y.x[size_t(i)].v.wo, 0).blur_changes(y.x[size_t(i)].blur)) {
          ++blurred;
          break;
        }
      if (brute.layers) {
        bool crosses = false;
        for (int i = 1; i < y.n && !crosses; ++i) crosses = brute.edge_layers(y, i, true) != 1 || brute.keeps(y, i, true) != 1;
        layered += crosses;
      }
      if (p.type == MutationType::Large) time_moved += y.time != x.time;
      else time_lost += y.time != x.time;
      specular += specular_vertices(x) + specular_vertices(y) > 0;
      large += p.type == MutationType::Large;
      const bdpt::PathVertex &end = y.x[size_t(y.n - 1)].v;
      infinite += end.infinite;
      if (scene.lights()[size_t(end.light)].type == LightType::Volume) {
        ++volume_light;
        volume_light_camera_side += y.fwd[size_t(y.n - 1)] > 0;
      }
      delta_sun += end.infinite && scene.lights()[size_t(end.light)].type == LightType::Sun &&
                   scene.lights()[size_t(end.light)].radius == 0;
      for (int i = 0; i < y.n; ++i) medium_paths += y.x[size_t(i)].v.type == VertexType::Medium;
    }
    // The lens perturbation: x_1 .. x_c move (x_c the first non-specular vertex); its ratio
    // is that of their camera-side densities.
    int c = 1;
    while (c < x.n - 1 && x.x[size_t(c)].v.delta) ++c;
    // The lens subpath mutation (a raster point uniform on the region: its density is the
    // same both ways) replaces the same vertices by a walk of any number of specular
    // vertices (E S* D joined to x_(c+1), or for E S* L a whole new E S* L); its ratio is
    // that of the walk's densities (BruteForce::lens_walk).
    for (int k = 0; k < 2 * mutations_per_start; ++k) {
      const bool subpath = k % 2 == 1;
      Proposal p;
      if (subpath) {
        const Vec2 raster{kOrigin.x + rng.next_float() * kSize.x, kOrigin.y + rng.next_float() * kSize.y};
        p = space.lens_subpath(x, raster, rng, stats, y);
      } else {
        p = space.perturb_lens(x, rng, stats, y);
      }
      if (!(p.ratio > 0)) continue;
      if (brute.grazes_layer(x) || brute.grazes_layer(y)) {
        ++grazing;
        continue;
      }
      int cy = 1;  // y's first non-specular vertex
      while (cy < y.n - 1 && y.x[size_t(cy)].v.delta) ++cy;
      double brute_ratio = 1;
      if (subpath) {
        brute_ratio = brute.lens_walk(x, c) / brute.lens_walk(y, cy);
      } else {
        for (int i = 1; i <= c; ++i) brute_ratio *= brute.camera_side(x, i) / brute.camera_side(y, i);
        if (kept_flight(p, x, y, c)) {
          ++kept_medium;
          brute_ratio *= brute.camera_side_stop(y, c) / brute.camera_side_stop(x, c);
        }
      }
      double error = std::fabs(std::log(p.ratio / brute_ratio));
      // A short path (E S* L, E S* D L) is replaced whole by another; else x_(c+1) .. are kept.
      const bool short_path = subpath && c >= x.n - 2;
      bool same_rest = short_path ? p.m == x.n && cy >= y.n - 2 : y.n == x.n - c + cy && p.m == c + 1;
      for (int i = c + 1; same_rest && !short_path && i < x.n; ++i)
        same_rest = y.x[size_t(i - c + cy)].v.p == x.x[size_t(i)].v.p;
      for (int i = 1; same_rest && i < cy; ++i) same_rest = y.x[size_t(i)].v.delta;
      EXPECT_TRUE(same_rest) << name << ": the lens " << (subpath ? "subpath mutation" : "perturbation")
                             << " moved more than x_1 .. x_c";
      time_lost += y.time != x.time;
      lens_specular += c > 1 || cy > 1;
      if (subpath) {
        lens_subpath_new_shape += cy != c;
        lens_subpath_to_light += cy == y.n - 1;
        lens_subpath_to_light_specular += cy == y.n - 1 && (c > 1 || cy > 1);
        lens_subpath_short += short_path && (c == x.n - 1) != (cy == y.n - 1);
      }
      if (!(error < 1e-3)) {
        ++worse;
        if (worse <= 3)
          ADD_FAILURE() << name << ": lens" << (subpath ? " subpath" : "") << " ratio " << p.ratio << " vs brute force "
                        << brute_ratio;
      }
      if (std::isfinite(error)) worst = std::max(worst, error);
      ++(subpath ? lens_subpaths : lens);
    }
    // The multi-chain perturbation (x_(c+1) specular, or x_c the light): x_1 .. x_c as the
    // lens perturbation moves them, then each chain x_a (not specular) -> x_(a+1) .. (specular) -> x_b from a
    // turned direction; its ratio is that of the camera-side densities of the moved
    // vertices, each x_(a+1) without its directional part.
    for (int k = 0; k < mutations_per_start; ++k) {
      Proposal p = space.perturb_multi_chain(x, rng, stats, y);
      if (!(p.ratio > 0)) continue;
      auto area = [&](const ExplicitPath &q, int i) {
        const bdpt::PathVertex &v = q.x[size_t(i)].v;
        return brute.to_area(q, i - 1, i) * brute.camera_flight(q, i - 1, i, v.type == VertexType::Medium) *
               brute.edge_layers(q, i, true) * brute.keeps(q, i, true);
      };
      double brute_ratio = 1;
      int chains = 0;
      for (int i = 1; i < p.m; ++i) {
        const bool turned = i - 1 >= c && !x.x[size_t(i - 1)].v.delta && x.x[size_t(i)].v.delta;
        chains += turned;
        brute_ratio *= turned ? area(x, i) / area(y, i) : brute.camera_side(x, i) / brute.camera_side(y, i);
        if (kept_flight(p, x, y, i)) {
          ++kept_medium;
          brute_ratio *= brute.camera_side_stop(y, i) / brute.camera_side_stop(x, i);
        }
      }
      double error = std::fabs(std::log(p.ratio / brute_ratio));
      // E S* D S+ ...: at least one turned chain; E S* L: the camera's chain retraced to the light.
      bool same_shape = y.n == x.n && (chains >= 1 ? p.m > c + 2 : c == x.n - 1 && p.m == x.n);
      for (int i = p.m; same_shape && i < x.n; ++i) same_shape = y.x[size_t(i)].v.p == x.x[size_t(i)].v.p;
      for (int i = 1; same_shape && i < p.m; ++i) same_shape = y.x[size_t(i)].v.delta == x.x[size_t(i)].v.delta;
      EXPECT_TRUE(same_shape) << name << ": the multi-chain perturbation changed the path's shape or kept vertices";
      if (!(error < 1e-3)) {
        ++worse;
        if (worse <= 3)
          ADD_FAILURE() << name << ": multi-chain ratio " << p.ratio << " vs brute force " << brute_ratio << " (m "
                        << p.m << " of " << x.n << ", " << chains << " chains)";
      }
      if (std::isfinite(error)) worst = std::max(worst, error);
      ++multi_chain;
      time_lost += y.time != x.time;
      multi_chain_chains += chains > 1;
      multi_chain_to_light += p.m == x.n;
    }
    // The caustic perturbation: x_1 .. x_(k-1) move (x_2 .. x_(k-1) the specular chain);
    // its ratio is that of their light-side densities, the first without its direction's.
    int kc = 2;
    while (kc < x.n - 1 && x.x[size_t(kc)].v.delta) ++kc;
    for (int k = 0; k < mutations_per_start; ++k) {
      Proposal p = space.perturb_caustic(x, rng, stats, y);
      if (!(p.ratio > 0)) continue;
      auto area = [&](const ExplicitPath &q) {
        const bdpt::PathVertex &v = q.x[size_t(kc - 1)].v;
        return brute.to_area(q, kc, kc - 1) * brute.free_flight(q, kc, kc - 1, v.type == VertexType::Medium) *
               brute.edge_layers(q, kc - 1, false) * brute.keeps(q, kc - 1, false);
      };
      double brute_ratio = area(x) / area(y);
      for (int i = 1; i <= kc - 2; ++i) brute_ratio *= brute.light_side(x, i) / brute.light_side(y, i);
      if (kept_flight(p, x, y, 1)) {
        ++kept_medium;
        brute_ratio *= brute.free_flight(y, 2, 1, true) * brute.edge_layers(y, 1, false) /
                       (brute.free_flight(x, 2, 1, true) * brute.edge_layers(x, 1, false));
      }
      double error = std::fabs(std::log(p.ratio / brute_ratio));
      bool same_rest = y.n == x.n && p.m == kc && kc >= 3;
      for (int i = kc; same_rest && i < x.n; ++i) same_rest = y.x[size_t(i)].v.p == x.x[size_t(i)].v.p;
      for (int i = 2; same_rest && i < kc; ++i) same_rest = y.x[size_t(i)].v.delta;
      EXPECT_TRUE(same_rest) << name << ": the caustic perturbation moved more than x_1 .. x_(k-1)";
      time_lost += y.time != x.time;
      if (!(error < 1e-3)) {
        ++worse;
        if (worse <= 3) ADD_FAILURE() << name << ": caustic ratio " << p.ratio << " vs brute force " << brute_ratio;
      }
      if (std::isfinite(error)) worst = std::max(worst, error);
      ++caustic;
    }
    EXPECT_TRUE(digest(x) == before) << name << ": a proposal changed the state it mutated";
  }
  std::printf("[ mlt densities ] %-12s %d bidirectional proposals checked (%d large, %d with specular vertices), %d "
              "lens, %d lens subpath (%d through specular vertices), %d caustic, %d multi-chain (%d of several "
              "chains, %d retraced to the light); %d medium vertices; %d ending at infinity (%d at a sun without an "
              "angle); %d ending in a volume light (%d of them reachable from the camera side); worst |log ratio "
              "error| %.2e; worst f rebuild error %.2e\n",
              name.c_str(), checked, large, specular, lens, lens_subpaths, lens_specular, caustic, multi_chain,
              multi_chain_chains, multi_chain_to_light, medium_paths, infinite, delta_sun, volume_light,
              volume_light_camera_side, worst, worst_f);
  std::printf("[ mlt densities ] %-12s lens subpath: %d with another number of specular vertices, %d to E S* L "
              "(%d with specular vertices), %d between E S* L and E S* D L; %d perturbations kept a medium "
              "vertex's distance\n",
              name.c_str(), lens_subpath_new_shape, lens_subpath_to_light, lens_subpath_to_light_specular,
              lens_subpath_short, kept_medium);
  if (brute.layers) {
    std::printf("[ mlt densities ] %-12s %d bidirectional proposals across or on plain transparent layers; %d "
                "proposals left out, an edge grazing a layer's edge\n",
                name.c_str(), layered, grazing);
    EXPECT_GT(layered, checked / 10) << name;
    EXPECT_LT(grazing, checked / 50) << name;  // (a grazing state leaves out all its proposals)
  }
  if (scene.has_motion())
    std::printf("[ mlt densities ] %-12s motion: %d of %d large steps at a new shutter time\n", name.c_str(), time_moved,
                large);
  EXPECT_EQ(time_lost, 0) << name << ": a mutation other than the large step changed the shutter time";
  if (filter_glossy > 0) {
    std::printf("[ mlt densities ] %-12s filter glossy %g: %d bidirectional proposals with a vertex the blur changed\n",
                name.c_str(), filter_glossy, blurred);
    // About 5% of them (49 of 1,005 on the mirror caustic since the lens subpath mutation's
    // walk draws another count of numbers): enough to check the blur's densities.
    EXPECT_GT(blurred, checked / 25) << name;
  }
  if (scene.has_motion()) EXPECT_GT(time_moved, large / 2) << name;
  bool volume_lights = false;
  for (const Light &l : scene.lights()) volume_lights |= l.type == LightType::Volume;
  if (volume_lights) EXPECT_GT(volume_light, checked / 10) << name;
  if (!scene.infinite_lights().empty()) EXPECT_GT(infinite, checked / 10) << name;
  EXPECT_GE(specular, min_specular) << name;
  EXPECT_GE(lens_specular, min_specular / 10) << name;
  EXPECT_GE(caustic, min_specular / 10) << name;
  EXPECT_GT(checked, 200) << name;
  EXPECT_GT(lens, 200) << name;
  EXPECT_GT(lens_subpaths, 50) << name;  // a raster point anywhere: fewer reach x_(c+1) than the lens perturbation's
  EXPECT_GE(multi_chain, min_specular / 10) << name;
  EXPECT_GE(lens_subpath_new_shape, min_specular / 100) << name;
  // scattering: a medium that never scatters has no medium vertices
  if ((scene.world_medium() >= 0 || box_lo) && scattering) {
    EXPECT_GT(medium_paths, 0) << name;
    EXPECT_GT(kept_medium, 0) << name;
  }
  EXPECT_EQ(worse, 0) << name;
  EXPECT_EQ(off_sphere, 0) << name << ": a lamp vertex off its sphere";
  EXPECT_LT(worst_f, 1e-5) << name;
  return lens_subpath_to_light_specular;
}

int check_scene(const std::string &name, int starts, int mutations_per_start) {
  return check_scene(name, test::load_scene(name), starts, mutations_per_start);
}

}  // namespace

TEST(PathMltDensities, CornellBoxRatiosMatchBruteForce) { check_scene("cornell_box.json", 300, 20); }

// Cameras (path_space.h): a thin lens (x_0 uniform on a hexagonal aperture, the lens
// perturbation keeping it), and an orthographic camera (x_0 x_1's foot on the image plane);
// in the Cornell box and in the fog through the door (free flights from the lens / plane).
nlohmann::json with_camera(nlohmann::json scene, const nlohmann::json &camera) {
  scene["camera"].update(camera);
  return scene;
}
const nlohmann::json kThinLens = {{"fstop", 0.5}, {"focus_distance", 3.0}, {"blades", 6}};
const nlohmann::json kOrthographic = {{"type", "orthographic"}, {"ortho_scale", 2.4}};
// Blender's orthographic aperture: radius 1 / (2 fstop) scene units (camera.cpp): 0.25 m.
const nlohmann::json kOrthographicLens = {
    {"type", "orthographic"}, {"ortho_scale", 2.4}, {"fstop", 2.0}, {"focus_distance", 3.0}, {"blades", 5}};
nlohmann::json cornell_window();  // below: the lamp taken out of the ceiling, sky and sun

TEST(PathMltDensities, ThinLensRatiosMatchBruteForce) {
  check_scene("cornell_box.json (thin lens)", with_camera(test::load_scene("cornell_box.json"), kThinLens), 300, 20);
  check_scene("fog_door.json (thin lens)",
              with_camera(test::load_scene("fog_door.json"), {{"fstop", 0.4}, {"focus_distance", 2.5}}), 3000, 20);
}

TEST(PathMltDensities, OrthographicRatiosMatchBruteForce) {
  check_scene("cornell_box.json (orthographic)", with_camera(test::load_scene("cornell_box.json"), kOrthographic),
              2000, 20);
  // The world seen along the view axis (E W, x_1 at infinity) around the box and through
  // the window in its ceiling (the sky HDRI and a sun 0.1 rad wide: one vertex at infinity).
  check_scene("cornell_box.json (window, orthographic, the sky around it)",
              with_camera(cornell_window(), {{"type", "orthographic"}, {"ortho_scale", 3.4}}), 3000, 20);
  check_scene("fog_door.json (orthographic)",
              with_camera(test::load_scene("fog_door.json"), {{"type", "orthographic"}, {"ortho_scale", 3.0}}), 8000,
              20);
}

// Orthographic with depth of field (path_space.h): x_0 a point of the image plane, its own
// vertex as a lens point is (the light side never makes it). The lens subpath mutation's
// raster point anywhere in the image is rarely within the aperture of the x_0 it keeps: many
// starts for 50 of them.
TEST(PathMltDensities, OrthographicLensRatiosMatchBruteForce) {
  check_scene("cornell_box.json (orthographic, depth of field)",
              with_camera(test::load_scene("cornell_box.json"), kOrthographicLens), 6000, 20);
  check_scene("fog_door.json (orthographic, depth of field)",
              with_camera(test::load_scene("fog_door.json"), {{"type", "orthographic"},
                                                              {"ortho_scale", 3.0},
                                                              {"fstop", 1.0},
                                                              {"focus_distance", 2.5}}),
              40000, 20);
}

TEST(PathMltDensities, FogDoorRatiosMatchBruteForce) { check_scene("fog_door.json", 4000, 20); }

// The large steps' path lengths as the bootstrap sets them (metropolis.cpp): far from
// uniform (the second length 40 times the last), the large step's ratio q(x) / q(y) by them.
TEST(PathMltDensities, LengthWeightsRatiosMatchBruteForce) {
  std::vector<double> weights(size_t(kMaxBounces + 1));
  for (size_t k = 0; k < weights.size(); ++k) weights[k] = k == 0 ? 0.0 : 40.0 / double(k * k);
  check_scene("fog_door.json (length weights)", test::load_scene("fog_door.json"), 5000, 20, 0, nullptr, nullptr, 0,
              false, weights);
  check_scene("cornell_box.json (length weights)", test::load_scene("cornell_box.json"), 300, 20, 0, nullptr, nullptr,
              0, false, weights);
}

// Filter Glossy (path_space.h, filter_glossy.h): each BSDF in f blurred by its camera-side
// prefix, the camera side sampling the blurred BSDF, the light side the unblurred one with
// density 0 where the blur changes it. The glass ball and mirror (its lamp a point) with
// Filter Glossy 1: the ball seen after the floor's diffuse bounce is blurred GGX glass, in the
// mirror or straight it stays sharp; the Cornell box with glossy walls (GGX 0.05, roughened
// after a diffuse bounce).
TEST(PathMltDensities, FilterGlossyRatiosMatchBruteForce) {
  nlohmann::json mirror = test::load_scene("mirror_caustic.json");
  for (auto &light : mirror["lights"]) light["radius"] = 0;
  check_scene("mirror_caustic.json (filter glossy 1)", mirror, 6000, 20, 0, nullptr, nullptr, 1.0f);
  nlohmann::json cornell = test::load_scene("cornell_box.json");
  for (auto &m : cornell["materials"])
    if (m["name"] == "red" || m["name"] == "green") {
      m["type"] = "glossy";
      m["roughness"] = 0.05;
    }
  check_scene("cornell_box.json (glossy walls, filter glossy 1)", cornell, 600, 20, 0, nullptr, nullptr, 1.0f);
}

// Motion blur (path_space.h): the shutter time a coordinate of the path, drawn by large
// steps (density 1) and kept by the other mutations; every density at the path's time. The
// Cornell box with its tall block sliding and turning, its lamp sliding and tilting (a moving
// emitter: Scene::light_now's point density and emission direction density), seen by a
// camera that moves while the shutter is open (its raster density and lens at that time); and
// the same with a thin lens.
nlohmann::json cornell_in_motion() {
  nlohmann::json j = test::load_scene("cornell_box.json");
  j["camera"]["shutter_open"] = -0.25;
  j["camera"]["shutter_close"] = 0.25;
  j["camera"]["motion"] = {{{"look_at", {{"from", {-0.3, -3.9, 0.9}}, {"to", {0, 0, 1}}, {"up", {0, 0, 1}}}}},
                           {{"look_at", {{"from", {0.3, -3.9, 1.1}}, {"to", {0, 0, 1}}, {"up", {0, 0, 1}}}}}};
  for (auto &m : j["meshes"]) {
    if (m["name"] == "tall_block")
      m["motion"] = {{{"translate", {-0.45, 0.3, 0.6}}, {"rotate", {0, 0, 5}}},
                     {{"translate", {-0.2, 0.3, 0.6}}, {"rotate", {0, 0, 30}}}};
    if (m["name"] == "lamp")
      m["motion"] = {{{"translate", {-0.1, 0, 1.99}}, {"rotate", {175, 0, 0}}},
                     {{"translate", {0.1, 0, 1.99}}, {"rotate", {185, 0, 0}}}};
  }
  return j;
}

TEST(PathMltDensities, MotionBlurRatiosMatchBruteForce) {
  check_scene("cornell_box.json (in motion)", cornell_in_motion(), 300, 20);
  check_scene("cornell_box.json (in motion, thin lens)", with_camera(cornell_in_motion(), kThinLens), 300, 20);
}

// Smooth glass and a mirror: paths through the ball and seen in the mirror. Its lamp made
// a point (radius 0) here; with its radius (3 cm: a sphere lamp) below.
TEST(PathMltDensities, MirrorCausticSpecularRatiosMatchBruteForce) {
  nlohmann::json j = test::load_scene("mirror_caustic.json");
  for (auto &light : j["lights"]) light["radius"] = 0;
  check_scene("mirror_caustic.json", j, 20000, 20, 100);
}

// Lamps with a radius (lights/sphere_lamp.h): the shipped mirror caustic's 3 cm point lamp
// (specular chains from a sphere lamp), and the fog through the door with its area lamp
// replaced by a 5 cm spot (medium vertices lit by a spot's sphere, the cap and cone
// densities).
TEST(PathMltDensities, RadiusLampRatiosMatchBruteForce) {
  check_scene("mirror_caustic.json (3 cm lamp)", test::load_scene("mirror_caustic.json"), 12000, 20, 60);
  nlohmann::json fog = test::load_scene("fog_door.json");
  fog["lights"] = nlohmann::json::array({{{"name", "spot"}, {"type", "spot"}, {"position", {3.5, 1.2, 2.4}},
                                          {"direction", {-0.3, 0, -1}}, {"power", 2000}, {"radius", 0.05},
                                          {"spot_size", 1.2}, {"spot_blend", 0.2}}});
  check_scene("fog_door.json (5 cm spot)", fog, 16000, 20);
}

// A box of homogeneous fog (medium 0, BruteForce::box) under the Cornell box's ceiling.
const Vec3 kFogBoxLo(-0.8f, -0.8f, 1.35f), kFogBoxHi(0.8f, 0.8f, 1.85f);
void add_fog_box(nlohmann::json &scene) {
  scene["materials"].push_back(
      {{"name", "fog"}, {"type", "volume"}, {"volume", {{"density", 0.8}, {"color", {0.9, 0.9, 0.9}}, {"anisotropy", 0.3}}}});
  scene["meshes"].push_back({{"name", "fog_box"}, {"shape", {{"type", "box"}, {"size", {1.6, 1.6, 0.5}}}},
                             {"materials", {"fog"}}, {"transform", {{"translate", {0, 0, 1.6}}}}});
}

// Equiangular distances toward point and spot lamps (mlt/equiangular.h; the 5 cm spot above
// is a sphere lamp): the fog through the door lit by two point lamps without a radius, one
// outside the door and a dim one in the room (the lamp chosen by power), and the Cornell box
// with a fog box under its ceiling and a 10 cm point lamp beside its mesh lamp (the distance
// drawn from where the ray enters the box; the mesh lamp is no target; the bulb's sphere
// takes camera walks toward the mesh lamp that meet it first).
TEST(PathMltDensities, EquiangularRatiosMatchBruteForce) {
  nlohmann::json fog = test::load_scene("fog_door.json");
  fog["lights"] = nlohmann::json::array(
      {{{"name", "outside"}, {"type", "point"}, {"position", {3.5, 1.2, 2.4}}, {"power", 800}, {"radius", 0}},
       {{"name", "inside"}, {"type", "point"}, {"position", {0.3, -0.4, 1.9}}, {"power", 60}, {"radius", 0}}});
  check_scene("fog_door.json (two point lamps)", fog, 8000, 20);
  nlohmann::json box = test::load_scene("cornell_box.json");
  add_fog_box(box);
  box["lights"] = nlohmann::json::array(
      {{{"name", "bulb"}, {"type", "point"}, {"position", {0.4, 0.3, 1.2}}, {"power", 30}, {"radius", 0.1}}});
  check_scene("cornell_box.json (fog box, point lamp)", box, 3000, 20, 0, &kFogBoxLo, &kFogBoxHi);
}

// Lamps are hidden from camera rays (Cycles), so a camera ray passes a lamp in view: the
// world behind a 0.5 m sphere lamp in the middle of the view (nothing else in the scene) is
// reached from the camera side too. Before 2026-11-25 the camera walk ended on the lamp there
// without ray visibility settings, leaving those E W paths to the light side alone (camera-side
// density 0; weights up to 186 times the others' on the Blender shadow-catcher scene).
TEST(PathMltDensities, WorldBehindALampInViewHasACameraSideDensity) {
  const nlohmann::json j = {
      {"camera", {{"focal_length", 35}, {"transform", {{"look_at", {{"from", {0, -5, 0}}, {"to", {0, 0, 0}}}}}}}},
      {"world", {{"color", {0.2, 0.3, 0.5}}}},
      {"materials", nlohmann::json::array()},
      {"meshes", nlohmann::json::array()},
      {"lights", {{{"type", "point"}, {"position", {0, 0, 0}}, {"power", 100}, {"radius", 0.5}}}}};
  LoadedScene loaded;
  load(loaded, j);
  const Scene &scene = loaded.scene();
  PathSpace space(scene, kMaxBounces, kOrigin, kSize, float(kWidth * kHeight), kLargeStep);
  const Light &lamp = scene.lights()[0];
  ASSERT_TRUE(is_sphere_lamp(lamp) && !lamp.visible_camera());
  Pcg32 rng(3, 5);
  RayStats stats;
  ExplicitPath x;
  int behind = 0, reached = 0;
  for (int k = 0; k < 200000 && behind < 50; ++k) {
    if (!(space.sample_independent(rng, stats, x) > 0) || x.n != 2 || !x.x[1].v.infinite) continue;
    float t;
    if (!intersect_sphere_lamp(lamp, x.x[0].v.p, x.x[1].v.dir, kInf, t)) continue;
    ++behind;
    reached += x.fwd[1] > 0;
  }
  EXPECT_GE(behind, 20) << "too few world paths behind the lamp";
  EXPECT_EQ(reached, behind) << "world paths behind the lamp the camera side cannot reach";
}

// An area lamp seen through the glass ball and in the mirror (E S+ L: the camera walk's
// last step reaches the lamp from its emitting side, the only strategy of such a path):
// the mirror caustic's lamp made a 20 cm square facing down.
TEST(PathMltDensities, AreaLampThroughSpecularRatiosMatchBruteForce) {
  nlohmann::json j = test::load_scene("mirror_caustic.json");
  j["lights"] = nlohmann::json::array({{{"name", "lamp"}, {"type", "area"}, {"shape", "square"}, {"size", 0.2},
                                        {"power", 300}, {"transform", {{"look_at", {{"from", {-0.6, -2.0, 2.4}},
                                                                                     {"to", {-0.3, 0, 0}}}}}}}});
  check_scene("mirror_caustic.json (area lamp)", j, 12000, 20, 60);
}

// A mesh lamp seen directly and through a glass ball: the lens subpath mutation from a path
// E S* L makes a new camera walk E S* L of any number of specular vertices (the lamp seen
// directly, reflected on the ball, or through it). scenes/glass_ball_mesh_lamp.json seen from
// the side, its lamp a 1 m square standing behind the ball facing the camera.
TEST(PathMltDensities, MeshLampThroughGlassRatiosMatchBruteForce) {
  nlohmann::json j = test::load_scene("glass_ball_mesh_lamp.json");
  j["camera"]["transform"] = {{"look_at", {{"from", {0, -3.0, 0.8}}, {"to", {0, 0, 0.6}}}}};
  for (auto &m : j["meshes"])
    if (m["name"] == "lamp") {
      m["shape"]["size"] = 1.0;
      m["transform"] = {{"translate", {0, 1.5, 0.8}}, {"rotate", {90, 0, 0}}};
    }
  const int to_light = check_scene("glass_ball_mesh_lamp.json (lamp behind)", j, 12000, 20);
  EXPECT_GT(to_light, 40);
}

// Plain transparent layers (Scene::is_plain_layer) are parts of edges, not vertices
// (path_space.h): f takes their straight-through coefficient, each walk along an edge the
// probability of passing them, a walk that stops on one the probability of not passing it
// (and its scattering there the rest of the layer's sampling). The Cornell box with a
// half-alpha card between the camera and the blocks, a Transparent BSDF sheet under the
// ceiling with a point lamp without a radius above it (its light reaches the room only
// through the sheet: connections across it, which paths with layers as vertices could not
// make), and an alpha'd mirror (a specular vertex on a layer); then with a fog box under the
// ceiling around the sheet (layers inside a medium, kept distances across them).
nlohmann::json cornell_with_layers() {
  nlohmann::json j = test::load_scene("cornell_box.json");
  j["materials"].push_back({{"name", "leaf"}, {"type", "principled"}, {"base_color", {0.3, 0.6, 0.2}}, {"alpha", 0.45}});
  j["materials"].push_back({{"name", "sheet"}, {"type", "transparent"}, {"color", {0.6, 0.8, 0.9}}});
  j["materials"].push_back({{"name", "faded_mirror"}, {"type", "principled"}, {"base_color", {0.9, 0.9, 0.9}},
                            {"metallic", 1.0}, {"roughness", 0.0}, {"alpha", 0.6}});
  j["meshes"].push_back({{"name", "leaf"}, {"shape", {{"type", "quad"}, {"size", 0.8}}}, {"materials", {"leaf"}},
                         {"transform", {{"translate", {-0.2, -0.6, 1.0}}, {"rotate", {90, 0, 0}}}}});
  j["meshes"].push_back({{"name", "sheet"}, {"shape", {{"type", "quad"}, {"size", 1.2}}}, {"materials", {"sheet"}},
                         {"transform", {{"translate", {0.2, 0.1, 1.7}}}}});
  j["meshes"].push_back({{"name", "faded_mirror"}, {"shape", {{"type", "quad"}, {"size", 0.5}}},
                         {"materials", {"faded_mirror"}},
                         {"transform", {{"translate", {0.65, 0.3, 1.0}}, {"rotate", {90, 0, 60}}}}});
  j["lights"] = nlohmann::json::array(
      {{{"name", "bulb"}, {"type", "point"}, {"position", {0.3, 0.2, 1.9}}, {"power", 20}, {"radius", 0}}});
  return j;
}

TEST(PathMltDensities, TransparentLayersRatiosMatchBruteForce) {
  check_scene("cornell_box.json (layers)", cornell_with_layers(), 1500, 20);
  nlohmann::json fog = cornell_with_layers();
  add_fog_box(fog);
  check_scene("cornell_box.json (layers, fog box)", fog, 3000, 20, 0, &kFogBoxLo, &kFogBoxHi);
  // The lamp on the fog box's top face: its media depend on the direction a ray leaves it by
  // (PathSpace::stack_toward; with the ones found along the emission direction, paths into
  // the box counted the fog twice and saw fog above it: 2,241 ratios failed here, and a
  // 64 px render of the box without layers was 0.9864 of BDPT's mean, now 1.0031).
  fog["lights"][0]["position"] = {0.3, 0.2, 1.85};
  check_scene("cornell_box.json (layers, fog box, lamp on its face)", fog, 3000, 20, 0, &kFogBoxLo, &kFogBoxHi);
}

// Lights at infinity (path_space.h): the Cornell box with its lamp taken out of the ceiling
// (a window), lit through it by a sky HDRI (importance-sampled) and a sun 0.1 rad wide, the
// two one vertex whose density is the sum of theirs; the glass ball and mirror under a sun
// without an angle (a delta in direction: reached only from the light side, its chains
// through the ball and the caustic perturbation's parallel shift of its ray) and a uniform
// world. Also the window with a fog box in it (medium vertices lit from infinity).
nlohmann::json cornell_window() {
  nlohmann::json j = test::load_scene("cornell_box.json");
  nlohmann::json meshes = nlohmann::json::array();
  for (auto &m : j["meshes"])
    if (m["name"] != "lamp") meshes.push_back(m);
  j["meshes"] = meshes;
  j["world"] = {{"environment", {{"file", "textures/sky_small.hdr"}}}, {"strength", 1.0}};
  j["lights"] = nlohmann::json::array(
      {{{"name", "sun"}, {"type", "sun"}, {"direction", {0.15, 0.1, -1}}, {"angle", 0.1}, {"strength", 3}}});
  return j;
}

TEST(PathMltDensities, InfiniteLightsRatiosMatchBruteForce) {
  check_scene("cornell_box.json (window: sky + sun)", cornell_window(), 3000, 20);
  nlohmann::json j = test::load_scene("mirror_caustic.json");
  j["lights"] = nlohmann::json::array(
      {{{"name", "sun"}, {"type", "sun"}, {"direction", {0.3, 0.4, -1}}, {"angle", 0}, {"strength", 3}}});
  j["world"] = {{"color", {0.05, 0.06, 0.08}}};
  check_scene("mirror_caustic.json (sun, world)", j, 20000, 20, 100);
  nlohmann::json fog = cornell_window();
  add_fog_box(fog);
  check_scene("cornell_box.json (window, fog box)", fog, 3000, 20, 0, &kFogBoxLo, &kFogBoxHi);
}

// Textured emission (the lamp's colour an image): f reads the texture at the vertex; the
// densities are the untextured ones (light choice by the material's mean emission x area).
TEST(PathMltDensities, TexturedLampRatiosMatchBruteForce) {
  nlohmann::json j = test::load_scene("cornell_box.json");
  for (auto &m : j["materials"])
    if (m["name"] == "lamp") m["color"] = {{"node", "image"}, {"file", "textures/tiles.png"}};
  check_scene("cornell_box.json (textured lamp)", j, 300, 20);
}

// Grid media (integrators/mlt/free_flights.h): the Cornell box with a box of grid fog under
// its ceiling (7 x 6 x 5 voxels whose density varies along every axis), lit by the
// lamp through it. mlt's column is exact piece by piece (a cubic between the voxel-centre
// planes); the brute force integrates the density along each segment by Simpson's rule
// and reads it at the stopping end.
TEST(PathMltDensities, GridFogRatiosMatchBruteForce) {
  const Vec3 lo(-0.9f, -0.9f, 1.3f), hi(0.9f, 0.9f, 1.9f);
  check_scene("cornell_box.json (grid fog)", test::cornell_grid_fog(test::load_scene("cornell_box.json"), 2.0), 600,
              20, 0, &lo, &hi, 0, true);
}

// Emissive media (volume lights): the grid fog emitting through an emission grid (5 x 4 x
// 6 voxels), the lamp kept: paths end at a point of the fog chosen by the volume light's
// power sampling, or where the last camera-side free flight stops in it. And the same fog
// absorbing only (no scattering: reached from the light side only, its transmittance in f).
TEST(PathMltDensities, EmissiveGridFogRatiosMatchBruteForce) {
  const Vec3 lo(-0.9f, -0.9f, 1.3f), hi(0.9f, 0.9f, 1.9f);
  const nlohmann::json emission = {
      {"emission_color", {1.0, 0.6, 0.3}},
      {"emission_strength", 1.5},
      {"emission_grid", test::varied_grid(5, 4, 6, {{-0.9, -0.9, 1.3}, {0.9, 0.9, 1.9}})}};
  const nlohmann::json cornell = test::load_scene("cornell_box.json");
  check_scene("cornell_box.json (emissive grid fog)", test::cornell_grid_fog(cornell, 2.0, emission), 600, 20, 0, &lo,
              &hi, 0, true);
  nlohmann::json absorbing = emission;
  absorbing["color"] = {0.0, 0.0, 0.0};
  check_scene("cornell_box.json (emissive absorbing grid)", test::cornell_grid_fog(cornell, 2.0, absorbing), 600, 20,
              0, &lo, &hi, 0, true);
}

// The perturbations of a medium vertex (Pauly, Kollig & Keller 2000, sec. 4) against the
// density they must leave invariant, evaluated numerically. On a fog-door path with one
// medium vertex x_j, the chains below move only x_j, with only one perturbation, inside a
// window (a proposal outside it is rejected, so the window's restriction of the target is
// the stationary density): along the line from its light-side neighbour c (propagation),
// the target over the distance r from c is f(r) r^2 (spherical coordinates: the volume
// measure's Jacobian); across it at fixed r (scattering), over the angle theta from the
// start direction it is the integral over phi of f sin(theta). 2,000 independent chains of
// 200 steps each (well mixed: the steps' spread is a fifth of the window) give independent
// draws; Pearson's chi-square against the density integrated by quadrature, false-alarm
// rate 1e-3 per test. The first also checks its own power: the same chains accepting by f
// alone (the r^2 Jacobian dropped) must fail (p < 1e-6).
namespace {

struct PerturbationSetup {
  LoadedScene loaded;
  ExplicitPath x;
  int j = -1;
  Vec3 c, w;
  float r = 0;
};

// A fog-door path whose only medium vertex is j, with light.
bool find_medium_path(PathSpace &space, PerturbationSetup &s) {
  Pcg32 rng(3, 5);
  RayStats stats;
  for (int attempt = 0; attempt < 200000; ++attempt) {
    if (!(space.sample_independent(rng, stats, s.x) > 0)) continue;
    int media = 0, j = -1;
    for (int i = 1; i + 1 < s.x.n; ++i)
      if (s.x.x[size_t(i)].v.type == VertexType::Medium) { ++media; j = i; }
    if (media != 1) continue;
    s.j = j;
    s.c = s.x.x[size_t(j + 1)].v.p;
    s.r = length(s.x.x[size_t(j)].v.p - s.c);
    s.w = (s.x.x[size_t(j)].v.p - s.c) / s.r;
    return true;
  }
  return false;
}

// Luminance of f with x_j moved to p (0 outside the window test's caller decides).
double f_at(const PathSpace &space, const Scene &scene, ExplicitPath &scratch, const PerturbationSetup &s, Vec3 p) {
  RayStats stats;
  scratch = s.x;
  scratch.x[size_t(s.j)].v.p = p;
  for (int i : {s.j, s.j + 1}) {
    ExplicitVertex &v = scratch.x[size_t(i)];
    Vec3 wo = normalize(scratch.x[size_t(i - 1)].v.p - v.v.p);
    v.v.wo = wo;
    if (v.v.type == VertexType::Surface) v.v.bsdf = scene.bsdf(v.hit, wo, 0);
  }
  space.evaluate(scratch, stats);
  return luminance(scratch.f);
}

// One chain from x, `steps` perturbations of type t, proposals outside the window rejected;
// returns the final coordinate.
// without_jacobian: accept by f(y) / f(x) alone (the test's power: that must fail).
// propose(current, rng, stats, proposal) -> Proposal: the perturbation (default: the
// medium vertex perturbation of type t).
template <class Coordinate, class Propose>
double run_chain(const PathSpace &space, const PerturbationSetup &s, MutationType t, Pcg32 &rng, int steps,
                 const Coordinate &coordinate, double lo, double hi, bool without_jacobian, const Propose &propose) {
  RayStats stats;
  ExplicitPath current = s.x, proposal;
  for (int k = 0; k < steps; ++k) {
    Proposal p = propose(current, rng, stats, proposal);
    if (!(p.ratio > 0)) continue;
    double q = coordinate(proposal.x[size_t(s.j)].v.p);
    if (!(q >= lo && q <= hi)) continue;  // NaN: outside a window the coordinate alone does not bound
    double a = std::min(1.0, luminance(proposal.f) * (without_jacobian ? 1.0 : p.ratio) / luminance(current.f));
    if (rng.next_float() < a) std::swap(current, proposal);
  }
  return coordinate(current.x[size_t(s.j)].v.p);
}

template <class Coordinate>
double run_chain(const PathSpace &space, const PerturbationSetup &s, MutationType t, Pcg32 &rng, int steps,
                 const Coordinate &coordinate, double lo, double hi, bool without_jacobian = false) {
  return run_chain(space, s, t, rng, steps, coordinate, lo, hi, without_jacobian,
                   [&](const ExplicitPath &x, Pcg32 &r, RayStats &stats, ExplicitPath &y) {
                     return space.perturb_medium_vertex(x, t, r, stats, y);
                   });
}

}  // namespace

TEST(PathMltPerturbations, PropagationLeavesTheDistanceDensityInvariant) {
  PerturbationSetup s;
  load(s.loaded, test::load_scene("fog_door.json"));
  const Scene &scene = s.loaded.scene();
  MutationSettings m;
  const float window = 0.4f;
  m.distance[0] = 1e-3f;
  m.distance[1] = window;
  PathSpace space(scene, kMaxBounces, kOrigin, kSize, float(kWidth * kHeight), 0.0f, m);
  ASSERT_TRUE(find_medium_path(space, s));
  const double lo = std::max(0.05, double(s.r) - window), hi = s.r + window;
  ExplicitPath scratch;
  auto g = [&](double r) { return f_at(space, scene, scratch, s, s.c + s.w * float(r)) * r * r; };
  double z = 0;
  for (int b = 0; b < 20; ++b)
    for (int k = 0; k < 64; ++k) z += g(lo + (hi - lo) * (b + (k + 0.5) / 64) / 20) * (hi - lo) / (20 * 64);
  ASSERT_GT(z, 0);
  Pcg32 rng(21, 22);
  auto distance = [&](Vec3 p) { return double(length(p - s.c)); };
  test::ChiSquareResult r = test::chi_square_1d(
      [&](float) { return float(run_chain(space, s, MutationType::Propagation, rng, 200, distance, lo, hi)); },
      [&](double x) { return g(x) / z; }, lo, hi, 2000, 1, 20);
  // The same chains accepting by f alone (no r^2) must be told apart.
  test::ChiSquareResult wrong = test::chi_square_1d(
      [&](float) { return float(run_chain(space, s, MutationType::Propagation, rng, 200, distance, lo, hi, true)); },
      [&](double x) { return g(x) / z; }, lo, hi, 2000, 1, 20);
  std::printf("[ mlt propagation ] vertex %d of %d, r %.3f in [%.3f, %.3f]: chi-square p = %.3g (dof %d); without the "
              "r^2 Jacobian p = %.3g\n",
              s.j, s.x.n, s.r, lo, hi, r.p_value, r.dof, wrong.p_value);
  EXPECT_GT(r.p_value, 1e-3) << r.detail;
  EXPECT_LT(wrong.p_value, 1e-6) << "the test cannot tell a missing Jacobian";
}

TEST(PathMltPerturbations, ScatteringLeavesTheAngleDensityInvariant) {
  PerturbationSetup s;
  load(s.loaded, test::load_scene("fog_door.json"));
  const Scene &scene = s.loaded.scene();
  MutationSettings m;
  const float window = 0.3f;  // radians
  m.angle[0] = 1e-3f;
  m.angle[1] = window;
  PathSpace space(scene, kMaxBounces, kOrigin, kSize, float(kWidth * kHeight), 0.0f, m);
  ASSERT_TRUE(find_medium_path(space, s));
  const Frame frame(s.w);
  ExplicitPath scratch;
  // Density over theta: the integral over phi of f sin(theta) (64-point rule).
  auto g = [&](double theta) {
    double sum = 0;
    for (int k = 0; k < 64; ++k) {
      double phi = 2 * kPi * (k + 0.5) / 64;
      Vec3 d = frame.to_world(Vec3(float(std::sin(theta) * std::cos(phi)), float(std::sin(theta) * std::sin(phi)),
                                   float(std::cos(theta))));
      sum += f_at(space, scene, scratch, s, s.c + d * s.r);
    }
    return sum * (2 * kPi / 64) * std::sin(theta);
  };
  const int bins = 12;
  double z = 0;
  for (int b = 0; b < bins; ++b)
    for (int k = 0; k < 64; ++k) z += g(window * (b + (k + 0.5) / 64) / bins) * window / (bins * 64);
  ASSERT_GT(z, 0);
  Pcg32 rng(31, 32);
  auto angle = [&](Vec3 p) { return double(std::acos(std::clamp(dot(normalize(p - s.c), s.w), -1.0f, 1.0f))); };
  test::ChiSquareResult r = test::chi_square_1d(
      [&](float) { return float(run_chain(space, s, MutationType::Scattering, rng, 200, angle, 0.0, window)); },
      [&](double x) { return g(x) / z; }, 0.0, window, 2000, 1, bins);
  std::printf("[ mlt scattering ] vertex %d of %d, r %.3f: chi-square p = %.3g (dof %d)\n", s.j, s.x.n, s.r, r.p_value,
              r.dof);
  EXPECT_GT(r.p_value, 1e-3) << r.detail;
}

// Pauly's retrace in the lens perturbation (path_space.h, MutationSettings::keep_distances):
// a medium x_1 keeps its distance r from the pinhole, so chains of lens perturbations that
// all retrace that way move x_1 on the sphere of radius r about x_0, where the target is f
// (the volume measure there is r^2 d omega). On a fog-door path whose x_1 is in the fog, away
// from the image's centre: directions omega = normalize(w + a s + b t) about x_1's w, s toward
// the view axis; 2,000 chains of 200 such perturbations inside the window a^2 + b^2 <= 0.25^2
// (a proposal outside it is rejected). Pearson's chi-square of a against the integral over b
// of f (1 + a^2 + b^2)^(-3/2) (d omega / da db) by quadrature, false-alarm rate 1e-3. Its power:
// the same chains accepting by f alone (the raster-to-direction Jacobian of the 20 mm lens,
// which tilts the density along s, dropped) must fail (p < 1e-6).
TEST(PathMltPerturbations, LensRetraceKeepingTheDistanceLeavesTheDirectionDensityInvariant) {
  PerturbationSetup s;
  load(s.loaded, test::load_scene("fog_door.json"));
  const Scene &scene = s.loaded.scene();
  MutationSettings m;
  m.keep_distances = 1;
  m.lens[0] = 0.05f;
  m.lens[1] = 2.0f;  // pixels of the 32 px image (84 degrees wide: about 0.05 rad)
  PathSpace space(scene, kMaxBounces, kOrigin, kSize, float(kWidth * kHeight), 0.0f, m);
  Pcg32 search(3, 5);
  RayStats stats;
  bool found = false;
  const Vec2 centre{kWidth / 2.0f, kHeight / 2.0f};
  for (int attempt = 0; attempt < 200000 && !found; ++attempt) {
    if (!(space.sample_independent(search, stats, s.x) > 0)) continue;
    // x_1 in the fog, 10 to 14 px from the centre, where the lens's Jacobian tilts the density
    // most (f is 0 past the sample region, in the chains and in the quadrature alike).
    const float off = length(Vec3(s.x.raster.x - centre.x, s.x.raster.y - centre.y, 0));
    found = s.x.x[1].v.type == VertexType::Medium && !s.x.x[2].v.delta && off > 10 && off < 14;
  }
  ASSERT_TRUE(found);
  s.j = 1;
  s.c = s.x.x[0].v.p;
  s.r = length(s.x.x[1].v.p - s.c);
  s.w = (s.x.x[1].v.p - s.c) / s.r;
  const Vec3 forward = scene.camera().forward();
  const Vec3 sa = normalize(forward - s.w * dot(forward, s.w)), tb = cross(s.w, sa);
  const double window = 0.25;
  ExplicitPath scratch;
  auto direction = [&](double a, double b) { return normalize(s.w + sa * float(a) + tb * float(b)); };
  auto g = [&](double a) {
    const double h = std::sqrt(std::max(0.0, window * window - a * a));
    double sum = 0;
    for (int k = 0; k < 64; ++k) {
      const double b = -h + 2 * h * (k + 0.5) / 64;
      sum += f_at(space, scene, scratch, s, s.c + direction(a, b) * s.r) * std::pow(1 + a * a + b * b, -1.5);
    }
    return sum * 2 * h / 64;
  };
  const int bins = 12;
  double z = 0;
  for (int b = 0; b < bins; ++b)
    for (int k = 0; k < 64; ++k) z += g(window * (-1 + 2 * (b + (k + 0.5) / 64) / bins)) * 2 * window / (bins * 64);
  ASSERT_GT(z, 0);
  auto coordinate = [&](Vec3 p) {  // a; NaN outside the window
    const Vec3 d = p - s.c;
    const double along = dot(d, s.w), a = dot(d, sa) / along, b = dot(d, tb) / along;
    return along > 0 && a * a + b * b <= window * window ? a : std::nan("");
  };
  auto lens = [&](const ExplicitPath &x, Pcg32 &r, RayStats &st, ExplicitPath &y) {
    Proposal p = space.perturb_lens(x, r, st, y);
    EXPECT_TRUE(!(p.ratio > 0) || p.kept_distances);
    return p;
  };
  Pcg32 rng(41, 42);
  auto chains = [&](bool without_jacobian) {
    return test::chi_square_1d(
        [&](float) {
          return float(run_chain(space, s, MutationType::Lens, rng, 200, coordinate, -window, window, without_jacobian,
                                 lens));
        },
        [&](double a) { return g(a) / z; }, -window, window, 2000, 1, bins);
  };
  test::ChiSquareResult r = chains(false), wrong = chains(true);
  std::printf("[ mlt lens retrace ] x_1 at r %.3f, raster (%.1f, %.1f): chi-square p = %.3g (dof %d); without the "
              "raster-to-direction Jacobian p = %.3g\n",
              s.r, s.x.raster.x, s.x.raster.y, r.p_value, r.dof, wrong.p_value);
  EXPECT_GT(r.p_value, 1e-3) << r.detail;
  EXPECT_LT(wrong.p_value, 1e-6) << "the test cannot tell a missing Jacobian";
}

// A medium vertex next to a specular vertex, moved to a distance d from it along the
// direction it has (so on the same delta event): the path's f and its densities read the
// specular event from the two positions, and a free flight that stops d = 3e-5 from the
// glass it left (the spawn offset is about 1e-6 there) points 0.03 rad off the event the
// walk sampled. mlt then found f > 0 while the light side's density of the medium vertex
// was 0: a path the walks make, scored as if only its other splits made it (q too small
// by up to 1e10; the volume caustic with its 2 cm spot ran to 45x BDPT's mean). Every path
// with f > 0 must have every interior vertex's density from both sides > 0; paths too
// short to read the event are outside path space (f = 0), longer ones keep f > 0.
// Deterministic (fixed seeds).
TEST(PathMltDensities, ShortEdgeAtSpecularVertexKeepsDensitiesConsistent) {
  LoadedScene loaded;
  load(loaded, test::load_scene("volume_caustic.json"));  // its 2 cm spot: a sphere lamp in fog
  const Scene &scene = loaded.scene();
  PathSpace space(scene, kMaxBounces, kOrigin, kSize, float(kWidth * kHeight), kLargeStep);
  Pcg32 rng(41, 43);
  RayStats stats;
  ExplicitPath x, y;
  int cases = 0, inconsistent = 0, kept = 0, dropped = 0;
  std::string first;
  for (int attempt = 0; attempt < 400000 && cases < 1000; ++attempt) {
    if (!(space.sample_independent(rng, stats, x) > 0)) continue;
    for (int m = 1; m + 1 < x.n; ++m) {
      if (x.x[size_t(m)].v.type != VertexType::Medium) continue;
      for (int s : {m - 1, m + 1}) {
        const bdpt::PathVertex &sv = x.x[size_t(s)].v;
        if (sv.type != VertexType::Surface || !sv.delta) continue;
        const Vec3 w = normalize(x.x[size_t(m)].v.p - sv.p);
        for (float d : {3e-5f, 1e-4f, 1e-3f, 1e-2f, 3e-2f}) {
          y = x;
          y.x[size_t(m)].v.p = spawn_origin(sv.p, sv.ng, sv.error, w) + w * d;
          for (int i : {m, m + 1}) {  // the moved vertex and its light-side neighbour face their camera side
            ExplicitVertex &v = y.x[size_t(i)];
            v.v.wo = normalize(y.x[size_t(i - 1)].v.p - v.v.p);
            if (v.v.type == VertexType::Surface) v.v.bsdf = scene.bsdf(v.hit, v.v.wo, 0);
          }
          space.evaluate(y, stats);
          ++cases;
          if (!(luminance(y.f) > 0)) {
            dropped += d >= 1e-2f;
            continue;
          }
          kept += d >= 1e-2f;
          for (int i = 1; i + 1 < y.n; ++i)
            if (!(y.fwd[size_t(i)] > 0) || !(y.rev[size_t(i)] > 0)) {
              if (inconsistent++ == 0)
                first = "path of " + std::to_string(y.n) + " vertices, medium vertex " + std::to_string(m) +
                        " at " + std::to_string(d) + " from specular vertex " + std::to_string(s) + ": vertex " +
                        std::to_string(i) + " fwd " + std::to_string(y.fwd[size_t(i)]) + " rev " +
                        std::to_string(y.rev[size_t(i)]);
              break;
            }
        }
      }
    }
  }
  std::printf("[ mlt short edges ] %d moved vertices, %d with f > 0 and a density 0; at >= 1 cm %d kept, %d not\n",
              cases, inconsistent, kept, dropped);
  EXPECT_GE(cases, 500);
  EXPECT_EQ(inconsistent, 0) << first;
  EXPECT_GT(kept, cases / 10);  // the exclusion is a thin shell: at 1-3 cm most moved paths still carry light
}

// Equiangular distances (mlt/equiangular.h) are sampled as their density says. The density
// tests above check the densities the ratios read against a brute force; this checks what
// the camera walk draws. fog_spot (an 8 x 8 x 4.5 m fog box) lit by its spot made a point and
// a second point lamp: camera rays through raster points whose rays pass 0.1-0.5 m from a
// lamp (where the mixture's density peaks), the walk's first vertex sampled 200,000 times.
// Its distance t from the pinhole is histogrammed in 40 cells of equal expected probability
// over the fog segment [t_in, t_out] (the box's slabs, computed here) plus one cell for
// passing the fog (the walk goes on to a surface). The expected law, written here from
// Kulla and Fajardo's closed form: (1 - s) x the free flight avg_c sigma_c exp(-sigma_c u) +
// s x sum_k pmf_k h_k / ((h_k^2 + (u - delta_k)^2) phi0_k), u = t - t_in, phi0_k =
// atan2(h_k, -delta_k); passing: (1 - s) avg_c exp(-sigma_c L) + s sum_k pmf_k atan2(h_k, L -
// delta_k) / phi0_k. Pearson's chi-square, false-alarm rate 1e-3 per ray; its power: the
// same samples against the law with the lamps moved 5 cm along the ray must fail (p < 1e-6).
TEST(PathMltSampling, EquiangularDistancesFollowTheirDensity) {
  nlohmann::json j = test::load_scene("fog_spot.json");
  j["lights"][0]["radius"] = 0;
  j["lights"].push_back({{"name", "bulb"}, {"type", "point"}, {"position", {-1.5, -1.0, 1.0}}, {"power", 1500},
                         {"radius", 0}});
  LoadedScene loaded;
  load(loaded, j);
  const Scene &scene = loaded.scene();
  MutationSettings m;
  const double share = 0.5;
  m.equiangular = float(share);
  PathSpace space(scene, kMaxBounces, kOrigin, kSize, float(kWidth * kHeight), 0.0f, m);
  ASSERT_EQ(scene.num_media(), 1);
  const Color sigma = scene.medium(0).sigma_t;
  const Vec3 box_lo{-4.0f, -4.0f, -0.5f}, box_hi{4.0f, 4.0f, 4.0f};
  struct Lamp {
    Vec3 centre;
    double pmf;
  };
  std::vector<Lamp> lamps;
  for (size_t k = 0; k < scene.lights().size(); ++k)
    lamps.push_back({scene.lights()[k].position, double(scene.light_distribution().pmf(k))});

  // Camera rays (the pinhole and a direction) through a grid of raster points.
  RayStats stats;
  Pcg32 probe(7, 8);
  struct Candidate {
    Vec2 raster;
    Vec3 o, d;
    size_t lamp;
    double h;
  };
  std::vector<Candidate> near;  // one ray per lamp: the nearest passing 0.1-0.5 m from it
  for (size_t k = 0; k < lamps.size(); ++k) near.push_back({{}, {}, {}, k, 1e9});
  for (int py = 0; py < kHeight; ++py)
    for (int px = 0; px < kWidth; ++px) {
      const Vec2 raster{px + 0.5f, py + 0.5f};
      ExplicitVertex x0, x1;
      if (!space.first_camera_step(raster, probe, stats, x0, x1)) continue;
      const Vec3 o = x0.v.p, d = normalize(x1.v.p - x0.v.p);
      for (size_t k = 0; k < lamps.size(); ++k) {
        const Vec3 c = lamps[k].centre - o;
        const double h = length(c - d * dot(c, d));
        if (h >= 0.1 && h <= 0.5 && dot(c, d) > 0 && std::abs(h - 0.25) < std::abs(near[k].h - 0.25))
          near[k] = {raster, o, d, k, h};
      }
    }

  for (const Candidate &ray : near) {
    ASSERT_LT(ray.h, 1.0) << "no camera ray passes 0.1-0.5 m from lamp " << ray.lamp;
    // The fog segment of the ray (slabs).
    double t_in = 0, t_out = 1e30;
    for (int a = 0; a < 3; ++a) {
      const double o = (&ray.o.x)[a], dd = (&ray.d.x)[a], lo = (&box_lo.x)[a], hi = (&box_hi.x)[a];
      double t0 = (lo - o) / dd, t1 = (hi - o) / dd;
      if (t0 > t1) std::swap(t0, t1);
      t_in = std::max(t_in, t0);
      t_out = std::min(t_out, t1);
    }
    ASSERT_LT(t_in, t_out);
    const double length_in_fog = t_out - t_in;
    const Vec3 start = ray.o + ray.d * float(t_in);
    // The law of u = t - t_in, optionally with every lamp moved `shift' along the ray.
    auto cdf = [&](double u, double shift) {  // P(stop before u)
      double ff = 0, eq = 0;
      for (int c = 0; c < 3; ++c) ff += (1 - std::exp(-double((&sigma.x)[c]) * u)) / 3;
      for (const Lamp &l : lamps) {
        const Vec3 c = l.centre - start;
        const double delta = dot(c, ray.d) + shift, h = length(c - ray.d * dot(c, ray.d));
        const double phi0 = std::atan2(h, -delta);
        eq += l.pmf * (phi0 - std::atan2(h, u - delta)) / phi0;
      }
      return (1 - share) * ff + share * eq;
    };
    constexpr int kCells = 40;
    const double stop_all = cdf(length_in_fog, 0);
    // Cell edges of equal expected probability (bisection of the cdf).
    std::vector<double> edges(kCells + 1, 0.0);
    edges[kCells] = length_in_fog;
    for (int i = 1; i < kCells; ++i) {
      double lo = 0, hi = length_in_fog;
      for (int it = 0; it < 60; ++it) {
        const double mid = 0.5 * (lo + hi);
        (cdf(mid, 0) < stop_all * i / kCells ? lo : hi) = mid;
      }
      edges[size_t(i)] = 0.5 * (lo + hi);
    }
    constexpr int kSamples = 200000;
    std::vector<int> counts(kCells + 1, 0);
    int strays = 0;
    Pcg32 rng(11, 12 + ray.lamp);
    for (int n = 0; n < kSamples; ++n) {
      ExplicitVertex x0, x1;
      if (!space.first_camera_step(ray.raster, rng, stats, x0, x1)) {
        ++strays;
        continue;
      }
      if (x1.v.type == VertexType::Surface) {
        ++counts[kCells];
        continue;
      }
      const double u = double(length(x1.v.p - x0.v.p)) - t_in;
      if (x1.v.type != VertexType::Medium || !(u >= 0 && u <= length_in_fog)) {
        ++strays;
        continue;
      }
      ++counts[size_t(std::upper_bound(edges.begin() + 1, edges.end() - 1, u) - edges.begin() - 1)];
    }
    auto p_value = [&](double shift) {
      double stat = 0;
      for (int i = 0; i <= kCells; ++i) {
        const double p = i < kCells ? cdf(edges[size_t(i + 1)], shift) - cdf(edges[size_t(i)], shift)
                                    : 1 - cdf(length_in_fog, shift);
        const double expected = p * kSamples, diff = counts[size_t(i)] - expected;
        stat += expected > 0 ? diff * diff / expected : (counts[size_t(i)] > 0 ? 1e30 : 0);
      }
      return test::gamma_q(0.5 * kCells, 0.5 * stat);  // kCells + 1 cells, no fitted parameter
    };
    const double p = p_value(0), p_shifted = p_value(0.05);
    std::printf("[ mlt equiangular ] ray passing %.3f m from lamp %zu, fog [%.3f, %.3f]: %d samples, pass %.4f "
                "(expected %.4f), chi-square p = %.3g; lamps 5 cm off: p = %.3g\n",
                ray.h, ray.lamp, t_in, t_out, kSamples, double(counts[kCells]) / kSamples, 1 - stop_all, p,
                p_shifted);
    EXPECT_EQ(strays, 0) << "first steps that are neither a fog vertex on the ray's segment nor the surface past it";
    EXPECT_GT(p, 1e-3);
    EXPECT_LT(p_shifted, 1e-6) << "the test cannot tell lamps 5 cm off";
  }
}

}  // namespace test_path_mlt_densities
