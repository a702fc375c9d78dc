// Path space for Metropolis light transport (Veach & Guibas 1997; Veach 1997, ch. 11):
// a state is an explicit path x_0 (the camera) ... x_(n-1) (a point on a light), its
// vertices BDPT's PathVertex (surfaces and medium scattering points), and what it
// carries is one function f(x) of the vertices alone, however the path was sampled:
//  - a surface's BSDF is built from the direction toward its camera-side neighbour,
//    with unfiltered texture lookups (no ray cone: a mutation can reproduce it from
//    either side); transport is evaluated in the radiance direction;
//  - transmittance is closed form (homogeneous media), visibility exact;
//  - plain transparent layers (Scene::is_plain_layer: alpha, Transparent BSDF) are no
//    vertices but parts of the edges that cross them, as in BDPT: f takes their
//    straight-through coefficient, a walk's density the probability of passing each and, at
//    a vertex on one, of not passing it (docs/mlt.md).
// Each vertex also has the two area (volume) densities of sampling it, from the camera
// side (fwd) and from the light side (rev), with the same rules the walks here use:
// BSDF / phase sampling (from the light side with a BSDF built toward the light-side
// neighbour), free-flight distances by one channel chosen uniformly, a camera ray by a
// raster point uniform over the sample region, a light by power and a point uniform on
// it (a lamp with a radius: a point on its sphere, lights/sphere_lamp.h, which the camera
// side's last step may also reach, as it reaches an area lamp). Lights at infinity (sun, world): the last vertex is a
// direction (solid-angle measure, no geometry term on its edge); the camera side reaches it
// by escaping (the BSDF / phase density of the direction); the light side picks it by the
// light's direction density (a sun without an angle: a delta, never hit) and then the next
// vertex by a point uniform on the disk perpendicular to it covering the scene (BDPT's),
// times the cosine there. Every light at infinity but a sun without an angle is one vertex:
// f sums their radiance, its light-side density their pmf x direction density. The bidirectional mutation's transition density T(x -> y) is a sum of products
// of these (Veach 1997, sec. 11.4.2), so the acceptance ratio is exact.
// Motion blur (scene/motion.h): the shutter time is one more coordinate of the state, one
// per path as BDPT traces one per camera sample. f, every density and every ray of a path
// are at its time (the scene's rays, Scene::camera_now, Scene::light_now); a large step
// draws a new time uniform over the shutter (density 1, a factor of q and T), every other
// mutation keeps it (a kept vertex lies on a surface only at the time it was found).
// Filter Glossy (integrators/filter_glossy.h) is a property of the path too, as in BDPT: a
// surface's BSDF in f is blurred by the smallest camera-side scattering density before it
// (vertex.v.filter_pdf), a function of the camera-side prefix. The camera side samples that
// blurred BSDF; the light side samples the unblurred one, so its density of a vertex is 0 where
// the blur changes the BSDF it scattered at (a split that samples there cannot make the path;
// a proposal that did is not made).
// Cycles' Light Paths limits (per-kind bounces, caustics switches) are a property of the
// vertices: f is 0 for a path outside them (integrators/light_path_limits.h), every vertex
// classified as the path tracer classifies it, so every mutation sees the same f.
// Film > Transparent (set_film; integrators/film_alpha.h): a path whose camera sees through
// (x_1 on, as below) to the world carries none of its colour; suns still light it. A holdout
// object the camera sees through to ends the path's f there (shown as nothing, as BDPT).
// Shadow catchers (set_film; film/shadow_catcher_passes.h): a path also carries
// f_catcher, what the same vertices carry to the Shadow Catcher pass. The path splits at the
// first catcher on the camera's see-through chain (x_1 on, through Transparent BSDFs and,
// with Transparent Glass, smooth refractions); f_catcher is 0 for a path that does not split,
// else f with each edge past the split blocked only by catchers, each vertex past it on a
// catcher (or in a medium) and the light one that lights catchers (Light::shadow_catcher).
// A chain targets both (as pssmlt targets a sample and its copy), so a path in a catcher's
// shadow, f = 0, is a state the chains visit; its blocked edge has no walk density (only a
// connection across it makes it), and the mutations trace the scene as it is. Where nothing
// but catchers lies past the split, f_catcher = f: the lit floor's pass is 1 up to rounding.
#pragma once
#include <algorithm>
#include <string>
#include <vector>
#include "core/hash.h"
#include "core/ray_offset.h"
#include "integrators/bdpt/path_vertex.h"
#include "integrators/filter_glossy.h"
#include "integrators/integrator.h"
#include "integrators/mlt/equiangular.h"
#include "integrators/mlt/image_strata.h"

