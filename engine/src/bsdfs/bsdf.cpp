#include "bsdfs/bsdf.h"
#include "bsdfs/clearcoat.h"
#include "bsdfs/conductor.h"
#include "bsdfs/dielectric.h"
#include "bsdfs/layering.h"
#include "bsdfs/lobe_merge.h"
#include "bsdfs/diffuse.h"
#include "bsdfs/oren_nayar.h"
#include "bsdfs/principled_diffuse.h"
#include "bsdfs/shading_normal.h"
#include "bsdfs/sheen.h"
#include "bsdfs/translucent.h"
#include "bsdfs/transparent.h"
#include <cmath>
#include <cstring>
#include <new>
#include "core/hash.h"
#include "core/ray_cone.h"

namespace rdv {

static Color lobe_eval_base(const Lobe &lobe, Vec3 wo, Vec3 wi, TransportMode mode) {
  switch (lobe.type) {
    case LobeType::Lambert: return diffuse::eval(lobe, wo, wi);
    case LobeType::GgxConductor: return conductor::eval(lobe, wo, wi);
    case LobeType::GgxDielectric: return dielectric::eval(lobe, wo, wi, mode);
    case LobeType::OrenNayar: return oren_nayar::eval(lobe, wo, wi);
    case LobeType::Translucent: return translucent::eval(lobe, wo, wi);
    case LobeType::Sheen: return sheen::eval(lobe, wo, wi);
    case LobeType::PrincipledDiffuse: return principled_diffuse::eval(lobe, wo, wi);
    case LobeType::Clearcoat: return clearcoat::eval(lobe, wo, wi);
    case LobeType::SpecularConductor:
    case LobeType::SmoothDielectric:
    case LobeType::Transparent: return Color(0.0f);  // delta lobes have no density
  }
  return Color(0.0f);
}

float lobe_pdf(const Lobe &lobe, Vec3 wo, Vec3 wi) {
  switch (lobe.type) {
    case LobeType::Lambert: return diffuse::pdf(lobe, wo, wi);
    case LobeType::GgxConductor: return conductor::pdf(lobe, wo, wi);
    case LobeType::GgxDielectric: return dielectric::pdf(lobe, wo, wi);
    case LobeType::OrenNayar: return oren_nayar::pdf(lobe, wo, wi);
    case LobeType::Translucent: return translucent::pdf(lobe, wo, wi);
    case LobeType::Sheen: return sheen::pdf(lobe, wo, wi);
    case LobeType::PrincipledDiffuse: return principled_diffuse::pdf(lobe, wo, wi);
    case LobeType::Clearcoat: return clearcoat::pdf(lobe, wo, wi);
    case LobeType::SpecularConductor:
    case LobeType::SmoothDielectric:
    case LobeType::Transparent: return 0;
  }
  return 0;
}

Color lobe_eval(const Lobe &lobe, Vec3 wo, Vec3 wi, TransportMode mode) {
  return lobe_eval_base(lobe, wo, wi, mode) * lobe.scale;
}

Color lobe_eval_and_pdf(const Lobe &lobe, Vec3 wo, Vec3 wi, TransportMode mode, float &pdf) {
  Color f;
  if (lobe.type == LobeType::GgxConductor) {
    f = conductor::eval_and_pdf(lobe, wo, wi, pdf);
  } else {
    f = lobe_eval_base(lobe, wo, wi, mode);
    pdf = lobe_pdf(lobe, wo, wi);
  }
  return f * lobe.scale;
}

static bool lobe_sample_base(const Lobe &lobe, Vec3 wo, Vec2 u, Vec3 &wi, Color &weight, float &pdf,
                             TransportMode mode, float uc);

bool lobe_sample(const Lobe &lobe, Vec3 wo, Vec2 u, Vec3 &wi, Color &weight, float &pdf, TransportMode mode,
                 float uc) {
  if (!lobe_sample_base(lobe, wo, u, wi, weight, pdf, mode, uc)) return false;
  weight *= lobe.scale;
  return true;
}

static bool lobe_sample_base(const Lobe &lobe, Vec3 wo, Vec2 u, Vec3 &wi, Color &weight, float &pdf,
                             TransportMode mode, float uc) {
  if (uc < 0) {  // no third dimension given: derive one that is independent of u in practice
    uint32_t a, b;
    std::memcpy(&a, &u.x, 4);
    std::memcpy(&b, &u.y, 4);
    uc = u32_to_unit_float(hash_combine(a, b));
  }
  switch (lobe.type) {
    case LobeType::Lambert: return diffuse::sample(lobe, wo, u, wi, weight, pdf);
    case LobeType::GgxConductor: return conductor::sample(lobe, wo, u, uc, wi, weight, pdf);
    case LobeType::SpecularConductor: pdf = 1; return conductor::sample_specular(lobe, wo, wi, weight);
    case LobeType::SmoothDielectric: return dielectric::sample_smooth(lobe, wo, u, wi, weight, pdf, mode);
    case LobeType::GgxDielectric: return dielectric::sample(lobe, wo, u, uc, wi, weight, pdf, mode);
    case LobeType::OrenNayar: return oren_nayar::sample(lobe, wo, u, wi, weight, pdf);
    case LobeType::Transparent: return transparent::sample(lobe, wo, wi, weight, pdf);
    case LobeType::Translucent: return translucent::sample(lobe, wo, u, wi, weight, pdf);
    case LobeType::Sheen: return sheen::sample(lobe, wo, u, wi, weight, pdf);
    case LobeType::PrincipledDiffuse: return principled_diffuse::sample(lobe, wo, u, wi, weight, pdf);
    case LobeType::Clearcoat: return clearcoat::sample(lobe, wo, u, wi, weight, pdf);
  }
  return false;
}

// The angular width a lobe adds to a ray cone (core/ray_cone.h): none for delta lobes;
// for GGX twice alpha (the reflected direction turns by twice the microfacet normal's
// angle, whose median tangent is alpha), capped; the cap for diffuse-like lobes.
static float lobe_cone_spread(const Lobe &lobe) {
  switch (lobe.type) {
    case LobeType::SpecularConductor:
    case LobeType::SmoothDielectric:
    case LobeType::Transparent: return 0;
    case LobeType::GgxConductor:
    case LobeType::GgxDielectric:
    case LobeType::Clearcoat: return std::min(2.0f * std::sqrt(lobe.ggx.ax * lobe.ggx.ay), kRoughConeSpread);
    case LobeType::Lambert:
    case LobeType::OrenNayar:
    case LobeType::Translucent:
    case LobeType::Sheen:
    case LobeType::PrincipledDiffuse: return kRoughConeSpread;
  }
  return kRoughConeSpread;
}

Bsdf::Bsdf(Vec3 ng, Vec3 ns, Vec3 wo) {
  // Two-sided surfaces: put both normals on the viewer's side of the geometry. A
  // viewer behind the front face sees dielectrics from the inside (inverse IOR).
  backfacing_ = dot(ng, wo) < 0;
  if (backfacing_) ng = -ng;
  if (dot(ns, ng) < 0) ns = -ns;
  // A shading normal that faces away from the viewer would make the surface black
  // (the "shadow terminator"): the geometric normal's frame there (frame_toward).
  ng_ = ng;
  frame_ = Frame(ns);
  smooth_ = ns.x != ng.x || ns.y != ng.y || ns.z != ng.z;
  if (smooth_) flat_ = Frame(ng);
}

// A frame about n with its first axis along the tangent (projected into n's plane).
static bool tangent_frame(Vec3 n, Vec3 tangent, Frame &out) {
  Vec3 t = tangent - n * dot(n, tangent);
  float len2 = length_squared(t);
  if (!(len2 > 1e-12f)) return false;
  t = t / std::sqrt(len2);
  out = Frame(t, cross(n, t), n);
  return true;
}

void Bsdf::bend_for_each_viewer(Vec3 mesh_normal) {
  bend_ = smooth_;
  mesh_normal_ = dot(mesh_normal, ng_) < 0 ? -mesh_normal : mesh_normal;
}

float Bsdf::bump_shadowing(Vec3 n, Vec3 wo_w, Vec3 wi_w, TransportMode mode) const {
  if (!bend_) return 1.0f;
  const Vec3 light = mode == TransportMode::Radiance ? wi_w : wo_w;
  const float cos_ni = dot(n, light);
  const Vec3 n0 = cos_ni < 0 ? -mesh_normal_ : mesh_normal_;  // transmission: the far side's
  const float denom = cos_ni * dot(n0, n);
  const float g = denom != 0 ? dot(n0, light) / denom : 0.0f;
  if (!(g < 1.0f)) return 1.0f;  // lit from the unshadowed side
  if (!(g > 0.0f)) return 0.0f;  // the light is behind the mesh's surface
  return g + g * g * (1.0f - g);  // smooth at g = 1
}

const Frame &Bsdf::bent_frame(Vec3 w, float side, Frame &scratch) const {
  // ensure_valid_reflection works on w's side of the surface; the result comes back to
  // frame_'s side. A normal it leaves alone is frame_ itself (the same floats).
  const Vec3 n = ensure_valid_reflection(ng_ * side, w, frame_.n * side) * side;
  if (n.x == frame_.n.x && n.y == frame_.n.y && n.z == frame_.n.z)
    return side * dot(w, frame_.n) > kTerminatorCos ? frame_ : flat_;
  if (!(oriented_ && tangent_frame(n, frame_.s, scratch)))  // anisotropy's axis turned with the normal
    scratch = Frame(n);
  return side * dot(w, n) > kTerminatorCos ? scratch : flat_;
}

Bsdf::Bsdf(Vec3 ng, Vec3 ns, Vec3 wo, Vec3 tangent) : Bsdf(ng, ns, wo) {
  Frame shading, flat;
  if (!tangent_frame(frame_.n, tangent, shading) || (smooth_ && !tangent_frame(ng_, tangent, flat))) return;
  frame_ = shading;
  if (smooth_) flat_ = flat;
  oriented_ = true;
}

uint16_t Bsdf::add_layer(const LayerAbove &layer) {
  if (num_layers_ == kMaxLayers) return uint16_t(1u << closest_layer(&layers_[0], num_layers_, layer));
  new (&layers_[num_layers_]) LayerAbove(layer);
  return uint16_t(1u << num_layers_++);
}

void Bsdf::layer_scales(Vec3 wo, Vec3 wi, LayerScales &out) const {
  for (int j = 0; j < num_layers_; ++j) out.of_layer[j] = layer_scale(layers_[j], std::fabs(wo.z), std::fabs(wi.z));
}

uint8_t Bsdf::add_view_factor(const ViewFactor &factor, Vec3 n) {
  view_normal_ = n;
  if (num_views_ == kMaxViewFactors) return 0;  // Material keeps within: not reached
  new (&views_[num_views_]) ViewFactor(factor);
  lambert_ = false;
  return uint8_t(1u << num_views_++);
}

const Bsdf::ViewScales *Bsdf::view_scales(Vec3 w, ViewScales &scratch) const {
  if (!num_views_) return nullptr;
  const Vec3 front = backfacing_ ? -ng_ : ng_;
  for (int j = 0; j < num_views_; ++j) scratch.of_view[j] = views_[j].at(w, view_normal_, front);
  return &scratch;
}

const float *Bsdf::picks_from(Vec3 w, Picks &scratch, const ViewScales *scales_at_w) const {
  if (!num_views_) return pick_.data();
  ViewScales computed;
  const ViewScales &views = scales_at_w ? *scales_at_w : *view_scales(w, computed);
  float total = 0;
  for (int i = 0; i < n_; ++i) total += scratch[size_t(i)] = raw_weight_[size_t(i)] * views.of(lobes_[i]);
  for (int i = 0; i < n_; ++i)
    scratch[size_t(i)] = 0.5f * pick_[size_t(i)] + (total > 0 ? 0.5f * scratch[size_t(i)] / total : 0.5f * pick_[size_t(i)]);
  return scratch.data();
}

void Bsdf::add_lobe(const Lobe &lobe, float sample_weight) {
  if (!(sample_weight > 0)) return;
  int slot = n_;
  if (n_ == kMaxLobes) {
    Lobe seen = lobe;
    if (seen.is_dielectric() && backfacing_) seen.ior = 1.0f / seen.ior;
    slot = make_room_for_lobe(&lobes_[0], raw_weight_.data(), n_, seen, sample_weight);
  } else {
    ++n_;
  }
  if (slot >= 0) {
    new (&lobes_[slot]) Lobe(lobe);
    if (lobe.is_dielectric() && backfacing_) lobes_[slot].ior = 1.0f / lobe.ior;
    raw_weight_[slot] = sample_weight;
  }
  lambert_ = n_ == 1 && lobe.type == LobeType::Lambert && lobe.layers_above == 0 && num_views_ == 0;
  float total = 0;
  for (int i = 0; i < n_; ++i) total += raw_weight_[i];
  for (int i = 0; i < n_; ++i) pick_[i] = raw_weight_[i] / total;
}

bool Bsdf::is_delta() const {
  for (int i = 0; i < n_; ++i)
    if (!lobes_[i].is_delta()) return false;
  return n_ > 0;
}

bool Bsdf::has_transmission() const {
  for (int i = 0; i < n_; ++i)
    if (lobes_[i].is_transmissive()) return true;
  return false;
}

// Veach's adjoint correction for shading normals on light paths (1997, eq. 5.17; as
// pbrt-v3's CorrectShadingNormal): |wo.ns| |wi.ng| / (|wo.ng| |wi.ns|), with wo toward
// the light-side vertex and wi the sampled direction. It keeps light tracing and BDPT
// consistent with path tracing on smooth-shaded meshes.
float Bsdf::shading_correction(Vec3 wo, Vec3 wi, TransportMode mode, const Frame &frame) const {
  if (mode == TransportMode::Radiance) return 1.0f;
  float num = absdot(wo, frame.n) * absdot(wi, ng_);
  float den = absdot(wo, ng_) * absdot(wi, frame.n);
  return den > 0 ? num / den : 0.0f;
}

// A direction counts only if the geometric and the shading normal agree on its side:
// reflection stays above both, transmission goes below both. Otherwise light would
// leak through the surface via the shading normal.
static bool consistent_side(Vec3 wi_world, Vec3 ng, float wi_local_z) {
  float g = dot(wi_world, ng);
  return (g > 0 && wi_local_z > 0) || (g < 0 && wi_local_z < 0);
}

// Evaluation from either side. The Bsdf is set up facing the direction it was
// reached from, but BDPT's MIS also needs densities for scattering the other way (a
// light path leaving through a refraction that a camera path entered by). Seen from
// behind, the surface is its mirror image: local z flips and dielectrics invert IOR.
bool Bsdf::local_pair(const Frame &frame, Vec3 wo_w, Vec3 wi_w, Vec3 &wo, Vec3 &wi, bool &flipped) const {
  float side = dot(wo_w, ng_);
  if (side == 0) return false;
  flipped = side < 0;
  wo = frame.to_local(wo_w);
  wi = frame.to_local(wi_w);
  if (flipped) { wo.z = -wo.z; wi.z = -wi.z; }
  return consistent_side(wi_w, flipped ? -ng_ : ng_, wi.z);
}

// The lobe as seen from the side wo is on. Only a dielectric seen from behind differs
// (inverse IOR); that one is copied into `scratch`, every other lobe is used in place.
// Raw storage: constructing (even an empty std::optional of) a Lobe on every
// evaluation cost more than evaluating a Lambert lobe.
struct LobeScratch {
  alignas(Lobe) unsigned char raw[sizeof(Lobe)];
};
static const Lobe &lobe_from_side(const Lobe &lobe, bool flipped, LobeScratch &scratch) {
  if (!flipped || !lobe.is_dielectric()) return lobe;
  Lobe *seen = new (scratch.raw) Lobe(lobe);
  seen->ior = 1.0f / lobe.ior;
  return *seen;
}

// The lobes Cycles labels a glossy or a diffuse reflection (bounce limits: glossy_odds).
static bool is_glossy_reflector(LobeType t) {
  return t == LobeType::GgxConductor || t == LobeType::Clearcoat || t == LobeType::SpecularConductor ||
         t == LobeType::SmoothDielectric || t == LobeType::GgxDielectric;
}
static bool is_diffuse_reflector(LobeType t) {
  return t == LobeType::Lambert || t == LobeType::OrenNayar || t == LobeType::PrincipledDiffuse ||
         t == LobeType::Sheen;
}

// What local_pair and the Lambert lobe decide, on the normal components alone: seen
// from wo's side of the geometry, both directions must be above both normals. On
// success the cosines are those of that side (all positive).
inline bool Bsdf::lambert_cosines(Vec3 n, Vec3 wo_w, Vec3 wi_w, LambertCosines &c) const {
  c = {dot(wo_w, n), dot(wi_w, n), dot(wo_w, ng_), dot(wi_w, ng_)};
  if (c.g_wo < 0) c = {-c.wo, -c.wi, -c.g_wo, -c.g_wi};
  return c.g_wo > 0 && c.g_wi > 0 && c.wo > 0 && c.wi > 0;
}

// The Lambert lobe's f with the shading correction, from the cosines at hand.
inline Color Bsdf::lambert_f(const LambertCosines &c, TransportMode mode) const {
  Color f = lobes_[0].color * kInvPi * lobes_[0].scale;
  return mode == TransportMode::Radiance ? f : f * ((c.wo * c.g_wi) / (c.g_wo * c.wi));
}

Color Bsdf::f_in(const Frame &frame, Vec3 wo_w, Vec3 wi_w, TransportMode mode) const {
  if (lambert_) {
    LambertCosines c;
    return lambert_cosines(frame.n, wo_w, wi_w, c) ? lambert_f(c, mode) * bump_shadowing(frame.n, wo_w, wi_w, mode)
                                                   : Color(0.0f);
  }
  Vec3 wo, wi;
  bool flipped;
  if (!local_pair(frame, wo_w, wi_w, wo, wi, flipped)) return Color(0.0f);
  ViewScales views;
  return local_f(wo, wi, flipped, mode, nullptr, nullptr, bump_shadowing(frame.n, wo_w, wi_w, mode),
                 view_scales(mode == TransportMode::Radiance ? wo_w : wi_w, views)) *
         shading_correction(wo_w, wi_w, mode, frame);
}

Color Bsdf::f(Vec3 wo_w, Vec3 wi_w, TransportMode mode) const {
  Frame bent;
  return f_in(camera_side_frame(wo_w, wi_w, mode, bent), wo_w, wi_w, mode);
}

Color Bsdf::local_f(Vec3 wo, Vec3 wi, bool flipped, TransportMode mode, float *pdf, const float *pick,
                    float diffuse_scale, const ViewScales *views, GlossyShare *glossy) const {
  Color f(0.0f);
  LobeScratch scratch;
  LayerScales layers;
  if (num_layers_) layer_scales(wo, wi, layers);
  for (int i = 0; i < n_; ++i) {
    const Lobe &lobe = lobe_from_side(lobes_[i], flipped, scratch);
    Color fi;
    if (pdf) {
      float p;
      fi = lobe_eval_and_pdf(lobe, wo, wi, mode, p);
      *pdf += pick[i] * p;
      if (glossy) {
        const float wp = glossy->weight[size_t(i)] * p;
        glossy->all += wp;
        if (is_glossy_reflector(lobe.type)) glossy->glossy += wp;
      }
    } else {
      fi = lobe_eval(lobe, wo, wi, mode);
    }
    if (views && lobe.view_factors) fi *= views->of(lobe);
    if (diffuse_scale != 1.0f && lobe.is_diffuse_like()) fi *= diffuse_scale;
    f += lobe.layers_above ? fi * layers.of(lobe.layers_above) : fi;
  }
  return f;
}

Color Bsdf::eval(Vec3 wo_w, Vec3 wi_w, TransportMode mode) const {
  Frame bent;
  const Frame &frame = camera_side_frame(wo_w, wi_w, mode, bent);
  return f_in(frame, wo_w, wi_w, mode) * absdot(wi_w, frame.n);
}

Color Bsdf::eval_and_pdf(Vec3 wo_w, Vec3 wi_w, TransportMode mode, float &pdf) const {
  pdf = 0;
  Frame bent, bent_seen;
  const Frame &frame = frame_toward(wo_w, bent);  // the sampler's
  const Frame &seen = camera_side_frame(wo_w, wi_w, mode, bent_seen);
  if (!same_frame(seen, frame)) {  // across the terminator fallback: the two apart
    const Color f = f_in(seen, wo_w, wi_w, mode);
    if (!is_black(f)) pdf = pdf_in(frame, wo_w, wi_w);
    return f * absdot(wi_w, seen.n);
  }
  if (lambert_) {
    LambertCosines c;
    if (!lambert_cosines(frame.n, wo_w, wi_w, c)) return Color(0.0f);
    pdf = c.wi * kInvPi;  // cosine_hemisphere_pdf, as the lobe samples
    return lambert_f(c, mode) * (c.wi * bump_shadowing(frame.n, wo_w, wi_w, mode));
  }
  Vec3 wo, wi;
  bool flipped;
  if (!local_pair(frame, wo_w, wi_w, wo, wi, flipped)) return Color(0.0f);
  Picks picks;
  ViewScales view_scratch;
  const ViewScales *views = view_scales(mode == TransportMode::Radiance ? wo_w : wi_w, view_scratch);
  const float *pick = picks_from(wo_w, picks, mode == TransportMode::Radiance ? views : nullptr);
  return local_f(wo, wi, flipped, mode, &pdf, pick, bump_shadowing(frame.n, wo_w, wi_w, mode), views) *
         shading_correction(wo_w, wi_w, mode, frame) * absdot(wi_w, frame.n);
}

Color Bsdf::eval_pdf_and_odds(Vec3 wo_w, Vec3 wi_w, float &pdf, bool defensive, float &glossy_odds) const {
  pdf = 0;
  glossy_odds = 0;
  constexpr TransportMode mode = TransportMode::Radiance;
  Frame bent, bent_seen;
  const Frame &frame = frame_toward(wo_w, bent);
  if (!same_frame(camera_side_frame(wo_w, wi_w, mode, bent_seen), frame)) {  // rare: two passes
    glossy_odds = this->glossy_odds(wo_w, wi_w, false, defensive);
    return eval_and_pdf(wo_w, wi_w, mode, pdf);
  }
  Vec3 wo, wi;
  bool flipped;
  if (!local_pair(frame, wo_w, wi_w, wo, wi, flipped)) return Color(0.0f);
  Picks picks;
  ViewScales view_scratch;
  const ViewScales *views = view_scales(wo_w, view_scratch);
  const float *pick = picks_from(wo_w, picks, views);
  GlossyShare share;
  odds_weights(std::fabs(wo.z), views, defensive, share.weight.data());
  const Color f = local_f(wo, wi, flipped, mode, &pdf, pick, bump_shadowing(frame.n, wo_w, wi_w, mode), views, &share) *
                  shading_correction(wo_w, wi_w, mode, frame) * absdot(wi_w, frame.n);
  glossy_odds = share.odds();
  return f;
}

Color Bsdf::f_and_pdfs(Vec3 wo_w, Vec3 wi_w, TransportMode mode, float &pdf_fwd, float &pdf_rev) const {
  pdf_fwd = pdf_rev = 0;
  Frame bent, bent_rev;
  const Frame &frame = frame_toward(wo_w, bent), &frame_rev = frame_toward(wi_w, bent_rev);
  if (!same_frame(frame, frame_rev)) {  // across the terminator fallback or a bend: each as its own
    const Color f = f_in(mode == TransportMode::Radiance ? frame : frame_rev, wo_w, wi_w, mode);
    if (is_black(f)) return f;
    pdf_fwd = pdf_in(frame, wo_w, wi_w);
    pdf_rev = pdf_in(frame_rev, wi_w, wo_w);
    return f;
  }
  if (lambert_) {
    LambertCosines c;
    if (!lambert_cosines(frame.n, wo_w, wi_w, c)) return Color(0.0f);
    pdf_fwd = c.wi * kInvPi;
    pdf_rev = c.wo * kInvPi;
    return lambert_f(c, mode) * bump_shadowing(frame.n, wo_w, wi_w, mode);
  }
  Vec3 wo, wi;
  bool flipped;
  if (!local_pair(frame, wo_w, wi_w, wo, wi, flipped)) return Color(0.0f);
  // The reverse pair as local_pair(wi_w, wo_w) would set it up: flipped by wi's side.
  float side_rev = dot(wi_w, ng_);
  bool flipped_rev = side_rev < 0;
  bool rev_ok = side_rev != 0;
  Vec3 wo_rev = wo, wi_rev = wi;  // local coordinates of wo_w and wi_w for the reverse pair
  if (flipped_rev != flipped) { wo_rev.z = -wo_rev.z; wi_rev.z = -wi_rev.z; }
  rev_ok = rev_ok && consistent_side(wo_w, flipped_rev ? -ng_ : ng_, wo_rev.z);
  Color f(0.0f);
  LobeScratch scratch, scratch_rev;
  LayerScales layers;
  if (num_layers_) layer_scales(wo, wi, layers);
  const float diffuse_scale = bump_shadowing(frame.n, wo_w, wi_w, mode);
  ViewScales view_scratch;
  const ViewScales *views = view_scales(mode == TransportMode::Radiance ? wo_w : wi_w, view_scratch);
  const bool radiance = mode == TransportMode::Radiance;  // the camera side's scales serve its picks
  Picks picks, picks_rev_scratch;
  const float *pick = picks_from(wo_w, picks, radiance ? views : nullptr);
  const float *pick_rev = picks_from(wi_w, picks_rev_scratch, radiance ? nullptr : views);
  for (int i = 0; i < n_; ++i) {
    const Lobe &lobe = lobe_from_side(lobes_[i], flipped, scratch);
    float p;
    Color fi = lobe_eval_and_pdf(lobe, wo, wi, mode, p);
    if (views && lobe.view_factors) fi *= views->of(lobe);
    if (diffuse_scale != 1.0f && lobe.is_diffuse_like()) fi *= diffuse_scale;
    f += lobe.layers_above ? fi * layers.of(lobe.layers_above) : fi;
    pdf_fwd += pick[i] * p;
    if (rev_ok) pdf_rev += pick_rev[i] * lobe_pdf(lobe_from_side(lobes_[i], flipped_rev, scratch_rev), wi_rev, wo_rev);
  }
  return f * shading_correction(wo_w, wi_w, mode, frame);
}

float Bsdf::pdf_in(const Frame &frame, Vec3 wo_w, Vec3 wi_w) const {
  if (lambert_) {
    LambertCosines c;
    return lambert_cosines(frame.n, wo_w, wi_w, c) ? c.wi * kInvPi : 0.0f;
  }
  Vec3 wo, wi;
  bool flipped;
  if (!local_pair(frame, wo_w, wi_w, wo, wi, flipped)) return 0;
  float p = 0;
  LobeScratch scratch;
  Picks picks;
  const float *pick = picks_from(wo_w, picks);
  for (int i = 0; i < n_; ++i) p += pick[i] * lobe_pdf(lobe_from_side(lobes_[i], flipped, scratch), wo, wi);
  return p;
}

float Bsdf::pdf(Vec3 wo_w, Vec3 wi_w) const {
  Frame bent;
  return pdf_in(frame_toward(wo_w, bent), wo_w, wi_w);
}

float Bsdf::share_refracted_below(Vec3 wo_w, Vec3 wi_w, float alpha2_max) const {
  if (lambert_) return 0;
  Vec3 wo, wi;
  bool flipped;
  Frame bent;
  if (!local_pair(frame_toward(wo_w, bent), wo_w, wi_w, wo, wi, flipped) || !(wo.z * wi.z < 0)) return 0;
  float all = 0, below = 0;
  LobeScratch scratch;
  Picks picks;
  const float *pick = picks_from(wo_w, picks);
  for (int i = 0; i < n_; ++i) {
    const Lobe &lobe = lobe_from_side(lobes_[i], flipped, scratch);
    const float p = pick[i] * lobe_pdf(lobe, wo, wi);
    all += p;
    if (lobe.type == LobeType::GgxDielectric && lobe.ggx.ax * lobe.ggx.ay <= alpha2_max) below += p;
  }
  return all > 0 ? std::min(1.0f, below / all) : 0.0f;
}

bool Bsdf::sample(Vec3 wo_w, float u_lobe, Vec2 u, TransportMode mode, BsdfSample &out, Odds odds) const {
  if (n_ == 0 || dot(wo_w, ng_) <= 0) return false;
  Picks picks;
  const float *pick = picks_from(wo_w, picks);
  int chosen = 0;
  float cdf = 0;
  for (; chosen < n_ - 1; ++chosen) {
    if (u_lobe < cdf + pick[chosen]) break;
    cdf += pick[chosen];
  }
  // The remainder of u_lobe drives choices inside the lobe (reflect or refract).
  float uc = clampf((u_lobe - cdf) / pick[chosen], 0.0f, 0.99999994f);
  const Lobe &lobe = lobes_[chosen];
  Frame bent, bent_wi;
  const Frame &frame = frame_toward(wo_w, bent);
  Vec3 wo = frame.to_local(wo_w), wi;
  Color weight;
  float pdf;
  if (!lobe_sample(lobe, wo, u, wi, weight, pdf, mode, uc)) return false;
  // The weight of a lone or delta lobe is its own: with the layers above it. (From a
  // mixture of non-delta lobes only the direction is kept; its weight comes below.)
  bool mixture = n_ > 1 && !lobe.is_delta();
  if (!mixture && lobe.layers_above) {
    LayerScales layers;
    layer_scales(wo, wi, layers);
    weight *= layers.of(lobe.layers_above);
  }
  out.wi = frame.to_world(wi);
  if (!consistent_side(out.wi, ng_, wi.z)) return false;
  // Light paths: f is the surface as a camera path from wi sees it (frame_toward). Where
  // that frame is the other one, a delta lobe sends wi elsewhere (no such path), and the
  // weight of any other is that f over the density sampled here.
  if (mode == TransportMode::Importance && !same_frame(frame_toward(out.wi, bent_wi), frame)) {
    if (lobe.is_delta()) return false;
    out.is_delta = false;
    out.cone_spread = lobe_cone_spread(lobe);
    out.pdf = pdf_in(frame, wo_w, out.wi);
    if (!(out.pdf > 0)) return false;
    out.weight = eval(wo_w, out.wi, mode) / out.pdf;
    return true;
  }
  out.cone_spread = lobe_cone_spread(lobe);
  if (lobe.is_dielectric() && wi.z * wo.z < 0)
    out.refraction_alpha2 = lobe.type == LobeType::SmoothDielectric ? 0.0f : lobe.ggx.ax * lobe.ggx.ay;
  if (lobe.view_factors && (lobe.is_delta() || n_ == 1)) {  // the mixture's weight below has them
    ViewScales views;
    weight *= view_scales(mode == TransportMode::Radiance ? wo_w : out.wi, views)->of(lobe);
  }
  if (lobe.is_delta()) {
    out.is_delta = true;
    out.pass_through = lobe.type == LobeType::Transparent;
    out.pdf = pick[chosen] * pdf;
    out.weight = weight * (shading_correction(wo_w, out.wi, mode, frame) / pick[chosen]);
    if (odds != Odds::None) out.glossy_odds = glossy_odds(wo_w, out.wi, true, false);
    return true;
  }
  out.is_delta = false;
  if (n_ == 1) {
    out.pdf = pdf;
    out.weight = weight * shading_correction(wo_w, out.wi, mode, frame);
    if (lobe.is_diffuse_like()) out.weight *= bump_shadowing(frame.n, wo_w, out.wi, mode);
    if (odds != Odds::None) out.glossy_odds = glossy_odds(wo_w, out.wi, false, false);  // one kind
  } else {  // mixture: the weight must use the full f and the mixture pdf
    const bool defensive = odds == Odds::Defensive;
    // The glossy odds of a diffuse-and-glossy reflection from the same pass over the lobes.
    const bool mixed_reflection = odds != Odds::None && mode == TransportMode::Radiance && wi.z * wo.z > 0 &&
                                  one_kind_odds(false) < 0;
    Color f = mixed_reflection ? eval_pdf_and_odds(wo_w, out.wi, out.pdf, defensive, out.glossy_odds)
                               : eval_and_pdf(wo_w, out.wi, mode, out.pdf);
    if (!(out.pdf > 0)) return false;
    out.weight = f / out.pdf;
    if (odds != Odds::None && !mixed_reflection) out.glossy_odds = glossy_odds(wo_w, out.wi, false, defensive);
  }
  return true;
}

Color Bsdf::delta_eval(Vec3 wo_w, Vec3 wi_w, TransportMode mode, float &pdf_out, float &jacobian) const {
  pdf_out = 0;
  jacobian = 1;
  Color f(0.0f);
  if (n_ == 0 || dot(wo_w, ng_) <= 0) return f;
  // The events of sample() from wo; light paths: none where a camera path from wi has the
  // other frame (sample() makes no such path).
  Frame bent, bent_wi;
  const Frame &frame = frame_toward(wo_w, bent);
  if (mode == TransportMode::Importance && !same_frame(frame_toward(wi_w, bent_wi), frame)) return f;
  const Vec3 wo = frame.to_local(wo_w);
  constexpr float kSameDirection = 1.0f - 1e-5f;  // cos of about 4.5e-3 rad
  ViewScales view_scratch;
  const ViewScales *views = view_scales(mode == TransportMode::Radiance ? wo_w : wi_w, view_scratch);
  Picks picks;
  const float *pick = picks_from(wo_w, picks, mode == TransportMode::Radiance ? views : nullptr);
  for (int i = 0; i < n_; ++i) {
    const Lobe &lobe = lobes_[i];
    if (!lobe.is_delta()) continue;
    // A smooth dielectric reflects for u.x < F and refracts above: both events; the
    // other delta lobes have one.
    Vec3 first_wi(0.0f);
    const int events = lobe.type == LobeType::SmoothDielectric ? 2 : 1;
    for (int e = 0; e < events; ++e) {
      Vec3 wi;
      Color weight;
      float pdf;
      if (!lobe_sample(lobe, wo, Vec2(e == 0 ? 0.0f : 0.99999994f, 0.5f), wi, weight, pdf, mode, 0.5f)) continue;
      if (e == 1 && wi == first_wi) continue;  // total internal reflection: one event
      if (e == 0) first_wi = wi;
      const Vec3 wi_event = frame.to_world(wi);
      if (dot(wi_event, wi_w) < kSameDirection || !consistent_side(wi_event, ng_, wi.z)) continue;
      if (lobe.layers_above) {
        LayerScales layers;
        layer_scales(wo, wi, layers);
        weight *= layers.of(lobe.layers_above);
      }
      if (views && lobe.view_factors) weight *= views->of(lobe);
      const float p = pick[i] * pdf;
      f += weight * (pdf * shading_correction(wo_w, wi_event, mode, frame));  // weight x p / pick
      pdf_out += p;
      if (wi.z < 0 && lobe.type == LobeType::SmoothDielectric && std::fabs(wi.z) > 0)
        jacobian = wo.z / (lobe.ior * lobe.ior * std::fabs(wi.z));
    }
  }
  return f;
}

float Bsdf::specularity() const {
  float w = 0;
  for (int i = 0; i < n_; ++i) {
    const Lobe &lobe = lobes_[i];
    if (lobe.is_delta()) return 1;  // connections cannot make the paths that scatter there
    if (lobe.type == LobeType::GgxConductor || lobe.type == LobeType::GgxDielectric || lobe.type == LobeType::Clearcoat)
      w += pick_[i] * (1.0f - std::min(1.0f, std::sqrt(std::sqrt(lobe.ggx.ax * lobe.ggx.ay))));  // roughness
  }
  return std::min(w, 1.0f);
}

ScatterKind Bsdf::scatter_kind(Vec3 wo, Vec3 wi) const {
  const bool reflection = dot(wo, ng_) * dot(wi, ng_) > 0;
  float diffuse = 0, glossy = 0, translucent = 0, refracting = 0, transparent = 0;
  for (int i = 0; i < n_; ++i) {
    const float w = pick_[i];
    switch (lobes_[i].type) {
      case LobeType::Lambert:
      case LobeType::OrenNayar:
      case LobeType::PrincipledDiffuse:
      case LobeType::Sheen: diffuse += w; break;
      case LobeType::GgxConductor:
      case LobeType::Clearcoat:
      case LobeType::SpecularConductor: glossy += w; break;
      case LobeType::SmoothDielectric:
      case LobeType::GgxDielectric:
        glossy += w;  // its reflection
        refracting += w;
        break;
      case LobeType::Translucent: translucent += w; break;
      case LobeType::Transparent: transparent += w; break;
    }
  }
  if (reflection) return glossy > diffuse ? ScatterKind::Glossy : ScatterKind::Diffuse;
  if (transparent > refracting && transparent > translucent) return ScatterKind::Transparent;
  return translucent > refracting ? ScatterKind::Translucent : ScatterKind::Transmission;
}

float Bsdf::one_kind_odds(bool delta) const {
  bool any_glossy = false, any_diffuse = false;
  for (int i = 0; i < n_; ++i) {
    any_glossy = any_glossy || is_glossy_reflector(lobes_[i].type);
    any_diffuse = any_diffuse || is_diffuse_reflector(lobes_[i].type);
  }
  if (!any_diffuse || delta) return 1;  // a delta reflection is a mirror's or glass's: glossy
  return any_glossy ? -1.0f : 0.0f;
}

void Bsdf::odds_weights(float cos_o, const ViewScales *views, bool defensive, float *weight) const {
  // Cycles' sample weight of each closure: the average of its weight, which holds its
  // colour (and, for the Fresnel-coloured Principled lobes, their Fresnel at the viewer).
  float sum = 0;
  for (int i = 0; i < n_; ++i) {
    const Lobe &lobe = lobes_[i];
    Color albedo = lobe.color;
    if ((lobe.type == LobeType::GgxConductor || lobe.type == LobeType::Clearcoat ||
         lobe.type == LobeType::SpecularConductor) && lobe.fresnel_mode != FresnelMode::Tint)
      albedo = lobe.fresnel(cos_o);
    weight[i] = std::max(0.0f, average(albedo) * lobe.scale * (views ? views->of(lobe) : 1.0f));
    sum += weight[i];
  }
  if (defensive)
    for (int i = 0; i < n_; ++i) weight[i] = std::max(weight[i], 0.125f * sum);
}

float Bsdf::glossy_odds(Vec3 camera_side, Vec3 light_side, bool delta, bool defensive) const {
  if (dot(camera_side, ng_) * dot(light_side, ng_) <= 0) return -1;
  const float one_kind = one_kind_odds(delta);
  if (one_kind >= 0) return one_kind;
  Vec3 wo, wi;
  bool flipped;
  Frame bent;
  if (!local_pair(frame_toward(camera_side, bent), camera_side, light_side, wo, wi, flipped)) return 0;
  ViewScales view_scratch;
  GlossyShare share;
  odds_weights(std::fabs(wo.z), view_scales(camera_side, view_scratch), defensive, share.weight.data());
  LobeScratch scratch;
  for (int i = 0; i < n_; ++i) {
    const float p = share.weight[size_t(i)] * lobe_pdf(lobe_from_side(lobes_[i], flipped, scratch), wo, wi);
    share.all += p;
    if (is_glossy_reflector(lobes_[i].type)) share.glossy += p;
  }
  return share.odds();
}

Color Bsdf::albedo(Vec3 wo) const {
  ViewScales view_scratch;
  const ViewScales *views = view_scales(wo, view_scratch);
  Color a(0.0f);
  for (int i = 0; i < n_; ++i) a += lobes_[i].color * (lobes_[i].scale * (views ? views->of(lobes_[i]) : 1.0f));
  return vmin(a, Color(1.0f));
}

}  // namespace rdv

