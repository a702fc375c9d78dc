// The BSDF at a surface point: a small fixed set of lobes, each a plain struct,
// dispatched with a switch (no allocation, no virtual calls in the hot loop).
// Each lobe has eval / sample / pdf in the local shading frame; the Bsdf adds the
// frame change, lobe selection and the transport-mode rules BDPT needs:
//  - Radiance mode (camera paths) and Importance mode (light paths) differ by the
//    shading-normal correction (Veach 1997, eq. 5.17) and, for refraction, by the
//    1 / eta^2 that Importance mode carries (bsdfs/dielectric.cpp says why).
#pragma once
#include <array>
#include <type_traits>
#include "bsdfs/fresnel.h"
#include "bsdfs/ggx_albedo.h"
#include "bsdfs/microfacet.h"
#include "bsdfs/scatter_kind.h"
#include "bsdfs/view_factor.h"
#include "core/math.h"
#include "film/denoising_passes.h"
#include "film/light_passes.h"

namespace rdv {

enum class TransportMode { Radiance, Importance };

enum class LobeType : uint8_t {
  Lambert,            // f = color / pi                                    (diffuse.cpp)
  GgxConductor,       // GGX reflection, Fresnel tint / complex IOR / Schlick (conductor.cpp)
  SpecularConductor,  // perfect mirror (GGX below Cycles' smoothness limit)  (conductor.cpp)
  SmoothDielectric,   // delta reflection + refraction, Fresnel-weighted      (dielectric.cpp)
  GgxDielectric,      // rough GGX reflection + refraction (Walter 2007)      (dielectric.cpp)
  OrenNayar,          // Cycles' (Fujii's) Oren-Nayar, sigma = roughness      (oren_nayar.cpp)
  Transparent,        // straight pass-through (Transparent BSDF, alpha)     (transparent.cpp)
  Translucent,        // Lambertian transmission                            (translucent.cpp)
  Sheen,              // Cycles 3.4 Principled sheen: (1 - |wi.h|)^5          (sheen.cpp)
  PrincipledDiffuse,  // Cycles 3.4 Principled diffuse (Disney), roughness in sigma (principled_diffuse.cpp)
  Clearcoat           // Cycles 3.4 Principled clearcoat: GTR1, alpha in ggx.ax  (clearcoat.cpp)
};

// How a microfacet reflection lobe colours its Fresnel term.
enum class FresnelMode : uint8_t {
  Tint,       // F = color (Glossy BSDF)
  Conductor,  // F = color * conductor Fresnel from complex IOR eta + i k
  Schlick,    // F = color * (f0 + (1 - f0) (1 - cos)^5) (Principled specular, clearcoat)
  Dielectric,  // F = color * dielectric Fresnel of the real IOR `ior`
  // F = color * (f0 + (1 - f0) FH), FH the dielectric Fresnel of `ior` taken from its normal-
  // incidence value (0) to 1: Cycles 3.4's Principled specular (interpolate_fresnel_color).
  Interpolated
};

// A reflecting layer above some lobes (Principled specular, sheen, clearcoat). A lobe
// below it is scaled by (1 - A(wo)) (1 - A(wi)) / (1 - A_avg), with A the layer's
// directional albedo: reciprocal, and a Lambertian base under it then reflects exactly
// base x (1 - A(wo)), so layer + base never exceed 1 (layering.cpp). Made by
// schlick_ggx_layer() / sheen_layer() (layering.h), which precompute everything that
// does not depend on a direction. A Bsdf holds its layers once; each lobe names the
// ones above it (Lobe::layers_above), so lobes under the same layer share its albedo.
struct LayerAbove {
  enum Kind : uint8_t { SchlickGgx, Sheen } kind = SchlickGgx;
  Color f0{0.04f};        // SchlickGgx: Fresnel at normal incidence
  Color ms{0.0f};         // SchlickGgx with multiscatter: Kulla-Conty's F_ms (else 0)
  Color weight{1.0f};     // the layer lobe's colour (closure weight x tint)
  GgxAlbedoRows rows;     // SchlickGgx: the GGX albedo tables at the layer's alpha
  Color norm{1.0f};       // 1 / (1 - A_avg)
  // Memo (per Bsdf, per thread): the layer's albedo at the last |cos| asked for, which
  // is wo's for most calls.
  mutable float memo_mu = -1;
  mutable Color memo_albedo{0.0f};
};

struct Lobe {
  LobeType type = LobeType::Lambert;
  FresnelMode fresnel_mode = FresnelMode::Tint;
  bool multiscatter = false;  // GgxConductor: Kulla-Conty energy compensation (Multiscatter GGX)
  Color color{1.0f};          // tint / albedo / closure weight
  GgxDistribution ggx{1, 1};
  Color eta{1.0f}, k{0.0f};   // conductor complex IOR
  Color f0{0.04f};            // Schlick reflectance at normal incidence
  // Dielectrics: IOR of the side below the local frame (z < 0) relative to the side
  // above (where wo is). The Bsdf inverts it when the ray arrives from the back face.
  float ior = 1.5f;
  float sigma = 0;            // Oren-Nayar roughness in [0, 1]
  bool refraction_only = false;  // dielectrics: Cycles' Refraction BSDF (no reflection, no Fresnel)
  // Rough dielectrics as Cycles 3.4's Glass BSDF: reflection and refraction weighted by the
  // Fresnel at the shading normal (dielectric.cpp), not per facet. With it, refraction_only
  // and reflection_only are its two parts alone (Cycles 3.4's Principled glass: a roughness each).
  bool macro_fresnel = false;
  bool reflection_only = false;
  // Closure weight (Mix Shader factors, Principled layer weights): multiplies f. Kept
  // apart from `color`, which multiscatter compensation compounds like a Fresnel tint.
  float scale = 1.0f;
  // The Bsdf's layers above this lobe (energy-conserving Principled), one bit each.
  uint16_t layers_above = 0;
  // The Bsdf's view factors (Mix Shaders by a Fresnel / Layer Weight node) this lobe is
  // weighted by, one bit each, and of those the ones it takes as 1 - factor (the mix's
  // first shader): f is multiplied by them at the pair's camera-side direction.
  uint8_t view_factors = 0, view_inverted = 0;