namespace rdv::mlt {

struct ExplicitVertex {
  // wo: toward the camera-side neighbour; bsdf built from it; media: the stack on that
  // side. Light vertices: light >= 0, media the light's.
  bdpt::PathVertex v;
  SurfaceHit hit;  // surfaces: rebuilds the BSDF when the camera-side neighbour changes
  float blur = 0;  // Filter Glossy: the roughness v.bsdf is blurred with (0: as built)
};

struct ExplicitPath {
  std::vector<ExplicitVertex> x;  // x[0] the camera ... x[n - 1] on a light
  int n = 0;
  std::vector<double> fwd, rev;  // per vertex: density of sampling it from the camera / light side
  // rev[i] over the directional density it was scattered with at x_(i+1): the solid angle
  // to area factor and the free flight (the caustic perturbation picks the direction itself).
  std::vector<double> rev_area;
  // fwd[i] over the directional density x_(i-1) scattered with (the multi-chain
  // perturbation picks the direction itself).
  std::vector<double> fwd_area;
  Color f{0.0f};                 // image_area x the measurement contribution (splat value)
  Color f_catcher{0.0f};         // shadow catchers: the Shadow Catcher pass's (set_shadow_catchers)
  int split = -1;                // shadow catchers: the vertex on the first catcher the camera sees through to (-1: none)
  Vec2 raster{0, 0};
  float time = 0.5f;  // the shutter time in [0, 1) of every vertex (scenes that move; else unused)
  void reserve(int max_vertices);
  // What a chain targets (before the relative target's weight): the image's luminance and the
  // catcher pass's.
  float carried() const { return luminance(f) + luminance(f_catcher); }
};

// Large: the whole path regenerated. Bidirectional: Veach's, on a subpath. Lens: Veach's
// lens perturbation (the raster point moved by a distance ~ 1/R, the camera ray traced
// afresh through the path's specular chain E S* to its first non-specular vertex, joined
// to the next). Propagation and
// Scattering (Pauly, Kollig & Keller 2000, sec. 4): a medium vertex moved in spherical
// coordinates about its light-side neighbour, along the line from it (distance D with
// density ~ 1/D) or across it (angle theta with density ~ 1/theta), the rest of the path
// kept and reconnected. Caustic: Veach's caustic perturbation of a path E D S+ (D|L) ...:
// the direction leaving the light-side end of the specular chain turned a little, the chain
// retraced toward the camera to its first vertex, joined to the camera. MultiChain: Veach's
// multi-chain perturbation of a path E S* D S+ D ...: the lens perturbation, then at each
// non-specular vertex whose light-side neighbour is specular the direction turned a little
// and the next specular chain retraced, until a chain ends at a vertex that can be joined
// (or at the light). LensSubpath: Veach's lens subpath mutation: a camera walk through a
// new image position (a chain's stratified sequence, image_strata.h) through any number of
// specular vertices, to the first non-specular one (joined to the rest of the path) or, for
// a path E S* L, to the first light.
enum class MutationType : uint8_t {
  Large, Bidirectional, Lens, Propagation, Scattering, Caustic, MultiChain, LensSubpath, Count
};
constexpr int kMutationTypes = int(MutationType::Count);
inline const char *mutation_name(MutationType t) {
  static const char *names[] = {"large",   "bidirectional", "lens",        "propagation",
                                "scattering", "caustic",    "multi_chain", "lens_subpath"};
  return names[int(t)];
}

// bidirectional, lens, propagation, scattering, caustic, multi_chain, lens_subpath: the
// MutationType order after Large (weights[i] is type i + 1's).
constexpr int kWeightedMutations = 7;
struct MutationSettings {
  float weights[kWeightedMutations] = {1.0f, 1.0f, 1.0f, 1.0f, 1.0f, 1.0f, 1.0f};  // of the non-large mutations
  float lens[2] = {0.1f, 10.0f};          // lens: [R_min, R_max], pixels
  float distance[2] = {1e-3f, 1.0f};      // propagation: [Dmin, Dmax], scene units
  float angle[2] = {1e-4f, 0.2f};         // scattering: [theta_min, theta_max], radians
  float caustic[2] = {1e-4f, 0.05f};      // caustic and multi-chain: [theta_min, theta_max], radians
  // Lens, caustic and multi-chain perturbations in scenes with media: the probability that a
  // proposal retraces as Pauly's perturbations do (every retraced vertex keeps its kind, a
  // medium vertex its distance from the vertex before it); else each medium vertex's distance
  // is a new free flight, as the walks draw it.
  float keep_distances = 0.5f;
  // Scenes with scattering media and point or spot lamps (with or without a radius): the
  // probability that a camera-side walk draws a distance in a medium equiangularly toward a
  // lamp instead of by free flight (equiangular.h); 0 (the default, docs/mlt.md): free
  // flights only.
  float equiangular = 0.0f;
  // The fewest vertices of a chain's path: 2 (every path), or 4 where the paths of one and
  // two edges (a light seen, direct lighting) are left to the path tracer, as Veach left
  // direct lighting to standard methods (Metropolis: MltSettings::direct_samples). Shorter
  // paths have f = 0, and large steps and bidirectional mutations make none; vertices passed
  // straight through (a transparent surface that emits, holds out or catches shadows) do not
  // count, as the path tracer does not count them.
  int min_vertices = 2;
};

// One proposal: the path it made, and T(y -> x) / T(x -> y) (0: no path).
struct Proposal {
  MutationType type = MutationType::Bidirectional;
  double ratio = 0;
  double independent = 0;  // large steps: lum(f(y)) / q(y), an independent sample of b
  int l = 0, m = 0, na = 0;  // x's vertices l+1 .. m-1 were replaced by y's l+1 .. l+na
  bool kept_distances = false;  // lens, caustic, multi-chain: retraced as Pauly's (MutationSettings)
};

class PathSpace {
 public:
  PathSpace(const Scene &scene, int max_bounces, Vec2 sample_origin, Vec2 sample_size, float image_area,
            float large_step_probability, const MutationSettings &mutations = {},
            const LightPathLimits &limits = {});
  // Why mlt cannot render this scene with these settings (a message naming the light,
  // medium, camera or setting), or "" when it can.
  static std::string unsupported(const Scene &scene, const RenderSettings &settings);
  int max_vertices() const { return max_vertices_; }

