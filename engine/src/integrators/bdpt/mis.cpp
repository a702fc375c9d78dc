// Multiple importance sampling over every strategy that could have made the path
// (Veach 1997, sec. 10.2; pbrt-v3's MISWeight), with the power heuristic. The weight
// is 1 / sum_i (p_i / p_s)^2, built from running products of reverse/forward density
// ratios along each subpath, so no product of densities ever overflows.
#include "integrators/bdpt/bdpt.h"
#include "lights/rectangle_lamp.h"
#include "lights/sphere_lamp.h"

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
void Bdpt::light_densities(const PathVertex &lv, const PathVertex &v, float &origin, float &toward,
                           float nee_pdf) const {
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
  Light moved;
  const Light &light = scene_.light_now(uint32_t(lv.light), moved);
  emission_pdf(light, lv.p, lv.ng, w, radius, pdf_pos, pdf_dir);
  origin = pdf_pos * scene_.light_distribution().pmf(lv.light);
  toward = 0;
  if (!(d2 > 0)) return;
  toward = pdf_dir / d2;
  if (v.on_surface()) toward *= absdot(v.ng, w);
  if (is_sphere_lamp(light) || is_rectangle_lamp(light))
    split_next_event_density(light, lv, v.p, origin, toward, nee_pdf);
}

