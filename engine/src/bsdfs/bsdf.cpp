#include "bsdfs/bsdf.h"
#include "bsdfs/conductor.h"
#include "bsdfs/diffuse.h"

namespace rdv {

Color lobe_eval(const Lobe &lobe, Vec3 wo, Vec3 wi) {
  switch (lobe.type) {
    case LobeType::Lambert: return diffuse::eval(lobe, wo, wi);
    case LobeType::GgxConductor: return conductor::eval(lobe, wo, wi);
    case LobeType::SpecularConductor: return Color(0.0f);
  }
  return Color(0.0f);
}

float lobe_pdf(const Lobe &lobe, Vec3 wo, Vec3 wi) {
  switch (lobe.type) {
    case LobeType::Lambert: return diffuse::pdf(lobe, wo, wi);
    case LobeType::GgxConductor: return conductor::pdf(lobe, wo, wi);
    case LobeType::SpecularConductor: return 0;
  }
  return 0;
}

bool lobe_sample(const Lobe &lobe, Vec3 wo, Vec2 u, Vec3 &wi, Color &weight, float &pdf) {
  switch (lobe.type) {
    case LobeType::Lambert: return diffuse::sample(lobe, wo, u, wi, weight, pdf);
    case LobeType::GgxConductor: return conductor::sample(lobe, wo, u, wi, weight, pdf);
    case LobeType::SpecularConductor: pdf = 1; return conductor::sample_specular(lobe, wo, wi, weight);
  }
  return false;
}

Bsdf::Bsdf(Vec3 ng, Vec3 ns, Vec3 wo) {
  // Two-sided surfaces: put both normals on the viewer's side of the geometry.
  if (dot(ng, wo) < 0) ng = -ng;
  if (dot(ns, ng) < 0) ns = -ns;
  // A shading normal that faces away from the viewer would make the surface black
  // (the "shadow terminator"): fall back to the geometric normal there.
  if (dot(ns, wo) <= 1e-4f) ns = ng;
  ng_ = ng;
  frame_ = Frame(ns);
}

void Bsdf::add_lobe(const Lobe &lobe, float sample_weight) {
  if (n_ == kMaxLobes || !(sample_weight > 0)) return;
  lobes_[n_] = lobe;
  raw_weight_[n_] = sample_weight;
  ++n_;
  float total = 0;
  for (int i = 0; i < n_; ++i) total += raw_weight_[i];
  for (int i = 0; i < n_; ++i) pick_[i] = raw_weight_[i] / total;
}

bool Bsdf::is_delta() const {
  for (int i = 0; i < n_; ++i)
    if (!lobes_[i].is_delta()) return false;
  return n_ > 0;
}

// Veach's adjoint correction for shading normals on light paths:
// |wo.ng| |wi.ns| / (|wo.ns| |wi.ng|), which keeps light tracing and BDPT consistent
// with path tracing on smooth-shaded meshes.
float Bsdf::shading_correction(Vec3 wo, Vec3 wi, TransportMode mode) const {
  if (mode == TransportMode::Radiance) return 1.0f;
  float num = absdot(wo, ng_) * absdot(wi, frame_.n);
  float den = absdot(wo, frame_.n) * absdot(wi, ng_);
  return den > 0 ? num / den : 0.0f;
}

Color Bsdf::eval(Vec3 wo_w, Vec3 wi_w, TransportMode mode) const {
  // Reflection lobes only: both directions on the same side of the geometry,
  // otherwise light would leak through the surface via the shading normal.
  if (dot(wo_w, ng_) <= 0 || dot(wi_w, ng_) <= 0) return Color(0.0f);
  Vec3 wo = frame_.to_local(wo_w), wi = frame_.to_local(wi_w);
  Color f(0.0f);
  for (int i = 0; i < n_; ++i) f += lobe_eval(lobes_[i], wo, wi);
  return f * (std::fabs(wi.z) * shading_correction(wo_w, wi_w, mode));
}

float Bsdf::pdf(Vec3 wo_w, Vec3 wi_w) const {
  if (dot(wo_w, ng_) <= 0 || dot(wi_w, ng_) <= 0) return 0;
  Vec3 wo = frame_.to_local(wo_w), wi = frame_.to_local(wi_w);
  float p = 0;
  for (int i = 0; i < n_; ++i) p += pick_[i] * lobe_pdf(lobes_[i], wo, wi);
  return p;
}

bool Bsdf::sample(Vec3 wo_w, float u_lobe, Vec2 u, TransportMode mode, BsdfSample &out) const {
  if (n_ == 0 || dot(wo_w, ng_) <= 0) return false;
  int chosen = 0;
  float cdf = 0;
  for (; chosen < n_ - 1; ++chosen) {
    if (u_lobe < cdf + pick_[chosen]) break;
    cdf += pick_[chosen];
  }
  const Lobe &lobe = lobes_[chosen];
  Vec3 wo = frame_.to_local(wo_w), wi;
  Color weight;
  float pdf;
  if (!lobe_sample(lobe, wo, u, wi, weight, pdf)) return false;
  out.wi = frame_.to_world(wi);
  if (dot(out.wi, ng_) <= 0) return false;  // below the geometric surface
  if (lobe.is_delta()) {
    out.is_delta = true;
    out.pdf = pick_[chosen];
    out.weight = weight * (shading_correction(wo_w, out.wi, mode) / pick_[chosen]);
    return true;
  }
  out.is_delta = false;
  if (n_ == 1) {
    out.pdf = pdf;
    out.weight = weight * shading_correction(wo_w, out.wi, mode);
  } else {  // mixture: the weight must use the full f and the mixture pdf
    out.pdf = this->pdf(wo_w, out.wi);
    if (!(out.pdf > 0)) return false;
    out.weight = eval(wo_w, out.wi, mode) / out.pdf;
  }
  return true;
}

Color Bsdf::albedo() const {
  Color a(0.0f);
  for (int i = 0; i < n_; ++i) a += lobes_[i].color;
  return vmin(a, Color(1.0f));
}

}  // namespace rdv