  // f, the image position and both densities of every vertex of y (y.n and the vertices set).
  void evaluate(ExplicitPath &y, RayStats &stats) const;
  // A path with every vertex sampled afresh (a large step); returns its density q(y)
  // (0: no path). The path length is drawn over min_vertices .. max_vertices vertices,
  // uniformly until set_length_weights.
  double sample_independent(Pcg32 &rng, RayStats &stats, ExplicitPath &y) const;
  // The large steps' path lengths in proportion to weights[n - min_vertices] (a bootstrap's
  // root mean square of target / q per vertex count n: the share of samples that minimises
  // the variance of b), mixed with the uniform choice so no length is left out. All zero:
  // uniform. Set between the bootstrap and the first mutation (the bootstrap's paths are
  // replayed with the uniform choice they were drawn with).
  void set_length_weights(const std::vector<double> &weights);
  double length_probability(int n) const {
    if (n < min_vertices_ || n > max_vertices_) return 0;
    return length_pmf_.empty() ? 1.0 / path_lengths() : length_pmf_[size_t(n - min_vertices_)];
  }
  int min_vertices() const { return min_vertices_; }
  // q(y) of a path whose densities are evaluated.
  double independent_density(const ExplicitPath &y) const;
  // One mutation of x (evaluated) into y, its type chosen by the settings' weights among the
  // types that can apply to x (large steps by their own probability); y is written, x never.
  // strata: the chain's sequence of image positions for the lens subpath mutation (none: a
  // position uniform on the region).
  Proposal mutate(const ExplicitPath &x, Pcg32 &rng, RayStats &stats, ExplicitPath &y,
                  ImageStrata *strata = nullptr) const;
  // Veach's bidirectional mutation (large: the whole path).
  Proposal bidirectional(const ExplicitPath &x, bool large, Pcg32 &rng, RayStats &stats, ExplicitPath &y) const;
  // The propagation (radial) or scattering (angular) perturbation of a medium vertex of x
  // chosen uniformly (none: no proposal). The ratio is the Jacobian of spherical coordinates
  // about the light-side neighbour, r_y^2 / r_x^2 (1 for the angular move): the perturbation
  // densities in r and in solid angle are symmetric.
  Proposal perturb_medium_vertex(const ExplicitPath &x, MutationType type, Pcg32 &rng, RayStats &stats,
                                 ExplicitPath &y) const;
  // The lens, caustic and multi-chain perturbations retrace with probability
  // keep_distances as Pauly, Kollig & Keller's scattering perturbations do ("preserving
  // the path characteristic", sec. 5): each retraced vertex must have x's kind, and a medium
  // vertex is put at x's distance from the vertex before it on the retraced ray instead of
  // a new free flight (a volume caustic's scattering point moves with the caustic instead of
  // jumping along the ray). The move then keeps that distance r: it is a move on the set of
  // paths with that r, whose target is f times the Jacobian of the vertex's volume measure
  // in (the perturbed coordinates, r). That Jacobian is the walk's density with its free
  // flight drawn divided by it, so the ratio below loses each kept vertex's free-flight
  // factor: T(y->x) / T(x->y) times flight_y / flight_x (camera_side_flight, light_side_flight).
  // Veach's lens perturbation of a path E S* D ...: the raster point moved, the camera ray
  // traced afresh through as many specular vertices as x has before its first non-specular
  // vertex x_c (each delta event sampled as the camera walk does), then joined to x_(c+1).
  // T(y->x) / T(x->y) = prod fwd_x[1..c] / prod fwd_y[1..c] (the raster offset's density
  // is symmetric; fwd[1] is the uniform raster density times the same Jacobian).
  Proposal perturb_lens(const ExplicitPath &x, Pcg32 &rng, RayStats &stats, ExplicitPath &y) const;
  // Veach's caustic perturbation of a path E D S+ (D|L) ...: x_1 not specular, x_2 .. x_(k-1)
  // specular, x_k not; the direction from x_k toward x_(k-1) turned by theta ~ 1/theta on
  // the caustic angle range (uniform azimuth: a density in solid angle symmetric in the two
  // directions), the chain retraced from x_k as the light walk samples it (each of
  // y_(k-1) .. y_2 must scatter by a delta lobe) to y_1, which is joined to the camera.
  // T(y->x) / T(x->y) = (rev_area_x[k-1] prod rev_x[1..k-2]) / (the same of y).
  Proposal perturb_caustic(const ExplicitPath &x, Pcg32 &rng, RayStats &stats, ExplicitPath &y) const;
  // Veach's multi-chain perturbation of a path E S* D S+ (D|L) ... (sec. 11.4.3), where the
  // lens perturbation stops: x_c the first non-specular vertex, x_(c+1) specular, or x_c the
  // light (E S* L: the retraced chain must hit it). The lens perturbation's move of x_1 ..
  // x_c, then for each chain: at its non-specular camera-side
  // end y_a the direction x_a -> x_(a+1) turned by theta ~ 1/theta on the caustic angle range
  // (uniform azimuth: symmetric in solid angle), traced from y_a and on through as many
  // specular vertices as x has there (each must scatter by a delta lobe, sampled as the
  // camera walk samples it) to y_b, x_b the next non-specular vertex; y_b is joined to
  // x_(b+1) when that is not specular, else the next chain starts at y_b. A chain that ends
  // at the light must hit it (a lamp with a radius, an area lamp, a mesh lamp, a light at infinity).
  // T(y->x) / T(x->y) = P(x) / P(y), P = prod fwd[1..c] times, per chain, fwd_area[a+1]
  // prod fwd[a+2..b] (the turn's density cancels).
  Proposal perturb_multi_chain(const ExplicitPath &x, Pcg32 &rng, RayStats &stats, ExplicitPath &y) const;
  // Veach's lens subpath mutation (sec. 11.4.4): x's lens subpath x_1 .. x_c replaced by a
  // camera walk through the raster point given (the chain's stratified sequence), on through
  // surfaces whose BSDF is all delta lobes (an event sampled at each) for as many vertices as
  // it takes (walk_lens_subpath). A path with more after its lens subpath than the light
  // (E S* D D ..., E S* D S ...: x_(c+1) must not be specular) keeps x_(c+1) .. and the walk
  // ends at its first vertex that is not all delta, joined to x_(c+1). A short path (E S* L,
  // E S* D L) is replaced whole: the walk ends at the first light it meets (E S* L: the lamp
  // seen directly, in a mirror or through glass, which only a camera walk makes) or at its
  // first vertex that is not all delta, joined to a light vertex sampled as the light side
  // samples it (E S* D L). The new path's density is the walk's (and the light vertex's)
  // whatever x is: T(y->x) / T(x->y) = lens_subpath_density(x) / lens_subpath_density(y)
  // (the raster density, uniform on the region, in fwd[1]), exact when the raster point is
  // uniform.
  Proposal lens_subpath(const ExplicitPath &x, Vec2 raster, Pcg32 &rng, RayStats &stats, ExplicitPath &y) const;
  // What the film keeps, set before the first path: catchers, a shadow catcher's sums
  // (evaluate() computes f_catcher and split); alpha, Film > Transparent (the world seen
  // through to is not in f) and Transparent Glass (smooth refractions keep the camera seeing
  // through, and rough ones below its roughness by their share: see_through_share).
  void set_film(bool catchers, const FilmAlpha &alpha) {
    catchers_ = catchers;
    film_transparent_ = alpha.film_transparent;
    holdouts_ = alpha.holdouts;
    transparent_glass_ = alpha.transparent_glass;
    glass_alpha2_ = alpha.glass_roughness * alpha.glass_roughness;
  }
  // After the bootstrap: whether any of its paths had a specular vertex. Without, the caustic
  // and multi-chain perturbations could only fail and get weight 0 (fixed before the chains run).
  void set_specular_paths(bool found);

