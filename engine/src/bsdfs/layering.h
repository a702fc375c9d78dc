// Energy-conserving layering (Principled BSDF): the scale a lobe gets from the
// reflecting layers above it, reciprocal in wo and wi. See LayerAbove in bsdf.h.
#pragma once
#include "bsdfs/bsdf.h"

namespace rdv {

// Directional albedo of a layer at cos(theta) = mu, and its cosine-weighted average.
Color layer_albedo(const LayerAbove &layer, float mu);
Color layer_average_albedo(const LayerAbove &layer);
// prod over the lobe's layers of (1 - A(|wo.z|)) (1 - A(|wi.z|)) / (1 - A_avg).
Color layer_factor(const Lobe &lobe, Vec3 wo, Vec3 wi);

}  // namespace rdv
