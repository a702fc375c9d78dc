// Bidirectional path tracing (Lafortune & Willems 1993; Veach 1997, ch. 10): a camera
// subpath and a light subpath, connected in every way (s light vertices, t camera
// vertices): s = 0 (the camera path finds an emitter), s = 1 (next-event estimation),
// t = 1 (light tracing: splatted wherever it lands on the image), and every inner
// connection; combined with multiple importance sampling (power heuristic) computed
// from ratios of densities, so long paths never overflow.
#pragma once
#include <vector>
#include "integrators/bdpt/path_vertex.h"
#include "integrators/tile_integrator.h"

namespace rdv::bdpt {

// How the strategies that can make a path share it.
enum class MisHeuristic : uint8_t {
  Power,            // Veach's power heuristic (exponent 2), the default
  Balance,          // Veach's balance heuristic
  LafortuneWillems  // Lafortune & Willems 1993: split by the specularity of camera-path vertices
};

struct BdptSettings {
  int max_bounces = 12;
  LightPathLimits limits;  // Cycles' per-kind bounces, caustics, clamps (light_path_limits.h)
  FilmAlpha alpha;         // transparent film and holdouts (film_alpha.h)
  MisHeuristic mis = MisHeuristic::Power;
  // Debug view: render only the (s, t) strategy with s + t - 2 == debug_depth... see
  // strategy_s / strategy_t: when >= 0, only that strategy contributes.
  int strategy_s = -1, strategy_t = -1;
  bool strategy_unweighted = false;  // that strategy without its MIS weight
};

// What a path vertex (surface or medium) does at a connection: its BSDF or phase
// value from v.wo to wi and its densities of scattering v.wo -> wi (fwd) and
// wi -> v.wo (rev), in solid angle.
struct Scattering {
  Color f{0.0f};
  float pdf_fwd = 0, pdf_rev = 0;
};

// The reverse densities (area measure) that change when a strategy joins light vertex
// q_s with camera vertex p_t: at p_t, p_(t-1), q_s and q_(s-1) (Veach 1997, sec. 10.2).
// connect() knows them from its own evaluations; the MIS weight only reads them.
struct ConnectionDensities {
  float pt_rev = 0, pt_minus_rev = 0, qs_rev = 0, qs_minus_rev = 0;
  // Ray visibility, next-event estimation (s = 1) in a scene with mixed visibility: the
  // camera path could not have found the light (something visible to its kind lies
  // between), so s = 0 is no strategy for this path.
  bool s0_impossible = false;
  // Mixed visibility: no light walk could have made the connection's segment (see
  // Bdpt), so no strategy with fewer camera vertices makes the path.
  bool light_cut = false;
  // Filter Glossy: the connection's light vertex q_s has a BSDF the blur changed (by the
  // path's camera-side densities), so no light walk could have sampled past it.
  bool qs_blurred = false;
};

// The MIS sums of a subpath's far end (Veach 1997, sec. 10.2, as running sums): for
// vertex k, the sum over the strategies that connect at vertex i <= k of
// prod_{j=i..k} (remap0(pdf_rev_j) / remap0(pdf_fwd_j))^2, over strategies whose two
// vertices are not delta. Set once pdf_rev of vertex k is final, from vertex k - 1's;
// delta_before: vertex k - 1 is delta (for k = 0, the light is). Every connection's
// weight then reads one of them instead of walking the subpath.
// balance: the balance heuristic's sums (ratio products not squared).
void set_mis_sum(PathVertex *path, int k, bool delta_before, bool balance);

class Bdpt final : public TileIntegrator {
 public:
  Bdpt(const Scene &scene, const BdptSettings &settings)
      : scene_(scene), settings_(settings), mixed_(scene.has_mixed_visibility()),
        catchers_(scene.has_shadow_catchers()) {}
  // Mixed visibility (Scene::has_mixed_visibility): objects that some kinds of ray after a
  // scattering see and others do not, or lamps that cast no shadows. A path's contribution
  // is the path tracer's: each segment traced as the kind of the scattering at its camera
  // end, which must see the vertex it reaches, and the last one blocked by the light's
  // shadow casters. A light walk cannot know the kind of a segment until the vertex it
  // reaches scatters on, so:
  // - light walks meet what any kind but the camera's sees and end where they would pass a
  //   surface of mixed visibility without a vertex (a plain layer), or meet a look copy of
  //   mixed visibility (Instance::look_copy: a material's look per kind of ray is a copy of
  //   its object on the same spot, shaders_map/ray_kinds.py; which copy the walk's ray meets
  //   is the BVH's choice, while the kind of that segment is known only once the walk
  //   scatters on);
  // - a light vertex's segment is checked once the scattering at its camera end is known
  //   (the walk's next direction, or a connection): the vertex before must be visible to
  //   that kind, else the walk ends there (a path the camera side does not have);
  // - a connection traces the kind of its camera vertex's scattering;
  // - the strategies that would need a light walk to make a segment with a surface of
  //   mixed visibility on it (or, toward a lamp that casts no shadows, any surface seen by
  //   rays after a scattering) cannot make the path: camera walks test each segment they
  //   make (one more ray: Scene::nearest_mixed) and mark the vertex they reach
  //   (PathVertex::light_cut), connections theirs (ConnectionDensities::light_cut), and the
  //   MIS weights leave those strategies out; so do the segments leaving a camera vertex on
  //   a look copy of mixed visibility (a light walk would have had to make a vertex there).
  // Every other segment a light walk makes, a camera walk can make too.
  Color Li(const CameraRay &camera_ray, Sampler &sampler, RayStats &stats, FirstHit *first_hit,
           std::vector<Splat> &splats) const override;