  Color fresnel(float cos_i) const {
    switch (fresnel_mode) {
      case FresnelMode::Tint: return color;
      case FresnelMode::Conductor: return color * fresnel_conductor(cos_i, eta, k);
      case FresnelMode::Schlick: {
        float m = clampf(1.0f - cos_i, 0.0f, 1.0f), m2 = m * m;
        return color * (f0 + (Color(1.0f) - f0) * (m2 * m2 * m));
      }
      case FresnelMode::Dielectric: return color * fresnel_dielectric(cos_i, ior);
      case FresnelMode::Interpolated: {
        const float a = (ior - 1) / (ior + 1), r0 = a * a;  // fresnel_dielectric(1, ior), in closed form
        const float fh = r0 < 1 ? (fresnel_dielectric(cos_i, ior) - r0) / (1 - r0) : 0.0f;
        return color * (f0 + (Color(1.0f) - f0) * fh);
      }
    }
    return color;
  }
  bool is_delta() const {
    return type == LobeType::SpecularConductor || type == LobeType::SmoothDielectric ||
           type == LobeType::Transparent;
  }
  // Cycles' diffuse closures (CLOSURE_IS_BSDF_DIFFUSE): those bump shadowing darkens.
  bool is_diffuse_like() const {
    return type == LobeType::Lambert || type == LobeType::OrenNayar || type == LobeType::PrincipledDiffuse ||
           type == LobeType::Sheen || type == LobeType::Translucent;
  }
  // Scatters to the other side of the surface (needs the refraction rules of the Bsdf).
  bool is_transmissive() const {
    return type == LobeType::SmoothDielectric || type == LobeType::GgxDielectric ||
           type == LobeType::Transparent || type == LobeType::Translucent;
  }
  bool is_dielectric() const { return type == LobeType::SmoothDielectric || type == LobeType::GgxDielectric; }
};

struct BsdfSample {
  Vec3 wi;            // world space
  Color weight;       // f * |cos| / pdf, including the transport-mode correction
  float pdf = 0;      // solid angle; for delta lobes the discrete selection probability
  // Bsdf::glossy_odds of (wo, wi) when sample() was asked for them (camera paths under
  // bounce limits: from the pass over the lobes that weighs a mixture), else -1.
  float glossy_odds = -1;
  bool is_delta = false;
  // A straight pass-through (Transparent BSDF, alpha): not a scattering event. The
  // path tracer keeps its MIS state across it, as transparent shadows see through it.
  bool pass_through = false;
  // How much wider the ray's footprint cone gets per unit distance after this
  // scattering (the sampled lobe's angular width; 0 for delta lobes; core/ray_cone.h).
  float cone_spread = 0;
  // A refraction by a dielectric lobe: its alpha_x * alpha_y (0 when smooth), else -1
  // (Cycles' transparent glass, integrators/film_alpha.h).
  float refraction_alpha2 = -1;
};

class Bsdf {
 public:
  // Room for what shading builds at one point: a Principled BSDF makes up to 6 lobes
  // and 3 layers, so a Mix of two full ones (12, 6) fits with room for 4 more closures
  // (or three Principled BSDFs without transmission and alpha: 12 lobes, 9 layers).
  // Beyond that lobes of one kind are merged (lobe_merge.h) and the material warns.
  static constexpr int kMaxLobes = 16;
  static constexpr int kMaxLayers = 12;  // bits of Lobe::layers_above
  static constexpr int kMaxViewFactors = 4;  // bits of Lobe::view_factors