namespace rdv {

// Which light-pass kind a lobe scatters as (film/light_passes.h; Cycles counts
// translucent and sheen as diffuse, a glass closure's reflection as glossy).
static int pass_kind(LobeType type, bool reflection) {
  switch (type) {
    case LobeType::Lambert:
    case LobeType::OrenNayar:
    case LobeType::PrincipledDiffuse:
    case LobeType::Sheen:
    case LobeType::Translucent: return 0;
    case LobeType::GgxConductor:
    case LobeType::Clearcoat:
    case LobeType::SpecularConductor: return 1;
    case LobeType::SmoothDielectric:
    case LobeType::GgxDielectric:
    case LobeType::Transparent: break;
  }
  return reflection ? 1 : 2;
}

int Bsdf::kind_parts(Vec3 wo_w, Vec3 wi_w, Color parts[3]) const {
  const bool reflection = dot(wo_w, ng_) * dot(wi_w, ng_) > 0;
  // Lobes all of one kind on this side (a plain diffuse surface): that kind, with no lobe
  // to evaluate (a path with a share has f > 0 here), where local_pair would find a pair;
  // only its test is made, on the normal components.
  int single = -1;
  for (int i = 0; i < n_ && single != -2; ++i)
    if (!lobes_[i].is_delta()) {
      const int k = pass_kind(lobes_[i].type, reflection);
      single = single == -1 || single == k ? k : -2;
    }
  if (single >= 0) {
    const float side = dot(wo_w, ng_);
    Frame bent;
    const float wi_z = dot(wi_w, frame_toward(wo_w, bent).n);
    return side != 0 && consistent_side(wi_w, side < 0 ? -ng_ : ng_, side < 0 ? -wi_z : wi_z) ? single : -1;
  }
  if (single == -1) return -1;  // no lobe that is not delta
  Vec3 wo, wi;
  bool flipped;
  Frame bent;
  const Frame &frame = frame_toward(wo_w, bent);
  if (!local_pair(frame, wo_w, wi_w, wo, wi, flipped)) return -1;
  LobeScratch scratch;
  LayerScales layers;
  if (num_layers_) layer_scales(wo, wi, layers);
  const float diffuse_scale = bump_shadowing(frame.n, wo_w, wi_w, TransportMode::Radiance);
  ViewScales view_scratch;
  const ViewScales *views = view_scales(wo_w, view_scratch);
  for (int k = 0; k < 3; ++k) parts[k] = Color(0.0f);
  for (int i = 0; i < n_; ++i) {
    const Lobe &lobe = lobe_from_side(lobes_[i], flipped, scratch);
    if (lobe.is_delta()) continue;
    Color fi = lobe_eval(lobe, wo, wi, TransportMode::Radiance);
    if (views && lobe.view_factors) fi *= views->of(lobe);
    if (lobe.is_diffuse_like()) fi *= diffuse_scale;
    if (lobe.layers_above) fi *= layers.of(lobe.layers_above);
    parts[pass_kind(lobe.type, reflection)] += vmax(fi, Color(0.0f));
  }
  return kSplitKinds;
}

// The kind a scattering counts as where its lobes were not split (kind_parts found none,
// or f is 0 there): the side's kind for a delta event, else the dominant one.
int Bsdf::whole_kind(Vec3 wo_w, Vec3 wi_w, bool delta) const {
  if (delta) return dot(wo_w, ng_) * dot(wi_w, ng_) > 0 ? 1 : 2;
  const ScatterKind kind = scatter_kind(wo_w, wi_w);
  return kind == ScatterKind::Diffuse || kind == ScatterKind::Translucent ? 0 : kind == ScatterKind::Glossy ? 1 : 2;
}

KindSplit Bsdf::kind_split(Vec3 wo_w, Vec3 wi_w, bool delta) const {
  if (!delta && n_ > 0) {
    Color parts[3];
    const int k = kind_parts(wo_w, wi_w, parts);
    if (k >= 0 && k < kSplitKinds) return KindSplit::only(k);
    if (k == kSplitKinds) {
      float w[3], total = 0;
      for (int j = 0; j < 3; ++j) total += (w[j] = average(parts[j]));
      if (total > 0) {
        KindSplit s;
        for (int j = 0; j < 3; ++j) s.w[j] = w[j] / total;
        return s;
      }
    }
  }
  return KindSplit::only(whole_kind(wo_w, wi_w, delta));
}

Color Bsdf::caustic_share(Vec3 camera_side, Vec3 light_side, bool delta, bool keep_glossy, bool keep_refraction) const {
  const bool keeps[3] = {true, keep_glossy, keep_refraction};
  if (!delta && n_ > 0) {
    Color parts[3];
    const int k = kind_parts(camera_side, light_side, parts);
    if (k >= 0 && k < kSplitKinds) return Color(keeps[k] ? 1.0f : 0.0f);
    if (k == kSplitKinds) {
      const Color all = parts[0] + parts[1] + parts[2];
      if (!is_black(all)) {
        Color kept(0.0f);
        for (int j = 0; j < 3; ++j)
          if (keeps[j]) kept += parts[j];
        auto share = [](float a, float b) { return b > 0 ? clampf(a / b, 0.0f, 1.0f) : 0.0f; };
        return Color(share(kept.x, all.x), share(kept.y, all.y), share(kept.z, all.z));
      }
    }
  }
  return Color(keeps[whole_kind(camera_side, light_side, delta)] ? 1.0f : 0.0f);
}

float Bsdf::transparent_pick(const float *pick) const {
  float q = 0;
  for (int i = 0; i < n_; ++i)
    if (lobes_[i].type == LobeType::Transparent) q += pick[i];
  return q;
}

float Bsdf::pass_probability(Vec3 wo) const {
  if (n_ == 0 || dot(wo, ng_) <= 0) return 0;  // sample() fails
  Picks picks;
  return transparent_pick(picks_from(wo, picks));
}

float Bsdf::scattering_lobe_u(Vec3 wo, float u) const {
  Picks picks;
  const float *pick = picks_from(wo, picks);
  const float pass = transparent_pick(pick);
  if (!(pass < 1)) return u;  // nothing else to pick: sample() passes (the caller fails)
  float left = u * (1 - pass), cdf = 0, last_end = 0;  // left: how far into the other lobes' picks
  for (int i = 0; i < n_; ++i) {
    if (lobes_[i].type != LobeType::Transparent) {
      if (left < pick[i]) return cdf + left;
      left -= pick[i];
      last_end = cdf + pick[i];
    }
    cdf += pick[i];
  }
  return std::nextafter(last_end, 0.0f);  // rounding left a sliver past the last one: its end
}

bool Bsdf::passes_straight_through(Vec3 wo, Vec3 wi) const {
  constexpr float kSameDirection = 1.0f - 1e-5f;  // as delta_eval's events
  if (dot(-wo, wi) < kSameDirection) return false;
  for (int i = 0; i < n_; ++i)
    if (lobes_[i].type == LobeType::Transparent) return true;
  return false;
}

void Bsdf::kind_colors(Vec3 wo_w, Color out[kColorKinds]) const {
  for (int k = 0; k < kColorKinds; ++k) out[k] = Color(0.0f);
  const float side = dot(wo_w, ng_);
  const float cos_o = absdot(wo_w, shading_normal(wo_w));
  ViewScales view_scratch;
  const ViewScales *views = view_scales(wo_w, view_scratch);
  for (int i = 0; i < n_; ++i) {
    const Lobe &lobe = lobes_[i];
    const Color c = lobe.color * (lobe.scale * (views ? views->of(lobe) : 1.0f));
    if (lobe.type == LobeType::Transparent) continue;
    if (!lobe.is_dielectric()) {
      out[pass_kind(lobe.type, true)] += c;
    } else if (lobe.refraction_only && !lobe.macro_fresnel) {
      out[2] += c;
    } else {
      const float F = fresnel_dielectric(cos_o, side < 0 ? 1.0f / lobe.ior : lobe.ior);
      if (!lobe.refraction_only) out[1] += c * F;
      if (!lobe.reflection_only) out[2] += c * (1.0f - F);
    }
  }
}

DenoisingClosures Bsdf::denoising_closures(Vec3 wo_w) const {
  DenoisingClosures out;
  Frame bent;
  const Frame &frame = frame_toward(wo_w, bent);
  const float cos_o = absdot(wo_w, frame.n);
  ViewScales view_scratch;
  const ViewScales *views = view_scales(wo_w, view_scratch);
  Picks picks;
  const float *pick = picks_from(wo_w, picks, views);
  for (int i = 0; i < n_; ++i) {
    const Lobe &lobe = lobes_[i];
    const float scale = lobe.scale * (views ? views->of(lobe) : 1.0f);
    Color albedo = lobe.color * scale;
    bool rough = true;
    switch (lobe.type) {
      case LobeType::GgxConductor:
      case LobeType::Clearcoat:
        if (lobe.fresnel_mode != FresnelMode::Tint) albedo = lobe.fresnel(cos_o) * scale;
        rough = lobe.ggx.ax * lobe.ggx.ay > kDenoisingRoughness2;
        break;
      case LobeType::GgxDielectric: rough = lobe.ggx.ax * lobe.ggx.ay > kDenoisingRoughness2; break;
      case LobeType::SpecularConductor:
        if (lobe.fresnel_mode != FresnelMode::Tint) albedo = lobe.fresnel(cos_o) * scale;
        rough = false;
        break;
      case LobeType::SmoothDielectric:
      case LobeType::Transparent: rough = false; break;
      default: break;  // diffuse-like lobes
    }
    out.weight += pick[i];
    if (rough) {
      out.rough_albedo += albedo;
      out.rough_weight += pick[i];
    } else {
      out.specular_albedo += albedo;
    }
  }
  if (out.weight > 0) out.normal = frame.n;
  return out;
}

float Bsdf::blur_threshold() const {
  float threshold = kInf;
  for (int i = 0; i < n_; ++i) {
    const Lobe &l = lobes_[i];
    if (l.type == LobeType::SpecularConductor || l.type == LobeType::SmoothDielectric) return -1;
    if (l.type == LobeType::GgxConductor || l.type == LobeType::GgxDielectric || l.type == LobeType::Clearcoat)
      threshold = std::min(threshold, std::min(l.ggx.ax, l.ggx.ay));
  }
  return threshold;
}

void Bsdf::blur(float alpha) {
  if (!blur_acts(alpha)) return;  // too small to make anything rough
  for (int i = 0; i < n_; ++i) {
    Lobe &l = lobes_[i];
    switch (l.type) {
      case LobeType::SpecularConductor: l.type = LobeType::GgxConductor; break;
      case LobeType::SmoothDielectric: l.type = LobeType::GgxDielectric; break;
      case LobeType::GgxConductor:
      case LobeType::GgxDielectric:
      case LobeType::Clearcoat: break;
      default: continue;  // not a microfacet lobe: Cycles blurs none of these
    }
    l.ggx.ax = std::max(l.ggx.ax, alpha);
    l.ggx.ay = std::max(l.ggx.ay, alpha);
  }
}

}  // namespace rdv
