// Sampling shared by the diffuse-like lobes (Lambert, Oren-Nayar, Principled diffuse,
// sheen): a cosine-weighted hemisphere on wo's side, weight = f cos / pdf.
#pragma once
#include "bsdfs/bsdf.h"
#include "core/sampling.h"

namespace rdv {

inline float cosine_lobe_pdf(Vec3 wo, Vec3 wi) { return wo.z > 0 ? cosine_hemisphere_pdf(wi.z) : 0.0f; }

// f_eval(wi) returns the lobe's f (without the cosine).
template <class F>
bool sample_cosine_lobe(Vec3 wo, Vec2 u, Vec3 &wi, Color &weight, float &pdf, const F &f_eval) {
  if (wo.z <= 0) return false;
  wi = cosine_hemisphere(u);
  pdf = cosine_hemisphere_pdf(wi.z);
  if (pdf <= 0) return false;
  weight = f_eval(wi) * (wi.z / pdf);
  return true;
}

}  // namespace rdv