  // User-provided, so `Bsdf{}` / `PathVertex{}` do not zero the 2 KB of lobe storage.
  Bsdf() {}
  // Copies move only the lobes in use: path vertices and make_bsdf's return value copy
  // Bsdfs on every bounce, and a plain diffuse one uses 1 of kMaxLobes.
  Bsdf(const Bsdf &o) { copy_from(o); }
  Bsdf &operator=(const Bsdf &o) {
    if (this != &o) copy_from(o);
    return *this;
  }
  // ng: geometric normal, ns: shading normal (both unit); wo: direction to the viewer
  // (for light paths, to the previous vertex). Two-sided: the frame is flipped to
  // wo's side of the geometry.
  // ng must point to the FRONT of the surface (the outside of a closed dielectric):
  // a ray arriving from the back face sees the inverse IOR.
  Bsdf(Vec3 ng, Vec3 ns, Vec3 wo);
  // With a tangent (anisotropy direction; zero = any): the frame's x axis follows it.
  Bsdf(Vec3 ng, Vec3 ns, Vec3 wo, Vec3 tangent);
  // ns is a normal map's (or bump's): bent for each direction that sees it as Cycles bends
  // it toward the viewer, just enough that the viewer's mirror direction stays above the
  // surface (shading_normal.h). Per direction, by frame_toward's rule, so light paths see
  // the surface as the camera paths that meet them do. mesh_normal: the normal before the
  // map (for Cycles' bump shadowing of diffuse lobes, bump_shadowing).
  void bend_for_each_viewer(Vec3 mesh_normal);

  // Past kMaxLobes the lobe is merged with one of its kind (lobe_merge.h).
  void add_lobe(const Lobe &lobe, float sample_weight);
  // Adds a layer; returns its bit for Lobe::layers_above (past kMaxLayers: the bit of
  // the existing layer most like it).
  uint16_t add_layer(const LayerAbove &layer);
  // Adds a view factor; returns its bit for Lobe::view_factors. n: the interpolated normal
  // the factors see (Cycles' N, before any normal map). A material holds at most
  // kMaxViewFactors (two Mix Shaders by one node are two: a lobe under both takes it twice).
  uint8_t add_view_factor(const ViewFactor &factor, Vec3 n);
  int num_lobes() const { return n_; }
  bool is_delta() const;  // every lobe is delta: no point connecting to lights
  bool has_lobes() const { return n_ > 0; }
  bool has_transmission() const;
  bool backfacing() const { return backfacing_; }