  // Each is compiled with and without participating media (kMedia): a scene without
  // media runs no medium code.
  // Subpath generation (subpaths.cpp). Return the number of vertices; camera subpaths
  // add what lamps and emissive media they pass give (s = 0 paths that end between two
  // vertices: lamps are transparent and not in the BVH, volume emission is gathered) to
  // emitted[n], n the vertex the segment leaves (the path has t = n + 2 vertices);
  // emitted has room for max_vertices (or max_bounces + 2) entries, zeroed by the caller.
  // max_vertices: at most this many (multiplexed MLT's one strategy); -1: as the
  // settings' max_bounces allow.
  // data: the sample's data passes (film/data_passes.h), gathered along the walk's
  // see-through chain; see_through_only: the walk ends where that chain does (the
  // Metropolis integrators' first-hit pass).
  // catcher_copy: the subpath of a sample's catcher-pass copy (shadow_catcher.cpp): a camera
  // subpath meets shadow catchers only from its split on; a light subpath starts only at a
  // light of the catcher pass and meets shadow catchers only.
  template <bool kMedia>
  int camera_subpath(const CameraRay &camera_ray, Sampler &sampler, RayStats &stats, PathVertex *path,
                     Color *emitted, int max_vertices = -1, DataPassSample *data = nullptr,
                     bool see_through_only = false, bool catcher_copy = false) const;
  template <bool kMedia>
  int light_subpath(Sampler &sampler, RayStats &stats, PathVertex *path, int max_vertices = -1,
                    bool catcher_copy = false) const;
  const BdptSettings &settings() const { return settings_; }
  // The first-hit AOVs of a camera subpath of n vertices (Depth, Normal, Albedo).
  FirstHit first_surface(const PathVertex *camera_path, int n) const;
  // What of a camera subpath of n vertices sees the transparent background (film_alpha.h).
  float transparency(const PathVertex *camera_path, int n) const;
  // One connection strategy (connect.cpp); raster receives the pixel for t == 1;
  // connection_dir (if given) the direction of the connection from its camera-side end
  // (t == 1: from the light vertex toward the lens).
  // catcher_copy: a strategy of a catcher-pass copy: its rays meet shadow catchers only past
  // the split, and only the catcher pass's lights shine; light tracing (t = 1) only from a
  // catcher, the camera ray to it checked against every object (the copy's prefix).
  template <bool kMedia>
  Color connect(PathVertex *light_path, PathVertex *camera_path, int s, int t, Sampler &sampler, RayStats &stats,
                Vec2 *raster, float *mis_weight_out, Vec3 *connection_dir = nullptr, bool catcher_copy = false) const;
  // Cycles' light passes (light_passes.cpp, film/light_passes.h): how many scattering
  // vertices the path of strategy (s, t) has and how its first one from the camera
  // splits by kind (connection_dir as connect gives it); the colour passes of a camera
  // subpath; the share of the world's background in what the camera sees at `v`.
  struct PassClass {
    int scatterings = 0;
    KindSplit first;
  };
  // The first scattering camera vertex's split toward the next camera vertex, the same
  // for every strategy that goes on past it: found once per camera subpath of n vertices.
  struct PassCache {
    int vertex = -1;
    KindSplit split;
  };
  // pass_cache, pass_class and add_light_pass run for every strategy of every sample:
  // inline (bdpt/pass_class.h, included where they are used), as out-of-line calls
  // their arguments and results went through memory and stalled.
  inline PassCache pass_cache(const PathVertex *camera_path, int n) const;
  inline PassClass pass_class(const PathVertex *light_path, const PathVertex *camera_path, int s, int t,
                              Vec3 connection_dir, const PassCache &cache) const;
  // The colour passes the camera walk gathered into data.
  static void add_color_passes(const DataPassSample &data, LightPassSample &passes);
  Color background_share(const PathVertex &v) const;
  // A contribution c of strategy (s, t >= 2), classified as pc, into a camera sample's
  // passes: the world seen directly goes to Environment by its background share.
  inline void add_light_pass(const PathVertex *camera_path, int s, int t, const PassClass &pc, Color c,
                             LightPassSample &passes) const;
  // A scattering vertex's split by kind between the directions toward the camera and the
  // light (delta: it scatters by a delta lobe; surfaces by their lobes' shares of f).
  static KindSplit split_at(const PathVertex &v, Vec3 toward_camera, Vec3 toward_light, bool delta);
  // Shadow catchers (shadow_catcher.cpp): the camera side of a sample's catcher values from
  // its camera subpath of n vertices: whether it split, the matte's transparency and the
  // world behind the catcher (film/shadow_catcher_passes.h); BDPT's samples and the
  // Metropolis integrators' first-hit rays (their see-through chain is all it reads).
  void camera_catcher_values(const PathVertex *camera_path, int n, CatcherSample &catcher) const;
  // The camera vertex where a camera subpath of n vertices splits (its see-through chain's
  // first catcher), -1 for none.
  int split_vertex(const PathVertex *camera_path, int n) const;
  // Multiplexed MLT's one strategy (s, t) of a sample's catcher-pass copy (catcher_pass's
  // term of that strategy), after the main strategy was evaluated with the same numbers:
  // its camera subpath (t vertices) split at `split` (-1: none) and its camera vertex are
  // in camera_path; the storage given is overwritten (emitted: `capacity` entries).
  // t == 1: light tracing, raster receives the pixel.
  template <bool kMedia>
  Color catcher_strategy(const CameraRay &camera_ray, Sampler &sampler, RayStats &stats, int s, int t, int split,
                         PathVertex *camera_path, PathVertex *light_path, Color *emitted, size_t capacity,
                         Vec2 *raster) const;

