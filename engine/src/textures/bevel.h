// Cycles' Bevel node: a normal averaged from the surfaces of the point's own object within a
// radius, so a hard edge shades as if rounded. Sampled as Cycles samples it (svm_bevel):
// points on a disk around one of three axes (the geometric normal, or either tangent),
// radii from the cubic falloff of its old cubic BSSRDF, a local ray through each along the
// axis collecting the object's surfaces there (TextureRays::texture_ray_local_hits), each
// hit's smooth normal weighted by the falloff at its true distance over the disk's pdf and by
// the power heuristic over the three axes. The sum's direction is the normal.
//
// The sample points are a fixed set per point (PointSampleSet); Cycles draws them per
// evaluation, so a bevelled edge here carries its noise as a fine grain of the surface,
// averaged out over a pixel as Cycles' is over its samples. Cycles skips the node after a
// blurry bounce (a bounce density below 8); here every ray sees it: a path's history is no
// input of a material, and a look per kind of ray (copies of the object) would cost BDPT's
// light walks there (README).
#pragma once
#include "core/math.h"

namespace rdv {

struct ShadingPoint;

// The bevelled normal at sp (world, on the front side as ShadingPoint::ns), from `samples`
// local rays within `radius`; sp.ns where there is nothing to sample (no scene, radius or
// samples below what makes sense, no surface met).
Vec3 bevel_normal(const ShadingPoint &sp, float radius, int samples);

// The falloff's radius for u in [0, 1): r / radius solving CDF(x) = u, CDF(x) = 10x^2 - 20x^3
// + 15x^4 - 4x^5 (the profile 10 (1 - x)^3 / pi over the disk, integrated over 2 pi x dx).
float bevel_falloff_radius(float u);

}  // namespace rdv