// Lamps whose point next-event estimation (s = 1) samples otherwise than the emission
// does, which the longer light subpaths (s >= 2) start from: a lamp's sphere from the cone
// it subtends at v (sphere_lamp.h; up to 4x denser on the visible cap than the emission's
// uniform point), a square or rectangle by the solid angle of the part that can light v
// (rectangle_lamp.h; far denser near v than its uniform point when v is close). Each
// strategy keeps its own density: `origin` becomes next-event estimation's (area measure
// at the lamp point) and `toward`, v's density from the lamp, takes the inverse ratio, so
// that origin x toward, all the strategies s >= 2 see of the lamp, is still the
// emission's. The power heuristic then weighs every strategy by its true density; with
// the emission's point density for s = 1 (pbrt's choice) next-event estimation was
// under-weighted on glossy highlights, with the cone's for every s (no ratio moved to
// v) light tracing was over-weighted, noisy on diffuse surfaces (2.8x the MSE of
// the disk model on the caustic scene).
void Bdpt::split_next_event_density(const Light &lamp, const PathVertex &lv, Vec3 v, float &origin, float &toward,
                                    float nee_pdf) const {
  Vec3 w = v - lv.p;
  const float d2 = length_squared(w);
  if (!(d2 > 0) || !(origin > 0)) return;
  // (A rectangle's density is a spherical rectangle's solid angle: not found twice for the
  // point next-event estimation has just sampled.)
  const float pdf_solid_angle = nee_pdf >= 0           ? nee_pdf
                                : is_sphere_lamp(lamp) ? sphere_lamp_cone_pdf(lamp, v)
                                                       : rectangle_lamp_pdf(lamp, v, lv.p);
  const float pmf = scene_.light_distribution().pmf(lv.light);
  const float nee = pmf * pdf_solid_angle * absdot(lv.ng, w / std::sqrt(d2)) / d2;
  // v inside the sphere, on its horizon, behind the lamp or beyond the part whose light
  // reaches it: no next-event estimation there, and no light from this point either.
  if (!(nee > 0) || !std::isfinite(nee)) return;
  toward *= origin / nee;
  origin = nee;
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

void set_mis_sum(PathVertex *path, int k, bool delta_before, bool balance) {
  double r = ratio(path[k].pdf_rev, path[k]);
  // Filter Glossy: the strategies below would have a light walk sample at a vertex the
  // blur changed (filter_glossy.h); mixed visibility: their light walk would have to make
  // the segment reaching path[k] (PathVertex::light_cut). They cannot make the path.
  double below = k > 0 && !path[k].ends_light_side() ? path[k - 1].mis_sum : 0.0;
  path[k].mis_sum = (balance ? r : r * r) * ((!path[k].delta && !delta_before ? 1.0 : 0.0) + below);
}

// Lafortune & Willems 1993 ("Selecting the weights"): each camera-path vertex y_k has a
// degree of specularity W_k in [0, 1]. At y_k the path's share still left is split: 1 - W_k
// to the connections there (whatever the light subpath's length), W_k passed on along the
// camera path. Strategy (s, t) connects at y_(t-1): weight (1 - W_(t-1)) prod_(k < t-1) W_k;
// the camera path finding the emitter there (s = 0) keeps prod_(k < t-1) W_k. W is a
// property of the path (Bsdf::specularity does not depend on the direction of travel), so
// every strategy computes the same split and the weights of a path sum to one.
// Where the connections at y_k cannot make the path (it scatters off a delta lobe at
// y_(k+1): a caustic seen on a diffuse y_k), W_k counts as 1: the share passes on. The
// vertex a strategy connects at (or the emitter, for s = 0) scatters by the connection,
// never by a delta lobe, whatever lobe the walk sampled there afterwards.
float Bdpt::lafortune_willems_weight(const PathVertex *light_path, const PathVertex *camera_path,
                                     const PathVertex &light_start, int s, int t) const {
  if (t == 1) return light_tracing_share(light_path, s);
  float w = 1;
  for (int k = 1; k < t - 1; ++k) w *= k + 1 < t - 1 && camera_path[k + 1].delta ? 1.0f : camera_path[k].specularity;
  if (s == 0) return w;
  // A delta light cannot be found by the camera path: the connection next to it (s = 1)
  // keeps the share s = 0 would have had.
  float specular = s == 1 && light_start_is_delta(light_start) ? 0.0f : camera_path[t - 1].specularity;
  return w * (1.0f - specular);
}

// Light tracing (t = 1) is not one of Lafortune & Willems' strategies; it takes only the
// share no other strategy can: a path from a delta light whose vertex next to the light is
// delta (a point lamp's caustic through a mirror or smooth glass) cannot be made by s = 0
// nor by next-event estimation there, and the share the camera-side split hands to the end
// of such a path would be lost. The path seen from the camera: z_k = light_path[s - k].
float Bdpt::light_tracing_share(const PathVertex *light_path, int s) const {
  if (s < 3 || !light_start_is_delta(light_path[0]) || !light_path[1].delta) return 0;
  float w = 1;
  for (int k = 1; k < s - 2; ++k) w *= light_path[s - k - 1].delta ? 1.0f : light_path[s - k].specularity;
  return w;  // W' of z_(s-2) is 1: the next vertex, z_(s-1) = light_path[1], is delta
}

float Bdpt::mis_weight(const PathVertex *light_path, const PathVertex *camera_path, const PathVertex &sampled, int s,
                       int t, const ConnectionDensities &c) const {
  if (s + t == 2) return 1.0f;
  const bool balance = this->balance();
  auto power = [balance](double r) { return balance ? r : r * r; };
  if (settings_.mis == MisHeuristic::LafortuneWillems)
    return lafortune_willems_weight(light_path, camera_path, s == 1 ? sampled : light_path[0], s, t);
  // Nothing is copied or modified: the densities this strategy changes are overrides
  // (c), read for the two vertices nearest the connection on each side; the strategies
  // further down each subpath are summed once per subpath (mis_sum). The connection
  // vertices are connectible by construction (never delta here).
  double sum = 0;
  // Camera side: strategies with fewer camera vertices (i = t - 1 down to 1). Filter
  // Glossy: each has its light walk sample at the vertices from its connection up to this
  // strategy's light vertex (qs), so it cannot make the path once one of them was blurred
  // (filter_glossy.h; set_mis_sum stops the running sums there). An emitter the camera
  // path found (s = 0) is no scattering vertex. Mixed visibility: each needs a light walk
  // to make the segments from its connection up to this strategy's, the connection's own
  // included (c.light_cut, PathVertex::light_cut).
  if (t >= 2 && !c.qs_blurred && !c.light_cut) {
    const PathVertex &pt_minus = camera_path[t - 2];
    const PathVertex &pt = camera_path[t - 1];
    double r = ratio(c.pt_rev, pt);
    if (!pt_minus.delta) sum += power(r);
    if (t >= 3 && !(s > 0 && pt.blurred) && !pt.light_cut) {
      const PathVertex &below = camera_path[t - 3];
      r *= ratio(c.pt_minus_rev, pt_minus);
      const double further = pt_minus.ends_light_side() ? 0.0 : below.mis_sum;
      sum += power(r) * ((!pt_minus.delta && !below.delta ? 1.0 : 0.0) + further);
    }
  }
  // Light side: strategies with fewer light vertices (i = s - 1 down to 0). The light
  // point an s = 1 strategy sampled afresh stands in for the subpath's first vertex.
  // Camera walks follow every segment a light walk made (mixed visibility: they meet what
  // their kind sees, the light walk what any kind but the camera's sees); the segment
  // next-event estimation made may have blocked one (c.s0_impossible).
  if (s >= 1) {
    const PathVertex &qs = s == 1 ? sampled : light_path[s - 1];
    double r = ratio(c.qs_rev, qs);
    bool delta_before = s >= 2 ? light_path[s - 2].delta : light_start_is_delta(qs);
    if (!delta_before && !(s == 1 && c.s0_impossible)) sum += power(r);
    if (s >= 2) {
      const PathVertex &qs_minus = light_path[s - 2];
      r *= ratio(c.qs_minus_rev, qs_minus);
      bool delta_below = s >= 3 ? light_path[s - 3].delta : light_start_is_delta(qs_minus);
      double below = s >= 3 ? light_path[s - 3].mis_sum : 0.0;
      sum += power(r) * ((!qs_minus.delta && !delta_below ? 1.0 : 0.0) + below);
    }
  }
  // A sum that overflowed (or met 0 x inf) even so: weight 0, as for any overflow.
  return sum < HUGE_VAL ? float(1.0 / (1.0 + sum)) : 0.0f;
}

}  // namespace rdv::bdpt
