// A Mix Shader factor that depends on the viewing direction: Cycles' Fresnel node, its Layer
// Weight node (Fresnel and Facing outputs), as svm_node_fresnel / svm_node_layer_weight compute
// them from the direction toward the viewer I and the surface's interpolated normal, and the
// Geometry node's Backfacing output (1 where I is behind the front face: two-sided materials).
//
// Cycles shades a hit once, from the ray that reached it. Our light paths reach a surface from
// the light's side, so a factor taken at the direction a Bsdf was built toward would differ
// between a camera path and a light path through the same pair of directions. The Bsdf keeps
// the factor as a function instead and evaluates it, per pair, at the pair's camera-side
// direction (Radiance: wo; Importance: wi), as it picks its shading frame: f(wo, wi) is then
// one value however the path was sampled.
#pragma once
#include <algorithm>
#include <cmath>
#include "bsdfs/fresnel.h"
#include "core/math.h"

namespace rdv {

enum class ViewFactorKind : uint8_t {
  Fresnel,       // Fresnel node: the dielectric Fresnel reflectance of IOR `param`
  LayerFresnel,  // Layer Weight > Fresnel: the same of IOR 1 / (1 - blend), blend = `param`
  LayerFacing,   // Layer Weight > Facing: 1 - |cos|^b, b from blend = `param`
  Backfacing     // Geometry > Backfacing: 1 seen from behind the front face, else 0
};

struct ViewFactor {
  ViewFactorKind kind = ViewFactorKind::Fresnel;
  float param = 1.45f;
  // The nodes between the factor and the Mix Shader (a Color Ramp, Math, a curve with
  // constant settings), baked by the exporter into `table_size` values over the factor's
  // [0, 1] and read linearly; nullptr: none. Held by the Material.
  const float *table = nullptr;
  int table_size = 0;

  bool operator==(const ViewFactor &o) const {
    return kind == o.kind && param == o.param && table == o.table && table_size == o.table_size;
  }

  // The factor seen from direction w (unit), n the surface's interpolated normal and front
  // its geometric normal, both toward the front face. Cycles' back-facing flag (w behind
  // the front face) inverts the relative IOR of the Fresnel outputs; |cos| with the normal
  // as Cycles' fresnel_dielectric_cos takes it.
  float at(Vec3 w, Vec3 n, Vec3 front) const {
    float f = raw(std::fabs(dot(w, n)), dot(w, front) < 0);
    f = f >= 0.0f ? std::min(f, 1.0f) : 0.0f;  // a NaN parameter (a texture's 0 / 0) gives 0
    if (!table) return f;
    const float x = clampf(f, 0.0f, 1.0f) * float(table_size - 1);
    const int i = std::min(int(x), table_size - 2);
    return clampf(table[i] + (table[i + 1] - table[i]) * (x - float(i)), 0.0f, 1.0f);
  }

  // The node's own output at |cos| c (before the table).
  float raw(float c, bool backfacing) const {
    switch (kind) {
      case ViewFactorKind::Fresnel: {
        const float eta = clamp_ior(param);
        return fresnel_dielectric_cos(c, backfacing ? 1.0f / eta : eta);
      }
      case ViewFactorKind::LayerFresnel: {
        const float eta = clamp_ior(1.0f - param);
        return fresnel_dielectric_cos(c, backfacing ? eta : 1.0f / eta);
      }
      case ViewFactorKind::Backfacing: return backfacing ? 1.0f : 0.0f;
      case ViewFactorKind::LayerFacing: {
        float blend = param, f = c;
        if (blend != 0.5f) {
          blend = clampf(blend, 0.0f, 1.0f - 1e-5f);
          f = std::pow(f, blend < 0.5f ? 2.0f * blend : 0.5f / (1.0f - blend));
        }
        return 1.0f - f;
      }
    }
    return 0.0f;
  }

  // Cycles' lower bound 1e-5 (NaN too); an upper one of 1e5 (reflectance 1 to float
  // precision), where Cycles would square past float range.
  static float clamp_ior(float eta) { return std::fmin(std::fmax(eta, 1e-5f), 1e5f); }

  // Cycles' fresnel_dielectric_cos: the reflectance at |cos| c of relative IOR eta (1 past the
  // critical angle), in its closed form.
  static float fresnel_dielectric_cos(float c, float eta) {
    float g = eta * eta - 1 + c * c;
    if (!(g > 0)) return 1.0f;
    g = std::sqrt(g);
    const float a = (g - c) / (g + c), b = (c * (g + c) - 1) / (c * (g - c) + 1);
    return clampf(0.5f * a * a * (1 + b * b), 0.0f, 1.0f);
  }

  // The factor's mean over the directions of a hemisphere seen from the front, weighted by
  // cos: where a factor cannot follow the direction (an emission under it), its stand-in.
  float cosine_weighted_mean() const {
    const int n = 256;
    double sum = 0;
    for (int i = 0; i < n; ++i) {  // mu^2 uniform: cos-weighted; midpoints
      const float mu = std::sqrt((i + 0.5f) / n);
      sum += at(Vec3(std::sqrt(std::fmax(0.0f, 1 - mu * mu)), 0, mu), Vec3(0, 0, 1), Vec3(0, 0, 1));
    }
    return float(sum / n);
  }
};

}  // namespace rdv
