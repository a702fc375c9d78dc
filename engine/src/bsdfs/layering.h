// Energy-conserving layering (Principled BSDF): the scale a lobe gets from the
// reflecting layers above it, reciprocal in wo and wi. See LayerAbove in bsdf.h.
#pragma once
#include "bsdfs/bsdf.h"

namespace rdv {

// A dielectric GGX layer with Schlick Fresnel f0 and GGX alpha (isotropic equivalent),
// and a Cycles 3.4 sheen layer; weight: the layer lobe's colour.
LayerAbove schlick_ggx_layer(Color f0, float alpha, bool multiscatter, Color weight);
LayerAbove sheen_layer(Color weight);
// Directional albedo of a layer at cos(theta) = mu, and its cosine-weighted average.
Color layer_albedo(const LayerAbove &layer, float mu);
Color layer_average_albedo(const LayerAbove &layer);
// prod over the lobe's layers of (1 - A(|wo.z|)) (1 - A(|wi.z|)) / (1 - A_avg).
Color layer_factor(const Lobe &lobe, Vec3 wo, Vec3 wi);

}  // namespace rdv