  // The pieces of T (tests check them against an independent evaluation).
  double deletion_probability(int nv, int l, int m) const;
  double addition_probability(int nv, int l, int m, int na) const;
  // T(x -> y) of a partial bidirectional mutation: x's vertices l+1 .. m-1 replaced by y's
  // l+1 .. l+na, read from y's densities.
  double transition_density(int nv_x, int l, int m, const ExplicitPath &y, int na) const;
  // The camera walk's first step through a raster point: x_0 as a path's, x_1 traced as every
  // camera-side walk traces it (tests: the distribution of its distances in media).
  bool first_camera_step(Vec2 raster, Pcg32 &rng, RayStats &stats, ExplicitVertex &x0, ExplicitVertex &x1) const;

 private:
  // The plain transparent layers (Scene::is_plain_layer) on an edge: no path vertices, as
  // in BDPT's walks. f carries their straight-through coefficient; a walk along the edge
  // passes each by the probability that its lobe choice there passes (Bsdf::pass_probability
  // with the BSDF built toward the side the walk comes from).
  struct LayerPasses {
    Color tr{1.0f};
    double fwd = 1, rev = 1;  // the camera walk's (along the edge) and the light walk's
    int count = 0;
  };
  struct EdgeTrace {
    bool visible = false;
    Color tr{1.0f};           // the media's transmittance (the layers': layers.tr)
    double fwd = 1, rev = 1;  // densities of reaching b from a / a from b past the edge's media and layers
    LayerPasses layers;       // the layers f's kind of ray meets (the walks': walks_along)
  };
  // The kinds of ray (scene/ray_visibility.h) an edge stands for: f's (what blocks the
  // edge), and those of the walks that would sample its two ends (what stops them); all
  // visibility::kAnyRay in scenes without ray visibility.
  struct EdgeMasks {
    uint32_t f, camera_walk, light_walk;
  };
  bool trace_edge(const ExplicitVertex &a, const ExplicitVertex &b, Vec3 w, const EdgeMasks &masks, EdgeTrace &e,
                  RayStats &stats) const;
  // A walk's density of an end is 0 where something its kind of ray meets lies on the edge,
  // and takes the passes of the layers that kind meets.
  void walks_along(const ShadowRay &s, Vec3 w, const EdgeMasks &masks, EdgeTrace &e, RayStats &stats) const;
  // The layers the ray s (along the edge's direction w) meets for this mask: false where a
  // surface that is no plain layer blocks it.
  bool layers_along(const ShadowRay &s, Vec3 w, uint32_t mask, LayerPasses &l, RayStats &stats) const;
  void add_layer(const SurfaceHit &hit, Vec3 w, LayerPasses &l) const;
  bool on_plain_layer(const ExplicitVertex &v) const {
    return layers_ && v.v.type == bdpt::VertexType::Surface && scene_.is_plain_layer(v.hit);
  }
  // The probability that a walk arriving at v from the side wo faces does not pass it (1 off
  // plain layers): the walk stops there, and its scattering from v is the rest of v's
  // sampling (Bsdf::scattering_lobe_u), so its density there is divided by it.
  double keeps(const ExplicitVertex &v, const Bsdf &bsdf, Vec3 wo) const {
    return on_plain_layer(v) ? 1.0 - double(bsdf.pass_probability(wo)) : 1.0;
  }
  // The kind of ray leaving y's vertex i toward w (camera rays from x_0; after a
  // scattering its kind's; a pass-through keeps the kind that reached it).
  uint32_t ray_mask(const ExplicitPath &y, int i, Vec3 w) const;
  // Light-side walks do not know the kind of the scattering they will meet: they meet what
  // any ray but the camera's meets.
  uint32_t light_walk_mask() const { return visibility_ ? visibility::kNonCamera : visibility::kAnyRay; }
  // to_light: the last vertex from the camera side, which may be a lamp's sphere or an area lamp.
  // kept_flight >= 0 (Pauly's retrace): no free flight is drawn; z is the medium point at that
  // distance along the ray, and there is none if a surface or a lamp comes first or the point
  // is in no medium.
  // side: which end the walk comes from (the camera side draws its distances in media from
  // the equiangular mixture, the light side by free flights).
  enum class Side { Camera, Light };
  bool trace_step(Ray ray, MediumStack media, Side side, Pcg32 &rng, RayStats &stats, ExplicitVertex &z,
                  bool to_light = false, float kept_flight = -1) const;
  // A distance drawn in medium m along the ray from its segment's start (-1: the segment of
  // that length is passed).
  float sample_distance(const Medium &medium, const Ray &ray, float segment, Side side, Pcg32 &rng) const;
  // The lamp the ray o + t d meets first for t < tmax (its index, t), or -1: a sphere lamp
  // (lights/sphere_lamp.h) where the ray enters it, an area lamp from its emitting side.
  int first_lamp(Vec3 o, Vec3 d, float tmax, float &t, uint32_t mask) const;
  // x_0: the pinhole, a point uniform on a thin lens's aperture, (orthographic) a stand-in
  // that evaluate() moves to x_1's foot on the image plane, or (orthographic with depth of
  // field) a point uniform on the image plane over the sample region widened by the
  // aperture's radius (lens_region_area).
  bool camera_vertex(Pcg32 &rng, ExplicitVertex &z) const;
  void lens_region(const Camera &camera, Vec2 &lo, Vec2 &hi) const;  // camera space, on the image plane
  double lens_region_area(const Camera &camera) const;
  // The raster point lies in the region this PathSpace samples (a tile, a farm part's image).
  bool in_sample_region(Vec2 raster) const {
    return raster.x >= sample_origin_.x && raster.x < sample_origin_.x + sample_size_.x &&
           raster.y >= sample_origin_.y && raster.y < sample_origin_.y + sample_size_.y;
  }
  // The camera ray from x_0 through a raster point (a thin lens: from x_0's lens point), of
  // the camera's kind (ray_mask). Orthographic with depth of field: from x_0 toward the
  // raster point's focal-plane point (evaluate() checks that x_0 is on the aperture there).
  Ray camera_ray(const ExplicitVertex &camera_vertex, Vec2 raster) const;
  bool light_vertex(Pcg32 &rng, ExplicitVertex &z, Vec3 &dir) const;
  // to_light (trace_step's): 1 or 0; -1: whether y_at is y's last vertex. kept_flight >= 0:
  // y_at is the medium point at that distance from the vertex the step leaves (trace_step's).
  bool extend_from_camera_side(ExplicitPath &y, int at, Pcg32 &rng, RayStats &stats, int to_light = -1,
                               float kept_flight = -1) const;
  bool extend_from_light_side(ExplicitPath &y, int at, Pcg32 &rng, RayStats &stats, float kept_flight = -1) const;
  void settle(ExplicitVertex &z, const ExplicitVertex &camera_side) const;
  // Filter Glossy: z's BSDF blurred by the roughness z.v.filter_pdf gives (rebuilt from the
  // hit when it was blurred by another prefix's).
  void blur_by_prefix(ExplicitVertex &z) const;
  // Filter Glossy: whether the light walk that sampled y's vertices lo .. hi could have made
  // them (each has a light-side density).
  static bool light_walk_made(const ExplicitPath &y, int lo, int hi);
  MediumStack stack_toward(const ExplicitVertex &z, Vec3 w) const;
  bool regenerate(ExplicitPath &y, int l, int na, int j, Pcg32 &rng, RayStats &stats) const;
  // y_(at+1) traced from y_at along wi (a walk's ray: spawn offset, media, ray kind), facing y_at;
  // scattered_pdf: y_at's density of wi (Filter Glossy's prefix; kInf for a delta event).
  bool trace_from(ExplicitPath &y, int at, Vec3 wi, float scattered_pdf, Pcg32 &rng, RayStats &stats,
                  int to_light = -1, float kept_flight = -1) const;
  // Pauly's retrace (MutationSettings::keep_distances): drawn once per lens, caustic or
  // multi-chain proposal in scenes with media (never in others, whose proposals stay as they were).
  bool keeps_distances(Pcg32 &rng) const { return media_ && rng.next_float() < mutations_.keep_distances; }
  // Where a retrace kept a medium vertex's distance, that vertex has no free flight drawn: its
  // density lacks the walk's free-flight factor, which these give (a factor of fwd_area[i], a
  // camera-side step from x_(i-1), and of rev_area[i], a light-side step from x_(i+1)).
  double camera_side_flight(const ExplicitPath &p, int i) const;
  static double light_side_flight(const ExplicitPath &p, int i);
  // The lens and multi-chain perturbations' move: y = x with x_1 .. x_c (E S*
  // (D|L)) retraced from the camera through `raster`, each of y_1 .. y_(c-1) scattering by a
  // delta lobe (x_c the light: y_c must be one). Returns c (0: no path; the raster point
  // outside the sample region, or a chain of another shape).
  // keep: Pauly's retrace (y_c must have x_c's kind; a medium x_c keeps its distance from x_(c-1)).
  int retrace_lens(const ExplicitPath &x, Vec2 raster, bool keep, Pcg32 &rng, RayStats &stats, ExplicitPath &y) const;
  // The lens perturbation through `raster`: retrace_lens, y_c joined to x_(c+1) (which must
  // not be specular).
  Proposal lens_move(const ExplicitPath &x, Vec2 raster, bool keep, MutationType type, Pcg32 &rng, RayStats &stats,
                     ExplicitPath &y) const;
  // The lens subpath mutation's walk: y_0 = x_0, y_1 from the camera ray through `raster`,
  // then on from each vertex whose BSDF is all delta lobes (an event sampled there), to the
  // first vertex that is not (returned if `after` more vertices fit behind it). to_light (a
  // short path's walk): every step may end at a light, which ends the walk (a lamp in front
  // of the next surface, a mesh lamp, a light at infinity, a volume light where a free flight
  // stops); without, lamps are passed as the other walks pass them. Returns the end's index
  // c (0: none; a walk beyond the path length, or a failed sample).
  int walk_lens_subpath(const ExplicitPath &x, Vec2 raster, bool to_light, int after, Pcg32 &rng,
                        RayStats &stats, ExplicitPath &y) const;
  // That walk's density of p's vertices 1 .. c (p evaluated): prod fwd[1..c], 0 where the
  // walk would not make them (a vertex before c not all delta). A short path: also 0 where
  // it would have ended at a light before (a mesh lamp before c, a lamp in front on an edge,
  // E S* D L with D a light), and E S* D L times the light vertex's density rev[n - 1].
  double lens_subpath_density(const ExplicitPath &p, int c, bool short_path) const;
  // w: from the light toward its camera-side neighbour; ray_kind: the kind of ray that meets
  // it (lights at infinity that kind does not see give nothing); background false: the world
  // (HDRI or colour) gives nothing (seen through a transparent film), suns still do.
  // scatterings: the path's scattering vertices (each light's Max Bounces, Light::lights_path);
  // receiver: that neighbour's point (Light Falloff's distance).
  Color emitted(const ExplicitVertex &light, Vec3 w, uint32_t ray_kind, bool background, int scatterings,
                Vec3 receiver) const;
  double light_position_density(const ExplicitVertex &light) const;
  // Film alpha, holdouts and shadow catchers: how much of the camera's seeing through goes on
  // past surface vertex v toward w. 1 through a Transparent BSDF or, with Transparent Glass, a
  // smooth refraction; with Transparent Glass, a rough refraction no rougher than its
  // roughness by the share of v's sampling density toward w that such lobes carry (BDPT's
  // camera walk keeps seeing through by the lobe it sampled; so f is the expectation of its
  // rule over that choice); 0 otherwise. (With shadow catchers, 0 or 1: a path has one split.)
  double see_through_share(const ExplicitVertex &v, Vec3 w) const;
  // The path tracer's MIS weight of a ray that surface vertex v scattered toward w and that
  // escapes to the world: the power heuristic against next-event estimation of the world
  // (integrators/path; 1 without a world light).
  double escape_weight(const ExplicitVertex &v, Vec3 w) const;
  // Whether v is on a catcher (a holdout never is).
  bool on_catcher(const ExplicitVertex &v) const;

