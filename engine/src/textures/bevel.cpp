#include "textures/bevel.h"
#include <cmath>
#include "textures/shading_point.h"
#include "textures/texture_rays.h"

namespace rdv {

namespace {
constexpr int kMaxHitsPerRay = 4;  // Cycles' LOCAL_MAX_HITS; more are a uniform choice, reweighted
constexpr uint32_t kBevelSalt = 0xb5e7e1u;

// The falloff (1 - r / R)^3, up to the constant its ratios cancel: the pdf of a disk radius
// and the weight of a hit at distance r are taken as one over the other. Relative to the
// radius, so a millimetre's bevel is as precise as a metre's.
float falloff(float radius, float r) {
  const float f = 1.0f - r / radius;
  return f > 0 ? f * f * f : 0.0f;
}
}  // namespace

float bevel_falloff_radius(float u) {
  // Newton's method on the CDF from x = 0.25, kept inside a bracket that shrinks with every
  // step (the CDF rises monotonically), so flat ends near 0 and 1 cannot throw it out.
  float lo = 0.0f, hi = 1.0f, x = 0.25f;
  for (int i = 0; i < 32; ++i) {
    const float x2 = x * x, nx = 1.0f - x;
    const float f = x2 * (10.0f - 20.0f * x + 15.0f * x2 - 4.0f * x2 * x) - u;
    if (std::fabs(f) < 1e-6f) break;
    (f < 0 ? lo : hi) = x;
    const float df = 20.0f * x * nx * nx * nx;
    float next = df > 0 ? x - f / df : 0.5f * (lo + hi);
    if (!(next > lo && next < hi)) next = 0.5f * (lo + hi);
    x = next;
  }
  return x;
}

Vec3 bevel_normal(const ShadingPoint &sp, float radius, int samples) {
  if (!sp.rays || !(radius > 0) || !std::isfinite(radius) || samples < 1) return sp.ns;
  const Frame frame(sp.ng);
  const PointSampleSet set(sp.p, kBevelSalt, samples);
  Vec3 sum(0.0f);
  for (int i = 0; i < samples; ++i) {
    Vec2 u = set[i];
    // The disk's axis: the normal half the time, either tangent a quarter (Cycles' choice).
    Vec3 axis = frame.n, tangent = frame.s, bitangent = frame.t;
    float pick_axis = 0.5f, pick_tangent = 0.25f, pick_bitangent = 0.25f;
    if (u.x < 0.5f) {
      u.x *= 2.0f;
    } else if (u.x < 0.75f) {
      std::swap(axis, tangent);
      std::swap(pick_axis, pick_tangent);
      u.x = (u.x - 0.5f) * 4.0f;
    } else {
      std::swap(axis, bitangent);
      std::swap(pick_axis, pick_bitangent);
      u.x = (u.x - 0.75f) * 4.0f;
    }
    const float disk_r = radius * bevel_falloff_radius(u.y);
    const float disk_pdf = falloff(radius, disk_r);
    if (!(disk_pdf > 0)) continue;
    const float height = std::sqrt(std::max(radius * radius - disk_r * disk_r, 0.0f));
    const float phi = 2.0f * kPi * u.x;
    const Vec3 origin = sp.p + axis * height + (tangent * std::cos(phi) + bitangent * std::sin(phi)) * disk_r;
    LocalHit hits[kMaxHitsPerRay];
    const int found = sp.rays->texture_ray_local_hits(sp, origin, -axis, 2.0f * height, hits, kMaxHitsPerRay,
                                                       hash_u32(set.hash() + uint32_t(i)));
    const int kept = std::min(found, kMaxHitsPerRay);
    for (int h = 0; h < kept; ++h) {
      const LocalHit &hit = hits[h];
      // The densities of reaching this hit through each axis' disk (up to the disk pdf the
      // three share here, as in Cycles), combined by the power heuristic.
      const float p_axis = pick_axis * std::fabs(dot(axis, hit.ng));
      const float p_tangent = pick_tangent * std::fabs(dot(tangent, hit.ng));
      const float p_bitangent = pick_bitangent * std::fabs(dot(bitangent, hit.ng));
      const float p2 = p_axis * p_axis + p_tangent * p_tangent + p_bitangent * p_bitangent;
      if (!(p2 > 0)) continue;
      float w = p_axis / p2 * (falloff(radius, length(hit.p - sp.p)) / disk_pdf);
      if (found > kept) w *= float(found) / float(kept);
      sum += hit.ns * w;
    }
  }
  const float len = length(sum);
  return len > 0 && std::isfinite(len) ? sum / len : sp.ns;
}

}  // namespace rdv