  Color eval(Vec3 wo, Vec3 wi, TransportMode mode) const;  // f * |cos(wi, ns)|
  // The BSDF value alone, without the cosine (BDPT's connections put the cosines
  // into their geometry term), including the importance-mode correction.
  Color f(Vec3 wo, Vec3 wi, TransportMode mode) const;
  float pdf(Vec3 wo, Vec3 wi) const;
  // eval() and pdf() with one frame change and one pass over the lobes (next-event
  // estimation, the weight of a sampled mixture).
  Color eval_and_pdf(Vec3 wo, Vec3 wi, TransportMode mode, float &pdf) const;
  // f(wo, wi) as f() and, with one frame change, pdf(wo, wi) and pdf(wi, wo): what a
  // BDPT connection needs at each end (its value and its MIS densities both ways).
  // The densities are left 0 where f is 0 (the connection contributes nothing).
  Color f_and_pdfs(Vec3 wo, Vec3 wi, TransportMode mode, float &pdf_fwd, float &pdf_rev) const;
  // odds (Radiance mode): also out.glossy_odds, as glossy_odds(wo, out.wi, ...) gives them
  // (defensive as there), at no second pass over the lobes.
  enum class Odds { None, Plain, Defensive };
  bool sample(Vec3 wo, float u_lobe, Vec2 u, TransportMode mode, BsdfSample &out, Odds odds = Odds::None) const;
  // The delta lobes' events (mirror reflection, smooth reflection and refraction, pass-
  // through) that send wo to wi, up to an angle of about 4e-3 (vertices rounded to
  // floats): f * |cos(wi)| summed over them as the coefficient of a Dirac delta in solid
  // angle about wi (what sample() gives as weight x pdf), their summed selection
  // probability (sample()'s pdf) in pdf, and in jacobian d omega_wi / d omega_wo of the
  // event (cos_o / (eta^2 cos_i) for a refraction, else 1), which converts a delta about
  // wi into one about wo (path-space MLT samples specular vertices from either side).
  // Black with pdf 0 where no delta event sends wo to wi.
  Color delta_eval(Vec3 wo, Vec3 wi, TransportMode mode, float &pdf, float &jacobian) const;
  // Directional albedo-like colour for the Diffuse Color AOV, seen from wo.
  Color albedo(Vec3 wo) const;
  // Lafortune & Willems' "degree of specularity" in [0, 1] (BDPT's "lafortune_willems"
  // weights): 1 if any lobe is delta, else the lobes' selection weights times 1 - roughness
  // for GGX lobes and 0 for diffuse ones.
  float specularity() const;
  // Cycles' label of the scattering from wo to wi (per-kind bounce limits, caustics):
  // reflection or transmission by the sides of the geometric normal; then the lobes of
  // that side with the larger total selection weight decide (diffuse or glossy
  // reflection; translucent, refracting or transparent transmission). Exact for BSDFs of
  // one kind; a mixture counts as its dominant kind (the caustics switches; bounce limits
  // weigh a diffuse-and-glossy reflection by glossy_odds).
  ScatterKind scatter_kind(Vec3 wo, Vec3 wi) const;
  // Cycles counts a bounce as diffuse or glossy by the closure it sampled there. For a
  // reflection from camera_side to light_side off a mixture of both kinds, the odds that
  // this was a glossy closure given the direction: each closure's share of the density
  // of sampling light_side, with Cycles 3.4's selection weights (a closure's albedo seen
  // from camera_side: Fresnel-weighted for Principled specular and clearcoat) and, at a
  // camera path's first scattering (defensive), its floor of 1/8 of their sum. 0 or 1
  // where the reflecting lobes are of one kind, or where a delta lobe reflected; -1 for
  // a transmission. (Bounce limits, integrators/light_path_limits.h.)
  float glossy_odds(Vec3 camera_side, Vec3 light_side, bool delta, bool defensive) const;
  // Cycles' light passes (film/light_passes.h), camera side: the share of each kind in f
  // from wo to wi (delta: the sampled lobe was delta, so the side decides: glossy
  // reflection or transmission), and the colour passes' closure colours seen from wo
  // (diffuse, glossy, transmission; a dielectric's colour split by its Fresnel at wo,
  // as Cycles 3.4's Glass BSDF weights its reflection and refraction closures).
  KindSplit kind_split(Vec3 wo, Vec3 wi, bool delta) const;
  // Cycles' caustics switches (integrators/caustics_switches.h): the share of f from
  // camera_side to light_side, per colour channel, that is left after a diffuse bounce, where
  // the glossy reflection closures (keep_glossy false) or the refracting ones (keep_refraction
  // false) are gone; by the same kinds as kind_split (delta: the side's kind).
  Color caustic_share(Vec3 camera_side, Vec3 light_side, bool delta, bool keep_glossy, bool keep_refraction) const;
  // The probability that sample() from wo passes straight through (its Transparent lobes'
  // selection): BDPT's walks keep a plain transparent layer as a vertex only otherwise.
  float pass_probability(Vec3 wo) const;
  // sample()'s lobe choice conditioned on not passing straight through: u uniform in [0, 1)
  // mapped onto the part of sample()'s u_lobe that picks the other lobes (each keeps its own
  // remainder for the choices inside it). Path-space MLT's walks, which decide a plain
  // layer's pass before its scattering (integrators/mlt/path_space.cpp).
  float scattering_lobe_u(Vec3 wo, float u) const;
  // Whether wo -> wi is a straight pass through a Transparent lobe (no scattering for the
  // light passes), for paths that know only their directions (path-space MLT).
  bool passes_straight_through(Vec3 wo, Vec3 wi) const;
  // Of the density of sampling wi (the non-delta lobes' mixture), the share that dielectric
  // lobes refracting toward it with alpha_x alpha_y <= alpha2_max carry: how often a camera
  // path that samples wi keeps seeing through with Transparent Glass (integrators/film_alpha.h
  // decides by the lobe sampled). 0 where wi is not a refraction.
  float share_refracted_below(Vec3 wo, Vec3 wi, float alpha2_max) const;
  // Cycles' Filter Glossy (integrators/filter_glossy.h): every microfacet lobe made at
  // least `alpha` rough (alpha_x, alpha_y); perfect mirrors and smooth glass become GGX
  // lobes of that roughness, as Cycles renders Sharp closures as GGX with the filter on.
  void blur(float alpha);
  // Whether blur(alpha) changes this BSDF: alpha is rough enough to act and some lobe is a
  // perfect mirror, smooth glass or a GGX lobe smoother than alpha in some direction.
  bool blur_changes(float alpha) const { return blur_acts(alpha) && alpha > blur_threshold(); }
  // The roughness above which blur() changes some lobe (-1: a sharp lobe, which any acting
  // blur changes; infinite: no microfacet lobe), and whether alpha acts at all.
  float blur_threshold() const;
  static bool blur_acts(float alpha) { return !GgxDistribution{alpha, alpha}.is_smooth(); }
  void kind_colors(Vec3 wo, Color out[kColorKinds]) const;
  // Cycles' denoising features (film/denoising_passes.h) seen from wo: each lobe's closure
  // albedo (a dielectric's reflection and refraction together, a Fresnel-coloured
  // reflection times its Fresnel at wo), rough (alpha_x alpha_y > 0.075^2, or diffuse-like)
  // or near-specular, and its selection weight.
  DenoisingClosures denoising_closures(Vec3 wo) const;
  // The shading normal a scattering whose camera-side direction is w sees (a normal map's,
  // or the geometric normal past the terminator): the cosine that goes with f there.
  Vec3 shading_normal(Vec3 w) const {
    Frame bent;
    return frame_toward(w, bent).n;
  }
  Vec3 geometric_normal() const { return ng_; }
  // Whether a and b see the same shading frame (frame_toward). Where they do not, a delta
  // lobe sampled from one (light walks sample from the light side) does not reach the other's
  // event: BDPT's strategies whose light walk would scatter there cannot make the path.
  bool same_frame_both_ways(Vec3 a, Vec3 b) const {
    if (!smooth_) return true;
    Frame bent_a, bent_b;
    return same_frame(frame_toward(a, bent_a), frame_toward(b, bent_b));
  }