 private:
  // One camera sample; kCatcher: in a scene with a shadow catcher whose sums the film keeps
  // (first_hit->catcher): the sample's Combined, its matte, and its catcher-pass copy
  // (shadow_catcher.cpp). Compiled apart, so scenes without a catcher run none of that code.
  template <bool kMedia, bool kCatcher>
  Color li(const CameraRay &camera_ray, Sampler &sampler, RayStats &stats, FirstHit *first_hit,
           std::vector<Splat> &splats) const;
  // Shadow catchers (shadow_catcher.cpp): a sample's copy,
  // in the subpath storage given (emitted: `capacity` entries): its light tracing into
  // `splats` (every sample) and, when the sample split at camera vertex `split`, the
  // catcher pass of its camera subpath traced again (returned); the world seen along dir by
  // a ray of the kinds in mask (Cycles' background pass).
  // camera_catcher_values with the split known (split_vertex's).
  void camera_catcher_values(const PathVertex *camera_path, int n, int split, CatcherSample &catcher) const;
  template <bool kMedia>
  Color catcher_pass(const CameraRay &camera_ray, Sampler &sampler, RayStats &stats, int split,
                     PathVertex *camera_path, PathVertex *light_path, Color *emitted, size_t capacity,
                     std::vector<Splat> &splats) const;
  Color background_along(Vec3 dir, uint32_t mask) const;
  // cone: the ray's footprint (camera paths), for filtered texture lookups.
  // catcher_copy: as camera_subpath's and light_subpath's.
  template <bool kMedia>
  int random_walk(Ray ray, Sampler &sampler, RayStats &stats, Color beta, float pdf, int max_vertices,
                  TransportMode mode, PathVertex *path, Color *emitted, RayCone cone = {},
                  DataPassSample *data = nullptr, bool see_through_only = false, bool catcher_copy = false) const;
  // catcher_only: the walk of a catcher copy past its split (its shadow rays meet catchers only).
  // layers: the plain layers the walk passed since path[n]. light_cut: no light walk makes
  // the segment to the lamp point (PathVertex::light_cut); cut_from: nor to the gathered
  // points this far along the ray or further.
  Color lamp_emission(int lamp, Vec3 q, Vec3 wo, Color Le, Color beta, PathVertex *path, int n, int layers,
                      float pdf_dir, bool light_cut, RayStats &stats, bool catcher_only) const;
  void gather_volume_emission(const Medium &medium, const Ray &ray, float tmax, SampleRun &rng, Color beta,
                              PathVertex *path, int n, int layers, float pdf_dir, float cut_from,
                              Color &emitted) const;
  // Densities (mis.cpp), area measure at the receiving vertex.
  // nee_pdf: next-event estimation's solid-angle density of the light vertex from v where
  // the caller sampled it so (s = 1), else < 0 (found afresh where it matters).
  void light_densities(const PathVertex &light_vertex, const PathVertex &v, float &origin, float &toward,
                       float nee_pdf = -1) const;
  void split_next_event_density(const Light &lamp, const PathVertex &light_vertex, Vec3 v, float &origin,
                                float &toward, float nee_pdf = -1) const;
  float infinite_light_density(Vec3 dir) const;
  bool light_start_is_delta(const PathVertex &light_vertex) const;
  float lafortune_willems_weight(const PathVertex *light_path, const PathVertex *camera_path,
                                 const PathVertex &light_start, int s, int t) const;
  float light_tracing_share(const PathVertex *light_path, int s) const;
  bool balance() const { return settings_.mis == MisHeuristic::Balance; }
  float mis_weight(const PathVertex *light_path, const PathVertex *camera_path, const PathVertex &sampled, int s,
                   int t, const ConnectionDensities &densities) const;
  // Cycles' Light Paths (light_path_limits.cpp): the kind of v's scattering toward wi;
  // Cycles' odds that it sampled a glossy closure there (Bsdf::glossy_odds; camera: v is
  // on the camera side's subpath); recording a walk's vertex v = path[n] once its next
  // direction wi is chosen (delta: by a delta lobe; returns false when no longer subpath
  // can make a path the limits keep); the share of the path of strategy (s, t) the limits
  // keep, given the connection vertices' kinds toward each other (kc: camera_path[t - 1]'s,
  // kl: light_path[s - 1]'s; unused where there is none) and the direction from the
  // camera side's connection vertex to the light side's (or to the lens from
  // light_path[s - 1], negated, for t = 1).
  ScatterKind kind_toward(const PathVertex &v, Vec3 wi) const;
  float glossy_odds_toward(const PathVertex &v, Vec3 w, bool camera, bool delta, bool defensive) const;
  CausticStep caustic_step_toward(const PathVertex &v, Vec3 w, bool camera, bool delta, ScatterKind kind,
                                  float glossy_odds, bool after_diffuse = true) const;
  bool record_kind(PathVertex *path, int n, Vec3 wi, bool camera, bool delta) const;
  // The straight passes of the path of strategy (s, t) on its two subpaths (Transparent
  // max bounces; a connection adds those it passes) and its scattering vertices (the clamps).
  static int path_passes(const PathVertex *light_path, const PathVertex *camera_path, int s, int t);
  static int path_scatterings(const PathVertex *light_path, const PathVertex *camera_path, int s, int t);
  Color limits_share(const PathVertex *light_path, const PathVertex *camera_path, int s, int t, ScatterKind kc,
                     ScatterKind kl, Vec3 to_light = Vec3(0.0f)) const;
  // Vertex helpers (connect.cpp).
  // bsdf: the BSDF to use at a surface instead of v's (Filter Glossy's blurred one).
  Scattering scatter(const PathVertex &v, Vec3 wi, TransportMode mode, const Bsdf *bsdf = nullptr) const;
  // Filter Glossy (filter_glossy.h): whether the blur leaves the light walk's vertices
  // light_path[s - 2] .. light_path[1] unchanged, given the smallest camera-side density of
  // the path up to light_path[s - 2] (its scatterings at the camera vertices and at
  // light_path[s - 1] toward light_path[s - 2]).
  bool light_walk_unblurred(const PathVertex *light_path, int s, float min_pdf) const;
  // Scenes with mixed visibility: the last segment of the path is tested against what
  // casts each light's shadows (integrators/visibility_clear.h), counting rays in stats.
  // catcher_only: a catcher copy's (only the catcher pass's lights; shadow rays meet catchers only).
  // scatterings: the path's scattering vertices, for the lights' Max Bounces (-1: none checked).
  Color Le(const PathVertex &v, const PathVertex &toward, RayStats &stats, bool catcher_only = false,
           int scatterings = -1) const;
  // Ray visibility: whether the light a light subpath of s >= 2 vertices starts at is
  // visible to the kind of scattering at light_path[1], whose next direction is `wi`
  // when s == 2 (else toward light_path[2]); with mixed visibility, also whether
  // light_path[s - 2] is visible to the kind of scattering at light_path[s - 1] toward wi
  // (the walk checked the segments before: light_walk_seen).
  bool light_start_visible(const PathVertex *light_path, int s, Vec3 wi) const;
  // A camera vertex no light walk makes (on a look copy of mixed visibility): a connection
  // there cannot be a light walk's segment.
  bool ends_light_walks(const PathVertex &pt) const { return mixed_ && pt.look_copy; }
  // Mixed visibility: whether the light walk's vertices before light_path[last] (back to its
  // scattering before, past the vertices it passed through; not the light) are visible to
  // the kind of light_path[last]'s scattering toward wi (its camera side).
  bool light_walk_seen(const PathVertex *light_path, int last, Vec3 wi) const;
  // Visibility (0 or 1) or, with media, transmittance from a to b, its estimators
  // drawing at `position` of `stream` (the connection's own dimensions), through up to
  // `layers` plain layers (Scene::is_plain_layer), which the walks do not make vertices.
  // mask: the kinds of ray the connection stands for (scene/ray_visibility.h).
  template <bool kMedia>
  Color transmittance(const PathVertex &a, const PathVertex &b, Sampler &sampler, SampleStream stream,
                      uint32_t position, RayStats &stats, uint32_t mask, int layers) const;

  const Scene &scene_;
  BdptSettings settings_;
  bool mixed_ = false;  // Scene::has_mixed_visibility
  bool catchers_ = false;  // the scene has a shadow catcher: walks mark its vertices (PathVertex::catcher)
};

}  // namespace rdv::bdpt