  // The settings' weight of each small step's type (MutationSettings::weights order), 0 for
  // the types that cannot apply to x's vertex kinds (they would propose nothing).
  void mutation_weights(const ExplicitPath &x, float w[kWeightedMutations]) const;
  // The small step of that type (not the large step).
  Proposal small_step(MutationType type, const ExplicitPath &x, Pcg32 &rng, RayStats &stats, ExplicitPath &y,
                      ImageStrata *strata) const;
  // A large step's shutter time: uniform over the shutter (density 1) in scenes that move;
  // none drawn in static ones (their paths trace as before, bit for bit).
  float shutter_time(Pcg32 &rng) const { return motion_ ? rng.next_float() : 0.5f; }
  // A large step's vertex count over min_vertices_ .. max_vertices_ (length_probability).
  int path_lengths() const { return max_vertices_ - min_vertices_ + 1; }
  int random_path_length(Pcg32 &rng) const;

  const Scene &scene_;
  int max_vertices_, min_vertices_;
  Vec2 sample_origin_, sample_size_;
  float image_area_, region_area_;
  float large_step_probability_;
  std::vector<double> length_pmf_;  // large steps' vertex counts from min_vertices_ (empty: uniform)
  MutationSettings mutations_;
  LightPathLimits limits_;  // per-kind bounces and caustics switches (clamps are refused)
  FilterGlossy filter_;     // Filter Glossy (off: 0)
  // The caustic and multi-chain perturbations' weights when paths have specular vertices.
  float caustic_weight_ = 0, multi_chain_weight_ = 0;
  bool media_;
  bool layers_;  // Scene::has_transparency: plain layers may lie on edges
  bool motion_;  // Scene::has_motion
  bool visibility_, mixed_visibility_;  // Scene::has_ray_visibility / has_mixed_visibility
  bool catchers_ = false, film_transparent_ = false, holdouts_ = false, transparent_glass_ = false;  // set_film
  float glass_alpha2_ = 0;
  // Camera-side distances in media: free flights mixed with equiangular ones toward the
  // point and spot lamps (equiangular.h; off without both).
  EquiangularTargets equiangular_;
  std::vector<uint32_t> hittable_lamps_;  // lamps with a radius (spheres) and area lamps: camera walks reach them
  // The lights at infinity but suns without an angle: one vertex (a direction) for all of
  // them, labelled with the first; f sums their radiance, the light side their densities.
  std::vector<uint32_t> infinite_lights_;
  int infinite_light_ = -1;
};

// Sum over the splits j = 0 .. count of y's new vertices lo .. lo + count - 1 (the
// first j from the camera side, the rest from the light side) of the product of
// their densities, each split chosen with probability 1 / (count + 1). A split whose
// connection would touch a specular vertex (PathVertex::delta) cannot make y: left out.
double split_sum(const ExplicitPath &y, int lo, int count);

}  // namespace rdv::mlt