 private:
  // The shading frame a Bsdf built toward w would have: the shading normal's, or the
  // geometric normal's where the shading normal faces away from w (the "shadow
  // terminator" fallback). Evaluations pick it by the pair's camera-side direction
  // (Radiance: wo; Importance: wi) and sampling and densities by the direction sampled
  // from, so f of a pair does not depend on the direction the Bsdf was built toward: a
  // light path sees a smooth-shaded surface as the camera path that meets it does (BDPT's
  // light tracing at silhouettes). Built toward wo, a camera path's evaluations are as they were.
  // A mapped normal (bend_) is first bent for w (bent_frame), into scratch when it moves.
  const Frame &frame_toward(Vec3 w, Frame &scratch) const {
    if (!smooth_) return frame_;
    const float side = dot(w, ng_) < 0 ? -1.0f : 1.0f;
    if (bend_) return bent_frame(w, side, scratch);
    return side * dot(w, frame_.n) > kTerminatorCos ? frame_ : flat_;
  }
  const Frame &bent_frame(Vec3 w, float side, Frame &scratch) const;
  const Frame &camera_side_frame(Vec3 wo, Vec3 wi, TransportMode mode, Frame &scratch) const {
    return frame_toward(mode == TransportMode::Radiance ? wo : wi, scratch);
  }
  // Two frames from frame_toward are the same one (the same normal and tangent).
  static bool same_frame(const Frame &a, const Frame &b) {
    return &a == &b || (a.n.x == b.n.x && a.n.y == b.n.y && a.n.z == b.n.z && a.s.x == b.s.x && a.s.y == b.s.y &&
                        a.s.z == b.s.z);
  }
  static constexpr float kTerminatorCos = 1e-4f;
  // The selection probability of the Transparent lobes (pass_probability, scattering_lobe_u)
  // among the picks of sampling from some direction (picks_from).
  float transparent_pick(const float *pick) const;
  float shading_correction(Vec3 wo, Vec3 wi, TransportMode mode, const Frame &frame) const;
  void copy_from(const Bsdf &o) {
    frame_ = o.frame_;
    flat_ = o.flat_;
    smooth_ = o.smooth_;
    bend_ = o.bend_;
    mesh_normal_ = o.mesh_normal_;
    oriented_ = o.oriented_;
    ng_ = o.ng_;
    backfacing_ = o.backfacing_;
    lambert_ = o.lambert_;
    n_ = o.n_;
    for (int i = 0; i < n_; ++i) {
      new (&lobes_[i]) Lobe(o.lobes_[i]);
      raw_weight_[i] = o.raw_weight_[i];
      pick_[i] = o.pick_[i];
    }
    num_layers_ = o.num_layers_;
    for (int i = 0; i < num_layers_; ++i) new (&layers_[i]) LayerAbove(o.layers_[i]);
    num_views_ = o.num_views_;
    if (num_views_) view_normal_ = o.view_normal_;
    for (int i = 0; i < num_views_; ++i) new (&views_[i]) ViewFactor(o.views_[i]);
  }
  // What the layers above a lobe scale it by, for one (wo, wi) pair (local frame).
  struct LayerScales {
    Color of_layer[kMaxLayers];
    Color of(uint16_t layers_above) const {
      Color k(1.0f);
      for (int j = 0; layers_above; ++j, layers_above >>= 1)
        if (layers_above & 1) k *= of_layer[j];
      return k;
    }
  };
  void layer_scales(Vec3 wo, Vec3 wi, LayerScales &out) const;
  // What the view factors scale the lobes by for one camera-side direction (view_factor.h).
  struct ViewScales {
    float of_view[kMaxViewFactors];
    float of(const Lobe &l) const {
      float s = 1;
      for (int j = 0; j < kMaxViewFactors; ++j)
        if (l.view_factors >> j & 1) s *= (l.view_inverted >> j & 1) ? 1 - of_view[j] : of_view[j];
      return s;
    }
  };
  // The scales at camera-side direction w into scratch, or nullptr without view factors.
  const ViewScales *view_scales(Vec3 w, ViewScales &scratch) const;
  // The lobe selection probabilities of sampling from w: pick_, or with view factors half
  // pick_ and half the raw weights times the factors at w, so the lobes a view favours are
  // sampled more and none is left out (its f may be > 0 where a light path's camera side
  // differs). A function of w alone, as BDPT's densities must be.
  using Picks = std::array<float, kMaxLobes>;
  // scales_at_w: the view scales at w when the caller has them (else computed here).
  const float *picks_from(Vec3 w, Picks &scratch, const ViewScales *scales_at_w = nullptr) const;
  // The lobes' f summed for a local pair (seen from the side local_pair found), with the
  // layers and view factors (views, may be nullptr) applied; with pdf, their mixture density
  // by `pick` added into *pdf as well.
  // diffuse_scale: what the diffuse-like lobes' f is multiplied by (bump_shadowing).
  // glossy: with pdf, each lobe's density weighted by glossy->weight summed into all and,
  // for glossy lobes, into glossy (glossy_odds' two sums).
  struct GlossyShare {
    std::array<float, kMaxLobes> weight;
    float glossy = 0, all = 0;
    float odds() const { return all > 0 ? clampf(glossy / all, 0.0f, 1.0f) : 0.0f; }
  };
  Color local_f(Vec3 wo, Vec3 wi, bool flipped, TransportMode mode, float *pdf, const float *pick,
                float diffuse_scale, const ViewScales *views, GlossyShare *glossy = nullptr) const;
  // glossy_odds' parts: 1 or 0 where one kind decides (delta: a mirror's or glass's; no
  // diffuse lobe; no glossy lobe), -1 for a mixture; Cycles' selection weight of each lobe
  // seen from the camera side (cos_o: its local cosine; views: its view scales).
  float one_kind_odds(bool delta) const;
  // f from wo to wi by light-pass kind (diffuse, glossy, transmission) over the non-delta
  // lobes: that kind where they are all of one kind on that side (nothing evaluated),
  // kSplitKinds with parts filled where they are not, -1 where no lobe scatters so.
  static constexpr int kSplitKinds = 3;
  int kind_parts(Vec3 wo, Vec3 wi, Color parts[kSplitKinds]) const;
  int whole_kind(Vec3 wo, Vec3 wi, bool delta) const;
  void odds_weights(float cos_o, const ViewScales *views, bool defensive, float *weight) const;
  // eval_and_pdf with the glossy odds of (wo, wi) too, for a sampled mixture (Radiance).
  Color eval_pdf_and_odds(Vec3 wo, Vec3 wi, float &pdf, bool defensive, float &glossy_odds) const;
  // Cycles darkens diffuse closures whose normal a normal map or bump moved (its
  // bump_shadowing_term, after Chiang et al. 2019): by a smooth step of g = cos(N0, I) /
  // (cos(N, I) cos(N0, N)), N0 the mesh's normal, N the mapped one (n, as the frame f uses),
  // I the light side's direction (wi on camera paths, wo on light paths). 1 unmapped.
  float bump_shadowing(Vec3 n, Vec3 wo_w, Vec3 wi_w, TransportMode mode) const;
  bool local_pair(const Frame &frame, Vec3 wo_w, Vec3 wi_w, Vec3 &wo, Vec3 &wi, bool &flipped) const;
  // One plain Lambert lobe (lambert_): f and its densities depend only on the cosines
  // with the two normals, so evaluation skips the frame change and the lobe loop.
  // wo, wi: with the shading normal; g_wo, g_wi: with the geometric normal.
  struct LambertCosines {
    float wo, wi, g_wo, g_wi;
  };
  // False where f is 0 (where the general code gives 0 too). n: the shading normal.
  bool lambert_cosines(Vec3 n, Vec3 wo_w, Vec3 wi_w, LambertCosines &c) const;
  Color lambert_f(const LambertCosines &c, TransportMode mode) const;
  // The Bsdf's whole f, densities (pdf of sampling wi from wo, and the reverse) with the
  // frames frame_toward gives when they differ (a pair across the terminator fallback, or
  // a mapped normal bent for one of them).
  Color f_in(const Frame &frame, Vec3 wo_w, Vec3 wi_w, TransportMode mode) const;
  float pdf_in(const Frame &frame, Vec3 wo_w, Vec3 wi_w) const;
  Frame frame_;  // the shading normal's (and tangent's)
  Frame flat_;   // the geometric normal's (the tangent projected onto it)
  bool smooth_ = false;      // the two differ
  bool bend_ = false;         // frame_ is a mapped normal's, bent per direction (bend_for_each_viewer)
  Vec3 mesh_normal_{0.0f};    // with bend_: the normal before the map, on ng_'s side
  bool oriented_ = false;     // frame_'s tangent is anisotropy's axis
  Vec3 ng_;
  bool backfacing_ = false;
  bool lambert_ = false;
  int n_ = 0;
  // Raw storage: only the lobes and layers that are added get written (a Bsdf is built
  // per hit; constructing all kMaxLobes defaults cost more than shading a diffuse surface).
  template <class T, int N>
  struct RawArray {
    static_assert(std::is_trivially_copyable_v<T> && std::is_trivially_destructible_v<T>);
    alignas(T) unsigned char raw[N * sizeof(T)];
    T &operator[](int i) { return reinterpret_cast<T *>(raw)[i]; }
    const T &operator[](int i) const { return reinterpret_cast<const T *>(raw)[i]; }
  };
  RawArray<Lobe, kMaxLobes> lobes_;
  int num_layers_ = 0;
  RawArray<LayerAbove, kMaxLayers> layers_;
  int num_views_ = 0;
  RawArray<ViewFactor, kMaxViewFactors> views_;
  Vec3 view_normal_;  // with view factors: the normal they see, toward the front face
  // Entries [0, n_) are valid, as in lobes_.
  std::array<float, kMaxLobes> raw_weight_;  // as given to add_lobe
  // Normalised lobe selection probabilities (raw_weight_, in which view factors are left
  // out: picks_from adds them per direction). scatter_kind and specularity weigh lobes by
  // them too: a function of the hit alone. A Transparent lobe is never under a view factor
  // (material.cpp), but the others' may make its pick depend on the direction sampled from.
  std::array<float, kMaxLobes> pick_;
};

// Per-lobe routines in the local frame (wo.z > 0), exposed for the statistical tests.
// They leave out the layers above a lobe (the Bsdf applies those).
// mode matters only for refraction: in Importance mode transmitted f is divided by
// eta^2 (eta = lobe.ior, the relative IOR of the side wi enters), in Radiance mode not
// (Cycles' convention; bsdfs/dielectric.cpp).
Color lobe_eval(const Lobe &lobe, Vec3 wo, Vec3 wi, TransportMode mode = TransportMode::Radiance);  // f (without cosine)
float lobe_pdf(const Lobe &lobe, Vec3 wo, Vec3 wi);
// lobe_eval and lobe_pdf at once (terms both need are computed once).
Color lobe_eval_and_pdf(const Lobe &lobe, Vec3 wo, Vec3 wi, TransportMode mode, float &pdf);
// Returns false when no direction is sampled. weight = f * |cos| / pdf. For delta lobes
// pdf is the discrete probability of the chosen event (reflect / refract).
// uc: a third uniform variate for discrete choices inside the lobe (reflect or
// refract, single or multiple scattering); negative: derived from a hash of u.
bool lobe_sample(const Lobe &lobe, Vec3 wo, Vec2 u, Vec3 &wi, Color &weight, float &pdf,
                 TransportMode mode = TransportMode::Radiance, float uc = -1.0f);

}  // namespace rdv
