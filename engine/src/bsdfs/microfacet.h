// GGX (Trowbridge-Reitz) microfacet distribution with anisotropic roughness, Smith
// masking-shadowing (height-correlated, or separable as in Cycles up to 3.4) and
// visible-normal sampling (Heitz 2018, "Sampling the GGX Distribution of Visible Normals").
// All vectors in the local shading frame (z = normal).
#pragma once
#include "core/math.h"

namespace rdv {

struct GgxDistribution {
  float ax, ay;
  // Shadowing-masking G2 as the separable product G1(wo) G1(wi), as Cycles 3.4 evaluates
  // every GGX closure (Blender 3.x materials), instead of the height-correlated
  // 1 / (1 + lambda(wo) + lambda(wi)) (Heitz 2014; Cycles 3.5 on). They differ where both
  // directions graze a rough surface: at 9 degrees and alpha 0.64, 0.150 against 0.240.
  bool separable = false;

  // Cycles treats alpha_x * alpha_y <= 1e-7 as a perfect mirror; so do we.
  static constexpr float kSmoothLimit = 1e-7f;
  bool is_smooth() const { return ax * ay <= kSmoothLimit; }

  float D(Vec3 h) const {
    if (h.z <= 0) return 0;
    float e = sqr(h.x / ax) + sqr(h.y / ay) + h.z * h.z;
    return 1.0f / (kPi * ax * ay * e * e);
  }
  float lambda(Vec3 w) const {
    float z2 = w.z * w.z;
    if (z2 == 0) return kInf;
    float a2tan2 = (sqr(ax * w.x) + sqr(ay * w.y)) / z2;
    return 0.5f * (-1.0f + std::sqrt(1.0f + a2tan2));
  }
  float G1(Vec3 w) const { return 1.0f / (1.0f + lambda(w)); }
  float G2(Vec3 wo, Vec3 wi) const { return G2_of_lambdas(lambda(wo), lambda(wi)); }
  float G2_of_lambdas(float lambda_o, float lambda_i) const {
    return separable ? 1.0f / ((1.0f + lambda_o) * (1.0f + lambda_i)) : 1.0f / (1.0f + lambda_o + lambda_i);
  }

  // Density of visible normals seen from wo (wo.z > 0).
  float D_visible(Vec3 wo, Vec3 h) const {
    return G1(wo) * std::max(0.0f, dot(wo, h)) * D(h) / wo.z;
  }

  Vec3 sample_visible_normal(Vec3 wo, Vec2 u) const {
    Vec3 vh = normalize(Vec3(ax * wo.x, ay * wo.y, wo.z));
    float lensq = vh.x * vh.x + vh.y * vh.y;
    Vec3 t1 = lensq > 0 ? Vec3(-vh.y, vh.x, 0) / std::sqrt(lensq) : Vec3(1, 0, 0);
    Vec3 t2 = cross(vh, t1);
    float r = std::sqrt(u.x), phi = 2.0f * kPi * u.y;
    float p1 = r * std::cos(phi), p2 = r * std::sin(phi);
    float s = 0.5f * (1.0f + vh.z);
    p2 = (1.0f - s) * safe_sqrt(1.0f - p1 * p1) + s * p2;
    Vec3 nh = t1 * p1 + t2 * p2 + vh * safe_sqrt(1.0f - p1 * p1 - p2 * p2);
    return normalize(Vec3(ax * nh.x, ay * nh.y, std::max(1e-7f, nh.z)));
  }
};

}  // namespace rdv
