// Transparent shadows: shadow rays pass through surfaces whose material is partly
// transparent (Transparent BSDF, Principled alpha), tinted by the transparent weight,
// as Cycles' transparent shadows do. Opaque surfaces block as before.
#pragma once
#include "scene/scene.h"

namespace rdv {

// Layers a shadow ray passes where no Transparent max bounces is set.
constexpr int kShadowLayers = 16;

// Transmittance along o + t d, t < tmax (o already offset off its surface). Returns
// black at the first opaque surface. At most max_layers transparent surfaces are
// crossed (Cycles' transparent max bounces); beyond that the ray counts as blocked.
// rays is incremented per traced ray.
// mask: the kinds of ray it stands for (scene/ray_visibility.h).
// plain_layers_only: only the layers BDPT's walks pass without making them path vertices
// let the ray through (Scene::is_plain_layer); any other surface blocks.
Color transparent_shadow(const Scene &scene, Vec3 o, Vec3 d, float tmax, uint64_t &rays, uint32_t mask,
                         int max_layers = kShadowLayers, bool plain_layers_only = false);

}  // namespace rdv
