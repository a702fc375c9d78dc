// Energy-conserving layering (Principled BSDF): the scale a lobe gets from a reflecting
// layer above it, reciprocal in wo and wi. See LayerAbove in bsdf.h.
#pragma once
#include "bsdfs/bsdf.h"

namespace rdv {

// A dielectric GGX layer with Schlick Fresnel f0 and GGX alpha (isotropic equivalent) and
// shadowing (GgxDistribution::separable), and a Cycles 3.4 sheen layer; weight: the layer
// lobe's colour.
LayerAbove schlick_ggx_layer(Color f0, float alpha, bool separable, bool multiscatter, Color weight);
LayerAbove sheen_layer(Color weight);
// Directional albedo of a layer at cos(theta) = mu, and its cosine-weighted average.
Color layer_albedo(const LayerAbove &layer, float mu);
Color layer_average_albedo(const LayerAbove &layer);
// What the layer scales a lobe below it by: (1 - A(mu_o)) (1 - A(mu_i)) / (1 - A_avg),
// mu = |cos theta| of wo and wi.
Color layer_scale(const LayerAbove &layer, float mu_o, float mu_i);

}  // namespace rdv
